"""The weight steps of the least-squares stage's continuation in the curvature weight
(:func:`surfinpaint.representation.least_squares_stage.curvature_continuation`): kept apart,
without imports, so that :class:`surfinpaint.fill.conformal.options.ConformalOptions` checks
``continuation_smallest`` against them without loading the λ-H solver at start-up."""

__all__ = ["CONTINUATION_SMALLEST", "CONTINUATION_STEP"]

# the first step; doubled after a solve that converges, halved after one that fails
CONTINUATION_STEP = 0.125
# the continuation ends where the step falls below this (by default; ConformalOptions.
# continuation_smallest: larger ends a stalled continuation sooner, session 49 helper)
CONTINUATION_SMALLEST = 1e-3
