"""Damped Newton's method on the mesh rebuild's equations at a fixed data weight t.

Used by :func:`~surfinpaint.representation.mesh_lambda_h.rebuild_on_mesh` from the harmonic
surface and at each crossing of t = 1 of its arclength continuation
(:mod:`~surfinpaint.representation.continuation`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["damped_newton"]

# halvings of the step before the backtracking gives up
BACKTRACKS = 30


def damped_newton(system, phi: np.ndarray, t: float, tol: float, budget: int,
                  scale: float) -> tuple[np.ndarray, bool, int, float]:
    """Newton's method on ``system.residual(φ, t) = 0``, each step backtracked until the
    residual's norm falls.

    Converged when a full step is shorter than ``tol · scale`` (max-norm), or when no
    fraction of the step lowers a residual that is already at its rounding level
    (``system.rounding(φ, t)``): there the step is rounding amplified by the Jacobian's
    condition, and whether it is shorter than ``tol`` depends on the BLAS kernel's
    rounding. Measured (docs/representation.md, session 33): on a cap over a quadruped's
    leg the last step was 1e-10 on one kernel and longer on another, at the same residual
    (1.8e-12 against a rounding level of 7.8e-12), and the rebuild failed there.

    Parameters
    ----------
    system
        With ``residual(φ, t)``, ``jacobian(φ, t)`` (its first item, sparse, over the
        unknowns ``idx``), ``factorized(J)`` (a solver), ``idx`` and ``rounding(φ, t)``.
    phi : (n, 3) float array
        The start (not modified).
    t : float
    tol, scale : float
    budget : int
        Newton steps allowed.

    Returns
    -------
    phi : (n, 3) float array
    converged : bool
    steps : int
    last : float
        The last step taken, relative to ``scale`` (inf: none).
    """
    x = phi.copy()
    r = system.residual(x, t)
    last = np.inf
    for k in range(budget):
        J, _ = system.jacobian(x, t)
        try:
            dx = system.factorized(J)(-r)
        except RuntimeError:  # exactly singular
            return x, False, k + 1, last
        step = float(np.abs(dx).max()) / scale
        if step < tol:  # at rounding level the residual need not fall any more
            x.ravel()[system.idx] += dx
            return x, True, k + 1, step
        norm0 = np.linalg.norm(r)
        damping = 1.0
        for _ in range(BACKTRACKS):
            trial = x.copy()
            trial.ravel()[system.idx] += damping * dx
            r_trial = system.residual(trial, t)
            enough = np.linalg.norm(r_trial) < (1 - 1e-4 * damping) * norm0
            if np.isfinite(r_trial).all() and enough:
                break
            damping /= 2
        else:
            return x, bool(norm0 <= system.rounding(x, t)), k + 1, last
        x, r = trial, r_trial
        last = damping * step
    return x, False, budget, last
