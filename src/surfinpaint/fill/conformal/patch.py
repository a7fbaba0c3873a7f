"""The disk patch around a filled hole: the fill plus rings of the surface around it."""

from __future__ import annotations

import numpy as np

from surfinpaint.errors import FillError
from surfinpaint.geometry.mesh import boundary_loops, faces_near, unique_edges

__all__ = ["hole_patch", "is_disk"]


def is_disk(faces: np.ndarray) -> bool:
    """Whether ``faces`` form a topological disk: edge-manifold, Euler characteristic 1, one
    boundary loop."""
    _, _, count = unique_edges(faces)
    if (count > 2).any():
        return False
    n_vertices = len(np.unique(faces))
    if n_vertices - len(count) + len(faces) != 1:
        return False
    try:
        return len(boundary_loops(faces)) == 1
    except ValueError:
        return False


def hole_patch(
    faces: np.ndarray, loop: np.ndarray, fill_faces: np.ndarray, rings: int
) -> tuple[np.ndarray, int]:
    """The disk patch around a filled hole: ``fill_faces`` plus up to ``rings`` face rings of
    ``faces`` around ``loop``.

    The rings shrink until the patch is a topological disk (a ring that reaches another hole
    or the mesh border would break that).

    Returns
    -------
    patch_faces : (p, 3) int array
        The fill's faces first, then the ring faces.
    rings : int
        The number of rings actually used.

    Raises
    ------
    FillError
        When not even one ring gives a disk.
    """
    n = int(max(faces.max(), fill_faces.max(), np.max(loop))) + 1
    for k in range(rings, 0, -1):
        patch = np.concatenate([fill_faces, faces_near(faces, loop, k - 1, n)])
        if is_disk(patch):
            return patch, k
    raise FillError("no disk-shaped patch around the hole: its neighbourhood is not a disk")
