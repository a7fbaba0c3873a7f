"""λ-H inpainting on the patch's own conformal mesh (method.md §8, "mesh-native").

The grid pipeline (:func:`surfinpaint.fill.conformal.grid_pass.inpaint_patch`) resamples the
patch on a regular grid, estimates λ and H there, inpaints them on the hole region dilated past the
crease between the fill and the surface, and rebuilds. This module does the same on the
patch's triangles, with the parameter mesh's cotangent Laplacian as Δ:

- λ² at a vertex is the ratio of its 3D to its parameter-plane (Voronoi) area, and H follows
  from the Laplacian form of the structure equations, Δφ = 2λ²H n (method.md §4):
  ``H = n · (M_uv⁻¹ L_uv φ) / (2λ²)``;
- λ and H are inpainted biharmonically (``L M⁻¹ L``, method.md §5) over the fill's interior
  vertices;
- the rebuild solves ``L_uv φ = M_uv 2λ²H n`` there with every other vertex fixed.

The difference that matters (measured, docs/accuracy.md): λ and H at the vertices on the
hole's edge are not taken as data (the fill pollutes them) and not left free either; they
stay tied to the unknown positions, so the inpainting and the rebuild are solved as one
linear system for (φ, H) on the fill, with the normals and λ lagged and updated a few times.
That coupling is what makes the fill continue the surface's curvature across the hole's
edge; solved one after the other (inpaint, then rebuild) the same discretization is 2-3×
worse than bilaplacian fairing on the benchmark holes.

Where the lagged iteration diverges, its fixed point is found by Newton–Krylov steps on the
fixed-point residual, bounded in edge lengths and line-searched (docs/convergence.md); where
that fails too, the caller's last stage is the positions nearest a fixed point
(:mod:`surfinpaint.representation.least_squares_stage`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from surfinpaint.errors import FillError, how_many
from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.geometry.linalg import definite_lu
from surfinpaint.geometry.mesh import (
    laplacian_and_areas,
    mean_edge_length,
    vertex_adjacency,
    vertex_areas,
)
from surfinpaint.geometry.rows import rows_any
from surfinpaint.geometry.vertex_measures import vertex_normals_and_areas
from surfinpaint.representation.blas_threads import blas_controller
from surfinpaint.representation.coupled_jacobian import (
    UpdateDerivative,
    lagged_update_jacobian,
)
from surfinpaint.representation.krylov import gmres_cycle
from surfinpaint.representation.least_squares import AndersonMixing
from surfinpaint.representation.sparse_newton import newton_step
from surfinpaint.representation.vertex_lambda_h import border_vertices, vertex_lambda_h
from surfinpaint.representation.vertex_sets import ThinPatchError, coupled_vertex_sets

__all__ = ["ThinPatchError", "coupled_system", "inpaint_on_mesh", "newton_solve",
           "vertex_lambda_h"]

# a step longer than this many mean edge lengths means the lagged iteration diverges (it
# contracts by a factor of about 0.3-0.7 per step on the benchmark holes); one still longer
# than SETTLED after the last iteration means it has not settled
DIVERGED = 10.0
SETTLED = 1e-2
# steps mixed by Anderson acceleration (measured: a quarter fewer solves, same fills)
ANDERSON = 3
# Newton's method where the lagged iteration fails: each step at most TRUST mean edge
# lengths, GMRES to NEWTON_RTOL with up to GMRES_RESTART products, LINE_SEARCH halvings
TRUST = 2.0
NEWTON_RTOL = 1e-3
GMRES_RESTART = 60
LINE_SEARCH = 8
# Newton's steps solve with the update's dense analytic Jacobian up to this many free vertices,
# by GMRES on its exact matrix-free products above (the dense Jacobian's cost grows faster than
# an update's: CPU s 0.007 at 60 free vertices, 0.056 at 249, 0.39 at 584; sessions 13, 14)
NEWTON_ANALYTIC_MAX = 200
NEWTON_STEPS = 30
# a Newton stage whose residual after its k-th step is above NEWTON_ENVELOPE * RATE**k edge
# lengths is given up: every stage that converged on the tuning side (209 of 814) stayed below
# 81.7 * 0.85**k (2.2 times less). A failed stage changes nothing after it (the next starts
# where it started): only time is saved where it would have failed anyway (session 27)
NEWTON_ENVELOPE = 180.0
NEWTON_ENVELOPE_RATE = 0.85
# or above STALL_LEVEL edge lengths and STALL_RATIO of |R| STALL_STEPS steps before: converging
# stages fell by ≥ 7.6 % in 3 steps above 10, by < 1 % only below 4.3 (session 34, helper 2)
NEWTON_STALL_STEPS = 3
NEWTON_STALL_RATIO = 0.99
NEWTON_STALL_LEVEL = 10.0
# or, at any level, where its last NEWTON_FLAT_STEPS + 1 residuals lie within a factor
# NEWTON_FLAT_BAND of each other: no converging stage on the tuning side had more than 4 in a
# row within 1 % (animal5 #4's plateau at 1.36 edge lengths), failing ones creep so for 10-20
# steps to their last or to one no step lowers (docs/convergence.md, session 42 helper)
NEWTON_FLAT_STEPS = 6
NEWTON_FLAT_BAND = 1.01


def inpaint_on_mesh(
    points: np.ndarray,
    faces: np.ndarray,
    uv: np.ndarray,
    free: np.ndarray,
    *,
    iterations: int = 20,
    tol: float = 1e-3,
    relax: float | None = None,
    natural: np.ndarray | None = None,
    system: _CoupledSystem | None = None,
) -> np.ndarray:
    """Move the ``free`` vertices so that λ and H are biharmonic over them and the surface
    is rebuilt from them, the other vertices fixed.

    Unknowns are the free positions φ_f and H_f. Equations, with the parameter mesh's
    cotangent Laplacian ``L``, its Voronoi areas ``M`` and ``s = 2λ²``:

    - rebuild, at each free vertex: ``(L φ)_f = M_f s_f H_f n_f``;
    - inpainting of H: ``(L M⁻¹ L H)_f = 0``, where H at the fixed vertices next to a free
      one is ``n · (L φ) / (M s)``, linear in φ_f (these are the hole's edge: not data, and
      not free either);
    - λ over the free vertices: ``(L M⁻¹ L λ)_f = 0`` with λ at the others from their
      current areas.

    ``n`` and λ are taken from the current positions, and the linear system is solved again
    until the positions move by less than ``tol`` mean edge lengths (at most
    ``iterations`` times; the iteration contracts by about 0.3-0.7 per step). Each new
    solution is taken in full (``relax=1``) or in part; by default (``relax=None``) in
    full, and when that diverges or does not settle, once more from the start by halves
    with three times the iterations (needed on some folded brain patches), and when that
    fails too, the fixed point is found by Newton's method (:func:`newton_solve`: on
    strongly curved patches the iteration overshoots although a fixed point lies near
    the start).

    Parameters
    ----------
    points : (n, 3) float array
        Positions; the free ones are the start (e.g. a faired fill).
    faces : (f, 3) int array
        A disk, counter-clockwise in ``uv``.
    uv : (n, 2) float array
        Its conformal map; no flipped triangles.
    free : (n,) bool array
        Vertices to move; at least two rings of fixed vertices must lie between them and
        the disk's border.
    iterations, tol, relax :
        See above.
    natural : (n,) bool array, optional
        Border vertices the free ones may come close to: a crease the mesh was cut along
        (:mod:`surfinpaint.fill.creases`), fixed in position. H has no two-sided Laplacian
        there, so near the free vertices it is an unknown of the inpainting with natural
        boundary conditions (the biharmonic energy of the one side), and further out the
        mean of its inner neighbours' H.
    system : optional
        The patch's coupled system, :func:`coupled_system` of these arguments (made here
        when None).

    Returns
    -------
    (n, 3) float array
        New positions (equal to ``points`` at the fixed vertices).

    Raises
    ------
    FillError
        When the free vertices come too close to the border, the system is singular, the
        result is not finite, or the positions do not settle.

    Notes
    -----
    Follows method.md §4-§5 (Lui, Wen, Gu, *A Conformal Approach for Surface Inpainting*),
    discretized on the mesh as method.md §8 suggests, with the coupling above as the
    safeguard it asks for.
    """
    points = np.asarray(points, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    free = np.asarray(free, dtype=bool)
    if not free.any():
        return points.copy()
    attempts = [(relax, iterations)] if relax is not None else [(1.0, iterations),
                                                                 (0.5, 3 * iterations)]
    # the dense products here are small (tied ring × free vertices): OpenBLAS's threads
    # cost more than they give (measured: a bunny hole's fill 0.45-0.51 s with two
    # threads, 0.37 s with one)
    with blas_controller().limit(limits=1, user_api="blas"):
        system = _CoupledSystem(points, faces, uv, free, natural) if system is None else system
        for weight, steps in attempts:
            try:
                return _coupled_solve(system, points, steps, tol, weight)
            except _Unsettled as exc:
                failure = exc
        if relax is not None:
            raise FillError(str(failure)) from None
        try:
            return newton_solve(system, points, tol, NEWTON_STEPS)
        except _Unsettled as exc:
            raise FillError(f"{failure}; {exc}") from None


def coupled_system(points: np.ndarray, faces: np.ndarray, uv: np.ndarray, free: np.ndarray,
                   natural: np.ndarray | None = None) -> _CoupledSystem:
    """The coupled λ-H system of a patch (:func:`inpaint_on_mesh`'s arguments), for its
    solve and, where that fails, its least-squares stage
    (:func:`~surfinpaint.representation.least_squares_stage.least_squares_on_mesh`):
    the same matrices and factorizations, made once. Each solve sets what the system
    keeps (λ, the last update) from the positions it starts from, so either outcome is
    the one it has on a system of its own (session 37 helper).

    Raises
    ------
    FillError
        As :func:`inpaint_on_mesh` (a singular system, a patch too thin: ThinPatchError).
    """
    with blas_controller().limit(limits=1, user_api="blas"):
        return _CoupledSystem(np.asarray(points, dtype=float), np.asarray(faces, dtype=np.int64),
                              uv, np.asarray(free, dtype=bool), natural)


class _Unsettled(FillError):
    """The lagged iteration diverged or did not settle."""


class _CoupledSystem:
    """The coupled λ-H system of :func:`inpaint_on_mesh` on one patch: its matrices and
    factorizations, made once, and :meth:`update`, one lagged solve."""

    # the curvature term's weight: the rebuild solves L φ = curvature · M 2λ²H n
    curvature = 1.0

    def __init__(self, points, faces, uv, free, natural=None):
        self.points, self.faces = points, faces
        f = self.f = np.flatnonzero(free)
        fixed = np.flatnonzero(~free)
        L, area = laplacian_and_areas(uv, faces)
        self.area = area
        if (area <= 0).any():
            raise FillError("the parameter map has vertices with no area")
        Q = (L @ sp.diags(1.0 / area) @ L).tocsr()
        table = EdgeTable.build(faces)  # for the border and the edge length
        border = border_vertices(faces, table)
        on_natural = np.zeros(len(points), dtype=bool)
        if natural is not None:
            on_natural[border] = np.asarray(natural, dtype=bool)[border]
        A = vertex_adjacency(faces, len(points)).astype(np.int32)  # the mesh's, not L's
        reach, crease, self.tied, U, self.stencil = coupled_vertex_sets(A, f, border, on_natural)
        tied, stencil = self.tied, self.stencil
        self.n_crease = len(crease)
        Q_f, L_f, L_t = Q[U], L[f], L[tied]  # row slices, each made once
        Q_rows_f = Q_f if len(crease) == 0 else Q[f]  # U is f without a crease
        L_ff, L_fk = L_f[:, f].tocsc(), L_f[:, fixed]
        self.L_ff = L_ff  # (the Newton steps' L̃ = L_ff ⊗ I₃)
        L_tf, L_tk = L_t[:, f], L_t[:, fixed]
        Q_ff, self.Q_ft, self.Q_fs = Q_f[:, U].tocsc(), Q_f[:, tied], Q_f[:, stencil]
        self.Q_fk, self.fixed = Q_rows_f[:, fixed], fixed
        try:
            # L_ff (the stiffness matrix with the fixed vertices out) and Q's blocks are
            # definite: factored without pivoting (geometry.linalg.definite_lu)
            self.L_lu, self.Q_lu = definite_lu(L_ff), definite_lu(Q_ff)
            # λ has data on the crease (its one-sided areas): the plain biharmonic over f
            self.lam_lu = self.Q_lu if len(crease) == 0 else definite_lu(Q_rows_f[:, f])
        except RuntimeError as exc:  # SuperLU: exactly singular
            raise FillError(f"the λ-H system on the patch is singular: {exc}") from exc
        self.g = self.L_lu.solve(-(L_fk @ points[fixed]))
        self.Z_t = self.L_lu.solve(L_tf.T.toarray()).T  # L_tf L_ff⁻¹, (t, m)
        self.Y = self.Q_lu.solve(self.Q_ft.toarray())  # Q_ff⁻¹ Q_ft, (m, t)
        self.L_t_phi = L_tk @ points[fixed] + L_tf @ self.g  # (t, 3)
        self.scale = mean_edge_length(points, faces, table)
        areas = vertex_areas(points, faces)
        self.lam = np.sqrt(areas / area)
        self.natural_data = stencil[on_natural[stencil]]
        self.on_natural_stencil = on_natural[stencil]
        if len(self.natural_data):
            # on a crease H has no two-sided Laplacian: there it is the mean H of the
            # neighbours off the border, which the free vertices move (so it is lagged too)
            self.inner = np.ones(len(points))
            self.inner[border] = 0.0
            self.adjacency = A.astype(float)[self.natural_data]  # the mesh's neighbours
            self.weight = np.maximum(self.adjacency @ self.inner, 1.0)
        self.L = L
        self.H_stencil = self.stencil_H(points)
        # λ changes at the vertices whose faces touch a free one, the normals likewise
        self.moving = np.union1d(f, reach)
        self.near = faces[rows_any(np.isin(faces, self.moving))]

    def stencil_H(self, phi):
        """H at the stencil's data vertices from the positions ``phi`` (the same bits as from
        the whole patch's normals, areas and ``L φ``: each read vertex's own sums)."""
        read, faces, L_read = self._reads()
        H = np.zeros(len(phi))
        normals, areas = vertex_normals_and_areas(phi, faces)
        lam2 = areas[read] / self.area[read]
        H[read] = (np.einsum("ij,ij->i", L_read @ phi, normals[read])
                   / (2.0 * lam2 * self.area[read]))
        out = H[self.stencil]
        if len(self.natural_data):
            out[self.on_natural_stencil] = ((self.adjacency @ np.where(self.inner > 0, H, 0.0))
                                            / self.weight)
        return out

    _read = None  # (the adjacency, read, faces, L's rows) of _reads

    def _reads(self):
        """The vertices :meth:`stencil_H` reads H at (the stencil and, on a crease, the
        natural data's neighbours), the faces around them and L's rows there, made where the
        adjacency is new. Why: on a natural border H is made at every lagged solve, where the
        whole patch's normals and areas took about half of it (session 30)."""
        adjacency = getattr(self, "adjacency", None)
        if self._read is None or self._read[0] is not adjacency:
            read = (np.union1d(self.stencil, adjacency.indices) if len(self.natural_data)
                    else self.stencil)
            self._read = (adjacency, read, self.faces[rows_any(np.isin(self.faces, read))],
                          self.L[read])
        return self._read[1:]

    def update(self, phi):
        """The free positions solved with the normals and λ of the positions ``phi``."""
        return self._lagged(phi)[0]

    _last = None  # (curvature, positions, result) of the last _lagged

    def _lagged(self, phi):
        """:meth:`update` and its intermediates (for :meth:`jacobian`): the new free
        positions, the normals, s = 2λ², w_n, d_n, K, H on ``U`` and ``I + K Y``. The last
        call's again at its ``phi`` and curvature weight (Newton's steps and the
        least-squares stage take the Jacobian where the residual was just evaluated; λ is
        then in its state already: nothing else sets it). Callers must not change the arrays
        returned."""
        last = self._last
        if last is not None and last[0] == self.curvature and np.array_equal(last[1], phi):
            return last[2]
        out = self._lagged_solve(phi)
        self._last = (self.curvature, phi.copy(), out)
        return out

    def _lagged_solve(self, phi):
        f, tied, area, lam = self.f, self.tied, self.area, self.lam
        H_stencil = self.stencil_H(phi) if len(self.natural_data) else self.H_stencil
        normals, areas = vertex_normals_and_areas(phi, self.near)  # at the moving vertices
        m = self.moving
        lam[m] = np.sqrt(areas[m] / area[m])
        lam[f] = self.lam_lu.solve(-(self.Q_fk @ lam[self.fixed]))
        s = 2.0 * lam**2
        w_n = normals[tied] / (area[tied] * s[tied])[:, None]  # (t, 3)
        d_n = normals[f] * (area[f] * s[f])[:, None]  # (m, 3)
        if self.curvature != 1.0:  # the curvature term scaled (least_squares_stage)
            d_n = self.curvature * d_n
        # H at the tied ring = w_n · (L_tk φ_k + L_tf φ_f), φ_f = g + L_ff⁻¹ (d_n H)
        K = self.Z_t * (w_n @ d_n.T)  # Σ_c w_n,c Z_t d_n,c: (t, m)
        if self.n_crease:  # H on a crease: no φ
            K = np.hstack([K, np.zeros((len(tied), self.n_crease))])
        b = (-(self.Q_ft @ np.einsum("ij,ij->i", w_n, self.L_t_phi))
             - self.Q_fs @ H_stencil)
        y = self.Q_lu.solve(b)
        Y = self.Y
        # I + K Y, kept with the state: the Jacobians at these positions take it again
        # (0.35 ms a Newton–Krylov step at 681 free vertices; session 47 helper)
        C = np.eye(len(tied)) + K @ Y
        try:
            H = y - Y @ np.linalg.solve(C, K @ y)
        except np.linalg.LinAlgError as exc:
            raise FillError(f"the coupled λ-H system is singular: {exc}") from exc
        H_f = H[:len(f)]
        new = self.g + self.L_lu.solve(d_n * H_f[:, None])
        if not np.isfinite(new).all():
            raise FillError("the coupled λ-H solve is not finite")
        return new, (normals, s, w_n, d_n, K, H, C)

    def jacobian(self, phi):
        """The (3m, 3m) Jacobian of :meth:`update` in the free positions, analytic
        (:func:`~surfinpaint.representation.coupled_jacobian.lagged_update_jacobian`)."""
        return lagged_update_jacobian(self, phi)


def _coupled_solve(system, points, iterations, tol, relax):
    """The lagged iteration of :func:`inpaint_on_mesh` from ``points``, mixed by Anderson
    (``relax=1``) or relaxed by ``relax``."""
    f, scale = system.f, system.scale
    phi = points.copy()
    mixing = AndersonMixing(ANDERSON)
    step = np.inf
    for _ in range(iterations):
        new = system.update(phi)
        step = float(np.abs(new - phi[f]).max()) / scale
        if step > DIVERGED:
            raise _Unsettled(f"the λ-H fill diverges: a step of {step:.2g} edge lengths")
        if step < tol:
            phi[f] = new
            return phi
        if ANDERSON and relax == 1.0:
            phi[f] = mixing.mix(new, phi[f])
        else:
            phi[f] += relax * (new - phi[f])
    if step > SETTLED:
        raise _Unsettled(f"the λ-H fill does not settle: it still moves by {step:.2g} edge "
                        f"lengths after {iterations} iterations")
    return phi


def newton_solve(system, points, tol, steps, envelope=None):
    """The fixed point of the lagged iteration found by Newton's method where the iteration
    itself diverges: the residual ``R(φ_f) = update(φ) − φ_f`` (in mean edge lengths) is
    driven to zero by Newton steps, each bounded to ``TRUST`` edge lengths and halved until
    ``|R|`` decreases, and given up where ``|R|`` after step k is above
    ``A ρ^k`` (no converging stage was; ``envelope`` (A, ρ), by default ``NEWTON_ENVELOPE``
    and ``NEWTON_ENVELOPE_RATE``, which add :func:`_stalled`'s and :func:`_flat`'s tests). Each
    step is solved exactly with R's analytic Jacobian on patches of at most
    ``NEWTON_ANALYTIC_MAX`` free vertices (:func:`.sparse_newton.newton_step`), by one
    GMRES cycle on its exact products on larger ones (Newton–Krylov,
    :class:`.UpdateDerivative`, :func:`.krylov.gmres_cycle`).

    Why: on strongly curved patches (a white-matter sulcus, 1-2 edge lengths of curvature
    radius) the lagged map amplifies the smooth modes, so its first step overshoots by ten
    edge lengths although a fixed point lies one edge length from the start (measured).
    """
    f, h = system.f, system.scale
    x = points[f].copy()
    bound, rate = envelope or (NEWTON_ENVELOPE, NEWTON_ENVELOPE_RATE)

    def residual(x):
        phi = points.copy()
        phi[f] = x
        return ((system.update(phi) - x) / h).ravel()

    r = residual(x)
    sizes = []  # |R| before each step
    for k in range(steps):
        size = float(np.abs(r).max())
        if size < tol:
            break
        if k and size > bound * rate**k:
            raise _Unsettled(f"the λ-H fill does not settle under Newton's method: a residual "
                             f"of {size:.2g} edge lengths after {how_many(k, 'step', 'steps')}, "
                             "more than a converging stage has")
        if envelope is None and _stalled(sizes, size):
            raise _Unsettled(f"the λ-H fill does not settle under Newton's method: a residual "
                             f"of {size:.2g} edge lengths after {how_many(k, 'step', 'steps')}, "
                             "stalled "
                             f"(above {NEWTON_STALL_RATIO} of it {NEWTON_STALL_STEPS} before)")
        if envelope is None and _flat(sizes, size):
            raise _Unsettled(f"the λ-H fill does not settle under Newton's method: a residual "
                             f"of {size:.2g} edge lengths after {how_many(k, 'step', 'steps')}, "
                             f"flat (within {NEWTON_FLAT_BAND - 1:.0%} over the last "
                             f"{NEWTON_FLAT_STEPS})")
        sizes.append(size)
        if len(f) <= NEWTON_ANALYTIC_MAX:
            dx = newton_step(system, points, x, r)
        else:
            phi = points.copy()
            phi[f] = x
            dx, _ = gmres_cycle(UpdateDerivative(system, phi).residual_product, -r,
                                NEWTON_RTOL, GMRES_RESTART)
        longest = float(np.abs(dx).max())
        if longest > TRUST:
            dx *= TRUST / longest
        x, r = _line_search(residual, x, r, h * dx.reshape(-1, 3))
    else:
        if float(np.abs(r).max()) > SETTLED:
            raise _Unsettled(f"the λ-H fill does not settle under Newton's method: a "
                             f"residual of {np.abs(r).max():.2g} edge lengths after "
                             f"{how_many(steps, 'step', 'steps')}")
    phi = points.copy()
    phi[f] = x
    return phi


def _stalled(sizes, size):
    """Whether a Newton stage whose residual was ``sizes`` before its steps and is ``size`` now
    has stalled far from a root: above ``NEWTON_STALL_LEVEL`` edge lengths and
    ``NEWTON_STALL_RATIO`` of its value ``NEWTON_STALL_STEPS`` steps before."""
    return (len(sizes) >= NEWTON_STALL_STEPS and size > NEWTON_STALL_LEVEL
            and size > NEWTON_STALL_RATIO * sizes[-NEWTON_STALL_STEPS])


def _flat(sizes, size):
    """Whether a Newton stage whose residual was ``sizes`` before its steps and is ``size`` now
    has crept at one level: its last ``NEWTON_FLAT_STEPS`` + 1 residuals within a factor
    ``NEWTON_FLAT_BAND`` of each other, whatever the level (:func:`_stalled` needs a level
    and a fall over 3 steps)."""
    if len(sizes) < NEWTON_FLAT_STEPS:
        return False
    window = [*sizes[-NEWTON_FLAT_STEPS:], size]
    return max(window) <= NEWTON_FLAT_BAND * min(window)


def _line_search(residual, x, r, dx):
    """``x + t dx`` for the largest ``t`` in 1, ½, ¼, ... whose residual is smaller
    (Armijo), and its residual."""
    norm = float(np.linalg.norm(r))
    t = 1.0
    for _ in range(LINE_SEARCH):
        try:
            trial = residual(x + t * dx)
        except FillError:  # a step so long that the surface it gives is not finite
            trial = None
        if trial is not None and np.linalg.norm(trial) <= (1.0 - 1e-4 * t) * norm:
            return x + t * dx, trial
        t /= 2.0
    raise _Unsettled(f"the λ-H fill does not settle under Newton's method: no step "
                     f"lowers its residual of {np.abs(r).max():.2g} edge lengths")
