"""The conformal fill: λ and H inpainted over the hole on the patch's conformal domain, the
surface rebuilt from them, measured against the faired fills by a truth-free self-check."""
