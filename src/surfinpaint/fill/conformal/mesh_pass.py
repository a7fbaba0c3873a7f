"""The mesh discretization of one λ-H pass, the default: λ and H live on the patch's own
triangles, and inpainting and rebuild are solved together so that the curvature at the
hole's edge stays tied to the positions (:mod:`surfinpaint.representation.on_mesh`)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from surfinpaint.errors import FillError, how_many
from surfinpaint.fill.conformal.checks import fold_count
from surfinpaint.fill.conformal.lattice import LatticeScale, lattice_patch, tutte_positions
from surfinpaint.fill.conformal.patch import grown_patch, hole_patch, hole_patch_and_boundary
from surfinpaint.fill.creases import cut_along
from surfinpaint.fill.results import LeastSquaresFill, MeshLambdaH
from surfinpaint.geometry import mean_value, parameterization
from surfinpaint.geometry.cutting import renumber
from surfinpaint.geometry.mesh import (
    boundary_halfedges,
    connected_components,
    edge_faces,
    unique_edges,
)
from surfinpaint.representation.grid_represent import smooth_subdivision
from surfinpaint.representation.least_squares_stage import (
    CONTINUATION_SMALLEST,
    curvature_continuation,
    least_squares_on_mesh,
    least_squares_steps_left_out,
)
from surfinpaint.representation.on_mesh import ThinPatchError, coupled_system, inpaint_on_mesh

__all__ = ["inpaint_patch_on_mesh"]

# the fewest rings of surface a patch keeps where the conformal map flips triangles
MIN_RINGS = 3
# the least-squares stage's fill is kept only where the λ-H update moves it by at most this
# many mean edge lengths (the bound on one of its steps, least_squares_stage.LSQ_TRUST):
# further from a fixed point it is not a λ-H fill (docs/convergence.md, session 11)
LEAST_SQUARES_RESIDUAL = 2.0
# where the coupled solve fails on the patch, the least-squares stage's continuation is made
# first while each of its solves converges, at most this many (and on after the subdivided
# patch's solve where that fails, if its first solve failed: continuation_resumed). Of its
# 12 runs that reached the full weight on the tuning side, 6 did so with every solve
# converging (4 solves each: cbblock #4, brain pial #4, #10, white #15, quad v480 r2.0, v149
# r3.5), and their subdivided patch's solve failed (the fill is main's); animal5 #4's
# reached it after a failed first solve where the subdivided patch's converged, and writing
# the continuation's fixed point there was 2.3 times worse (docs/convergence.md, session 38)
CONTINUATION_FIRST = 8
# with ConformalOptions.skip_stalled_subdivision, the subdivided patch's solve is not tried
# on a patch of at least this many free vertices where that continuation raised the weight
# and then stalled (subdivision_skipped; between the tuning side's largest patch where it
# converged, 82, and its smallest where it failed, 94: sessions 44 and 48 helpers)
SUBDIVIDED_SKIP_FREE = 90
# where that fails too, the patch resampled on a regular lattice of its map, of these
# spacings (per mean map edge of the fill) in turn (:func:`_on_lattice`)
LATTICE_PER_EDGE = (2.0, 1.0, 4.0)


def inpaint_patch_on_mesh(
    vertices: np.ndarray,
    faces: np.ndarray,
    loop: np.ndarray,
    fill_faces: np.ndarray,
    moving: np.ndarray,
    *,
    rings: int = 4,
    iterations: int = 20,
    tol: float = 1e-3,
    cut_edges: np.ndarray | None = None,
    subdivide: bool = True,
    lattice_after: str = "",
    skip_stalled_subdivision: bool = False,
    continuation_smallest: float = CONTINUATION_SMALLEST,
) -> tuple[np.ndarray, np.ndarray, int, MeshLambdaH]:
    """λ-H inpainting of a filled hole on its patch's own triangles
    (:func:`surfinpaint.representation.on_mesh.inpaint_on_mesh`).

    The patch is the fill plus ``rings`` face rings of the surface around the hole, mapped by
    LSCM; where that map flips or squashes a triangle the patch loses a ring, down to 3
    rings, and then its bad triangles are untangled (:func:`_mapped_patch`). Where the
    coupled solve fails on the patch, it is solved again on the patch split once into four
    onto its smooth interpolant, and where that fails too, the positions nearest a fixed
    point are taken if they are near enough (:func:`_solve_or_subdivide`; neither with
    ``subdivide=False``). With
    ``cut_edges`` (a crease across the hole, :func:`surfinpaint.fill.creases.split_fill`) the
    mesh is cut open along them first and each side of the crease is a patch of its own,
    the crease its fixed border.

    Parameters
    ----------
    vertices : (n, 3) float array
        Positions of the mesh's vertices followed by the fill's new ones.
    faces : (f, 3) int array
        The mesh's faces (without the fill).
    loop : (k,) int array
        The hole's boundary loop.
    fill_faces : (p, 3) int array
        The fill's faces.
    moving : (m,) int array
        Vertex ids to move (the fill's interior vertices).
    rings : int
        Face rings of the surface in the patch.
    iterations, tol :
        Updates of the normals and λ in the coupled solve, and the step (in mean edge
        lengths) below which it stops.
    cut_edges : (c, 2) int array, optional
        Edges to cut along (see above).
    subdivide : bool
        Retry a failed solve on the subdivided patch (False for a self-check test hole: a
        fill that fails there says nothing, and the retry cost 5-8 s a hole, measured).
    lattice_after : str, optional
        Solve on the regular lattice of the patch's map straight away (:func:`_on_lattice`),
        because the fill made on the patch's own triangles was rejected for this reason
        (a fold-over at every damping step: the caller's retry,
        :meth:`surfinpaint.fill.conformal.candidates.Candidates.lambda_h`). Not on the
        sides of a crease.
    skip_stalled_subdivision : bool
        The subdivided patch's solve left out where :func:`subdivision_skipped` says
        (``ConformalOptions.skip_stalled_subdivision``).
    continuation_smallest : float
        The least-squares stage's continuation ends where its weight step falls below this
        (``ConformalOptions.continuation_smallest``).

    Returns
    -------
    positions : (m, 3) float array
        New positions of ``moving``.
    patch_faces : (p', 3) int array
        The patch used (fill faces first).
    rings : int
        The rings used (with a crease, the fewest of its sides).
    lambda_h : MeshLambdaH
        The patch's map and its positions before and after (with a crease, of its side
        with the larger fill), from which the report draws λ and H.

    Raises
    ------
    FillError
        When the map flips triangles even with 3 rings, or the coupled solve fails.
    """
    moving = np.asarray(moving, dtype=np.int64)
    if cut_edges is None:
        return _inpaint_piece(vertices, faces, loop, fill_faces, moving, rings=rings,
                              iterations=iterations, tol=tol, subdivide=subdivide,
                              lattice_after=lattice_after,
                              skip_stalled_subdivision=skip_stalled_subdivision,
                              continuation_smallest=continuation_smallest)
    if lattice_after:
        raise FillError(f"{lattice_after}; no lattice on the sides of a crease")
    return _inpaint_crease_sides(vertices, faces, fill_faces, moving, cut_edges, rings=rings,
                                 iterations=iterations, tol=tol)


def _inpaint_crease_sides(vertices, faces, fill_faces, moving, cut_edges, *, rings,
                          iterations, tol):
    """:func:`inpaint_patch_on_mesh` with ``cut_edges``: the mesh cut open along the crease
    and each side of it inpainted as a patch of its own (:func:`_inpaint_piece`, the larger
    fill first), the crease a natural border. The patch returned is the fill's faces and
    every side's rings of surface (each face once, in the order first met)."""
    cut, parent = cut_along(np.vstack([fill_faces, faces]), cut_edges)
    cut_fill, cut_known = cut[:len(fill_faces)], cut[len(fill_faces):]
    points = vertices[parent]
    free = np.isin(parent, moving)
    natural = np.isin(parent, cut_edges)
    _, label = connected_components(cut_fill, len(parent))
    side = label[cut_fill[:, 0]]
    positions = vertices[moving].copy()
    order = np.argsort(moving)
    ring_faces, used, first = [], rings, None
    for piece in sorted(np.unique(side), key=lambda s: -(side == s).sum()):
        piece_fill = cut_fill[side == piece]
        piece_moving = np.unique(piece_fill[free[piece_fill]])
        seeds = np.unique(piece_fill[~free[piece_fill]])
        new, patch, piece_rings, lambda_h = _inpaint_piece(
            points, cut_known, seeds, piece_fill, piece_moving, rings=rings,
            iterations=iterations, tol=tol, natural=natural)
        positions[order[np.searchsorted(moving[order], parent[piece_moving])]] = new
        ring_faces.append(parent[patch[len(piece_fill):]])
        first = first or lambda_h
        used = min(used, piece_rings)
    rings_all = np.unique(np.sort(np.vstack(ring_faces), axis=1), axis=0, return_index=True)[1]
    ring_faces = np.vstack(ring_faces)[np.sort(rings_all)]
    first = replace(first, one_side=True)
    return positions, np.vstack([fill_faces, ring_faces]), used, first


def _inpaint_piece(vertices, faces, seeds, fill_faces, moving, *, rings, iterations, tol,
                   natural=None, subdivide=False, lattice_after="",
                   skip_stalled_subdivision=False,
                   continuation_smallest=CONTINUATION_SMALLEST):
    """:func:`inpaint_patch_on_mesh` of one patch, grown from ``seeds`` over ``faces``.

    Where the patch is too thin for the biharmonic stencil (its rings stopped short, e.g.
    around a thin limb) it is grown unevenly instead (:func:`grown_patch`), and where even
    that one is too thin its whole border is taken as natural."""
    # the surface's own border is a natural border of the patch, as a crease is: H has no
    # two-sided Laplacian there, so a hole near it is inpainted with natural boundary
    # conditions instead of giving up because the patch is too thin
    on_border = np.zeros(len(vertices), dtype=bool)
    on_border[boundary_halfedges(faces).ravel()] = True
    on_border[seeds] = False  # the hole's own loop, which the fill closes
    if natural is not None:
        on_border |= natural
    # (grown unevenly, whole border natural): measured on thin tori, the grown patch is
    # 0.61-0.91x the error of the shrunk one with its border natural (docs/convergence.md)
    mapped = {}  # the last try takes the grown patch and its map again: made once
    for grow, all_natural in ((False, False), (True, False), (True, True)):
        if grow not in mapped:
            mapped[grow] = _mapped_patch(vertices, faces, seeds, fill_faces, rings, grow=grow)
        patch, ids, local, uv, used, map_name = mapped[grow]
        free = np.isin(ids, moving)
        points = vertices[ids]
        # the patch's whole border natural: which it is not, but H near it is left to
        # the inpainting instead of giving up
        natural_ids = np.ones(len(ids), dtype=bool) if all_natural else on_border[ids]
        try:
            if lattice_after:
                new_points, lattice = _on_lattice(points, local, uv, free, len(fill_faces),
                                                  natural_ids, iterations, tol, lattice_after)
                least_squares = LeastSquaresFill(np.nan, np.nan, lattice_after,
                                                 lattice=lattice, folded=lattice_after)
            else:
                new_points, least_squares = _solve_or_subdivide(
                    points, local, uv, free, len(fill_faces), natural_ids, iterations, tol,
                    subdivide, skip_stalled_subdivision, continuation_smallest)
            break
        except ThinPatchError:
            if all_natural:
                raise
    lambda_h = MeshLambdaH(uv=uv, faces=local, n_fill_faces=len(fill_faces), free=free,
                           before=points, after=new_points, map=map_name,
                           least_squares=least_squares)
    return new_points[np.searchsorted(ids, moving)], patch, used, lambda_h


def _solve_or_subdivide(points, local, uv, free, n_fill, natural, iterations, tol,
                        subdivide, skip_stalled_subdivision=False,
                        continuation_smallest=CONTINUATION_SMALLEST):
    """The coupled solve on the patch, and where it fails (not for want of rings), on the
    patch split once into four onto its smooth interpolant (:func:`_subdivided`), read back
    at the patch's own vertices.

    Why: where the surface's curvature radius is 1-2 edge lengths (an egg-crate of period
    5-8 edges, a white-matter sulcus) the lagged iteration and Newton's method from the
    start find no fixed point on the patch; with its edges halved the same solve converges
    on 10 of the 18 such holes of ``benchmarks/eggcrate.py`` (docs/convergence.md). Only
    tried where the solve failed and the hole would fall back (``subdivide``): not on the
    sides of a crease, whose failure has its own fallback (the hole filled as a smooth one),
    so every fill that worked before is unchanged.

    Where that fails too, the next stage: the patch's positions nearest to a fixed point
    (:func:`~surfinpaint.representation.least_squares_stage.least_squares_on_mesh`: a
    continuation in
    the curvature weight from the harmonic fill, then least squares at full weight, on the
    patch itself), kept where their residual is at most
    ``LEAST_SQUARES_RESIDUAL`` edge lengths. Measured (docs/convergence.md, session 11):
    the coupled system has no root near the start on most such holes (the inpainted λ and
    H are no surface's data there); this fills the 8 egg-crate holes that fell back (0.45-
    1.76 of the bilaplacian fill's error, median 0.78) and halves the fallbacks on the
    coarse quadruped and the brain probes. Where their residual is larger, the last stage
    before a fallback: the coupled solve on the patch resampled on a regular lattice of its
    map (:func:`_on_lattice`).

    That stage's continuation is made first while its solves converge
    (:func:`continuation_paused`; session 38): where it runs straight to the full curvature
    weight, its surface is a fixed point of the patch's own solve, and the subdivided patch's
    solve (0.3 s on the CAD tuning part cbblock #4, failing) is not made; otherwise the
    subdivided patch is tried as before and, where that fails too, the continuation goes on
    from where it stopped (the same surface as made in one go) and least squares from its end,
    except where it stopped at a fold after raising the weight: least squares from there
    (:func:`continuation_resumed`; session 40). It ends where its weight step falls below
    ``continuation_smallest`` (session 49 helper).

    Returns
    -------
    positions : (n, 3) float array
    least_squares : LeastSquaresFill or None
        Set when the positions are the least-squares stage's or the lattice's
        (``lattice`` set).
    """
    system = None  # the patch's coupled system, made once for the solve and the last stage
    try:
        if free.any():
            system = coupled_system(points, local, uv, free, natural)
        return inpaint_on_mesh(points, local, uv, free, iterations=iterations, tol=tol,
                               natural=natural, system=system), None
    except ThinPatchError:
        raise
    except FillError as coarse:
        if not subdivide:
            raise
        failure = str(coarse)
        # the last stage's continuation first: where it reaches the full weight, its surface is
        # the patch's fixed point and the subdivided patch's solve is not needed (session 38)
        continued, stalled = ((None, False) if system is None
                              else _continued_first(system, points, tol, continuation_smallest))
        if (skip_stalled_subdivision and continued is not None
                and subdivision_skipped(continued[1], stalled, len(system.f))):
            failure = (f"{coarse}; the subdivided patch not tried (the continuation stalled "
                       f"at the curvature weight {continued[1]:.2g})")
        elif continued is None or continued[1] < 1.0:
            fine = _subdivided(points, local, uv, free, n_fill, natural)
            try:
                out = inpaint_on_mesh(fine[0], fine[1], fine[2], fine[3],
                                      iterations=iterations, tol=tol, natural=fine[4])
            except FillError as exc:
                failure = f"{coarse}; on the patch subdivided once: {exc}"
            else:
                return out[:len(points)], None
    if continued is not None and not continuation_resumed(continued[1], stalled):
        continued = [*continued[:4], True]  # ended: least squares from where it stopped
    positions, residual, weight = least_squares_on_mesh(points, local, uv, free,
                                                        natural=natural, tol=tol, system=system,
                                                        continued=continued,
                                                        smallest=continuation_smallest)
    if residual <= LEAST_SQUARES_RESIDUAL:
        return positions, LeastSquaresFill(residual, weight, failure)
    left_out = least_squares_steps_left_out(int(free.sum()))
    reached = f"curvature weight {weight:.2g} reached" + (f"; {left_out}" if left_out else "")
    failure = (f"{failure}; the least-squares stage ends at a residual of {residual:.2g} "
               f"edge lengths ({reached})")
    positions, lattice = _on_lattice(points, local, uv, free, n_fill, natural, iterations,
                                     tol, failure)
    return positions, LeastSquaresFill(residual, weight, failure, lattice=lattice)


def _continued_first(system, points, tol, smallest=CONTINUATION_SMALLEST):
    """The least-squares stage's continuation on ``system`` (:func:`curvature_continuation`),
    solve by solve, until it ends or :func:`continuation_paused` says to try the subdivided
    patch first; its state, to resume, and whether it stopped at a failed solve."""
    state, failures = None, 0
    while True:
        before = 0.0 if state is None else state[1]
        state = curvature_continuation(system, points, tol, solves=1, resume=state,
                                       smallest=smallest)
        failures += state[1] <= before  # a solve that converged raised the weight
        if state[4] or continuation_paused(state[3], failures):
            return state, failures > 0


def continuation_paused(solves: int, failures: int) -> bool:
    """Whether the continuation made before the subdivided patch's solve stops there, after
    ``solves`` solves of which ``failures`` failed: at the first failure (where its path
    does not run straight to weight 1, the subdivided patch's fill comes first), or after
    ``CONTINUATION_FIRST`` solves."""
    return failures > 0 or solves >= CONTINUATION_FIRST


def subdivision_skipped(weight: float, stalled: bool, n_free: int) -> bool:
    """Whether the subdivided patch's solve is left out (with
    ``ConformalOptions.skip_stalled_subdivision``) on a patch of ``n_free`` free vertices
    after the continuation made first stopped at ``weight`` (``stalled``: at a failed solve):
    where it raised the weight and then stalled (where it is not taken on either,
    :func:`continuation_resumed`: least squares starts where it stopped) on a patch of at
    least ``SUBDIVIDED_SKIP_FREE`` free vertices.

    Why: there the subdivided patch's solve is the failing path's costliest stage (0.05-0.27 s
    of CPU, up to 40 % of the slowest holes' fill) and on the tuning side it never
    converged: of the patches of at least 50 free vertices where it ran after such a stall
    (the five tuning-side sets' 409 holes, the egg-crate, quadruped and brain families, spent
    holdouts 18-19; docs/convergence.md, session 44 helper) it failed on the four of 94-157
    free vertices (brain white #14, CAD channel #5, lathe_dog #6, junction_box #6) and
    converged on two of 53 and 82 (brain white #17, #22; least squares from the stall 0.89
    and 1.31 times its error there), which the threshold keeps out (session 48 helper)."""
    return stalled and 0.0 < weight < 1.0 and n_free >= SUBDIVIDED_SKIP_FREE


def continuation_resumed(weight: float, stalled: bool) -> bool:
    """Whether the continuation made before the subdivided patch's solve is taken on after
    that solve fails too, from ``weight`` where it stopped (``stalled``: at a failed solve):
    not where it stalled after raising the weight (a fold of its path; Levenberg–Marquardt
    starts where it stopped), else yes.

    Why: there it goes on bisecting its step at the fold down to ``CONTINUATION_SMALLEST``,
    most of those solves failing (CAD channel #5: 14 more solves, a third of a second, for
    0.07 more weight), and least squares from where it stopped is as close to the truth on
    the tuning side's 11 such holes (CAD channel #5, ribplate #2, 7 egg-crates, brain white
    #14, quad v361 r3.5: 0.47-1.01 times the error of the fill made before; channel #5 0.68
    times the CPU; docs/convergence.md, session 40). Where its first solve failed (weight
    0), taken on, it creeps from the harmonic fill to surfaces least squares does not find
    from there (brain white #5: 2.2 % against 3.3 % without, quad v501 r2.0: 4.0 % against
    12.8 %): as before."""
    return weight <= 0.0 or not stalled


def _on_lattice(points, local, uv, free, n_fill, natural, iterations, tol, failure):
    """The coupled solve on the patch resampled on an equilateral lattice of its map
    (:func:`~surfinpaint.fill.conformal.lattice.lattice_patch`), of the spacings
    ``LATTICE_PER_EDGE`` in turn, read back at the patch's free vertices; and the number of
    the lattice's free vertices.

    Why: on a coarse CAD tessellation (the built quadruped) the patch's triangles are
    slivers (parameter angles 0.01-179°, negative cotangent weights on 10-20 % of the
    edges), their subdivision keeps their shapes, and the coupled system on either has no
    root near the start (docs/convergence.md, session 14). On the lattice it converges on
    7 of the quadruped's 8 such holes (session 23). Not on a patch with a natural border
    (a crease, the surface's own border), which the lattice does not carry.

    Raises
    ------
    FillError
        ``failure`` and why the lattice failed too.
    """
    if natural is not None and np.asarray(natural).any():
        raise FillError(f"{failure}; no lattice on a patch with a natural border")
    reasons, spacings = [], []
    refused: dict[float, FillError] = {}  # a spacing whose lattice could not be made: why
    scale = None
    for per_edge in LATTICE_PER_EDGE:
        try:
            # a spacing bounded by the border or MAX_FREE repeats: its lattice is not made
            # again (the same lattice, or the same reason it could not be; session 47)
            scale = LatticeScale.of(local, uv, n_fill) if scale is None else scale
            spacing = scale.spacing(per_edge)
            if spacing in spacings:  # tried
                continue
            if spacing in refused:
                raise refused[spacing]
            lattice = _lattice_or_refused(points, local, uv, free, n_fill, per_edge, scale,
                                          refused)
            spacings.append(lattice.spacing)
            fine = inpaint_on_mesh(lattice.points, lattice.faces, lattice.uv, lattice.free,
                                   iterations=iterations, tol=tol)
        except FillError as exc:
            reasons.append(f"{per_edge:g} per edge: {exc}")
            continue
        return _read_back(lattice, fine, points, local, uv, free, n_fill), int(
            lattice.free.sum())
    raise FillError(f"{failure}; on a regular lattice of its map, "
                    + "; ".join(reasons))


def _lattice_or_refused(points, local, uv, free, n_fill, per_edge, scale, refused):
    """:func:`lattice_patch`, its FillError kept in ``refused`` under its spacing."""
    try:
        return lattice_patch(points, local, uv, free, n_fill, per_edge, scale=scale)
    except FillError as exc:
        refused[scale.spacing(per_edge)] = exc
        raise


def _read_back(lattice, fine, points, local, uv, free, n_fill):
    """The lattice's solution ``fine`` read back at the fill's free vertices; where that
    folds the fill over at more edges than its start ``points`` does, read back instead at
    their Tutte positions in the map (:func:`~surfinpaint.fill.conformal.lattice.
    tutte_positions`) if that folds it less.

    Why: on a thin part the start's own triangles can fold in 3D (4-5 edges on two of the
    built animals' holes, docs/convergence.md, session 23) while the lattice's solution
    folds nowhere; read back at the start's map positions the fill inherits their folds
    and more (9, 13 edges), and the checks then write a blend with the faired fill. The
    fill's vertices only slide on the λ-H surface: its triangles change, not its surface.
    """
    edges = edge_faces(local)  # one topology for every fold count here
    read = lattice.read_back(fine, points)
    folds = fold_count(read, local, n_fill, edges=edges)
    if folds <= fold_count(points, local, n_fill, edges=edges):
        return read
    moving = np.flatnonzero(free)
    try:
        relaxed = lattice.relocated(tutte_positions(uv, local[:n_fill], moving)).read_back(
            fine, points)
    except FillError:
        return read
    return relaxed if fold_count(relaxed, local, n_fill, edges=edges) < folds else read


def _subdivided(points, local, uv, free, n_fill, natural):
    """The patch split once into four (edge midpoints) onto the Clough–Tocher interpolant
    of its positions over ``uv`` (:func:`smooth_subdivision`): positions, faces, map (the
    midpoints of the map), free vertices (those off the surface's faces) and natural ones
    (midpoints of natural border edges)."""
    fine_points, fine_faces = smooth_subdivision(points, local, uv, 1)
    edges, face_edge, _ = unique_edges(local)
    fine_uv = np.vstack([uv, uv[edges].mean(axis=1)])
    on_surface = np.zeros(len(edges), dtype=bool)
    on_surface[face_edge[n_fill:].ravel()] = True
    fine_free = np.concatenate([free, ~on_surface])
    fine_natural = np.concatenate([natural, natural[edges[:, 0]] & natural[edges[:, 1]]])
    return fine_points, fine_faces, fine_uv, fine_free, fine_natural


def _mapped_patch(vertices, faces, seeds, fill_faces, rings, grow=False):
    """The hole's patch and its map: LSCM with ``rings`` rings, fewer while LSCM flips a
    triangle or squashes one flat (:func:`~surfinpaint.geometry.mean_value.bad_faces`; down
    to ``MIN_RINGS``), and where it does at every size, LSCM of the ``rings``-ring patch
    with those triangles untangled, or the mean-value map, which cannot flip one (slivers
    make LSCM's cotangent weights negative; the mean-value weights stay positive).

    Returns
    -------
    patch, ids, local, uv, rings used, map name ("lscm", "lscm-untangled" or "mean-value")
    """
    first = None  # the ``rings``-ring patch and its LSCM, which the untangling starts from
    k = rings
    while k >= MIN_RINGS:
        patch, used, boundary = ((grown_patch(faces, seeds, fill_faces, k), k, None) if grow
                                 else hole_patch_and_boundary(faces, seeds, fill_faces, k))
        ids, local = renumber(patch)
        # a patch of full rings was found a disk with this boundary: LSCM need not check
        # its topology again (through the module: tests stand in for the flip test)
        uv = parameterization.lscm(vertices[ids], local, boundary=None if boundary is None
                                   else np.searchsorted(ids, boundary))
        if len(mean_value.bad_faces(vertices[ids], local, uv)) == 0:
            return patch, ids, local, uv, used, "lscm"
        first = first or (patch, used, ids, local, uv)
        # fewer rings than ``k`` were a disk: each k down to ``used`` gives this patch again
        k = min(k, used) - 1
    if first is None:
        patch, used = ((grown_patch(faces, seeds, fill_faces, rings), rings) if grow
                       else hole_patch(faces, seeds, fill_faces, rings))
        ids, local = renumber(patch)
        first = (patch, used, ids, local, parameterization.lscm(vertices[ids], local))
    # the ``rings``-ring patch's LSCM made above: the same map (its boundary is the loop
    # LSCM finds, session 44 helper)
    patch, used, ids, local, uv = first
    uv = mean_value.untangle(vertices[ids], local, uv)
    if uv is not None:
        return patch, ids, local, uv, used, "lscm-untangled"
    uv = mean_value.mean_value_map(vertices[ids], local)
    flipped = parameterization.flipped_faces(local, uv)
    if len(flipped):  # only round-off can do this
        raise FillError("the map of the patch folds "
                        f"({how_many(len(flipped), 'flipped face', 'flipped faces')}, with "
                        "LSCM at every ring count and with the mean-value map)")
    return patch, ids, local, uv, used, "mean-value"
