"""The λ-H solve's least-squares stage on a mesh patch, where the coupled solve
(:func:`surfinpaint.representation.on_mesh.inpaint_on_mesh`) finds no fixed point: a
continuation in the curvature term's weight from the harmonic fill, then Levenberg–Marquardt
steps on the fixed-point residual at the full weight (docs/convergence.md, sessions 11, 28,
38, 40).

Kept apart from :mod:`~surfinpaint.representation.on_mesh` because it is the failing path's
own stage: it runs only after the patch's (and the subdivided patch's) solves have failed, on
the same coupled system (:func:`~surfinpaint.representation.on_mesh.coupled_system`) and with
the same Newton solver (:func:`~surfinpaint.representation.on_mesh.newton_solve`).
"""

from __future__ import annotations

import numpy as np

from surfinpaint.errors import FillError
from surfinpaint.representation.blas_threads import blas_controller
from surfinpaint.representation.least_squares import levenberg_marquardt
from surfinpaint.representation.on_mesh import coupled_system, newton_solve
from surfinpaint.representation.weight_steps import CONTINUATION_SMALLEST, CONTINUATION_STEP

__all__ = ["continuation_ended", "curvature_continuation", "least_squares_on_mesh",
           "least_squares_steps_left_out"]

# the least-squares stage where Newton's method fails too (least_squares_on_mesh): Levenberg-
# Marquardt steps of at most LSQ_TRUST edge lengths, LSQ_STEPS steps, LSQ_JACOBIANS Jacobians
LSQ_TRUST = 2.0
LSQ_STEPS = 30
LSQ_JACOBIANS = 12
# ... and only on patches of at most LSQ_MAX_UNKNOWNS unknowns (3 a moved vertex): its Jacobian
# is dense, O(n^2) memory and O(n^3) time a solve (a scan's 374-edge hole, 6618 unknowns:
# 200 s and 350 MB a matrix; 1500 unknowns about 2 s). Every use on the tuning-side families
# (eggcrate, the coarse quadruped, the brain probes) had at most 282 (session 46)
LSQ_MAX_UNKNOWNS = 1500
# its continuation in the curvature weight (least_squares_on_mesh, stage 1): its steps in
# weight_steps (CONTINUATION_STEP, CONTINUATION_SMALLEST), at most this many solves
CONTINUATION_SOLVES = 60
CONTINUATION_NEWTON = 10
# its solves' envelope (as NEWTON_ENVELOPE's): 2.1 times the 28.3 * 0.6**k below which every
# continuation solve that converged on the tuning side stayed (convergence.md, session 28)
CONTINUATION_ENVELOPE = (60.0, 0.6)


