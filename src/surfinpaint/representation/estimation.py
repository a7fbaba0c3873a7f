"""Robust estimates of the conformal factor λ and the mean curvature H on a grid.

Central differences of a piecewise-linear surface resampled on a grid give a spiky H: the
surface has no curvature inside its triangles and all of it on the edges (method.md §8). Here
each node instead gets a weighted least-squares quadratic fit of φ over a (2r+1)² window of
valid nodes (a Savitzky–Golay filter where the window is full), and λ and H come from the
fitted first and second derivatives with the conventions of method.md §1. Invalid nodes (NaN
positions, or nodes the caller masks out, such as an initial hole fill) are left out of the
fits, so estimates next to them use one-sided windows and never see them.
"""

from __future__ import annotations

import numpy as np

from surfinpaint.lazy import lazy_module

ndimage = lazy_module("scipy.ndimage")  # the grid world only: no mesh fill imports it

__all__ = ["fitted_derivatives", "robust_lambda_h"]

# monomials of the local quadratic model in window offsets (a, b): 1, a, b, a², ab, b²
_POWERS = ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2))


def _window(radius: int, sigma: float | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    a, b = np.meshgrid(np.arange(-radius, radius + 1), np.arange(-radius, radius + 1),
                       indexing="ij")
    if sigma is None:
        w = np.ones_like(a, dtype=float)
    else:
        w = np.exp(-(a**2 + b**2) / (2.0 * sigma**2))
    return a.astype(float), b.astype(float), w


def _condition(gram: np.ndarray) -> np.ndarray:
    """2-norm condition numbers of symmetric positive semi-definite matrices (..., k, k):
    their singular values are their eigenvalues, and eigvalsh is cheaper than an SVD."""
    if gram.size == 0:
        return np.zeros(gram.shape[:-2])
    ev = np.abs(np.linalg.eigvalsh(gram))
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(ev.min(axis=-1) > 0, ev.max(axis=-1) / ev.min(axis=-1), np.inf)


def fitted_derivatives(
    phi: np.ndarray,
    h: float,
    *,
    valid: np.ndarray | None = None,
    radius: int = 2,
    sigma: float | None = 1.5,
    min_fraction: float = 0.5,
) -> dict[str, np.ndarray]:
    """First and second derivatives of a gridded surface from local quadratic fits.

    Parameters
    ----------
    phi : (n, m, k) array
        Values on a uniform grid of spacing ``h`` (NaN where undefined).
    h : float
        Grid spacing.
    valid : (n, m) bool array, optional
        Nodes whose values may be used (default: the finite ones).
    radius : int
        Window half-width in nodes; the fit uses up to (2·radius + 1)² nodes.
    sigma : float or None
        Gaussian weight width in nodes (None: uniform weights).
    min_fraction : float
        Nodes whose window holds fewer valid nodes than this fraction, or whose fit is
        ill-conditioned, get NaN.

    Returns
    -------
    dict with (n, m, k) arrays ``value``, ``u``, ``v``, ``uu``, ``uv``, ``vv``.

    Examples
    --------
    >>> u, v = np.meshgrid(np.arange(9.0), np.arange(9.0), indexing="ij")
    >>> d = fitted_derivatives((u**2 + 3 * v)[..., None], 1.0)
    >>> round(float(d["uu"][4, 4, 0]), 9), round(float(d["v"][4, 4, 0]), 9)
    (2.0, 3.0)
    """
    phi = np.asarray(phi, dtype=float)
    if phi.ndim == 2:
        phi = phi[..., None]
    finite = np.isfinite(phi).all(axis=-1)
    valid = finite if valid is None else (np.asarray(valid, dtype=bool) & finite)
    _, _, w = _window(radius, sigma)
    mask = valid.astype(float)
    data = np.where(valid[..., None], phi, 0.0)
    nb = len(_POWERS)
    # normal equations per node: G c = r, G_pq = Σ w B_p B_q [valid], r_p = Σ w B_p f.
    # The window weights factor, w B_p B_q = (g(a) a^i)(g(b) b^j) with the Gaussian g, so
    # each window sum is two 1-D correlations, and the first pass serves several sums.
    offsets = np.arange(-radius, radius + 1, dtype=float)
    g = (np.ones_like(offsets) if sigma is None
         else np.exp(-offsets**2 / (2.0 * sigma**2)))

    def window_sums(x, degree):
        """{(i, j): Σ_window g(a) a^i g(b) b^j x} for i + j <= degree."""
        along_a = [ndimage.correlate1d(x, g * offsets**i, axis=0, mode="constant")
                   for i in range(degree + 1)]
        return {(i, j): ndimage.correlate1d(along_a[i], g * offsets**j, axis=1,
                                            mode="constant")
                for i in range(degree + 1) for j in range(degree + 1 - i)}

    moments = window_sums(mask, 4)
    names = list(moments)
    which = np.array([[names.index((pa + qa, pb + qb)) for qa, qb in _POWERS]
                      for pa, pb in _POWERS])
    gram = np.stack([moments[k] for k in names], axis=-1)[..., which]
    sums = window_sums(data, 2)
    rhs = np.stack([sums[power] for power in _POWERS], axis=-2)
    ones = np.ones_like(offsets)
    count = ndimage.correlate1d(ndimage.correlate1d(mask, ones, axis=0, mode="constant"),
                                ones, axis=1, mode="constant")
    ok = count >= min_fraction * w.size
    # scale-aware conditioning test: a one-sided or collinear window cannot fix a quadratic
    # Full windows all have the same Gram matrix (same sums over the same all-one mask, so
    # bit-identical): its condition number is taken once, and only partial windows pay for
    # their own.
    cond = np.full(valid.shape, np.inf)
    full = count == w.size
    partial = ok & ~full
    cond[partial] = _condition(gram[partial])
    if full.any():
        cond[full] = _condition(gram[np.unravel_index(np.argmax(full), full.shape)])
    ok &= cond < 1e6
    coef = np.full(valid.shape + (nb, phi.shape[-1]), np.nan)
    partial &= ok
    coef[partial] = np.linalg.solve(gram[partial], rhs[partial])
    full &= ok
    if full.any():  # one factorization serves every full window
        g0 = gram[np.unravel_index(np.argmax(full), full.shape)]
        r = rhs[full]  # (k, nb, c)
        sol = np.linalg.solve(g0, r.transpose(1, 0, 2).reshape(nb, -1))
        coef[full] = sol.reshape(nb, len(r), -1).transpose(1, 0, 2)
    return {
        "value": coef[..., 0, :],
        "u": coef[..., 1, :] / h,
        "v": coef[..., 2, :] / h,
        "uu": 2.0 * coef[..., 3, :] / h**2,
        "uv": coef[..., 4, :] / h**2,
        "vv": 2.0 * coef[..., 5, :] / h**2,
    }


def robust_lambda_h(
    phi: np.ndarray,
    h: float,
    *,
    valid: np.ndarray | None = None,
    radius: int = 2,
    sigma: float | None = 1.5,
    min_fraction: float = 0.5,
) -> tuple[np.ndarray, np.ndarray]:
    """λ and H of a gridded surface from local quadratic fits (see :func:`fitted_derivatives`).

    Conventions as :func:`surfinpaint.representation.fields`: λ² = (|φu|² + |φv|²)/2, n = φu × φv
    normalized, H = <φuu + φvv, n> / (2λ²). On a smooth conformal grid both are O(h²)
    accurate where the window is full; on a resampled piecewise-linear surface they average
    the curvature over the window instead of seeing it concentrated on the edges.

    Returns
    -------
    lam, H : (n, m) arrays, NaN where no fit was possible.
    """
    d = fitted_derivatives(phi, h, valid=valid, radius=radius, sigma=sigma,
                           min_fraction=min_fraction)
    pu, pv = d["u"], d["v"]
    lam2 = 0.5 * ((pu * pu).sum(-1) + (pv * pv).sum(-1))
    normal = np.cross(pu, pv)
    norm = np.linalg.norm(normal, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        normal = normal / norm
        H = ((d["uu"] + d["vv"]) * normal).sum(-1) / (2.0 * lam2)
    lam = np.sqrt(lam2)
    bad = ~np.isfinite(lam) | ~np.isfinite(H) | (lam2 <= 0)
    lam[bad] = np.nan
    H[bad] = np.nan
    return lam, H
