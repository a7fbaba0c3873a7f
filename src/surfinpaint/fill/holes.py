"""Holes of a triangle mesh: its boundary loops, measured, and which of them to fill."""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from surfinpaint.errors import MeshError, agreeing, how_many, preview
from surfinpaint.geometry.degenerate import triangle_rows
from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.geometry.mesh import boundary_loops, face_areas, face_blocks, orient_loop
from surfinpaint.geometry.validation import (
    check_arrays,
    degenerate_notes,
    face_ids,
    validate_mesh,
    zero_area_faces,
)
from surfinpaint.io.base import MeshWarning
from surfinpaint.lazy import lazy_module

# imported at its first use: scipy.spatial (with scipy.special) is 50-60 ms of a start,
# and a large fill's kernels import it on their loading thread, beside the passes
spatial = lazy_module("scipy.spatial")
# a trimesh or PyVista mesh in find_holes (the attribute carrying is not needed otherwise)
objects = lazy_module("surfinpaint.fill.objects")

# orient_loop lives with the other loop primitives in geometry.mesh; named here too, where
# callers picking holes look for it
__all__ = ["Hole", "find_holes", "hole_numbers", "loop_diameter", "select_holes", "orient_loop",
           "over_size", "percent_below", "seam_edges", "spanned_area", "warn_degenerate"]

# A component's largest loop (the one spanning the most area, not the one with the most
# edges) is its outer border when the area the loop spans is at least this fraction of the
# component's own area: a scan's border spans about its whole area (0.6–1), while a hole in
# a closed surface spans a small part of what remains (a third of a sphere removed spans
# 0.33).
BORDER_SPAN_FRACTION = 0.4
# A component's largest loop spanning at least this fraction (but less than the border's) is
# filled as a hole, with a warning: it may be an open surface's margin, e.g. a tooth crown
# scanned down to the gum (its margin spans about a third of the crown's area), which the
# area alone cannot tell from a large hole in a closed surface (a tenth of a sphere removed
# spans 0.1 of what remains).
MAY_BE_BORDER_FRACTION = 0.1
# A loop inside a component's outer border spanning at least this fraction of the component
# may be an inner margin (the inner edge of a scanned ring, washer or bore: 21-51 % on
# simulated scans of tori along their axis; a washer's opening half its width 33 %), also
# filled with a warning. Real holes cut in the tuning side's and spent holdouts' range scans
# span at most 9.2 % (563 holes, docs/robustness.md "Session 48 (lead)"); twice that is the
# margin for smaller scans, and small test plates with a hole a fifth of their width (12-14 %)
# stay holes.
INNER_MARGIN_FRACTION = 0.2


