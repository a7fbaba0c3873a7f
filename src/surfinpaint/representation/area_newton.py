"""Gauss–Newton on the rebuild equations together with the vertex areas λ prescribes.

The mesh form's rebuild equations ``L φ = M (2λ²H n + a e1 + b e2)`` use λ only through
2λ²H, and they have other solutions than the surface whose data they are: on the grid
export's finer levels (docs/representation.md, sessions 13–14) Newton's method from the
bicubic prolongation of the exact coarser solution converges to one of them (vertex areas off
by 0.5) or not at all, where the coarse grid under-resolves the surface. The vertex areas
``A(φ) = λ² A_uv`` are what tell the solutions apart (:func:`area_mismatch`), so this solver
appends them to the equations and minimizes ``‖R(φ)‖² + ‖(A(φ) − λ² A_uv) / √(λ² A_uv)‖²``
(both in units of length) by Gauss–Newton steps on the normal equations with a
backtracking line search. The system is consistent at the original (both parts vanish), so
Gauss–Newton converges there quadratically; once its step is short (``SWITCH`` of the
border's diagonal) plain Newton on the square equations finishes the solve, and the result
is kept only if its areas match λ's.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from surfinpaint.geometry.mesh import vertex_areas
from surfinpaint.representation.coupled_jacobian import voronoi_area_derivative
from surfinpaint.representation.mesh_lambda_h import (
    AREA_MATCH,
    NEWTON_STEPS,
    RebuildSystem,
    area_mismatch,
    rebuild_on_mesh,
)

__all__ = ["rebuild_with_areas"]

# Gauss–Newton steps shorter than this (of the border's diagonal) hand over to Newton
SWITCH = 1e-4
# the least-squares step's LSQR: tolerances and iterations (each two triangular solves)
LSQR_TOL = 1e-10
LSQR_ITERATIONS = 200


def rebuild_with_areas(start: np.ndarray, faces: np.ndarray, uv: np.ndarray, lam: np.ndarray,
                       H: np.ndarray, defect: np.ndarray, known: np.ndarray, *,
                       tol: float = 1e-10, budget: int = 30) -> tuple[np.ndarray, bool, int]:
    """Solve the rebuild equations for the unknown vertices from ``start``, the vertex areas
    λ prescribes appended (see the module's docstring).

    Parameters
    ----------
    start : (n, 3) float array
        Positions: the known ones are the boundary data, the others the start.
    faces, uv, lam, H, defect, known
        As for :func:`~surfinpaint.representation.mesh_lambda_h.rebuild_on_mesh` (λ finite
        wherever an area is compared: the vertices with a positive parameter area).
    tol : float
        Converged when a full step is shorter than ``tol`` times the known vertices'
        bounding-box diagonal.
    budget : int
        Sparse factorizations allowed (Gauss–Newton and Newton steps).

    Returns
    -------
    points : (n, 3) float array
    converged : bool
        A root of the equations whose vertex areas match λ's (within ``AREA_MATCH``).
    steps : int
        Factorizations used.
    """
    f = np.asarray(faces, dtype=np.int64)
    x = np.array(start, dtype=float, copy=True)
    unknown = ~np.asarray(known, dtype=bool)
    system = RebuildSystem(f, uv, lam, H, defect, unknown)
    free = np.flatnonzero(unknown)
    target = np.where(np.isfinite(lam), lam, 0.0) ** 2 * vertex_areas(uv, f)
    rows = target > 0
    root = np.sqrt(target[rows])
    scale = float(np.linalg.norm(np.ptp(x[~unknown], axis=0))) or 1.0

    def residual(y):
        areas = (vertex_areas(y, f)[rows] - target[rows]) / root
        return np.concatenate([system.residual(y, 1.0), areas])

    r = residual(x)
    for k in range(budget):
        J, _ = system.jacobian(x, 1.0)
        A = sp.diags(1.0 / root) @ voronoi_area_derivative(x, f, free)[rows]
        try:
            dx = _least_squares_step(J, A.tocsr(), r)
        except RuntimeError:  # exactly singular
            return x, False, k + 1
        step = float(np.abs(dx).max()) / scale
        if step < SWITCH:
            return _finish(x, f, uv, lam, H, defect, known, tol, budget - k - 1, k + 1)
        norm0, damping = np.linalg.norm(r), 1.0
        for _ in range(30):  # backtracking on the appended residual
            trial = x.copy()
            trial.ravel()[system.idx] += damping * dx
            r_trial = residual(trial)
            if np.isfinite(r_trial).all() and (np.linalg.norm(r_trial)
                                               < (1 - 1e-4 * damping) * norm0):
                break
            damping /= 2
        else:
            return x, False, k + 1
        x, r = trial, r_trial
    return x, False, budget


def _least_squares_step(J: sp.csc_matrix, A: sp.csr_matrix, r: np.ndarray) -> np.ndarray:
    """``argmin ‖J dx + r₁‖² + ‖A dx + r₂‖²`` (r = (r₁, r₂)): with z = J dx it is LSQR on
    ``[I; A J⁻¹]``, well conditioned where J is, one sparse LU of the square J (as a Newton
    step) instead of one of the normal equations (measured 9× slower on 554k unknowns)."""
    lu = spla.splu(J, permc_spec="MMD_AT_PLUS_A")
    m = J.shape[0]
    op = spla.LinearOperator(
        (m + A.shape[0], m), dtype=float,
        matvec=lambda z: np.concatenate([z, A @ lu.solve(np.ravel(z))]),
        rmatvec=lambda w: np.ravel(w)[:m] + lu.solve(A.T @ np.ravel(w)[m:], trans="T"))
    z = spla.lsqr(op, -r, atol=LSQR_TOL, btol=LSQR_TOL, iter_lim=LSQR_ITERATIONS)[0]
    return lu.solve(z)


def _finish(x, f, uv, lam, H, defect, known, tol, budget, used):
    """Newton on the square equations from a Gauss–Newton point close to the original."""
    if budget <= 0:
        return x, False, used
    solve = rebuild_on_mesh(x, f, uv, lam, H, defect, known, tol=tol,
                            max_iter=min(NEWTON_STEPS, budget), start=x, select_by_area=False)
    ok = solve.converged and area_mismatch(solve.points, f, uv, lam) <= AREA_MATCH
    return solve.points, ok, used + solve.iterations
