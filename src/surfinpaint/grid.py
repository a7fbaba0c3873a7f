"""Regular grids over a parameter domain: sampling a parameterized mesh on the grid and
interpolating grid functions back at arbitrary parameter points (method.md §6.5, §6.8).

Grid arrays are indexed ``[i, j]`` with ``u = u0 + i h`` and ``v = v0 + j h`` (numpy's
``indexing="ij"``), the layout of :mod:`surfinpaint.lambda_h` and :mod:`surfinpaint.analytic`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Grid", "grid_over", "interpolate", "resample"]

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
             grid: Grid) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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
    t = grid.to_index(q)  # vertex positions in node units
    tri = t[f]  # (f, 3, 2)
    lo = np.ceil(np.nanmin(tri, axis=1) - 1e-9).astype(np.int64)
    hi = np.floor(np.nanmax(tri, axis=1) + 1e-9).astype(np.int64)
    lo = np.maximum(lo, 0)
    hi = np.minimum(hi, [N - 1, M - 1])
    valid = np.isfinite(tri).all(axis=(1, 2))
    ni = np.where(valid, hi[:, 0] - lo[:, 0] + 1, 0).clip(min=0)
    nj = np.where(valid, hi[:, 1] - lo[:, 1] + 1, 0).clip(min=0)
    count = ni * nj

    out = np.full((N * M, vals.shape[1]), np.nan)
    face_index = np.full(N * M, -1, dtype=np.int64)
    cum = np.cumsum(count)
    start = 0
    while start < len(f):
        # faces [start, stop) hold about _CHUNK candidate nodes
        base = cum[start - 1] if start else 0
        stop = int(np.searchsorted(cum, base + _CHUNK, side="right"))
        stop = max(stop, start + 1)
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
        fid, ii, jj, l0, l1, l2 = fid[hit], ii[hit], jj[hit], l0[hit], l1[hit], l2[hit]
        tv = f[fid]
        node = ii * M + jj
        out[node] = (l0[:, None] * vals[tv[:, 0]] + l1[:, None] * vals[tv[:, 1]]
                     + l2[:, None] * vals[tv[:, 2]])
        face_index[node] = fid
        start = stop
    inside = (face_index >= 0).reshape(N, M)
    sampled = out.reshape(N, M, -1)
    if scalar:
        sampled = sampled[..., 0]
    return sampled, inside, face_index.reshape(N, M)


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
