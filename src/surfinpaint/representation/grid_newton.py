"""The grid export's rebuild: the mesh form's equations on the grid's own triangles, solved
coarse to fine.

Every grid cell whose four nodes lie in the parameter domain is split into two triangles;
their cotangent Laplacian is the 5-point stencil. λ, H and the conformality defect of the
sampled φ on those triangles (:func:`~surfinpaint.representation.mesh_lambda_h.mesh_lambda_h`)
make the sampled φ an exact solution of the mesh form's equations
``L φ = M (2λ²H n + a e1 + b e2)`` (the tangential part of the grid Laplacian, which the
paper's ``Δh φ = 2λ²H n`` has no place for, is carried by the defect instead of forcing a
displacement). The same is done on the subgrids of every 2nd, 4th, ... node (the
*levels*, stored with the representation), so the sampled φ at their nodes solves their
equations too.

The rebuild (:func:`rebuild_nested`) solves the coarsest level from the harmonic surface
(:func:`~surfinpaint.representation.mesh_lambda_h.rebuild_on_mesh`: Newton, then the
arclength continuation) and then each finer level from the level below: its solution is
prolonged (:func:`prolong`, bicubic), the nodes the two levels share are held at the coarse
solution while Newton's method solves for the others, then all the level's unknown nodes are
released (one Newton check, a full solve only if the residual is not at rounding level).
Where the held-node Newton fails or (the level's own data) finds a solution whose vertex
areas do not match λ's, the held level is solved again from the prolonged start by
Gauss–Newton with the vertex areas appended
(:func:`~surfinpaint.representation.area_newton.rebuild_with_areas`; session 14: the
prolongation misses the sampled φ by 1–4 % of the diagonal where the coarse grid
under-resolves the surface, and Newton there went to another solution or none).
Measured (docs/representation.md, session 11): Newton from the prolonged start with every
node free went to another solution of the same equations on the 50 mm pial disk at 256²
(0.82 % of the diagonal away, its first step 1.2 % long from a start 0.36 % off); with the
shared nodes held it converged to 9e-14 in 8 steps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as spla

from surfinpaint.geometry.cutting import renumber
from surfinpaint.geometry.mesh import cotangent_laplacian
from surfinpaint.representation.area_newton import rebuild_with_areas
from surfinpaint.representation.grid import Grid, interpolate
from surfinpaint.representation.mesh_lambda_h import (
    AREA_MATCH,
    NEWTON_STEPS,
    area_mismatch,
    mesh_lambda_h,
    rebuild_on_mesh,
    relative_residual,
)

__all__ = ["GridLevel", "GridSolve", "grid_triangles", "harmonic_fill", "prolong",
           "rebuild_nested", "solve_finer_level", "solve_held", "triangle_levels"]

# the coarsest level has at least this many nodes along its long side
MIN_LEVEL = 48
# a level whose residual is below this (relative to |L φ|) after the held-node solve is
# taken as solved without a full Newton step
RESIDUAL_DONE = 1e-9
# factorizations for a held level's Gauss–Newton with the vertex areas, where Newton fails
AREA_STEPS = 30


@dataclass(frozen=True)
class GridLevel:
    """λ, H and the defect of the sampled φ on the triangles of the subgrid
    ``[::step, ::step]``.

    Attributes
    ----------
    step : int
    lam, H : (n, m) float arrays
        NaN off the level's triangles (H also on their border).
    defect : (n, m, 2) float array
    """

    step: int
    lam: np.ndarray
    H: np.ndarray
    defect: np.ndarray


@dataclass(frozen=True)
class GridSolve:
    """The outcome of :func:`rebuild_nested`: ``phi`` (N, M, 3), whether every level
    converged, the sparse factorizations in all, and a message."""

    phi: np.ndarray
    converged: bool
    iterations: int
    message: str


def grid_triangles(domain: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The triangles of a grid: each cell whose 4 nodes are in ``domain``, split along its
    (i, j)–(i+1, j+1) diagonal, counter-clockwise in (u, v).

    Returns
    -------
    nodes : (k,) int array
        Flat indices (``i * M + j``) of the nodes on some triangle.
    faces : (f, 3) int array
        Into ``nodes``.
    border : (k,) bool array
        Nodes on an edge of one triangle only.
    """
    N, M = domain.shape
    cell = domain[:-1, :-1] & domain[1:, :-1] & domain[1:, 1:] & domain[:-1, 1:]
    i, j = np.nonzero(cell)
    a, b, c, d = i * M + j, (i + 1) * M + j, (i + 1) * M + j + 1, i * M + j + 1
    f = np.vstack([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    nodes, f = renumber(f)
    e = np.sort(np.vstack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    key = e[:, 0] * max(len(nodes), 1) + e[:, 1]
    unique, count = np.unique(key, return_counts=True)
    once = unique[count == 1]
    border = np.zeros(len(nodes), dtype=bool)
    border[once // max(len(nodes), 1)] = True
    border[once % max(len(nodes), 1)] = True
    return nodes, f, border


def _node_uv(nodes: np.ndarray, M: int, spacing: float | Grid, step: int) -> np.ndarray:
    """Parameter coordinates (from the first node) of the flat ``nodes`` of the subgrid
    ``[::step, ::step]`` (``M`` columns), on a square grid of spacing ``spacing`` (a float
    or a :class:`Grid`) or on a graded :class:`Grid`."""
    i, j = nodes // M, nodes % M
    if isinstance(spacing, Grid) and spacing.graded:
        u, v = spacing.u[::step], spacing.v[::step]
        return np.column_stack([u[i] - u[0], v[j] - v[0]])
    h = spacing.h if isinstance(spacing, Grid) else spacing
    return np.column_stack([i, j]).astype(float) * (step * h)


def triangle_levels(phi: np.ndarray, domain: np.ndarray, known: np.ndarray,
                    spacing: float | Grid) -> tuple[GridLevel, ...]:
    """The levels of :func:`rebuild_nested`: steps 1, 2, 4, ... while the level has at
    least ``MIN_LEVEL`` nodes along its long side and its triangles' border nodes are all
    ``known`` (the rebuild's boundary data). ``spacing``: as :func:`rebuild_nested`
    takes it."""
    levels = []
    step = 1
    while True:
        dom = domain[::step, ::step]
        if step > 1 and max(dom.shape) < MIN_LEVEL:
            break
        nodes, f, border = grid_triangles(dom)
        if len(f) == 0 or (step > 1 and not known[::step, ::step].ravel()[nodes[border]].all()):
            break
        N, M = dom.shape
        p = phi[::step, ::step].reshape(-1, 3)[nodes]
        lam, H, defect = mesh_lambda_h(p, f, _node_uv(nodes, M, spacing, step))
        out = np.full((N * M, 4), np.nan)
        out[nodes, 0], out[nodes, 1], out[nodes, 2:] = lam, H, defect
        out = out.reshape(N, M, 4)
        levels.append(GridLevel(step, out[..., 0], out[..., 1], out[..., 2:].copy()))
        step *= 2
    return tuple(levels)


def prolong(coarse: np.ndarray, ratio: int, shape: tuple[int, int],
            nodes: np.ndarray) -> np.ndarray:
    """Values of a function given on the subgrid ``[::ratio, ::ratio]`` (``coarse``, NaN
    where unknown) at the fine grid's flat ``nodes``: bicubic (Catmull–Rom, exact at the
    shared nodes and for cubics) where the 4×4 coarse nodes around exist, bilinear where only
    the cell's corners do, NaN elsewhere."""
    Nc, Mc = coarse.shape[:2]
    grid = Grid((0.0, 0.0), float(ratio), (Nc, Mc))
    M = shape[1]
    ij = np.column_stack([nodes // M, nodes % M]).astype(float)
    return interpolate(coarse, grid, ij, order=3)


def harmonic_fill(x: np.ndarray, gap: np.ndarray, uv: np.ndarray, f: np.ndarray) -> None:
    """Fill ``x[gap]`` with the harmonic extension of the rest (in place)."""
    if not gap.any():
        return
    L = cotangent_laplacian(uv, f).tocsr()
    rest = ~gap
    x[gap] = spla.splu(L[gap][:, gap].tocsc()).solve(-(L[gap][:, rest] @ x[rest]))


def solve_held(start: np.ndarray, data: tuple, held: np.ndarray, tol: float,
                own: bool) -> tuple[np.ndarray, bool, int]:
    """A finer level with the nodes it shares with the coarser one held: Newton from the
    prolonged ``start``; where it fails, or (``own`` data) its solution's vertex areas do
    not match λ's, Gauss–Newton with the areas appended (:func:`rebuild_with_areas`) from
    the same start. Returns (φ, converged, factorizations)."""
    f, uv, lam, _, _ = data
    held_solve = rebuild_on_mesh(start, *data, held, tol=tol, max_iter=NEWTON_STEPS,
                                 start=start, select_by_area=False)
    x, ok, steps = held_solve.points, held_solve.converged, held_solve.iterations
    if ok and (not own or area_mismatch(x, f, uv, lam) <= AREA_MATCH):
        return x, ok, steps
    y, y_ok, more = rebuild_with_areas(start, *data, held, tol=tol, budget=AREA_STEPS)
    if y_ok or not ok:
        return y, y_ok, steps + more
    return x, ok, steps + more


def solve_finer_level(start: np.ndarray, data: tuple, known: np.ndarray, shared: np.ndarray,
                      tol: float, own: bool) -> tuple[np.ndarray, bool, int]:
    """A finer level from the coarser solution ``start`` (prolonged to its nodes): the
    ``shared`` nodes held (:func:`solve_held`), then all the unknown nodes released for a
    Newton check, a full solve only where the residual is not at rounding level
    (``RESIDUAL_DONE``). ``data`` = (faces, uv, λ, H, defect); ``known``: the boundary
    data. Returns (φ, converged, factorizations)."""
    f, uv, lam, H, defect = data
    x, ok, steps = solve_held(start, data, known | shared, tol, own)
    if not ok or relative_residual(x, f, uv, lam, H, defect, known) > RESIDUAL_DONE:
        free = rebuild_on_mesh(x, f, uv, lam, H, defect, known, tol=tol,
                               max_iter=NEWTON_STEPS, start=x, select_by_area=False)
        x, ok, steps = free.points, free.converged, steps + free.iterations
    return x, ok, steps


def rebuild_nested(levels: tuple[GridLevel, ...], phi: np.ndarray, domain: np.ndarray,
                   known: np.ndarray, spacing: float | Grid, *,
                   lam: np.ndarray | None = None,
                   H: np.ndarray | None = None, tol: float = 1e-10,
                   max_iter: int = 150) -> GridSolve:
    """φ on the grid from the levels' λ, H and defect with ``phi[known]`` as boundary data.

    Parameters
    ----------
    levels : tuple of GridLevel
        From :func:`triangle_levels`, finest (step 1) first.
    phi : (N, M, 3) float array
        Only read at ``known`` nodes.
    domain, known : (N, M) bool arrays
    spacing : float or Grid
        The square grid's spacing, or the grid itself (a graded one: its triangles are
        the cells of its unequal spacing; the prolongation between levels stays bicubic in
        node indices, only a start for the finer level's Newton).
    lam, H : (N, M) float arrays, optional
        Replace the finest level's λ and H (e.g. edited ones); the coarser levels then take
        them at their nodes (an approximate start only).
    tol, max_iter : float, int
        Newton's tolerance (relative to the border's diagonal) and the coarsest level's
        budget of factorizations (Newton, then the continuation); finer levels get
        ``NEWTON_STEPS`` Newton steps for the held-node solve and as many for the release.
    """
    N, M = domain.shape
    out = np.array(phi, dtype=float, copy=True)
    used, ok_all, parts = 0, True, []
    previous = None  # (coarse solution on its subgrid (n, m, 3), its step)
    mismatch = np.nan
    for level in reversed(levels):
        s = level.step
        dom = domain[::s, ::s]
        Ns, Ms = dom.shape
        nodes, f, border = grid_triangles(dom)
        uv = _node_uv(nodes, Ms, spacing, s)
        lv_known = border | known[::s, ::s].ravel()[nodes]
        p = phi[::s, ::s].reshape(-1, 3)[nodes].copy()
        p[~lv_known] = np.nan  # only the boundary data are read
        lv_lam, lv_H = level.lam.ravel()[nodes], level.H.ravel()[nodes]
        if lam is not None:
            lv_lam = np.asarray(lam, dtype=float)[::s, ::s].ravel()[nodes]
        if H is not None:
            lv_H = np.where(np.isfinite(lv_H), np.asarray(H, dtype=float)[::s, ::s].ravel()[nodes],
                            np.nan)
        defect = level.defect.reshape(-1, 2)[nodes]
        edited = lam is not None or H is not None
        if previous is None:
            sol = rebuild_on_mesh(p, f, uv, lv_lam, lv_H, defect, lv_known, tol=tol,
                                  max_iter=max_iter, select_by_area=not edited)
            x, ok, steps = sol.points, sol.converged, sol.iterations
        else:
            coarse, cs = previous
            ratio = cs // s
            start = prolong(coarse, ratio, (Ns, Ms), nodes)
            gi, gj = nodes // Ms, nodes % Ms
            shared = (gi % ratio == 0) & (gj % ratio == 0)
            shared &= np.isfinite(coarse[gi // ratio, gj // ratio]).all(axis=1)
            start[shared] = coarse[gi[shared] // ratio, gj[shared] // ratio]
            start[lv_known] = p[lv_known]
            harmonic_fill(start, ~np.isfinite(start).all(axis=1), uv, f)
            x, ok, steps = solve_finer_level(start, (f, uv, lv_lam, lv_H, defect), lv_known,
                                             shared, tol, not edited)
        used += steps
        ok_all &= bool(ok)
        mismatch = area_mismatch(x, f, uv, lv_lam)
        parts.append(f"{Ns}×{Ms}: {steps}")
        grid_x = np.full((Ns * Ms, 3), np.nan)
        grid_x[nodes] = x
        previous = (grid_x.reshape(Ns, Ms, 3), s)
        if s == 1:
            flat = out.reshape(-1, 3)
            flat[nodes] = x
    verdict = "converged" if ok_all else "did not converge"
    if ok_all and lam is None and H is None and np.isfinite(mismatch) \
            and mismatch > AREA_MATCH:
        # the levels' own data: a root whose vertex areas miss λ's is another solution of
        # the equations, not the surface (a cow's hoof cap at 128², graded: 3.1 % mean off
        # against its 0.035 % floor, areas 2.0 off)
        ok_all, verdict = False, "converged to another solution"
    message = (f"nested Newton on the grid's triangles {verdict} ({', '.join(parts)} "
               f"factorizations), vertex areas within {mismatch:.1e} of λ's")
    return GridSolve(out, ok_all, used, message)
