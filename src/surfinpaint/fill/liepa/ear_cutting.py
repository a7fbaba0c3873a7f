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
    k = len(front)
    # normal beyond front edge (front[i], front[i + 1]): the known face on loop edge
    # (front[i + 1], front[i]), which is oriented edge k - 2 - i
    beyond = across[::-1][np.r_[1:k, 0]]
    joined = existing_diagonals(faces, front, len(v))
    joined = joined | joined.T
    # the front as a ring of slots (its loop positions: ``joined``'s indices), cut ears
    # unlinked and priced infinite, so argmin's first minimum is the front's in its order
    before, after = np.roll(np.arange(k), 1), np.roll(np.arange(k), -1)
    cost = _ear_costs(v, front, beyond, joined, before, after, np.arange(k))
    out = []
    for _ in range(k - 3):
        if not np.isfinite(cost).any():
            raise FillError("ear cutting: every ear would join two vertices already joined")
        ear = int(np.argmin(cost))
        prev, nxt = int(before[ear]), int(after[ear])
        a, b, c = front[prev], front[ear], front[nxt]
        out.append((a, b, c))
        joined[prev, nxt] = joined[nxt, prev] = True
        beyond[prev] = row_cross(v[[b]] - v[[a]], v[[c]] - v[[a]])[0]
        after[prev], before[nxt], cost[ear] = nxt, prev, np.inf
        # only the ears at the cut's two ends changed (their neighbours, the triangle
        # beyond); every other ear's cost is as it was
        ends = np.array([prev, nxt])
        cost[ends] = _ear_costs(v, front, beyond, joined, before, after, ends)
    last = int(np.argmin(cost))  # any slot left: the three in the front's order
    ring = [last, int(after[last]), int(after[after[last]])]
    out.append(tuple(front[sorted(ring)]))
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


def _ear_costs(v: np.ndarray, front: np.ndarray, beyond: np.ndarray, joined: np.ndarray,
               before: np.ndarray, after: np.ndarray, at: np.ndarray) -> np.ndarray:
    """The costs of the ears at front slots ``at`` (neighbours ``before``, ``after``):
    corner angle plus dihedral angles with the triangles beyond its two sides
    (``beyond[i]`` is beyond front edge (i, after[i])); an ear that would join two joined
    vertices costs infinity (never cut), a straight corner :data:`_STRAIGHT`."""
    prev_slot, next_slot = before[at], after[at]
    prev, here, nxt = v[front[prev_slot]], v[front[at]], v[front[next_slot]]
    corner = _angle(prev - here, nxt - here)
    normal = row_cross(here - prev, nxt - prev)
    cost = corner + _angle(normal, beyond[prev_slot]) + _angle(normal, beyond[at])
    # np.isclose(corner, π, rtol=0, atol=1e-12), without its overhead
    cost[np.abs(corner - np.pi) <= 1e-12] = _STRAIGHT
    cost[joined[prev_slot, next_slot]] = _FORBIDDEN
    return cost
