"""Inpainting of scalar fields on a grid (the paper's §5, method.md §5).

The λ and H of the surface around a hole are extended into it. ``"biharmonic"`` minimizes
Σ|Δh f|² over the 5-point stencils that touch the region (two rings of Dirichlet data),
``"harmonic"`` minimizes the Dirichlet energy Σ (f(p) − f(q))² over the grid edges. Both are
one sparse direct solve. Irregular parameter domains are handled by using only the stencils
(or edges) whose nodes all exist.

With ``fidelity=w`` the known nodes near the region are no longer hard data but are fitted in
least squares, E = Σ|h²Δh f|² + w Σ_known (f − f0)², which keeps noise in the known λ, H
from being carried straight into the hole (method.md §8). ``w → ∞`` gives the hard version.

:func:`biharmonic_flow` is the paper's explicit flow fⁿ = fⁿ⁻¹ − dt Δh²fⁿ⁻¹ (the gradient
flow of the same energy), kept only as a reference check.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse import csgraph

from surfinpaint.geometry.linalg import factorized_definite
from surfinpaint.lazy import lazy_module
from surfinpaint.representation.fields import check_spacing, domain_mask

ndimage = lazy_module("scipy.ndimage")  # the grid world only: no mesh fill imports it

__all__ = ["INPAINT_METHODS", "biharmonic_flow", "inpaint"]

INPAINT_METHODS = ("biharmonic", "harmonic")

_STENCIL = ((0, 0, -4.0), (1, 0, 1.0), (-1, 0, 1.0), (0, 1, 1.0), (0, -1, 1.0))


def inpaint(
    values: np.ndarray,
    region: np.ndarray,
    *,
    domain: np.ndarray | None = None,
    method: str = "biharmonic",
    h: float = 1.0,
    fidelity: float | None = None,
    **options,
) -> np.ndarray:
    """Fill the nodes of ``region`` from the values around them.

    Parameters
    ----------
    values : (n, m) or (n, m, k) array
        Field on the grid; only nodes in ``domain`` and not in ``region`` are read (the
        others may be NaN).
    region : (n, m) bool array
        Nodes to fill (only those inside ``domain`` are used).
    domain : (n, m) bool array, optional
        Nodes that exist (default all). Nodes outside come back as given.
    method : {"biharmonic", "harmonic"}
    h : float
        Grid spacing. The hard-data solutions do not depend on it; it is accepted so that
        callers can pass their grid's spacing uniformly.
    fidelity : float, optional
        Weight ``w > 0`` of the data term; with it the known nodes within ``rings`` (option,
        default 4, Chebyshev distance) of the region are fitted instead of fixed. The
        smoothness term uses the unscaled stencil h²Δh (or edge differences), so ``w`` is
        per node and dimensionless. Biharmonic data (e.g. cubics) is a stationary point for
        every ``w`` as long as the annulus stays clear of the domain edge (there Δh²f = 0
        still holds at each soft node), so the soft fit removes noise without bias.
    **options
        ``rings`` (int, default 4): width of the softly fitted annulus when ``fidelity`` is
        given.

    Returns
    -------
    array shaped like ``values``
        ``values`` with the region (and with ``fidelity``, the annulus) filled in.

    Raises
    ------
    ValueError
        On bad shapes or parameters, non-finite known values that the solve needs, or a
        connected part of the region that no known node constrains.

    Examples
    --------
    >>> u, v = np.meshgrid(np.arange(9.0), np.arange(9.0), indexing="ij")
    >>> f = u**3 - 3 * u * v**2 + u * v          # biharmonic (even harmonic)
    >>> hole = (abs(u - 4) <= 1) & (abs(v - 4) <= 1)
    >>> g = inpaint(np.where(hole, np.nan, f), hole)
    >>> bool(np.allclose(g, f))
    True
    """
    rings = _fidelity_options(method, fidelity, options)
    f, region, domain, squeeze = _check(values, region, domain, h)
    fidelity = None if fidelity is None else float(fidelity)
    region = region & domain
    out = f.copy()
    if region.any():
        if fidelity is None:
            free = region
        else:
            near = ndimage.binary_dilation(region, np.ones((3, 3), bool), iterations=rings)
            free = near & domain
        rows = _laplacian_rows if method == "biharmonic" else _edge_rows
        out[free] = _least_squares_fill(f, rows(domain, free), region, domain, free, fidelity)
    return out[..., 0] if squeeze else out


def _fidelity_options(method: str, fidelity: float | None, options: dict) -> int:
    """Check :func:`inpaint`'s method and soft-fit options; the annulus width ``rings``."""
    rings = int(options.pop("rings", 4))
    if options:
        raise ValueError(f"unknown inpainting options: {sorted(options)}")
    if method not in INPAINT_METHODS:
        raise ValueError(f"unknown inpainting method {method!r}; choose from {INPAINT_METHODS}")
    if fidelity is not None:
        if not (np.isfinite(float(fidelity)) and float(fidelity) > 0):
            raise ValueError(f"fidelity must be a positive number, got {fidelity}")
        if rings < 1:
            raise ValueError(f"rings must be >= 1, got {rings}")
    return rings


