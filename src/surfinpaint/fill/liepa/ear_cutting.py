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
    return np.array(out, dtype=np.int64).reshape(-1, 3)


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
