"""The triangle of a planar triangulation that holds each of many points.

For parameter domains: a mesh's conformal map, sampled at arbitrary points (the nodes of
an adaptive tree, the vertices of another map). A conformal map squeezes parts of a surface
into tiny spots (a fingertip's triangles 10⁻⁶ of the median area), so the triangles are
registered in a hierarchy of bucket grids (a "loose" quadtree): each triangle on the level
whose buckets are as large as its bounding box (2⁻ˡ of the domain's side), where it touches
at most 2 × 2 of them. Each point is tested, vectorized, against the triangles of its
bucket on each level, so the cost is about (points + triangles) × levels, however crowded
the triangles are. (A single uniform grid put thousands of a fingertip's triangles in one
bucket with thousands of an adaptive tree's nodes: 38 of the 45 s of a quadtree export of
a cow's hoof, session 21.)
"""

from __future__ import annotations

import numpy as np

__all__ = ["barycentric", "chunked_pairs", "locate_points"]

# candidate (point, triangle) pairs tested at once
_CHUNK = 2_000_000
# the finest bucket level (buckets 2⁻²⁴ of the domain's side: below a map's resolution in
# doubles), and the bits of a bucket's i and j in its key
_DEEPEST = 24
_KEY_BITS = 25


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


def barycentric(corners: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(k, 3) barycentric weights of ``points`` (k, 2) in the triangles ``corners``
    (k, 3, 2), one point per triangle; non-finite for a triangle of zero area."""
    e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    r = points - corners[:, 0]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    # a triangle of zero area gives non-finite weights, which its callers read as outside
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
    side = max(float((hi.max(axis=0) - origin).max()), np.finfo(float).tiny)
    # each triangle on the finest level whose buckets are at least as large as its box
    box = (hi - lo).max(axis=1)
    with np.errstate(divide="ignore"):
        level = np.floor(np.log2(side / box))
    level = np.nan_to_num(level, posinf=_DEEPEST).clip(0, _DEEPEST).astype(np.int64)
    # every triangle under each bucket its box touches (≤ 2 × 2), keyed (level, i, j)
    first, last = _cell(lo, origin, side, level), _cell(hi, origin, side, level)
    (ax, ay), (bx, by) = first.T, last.T
    wide, count = bx - ax + 1, (bx - ax + 1) * (by - ay + 1)
    tri = np.repeat(np.arange(len(q)), count)
    k = np.arange(len(tri)) - np.repeat(np.cumsum(count) - count, count)
    key = _key(level[tri], ax[tri] + k % wide[tri], ay[tri] + k // wide[tri])
    order = np.argsort(key, kind="stable")
    key, tri = key[order], tri[order]
    # each point against the triangles of its bucket on each level (a point off the
    # buckets against the nearest edge bucket's, which it fails unless it is within the
    # tolerance); of all, the one it is deepest in, the lowest index on a tie
    on = np.flatnonzero(np.isfinite(pts).all(axis=1))
    best = np.full(len(pts), -np.inf)
    for depth in np.unique(level):
        cell = _cell(pts[on], origin, side, np.full(len(on), depth))
        wanted = _key(np.full(len(on), depth), cell[:, 0], cell[:, 1])
        start = np.searchsorted(key, wanted, side="left")
        pairs = np.searchsorted(key, wanted, side="right") - start
        for owner, offset in chunked_pairs(pairs, _CHUNK):
            if len(owner) == 0:
                continue
            pid, cand = on[owner], tri[start[owner] + offset]
            w = barycentric(q[cand], pts[pid])
            least = np.where(np.isfinite(w).all(axis=1), w.min(axis=1), -np.inf)
            # per point (each in one chunk only), the candidate with the largest smallest
            # weight, the lowest index among equals
            pick = np.lexsort((cand, -least, pid))
            head = pick[np.r_[True, pid[pick][1:] != pid[pick][:-1]]]
            p, c, m = pid[head], cand[head], least[head]
            better = (m > best[p]) | ((m == best[p]) & (c < face_index[p]))
            p, c, m, w = p[better], c[better], m[better], w[head[better]]
            best[p], face_index[p], weights[p] = m, c, w
    outside = best < -tolerance
    face_index[outside] = -1
    weights[outside] = np.nan
    return face_index, weights


def _cell(points: np.ndarray, origin: np.ndarray, side: float, level: np.ndarray
          ) -> np.ndarray:
    """(i, j) of the bucket of each point on its level (``2**level`` buckets a side)."""
    n = np.left_shift(1, level)
    cell = np.floor((points - origin) / (side / n)[:, None]).astype(np.int64)
    return np.clip(cell, 0, (n - 1)[:, None])


def _key(level: np.ndarray, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    return (level << 2 * _KEY_BITS) | (i << _KEY_BITS) | j
