"""Fills that cross the surface away from their hole, found after the fill.

Each fill is checked against the surface within ``CROSSING_RINGS`` rings of its loop as it
is made (:func:`surfinpaint.fill.parallel.crossing_triangles`): that is where a folded loop makes
a fill cross. A fill can also reach through surface that is near in space but farther along
the mesh: the other bank of a brain's fold, the other side of a thin part. The neighbourhood
a hole is filled in may not even hold that surface. :func:`far_crossing_triangles` checks each
fill against the rest of the original faces near it, after all fills; the pipeline warns
where it finds any. No fill is changed by it.

Each hole is filled without the others' fills (they may be made at once, in worker
processes), so two holes near in space can have fills that cross each other:
:func:`crossing_fill_pairs` finds them, after all fills, and the pipeline warns naming both
holes. No fill is changed by it either.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from surfinpaint.fill.parallel import CROSSING_RINGS
from surfinpaint.geometry.intersection import intersecting_pairs
from surfinpaint.geometry.rows import row_norms

__all__ = ["CrossingFills", "crossing_fill_pairs", "far_crossing_triangles"]


def _within_rings(faces: np.ndarray, vertex_faces: sp.csr_matrix, loop: np.ndarray,
                  rings: int) -> np.ndarray:
    """The vertices within ``rings`` edge rings of ``loop`` (through the faces)."""
    near = np.asarray(loop, dtype=np.int64)
    for _ in range(rings):
        near = np.unique(faces[vertex_faces[near].indices])
    return near


def far_crossing_triangles(vertices: np.ndarray, faces: np.ndarray,
                           vertex_faces: sp.csr_matrix, hole_faces: list[np.ndarray],
                           loops: list[np.ndarray]) -> list[np.ndarray]:
    """Each fill's triangles that cross original faces that the check made with the fill
    (within ``CROSSING_RINGS`` rings of its loop) did not look at.

    Parameters
    ----------
    vertices : (n, 3) float array
        The filled mesh's vertices: the original ones first, then the fills'.
    faces : (f, 3) int array
        The original faces.
    vertex_faces : (m, f) sparse matrix
        Vertex-face incidence of ``faces`` over the ``m`` original vertices
        (:func:`~surfinpaint.geometry.degenerate.triangle_incidence`).
    hole_faces : list of (k, 3) int arrays
        Each fill's faces (ids into ``vertices``).
    loops : list of int arrays
        Each fill's hole loop (original vertex ids).

    Returns
    -------
    list of int64 arrays
        Per fill, its triangles (rows of its ``hole_faces``, sorted) that pierce or overlap
        an original face with
        no corner within ``CROSSING_RINGS`` rings of the loop and a corner in the fill's
        bounding box grown by its longest edge (:func:`~surfinpaint.geometry.intersection.
        intersecting_pairs`). A face that crosses the fill with every corner outside that
        box (a face much larger than the fill's edges) is not seen.

    Notes
    -----
    Cost: per fill, one comparison per original vertex along one axis, the rings of its
    loop, and the exact test on the faces in the box beyond them: 33-37 ms for the 10
    fills of the 651k-vertex sphere of ``benchmarks/scale.py`` (about 1.4 % of the fill).
    """
    v = np.asarray(vertices, dtype=float)
    n_original = vertex_faces.shape[0]
    # one contiguous column per axis: each narrows the last one's survivors (cheaper than
    # gathering whole rows of a slab, which on a closed surface holds a band around it)
    axes = [np.ascontiguousarray(v[:n_original, k]) for k in range(3)]
    none = np.empty(0, dtype=np.int64)
    crossing = []
    for fill, loop in zip(hole_faces, loops, strict=True):
        fill = np.asarray(fill, dtype=np.int64).reshape(-1, 3)
        if not len(fill):
            crossing.append(none)
            continue
        corners = v[fill]
        reach = float(row_norms(corners - np.roll(corners, 1, axis=1)).max())
        low, high = corners.min(axis=(0, 1)) - reach, corners.max(axis=(0, 1)) + reach
        boxed = np.flatnonzero((axes[0] >= low[0]) & (axes[0] <= high[0]))
        for k in (1, 2):
            along = axes[k][boxed]
            boxed = boxed[(along >= low[k]) & (along <= high[k])]
        # the faces with a corner within the rings were checked as the fill was made
        checked = _within_rings(faces, vertex_faces, loop, CROSSING_RINGS)
        beyond = boxed[~np.isin(boxed, checked)]
        if not len(beyond):
            crossing.append(none)
            continue
        other = faces[np.unique(vertex_faces[beyond].indices)]
        other = other[~np.isin(other, checked).any(axis=1)]
        pairs = intersecting_pairs(v, fill, other) if len(other) else ()
        crossing.append(np.unique(pairs[:, 0]).astype(np.int64) if len(pairs) else none)
    return crossing


class CrossingFills(NamedTuple):
    """Two fills that cross each other: their positions in the list of fills, and the
    triangles of each (rows of its faces, sorted) that cross the other's."""

    first: int
    second: int
    first_triangles: np.ndarray
    second_triangles: np.ndarray


def crossing_fill_pairs(vertices: np.ndarray,
                        hole_faces: list[np.ndarray]) -> list[CrossingFills]:
    """The pairs of fills whose triangles cross (pierce or overlap) each other.

    Parameters
    ----------
    vertices : (n, 3) float array
        The filled mesh's vertices.
    hole_faces : list of (k, 3) int arrays
        Each fill's faces (ids into ``vertices``).

    Returns
    -------
    list of CrossingFills
        In the order of the first fill, then the second (``first < second``). Fills that
        share loop vertices (two holes meeting at a vertex) touch there, which is not a
        crossing (:func:`~surfinpaint.geometry.intersection.triangles_intersect`).

    Notes
    -----
    Only the pairs whose bounding boxes overlap are tested, triangle by triangle
    (:func:`~surfinpaint.geometry.intersection.intersecting_pairs`): the boxes are swept
    along x (sorted by their low x, each box meets the run of those that start before it
    ends), then compared in y and z. Fills far apart, the rule, cost one box each.
    """
    v = np.asarray(vertices, dtype=float)
    fills = [np.asarray(f, dtype=np.int64).reshape(-1, 3) for f in hole_faces]
    made = np.flatnonzero([len(f) > 0 for f in fills])
    if len(made) < 2:
        return []
    low = np.array([v[fills[k]].min(axis=(0, 1)) for k in made])
    high = np.array([v[fills[k]].max(axis=(0, 1)) for k in made])
    # the sweep: by low x, box i meets in x the boxes after it that start before it ends
    order = np.argsort(low[:, 0], kind="stable")
    ends = np.searchsorted(low[order, 0], high[order, 0], side="right")
    runs = np.maximum(ends - np.arange(1, len(order) + 1), 0)
    first = np.repeat(np.arange(len(order)), runs)
    second = np.arange(len(first)) - np.repeat(np.cumsum(runs) - runs, runs) + first + 1
    a, b = order[first], order[second]
    meet = ((low[a] <= high[b]) & (low[b] <= high[a])).all(axis=1)
    a, b = np.minimum(a[meet], b[meet]), np.maximum(a[meet], b[meet])
    out = []
    for i, j in sorted(zip(made[a].tolist(), made[b].tolist(), strict=True)):
        pairs = intersecting_pairs(v, fills[i], fills[j])
        if len(pairs):
            out.append(CrossingFills(i, j, np.unique(pairs[:, 0]).astype(np.int64),
                                     np.unique(pairs[:, 1]).astype(np.int64)))
    return out
