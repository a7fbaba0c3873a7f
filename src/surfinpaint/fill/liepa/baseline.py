"""The conventional hole filler: triangulate, refine, fair (Liepa 2003).

P. Liepa, "Filling holes in meshes", SGP 2003; the same pipeline as CGAL's
``triangulate_refine_and_fair_hole``. It is the baseline the conformal method is measured
against, and its first two steps give the initial fill S0 the conformal method starts from.
"""

from __future__ import annotations

import numpy as np

from surfinpaint.errors import FillError, MeshError
from surfinpaint.fill.liepa.fairing import fair as fair_patch
from surfinpaint.fill.liepa.fairing import fair_orders, fair_smoothed
from surfinpaint.fill.liepa.refinement import refine_patch
from surfinpaint.fill.liepa.triangulation import minimum_weight_triangulation
from surfinpaint.fill.results import Smoothing
from surfinpaint.geometry.edges import edge_keys
from surfinpaint.geometry.flatness import meeting_line
from surfinpaint.geometry.mesh import faces_near, k_ring, mean_edge_length, orient_loop
from surfinpaint.geometry.surface_noise import surface_noise
from surfinpaint.geometry.validation import face_ids

__all__ = ["conventional_fill", "faired_fill", "faired_fills", "laid_on_plane",
           "laid_on_two_planes", "smoothing_decision", "smoothing_for_hole"]

# the bilaplacian smoothing fill (faired_fills' ``smoothing``): the known vertices within
# SOFT_RINGS rings of the loop are its data, its energy is summed over SMOOTHING_RINGS
# rings (the data's L M⁻¹ L rows complete)
SOFT_RINGS = 2
SMOOTHING_RINGS = 4
# smoothing="auto" (:func:`smoothing_for_hole`): the smoothing length, in mean edges, where
# the known surface within NOISE_RINGS rings of the loop reads as a range scan's noise
# (:func:`surfinpaint.geometry.surface_noise.surface_noise`): NOISY_SIGMA to NOISY_SIGMA_MAX
# mean edges (above it: shape at the mesh's scale, or a noise the length was not chosen
# for), residuals no more alike between neighbours than NOISY_CORRELATION, and no more
# spread from fits over 3 rings than NOISY_SCALE times that over 2 (all chosen on the
# tuning side only, by a rule written down first; docs/candidates.md, "Session 45 (helper)")
AUTO_SMOOTHING = 0.35
NOISE_RINGS = 3
NOISY_SIGMA = 0.015
NOISY_SIGMA_MAX = 0.08
NOISY_CORRELATION = -0.1
NOISY_SCALE = 1.3