@dataclass(frozen=True)
class Hole:
    """One boundary loop of a mesh.

    Attributes
    ----------
    loop : (k,) int array
        Vertex ids in order, oriented like the half-edges of the faces next to it.
    n_edges : int
        Number of boundary edges (= number of loop vertices).
    perimeter : float
        Length of the loop.
    diameter : float
        Largest distance between two loop vertices.
    component : int
        Connected component of the surface the loop belongs to: 0, 1, ... over the
        components that have faces, in the order of their lowest vertex id (vertices no face
        uses are no component).
    is_border : bool
        True when the loop looks like the surface's own outer border rather than a hole.
    span_fraction : float
        For its component's largest loop (the one spanning the most area), the area the
        loop spans over the component's area
        (``is_border`` from ``BORDER_SPAN_FRACTION``); NaN where a first part of the
        component's area was enough to tell the loop is small. For the other loops of a
        component whose largest loop is its outer border, the same fraction (a scanned
        ring's inner edge spans a large part); NaN for the other loops of other components.
    spans_no_area : bool
        Every face of its component has zero area (collinear or coincident corners, as
        :func:`~surfinpaint.geometry.validation.zero_area_faces` finds them: a stray
        degenerate triangle, say): the loop spans no area, like a slit, and no fill of it
        is a surface, so it is never filled (left open with a warning).
    seam_edges : (n_edges,) bool array or None
        Per loop edge (``loop[i]`` to ``loop[i + 1]``), whether it lies exactly on another
        boundary edge (:func:`seam_edges`): faces that meet there do not join.
    inside_border : bool
        The loop is not its component's largest, and that one is the outer border: the
        loop lies inside an open surface (a scan's hole, or a scanned ring's inner edge).
    """

    loop: np.ndarray
    n_edges: int
    perimeter: float
    diameter: float
    component: int
    is_border: bool
    span_fraction: float = float("nan")
    spans_no_area: bool = False
    seam_edges: np.ndarray | None = None
    inside_border: bool = False

    @property
    def runs_along_other_loops(self) -> bool:
        """Every edge of the loop lies exactly on another boundary edge: the loop is a seam
        between faces that do not join (their own copies of the vertices they share), not a
        hole, and it is never filled (left open with a warning; merge coincident vertices
        first). trimesh splits a textured mesh so along its UV seams."""
        return self.seam_edges is not None and bool(self.seam_edges.all())

    @property
    def may_be_border(self) -> bool:
        """A hole (not ``is_border``) that may be an open surface's margin: its
        component's largest loop spanning at least ``MAY_BE_BORDER_FRACTION`` of it (a
        tooth crown scanned to the gum), or a loop inside the outer border spanning at
        least ``INNER_MARGIN_FRACTION`` (the inner edge of a scanned ring or bore);
        filling it by default warns."""
        least = INNER_MARGIN_FRACTION if self.inside_border else MAY_BE_BORDER_FRACTION
        return not self.is_border and self.span_fraction >= least


