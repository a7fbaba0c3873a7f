"""Holes of a triangle mesh: its boundary loops, measured, and which of them to fill."""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from surfinpaint.errors import MeshError
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
           "over_size", "percent_below", "seam_edges", "warn_degenerate"]

# A component's longest loop is its outer border when the area the loop spans is at least
# this fraction of the component's own area: a scan's border spans about its whole area
# (0.6–1), while a hole in a closed surface spans a small part of what remains (a third of a
# sphere removed spans 0.33).
BORDER_SPAN_FRACTION = 0.4
# A component's longest loop spanning at least this fraction (but less than the border's) is
# filled as a hole, with a warning: it may be an open surface's margin, e.g. a tooth crown
# scanned down to the gum (its margin spans about a third of the crown's area), which the
# area alone cannot tell from a large hole in a closed surface (a tenth of a sphere removed
# spans 0.1 of what remains).
MAY_BE_BORDER_FRACTION = 0.1


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
        For its component's longest loop, the area the loop spans over the component's area
        (``is_border`` from ``BORDER_SPAN_FRACTION``); NaN for the other loops and where a
        first part of the component's area was enough to tell the loop is small.
    spans_no_area : bool
        Every face of its component has zero area (collinear or coincident corners, as
        :func:`~surfinpaint.geometry.validation.zero_area_faces` finds them: a stray
        degenerate triangle, say): the loop spans no area, like a slit, and no fill of it
        is a surface, so it is never filled (left open with a warning).
    seam_edges : (n_edges,) bool array or None
        Per loop edge (``loop[i]`` to ``loop[i + 1]``), whether it lies exactly on another
        boundary edge (:func:`seam_edges`): faces that meet there do not join.
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

    @property
    def runs_along_other_loops(self) -> bool:
        """Every edge of the loop lies exactly on another boundary edge: the loop is a seam
        between faces that do not join (their own copies of the vertices they share), not a
        hole, and it is never filled (left open with a warning; merge coincident vertices
        first). trimesh splits a textured mesh so along its UV seams."""
        return self.seam_edges is not None and bool(self.seam_edges.all())

    @property
    def may_be_border(self) -> bool:
        """A hole (not ``is_border``) that spans at least ``MAY_BE_BORDER_FRACTION`` of its
        component: it may be an open surface's margin; filling it by default warns."""
        return not self.is_border and self.span_fraction >= MAY_BE_BORDER_FRACTION


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
    _, point = np.unique(np.asarray(vertices, dtype=float)[ids], axis=0, return_inverse=True)
    first = point.ravel()[at.ravel()]
    second = np.concatenate([np.roll(p, -1) for p in np.split(first, cuts)])
    keys = np.sort(np.column_stack([first, second]), axis=1)
    _, key = np.unique(keys, axis=0, return_inverse=True)
    key = key.ravel()
    owner = np.repeat(np.arange(len(loops)), sizes)
    # the loops each edge's points appear in, each loop once
    pairs = np.unique(np.column_stack([key, owner]), axis=0)
    loops_at = np.bincount(pairs[:, 0], minlength=key.max() + 1)
    return np.split(loops_at[key] > 1, cuts)


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


def _spanned_area(points: np.ndarray) -> float:
    """Norm of the vector area of a closed polygon: the area of a surface it bounds, at least."""
    centred = points - points.mean(axis=0)
    return 0.5 * float(np.linalg.norm(np.cross(centred, np.roll(centred, -1, axis=0)).sum(0)))