def conventional_fill(
    vertices: np.ndarray,
    faces: np.ndarray,
    loop: np.ndarray,
    *,
    refine: bool = True,
    fair: bool = True,
    density: float = np.sqrt(2.0),
    order: int = 2,
    fair_iterations: int = 1,
    search: str = "delaunay",
    operator: str = "cotan",
    refinement: str = "liepa",
) -> tuple[np.ndarray, np.ndarray]:
    """Fill one hole by Liepa's triangulate / refine / fair.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        A consistently oriented mesh with the hole.
    loop : (k,) int array
        The hole's boundary loop (e.g. from :func:`surfinpaint.geometry.mesh.boundary_loops`), in
        either orientation and from any start.
    refine : bool
        Refine the triangulation to the density of the surrounding mesh. ``refine=True,
        fair=False`` gives the initial fill S0 of the conformal method.
    fair : bool
        Move the new vertices so that Δ²x = 0 there (cotangent Laplacian, Voronoi mass), with
        the surrounding mesh fixed.
    density : float
        Liepa's density factor for the refinement.
    order : int
        Fairing order (1 harmonic, 2 biharmonic, 3 triharmonic).
    fair_iterations : int
        Fairing solves; each after the first recomputes the cotangent weights from the
        previous result. One (weights of the flat refined patch) is the classic choice;
        two measured 1.5–2× better on regular meshes (icosphere, torus) but 5 % worse on
        average on the irregular bunny (``benchmarks/baseline_vs_cgal.py``).
    search : {"delaunay", "all"}
        The triangulation's candidate diagonals
        (:func:`~surfinpaint.fill.liepa.triangulation.minimum_weight_triangulation`).
    operator : {"cotan", "clamped", "intrinsic"}
        The fairing's Laplacian (:func:`~surfinpaint.fill.liepa.fairing.fair`).
    refinement : {"liepa", "cgal"}
        The refinement's style (:func:`~surfinpaint.fill.liepa.refinement.refine_patch`).

    Returns
    -------
    new_vertices : (m, 3) float array
        The added vertices; they get ids ``n .. n + m - 1``.
    new_faces : (p, 3) int array
        The patch faces over original and new ids, oriented like the mesh. Appending them to
        ``faces`` closes the hole. Original vertices never move.

    Raises
    ------
    FillError
        If the loop is not a boundary loop of the mesh (ids out of range, repeated vertices,
        edges that are not boundary edges) or the fill fails.
    MeshError
        Face ids that are not whole numbers (:func:`surfinpaint.geometry.validation.
        face_ids`).

    Examples
    --------
    >>> import trimesh
    >>> from surfinpaint.geometry.mesh import boundary_loops
    >>> m = trimesh.creation.icosphere(3)
    >>> faces = m.faces[1:]  # a one-triangle hole
    >>> new_v, new_f = conventional_fill(m.vertices, faces, boundary_loops(faces)[0])
    >>> new_v.shape, new_f.shape
    ((0, 3), (1, 3))
    """
    v, faces, loop = _checked_input(vertices, faces, loop)
    n = len(v)
    faces = _neighbourhood(faces, loop, n, max(order - 2, 0))
    try:
        loop = orient_loop(faces, loop, boundary=False)
        _check_boundary(faces, loop)
        patch = minimum_weight_triangulation(v, loop, faces, search=search)
        new_v = np.empty((0, 3))
        if refine:
            new_v, patch = refine_patch(v, patch, loop, faces=faces, density=density,
                                        style=refinement)
        if fair and len(new_v):
            new_v = _faired(v, faces, new_v, patch, order=order, iterations=fair_iterations,
                            operator=operator)
    except MeshError as err:
        raise FillError(f"cannot fill the hole: {err}") from err
    return _finite(new_v), patch


