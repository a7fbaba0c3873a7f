"""The disk patch around a filled hole: the fill plus rings of the surface around it."""

from __future__ import annotations

import numpy as np

from surfinpaint.errors import FillError
from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.geometry.mesh import boundary_loops, faces_near
from surfinpaint.geometry.rows import rows_any

__all__ = ["disk_loop", "grown_patch", "hole_patch", "hole_patch_and_boundary", "is_disk"]


def is_disk(faces: np.ndarray) -> bool:
    """Whether ``faces`` form a topological disk: edge-manifold, Euler characteristic 1, one
    boundary loop."""
    return disk_loop(faces) is not None


def disk_loop(faces: np.ndarray) -> np.ndarray | None:
    """The boundary loop of ``faces`` (as :func:`~surfinpaint.geometry.mesh.boundary_loops`
    gives it) when they form a topological disk (:func:`is_disk`), else None."""
    table = EdgeTable.build(faces)  # one edge sort for the counts and the loops
    count = table.count
    if (count > 2).any():
        return None
    n_vertices = len(np.unique(faces))
    if n_vertices - len(count) + len(faces) != 1:
        return None
    try:
        loops = boundary_loops(faces, table=table)
    except ValueError:
        return None
    return loops[0] if len(loops) == 1 else None


def hole_patch(
    faces: np.ndarray, loop: np.ndarray, fill_faces: np.ndarray, rings: int
) -> tuple[np.ndarray, int]:
    """The disk patch around a filled hole: ``fill_faces`` plus up to ``rings`` face rings of
    ``faces`` around ``loop``.

    The rings shrink until the patch is a topological disk (a ring that reaches another hole
    or the mesh border would break that); where not even one ring is a disk, the patch is
    grown unevenly (:func:`grown_patch`).

    Returns
    -------
    patch_faces : (p, 3) int array
        The fill's faces first, then the ring faces.
    rings : int
        The number of rings actually used.

    Raises
    ------
    FillError
        When not even the unevenly grown patch is a disk.
    """
    patch, k, _ = hole_patch_and_boundary(faces, loop, fill_faces, rings)
    return patch, k


def hole_patch_and_boundary(faces: np.ndarray, loop: np.ndarray, fill_faces: np.ndarray,
                            rings: int) -> tuple[np.ndarray, int, np.ndarray | None]:
    """:func:`hole_patch` and the patch's boundary loop (:func:`disk_loop`) where its rings
    made a disk (None where it was grown unevenly). Such a patch is also connected: its ring
    faces are reached from the loop, and the fill spans the loop."""
    n = int(max(faces.max(), fill_faces.max(), np.max(loop))) + 1
    for k in range(rings, 0, -1):
        patch = np.concatenate([fill_faces, faces_near(faces, loop, k - 1, n)])
        boundary = disk_loop(patch)
        if boundary is not None:
            return patch, k, boundary
    return grown_patch(faces, loop, fill_faces, rings), rings, None


def grown_patch(faces: np.ndarray, loop: np.ndarray, fill_faces: np.ndarray,
                rings: int) -> np.ndarray:
    """A disk patch grown unevenly: ``fill_faces`` plus the faces within ``rings`` rings
    of ``loop``, nearest ring first, each added only where it keeps the patch a disk.

    Where full rings close around a thin limb (or reach another hole) the patch grows on
    regardless, and the fronts that meet on the far side leave a slit instead: the patch
    keeps its rings near the hole, which the biharmonic stencil needs.

    Returns
    -------
    (p, 3) int array
        The fill's faces first, then the ring faces added.

    Raises
    ------
    FillError
        When the fill is not a disk holding every loop vertex, or the patch grown from it
        is still not a disk.
    """
    if not (is_disk(fill_faces) and np.isin(loop, fill_faces).all()):
        raise FillError("no disk-shaped patch around the hole: its fill is not a disk "
                        "on its loop")
    n = int(max(faces.max(), fill_faces.max(), np.max(loop))) + 1
    near = faces_near(faces, loop, rings - 1, n)
    # ring of each face: the vertex rings out from the loop, nearest first
    depth = np.full(n, rings + 1)
    mask = np.zeros(n, dtype=bool)
    mask[np.asarray(loop, dtype=np.int64)] = True
    depth[mask] = 0
    for k in range(1, rings + 1):
        mask[near[rows_any(mask[near])].ravel()] = True
        depth[mask & (depth > k)] = k
    order = near[np.argsort(depth[near].min(axis=1), kind="stable")]
    count: dict[tuple[int, int], int] = {}
    inside: set[int] = set()  # the patch's vertices (a set: each test looks up three)
    for face in np.asarray(fill_faces, dtype=np.int64).tolist():
        _add(face, count, inside)
    pending, added, grew = [tuple(t) for t in order.tolist()], [], True
    # a Python loop over the patch's ring faces, only where the full rings fail: each
    # face's test is local (its edges and vertices against the patch so far)
    while grew:
        grew, rest = False, []
        for face in pending:
            if _keeps_disk(face, count, inside):
                _add(face, count, inside)
                added.append(face)
                grew = True
            else:
                rest.append(face)
        pending = rest
    patch = np.vstack([fill_faces, np.array(added, dtype=np.int64).reshape(-1, 3)])
    if not is_disk(patch):
        raise FillError("no disk-shaped patch around the hole: its neighbourhood is not a "
                        "disk")
    return patch


def _edges_of(face):
    a, b, c = face
    return ((a, b) if a < b else (b, a), (b, c) if b < c else (c, b),
            (c, a) if c < a else (a, c))


def _add(face, count, inside):
    for e in _edges_of(face):
        count[e] = count.get(e, 0) + 1
    inside.update(face)


def _keeps_disk(face, count, inside) -> bool:
    """Whether a disk stays one with ``face`` added: glued along one boundary edge with
    its third vertex new, or along two (a notch filled)."""
    x, y, z = map(count.get, _edges_of(face), (0, 0, 0))
    if x > 1 or y > 1 or z > 1:
        return False
    a, b, c = face
    glued, touching = x + y + z, (a in inside) + (b in inside) + (c in inside)
    return (glued, touching) in ((1, 2), (2, 3))