def _least_squares_fill(f: np.ndarray, D, region: np.ndarray, domain: np.ndarray,
                        free: np.ndarray, fidelity: float | None) -> np.ndarray:
    """The values at the ``free`` nodes minimising ``|D x|²`` (plus ``fidelity`` times the
    squared distance to the known values at the free nodes outside ``region``), the other
    nodes of ``domain`` held at ``f``: (free nodes, k)."""
    soft = free & ~region
    fixed = domain & ~free
    idx = np.full(region.shape, -1, dtype=np.int64)
    idx[free] = np.arange(free.sum())
    flat = np.flatnonzero(free.ravel())
    A = D[:, flat]
    fixed_all = np.flatnonzero(fixed.ravel())
    fixed_flat = fixed_all[np.asarray(abs(D[:, fixed_all]).sum(0)).ravel() > 0]
    _require_finite(f.reshape(-1, f.shape[-1])[fixed_flat], fixed_flat, region.shape, "known")
    b = -(D[:, fixed_flat] @ f.reshape(-1, f.shape[-1])[fixed_flat])
    Q = (A.T @ A).tocsc()
    rhs = A.T @ b
    if fidelity is not None:
        soft_ids = idx[soft]
        f0 = f[soft]
        _require_finite(f0, np.flatnonzero(soft.ravel()), region.shape, "known")
        wdiag = np.zeros(len(flat))
        wdiag[soft_ids] = fidelity
        Q = (Q + sp.diags(wdiag)).tocsc()
        rhs = rhs.copy()
        rhs[soft_ids] += fidelity * f0
    _require_constrained(Q, free, region, fixed, D, fidelity is not None)
    try:
        solve = factorized_definite(Q)
    except RuntimeError as err:  # singular: a part of the region left unconstrained
        raise ValueError(f"inpainting system is singular ({err}); the region needs known "
                         "data around it inside the domain") from err
    return np.column_stack([solve(np.ascontiguousarray(rhs[:, k]))
                            for k in range(rhs.shape[1])])


def biharmonic_flow(
    values: np.ndarray,
    region: np.ndarray,
    dt: float,
    steps: int,
    *,
    domain: np.ndarray | None = None,
    h: float = 1.0,
) -> np.ndarray:
    """The paper's explicit biharmonic flow fⁿ = fⁿ⁻¹ − dt Δh²fⁿ⁻¹ on the region.

    Exactly the gradient flow of ½Σ|Δh f|² over the stencils that :func:`inpaint` uses, so it
    tends to the same minimizer; stable for ``dt <= h⁴/64``. Region nodes start at the mean
    of the known values. Reference only: use :func:`inpaint`.

    Raises
    ------
    ValueError
        On bad parameters (including ``dt`` above the stability bound).
    """
    f, region, domain, squeeze = _check(values, region, domain, h)
    dt = float(dt)
    if not (dt > 0 and dt <= h**4 / 64 * (1 + 1e-12)):
        raise ValueError(f"dt must be in (0, h^4/64 = {h**4 / 64:g}] for stability, got {dt}")
    region = region & domain
    out = f.copy()
    if not region.any():
        return out[..., 0] if squeeze else out
    D = _laplacian_rows(domain, region) / h**2
    known_mask = domain & ~region
    out[region] = np.nanmean(f[known_mask], axis=0)
    x = out.reshape(-1, f.shape[-1]).copy()
    fixed = np.where(known_mask.ravel()[:, None], x, 0.0)
    flat = np.flatnonzero(region.ravel())
    A = D[:, flat].tocsr()
    AT = A.T.tocsr()
    b = D @ fixed
    xr = x[flat]
    for _ in range(int(steps)):
        xr = xr - dt * (AT @ (A @ xr + b))
    out[region] = xr
    return out[..., 0] if squeeze else out


# ----------------------------------------------------------------------------- internals