def _checked_input(vertices, faces, loop) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`conventional_fill`'s arrays as float vertices, int64 faces and loop, or a
    :class:`FillError` naming what is wrong with them (a :class:`MeshError` for face ids that
    are not whole numbers)."""
    v = np.asarray(vertices, dtype=float)
    faces = face_ids(faces)  # whole-number floats taken, never truncated
    loop = np.asarray(loop, dtype=np.int64).ravel()
    n = len(v)
    if v.ndim != 2 or v.shape[1] != 3:
        raise FillError(f"vertices must be an (n, 3) array, got shape {v.shape}")
    if len(loop) < 3:
        raise FillError(f"a hole loop needs at least 3 vertices, got {len(loop)}")
    bad = loop[(loop < 0) | (loop >= n)]
    if len(bad):
        raise FillError(f"loop vertex ids {bad[:10].tolist()} are out of range 0..{n - 1}")
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise FillError(f"faces must be an (f, 3) array, got shape {faces.shape}")
    return v, faces, loop


def _faired(vertices: np.ndarray, faces: np.ndarray, new_vertices: np.ndarray,
            patch: np.ndarray, **fairing) -> np.ndarray:
    """The positions of ``new_vertices`` (appended after ``vertices``) faired over the mesh
    ``faces`` closed by ``patch``, everything else fixed (``fairing``: the options of
    :func:`~surfinpaint.fill.liepa.fairing.fair`)."""
    n = len(vertices)
    allv = np.vstack([vertices, new_vertices])
    allf = np.vstack([faces, patch])
    return fair_patch(allv, allf, np.arange(n, n + len(new_vertices)), **fairing)[n:]


def _finite(new_vertices: np.ndarray) -> np.ndarray:
    """``new_vertices``, checked: a fairing whose system was singular in floating point
    gives non-finite positions rather than an error, and they must not reach a mesh."""
    if not np.isfinite(new_vertices).all():
        raise FillError("fairing produced non-finite positions")
    return new_vertices


def faired_fill(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, order: int = 3
                ) -> tuple[np.ndarray, np.ndarray, int]:
    """The conventional fill (triangulate, refine, fair) with fairing of ``order``, or of
    order 2 where the surface around the hole has too few rings to anchor a higher order.

    Returns
    -------
    new_vertices, new_faces : arrays
        As :func:`surfinpaint.fill.liepa.baseline.conventional_fill`.
    order : int
        The order actually used.

    Raises
    ------
    FillError
        When even the order-2 (or the requested lower-order) fill cannot be made.
    """
    return faired_fills(vertices, faces, loop, (order,))[order]


def smoothing_for_hole(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                       smoothing: float | str | None) -> float | None:
    """The smoothing length :func:`faired_fills` uses for ``smoothing``: a number or None as
    given; for "auto", :data:`AUTO_SMOOTHING` where the known surface around the loop is a
    noisy one (a range scan's) and None elsewhere (:func:`smoothing_decision`)."""
    if not isinstance(smoothing, str):
        return smoothing
    return smoothing_decision(vertices, faces, loop, smoothing).length


def smoothing_decision(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                       smoothing: float | str | None) -> Smoothing | None:
    """:func:`smoothing_for_hole`'s length with what decided it, for the hole's report
    (None where ``smoothing`` is None: not asked for).

    Why "auto" decides so: the thin-plate smoothing fill gains on range scans, whose noise
    the bilaplacian fill carries into the hole, and costs on clean meshes (docs/candidates.md,
    sessions 44 and 45). Noisy: the noise estimate of the known vertices within
    :data:`NOISE_RINGS` rings of the loop (:func:`~surfinpaint.geometry.surface_noise.
    surface_noise`) is :data:`NOISY_SIGMA` to :data:`NOISY_SIGMA_MAX` mean edges, its
    residuals are not alike between neighbours (correlation at most :data:`NOISY_CORRELATION`)
    and fits over 3 rings find about as much (at most :data:`NOISY_SCALE` times): independent
    noise, not shape finer than the fits (a folded cortex, a tooth's fissures, a part's crease).
    """
    if smoothing is None:
        return None
    if not isinstance(smoothing, str):
        return Smoothing(smoothing, smoothing, f"fair_smoothing={smoothing:g} given")
    if smoothing != "auto":
        raise ValueError(f"smoothing must be a positive number, 'auto' or None, got "
                         f"{smoothing!r}")
    # the 3-ring fits only where the 2-ring ones already read as noise (most clean holes
    # stop here: a default fill's cost on them, session 45)
    noise = surface_noise(vertices, faces, loop, rings=NOISE_RINGS, wide=False)
    shut = _not_noise(noise)
    if shut is None:
        noise = surface_noise(vertices, faces, loop, rings=NOISE_RINGS)
        if not noise.scale_ratio <= NOISY_SCALE:
            shut = (f"fits over 3 rings find {noise.scale_ratio:.2g}x the 2-ring ones' "
                    f"spread (noise: up to {NOISY_SCALE:g}x): shape, not noise")
    said = f"noise {noise.relative:.2g} edges"
    if shut is not None:
        return Smoothing(None, smoothing, f"{said}, but {shut}", noise)
    return Smoothing(AUTO_SMOOTHING, smoothing,
                     f"{said} around it, read as a scanner's (neighbours' correlation "
                     f"{noise.correlation:.2g}, 3-ring/2-ring {noise.scale_ratio:.2g})", noise)


def _not_noise(noise) -> str | None:
    """Why the 2-ring estimate ``noise`` does not read as a scanner's noise (None: it does)."""
    if not noise.relative >= NOISY_SIGMA:
        return f"below {NOISY_SIGMA:g}: a clean surface"
    if not noise.relative <= NOISY_SIGMA_MAX:
        return f"above {NOISY_SIGMA_MAX:g}: shape at the mesh's scale, or coarser noise"
    if not noise.correlation <= NOISY_CORRELATION:
        return (f"neighbours' residuals are alike (correlation {noise.correlation:.2g}; "
                f"noise: up to {NOISY_CORRELATION:g}): shape finer than the fits")
    return None


def faired_fills(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                 orders=(2, 3), *, search: str = "delaunay", operator: str = "cotan",
                 refinement: str = "liepa", smoothing: float | str | None = None
                 ) -> dict[int, tuple[np.ndarray, np.ndarray, int]]:
    """:func:`faired_fill` for several fairing orders, sharing the triangulation and the
    refinement (those of the order-2 fill); ``search``, ``operator`` and ``refinement`` as in
    :func:`conventional_fill`. ``smoothing``: the order-2 fill is the thin-plate smoothing
    fill (:func:`~surfinpaint.fill.liepa.fairing.fair_smoothed`, cotangent weights) of
    smoothing length ``smoothing`` mean edges of the known surface around the hole, the
    known vertices within 2 rings of the loop its data (for range scans: session 44); "auto":
    that fill where the surface around the loop is noisy (:func:`smoothing_for_hole`); None
    (default): the bilaplacian fill.

    Returns
    -------
    dict
        order -> (new_vertices, new_faces, order actually used).

    Raises
    ------
    FillError
        As :func:`faired_fill`.
    """
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    smoothing = smoothing_for_hole(v, faces, loop, smoothing)
    initial_v, patch = conventional_fill(v, faces, loop, refine=True, fair=False,
                                         search=search, refinement=refinement)
    initial_v = np.asarray(initial_v, dtype=float)
    patch = np.asarray(patch, dtype=np.int64)
    n = len(v)
    if len(initial_v) == 0:
        return {order: (initial_v, patch, order) for order in orders}
    # every order on the neighbourhood of the highest (a lower order's submesh is the same
    # within it) with one Laplacian: the same bits as one fairing per order
    wanted = sorted(set(orders) | ({2} if max(orders) > 2 else set()))
    near = _neighbourhood(faces, np.asarray(loop, dtype=np.int64).ravel(), n,
                          max(max(wanted) - 2, 0))
    made = fair_orders(np.vstack([v, initial_v]), np.vstack([near, patch]),
                       np.arange(n, n + len(initial_v)), wanted, operator=operator)
    if smoothing is not None and 2 in made and not isinstance(made[2], MeshError):
        made[2] = _smoothed(v, faces, np.asarray(loop, dtype=np.int64).ravel(), initial_v,
                            patch, smoothing)
    out = {}
    for order in orders:
        used = order if not isinstance(made[order], MeshError) else min(order, 2)
        if isinstance(made[used], MeshError):  # too few rings to anchor even order 2
            raise FillError(f"cannot fill the hole: {made[used]}") from made[used]
        out[order] = (_finite(made[used][n:]), patch, used)
    return out


def _smoothed(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
              new_vertices: np.ndarray, patch: np.ndarray, smoothing: float) -> np.ndarray:
    """All positions (original, then the new vertices') of :func:`faired_fills`' order-2
    smoothing fill with smoothing length ``smoothing`` mean edges."""
    n = len(vertices)
    near = faces_near(faces, loop, SMOOTHING_RINGS, n)
    stiffness = (smoothing * mean_edge_length(vertices, near)) ** 4
    soft = np.flatnonzero(k_ring(faces, loop, SOFT_RINGS, n))
    try:
        return fair_smoothed(np.vstack([vertices, new_vertices]), np.vstack([near, patch]),
                             np.arange(n, n + len(new_vertices)), soft, stiffness)
    except MeshError as err:
        return err


def laid_on_plane(new_vertices: np.ndarray, centre: np.ndarray, normal: np.ndarray
                  ) -> np.ndarray:
    """A fill laid on a plane: its new vertices projected onto it (the loop and every other
    original vertex stay where they are, so only the triangles along the loop tilt).

    Why: where the known surface around a hole is a plane within its noise (a range scan's
    flat face), the plane fitted to a few hundred of its vertices is a far better estimate
    of the removed surface than the loop's own noisy heights. A faired fill extrapolates
    the noisy rings' slopes across the hole (docs/candidates.md, "Session 26"); the
    harmonic extension of the loop's heights, used until session 29, averages them but
    keeps them near the loop: on the tuning side's 57 flat holes with new vertices off the
    plane the projection is 0.69× its error on the median hole, better on 49, worse by more
    than 10 % on 2 (docs/candidates.md, "Session 29").

    Parameters
    ----------
    new_vertices : (m, 3) float array
        The fill's new vertices.
    centre, normal : (3,) float arrays
        The plane (e.g. :func:`surfinpaint.geometry.flatness.plane_test`'s); ``normal`` of
        unit length.

    Returns
    -------
    (m, 3) float array
        The new vertices' positions.
    """
    new_vertices = np.asarray(new_vertices, dtype=float)
    centre, normal = np.asarray(centre, dtype=float), np.asarray(normal, dtype=float)
    return new_vertices - np.outer((new_vertices - centre) @ normal, normal)


def laid_on_two_planes(new_vertices: np.ndarray, first: tuple[np.ndarray, np.ndarray],
                       second: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """A fill laid on two planes that meet at an edge: each new vertex projected onto the
    plane on whose side of their intersection line its projection falls (the side its
    plane's fitted points are on); where both or neither would take it, the nearer one
    (a vertex that neither takes goes onto the line).

    Why: as :func:`laid_on_plane`, on a scanned part's edge, where the crease search sees
    no sharp edge in the noise (docs/candidates.md, "Session 29").

    Parameters
    ----------
    new_vertices : (m, 3) float array
        The fill's new vertices.
    first, second : (centre, unit normal) pairs
        The planes, each ``centre`` the centroid of its fitted points (it tells the side).

    Returns
    -------
    (m, 3) float array

    Raises
    ------
    ValueError
        For parallel planes (no line where they meet).
    """
    new_vertices = np.asarray(new_vertices, dtype=float)
    on_line, direction, away = meeting_line(*first, *second)
    projected, taken = [], []
    for (c, m), out in zip((first, second), away, strict=True):
        c, m = np.asarray(c, dtype=float), np.asarray(m, dtype=float)
        onto = new_vertices - np.outer((new_vertices - c) @ m, m)
        projected.append(onto)
        taken.append((onto - on_line) @ out >= 0.0)
    nearer_first = (np.linalg.norm(projected[0] - new_vertices, axis=1)
                    <= np.linalg.norm(projected[1] - new_vertices, axis=1))
    use_first = np.where(taken[0] == taken[1], nearer_first, taken[0])
    out = np.where(use_first[:, None], projected[0], projected[1])
    neither = ~taken[0] & ~taken[1]
    out[neither] = on_line + np.outer((new_vertices[neither] - on_line) @ direction, direction)
    return out


def _neighbourhood(faces: np.ndarray, loop: np.ndarray, n: int, rings: int) -> np.ndarray:
    """Faces within ``rings`` rings of the loop's one-ring: all that triangulation,
    refinement and fairing of order ``rings + 2`` look at. Working on them alone keeps the
    cost of filling a small hole in a big mesh small."""
    return faces_near(faces, loop, rings, n)


def _check_boundary(faces: np.ndarray, loop: np.ndarray) -> None:
    """Every loop edge must be a boundary edge (in exactly one face)."""
    n = int(max(faces.max(initial=-1), loop.max())) + 1
    on_loop = np.zeros(n, dtype=bool)
    on_loop[loop] = True
    near = faces[on_loop[faces].sum(axis=1) >= 2]
    key = edge_keys(near.ravel(), near[:, [1, 2, 0]].ravel(), n)
    lkey = edge_keys(loop, np.roll(loop, -1), n)
    keys, counts = np.unique(key, return_counts=True)
    pos = np.searchsorted(keys, lkey)
    pos = np.clip(pos, 0, len(keys) - 1)
    c = np.where(keys[pos] == lkey, counts[pos], 0)
    bad = np.flatnonzero(c != 1)
    if len(bad):
        edges = [(int(loop[i]), int(loop[(i + 1) % len(loop)])) for i in bad[:10]]
        raise MeshError(f"loop edges {edges} are not boundary edges of the mesh "
                        f"(in {c[bad[:10]].tolist()} faces)", edges=edges)
