"""Tests on a Newton stage's trajectory so far that give it up before its last step.

A Newton stage of the λ-H fill (:func:`surfinpaint.representation.on_mesh.inpaint_on_mesh`'s,
or one solve of the least-squares stage's continuation) that fails changes nothing after it:
the next stage, or the continuation's next solve, starts where the failed one started. So a
test that stops only stages that would fail anyway saves their remaining steps and changes no
fill. Each test here was chosen on a log of every stage on the tuning side, such that it
stops none of the stages that converged there (docs/convergence.md).
"""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["NEWTON_STALL_LEVEL", "NEWTON_STALL_RATIO", "NEWTON_STALL_STEPS", "TURN_CUT",
           "TURN_GROWTH", "TURN_STEPS", "stalled", "turning"]

# a stage outside the continuation above STALL_LEVEL edge lengths and STALL_RATIO of |R|
# STALL_STEPS steps before: converging stages fell by ≥ 7.6 % in 3 steps above 10, by < 1 %
# only below 4.3 (session 34, helper 2)
NEWTON_STALL_STEPS = 3
NEWTON_STALL_RATIO = 0.99
NEWTON_STALL_LEVEL = 10.0
# a stage whose last TURN_STEPS Newton steps were each at least TURN_GROWTH times as long as
# the one before (before the trust region's cut) and each cut by the line search to at most
# TURN_CUT of it: of the 247 stages and continuation solves that converged on the tuning
# side, none had two steps in a row cut to a quarter and both growing by more than 0.91
# (a CAD part's 225-vertex stage; session 35, helper)
TURN_STEPS = 2
TURN_GROWTH = 1.25
TURN_CUT = 0.25


def stalled(sizes: Sequence[float], size: float) -> bool:
    """Whether a Newton stage whose residual was ``sizes`` before its steps and is ``size`` now
    has stalled far from a root: above ``NEWTON_STALL_LEVEL`` edge lengths and
    ``NEWTON_STALL_RATIO`` of its value ``NEWTON_STALL_STEPS`` steps before."""
    return (len(sizes) >= NEWTON_STALL_STEPS and size > NEWTON_STALL_LEVEL
            and size > NEWTON_STALL_RATIO * sizes[-NEWTON_STALL_STEPS])


def turning(longest: Sequence[float], fractions: Sequence[float]) -> bool:
    """Whether a Newton stage is running into a point where its Jacobian is singular (a fold
    of the solution path in the continuation, no root nearby): its last ``TURN_STEPS`` steps
    each grew by ``TURN_GROWTH`` at least and each was cut by the line search to at most
    ``TURN_CUT``.

    Parameters
    ----------
    longest : sequence of float
        Each step's longest entry before the trust region's cut (edge lengths), in order.
    fractions : sequence of float
        The fraction of each step the line search took (1, ½, ¼, ...), in order.

    Why: near a root Newton's steps shrink and are taken whole; where the Jacobian turns
    singular they grow (towards its null direction) and the line search cuts them, and the
    stage then ends where no step lowers the residual (the continuation's solves near a fold:
    docs/convergence.md, session 35).
    """
    n = TURN_STEPS
    if len(longest) < n + 1 or len(fractions) < n:
        return False
    return all(longest[-i] >= TURN_GROWTH * longest[-i - 1] and fractions[-i] <= TURN_CUT
               for i in range(1, n + 1))
