"""The fill of a hole with islands inside it (:mod:`surfinpaint.fill.islands`): the region
between the hole's loop and the islands' loops is an annulus (a disk with one hole per
island), not a disk, so the λ-H method, which maps its patch onto a disk, does not apply. It
is filled the conventional way, Liepa's triangulate / refine / fair with every loop as
boundary:

1. each island's loop is spliced into the hole's by a *bridge*: two triangles on a loop edge
   at each end of the closest pair of vertices between the island's loop and the loop made
   so far (:func:`splice`). What is left to fill is then a disk, bounded by one loop with
   no repeated vertex: the hole's loop, across the bridge, around the island, and back;
2. that loop is triangulated (Liepa's minimum-weight triangulation, with the planar
   constrained Delaunay triangulation first where its projection is a simple polygon);
3. the bridges and that triangulation are refined together to the density of the
   surrounding mesh (Liepa's refinement, every edge of the original loops kept; the bridges'
   long edges are flipped and split like the others);
4. the new vertices are faired (:func:`~surfinpaint.fill.liepa.fairing.fair_orders`), every
   original vertex fixed: the rings around the hole's loop and around the islands' give the
   boundary conditions together.

A bridge is checked before it is used: projected on the hole's plane both its triangles
must turn the way the hole's fill does (of the four pairs of loop edges at the closest pair
of vertices, the first that does); otherwise the hole cannot be joined to that island, a
:class:`FillError`.
"""

from __future__ import annotations

import numpy as np

from surfinpaint.errors import FillError, MeshError
from surfinpaint.fill.islands import vector_area
from surfinpaint.fill.liepa.fairing import fair_orders
from surfinpaint.fill.liepa.refinement import refine_patch
from surfinpaint.fill.liepa.triangulation import minimum_weight_triangulation
from surfinpaint.geometry.mesh import faces_near

__all__ = ["annulus_fill", "splice"]

# rows of the loop-to-loop distance matrix per block (closest pair)
_BLOCK = 1 << 22


