"""Islands: a small separate piece of surface floating inside another piece's hole.

A scan often keeps a fragment of the surface inside a hole: a piece of its own, whose one
boundary loop lies inside the loop of the hole around it. The region to fill between the two
loops is then an annulus, not a disk. :func:`find_islands` tells which pieces are islands of
which holes; :mod:`surfinpaint.fill.annulus` fills the annulus (``islands="bridge"``, the
default of :func:`surfinpaint.fill_holes`).

The rule (:func:`island_offset`, :func:`find_islands`): a piece is an island of a hole when

- it has exactly one boundary loop (a closed piece has nothing to join; a piece with
  holes of its own is no fragment);
- its area is at most ``ISLAND_MAX_AREA_FRACTION`` of the area of the piece holding the
  hole;
- projected on the hole loop's plane (through the loop's centroid, normal to its vector
  area), at least ``ISLAND_MIN_INSIDE`` of its loop's vertices fall inside the hole's
  polygon (all of them where the hole is flat; on a folded surface, a brain's, a hole's
  loop runs in and out of the folds and its projection cuts across the island's);
- its loop's largest distance from that plane is at most ``ISLAND_MAX_OFFSET`` times the
  hole's diameter.

A piece that several holes would take (nested in projection: a hole inside the polygon of
a piece's outer loop filled with ``include_border``) is the island of the innermost one
(the smallest diameter). The table of cases is pinned in tests/test_islands.py.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from surfinpaint.fill.holes import Hole, loop_diameter
from surfinpaint.geometry.mesh import connected_components, face_areas

__all__ = ["ISLAND_MAX_AREA_FRACTION", "ISLAND_MAX_OFFSET", "ISLAND_MIN_INSIDE",
           "ISLAND_MODES", "Island",
           "check_islands_mode", "find_islands", "island_offset", "vector_area"]

#: what :func:`surfinpaint.fill_holes` does with a hole's islands: "bridge" fills the annulus
#: between the hole's loop and each island's (faired), "ignore" fills the hole as a disk
#: through or by the island and leaves the island as it is (with a warning)
ISLAND_MODES = ("bridge", "ignore")

# A fragment inside a hole is a small part of what was scanned: the sphere case's cap is
# 0.5 % of the piece around it. A tenth keeps two comparable objects (a small ball set in a
# ring) from being taken for fragments of one surface.
ISLAND_MAX_AREA_FRACTION = 0.1
# The removed surface bulges out of the hole loop's plane by up to about half the hole's
# diameter (a hemisphere cut away: exactly half); a fragment of it lies within that. The
# sphere case's cap lies 0.1 diameters off the plane; a piece on the far side of a sphere
# whose hole faces it, about one diameter of the sphere.
ISLAND_MAX_OFFSET = 0.5
# Of 12 annuli cut from fsaverage5's left pial surface (benchmarks/islands.py --sweep),
# every vertex of the island's loop projected inside the hole's polygon in 4; in 5 more,
# 52-92 % did (47 % in one). A piece beside the hole projects outside it whole.
ISLAND_MIN_INSIDE = 0.5

# loop vertices times polygon edges per block of the point-in-polygon test
_BLOCK = 1 << 22


@dataclass(frozen=True)
class Island:
    """A piece of surface found inside a hole.

    Attributes
    ----------
    hole : int
        The hole's number (as :func:`~surfinpaint.fill.holes.find_holes` numbers loops).
    loop : int
        The number of the island's one boundary loop.
    piece : int
        The island's piece (:attr:`Hole.component` of its loop).
    offset : float
        Its loop's largest distance from the hole loop's plane, over the hole's diameter.
    opposite : bool
        The island is wound opposite to the surface around the hole: in the hole's plane its
        loop turns the same way as the hole's (a consistently oriented island's turns the
        other way). Such an island is not joined: its faces would disagree with the fill's.
    loop_vertices : (j,) int array
        The island's loop, oriented like its faces.
    """

    hole: int
    loop: int
    piece: int
    offset: float
    opposite: bool = False
    loop_vertices: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=np.int64),
                                      compare=False, repr=False)


def check_islands_mode(islands: str) -> str:
    """``islands`` checked against :data:`ISLAND_MODES` (a ValueError otherwise)."""
    if not isinstance(islands, str) or islands not in ISLAND_MODES:
        raise ValueError(f"islands must be one of {', '.join(map(repr, ISLAND_MODES))}, "
                         f"got {islands!r}")
    return islands


def vector_area(points: np.ndarray) -> np.ndarray:
    """The vector area of a closed polygon (Newell): its normal times the area it spans,
    pointing the way the polygon turns counter-clockwise about it."""
    centred = np.asarray(points, dtype=float) - np.mean(points, axis=0)
    return 0.5 * np.cross(centred, np.roll(centred, -1, axis=0)).sum(axis=0)


def _inside_polygon(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Per 2-D point, whether it lies inside the closed 2-D ``polygon`` (crossing number,
    vectorized over points and edges in blocks)."""
    x1, y1 = polygon[:, 0], polygon[:, 1]
    x2, y2 = np.roll(x1, -1), np.roll(y1, -1)
    rows = max(1, _BLOCK // max(len(polygon), 1))
    inside = np.empty(len(points), dtype=bool)
    for start in range(0, len(points), rows):
        x = points[start:start + rows, :1]
        y = points[start:start + rows, 1:2]
        spans = (y1 > y) != (y2 > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            cross_x = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
        inside[start:start + rows] = (spans & (x < cross_x)).sum(axis=1) % 2 == 1
    return inside


def island_offset(hole_points: np.ndarray, loop_points: np.ndarray) -> float:
    """How far a loop lies from a hole's plane, or inf when it is not inside the hole.

    Parameters
    ----------
    hole_points : (k, 3) float array
        The hole's loop, in order.
    loop_points : (j, 3) float array
        The other loop (an island's candidate).

    Returns
    -------
    float
        The largest distance of ``loop_points`` from the hole loop's plane (through its
        centroid, normal to its :func:`vector_area`), over the hole's diameter; inf when
        fewer than ``ISLAND_MIN_INSIDE`` of the loop's vertices project inside the hole's
        polygon, or the hole spans no area.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    >>> ring = np.column_stack([np.cos(t), np.sin(t), np.zeros(12)])
    >>> island_offset(ring, 0.3 * ring + [0, 0, 0.2])
    0.1
    >>> island_offset(ring, 0.3 * ring + [2, 0, 0])
    inf
    """
    hole_points = np.asarray(hole_points, dtype=float)
    loop_points = np.asarray(loop_points, dtype=float)
    normal = vector_area(hole_points)
    length = float(np.linalg.norm(normal))
    diameter = float(np.ptp(hole_points, axis=0).max()) if len(hole_points) else 0.0
    if not length > 1e-12 * diameter * diameter or diameter == 0.0:
        return float("inf")
    normal /= length
    # two axes of the plane
    axis = np.eye(3)[int(np.argmin(np.abs(normal)))]
    u = np.cross(normal, axis)
    u /= np.linalg.norm(u)
    w = np.cross(normal, u)
    centre = hole_points.mean(axis=0)
    plane = np.column_stack([u, w])
    inside = _inside_polygon((loop_points - centre) @ plane, (hole_points - centre) @ plane)
    if not inside.mean() >= ISLAND_MIN_INSIDE:
        return float("inf")
    diameter = loop_diameter(hole_points)
    return round(float(np.abs((loop_points - centre) @ normal).max()) / diameter, 12)


def find_islands(vertices: np.ndarray, faces: np.ndarray, found: Sequence[Hole],
                 holes: Sequence[int] | None = None) -> list[Island]:
    """The islands of the holes: small pieces whose one loop lies inside a hole.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        The mesh's triangles (those :func:`~surfinpaint.fill.holes.find_holes` saw).
    found : list of Hole
        :func:`~surfinpaint.fill.holes.find_holes`' answer for the mesh.
    holes : sequence of int, optional
        The numbers of the holes to look in (those to be filled); None: every loop that is
        not an outer border.

    Returns
    -------
    list of Island
        By hole, then by island loop number; each island piece at most once (in the
        innermost hole that takes it: the smallest diameter), and none in a loop that is
        itself an island's. Empty when the mesh has one piece with loops.

    Examples
    --------
    >>> from surfinpaint.data import sphere
    >>> from surfinpaint.fill.holes import find_holes
    >>> v, f = sphere(4)
    >>> c = v[f].mean(1) / np.linalg.norm(v[f].mean(1), axis=1)[:, None]
    >>> f = f[(c[:, 2] > np.cos(np.radians(8))) | (c[:, 2] < np.cos(np.radians(25)))]
    >>> [(i.hole, i.loop, i.piece) for i in find_islands(v, f, find_holes(v, f))]
    [(0, 1, 1)]
    """
    holes = [k for k, h in enumerate(found) if not h.is_border] if holes is None \
        else sorted({int(k) for k in holes})
    loops_of = np.bincount([h.component for h in found], minlength=1)
    candidates = [k for k, h in enumerate(found) if loops_of[h.component] == 1
                  and not h.spans_no_area]
    if not holes or not candidates:
        return []
    vertices = np.asarray(vertices, dtype=float)
    # one reduction over the candidates' loops (a soup of faces has a loop a face)
    sizes = np.array([found[c].n_edges for c in candidates])
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    centroids = np.add.reduceat(vertices[np.concatenate([found[c].loop for c in candidates])],
                                starts, axis=0) / sizes[:, None]
    pairs = []  # (hole diameter, offset, hole, candidate) inside, by the geometry
    for k in holes:
        hole = found[k]
        points = vertices[hole.loop]
        # a loop inside the hole's polygon and near its plane has its centroid within
        # (1 + offset) diameters of the hole's centroid: the others are not looked at
        near = np.linalg.norm(centroids - points.mean(axis=0), axis=1) \
            <= (1.0 + ISLAND_MAX_OFFSET) * hole.diameter
        for c in np.asarray(candidates)[near]:
            if found[c].component == hole.component:
                continue
            offset = island_offset(points, vertices[found[c].loop])
            if offset <= ISLAND_MAX_OFFSET:
                pairs.append((hole.diameter, offset, k, int(c)))
    if not pairs:
        return []
    area = _piece_areas(vertices, faces, found)
    taken: dict[int, tuple[float, int]] = {}
    for _, offset, k, c in sorted(pairs):  # the innermost hole first
        if c not in taken and area[found[c].component] <= \
                ISLAND_MAX_AREA_FRACTION * area[found[k].component]:
            taken[c] = (offset, k)
    # a loop that is itself an island is no hole with islands: its hole takes it
    taken = {c: (offset, k) for c, (offset, k) in taken.items() if k not in taken}
    islands = []
    for c, (offset, k) in taken.items():
        same_turn = float(vector_area(vertices[found[k].loop])
                          @ vector_area(vertices[found[c].loop])) > 0
        islands.append(Island(hole=k, loop=c, piece=found[c].component, offset=offset,
                              opposite=same_turn, loop_vertices=found[c].loop))
    return sorted(islands, key=lambda i: (i.hole, i.loop))


def _piece_areas(vertices: np.ndarray, faces: np.ndarray, found: Sequence[Hole]
                 ) -> dict[int, float]:
    """Per piece with a loop in ``found`` (by :attr:`Hole.component`), its area."""
    faces = np.asarray(faces, dtype=np.int64)
    _, label = connected_components(faces, len(vertices))
    per_label = np.bincount(label[faces[:, 0]], weights=face_areas(vertices, faces),
                            minlength=int(label.max()) + 1)
    return {h.component: float(per_label[label[h.loop[0]]]) for h in found}