def seam_edges(vertices: np.ndarray, loops: Sequence[np.ndarray]) -> list[np.ndarray]:
    """Per loop, which of its edges lie exactly on a boundary edge of another loop: both
    ends at the same points (equal coordinates) as the two ends of an edge of that loop.
    (A loop that runs back along itself is a slit: :func:`~surfinpaint.fill.seams.
    find_slit`.) Only boundary vertices are compared, O(b log b) for b of them.

    Examples
    --------
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.]])
    >>> [m.tolist() for m in seam_edges(v, [np.array([0, 1, 2]), np.array([3, 5, 4])])]
    [[False, True, False], [False, False, True]]
    """
    if not loops:
        return []
    sizes = [len(loop) for loop in loops]
    cuts = np.cumsum(sizes)[:-1]
    ids, at = np.unique(np.concatenate(loops), return_inverse=True)
    point = _equal_rows(np.asarray(vertices, dtype=float)[ids])
    first = point[at.ravel()]
    # each loop vertex's successor along its loop (the last one's is the loop's first)
    successor = np.arange(1, len(first) + 1)
    successor[np.cumsum(sizes) - 1] = np.concatenate([[0], cuts])
    second = first[successor]
    # one int64 per unordered pair of points, and per (pair, loop): 1-D uniques, not the
    # row uniques (axis=0) whose sort of structured rows was most of a soup's time
    n_points = np.int64(point.max()) + 1
    _, key = np.unique(np.minimum(first, second) * n_points + np.maximum(first, second),
                       return_inverse=True)
    key = key.ravel()
    owner = np.repeat(np.arange(len(loops)), sizes)
    # the loops each edge's points appear in, each loop once
    pair_loop = np.unique(key * np.int64(len(loops)) + owner)
    loops_at = np.bincount(pair_loop // len(loops), minlength=key.max() + 1)
    shared = loops_at[key] > 1
    # slices, not np.split: its Python cost per piece was most of a triangle soup's time
    return [shared[a:b] for a, b in zip([0, *cuts.tolist()], np.cumsum(sizes).tolist(),
                                        strict=True)]


def _equal_rows(points: np.ndarray) -> np.ndarray:
    """One id per row of ``points``, the same for rows with equal coordinates (``==``, as
    ``np.unique(points, axis=0)`` compares them), numbered in their lexicographic order."""
    order = np.lexsort(points.T[::-1])
    ordered = points[order]
    new = np.r_[True, (ordered[1:] != ordered[:-1]).any(axis=1)] if len(points) else []
    ids = np.empty(len(points), dtype=np.int64)
    ids[order] = np.cumsum(new) - 1
    return ids


def percent_below(fraction: float) -> str:
    """``fraction`` as a whole percentage rounded down: a loop that spans 39.7 % of its
    surface is below the 40 % of ``BORDER_SPAN_FRACTION``, and says "39%", not "40%"."""
    return f"{np.floor(100 * fraction + 1e-9):.0f}%"


def loop_diameter(points: np.ndarray) -> float:
    """Largest distance between two of ``points`` (exact; via the convex hull when many)."""
    if len(points) > 1500:
        # the diameter is attained on the convex hull; fall back to a subsample when flat

        try:
            points = points[spatial.ConvexHull(points).vertices]
        except spatial.QhullError:
            points = points[:: max(1, len(points) // 1500)]
    d = points[:, None, :] - points[None, :, :]
    return float(np.sqrt((d * d).sum(-1)).max())


def spanned_area(points: np.ndarray) -> float:
    """Norm of the vector area of a closed polygon: the area of a surface it bounds, at least."""
    centred = points - points.mean(axis=0)
    return 0.5 * float(np.linalg.norm(np.cross(centred, np.roll(centred, -1, axis=0)).sum(0)))


def find_holes(vertices: np.ndarray, faces: np.ndarray | None = None,
               table: EdgeTable | None = None, *, validate: bool = True) -> list[Hole]:
    """Boundary loops of a mesh, measured, with the outer borders flagged.

    Every boundary loop is returned. Faces that use a vertex twice are no triangles and are
    left out (:func:`~surfinpaint.geometry.degenerate.triangle_rows`): their two edges
    between the same two vertices would otherwise open a slit in the surface. In each
    connected component the largest loop (spanning the most area) is flagged ``is_border``
    when it spans at least ``BORDER_SPAN_FRACTION`` of that component's area (an open
    scan's outer edge); all other loops are holes. Callers choose what to fill with
    :func:`select_holes`.

    Parameters
    ----------
    vertices : (n, 3) float array, ``trimesh.Trimesh`` or ``pyvista.PolyData``
        A mesh object is taken whole (``faces`` then None), as by
        :func:`surfinpaint.fill_holes`.
    faces : (f, 3) int array
    table : EdgeTable, optional
        The faces' edge table, if already built (e.g. by the caller that validated the
        mesh): the loops and components are then read from it in O(E). ``faces`` are then
        taken as the triangles it was built from (those that repeat a vertex left out).
    validate : bool
        Check the mesh first, as :func:`surfinpaint.fill_holes` does
        (:func:`surfinpaint.validate_mesh`); False when the caller has.

    Returns
    -------
    list of Hole, ordered by component and then by decreasing length.

    Raises
    ------
    MeshError
        A mesh :func:`surfinpaint.validate_mesh` refuses (the message names the offending
        ids: out-of-range vertex ids, non-manifold edges, ...), face ids that are not whole
        numbers (whole-number floats are taken), or a boundary that does not close into
        loops.

    Examples
    --------
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.]])
    >>> [h.n_edges for h in find_holes(v, np.array([[0, 1, 2], [0, 2, 3]]))]
    [4]
    """
    if faces is None:  # a trimesh or PyVista mesh
        vertices, faces, _, _ = objects.mesh_arrays(vertices)
    faces = face_ids(faces)
    if validate:
        check_arrays(vertices, faces)  # before the table: it indexes by the ids
    if table is None:  # a face that repeats a vertex joins no faces and bounds no hole
        faces = triangle_rows(faces)[0]
    if validate:
        if table is None:
            table = EdgeTable.build(faces, len(vertices))
        validate_mesh(vertices, faces, table=table)
    vertices = np.asarray(vertices, dtype=float)
    if table is None:
        table = EdgeTable.build(faces, len(vertices))
    loops = boundary_loops(faces, table)
    if not loops:
        return []
    _, label = table.vertex_components
    lengths = np.array([len(loop) for loop in loops])
    firsts = label[np.array([loop[0] for loop in loops])]
    # by component, then longest first (stable: boundary_loops' order among equal lengths)
    rank = np.lexsort((-lengths, firsts))
    ordered = [loops[k] for k in rank.tolist()]
    owner = firsts[rank]
    perimeters, diameters = _loop_lengths(vertices, ordered)
    spanned = _spanned_areas(vertices, ordered)
    largest = _largest_loops(owner, spanned)
    spans = dict(zip(owner[largest].tolist(), spanned[largest].tolist(), strict=True))
    fractions = _span_fractions(vertices, faces, label, spans)
    flat = _zero_area_components(label, spans, owner[largest], perimeters[largest],
                                 vertices, faces)
    is_largest = np.zeros(len(ordered), dtype=bool)
    is_largest[largest] = True
    bordered = {c for c, f in fractions.items() if f >= BORDER_SPAN_FRACTION}
    inner = _inner_fractions(owner, is_largest, spanned, spans, fractions, bordered)
    # numbered over the components with faces: a vertex no face uses (left where faces were
    # cut away) is a component of its own in the labels and would skip numbers. A face's
    # three vertices share its component (the labels are of its edges), so its first
    # vertex's label is enough: a count of those in place of np.unique of every corner's
    # (651k case: 0.004 instead of 0.04 s, the same sorted ids; docs/scale.md, session 36)
    numbers = np.searchsorted(np.flatnonzero(np.bincount(label[faces[:, 0]])), owner)
    # the largest loops' fractions decide the borders; the inner loops' may call a margin
    span = [fractions[c] if first else inner.get(k, float("nan"))
            for k, (c, first) in enumerate(zip(owner.tolist(), is_largest.tolist(),
                                               strict=True))]
    # one Hole a loop, its numbers computed above for all loops at once (a triangle soup's
    # 10^5 loops: docs/scale.md, session 38)
    return [Hole(loop=loop, n_edges=n_edges, perimeter=perimeter, diameter=diameter,
                 component=number,
                 is_border=bool(first and fraction >= BORDER_SPAN_FRACTION),
                 span_fraction=fraction, spans_no_area=component in flat, seam_edges=seams,
                 inside_border=bool(not first and component in bordered))
            for loop, n_edges, perimeter, diameter, number, component, first, fraction, seams
            in zip(ordered, lengths[rank].tolist(), perimeters.tolist(), diameters.tolist(),
                   numbers.tolist(), owner.tolist(), is_largest.tolist(), span,
                   seam_edges(vertices, ordered), strict=True)]


# the loops measured at once are grouped by length, and a group's pairwise differences
# (diameters) are made in chunks of at most this many point pairs
_PAIRS_PER_CHUNK = 1 << 20


def _by_length(loops: list[np.ndarray], vertices: np.ndarray):
    """Per loop length ``k``: the positions in ``loops`` of the loops of ``k`` vertices and
    their points as one ``(m, k, 3)`` array (each row the same values, in the same order, as
    ``vertices[loop]``: the per-loop formulas applied along its axis 1 give the same bits)."""
    lengths = np.array([len(loop) for loop in loops])
    flat = np.concatenate(loops)
    starts = np.concatenate([[0], np.cumsum(lengths)[:-1]])
    for k in np.unique(lengths).tolist():
        at = np.flatnonzero(lengths == k)
        yield at, vertices[flat[starts[at][:, None] + np.arange(k)]]


def _loop_lengths(vertices: np.ndarray, loops: list[np.ndarray]
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Each loop's perimeter and diameter (:func:`loop_diameter`), the same bits as loop by
    loop, with numpy calls per loop length, not per loop."""
    perimeters, diameters = np.empty(len(loops)), np.empty(len(loops))
    for at, points in _by_length(loops, vertices):
        perimeters[at] = np.linalg.norm(points - np.roll(points, -1, axis=1), axis=2).sum(1)
        k = points.shape[1]
        if k > 1500:  # the convex hull's way, loop by loop (few loops are this long)
            diameters[at] = [loop_diameter(p) for p in points]
            continue
        step = max(1, _PAIRS_PER_CHUNK // (k * k))
        for c in range(0, len(at), step):
            chunk = points[c:c + step]
            d = chunk[:, :, None, :] - chunk[:, None, :, :]
            diameters[at[c:c + step]] = np.sqrt((d * d).sum(-1)).max(axis=(1, 2))
    return perimeters, diameters


def _spanned_areas(vertices: np.ndarray, loops: list[np.ndarray]) -> np.ndarray:
    """:func:`spanned_area` of each loop, the same bits, with numpy calls per loop length."""
    out = np.empty(len(loops))
    for at, points in _by_length(loops, vertices):
        centred = points - points.mean(axis=1, keepdims=True)
        vector = np.cross(centred, np.roll(centred, -1, axis=1)).sum(1)
        out[at] = 0.5 * np.linalg.norm(vector, axis=-1)
    return out


# a component is taken for no border once part of its area alone exceeds the span by this
# relative margin: far above the rounding of summing its faces' areas in another order
_PARTIAL_AREA_MARGIN = 1e-6


def _span_fractions(vertices: np.ndarray, faces: np.ndarray, label: np.ndarray,
                    spans: dict[int, float]) -> dict[int, float]:
    """Per component, the area its largest loop spans over the component's area (``spans``:
    component -> that spanned area, ``label``: component per vertex); NaN where the loop
    is small for certain (below ``MAY_BE_BORDER_FRACTION``).

    The faces' areas are summed block by block (:func:`face_blocks`, the blocks of
    :func:`face_areas`) and the sum stops as soon as every component's partial area clears
    its span with a margin: the holes of a closed surface cost one block of faces, not the
    whole mesh. Otherwise the areas are summed per component as one ``np.bincount`` over
    all faces (the same bits as one sum).
    """
    n = int(label.max()) + 1
    partial = np.zeros(n)
    components = np.fromiter(spans, dtype=np.int64, count=len(spans))
    spanned = np.fromiter(spans.values(), dtype=float, count=len(spans))
    # one flag per component, not a set rebuilt a block (a soup has a component a face)
    undecided = np.ones(len(spans), dtype=bool)
    areas = []
    for block in face_blocks(len(faces)):
        areas.append(face_areas(vertices, faces[block]))
        partial += np.bincount(label[faces[block, 0]], weights=areas[-1], minlength=n)
        undecided &= spanned >= MAY_BE_BORDER_FRACTION * partial[components] * (
            1 - _PARTIAL_AREA_MARGIN)
        if not undecided.any():
            return dict.fromkeys(spans, float("nan"))
    area = np.bincount(label[faces[:, 0]], weights=np.concatenate(areas), minlength=n)
    own = area[components]
    known = undecided & (own > 0)
    fraction = np.full(len(spans), np.nan)
    fraction[known] = spanned[known] / own[known]
    return dict(zip(spans, fraction.tolist(), strict=True))


def _largest_loops(owner: np.ndarray, spanned: np.ndarray) -> np.ndarray:
    """Per component (``owner``: per loop, sorted), the position of its largest loop: the
    one spanning the most area (``spanned``: per loop), the first of equals (the loops are
    longest first). That loop is the outer border's candidate: the border rule asks what
    part of the component a loop spans, and this one spans the most. Not the loop with the
    most edges: a scanned ring's inner edge may have more than its outer one (a finer
    scan there, or a jagged bore), and then neither was the border."""
    order = np.lexsort((np.arange(len(owner)), -spanned, owner))
    return order[np.r_[True, owner[order][1:] != owner[order][:-1]]]


def _inner_fractions(owner: np.ndarray, is_largest: np.ndarray, spanned: np.ndarray,
                     spans: dict[int, float], fractions: dict[int, float],
                     bordered: set[int]) -> dict[int, float]:
    """Per loop (its position: ``owner``, ``is_largest`` and ``spanned``, the area it
    spans, are per loop) that is not the largest of its component and whose component's
    largest loop is its outer border (``bordered``): the area the loop spans over the
    component's area. That area is the border's span over its fraction (both known there:
    the fraction is at least ``BORDER_SPAN_FRACTION``), so no face is summed again;
    components without a border (a closed surface's holes) cost nothing."""
    area = {c: spans[c] / fractions[c] for c in bordered}
    if not area:
        return {}
    at = np.flatnonzero(~is_largest & np.isin(owner, list(area))).tolist()
    return {k: float(spanned[k] / area[int(owner[k])]) for k in at}


def _zero_area_components(label: np.ndarray, spans: dict[int, float], components: np.ndarray,
                          perimeters: np.ndarray, vertices: np.ndarray,
                          faces: np.ndarray) -> set[int]:
    """The components (of ``label``) with loops whose faces all have zero area
    (:func:`~surfinpaint.geometry.validation.zero_area_faces`). The vector areas of a
    component's loops add up to its faces', so the loop of such a component (a stray
    degenerate triangle's) spans no area: only the components whose largest loop
    (``spans``: the area it spans; ``perimeters``: its length, per component of
    ``components``) spans at most ``_NO_AREA_SPAN`` times its perimeter squared are looked
    at, their faces alone (a closed surface's holes cost nothing more)."""
    span = np.array([spans[c] for c in components.tolist()])
    candidates = components[span <= _NO_AREA_SPAN * perimeters * perimeters].tolist()
    if not candidates:
        return set()
    rows = np.flatnonzero(np.isin(label[faces[:, 0]], candidates))
    flat = np.zeros(len(faces), dtype=bool)
    flat[rows[zero_area_faces(vertices, faces[rows])]] = True
    owner = label[faces[rows, 0]]
    # a component has no face with area when the count of its faces with area is zero
    with_area = np.bincount(owner[~flat[rows]], minlength=int(label.max()) + 1)
    return {c for c in candidates if with_area[c] == 0}


# a loop spanning less than this times its perimeter squared may bound zero-area faces only
# (then checked face by face); a round hole spans 1/(4π) of it, a slit's sides within
# SLIT_RTOL of each other about SLIT_RTOL
_NO_AREA_SPAN = 1e-2


def warn_degenerate(vertices: np.ndarray, faces: np.ndarray, path: str | None = None
                    ) -> None:
    """:func:`~surfinpaint.geometry.validation.validate_mesh` (its errors), and a
    :class:`~surfinpaint.io.MeshWarning` for each kind of degenerate face it reports, saying
    what the holes and the fills do with them (as :func:`surfinpaint.fill_holes` warns):
    for the commands that list the holes or report on their fills."""
    report = validate_mesh(vertices, faces, path=path)
    for note in degenerate_notes(face_ids(faces), report.repeated_vertex_faces,
                                 report.zero_area_faces):
        warnings.warn(f"{path}: {note}" if path else note, MeshWarning, stacklevel=2)


def over_size(n_edges: int, max_hole_edges: int | None) -> str | None:
    """Why a hole of ``n_edges`` boundary edges is skipped for its size (``max_hole_edges``,
    ``--max-hole-edges``; None: it is not): the rule of :func:`surfinpaint.fill_holes` and
    of ``surfinpaint holes``."""
    if max_hole_edges is not None and n_edges > max_hole_edges:
        return f"{n_edges} boundary edges > max_hole_edges={max_hole_edges}"
    return None


def select_holes(
    vertices: np.ndarray,
    faces: np.ndarray,
    holes: Sequence | None = None,
    *,
    include_border: bool = False,
    keep_margins: bool = False,
    table: EdgeTable | None = None,
    validate: bool = True,
    found: list[Hole] | None = None,
) -> list[np.ndarray]:
    """Oriented loops to fill, from a caller's choice.

    Parameters
    ----------
    holes : None, sequence of int, or sequence of loops
        None: every loop except outer borders (all loops with ``include_border``), and
        except the loops that may be a margin (:attr:`Hole.may_be_border`) with
        ``keep_margins``. Integers: indices into :func:`find_holes`' list. Sequences:
        boundary loops given by their vertex ids (any start, any direction). A hole named
        twice is chosen once.
    table : EdgeTable, optional
        The faces' edge table, if already built (passed on to :func:`find_holes`).
    validate : bool
        Check the mesh first (as :func:`find_holes`); False when the caller has.
    found : list of Hole, optional
        :func:`find_holes`' answer for this mesh, if already known (not recomputed, and the
        mesh taken as checked).

    Raises
    ------
    MeshError
        When the mesh is refused (as by :func:`find_holes`), an index is out of range, a
        loop names a vertex the mesh does not have or is not a boundary loop of the mesh.
    ValueError
        A hole index that is not a whole number (a bool too: ``True`` is no hole's name).
    """
    if holes is None:
        if found is None:
            found = find_holes(vertices, faces, table, validate=validate)
        return [h.loop for h in found if (include_border or not h.is_border)
                and not (keep_margins and h.may_be_border)]
    holes = list(holes)
    if not all(np.ndim(h) == 0 for h in holes):  # loops given by their vertex ids
        if validate and found is None:
            find_holes(vertices, faces, table)  # the mesh checked all the same
        for loop in holes:
            _check_loop_ids(loop, len(vertices))
        unique: dict[tuple, np.ndarray] = {}
        for loop in holes:  # by its vertices: any start, any direction
            unique.setdefault(tuple(sorted(np.asarray(loop).tolist())), loop)
        triangles = triangle_rows(face_ids(faces))[0]
        return [orient_loop(triangles, loop) for loop in unique.values()]
    if found is None:
        found = find_holes(vertices, faces, table, validate=validate)
    chosen: dict[int, np.ndarray] = {}
    for index in holes:
        if isinstance(index, bool | np.bool_) or int(index) != index:
            raise ValueError(f"hole indices must be integers, got {index!r}")
        if not 0 <= int(index) < len(found):
            raise MeshError(
                f"hole index {index} out of range: the mesh has "
                f"{how_many(len(found), 'boundary loop', 'boundary loops')}"
            )
        chosen.setdefault(int(index), found[int(index)].loop)
    return list(chosen.values())


def hole_numbers(vertices: np.ndarray, faces: np.ndarray, loops: Sequence[np.ndarray], *,
                 table: EdgeTable | None = None, validate: bool = True,
                 found: list[Hole] | None = None) -> list[int]:
    """The number :func:`find_holes` gives each of ``loops``: the one numbering that
    ``surfinpaint holes``, ``--holes``, every report, warning and error use.

    A loop is matched by its vertices (any start, any direction); -1 for a loop that
    :func:`find_holes` does not list as one (a piece of a loop pinched at a bow-tie).
    ``table`` and ``found`` as for :func:`select_holes`.
    """
    if found is None:
        found = find_holes(vertices, faces, table, validate=validate)
    if not loops or not found:
        return [-1] * len(loops)
    # only the found loops whose smallest vertex is one of ``loops``' are keyed (a triangle
    # soup has a loop a face, and a tuple each cost seconds)
    sizes = np.array([len(h.loop) for h in found])
    lowest = np.minimum.reduceat(np.concatenate([h.loop for h in found]),
                                 np.concatenate([[0], np.cumsum(sizes)[:-1]]))
    wanted = np.isin(lowest, [np.min(loop) for loop in loops if len(loop)])
    keyed = {tuple(sorted(map(int, found[k].loop))): k for k in np.flatnonzero(wanted).tolist()}
    return [keyed.get(tuple(sorted(map(int, loop))), -1) for loop in loops]


def _check_loop_ids(loop, n_vertices: int) -> None:
    """A caller's loop names vertices of the mesh by whole-number ids (else a MeshError
    naming the ids out of range, before any edge of the loop is looked up)."""
    ids = np.asarray(loop).ravel()
    if ids.size and not (np.issubdtype(ids.dtype, np.integer)
                         or (np.issubdtype(ids.dtype, np.floating)
                             and np.all(np.isfinite(ids)) and np.all(ids == np.round(ids)))):
        raise ValueError(f"a hole loop's vertex ids must be integers, got "
                         f"{preview(ids.tolist())}")
    bad = ids[(ids < 0) | (ids >= n_vertices)]
    if bad.size:
        named = f"{agreeing(bad.size, 'vertex', 'vertices')} {preview(bad.tolist())}"
        raise MeshError(f"hole loop {named} out of range: the mesh has "
                        f"{how_many(n_vertices, 'vertex', 'vertices')}",
                        vertices=bad.astype(np.int64)[:10].tolist())
