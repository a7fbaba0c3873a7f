"""The fill of a hole across the edge where two planes meet (a scanned part's edge that the
crease search does not see in the noise, :func:`surfinpaint.geometry.flatness.
two_plane_test`): split along the planes' meeting line as a crease is
(:func:`surfinpaint.fill.creases.split_fill`), each side laid on its own plane.
"""

from __future__ import annotations

import numpy as np

from surfinpaint.errors import FillError, how_many
from surfinpaint.fill.creases import Crease, cut_along, split_fill
from surfinpaint.geometry.flatness import meeting_line
from surfinpaint.geometry.mesh import connected_components, face_cross

__all__ = ["split_on_two_planes"]


def split_on_two_planes(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                        first: tuple[np.ndarray, np.ndarray],
                        second: tuple[np.ndarray, np.ndarray], *, order: int = 2
                        ) -> tuple[np.ndarray, np.ndarray]:
    """A hole across the edge where two planes meet, split along that edge: the hole cut in
    two by a path of new vertices on the planes' meeting line between the two loop vertices
    where the loop changes plane (:func:`~surfinpaint.fill.creases.split_fill`, the crease
    search's split, with the line as a known crease), each side triangulated, refined and
    faired (order ``order``) with the path fixed, then each side's new vertices laid on its
    own plane. The path's vertices are on both planes, so every triangle lies in one plane
    but those at the two loop vertices, which are where the loop puts them.

    Why: :func:`laid_on_two_planes` lays the faired fill's vertices on the planes but keeps
    its triangles, so those that straddle the line cut the edge off (a bevel).

    Parameters
    ----------
    vertices, faces, loop :
        The mesh and the hole (loop oriented as :func:`surfinpaint.geometry.mesh.
        boundary_loops` gives it).
    first, second : (centre, unit normal) pairs
        The planes, as in :func:`laid_on_two_planes`; each loop vertex belongs to the one
        nearer it.
    order : int
        Fairing order of the sides (2 where they are too narrow for more).

    Returns
    -------
    new_vertices : (m, 3) float array
        The path's vertices first, then the sides' (ids ``n ..``).
    new_faces : (p, 3) int array
        The fill, oriented like the mesh.

    Raises
    ------
    FillError
        Where the split cannot be made (in words): the loop changes plane more than twice
        away from the line, a side without loop vertices of its own, a side that cannot be
        filled, a fill whose triangles fold once laid on the planes; or the planes are
        parallel.
    """
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    loop = np.asarray(loop, dtype=np.int64).ravel()
    planes = [(np.asarray(c, dtype=float), np.asarray(m, dtype=float)) for c, m in (first, second)]
    try:
        on_line, direction, _ = meeting_line(*planes[0], *planes[1])
    except ValueError as err:
        raise FillError(str(err)) from err
    second_side = (np.abs((v[loop] - planes[1][0]) @ planes[1][1])
                   < np.abs((v[loop] - planes[0][0]) @ planes[0][1]))
    ends = _line_ends(v[loop], second_side, on_line, direction)
    toward = np.sign((v[loop[ends[1]]] - v[loop[ends[0]]]) @ direction) or 1.0
    crease = Crease(ends=ends, chains=[loop[ends[:1]], loop[ends[1:]]],
                    directions=np.array([toward * direction, -toward * direction]),
                    angle=float(np.degrees(np.arccos(min(1.0, abs(planes[0][1]
                                                                  @ planes[1][1]))))),
                    line=(on_line, direction))
    new_v, new_f, cut_edges = split_fill(v, faces, loop, [crease], order=order)
    n = len(v)
    path = cut_edges[(cut_edges >= n).any(axis=1)]  # the others are known sharp edges
    on_path = np.zeros(n + len(new_v), dtype=bool)
    on_path[path] = True
    # each face's side: the fill cut open along the path, in pieces (as the crease fill's
    # λ-H pass cuts it, fill.conformal.mesh_pass)
    cut, parent = cut_along(new_f, path)
    side = np.unique(connected_components(cut, len(parent))[1][cut[:, 0]],
                     return_inverse=True)[1]
    is_second = np.zeros(n, dtype=bool)
    is_second[loop] = second_side
    allv = np.vstack([v, new_v])
    laid = allv.copy()
    plane_of = []
    for label in range(side.max() + 1):
        own = np.unique(new_f[side == label])
        known = own[(own < n) & ~on_path[own]]
        if len(known) == 0:
            raise FillError("a side of the split has no loop vertex of its own")
        plane_of.append(int(2 * is_second[known].sum() > len(known)))
        inner = own[(own >= n) & ~on_path[own]]
        c, m = planes[plane_of[-1]]
        laid[inner] = allv[inner] - np.outer((allv[inner] - c) @ m, m)
    if len(plane_of) != 2 or plane_of[0] == plane_of[1]:
        raise FillError(f"the split gave {how_many(len(plane_of), 'side', 'sides')}, not one "
                        "on each plane")
    _check_unfolded(face_cross(allv, new_f), face_cross(laid, new_f))
    if not np.isfinite(laid).all():
        raise FillError("laid on their planes, the sides' positions are not finite")
    return laid[n:], new_f


def _line_ends(points: np.ndarray, second_side: np.ndarray, on_line: np.ndarray,
               direction: np.ndarray) -> np.ndarray:
    """Where a meeting line enters and leaves a hole: two positions in the loop (ascending),
    the loop vertex nearer the line at a change of plane, one at each end of the changes
    along the line. Between them, each arc of the loop is on one plane, but for vertices
    within a mean loop edge of the line (noise); else a :class:`FillError`."""
    k = len(points)
    rel = points - on_line
    along = rel @ direction
    off = np.linalg.norm(rel - np.outer(along, direction), axis=1)
    changes = np.flatnonzero(second_side != np.roll(second_side, -1))
    if len(changes) < 2:
        raise FillError("the loop does not change plane")
    nearer = np.where(off[changes] <= off[(changes + 1) % k], changes, (changes + 1) % k)
    # the changes at either end of the hole along the line (a noisy loop changes plane
    # several times where it runs near the line): the one nearest the line at each
    order = np.argsort(along[nearer])
    cut = int(np.argmax(np.diff(along[nearer][order]))) + 1
    ends = np.sort([nearer[g][np.argmin(off[nearer[g]])] for g in (order[:cut], order[cut:])])
    tolerance = float(np.linalg.norm(points - np.roll(points, 1, axis=0), axis=1).mean())
    if (off[ends] > tolerance).any():
        raise FillError("the meeting line passes no loop vertex where the loop changes plane")
    arcs = [np.arange(ends[0] + 1, ends[1]), np.arange(ends[1] + 1, ends[0] + k) % k]
    labels = []
    for arc in arcs:
        if len(arc) == 0:
            raise FillError("a side of the split has no loop vertex of its own")
        label = 2 * second_side[arc].sum() > len(arc)
        if (off[arc[second_side[arc] != label]] > tolerance).any():
            raise FillError("the meeting line crosses the loop more than twice")
        labels.append(label)
    if labels[0] == labels[1]:
        raise FillError("the loop's two arcs between the line's ends are on one plane")
    return ends


def _check_unfolded(before: np.ndarray, after: np.ndarray) -> None:
    """A :class:`FillError` where a face laid on its plane turned over or collapsed (its
    area vector ``after`` against ``before``, the faired fill's)."""
    area = np.linalg.norm(before, axis=1)
    if (np.einsum("ij,ij->i", before, after) <= 1e-6 * area * area).any():
        raise FillError("laid on their planes, the sides' triangles fold")