def least_squares_on_mesh(
    points: np.ndarray,
    faces: np.ndarray,
    uv: np.ndarray,
    free: np.ndarray,
    *,
    natural: np.ndarray | None = None,
    tol: float = 1e-3,
    system=None,
    continued: list | None = None,
    smallest: float = CONTINUATION_SMALLEST,
) -> tuple[np.ndarray, float, float]:
    """The positions nearest to a fixed point of the coupled system of
    :func:`~surfinpaint.representation.on_mesh.inpaint_on_mesh`,
    where its solves find none: a local minimum of the fixed-point residual
    ``R(φ) = update(φ) − φ_f`` (in mean edge lengths), reached in two stages.

    1. Continuation in the curvature term's weight w (the rebuild ``L φ = w M 2λ²H n``):
       from the harmonic fill (w = 0) w is raised towards 1 in steps (first
       ``CONTINUATION_STEP``, doubled after a step Newton's method corrects, halved after
       one it cannot, down to ``CONTINUATION_SMALLEST``; at most ``CONTINUATION_SOLVES``
       corrections of ``CONTINUATION_NEWTON`` Newton steps each). Where the path reaches
       w = 1 that is a fixed point Newton's method from the start did not reach.
    2. Otherwise Levenberg–Marquardt steps on ``R`` at w = 1 from the surface at the largest
       w reached (:func:`~surfinpaint.representation.least_squares.levenberg_marquardt`;
       the residual's Jacobian analytic, the coupled system's ``jacobian``; each step at most
       ``LSQ_TRUST`` edge lengths, ``LSQ_STEPS`` steps and ``LSQ_JACOBIANS`` Jacobians at
       most). Left out on a patch of more than ``LSQ_MAX_UNKNOWNS`` unknowns
       (:func:`least_squares_steps_left_out`): the surface at the largest w is returned.

    Where the coupled system has no root near the start (the inpainted λ and H are not the
    data of a surface there: docs/convergence.md) this is the surface nearest to being one.

    Parameters are those of ``inpaint_on_mesh``, and ``continued``: stage 1 on
    ``system`` as far as it was made before (:func:`curvature_continuation`), taken on to its
    end here; ``smallest``: stage 1's smallest weight step (``CONTINUATION_SMALLEST``, or
    larger to give a stalled continuation up sooner: :func:`curvature_continuation`).

    Returns
    -------
    positions : (n, 3) float array
    residual : float
        ``R``'s largest entry at them, in mean edge lengths (at w = 1).
    weight : float
        The largest w the continuation reached.
    """
    points = np.asarray(points, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    free = np.asarray(free, dtype=bool)
    with blas_controller().limit(limits=1, user_api="blas"):
        system = (coupled_system(points, faces, uv, free, natural) if system is None
                  else system)
        if continued is None or not continued[4]:
            continued = _continuation(system, points, tol, continued, smallest=smallest)
        phi, weight = continued[:2]
        f, h = system.f, system.scale
        start = phi[f].copy()

        def residual(y):
            trial = phi.copy()
            trial[f] = start + h * y.reshape(-1, 3)
            try:
                return ((system.update(trial) - trial[f]) / h).ravel()
            except FillError:
                return np.full(y.size, np.nan)

        def jacobian(y, r):  # R's Jacobian in y: update's, minus the identity
            trial = phi.copy()
            trial[f] = start + h * y.reshape(-1, 3)
            J = system.jacobian(trial)
            J[np.diag_indices_from(J)] -= 1.0
            return J

        n = 3 * len(f)
        if weight >= 1.0 or least_squares_steps_left_out(len(f)):
            size = float(np.abs(residual(np.zeros(n))).max())
            return phi, size, weight
        out = levenberg_marquardt(residual, np.zeros(n), jacobian=jacobian, steps=LSQ_STEPS,
                                  jacobians=LSQ_JACOBIANS, max_step=LSQ_TRUST,
                                  tol=tol * 1e-2)
    phi = phi.copy()
    phi[f] = start + h * out.x.reshape(-1, 3)
    return phi, out.size, weight


def least_squares_steps_left_out(n_moved: int) -> str:
    """Why :func:`least_squares_on_mesh` leaves its Levenberg–Marquardt steps out on a patch
    of ``n_moved`` moved vertices ("" where it makes them): more than ``LSQ_MAX_UNKNOWNS``
    unknowns, whose dense Jacobian would take minutes and gigabytes (the stage's outcome is
    then the surface its continuation reached)."""
    n = 3 * n_moved
    return (f"its least-squares steps left out: {n} unknowns, more than {LSQ_MAX_UNKNOWNS}"
            if n > LSQ_MAX_UNKNOWNS else "")


def curvature_continuation(system, points: np.ndarray, tol: float = 1e-3, *,
                           solves: int | None = None, resume: list | None = None,
                           smallest: float = CONTINUATION_SMALLEST) -> list:
    """Stage 1 of :func:`least_squares_on_mesh` on a patch's coupled system
    (:func:`coupled_system`) from ``points``, or on from where ``resume`` (an earlier call's
    outcome) stopped; after ``solves`` more solves at most (and stopped there, to resume) or
    to its end. Returns ``[surface, weight reached, step, solves, ended]``: a weight of 1 is a
    fixed point of the coupled solve; continued to its end, the outcome is the same (to the
    bit) however often it was stopped and resumed.

    It ends where the weight step, halved after each failed solve, falls below ``smallest``
    (``CONTINUATION_SMALLEST``; larger with ``ConformalOptions.continuation_smallest``): the
    same path cut short, so its outcome is the default's wherever no solve the default makes
    after that point converges (:func:`continuation_ended`)."""
    with blas_controller().limit(limits=1, user_api="blas"):
        return _continuation(system, np.asarray(points, dtype=float), tol, resume, solves,
                             smallest)


def continuation_ended(weight: float, step: float, solves: int,
                       smallest: float = CONTINUATION_SMALLEST) -> bool:
    """Whether the continuation is over at ``weight`` with its next step ``step`` after
    ``solves`` solves: the full weight reached, the step below ``smallest``, or
    ``CONTINUATION_SOLVES`` made."""
    return weight >= 1.0 or step < smallest or solves >= CONTINUATION_SOLVES


def _continuation(system, points, tol, state=None, more=None, smallest=CONTINUATION_SMALLEST):
    """Stage 1 of :func:`least_squares_on_mesh`, :func:`curvature_continuation`'s state from
    the harmonic fill (or on from ``state``, at most ``more`` solves, until ``smallest``):
    ``system.curvature`` is 1 again after it."""
    try:
        if state is None:
            system.curvature = 0.0
            phi = points.copy()
            phi[system.f] = system.update(phi)  # the harmonic fill: no curvature term
            state = [phi, 0.0, CONTINUATION_STEP, 0, False]
        phi, weight, step, solves, _ = state
        last = CONTINUATION_SOLVES if more is None else min(solves + more, CONTINUATION_SOLVES)
        while not continuation_ended(weight, step, solves, smallest) and solves < last:
            trial = min(1.0, weight + step)
            system.curvature = trial
            solves += 1
            try:
                phi = newton_solve(system, phi, tol, CONTINUATION_NEWTON,
                                    CONTINUATION_ENVELOPE)
            except FillError:
                step /= 2.0
                continue
            weight = trial
            step *= 2.0
        ended = continuation_ended(weight, step, solves, smallest)
        return [phi, weight, step, solves, ended]
    finally:
        system.curvature = 1.0
