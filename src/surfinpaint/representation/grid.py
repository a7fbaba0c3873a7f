"""Regular grids over a parameter domain: sampling a parameterized mesh on the grid and
interpolating grid functions back at arbitrary parameter points (method.md §6.5, §6.8).

Grid arrays are indexed ``[i, j]`` with ``u = u0 + i h`` and ``v = v0 + j h`` (numpy's
``indexing="ij"``), the layout of :mod:`surfinpaint.representation.fields` and
:mod:`surfinpaint.representation.analytic`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from surfinpaint.geometry.edges import edge_keys

__all__ = [
    "Grid",
    "clough_tocher",
    "face_neighbours",
    "grid_over",
    "interpolate",
    "locate_nodes",
    "resample",
    "vertex_gradients",
]

# barycentric slack: nodes exactly on a shared edge or vertex must land in some triangle
_BARY_TOL = 1e-10
# at most this many (node, triangle) candidate pairs are tested at once
_CHUNK = 4_000_000


@dataclass(frozen=True)
class Grid:
    """A regular square grid: node ``(i, j)`` sits at ``(u0 + i h, v0 + j h)``.

    Attributes
    ----------
    origin : (u0, v0)
    h : float
        Spacing, the same along u and v.
    shape : (n, m)
        Nodes along u and along v.
    """

    origin: tuple[float, float]
    h: float
    shape: tuple[int, int]

    @property
    def u(self) -> np.ndarray:
        """(n,) node u coordinates."""
        return self.origin[0] + self.h * np.arange(self.shape[0])

    @property
    def v(self) -> np.ndarray:
        """(m,) node v coordinates."""
        return self.origin[1] + self.h * np.arange(self.shape[1])

    def nodes(self) -> tuple[np.ndarray, np.ndarray]:
        """``(U, V)``, each ``shape``, the coordinates of every node."""
        return np.meshgrid(self.u, self.v, indexing="ij")

    def to_index(self, uv: np.ndarray) -> np.ndarray:
        """(k, 2) fractional node indices of parameter points."""
        return (np.asarray(uv, dtype=float) - np.asarray(self.origin)) / self.h


def grid_over(uv: np.ndarray, h: float | None = None, resolution: int | None = None,
              margin: float = 0.0) -> Grid:
    """The grid covering the bounding box of ``uv`` (plus ``margin`` on every side).

    Give either the spacing ``h`` or the ``resolution``, the number of nodes along the longer
    side of the box. The grid starts at the box's lower-left corner; its last nodes reach or
    pass the upper-right corner.

    Parameters
    ----------
    uv : (k, 2) float array
        Parameter points; NaN rows are ignored.
    h : float, optional
    resolution : int, optional
        At least 2.
    margin : float
        Added around the box, in parameter units.

    Returns
    -------
    Grid

    Raises
    ------
    ValueError
        When neither or both of ``h`` and ``resolution`` are given, or they are invalid.

    Examples
    --------
    >>> g = grid_over(np.array([[0.0, 0.0], [2.0, 1.0]]), resolution=5)
    >>> g.h, g.shape
    (0.5, (5, 3))
    """
    q = np.asarray(uv, dtype=float)
    q = q[np.isfinite(q).all(axis=1)]
    if len(q) == 0:
        raise ValueError("no finite parameter points to put a grid over")
    if (h is None) == (resolution is None):
        raise ValueError("give exactly one of h and resolution")
    lo = q.min(axis=0) - margin
    size = q.max(axis=0) + margin - lo
    if resolution is not None:
        if resolution < 2:
            raise ValueError(f"resolution must be at least 2, got {resolution}")
        h = float(size.max()) / (resolution - 1)
    if not h or h <= 0 or not np.isfinite(h):
        raise ValueError(f"grid spacing must be positive and finite, got {h}")
    # a tiny slack so a box side that is an exact multiple of h gets its last node
    shape = np.floor(size / h + 1e-9).astype(int) + 1
    shape = np.where(size / h - (shape - 1) > 1e-9, shape + 1, shape)
    return Grid((float(lo[0]), float(lo[1])), float(h), (int(shape[0]), int(shape[1])))


def resample(uv: np.ndarray, faces: np.ndarray, values: np.ndarray,
             grid: Grid, *, interpolant: str = "linear",
             gradients: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sample per-vertex values at the grid nodes by barycentric interpolation.

    Each triangle's bounding box of nodes is tested at once (vectorized, in chunks), so the
    cost is about the number of grid nodes plus the number of faces.

    Parameters
    ----------
    uv : (n, 2) float array
        Parameter coordinates of the vertices.
    faces : (f, 3) int array
    values : (n,) or (n, k) float array
        Per-vertex values, e.g. the 3D positions.
    grid : Grid
    interpolant : {"linear", "clough-tocher"}
        ``"linear"`` (the default): the piecewise-linear interpolant. ``"clough-tocher"``:
        the C1 piecewise-cubic interpolant of :func:`clough_tocher` on the same triangles,
        through the same vertex values, with vertex gradients from
        :func:`vertex_gradients` (or ``gradients``). The nodes inside (``inside``,
        ``face_index``) are the same for both.
    gradients : (n, 2, k) float array, optional
        Vertex gradients for ``"clough-tocher"``.

    Returns
    -------
    sampled : (N, M, k) float array
        NaN at nodes outside every parameter triangle (``(N, M)`` for 1-D ``values``).
    inside : (N, M) bool array
    face_index : (N, M) int array
        The triangle each node fell in, −1 outside. A node on a shared edge takes one of the
        triangles (the values agree there).

    Examples
    --------
    >>> uv = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    >>> s, inside, _ = resample(uv, np.array([[0, 1, 2]]), uv[:, 0], grid_over(uv, h=0.5))
    >>> int(inside.sum()), float(np.nansum(s))
    (6, 2.0)
    """
    q = np.asarray(uv, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    vals = np.asarray(values, dtype=float)
    scalar = vals.ndim == 1
    vals = vals.reshape(len(vals), -1)
    N, M = grid.shape
    face_index, weights = locate_nodes(grid.to_index(q), f, grid.shape)
    out = np.full((N * M, vals.shape[1]), np.nan)
    node = np.flatnonzero(face_index >= 0)
    tv = f[face_index[node]]
    w = weights[node]
    out[node] = (w[:, 0, None] * vals[tv[:, 0]] + w[:, 1, None] * vals[tv[:, 1]]
                 + w[:, 2, None] * vals[tv[:, 2]])
    inside = (face_index >= 0).reshape(N, M)
    if interpolant == "clough-tocher":
        U, V = grid.nodes()
        points = np.column_stack([U.ravel()[node], V.ravel()[node]])
        if gradients is None:
            gradients = vertex_gradients(q, f, vals)
        out[node] = clough_tocher(q, f, vals, gradients, face_index[node], points)
    elif interpolant != "linear":
        raise ValueError(f"unknown interpolant {interpolant!r}; choose 'linear' or "
                         "'clough-tocher'")
    sampled = out.reshape(N, M, -1)
    if scalar:
        sampled = sampled[..., 0]
    return sampled, inside, face_index.reshape(N, M)


def locate_nodes(t: np.ndarray, faces: np.ndarray,
                 shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """The triangle each grid node falls in, and its barycentric weights there.

    Each triangle's bounding box of nodes is tested at once (vectorized, in chunks of about
    ``_CHUNK`` candidate nodes), so the cost is about the number of grid nodes plus the
    number of faces.

    Parameters
    ----------
    t : (n, 2) float array
        Vertex positions in node units (:meth:`Grid.to_index`); NaN rows are never hit.
    faces : (f, 3) int array
    shape : (N, M)
        The grid's number of nodes along each axis.

    Returns
    -------
    face_index : (N·M,) int array
        The triangle of each node (row-major), −1 outside every triangle. A node on a shared
        edge takes the last triangle that contains it (the values agree there).
    weights : (N·M, 3) float array
        The node's barycentric weights on its triangle's three vertices (NaN outside).
    """
    N, M = shape
    f = faces
    tri = t[f]  # (f, 3, 2)
    lo = np.ceil(np.nanmin(tri, axis=1) - 1e-9).astype(np.int64)
    hi = np.floor(np.nanmax(tri, axis=1) + 1e-9).astype(np.int64)
    lo = np.maximum(lo, 0)
    hi = np.minimum(hi, [N - 1, M - 1])
    valid = np.isfinite(tri).all(axis=(1, 2))
    ni = np.where(valid, hi[:, 0] - lo[:, 0] + 1, 0).clip(min=0)
    nj = np.where(valid, hi[:, 1] - lo[:, 1] + 1, 0).clip(min=0)
    count = ni * nj
    face_index = np.full(N * M, -1, dtype=np.int64)
    weights = np.full((N * M, 3), np.nan)
    cum = np.cumsum(count)
    start = 0
    while start < len(f):
        # faces [start, stop) hold about _CHUNK candidate nodes
        base = cum[start - 1] if start else 0
        stop = max(int(np.searchsorted(cum, base + _CHUNK, side="right")), start + 1)
        ids = np.arange(start, stop)
        c = count[ids]
        fid = np.repeat(ids, c)
        k = np.arange(c.sum()) - np.repeat(np.cumsum(c) - c, c)
        ii = lo[fid, 0] + k // nj[fid]
        jj = lo[fid, 1] + k % nj[fid]
        a, b, cc = tri[fid, 0], tri[fid, 1], tri[fid, 2]
        e1, e2 = b - a, cc - a
        p = np.column_stack([ii, jj]) - a
        det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            l1 = (p[:, 0] * e2[:, 1] - p[:, 1] * e2[:, 0]) / det
            l2 = (e1[:, 0] * p[:, 1] - e1[:, 1] * p[:, 0]) / det
        l0 = 1.0 - l1 - l2
        hit = (l0 >= -_BARY_TOL) & (l1 >= -_BARY_TOL) & (l2 >= -_BARY_TOL) & (det != 0)
        node = ii[hit] * M + jj[hit]
        face_index[node] = fid[hit]
        weights[node] = np.column_stack([l0[hit], l1[hit], l2[hit]])
        start = stop
    return face_index, weights


def _cubic_weights(x: np.ndarray) -> np.ndarray:
    """(k, 4) Keys cubic-convolution weights (a = −½, Catmull–Rom) for nodes −1..2 at
    fractional offset ``x`` in [0, 1]; exact for quadratics, O(h³)."""
    x2, x3 = x * x, x * x * x
    return np.column_stack([
        -0.5 * x3 + x2 - 0.5 * x,
        1.5 * x3 - 2.5 * x2 + 1.0,
        -1.5 * x3 + 2.0 * x2 + 0.5 * x,
        0.5 * x3 - 0.5 * x2,
    ])


def interpolate(grid_values: np.ndarray, grid: Grid, uv_points: np.ndarray,
                order: int = 1) -> np.ndarray:
    """Values of a grid function at arbitrary parameter points.

    Parameters
    ----------
    grid_values : (N, M) or (N, M, k) float array
        NaN where undefined.
    grid : Grid
    uv_points : (p, 2) float array
    order : {1, 3}
        1: bilinear on the cell containing the point. 3: bicubic (Catmull–Rom) on the 4×4
        nodes around the cell where all of them exist and are finite, bilinear elsewhere.

    Returns
    -------
    (p,) or (p, k) float array
        NaN where a corner of the point's cell is NaN or the point is off the grid.

    Examples
    --------
    >>> g = Grid((0.0, 0.0), 1.0, (2, 2))
    >>> interpolate(np.array([[0.0, 1.0], [2.0, 3.0]]), g, np.array([[0.5, 0.5]])).tolist()
    [1.5]
    """
    if order not in (1, 3):
        raise ValueError(f"order must be 1 or 3, got {order}")
    G = np.asarray(grid_values, dtype=float)
    scalar = G.ndim == 2
    if scalar:
        G = G[..., None]
    N, M = grid.shape
    if G.shape[:2] != (N, M):
        raise ValueError(f"grid values have shape {G.shape[:2]}, the grid {grid.shape}")
    t = grid.to_index(np.asarray(uv_points, dtype=float).reshape(-1, 2))
    finite = np.isfinite(t).all(axis=1)
    t0 = np.where(finite[:, None], t, 0.0)
    on = finite & (t0[:, 0] >= -1e-9) & (t0[:, 0] <= N - 1 + 1e-9) \
        & (t0[:, 1] >= -1e-9) & (t0[:, 1] <= M - 1 + 1e-9)
    i = np.clip(np.floor(t0[:, 0]).astype(np.int64), 0, max(N - 2, 0))
    j = np.clip(np.floor(t0[:, 1]).astype(np.int64), 0, max(M - 2, 0))
    x = t0[:, 0] - i
    y = t0[:, 1] - j
    i1, j1 = np.minimum(i + 1, N - 1), np.minimum(j + 1, M - 1)
    out = ((1 - x)[:, None] * (1 - y)[:, None] * G[i, j] + x[:, None] * (1 - y)[:, None] * G[i1, j]
           + (1 - x)[:, None] * y[:, None] * G[i, j1] + x[:, None] * y[:, None] * G[i1, j1])
    if order == 3:
        di = np.arange(-1, 3)
        ii = i[:, None] + di  # (p, 4)
        jj = j[:, None] + di
        inrange = (ii[:, 0] >= 0) & (ii[:, 3] < N) & (jj[:, 0] >= 0) & (jj[:, 3] < M)
        iic, jjc = np.clip(ii, 0, N - 1), np.clip(jj, 0, M - 1)
        block = G[iic[:, :, None], jjc[:, None, :]]  # (p, 4, 4, k)
        ok = inrange & np.isfinite(block).all(axis=(1, 2, 3))
        wx, wy = _cubic_weights(x), _cubic_weights(y)
        cubic = np.einsum("pa,pb,pabk->pk", wx, wy, np.where(ok[:, None, None, None], block, 0))
        out = np.where(ok[:, None], cubic, out)
    out[~on] = np.nan
    return out[:, 0] if scalar else out


# --------------------------------------------------------------------- C1 interpolation
# A piecewise-linear surface sampled finer than its triangles has Δφ = 0 inside them and
# spikes on the edges, so central-difference curvatures of it are noise. The Clough–Tocher
# interpolant below is C1 on the mesh's own parameter triangles (no re-triangulation of the
# points, so concave domains stay as they are), passes through the vertex values and
# reproduces quadratics exactly (cubic error, O(e³), for smooth data).


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
