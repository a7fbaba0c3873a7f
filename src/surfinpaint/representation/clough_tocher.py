"""The C1 Clough–Tocher interpolant on a mesh's own parameter triangles, for sampling a
surface on a grid (:func:`surfinpaint.representation.grid.resample`).

A piecewise-linear surface sampled finer than its triangles has Δφ = 0 inside them and
spikes on the edges, so central-difference curvatures of it are noise. This interpolant is
C1 on the mesh's own parameter triangles (no re-triangulation of the points, so concave
domains stay as they are), passes through the vertex values and reproduces quadratics
exactly (cubic error, O(e³), for smooth data).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from surfinpaint.geometry.edges import edge_keys

__all__ = ["clough_tocher", "face_neighbours", "vertex_gradients"]


def face_neighbours(faces: np.ndarray) -> np.ndarray:
    """(f, 3) int array: the face across the edge opposite corner ``k`` of each face, −1 on
    the border (the first other face where an edge is non-manifold)."""
    f = np.asarray(faces, dtype=np.int64)
    nf = len(f)
    a = np.concatenate([f[:, 1], f[:, 2], f[:, 0]])
    b = np.concatenate([f[:, 2], f[:, 0], f[:, 1]])
    fid = np.tile(np.arange(nf), 3)
    corner = np.repeat(np.arange(3), nf)
    base = np.int64(f.max()) + 1 if nf else np.int64(1)
    key = edge_keys(a, b, base)
    order = np.argsort(key, kind="stable")
    same = key[order][1:] == key[order][:-1]
    out = np.full((nf, 3), -1, dtype=np.int64)
    i0, i1 = order[:-1][same], order[1:][same]
    out[fid[i0], corner[i0]] = fid[i1]
    out[fid[i1], corner[i1]] = fid[i0]
    return out


def vertex_gradients(uv: np.ndarray, faces: np.ndarray, values: np.ndarray,
                     rings: int | None = None) -> np.ndarray:
    """Parameter-space gradients of per-vertex values, by a weighted least-squares quadratic
    fit over each vertex's ``rings``-ring (weights 1/distance², the vertex's own value held
    fixed). Exact for quadratics, O(e²) for smooth data.

    Parameters
    ----------
    uv : (n, 2) float array
    faces : (f, 3) int array
    values : (n,) or (n, k) float array
    rings : int, optional
        Neighbourhood size. By default the 1-ring for vertices with at least 6 neighbours
        and the 2-ring for the others (border vertices), so every fit has more points than
        the 5 unknowns of a quadratic (a small ridge keeps it defined where it has fewer);
        the full 2-ring costs twice as much and measured equal or larger round-trip errors
        (``represent``: 1.6–2.7× larger on the coarse pial disk, whose 2-ring spans too
        much curvature for one quadratic).

    Returns
    -------
    (n, 2, k) float array
        ``[:, 0]`` the u-derivative, ``[:, 1]`` the v-derivative (NaN for unreferenced
        vertices with NaN ``uv``).
    """
    q = np.asarray(uv, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    vals = np.asarray(values, dtype=float).reshape(len(q), -1)
    n, k = vals.shape
    e = np.vstack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    A = sp.csr_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
    A = ((A + A.T) > 0).astype(np.float64).tocsr()
    if rings is None:  # the 1-ring where it has 6 neighbours or more, else the 2-ring
        few = sp.diags((np.diff(A.indptr) < 6).astype(np.float64))
        R = (A + few @ (A @ A)).tocsr()
    else:
        R = A
        for _ in range(rings - 1):
            R = (R + R @ A).tocsr()
    R = R.tocoo()
    keep = R.row != R.col
    rows, cols = R.row[keep].astype(np.int64), R.col[keep].astype(np.int64)
    du, dv = q[cols, 0] - q[rows, 0], q[cols, 1] - q[rows, 1]
    dist2 = du * du + dv * dv
    count = np.maximum(np.bincount(rows, minlength=n), 1)
    scale = np.sqrt(np.bincount(rows, dist2, minlength=n) / count)
    scale = np.where(scale > 0, scale, 1.0)
    inv = 1.0 / scale[rows]  # well conditioned 5x5 systems
    du, dv, dist2 = du * inv, dv * inv, dist2 * inv * inv
    a = np.stack([du, dv, du * du / 2, du * dv, dv * dv / 2])  # (5, nnz), contiguous rows
    wa = a / np.maximum(dist2, 1e-12)  # weights 1/distance²
    M = np.empty((n, 5, 5))
    for r in range(5):
        for c in range(r, 5):
            M[:, r, c] = M[:, c, r] = np.bincount(rows, wa[r] * a[c], minlength=n)
    B = np.empty((n, 5, k))
    for c in range(k):
        df = vals[cols, c] - vals[rows, c]
        for r in range(5):
            B[:, r, c] = np.bincount(rows, wa[r] * df, minlength=n)
    trace = np.trace(M, axis1=1, axis2=2)[:, None, None]
    M[:, 2:, 2:] += 1e-8 * trace * np.eye(3)
    M[:, :2, :2] += 1e-12 * np.maximum(trace, 1.0) * np.eye(2)
    B = np.nan_to_num(B)
    M = np.where(np.isfinite(M), M, 0.0) + np.where(trace > 0, 0.0, np.eye(5))
    grads = np.linalg.solve(M, B)[:, :2, :] / scale[:, None, None]
    grads[~np.isfinite(q).all(axis=1)] = np.nan
    return grads


def clough_tocher(uv: np.ndarray, faces: np.ndarray, values: np.ndarray,
                  gradients: np.ndarray, face_index: np.ndarray,
                  points: np.ndarray) -> np.ndarray:
    """The C1 Clough–Tocher interpolant of per-vertex values and gradients, on the given
    parameter triangles, evaluated at points.

    Each triangle is split at its centroid into three cubic Bézier patches (the reduced
    Clough–Tocher element as in scipy's ``CloughTocher2DInterpolator``, with its
    affine-invariant choice of the cross-edge direction: towards the neighbour's centroid,
    so two triangles sharing an edge agree and the interpolant is C1 across it). It passes
    through the values, has the given gradients at the vertices and reproduces quadratics.

    Parameters
    ----------
    uv : (n, 2) float array
    faces : (f, 3) int array
    values : (n,) or (n, k) float array
    gradients : (n, 2, k) float array
        E.g. from :func:`vertex_gradients`.
    face_index : (p,) int array
        The triangle each point lies in.
    points : (p, 2) float array

    Returns
    -------
    (p, k) float array
    """
    q = np.asarray(uv, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    vals = np.asarray(values, dtype=float).reshape(len(q), -1)
    grads = np.asarray(gradients, dtype=float).reshape(len(q), 2, -1)
    fi = np.asarray(face_index, dtype=np.int64)
    tv = f[fi]
    p1, p2, p3 = q[tv[:, 0]], q[tv[:, 1]], q[tv[:, 2]]
    e12, e23, e31 = p2 - p1, p3 - p2, p1 - p3
    t1, t2 = p1 - p3, p2 - p3
    det = t1[:, 0] * t2[:, 1] - t2[:, 0] * t1[:, 1]

    def barycentric(pt):
        r = pt - p3
        with np.errstate(divide="ignore", invalid="ignore"):
            b1 = (r[:, 0] * t2[:, 1] - r[:, 1] * t2[:, 0]) / det
            b2 = (t1[:, 0] * r[:, 1] - t1[:, 1] * r[:, 0]) / det
        return np.column_stack([b1, b2, 1.0 - b1 - b2])

    b = barycentric(np.asarray(points, dtype=float).reshape(-1, 2))
    c3000, c0300, c0030 = vals[tv[:, 0]], vals[tv[:, 1]], vals[tv[:, 2]]
    g1, g2, g3 = grads[tv[:, 0]], grads[tv[:, 1]], grads[tv[:, 2]]

    def along(g, e):  # directional derivative (p, k)
        return g[:, 0, :] * e[:, 0, None] + g[:, 1, :] * e[:, 1, None]

    c2100 = c3000 + along(g1, e12) / 3
    c2010 = c3000 - along(g1, e31) / 3
    c1200 = c0300 - along(g2, e12) / 3
    c0210 = c0300 + along(g2, e23) / 3
    c1020 = c0030 + along(g3, e31) / 3
    c0120 = c0030 - along(g3, e23) / 3
    c2001 = (c2100 + c2010 + c3000) / 3
    c0201 = (c1200 + c0300 + c0210) / 3
    c0021 = (c1020 + c0120 + c0030) / 3
    # cross-edge directions: towards the neighbour's centroid (−½: the border default)
    nb = face_neighbours(f)[fi]
    centroid = q[f].mean(axis=1)
    g = np.full((len(fi), 3), -0.5)
    for k, (x, y) in enumerate(((2, 1), (0, 2), (1, 0))):
        has = nb[:, k] >= 0
        c = barycentric(centroid[np.where(has, nb[:, k], 0)])
        with np.errstate(divide="ignore", invalid="ignore"):
            gk = (2 * c[:, x] + c[:, y] - 1) / (2 - 3 * c[:, x] - 3 * c[:, y])
        g[:, k] = np.where(has & np.isfinite(gk), gk, -0.5)
    c0111 = (g[:, 0:1] * (-c0300 + 3 * c0210 - 3 * c0120 + c0030)
             + (-c0300 + 2 * c0210 - c0120 + c0021 + c0201)) / 2
    c1011 = (g[:, 1:2] * (-c0030 + 3 * c1020 - 3 * c2010 + c3000)
             + (-c0030 + 2 * c1020 - c2010 + c2001 + c0021)) / 2
    c1101 = (g[:, 2:3] * (-c3000 + 3 * c2100 - 3 * c1200 + c0300)
             + (-c3000 + 2 * c2100 - c1200 + c2001 + c0201)) / 2
    c1002 = (c1101 + c1011 + c2001) / 3
    c0102 = (c1101 + c0111 + c0201) / 3
    c0012 = (c1011 + c0111 + c0021) / 3
    c0003 = (c1002 + c0102 + c0012) / 3
    # coordinates in the micro-triangle (one of b1, b2, b3 is zero, so is b1 b2 b3)
    low = b.min(axis=1, keepdims=True)
    b1, b2, b3 = (b[:, 0:1] - low), (b[:, 1:2] - low), (b[:, 2:3] - low)
    b4 = 3 * low
    return (b1**3 * c3000 + 3 * b1**2 * b2 * c2100 + 3 * b1**2 * b3 * c2010
            + 3 * b1**2 * b4 * c2001 + 3 * b1 * b2**2 * c1200 + 6 * b1 * b2 * b4 * c1101
            + 3 * b1 * b3**2 * c1020 + 6 * b1 * b3 * b4 * c1011 + 3 * b1 * b4**2 * c1002
            + b2**3 * c0300 + 3 * b2**2 * b3 * c0210 + 3 * b2**2 * b4 * c0201
            + 6 * b2 * b3 * b4 * c0111 + 3 * b2 * b4**2 * c0102 + 3 * b2 * b3**2 * c0120
            + b3**3 * c0030 + 3 * b3**2 * b4 * c0021 + 3 * b3 * b4**2 * c0012
            + b4**3 * c0003)
