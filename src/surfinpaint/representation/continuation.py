"""Pseudo-arclength continuation of the mesh rebuild from the harmonic surface.

The rebuild equations of :mod:`~surfinpaint.representation.mesh_lambda_h` with their data
scaled by t, ``G(φ, t) = L φ − t M F(φ) = 0``, have the harmonic surface as the solution at
t = 0 and the surface sought among the solutions at t = 1. Newton's method from the harmonic
surface does not reach it on caps (a tall finger, a cap over a bunny's ear): the surface has
to travel far from the plane. Stepping t from 0 to 1 (natural continuation) stalls where
the solution curve turns back in t (a fold, as for a spherical cap of prescribed mean
curvature beyond the hemisphere). Pseudo-arclength continuation (Keller 1977) follows the
curve by its length in (φ, t) instead, so it goes round folds:

- at a point y = (φ/D, t) of the curve (D the border's diagonal), the tangent τ solves
  ``[J G_t; τ_prevᵀ] τ = e_last``;
- the predictor y + Δs τ is corrected by chord-Newton steps on ``G = 0`` with the
  constraint ``τ_prev · (y − y_pred) = 0``, all with the one factorization of that
  bordered matrix at y;
- Δs grows when the corrector converges in a few steps and halves when it does not.

Each time the curve crosses t = 1, Newton's method at t = 1 from the crossing gives a
solution of the rebuild equations; the caller's ``accept`` decides whether it is the one
sought (the rebuild checks the vertex areas that λ prescribes, which the Laplacian form does
not use: with them the original is told apart from other solutions of the same equations).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from surfinpaint.errors import how_many

__all__ = ["Continuation", "arclength_continuation"]

# corrector: chord steps per attempt, the attempts (Δs halved each time) per step, and
# the step (relative to the border's diagonal) that ends it: the curve needs to be followed
# only closely enough for the next predictor; Newton's method polishes each crossing
CHORD_STEPS = 12
# a chord step longer than this times the previous one: the corrector is not contracting
CONTRACTION = 0.9
CORRECTED = 1e-6
# refactorizations of the bordered matrix per corrector attempt (see _correct)
REFACTOR = 2
ATTEMPTS = 10
# arclength step in units of (φ / border diagonal, t): first, and largest per unknown
# vertex (the cap is LARGEST_STEP √(unknown vertices) in the 2-norm over all of them, a
# root-mean-square motion of half the diagonal per vertex: an absolute cap of 0.5 held a
# 2589-vertex foot cap, whose tube travels ~2.5 diagonals, at the cap for 400 steps;
# benchmarks/represent_speed.py, docs/representation.md session 13)
FIRST_STEP = 0.05
LARGEST_STEP = 0.5


@dataclass(frozen=True)
class Continuation:
    """The outcome of :func:`arclength_continuation`.

    Attributes
    ----------
    points : (n, 3) float array
        The accepted solution at t = 1, or else the best solution found at a crossing (by
        ``accept``'s score), or else the last point of the curve.
    found : bool
        A crossing of t = 1 gave a solution that ``accept`` took.
    steps : int
        Continuation steps (one sparse factorization each) and Newton steps at the
        crossings, in all.
    crossings : int
        Times the curve crossed t = 1.
    t : float
        t at the last point of the curve.
    score : float
        ``accept``'s score of the returned points (inf when no crossing converged).
    message : str
    """

    points: np.ndarray
    found: bool
    steps: int
    crossings: int
    t: float
    score: float
    message: str


def _bordered(J: sp.spmatrix, g: np.ndarray, tau: np.ndarray) -> sp.csc_matrix:
    """``[[J, g], [τ_xᵀ, τ_t]]``."""
    return sp.bmat([[J, g[:, None]], [sp.csr_matrix(tau[None, :-1]),
                                      sp.csr_matrix([[tau[-1]]])]]).tocsc()


def arclength_continuation(system, start: np.ndarray, scale: float,
                           newton: Callable, score: Callable[[np.ndarray], float],
                           accept: float, budget: int) -> Continuation:
    """Follow ``system.residual(φ, t) = 0`` from ``start`` (a solution at t = 0) to t = 1.

    Parameters
    ----------
    system
        With ``residual(φ, t)`` (at the unknowns), ``jacobian(φ, t)`` (sparse, with
        respect to the unknowns, returned first of a pair) and ``idx`` (the unknowns'
        positions in ``φ.ravel()``).
    start : (n, 3) float array
    scale : float
        The length that makes φ comparable with t (the border's diagonal).
    newton : callable
        ``newton(φ) -> (φ, converged, steps)`` at t = 1.
    score : callable
        A converged solution's distance from the one sought (smaller is better).
    accept : float
        A score below this ends the continuation.
    budget : int
        Factorizations allowed (continuation steps plus Newton steps at crossings).
    """
    idx = system.idx

    def point(y):
        x = start.copy()
        x.ravel()[idx] = y[:-1] * scale
        return x

    def residual(y):
        return system.residual(point(y), y[-1]) / scale

    def t_derivative(x):
        return (system.residual(x, 1.0) - system.residual(x, 0.0)) / scale

    y = np.concatenate([start.ravel()[idx] / scale, [0.0]])
    tau = np.zeros_like(y)
    tau[-1] = 1.0
    ds, used, crossings = FIRST_STEP, 0, 0
    largest = LARGEST_STEP * np.sqrt(len(idx) / 3)
    best, best_score = None, np.inf
    e_last = np.zeros(len(y))
    e_last[-1] = 1.0
    def factor(z, row):
        """The bordered matrix at the point z with the constraint row ``row``, factored."""
        x = point(z)
        J = system.jacobian(x, z[-1])[0]
        return spla.splu(_bordered(J, t_derivative(x), row), permc_spec="MMD_AT_PLUS_A")

    while used < budget:
        x = point(y)
        try:
            lu = factor(y, tau)
        except RuntimeError:
            return _end(best, best_score, x, y, used, crossings, "the bordered matrix is "
                        "singular")
        used += 1
        new_tau = lu.solve(e_last)
        new_tau /= np.linalg.norm(new_tau)
        if new_tau @ tau < 0:
            new_tau = -new_tau
        corrected, chords, refactored = _correct(residual, lu, y, new_tau, tau, ds,
                                                 lambda z, row=tau: factor(z, row),
                                                 budget - used)
        used += refactored
        if corrected is None:
            return _end(best, best_score, x, y, used, crossings,
                        f"the corrector failed at t = {y[-1]:.3g}")
        ds = corrected[1]
        y_new = corrected[0]
        tau = new_tau
        if (y[-1] - 1.0) * (y_new[-1] - 1.0) <= 0 and y_new[-1] != y[-1]:
            crossings += 1
            w = (1.0 - y[-1]) / (y_new[-1] - y[-1])
            solution, ok, steps = newton(point(y + w * (y_new - y)))
            used += steps
            if ok:
                s = score(solution)
                if s < best_score:
                    best, best_score = solution, s
                if s < accept:
                    return Continuation(solution, True, used, crossings, 1.0, s,
                                        f"crossing {crossings} of t = 1 accepted")
        y = y_new
        ds = min(ds * 1.5, largest) if chords <= 4 else ds / 1.5 if chords >= 7 else ds
    return _end(best, best_score, point(y), y, used, crossings, "the step budget ran out")


def _correct(residual, lu, y, tau, tau_row, ds, factor, budget):
    """Chord-Newton from the predictor ``y + ds τ``, with the bordered matrix refactored
    at the current point (a Newton step) when the chord steps stop contracting, at most
    ``REFACTOR`` times per attempt and ``budget`` times in all; Δs halved on failure.

    Returns ((point, Δs), steps, refactorizations), or (None, 0, refactorizations).
    Why the refactorization: on the cow's hoof cap (PyMeshLab's cow, a validation mesh
    since dropped from the benchmark) the predictor lands within 3e-5 of the curve
    (in φ / diagonal) and yet the chord steps grow, so the chord corrector alone held Δs
    near 0.05 (800 factorizations reached t = 0.6); Newton steps from the same predictor
    converge (measured, docs/representation.md).
    """
    refactored = 0
    for _ in range(ATTEMPTS):
        predicted = y + ds * tau
        z = predicted.copy()
        solver, previous, fresh = lu, np.inf, 0
        for k in range(CHORD_STEPS):
            r = np.concatenate([residual(z), [tau_row @ (z - predicted)]])
            if not np.isfinite(r).all():
                break
            d = solver.solve(-r)
            size = float(np.abs(d).max())
            if size > CONTRACTION * previous:  # the chord iteration is not contracting
                if fresh == REFACTOR or refactored == budget:
                    break
                try:
                    solver = factor(z)
                except RuntimeError:
                    break
                fresh += 1
                refactored += 1
                d = solver.solve(-r)
                size = float(np.abs(d).max())
            z = z + d
            previous = size
            if size < CORRECTED:
                # a refactorization counts as the slow convergence it replaced
                return (z, ds), min(k + 1 + fresh, 6), refactored
        ds /= 2
    return None, 0, refactored


def _end(best, best_score, x, y, used, crossings, why):
    if best is not None:
        return Continuation(best, False, used, crossings, float(y[-1]), best_score,
                            f"{why}; the best of {how_many(crossings, 'crossing', 'crossings')} "
                            "of t = 1 returned")
    return Continuation(x, False, used, crossings, float(y[-1]), np.inf,
                        f"{why} (t = {y[-1]:.3g}, "
                        f"{how_many(crossings, 'crossing', 'crossings')} of t = 1)")