def _check(values, region, domain, h):
    f = np.array(values, dtype=float)  # a copy: nothing modifies the input
    if f.ndim not in (2, 3):
        raise ValueError(f"values must have shape (n, m) or (n, m, k), got {f.shape}")
    squeeze = f.ndim == 2
    if squeeze:
        f = f[..., None]
    shape = f.shape[:2]
    region = np.asarray(region)
    if region.shape != shape or region.dtype != bool:
        raise ValueError(f"region must be a boolean mask of shape {shape}")
    domain = domain_mask(domain, shape)
    h = check_spacing(h)
    return f, region, domain, squeeze


def _laplacian_rows(domain: np.ndarray, free: np.ndarray) -> sp.csr_matrix:
    """Rows of the unscaled 5-point Laplacian at every node whose stencil lies in the domain
    and touches a free node; columns index all grid nodes (row-major)."""
    n, m = domain.shape
    pad = np.pad(domain, 1)
    inside = np.ones_like(domain)
    touches = np.zeros_like(domain)
    padf = np.pad(free, 1)
    for di, dj, _ in _STENCIL:
        inside &= pad[1 + di : 1 + di + n, 1 + dj : 1 + dj + m]
        touches |= padf[1 + di : 1 + di + n, 1 + dj : 1 + dj + m]
    centres = np.argwhere(inside & touches)
    ci, cj = centres.T
    rows, cols, vals = [], [], []
    r = np.arange(len(centres))
    for di, dj, w in _STENCIL:
        rows.append(r)
        cols.append((ci + di) * m + (cj + dj))
        vals.append(np.full(len(r), w))
    return sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(len(centres), n * m),
    )


def _edge_rows(domain: np.ndarray, free: np.ndarray) -> sp.csr_matrix:
    """Difference rows f(q) − f(p) for the grid edges inside the domain touching a free node."""
    n, m = domain.shape
    ids = np.arange(n * m).reshape(n, m)
    p_list, q_list = [], []
    for a, b in (
        (np.s_[:-1, :], np.s_[1:, :]),
        (np.s_[:, :-1], np.s_[:, 1:]),
    ):
        ok = domain[a] & domain[b] & (free[a] | free[b])
        p_list.append(ids[a][ok])
        q_list.append(ids[b][ok])
    p = np.concatenate(p_list)
    q = np.concatenate(q_list)
    r = np.arange(len(p))
    return sp.csr_matrix(
        (np.r_[-np.ones(len(p)), np.ones(len(q))], (np.r_[r, r], np.r_[p, q])),
        shape=(len(p), n * m),
    )


def _nodes(flat: np.ndarray, shape: tuple[int, int], limit: int = 5) -> str:
    ii, jj = np.unravel_index(flat[:limit], shape)
    head = ", ".join(f"({i}, {j})" for i, j in zip(ii, jj, strict=True))
    return head + (f" and {len(flat) - limit} more" if len(flat) > limit else "")


def _require_finite(vals: np.ndarray, flat: np.ndarray, shape, what: str) -> None:
    bad = ~np.all(np.isfinite(vals), axis=-1)
    if bad.any():
        raise ValueError(
            f"{bad.sum()} {what} nodes that the inpainting reads are not finite, "
            f"e.g. {_nodes(flat[bad], shape)}"
        )


def _require_constrained(Q, free, region, fixed, D, soft: bool) -> None:
    """Each connected part of the free nodes (linked through shared stencils) must reach a
    fixed node or a soft data node; otherwise the minimizer is not unique."""
    n_free = Q.shape[0]
    flat_free = np.flatnonzero(free.ravel())
    # Free nodes linked through any shared stencil row.
    comp_n, labels = csgraph.connected_components((Q != 0).astype(np.int8), directed=False)
    anchored = np.zeros(comp_n, dtype=bool)
    fixed_cols = np.flatnonzero(fixed.ravel())
    rows_touching_fixed = np.flatnonzero(np.asarray(abs(D[:, fixed_cols]).sum(1)).ravel())
    if len(rows_touching_fixed):
        Dfree = D[rows_touching_fixed][:, flat_free]
        anchored[labels[np.unique(Dfree.nonzero()[1])]] = True
    if soft:
        anchored[labels[~region.ravel()[flat_free]]] = True
    # Isolated free nodes that no stencil reaches have an all-zero row.
    empty = np.asarray(abs(Q).sum(1)).ravel() == 0
    bad = ~anchored[labels] | empty
    if bad.any():
        raise ValueError(
            f"{bad.sum()} region nodes are not constrained by any known value through the "
            f"{'stencils' if n_free else 'grid'} inside the domain, e.g. "
            f"{_nodes(flat_free[bad], free.shape)}; the region needs known data around it"
        )
