"""The conventional fill (Liepa 2003): minimum-weight triangulation, refinement, fairing."""