def _closest_pair(a: np.ndarray, b: np.ndarray) -> tuple[int, int]:
    """The positions in ``a`` and ``b`` (points) of their closest pair."""
    rows = max(1, _BLOCK // max(len(b), 1))
    best, at = np.inf, (0, 0)
    for start in range(0, len(a), rows):
        d = np.linalg.norm(a[start:start + rows, None, :] - b[None, :, :], axis=2)
        k = int(np.argmin(d))
        if d.flat[k] < best:
            best, at = float(d.flat[k]), (start + k // len(b), k % len(b))
    return at


def _turns(points: np.ndarray, triangles: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Per triangle, its area projected along ``normal`` (signed)."""
    p = points[triangles]
    return np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]) @ normal


def splice(vertices: np.ndarray, outer: np.ndarray, inner: np.ndarray,
           normal: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Join an island's loop to a hole's by a bridge of two triangles.

    Parameters
    ----------
    vertices : (n, 3) float array
    outer : (k,) int array
        The hole's loop (or a loop already spliced), oriented like the faces beside it (as
        :func:`~surfinpaint.fill.holes.find_holes` gives it).
    inner : (j,) int array
        The island's loop, oriented like the island's faces: in the hole's plane it turns
        the other way from ``outer`` (:attr:`~surfinpaint.fill.islands.Island.opposite`
        False).
    normal : (3,) float array, optional
        The fill's side of the hole's plane (default: from ``outer``'s vector area).

    Returns
    -------
    loop : (k + j,) int array
        The one loop left to fill, oriented like the faces beside it, the bridge's included.
    bridge : (2, 3) int array
        The bridge's triangles, oriented like the fill.

    Raises
    ------
    FillError
        When no bridge at the closest pair of vertices turns the fill's way in the hole's
        plane.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    >>> ring = np.column_stack([np.cos(t), np.sin(t), np.zeros(8)])
    >>> v = np.vstack([2 * ring, ring])
    >>> loop, bridge = splice(v, np.arange(8)[::-1], np.arange(8, 16))
    >>> len(loop), len(set(loop.tolist())), bridge.tolist()
    (16, 16, [[6, 7, 15], [7, 8, 15]])
    """
    v = np.asarray(vertices, dtype=float)
    outer = np.asarray(outer, dtype=np.int64)
    inner = np.asarray(inner, dtype=np.int64)
    if normal is None:  # the fill turns counter-clockwise about the reversed loop's area
        normal = -vector_area(v[outer])
    a, b = _closest_pair(v[outer], v[inner])
    k, j = len(outer), len(inner)
    # the loop edges outer[p] -> outer[p + 1] and inner[q] -> inner[q + 1] at the pair:
    # the fill takes them backwards, the triangles (outer[p + 1], outer[p], inner[q])
    # and (outer[p], inner[q + 1], inner[q]) (their diagonal at the pair when p = a and
    # q = b, beside it otherwise)
    for p in (a, (a - 1) % k):
        for q in (b, (b - 1) % j):
            bridge = np.array([[outer[(p + 1) % k], outer[p], inner[q]],
                               [outer[p], inner[(q + 1) % j], inner[q]]])
            if (_turns(v, bridge, normal) > 0).all():
                loop = np.concatenate([np.roll(outer, -(p + 1)), np.roll(inner, -(q + 1))])
                return loop, bridge
    raise FillError("cannot join the island's loop to the hole's: every bridge at their "
                    "closest vertices folds over in the hole's plane")


def annulus_fill(vertices: np.ndarray, faces: np.ndarray, outer: np.ndarray,
                 inners: list[np.ndarray], order: int = 2
                 ) -> tuple[np.ndarray, np.ndarray, int]:
    """Fill a hole with islands: splice, triangulate, refine, fair.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        The mesh around the loops (consistently oriented; the islands' pieces too).
    outer : int array
        The hole's loop, oriented like the faces beside it.
    inners : list of int arrays
        The islands' loops, each oriented like its island's faces (as :func:`splice`).
    order : int
        Fairing order (2 biharmonic, 3 triharmonic); order 2 where the rings around the
        loops cannot anchor a higher one.

    Returns
    -------
    new_vertices : (m, 3) float array
        The added vertices (ids ``n .. n + m - 1``).
    new_faces : (p, 3) int array
        The fill's faces over the original and the new ids, oriented like the mesh.
    order : int
        The fairing order used.

    Raises
    ------
    FillError
        When an island cannot be joined (:func:`splice`), or the triangulation or the
        fairing fails.

    Examples
    --------
    A unit sphere with a band 0.9 < z < 0.985 cut away around its north cap:

    >>> from surfinpaint.data import sphere
    >>> from surfinpaint.fill.holes import find_holes
    >>> v, f = sphere(4)
    >>> height = v[f].mean(axis=1)[:, 2]
    >>> hole, island = find_holes(v, f[(height < 0.9) | (height > 0.985)])
    >>> f = f[(height < 0.9) | (height > 0.985)]
    >>> new_v, new_f, used = annulus_fill(v, f, hole.loop, [island.loop])
    >>> bool(np.allclose(np.linalg.norm(new_v, axis=1), 1, atol=0.01)), used
    (True, 2)
    """
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    outer = np.asarray(outer, dtype=np.int64)
    inners = [np.asarray(inner, dtype=np.int64) for inner in inners]
    normal = -vector_area(v[outer])
    loop, bridges = outer, []
    for inner in inners:
        loop, bridge = splice(v, loop, inner, normal)
        bridges.append(bridge)
    bridges = np.concatenate(bridges)
    n = len(v)
    try:
        patch = minimum_weight_triangulation(v, loop, np.vstack([faces, bridges]),
                                             search="cdt")
        new_v, patch = refine_patch(v, np.vstack([bridges, patch]),
                                    np.concatenate([outer, *inners]), faces=faces,
                                    loops=[outer, *inners])
        if not len(new_v):
            return new_v, patch, order
        wanted = sorted({2, order})
        near = faces_near(faces, np.concatenate([outer, *inners]), max(order - 2, 0), n)
        made = fair_orders(np.vstack([v, new_v]), np.vstack([near, patch]),
                           np.arange(n, n + len(new_v)), wanted)
    except MeshError as err:
        raise FillError(f"cannot fill the hole with its islands: {err}") from err
    used = order if not isinstance(made[order], MeshError) else 2
    if isinstance(made[used], MeshError):
        raise FillError(f"cannot fair the hole with its islands: {made[used]}") from made[used]
    positions = made[used][n:]
    if not np.isfinite(positions).all():
        raise FillError("fairing the hole with its islands produced non-finite positions")
    return positions, patch, used
