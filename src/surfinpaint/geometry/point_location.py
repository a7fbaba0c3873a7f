"""The triangle of a planar triangulation that holds each of many points.

For parameter domains: a mesh's conformal map, sampled at arbitrary points (the nodes of
an adaptive tree, the vertices of another map). The triangles are registered in a uniform
grid of buckets over their bounding boxes (about one bucket per triangle), and each point
is tested, vectorized, against the triangles of its bucket only; so the cost is about the
number of points plus the number of triangles, times the triangles a bucket holds where
they are crowded.
"""

from __future__ import annotations

import numpy as np

__all__ = ["chunked_pairs", "locate_points"]

# candidate (point, triangle) pairs tested at once
_CHUNK = 2_000_000


def chunked_pairs(count: np.ndarray, chunk: int):
    """Enumerate ``count[i]`` pairs for each ``i``, in chunks of about ``chunk`` pairs.

    Yields ``(owner, offset)`` int arrays: each pair's ``i`` (in order, each ``i`` in one
    chunk only) and its index ``0 … count[i] − 1`` among that ``i``'s pairs. For
    vectorized tests of many candidates each (points in a triangle's box, triangles in a
    point's bucket) without holding all of them at once.
    """
    count = np.asarray(count, dtype=np.int64)
    cum = np.cumsum(count)
    start = 0
    while start < len(count):
        base = cum[start - 1] if start else 0
        stop = max(int(np.searchsorted(cum, base + chunk, side="right")), start + 1)
        ids = np.arange(start, stop)
        c = count[ids]
        yield np.repeat(ids, c), np.arange(c.sum()) - np.repeat(np.cumsum(c) - c, c)
        start = stop


def _bucket_range(lo: np.ndarray, hi: np.ndarray, origin: np.ndarray, size: np.ndarray,
                  n: int) -> tuple[np.ndarray, np.ndarray]:
    first = np.floor((lo - origin) / size).astype(np.int64).clip(0, n - 1)
    last = np.floor((hi - origin) / size).astype(np.int64).clip(0, n - 1)
    return first, last


def _barycentric(corners: np.ndarray, points: np.ndarray) -> np.ndarray:
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    r = points - corners[:, 0]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        w1 = (r[:, 0] * e2[:, 1] - r[:, 1] * e2[:, 0]) / det
        w2 = (e1[:, 0] * r[:, 1] - e1[:, 1] * r[:, 0]) / det
    return np.column_stack([1.0 - w1 - w2, w1, w2])


def locate_points(uv: np.ndarray, faces: np.ndarray, points: np.ndarray, *,
                  tolerance: float = 1e-9) -> tuple[np.ndarray, np.ndarray]:
    """The triangle holding each point, and the point's barycentric weights in it.

    Parameters
    ----------
    uv : (n, 2) float array
        The triangulation's vertices in the plane.
    faces : (f, 3) int array
        Either orientation; degenerate triangles never hold a point.
    points : (p, 2) float array
    tolerance : float
        A point holds when its smallest barycentric weight is at least ``−tolerance`` (so
        points on an edge or a vertex are found). Of several triangles that hold a point
        (a shared edge, or triangles that overlap where a map folds) the one in which its
        smallest weight is largest is taken.

    Returns
    -------
    face_index : (p,) int array
        −1 for a point in no triangle.
    weights : (p, 3) float array
        NaN for a point in no triangle.

    Examples
    --------
    >>> uv = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    >>> f, w = locate_points(uv, np.array([[0, 1, 2], [1, 3, 2]]),
    ...                      np.array([[0.2, 0.2], [0.9, 0.8], [2.0, 0.0]]))
    >>> f.tolist(), w[0].round(3).tolist()
    ([0, 1, -1], [0.6, 0.2, 0.2])
    """
    q = np.asarray(uv, dtype=float)[np.asarray(faces, dtype=np.int64)]
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    face_index = np.full(len(pts), -1, dtype=np.int64)
    weights = np.full((len(pts), 3), np.nan)
    if len(q) == 0 or len(pts) == 0:
        return face_index, weights
    lo, hi = q.min(axis=1), q.max(axis=1)
    origin = lo.min(axis=0)
    n = max(1, int(np.sqrt(len(q))))
    size = np.maximum((hi.max(axis=0) - origin) / n, np.finfo(float).tiny)
    # every triangle under each bucket its bounding box touches, sorted by bucket
    (ax, ay), (bx, by) = (a.T for a in _bucket_range(lo, hi, origin, size, n))
    wide, count = bx - ax + 1, (bx - ax + 1) * (by - ay + 1)
    tri = np.repeat(np.arange(len(q)), count)
    k = np.arange(len(tri)) - np.repeat(np.cumsum(count) - count, count)
    bucket = (ax[tri] + k % wide[tri]) * n + ay[tri] + k // wide[tri]
    order = np.argsort(bucket, kind="stable")
    bucket, tri = bucket[order], tri[order]
    starts = np.searchsorted(bucket, np.arange(n * n + 1))
    # each point against the triangles of its bucket (a point off the buckets against the
    # nearest edge bucket's, which it fails unless it is within the tolerance)
    on = np.isfinite(pts).all(axis=1)
    cell = np.floor((np.where(on[:, None], pts, origin) - origin) / size)
    cell = cell.clip(0, n - 1).astype(np.int64)
    pb = cell[:, 0] * n + cell[:, 1]
    pairs = np.where(on, starts[pb + 1] - starts[pb], 0)
    best = np.full(len(pts), -np.inf)
    for pid, offset in chunked_pairs(pairs, _CHUNK):
        cand = tri[starts[pb[pid]] + offset]
        w = _barycentric(q[cand], pts[pid])
        least = np.where(np.isfinite(w).all(axis=1), w.min(axis=1), -np.inf)
        # per point (each in one chunk only), the candidate with the largest smallest weight
        pick = np.lexsort((-least, pid))
        head = pick[np.r_[True, pid[pick][1:] != pid[pick][:-1]]] if len(pick) else pick
        best[pid[head]] = least[head]
        face_index[pid[head]] = cand[head]
        weights[pid[head]] = w[head]
    outside = best < -tolerance
    face_index[outside] = -1
    weights[outside] = np.nan
    return face_index, weights
