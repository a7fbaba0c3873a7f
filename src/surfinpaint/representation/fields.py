"""The λ-H representation of a conformal grid surface (method.md §1, §3).

``phi`` is an ``(n, m, 3)`` array of positions on a uniform grid of spacing ``h``:
``phi[i, j] = φ(u0 + i h, v0 + j h)``. Every operator uses central differences and returns
NaN where its stencil leaves the grid (the outer ring) or touches a NaN node, so grids over an
irregular parameter domain are handled by setting the nodes outside it to NaN.

Conventions: λ² = (|Duφ|² + |Dvφ|²)/2, n = Duφ × Dvφ / |Duφ × Dvφ|,
H = <Δhφ, n> / (2λ²), μ = <φzz, n> with ∂z = ½(∂u − i∂v). All are O(h²) on smooth
conformal grids.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "central_derivatives",
    "grid_laplacian",
    "hopf_differential",
    "lambda_h",
    "normals",
    "shifted",
]


def shifted(f: np.ndarray, di: int, dj: int) -> np.ndarray:
    """``out[i, j] = f[i + di, j + dj]``, NaN where that index leaves the grid.

    Works on any array whose first two axes are the grid axes.
    """
    f = np.asarray(f, dtype=np.result_type(f, float))
    out = np.full_like(f, np.nan)
    n, m = f.shape[:2]
    src_i = slice(max(di, 0), n + min(di, 0))
    dst_i = slice(max(-di, 0), n + min(-di, 0))
    src_j = slice(max(dj, 0), m + min(dj, 0))
    dst_j = slice(max(-dj, 0), m + min(-dj, 0))
    out[dst_i, dst_j] = f[src_i, src_j]
    return out


def central_derivatives(f: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Central differences ``Du f = (f[i+1] − f[i−1]) / 2h`` and ``Dv f`` along the axes.

    Parameters
    ----------
    f : (n, m, ...) array
    h : float
        Grid spacing.

    Returns
    -------
    fu, fv : arrays shaped like ``f``, NaN on the outer ring and next to NaN nodes.
    """
    fu = (shifted(f, 1, 0) - shifted(f, -1, 0)) / (2 * h)
    fv = (shifted(f, 0, 1) - shifted(f, 0, -1)) / (2 * h)
    return fu, fv


def grid_laplacian(f: np.ndarray, h: float) -> np.ndarray:
    """The 5-point Laplacian ``Δh f``, NaN where the stencil leaves the grid or hits NaN."""
    f = np.asarray(f, dtype=float)
    nb = shifted(f, 1, 0) + shifted(f, -1, 0) + shifted(f, 0, 1) + shifted(f, 0, -1)
    return (nb - 4 * f) / (h * h)


def _unit(x: np.ndarray) -> np.ndarray:
    norm = np.linalg.norm(x, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(norm > 0, x / np.where(norm > 0, norm, 1.0), np.nan)


def normals(phi: np.ndarray, h: float) -> np.ndarray:
    """Unit normals ``n = Duφ × Dvφ / |Duφ × Dvφ|`` as an ``(n, m, 3)`` array.

    NaN where the stencil is incomplete or the cross product vanishes.
    """
    phi = _check_phi(phi)
    pu, pv = central_derivatives(phi, h)
    # The stencil is the 5-point cross: a node outside the domain has no normal either.
    return np.where(_centre_ok(phi)[..., None], _unit(np.cross(pu, pv)), np.nan)


def _centre_ok(phi: np.ndarray) -> np.ndarray:
    return np.all(np.isfinite(phi), axis=-1)


def _check_phi(phi: np.ndarray) -> np.ndarray:
    phi = np.asarray(phi, dtype=float)
    if phi.ndim != 3 or phi.shape[2] != 3:
        raise ValueError(f"phi must have shape (n, m, 3), got {phi.shape}")
    return phi


def check_spacing(h: float) -> float:
    """``h`` as a float; ValueError unless it is a positive finite grid spacing."""
    h = float(h)
    if not (np.isfinite(h) and h > 0):
        raise ValueError(f"grid spacing h must be a positive number, got {h}")
    return h


def domain_mask(domain: np.ndarray | None, shape: tuple[int, int]) -> np.ndarray:
    """The boolean mask of grid nodes that exist (all of them when ``domain`` is None);
    ValueError when it is not a boolean array of ``shape``."""
    if domain is None:
        return np.ones(shape, dtype=bool)
    domain = np.asarray(domain)
    if domain.shape != shape or domain.dtype != bool:
        raise ValueError(f"domain must be a boolean mask of shape {shape}")
    return domain


def lambda_h(phi: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Conformal factor λ and mean curvature H of a conformal grid surface.

    Parameters
    ----------
    phi : (n, m, 3) array
        Positions on a uniform grid (NaN for nodes outside the parameter domain).
    h : float
        Grid spacing.

    Returns
    -------
    lam, H : (n, m) arrays
        λ = √((|Duφ|² + |Dvφ|²)/2) and H = <Δhφ, n>/(2λ²) (method.md §3). NaN on the outer
        ring, wherever a stencil node is NaN and where the normal is undefined.

    Raises
    ------
    ValueError
        If ``phi`` is not ``(n, m, 3)`` or ``h`` is not positive.

    Examples
    --------
    >>> from surfinpaint.representation.analytic import grid, stereographic_sphere
    >>> u, v, h = grid(65, (-0.5, 0.5, -0.5, 0.5))
    >>> phi, lam, H = stereographic_sphere(u, v)
    >>> lam_h, H_h = lambda_h(phi, h)
    >>> bool(np.nanmax(abs(H_h - 1)) < 1e-3)
    True
    """
    phi = _check_phi(phi)
    h = check_spacing(h)
    pu, pv = central_derivatives(phi, h)
    lam2 = 0.5 * (np.sum(pu * pu, axis=-1) + np.sum(pv * pv, axis=-1))
    n = normals(phi, h)
    with np.errstate(invalid="ignore", divide="ignore"):
        H = np.sum(grid_laplacian(phi, h) * n, axis=-1) / (2 * lam2)
    H = np.where(np.isfinite(H), H, np.nan)
    lam = np.where(_centre_ok(phi), np.sqrt(lam2), np.nan)
    return lam, H


def hopf_differential(phi: np.ndarray, h: float) -> np.ndarray:
    """Hopf differential μ = <φzz, n> (complex) of a conformal grid surface.

    φzz = ¼(φuu − φvv − 2i φuv) with 3-point second differences and the 4-corner mixed
    difference, so the stencil is the 3 × 3 block around each node.

    Parameters
    ----------
    phi : (n, m, 3) array
    h : float

    Returns
    -------
    mu : (n, m) complex array, NaN (real and imaginary part) where undefined.
    """
    phi = _check_phi(phi)
    h = check_spacing(h)
    c = phi
    puu = (shifted(c, 1, 0) - 2 * c + shifted(c, -1, 0)) / (h * h)
    pvv = (shifted(c, 0, 1) - 2 * c + shifted(c, 0, -1)) / (h * h)
    puv = (
        shifted(c, 1, 1) - shifted(c, 1, -1) - shifted(c, -1, 1) + shifted(c, -1, -1)
    ) / (4 * h * h)
    n = normals(phi, h)
    re = 0.25 * np.sum((puu - pvv) * n, axis=-1)
    im = -0.5 * np.sum(puv * n, axis=-1)
    return re + 1j * im
