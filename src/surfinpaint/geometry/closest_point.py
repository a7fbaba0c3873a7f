"""The exact closest point on a triangle, for many point–triangle pairs at once: the
geometry under :mod:`surfinpaint.geometry.metrics`' distances, which add the search for
each point's nearest triangles."""

from __future__ import annotations

import numpy as np

__all__ = ["closest_point_on_triangles"]


_FLAT = 1e-20  # |ab × ac|² / (|ab|² |ac|²) below this: a degenerate triangle


def _closest_on_edges(p, a, b, c, rows: np.ndarray) -> np.ndarray:
    """Closest point to ``p`` on the three edges of each triangle (only ``rows`` computed;
    the others are left zero)."""
    out = np.zeros_like(p)
    best = np.full(len(p), np.inf)
    for u, w in ((a, b), (b, c), (c, a)):
        e = w[rows] - u[rows]
        t = _fraction(_dot(p[rows] - u[rows], e), _dot(e, e))
        q = u[rows] + t[:, None] * e
        d = ((q - p[rows]) ** 2).sum(axis=1)
        closer = d < best[rows]
        idx = np.flatnonzero(rows)[closer]
        out[idx], best[idx] = q[closer], d[closer]
    return out


def _dot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Row dot products added left to right, ``(x0 y0 + x1 y1) + x2 y2``: the order of the
    compiled distance kernel (``metrics._min_distance_loops``), so that the numpy version
    gives its numbers bit for bit (numpy's ``einsum`` adds a row in another order, and the
    self-check's scores then differed in the last digit between a cold and a warm numba
    cache: session 43)."""
    return (x[:, 0] * y[:, 0] + x[:, 1] * y[:, 1]) + x[:, 2] * y[:, 2]


def _fraction(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    """``num / den`` clipped to [0, 1]; 0 where ``den`` (a squared edge length) is 0: the
    closest point of a zero-length edge is its first end."""
    safe = den > 0
    return np.clip(np.divide(num, np.where(safe, den, 1.0)), 0, 1) * safe


def closest_point_on_triangles(p: np.ndarray, a: np.ndarray, b: np.ndarray,
                               c: np.ndarray) -> np.ndarray:
    """Closest point to ``p[i]`` on triangle ``(a[i], b[i], c[i])``, for all ``i`` at once.

    Exact (Ericson, *Real-Time Collision Detection*, §5.1.5): the Voronoi regions of the
    vertices, edges and face are tested in turn. Degenerate triangles are handled (the
    closest point on their segments is returned).

    Parameters
    ----------
    p, a, b, c : (m, 3) float arrays

    Returns
    -------
    (m, 3) float array
    """
    ab, ac, ap = b - a, c - a, p - a
    d1 = _dot(ab, ap)
    d2 = _dot(ac, ap)
    bp = p - b
    d3 = _dot(ab, bp)
    d4 = _dot(ac, bp)
    cp = p - c
    d5 = _dot(ab, cp)
    d6 = _dot(ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2

    out = np.empty_like(p)
    done = np.zeros(len(p), bool)

    def put(mask, value):
        m = mask & ~done
        out[m] = value[m] if value.ndim == 2 else value
        done[:] |= m

    # degenerate triangles (repeated or collinear corners): the region tests below do not
    # hold there (a zero-length ab sends every point to a); nearest point of the three edges
    cross = np.cross(ab, ac)
    flat = _dot(cross, cross) <= _FLAT * _dot(ab, ab) * _dot(ac, ac)
    if flat.any():
        put(flat, _closest_on_edges(p, a, b, c, flat))
    with np.errstate(divide="ignore", invalid="ignore"):
        put((d1 <= 0) & (d2 <= 0), a)
        put((d3 >= 0) & (d4 <= d3), b)
        put((d6 >= 0) & (d5 <= d6), c)
        t = _fraction(d1, d1 - d3)
        put((vc <= 0) & (d1 >= 0) & (d3 <= 0), a + t[:, None] * ab)
        t = _fraction(d2, d2 - d6)
        put((vb <= 0) & (d2 >= 0) & (d6 <= 0), a + t[:, None] * ac)
        t = _fraction(d4 - d3, (d4 - d3) + (d5 - d6))
        put((va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0), b + t[:, None] * (c - b))
        denom = va + vb + vc
        v = vb / denom
        w = vc / denom
        inside = a + v[:, None] * ab + w[:, None] * ac
        put(np.isfinite(inside).all(axis=1), inside)
    if not done.all():  # degenerate triangles: nearest of the three vertices
        rest = ~done
        cand = np.stack([a[rest], b[rest], c[rest]], 1)
        k = np.argmin(((cand - p[rest, None]) ** 2).sum(-1), axis=1)
        out[rest] = cand[np.arange(len(k)), k]
    return out
