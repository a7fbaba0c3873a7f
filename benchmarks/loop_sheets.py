"""Whether a hole reaches across a thin part, from its boundary loop only (truth-free): a
study's measure (``thin_holes.py``), not used by any fill.

A hole cut wider than the part it sits on (a tentacle's tip, a flange's rim, a blade) wraps
over the part's edge: its loop runs on both faces of the part, and the known surface at the
loop faces two opposite ways, each side behind the other's tangent plane (the part is convex
there). The facing walls of a slot also face opposite ways, but each lies in front of the
other's plane, so they are not counted. docs/selfcheck.md "Session 48 (helper): holes across
thin parts".
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from surfinpaint.geometry.mesh import faces_near, vertex_normals

# two loop vertices face opposite ways when their normals' dot product is below this
# (the truth-based test's threshold, docs/validation.md "Holdout set 24 (session 47)")
OPPOSED_DOT = -0.5


@dataclass(frozen=True)
class LoopSheets:
    """How a hole's loop runs on two opposite faces of a part.

    Attributes
    ----------
    opposed : float
        The fraction of the loop's length at vertices that face away from some other loop
        vertex (normals' dot below ``OPPOSED_DOT``, each behind the other's tangent plane);
        0 on a loop that stays on one side of the part. By length, not by vertex count:
        a sharp rim's side face can be meshed much finer than the faces it joins.
    gap : float
        The least distance between two such loop vertices, over the loop's diameter (about
        the part's thickness over the hole's width); ``inf`` where no pair faces away.
    """

    opposed: float
    gap: float


def facing_away(points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """(k, k) bool: points i and j face opposite ways (normals' dot below ``OPPOSED_DOT``)
    and each lies behind the other's tangent plane, a convex part between them.

    Examples
    --------
    >>> p = np.array([[0.0, 0, 1], [0, 0, -1], [0, 0, 3]])
    >>> n = np.array([[0.0, 0, 1], [0, 0, -1], [0, 0, -1]])
    >>> facing_away(p, n).astype(int).tolist()  # 0, 1: a plate's faces; 0, 2: a slot's
    [[0, 1, 0], [1, 0, 0], [0, 0, 0]]
    """
    step = points[None, :, :] - points[:, None, :]  # step[i, j] = p_j - p_i
    behind = np.einsum("ijk,ik->ij", step, normals) < 0  # p_j behind p_i's plane
    return (normals @ normals.T < OPPOSED_DOT) & behind & behind.T


def loop_sheets(vertices: np.ndarray, faces: np.ndarray, loop) -> LoopSheets:
    """The loop's two opposite sheets, if it has them (truth-free: the known faces only).

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        The mesh with the hole (the known surface).
    loop : (k,) int array
        The hole's boundary loop.

    Returns
    -------
    LoopSheets

    Examples
    --------
    >>> from surfinpaint.data import sphere
    >>> from surfinpaint.geometry.cutting import cut_geodesic_disk
    >>> v, f = sphere(3)
    >>> cut = cut_geodesic_disk(v, f, 0, 0.4)
    >>> loop_sheets(cut.vertices, cut.faces, cut.loop).opposed
    0.0
    """
    loop = np.asarray(loop, dtype=np.int64)
    near = faces_near(faces, loop, 0, len(vertices))  # the known faces at the loop
    points = np.asarray(vertices, dtype=float)[loop]
    pairs = facing_away(points, vertex_normals(vertices, near)[loop])
    if not pairs.any():
        return LoopSheets(0.0, float("inf"))
    distance = np.linalg.norm(points[None, :, :] - points[:, None, :], axis=2)
    edges = np.diagonal(distance, offset=1).tolist() + [distance[-1, 0]]  # edge i: i → i+1
    length = 0.5 * (np.asarray(edges) + np.roll(edges, 1))  # half of each edge at a vertex
    opposed = float(length[pairs.any(axis=1)].sum() / length.sum())
    return LoopSheets(opposed, float(distance[pairs].min() / distance.max()))
