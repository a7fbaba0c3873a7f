"""Whether a disk's map into the plane overlaps itself as a whole.

A map can flip no triangle (:func:`~surfinpaint.geometry.parameterization.flipped_faces`)
and still cover part of the plane twice: LSCM's free border curls over itself on a large
folded disk. Sampling such a map at points of the plane (a grid's or a quadtree's nodes)
then reads one sheet of the surface where the mesh has two.
"""

from __future__ import annotations

import numpy as np

from surfinpaint.geometry.mesh import boundary_loops

__all__ = ["border_crossings"]


def border_crossings(faces: np.ndarray, uv: np.ndarray, *, chunk: int = 1_000_000
                     ) -> np.ndarray:
    """Pairs of border edges of a disk's map that cross each other.

    A map with no flipped triangle can still overlap itself as a whole: LSCM's free border
    curls over itself on a large folded disk (a 50 mm pial disk's map crosses its border 3
    times), and a point of the plane there lies on two sheets of the surface. The map is an
    embedding exactly when its border is a simple polygon, so this is the test.

    Parameters
    ----------
    faces : (f, 3) int array
        A topological disk.
    uv : (n, 2) float array
    chunk : int
        Edge pairs tested at once.

    Returns
    -------
    (k, 2) int array
        Positions along the border loop (``boundary_loops(faces)[0]``) of the first edge
        of each crossing pair; edges that share a vertex never count.
    """
    loop = boundary_loops(np.asarray(faces, dtype=np.int64))[0]
    q = np.asarray(uv, dtype=float)
    a, b = q[loop], q[np.roll(loop, -1)]
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    n = len(loop)
    found = []
    rows = max(1, chunk // max(n, 1))
    for start in range(0, n, rows):
        i, j = np.nonzero(np.arange(start, min(start + rows, n))[:, None]
                          < np.arange(n)[None, :] - 1)
        i += start
        keep = ~((i == 0) & (j == n - 1))  # the loop's last edge meets its first
        keep &= (lo[i] <= hi[j]).all(axis=1) & (lo[j] <= hi[i]).all(axis=1)
        i, j = i[keep], j[keep]
        d1, d2 = _orientation(a[i], b[i], a[j]), _orientation(a[i], b[i], b[j])
        d3, d4 = _orientation(a[j], b[j], a[i]), _orientation(a[j], b[j], b[i])
        cross = (d1 * d2 < 0) & (d3 * d4 < 0)
        found.append(np.column_stack([i[cross], j[cross]]))
    return np.vstack(found) if found else np.zeros((0, 2), dtype=np.int64)


def _orientation(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    return np.sign((q[:, 0] - p[:, 0]) * (r[:, 1] - p[:, 1])
                   - (q[:, 1] - p[:, 1]) * (r[:, 0] - p[:, 0]))