def find_holes(vertices: np.ndarray, faces: np.ndarray | None = None,
               table: EdgeTable | None = None, *, validate: bool = True) -> list[Hole]:
    """Boundary loops of a mesh, measured, with the outer borders flagged.

    Every boundary loop is returned. Faces that use a vertex twice are no triangles and are
    left out (:func:`~surfinpaint.geometry.degenerate.triangle_rows`): their two edges
    between the same two vertices would otherwise open a slit in the surface. In each
    connected component the longest loop is flagged ``is_border`` when it spans at least
    ``BORDER_SPAN_FRACTION`` of that component's area (an open scan's outer edge); all
    other loops are holes. Callers choose what to fill with :func:`select_holes`.

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
    ordered = sorted(loops, key=lambda l: (label[l[0]], -len(l)))
    spans: dict[int, float] = {}  # per component, the area its longest loop spans
    for loop in ordered:
        component = int(label[loop[0]])
        if component not in spans:
            spans[component] = _spanned_area(vertices[loop])
    fractions = _span_fractions(vertices, faces, label, spans)
    flat = _zero_area_components(vertices, faces, label, spans, ordered)
    # numbered over the components with faces: a vertex no face uses (left where faces were
    # cut away) is a component of its own in the labels and would skip numbers. A face's
    # three vertices share its component (the labels are of its edges), so its first
    # vertex's label is enough: a count of those in place of np.unique of every corner's
    # (651k case: 0.004 instead of 0.04 s, the same sorted ids; docs/scale.md, session 36)
    surface = np.flatnonzero(np.bincount(label[faces[:, 0]]))
    holes: list[Hole] = []
    longest_seen: set[int] = set()
    for loop, seams in zip(ordered, seam_edges(vertices, ordered), strict=True):
        points = vertices[loop]
        perimeter = float(np.linalg.norm(points - np.roll(points, -1, axis=0), axis=1).sum())
        component = int(label[loop[0]])
        fraction = fractions[component] if component not in longest_seen else float("nan")
        longest_seen.add(component)
        holes.append(
            Hole(loop=loop, n_edges=len(loop), perimeter=perimeter,
                 diameter=loop_diameter(points),
                 component=int(np.searchsorted(surface, component)),
                 is_border=bool(fraction >= BORDER_SPAN_FRACTION), span_fraction=fraction,
                 spans_no_area=component in flat, seam_edges=seams)
        )
    return holes


# a component is taken for no border once part of its area alone exceeds the span by this
# relative margin: far above the rounding of summing its faces' areas in another order
_PARTIAL_AREA_MARGIN = 1e-6


def _span_fractions(vertices: np.ndarray, faces: np.ndarray, label: np.ndarray,
                    spans: dict[int, float]) -> dict[int, float]:
    """Per component, the area its longest loop spans over the component's area (``spans``:
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
    areas, undecided = [], set(spans)
    for block in face_blocks(len(faces)):
        areas.append(face_areas(vertices, faces[block]))
        partial += np.bincount(label[faces[block, 0]], weights=areas[-1], minlength=n)
        undecided = {c for c in undecided if spans[c] >= MAY_BE_BORDER_FRACTION * partial[c]
                     * (1 - _PARTIAL_AREA_MARGIN)}
        if not undecided:
            return dict.fromkeys(spans, float("nan"))
    area = np.bincount(label[faces[:, 0]], weights=np.concatenate(areas), minlength=n)
    return {c: float(span / area[c]) if c in undecided and area[c] > 0 else float("nan")
            for c, span in spans.items()}


def _zero_area_components(vertices: np.ndarray, faces: np.ndarray, label: np.ndarray,
                          spans: dict[int, float], ordered: list[np.ndarray]) -> set[int]:
    """The components (of ``label``) with loops whose faces all have zero area
    (:func:`~surfinpaint.geometry.validation.zero_area_faces`). The vector areas of a
    component's loops add up to its faces', so the loop of such a component (a stray
    degenerate triangle's) spans no area: only the components whose longest loop (the
    first of ``ordered``'s, ``spans`` its spanned area) spans at most ``_NO_AREA_SPAN``
    times its perimeter squared are looked at, their faces alone (a closed surface's holes
    cost nothing more)."""
    candidates, seen = [], set()
    for loop in ordered:  # a component's longest loop first
        component = int(label[loop[0]])
        if component in seen:
            continue
        seen.add(component)
        points = vertices[loop]
        perimeter = float(np.linalg.norm(points - np.roll(points, -1, axis=0), axis=1).sum())
        if spans[component] <= _NO_AREA_SPAN * perimeter * perimeter:
            candidates.append(component)
    if not candidates:
        return set()
    rows = np.flatnonzero(np.isin(label[faces[:, 0]], candidates))
    flat = np.zeros(len(faces), dtype=bool)
    flat[rows[zero_area_faces(vertices, faces[rows])]] = True
    owner = label[faces[rows, 0]]
    return {c for c in candidates if flat[rows[owner == c]].all()}


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
        When the mesh is refused (as by :func:`find_holes`), an index is out of range or a
        loop is not a boundary loop of the mesh.
    ValueError
        A hole index that is not a whole number.
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
        unique: dict[tuple, np.ndarray] = {}
        for loop in holes:  # by its vertices: any start, any direction
            unique.setdefault(tuple(sorted(np.asarray(loop).tolist())), loop)
        triangles = triangle_rows(face_ids(faces))[0]
        return [orient_loop(triangles, loop) for loop in unique.values()]
    if found is None:
        found = find_holes(vertices, faces, table, validate=validate)
    chosen: dict[int, np.ndarray] = {}
    for index in holes:
        if int(index) != index:
            raise ValueError(f"hole indices must be integers, got {index!r}")
        if not 0 <= int(index) < len(found):
            raise MeshError(
                f"hole index {index} out of range: the mesh has {len(found)} boundary loops"
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
    found = {tuple(sorted(map(int, h.loop))): k for k, h in enumerate(found)}
    return [found.get(tuple(sorted(map(int, loop))), -1) for loop in loops]
