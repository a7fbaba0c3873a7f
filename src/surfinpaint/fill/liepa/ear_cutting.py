"""A hole's loop triangulated by greedy ear cutting, as MeshFix does (Attene's TMesh,
``Basic_TMesh::TriangulateHole``, read in session 49): the front starts as the loop and
each step closes the ear at the front vertex whose ear triangle turns least, measured as
the corner's angle plus the dihedral angles between the ear and the two triangles beyond
its sides (``Vertex::getAngleForTriangulation``). An ear coplanar with both neighbours
costs only its corner, so the known surface's planes grow into the hole: on a machined
part the faces and their edges are continued, where the minimum-weight triangulation
(:mod:`.triangulation`, area second) cuts corners. No vertex is added.

docs/candidates.md, "Session 49 (helper): CAD holes PyMeshFix fills closer".
"""

from __future__ import annotations

import numpy as np

from surfinpaint.errors import FillError
from surfinpaint.fill.liepa.triangulation import existing_diagonals
from surfinpaint.geometry.mesh import halfedge_faces, orient_loop
from surfinpaint.geometry.rows import row_cross, row_norms

__all__ = ["ear_cut_triangulation"]

# an ear whose corner is straight (its triangle has no area) is cut only when nothing else
# can be: MeshFix's 3π
_STRAIGHT = 3 * np.pi
_FORBIDDEN = np.inf


def _angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise angle between vectors, atan2(|a × b|, a · b) (exact near 0 and π)."""
    return np.arctan2(row_norms(row_cross(a, b)), np.einsum("ij,ij->i", a, b))


def ear_cut_triangulation(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray
                          ) -> np.ndarray:
    """The faces that close the hole ``loop`` by greedy ear cutting (module docstring).

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        A consistently oriented mesh; every loop edge a boundary edge.
    loop : (k,) int array
        The hole's boundary loop, either direction, any start.

    Returns
    -------
    (k - 2, 3) int64 array
        The new faces, oriented as the mesh.

    Raises
    ------
    FillError
        When every remaining ear would join two vertices that are joined already.
    """
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    oriented = orient_loop(faces, loop)  # follows the known faces' half-edges
    owner, _ = halfedge_faces(faces, oriented)
    known = faces[owner]
    across = row_cross(v[known[:, 1]] - v[known[:, 0]], v[known[:, 2]] - v[known[:, 0]])
    front = oriented[::-1].copy()  # the patch's half-edges run the other way
    # normal beyond front edge (front[i], front[i + 1]): the known face on loop edge
    # (front[i + 1], front[i]), which is oriented edge k - 2 - i
    beyond = across[::-1][np.r_[1:len(front), 0]]
    joined = existing_diagonals(faces, front, len(v))
    joined = joined | joined.T
    pos = np.arange(len(front))  # each front vertex's index in ``joined``
    out = []
    while len(front) > 3:
        ear = _cheapest_ear(v, front, beyond, joined, pos)
        prev, nxt = (ear - 1) % len(front), (ear + 1) % len(front)
        a, b, c = front[prev], front[ear], front[nxt]
        out.append((a, b, c))
        joined[pos[prev], pos[nxt]] = joined[pos[nxt], pos[prev]] = True
        beyond[prev] = row_cross(v[[b]] - v[[a]], v[[c]] - v[[a]])[0]
        front, beyond, pos = (np.delete(x, ear, axis=0) for x in (front, beyond, pos))
    out.append(tuple(front))
    return _flattened_straight_ears(v, np.array(out, dtype=np.int64).reshape(-1, 3))


def _flattened_straight_ears(v: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """``tri`` with each zero-area triangle (a corner on its longest side, left where the
    greedy order ends on a straight run of the loop) flipped with the new triangle across
    that side: the two triangles made cover the same surface, neither is flat. One beside
    the loop stays (the caller checks)."""
    for _ in range(len(tri)):
        p = v[tri]
        sides = np.roll(p, -1, axis=1) - p  # side j from corner j to corner j + 1
        length = row_norms(sides.reshape(-1, 3)).reshape(-1, 3)
        area = row_norms(row_cross(sides[:, 0], sides[:, 1]))
        flat = np.flatnonzero(area <= 1e-12 * length.max(axis=1) ** 2)
        flipped = next((t for t in flat if _flip(tri, t, int(np.argmax(length[t])))), None)
        if flipped is None:
            return tri
    return tri


def _flip(tri: np.ndarray, t: int, side: int) -> bool:
    """Flip side ``side`` of triangle ``t`` (its half-edge a → c, the third corner b) with
    the triangle across it (half-edge c → a, third corner d), in place: (a, d, b) and
    (d, c, b), the same orientation. False where no triangle of ``tri`` is across."""
    a, c, b = (int(tri[t, (side + k) % 3]) for k in range(3))
    for u in np.flatnonzero(((tri == c) | (tri == a)).sum(axis=1) == 2):
        i = int(np.flatnonzero(tri[u] == c)[0])
        if u != t and tri[u, (i + 1) % 3] == a:
            d = int(tri[u, (i + 2) % 3])
            tri[t], tri[u] = (a, d, b), (d, c, b)
            return True
    return False


def _cheapest_ear(v: np.ndarray, front: np.ndarray, beyond: np.ndarray, joined: np.ndarray,
                  pos: np.ndarray) -> int:
    """The front index of the ear to cut next: least corner angle plus dihedral angles with
    the triangles beyond its two sides; ears that would join two joined vertices are never
    cut."""
    prev, nxt = np.roll(front, 1), np.roll(front, -1)
    to_prev, to_next = v[prev] - v[front], v[nxt] - v[front]
    corner = _angle(to_prev, to_next)
    normal = row_cross(v[front] - v[prev], v[nxt] - v[prev])
    cost = corner + _angle(normal, np.roll(beyond, 1, axis=0)) + _angle(normal, beyond)
    cost = np.where(np.isclose(corner, np.pi, rtol=0, atol=1e-12), _STRAIGHT, cost)
    cost[joined[np.roll(pos, 1), np.roll(pos, -1)]] = _FORBIDDEN
    if not np.isfinite(cost).any():
        raise FillError("ear cutting: every ear would join two vertices already joined")
    return int(np.argmin(cost))
