"""Rebuild a conformal grid surface from its λ-H representation (method.md §4).

Where the mask ``known`` is False the positions are unknown and rebuilt from the conformal
factor λ and the mean curvature H, with the known positions around them as boundary data.
Two methods:

``"gauss-codazzi"`` (the paper's §6.1)
    1. Hopf differential μ on the unknown region from the Codazzi equation μz̄ = (λ²/2) Hz in
       its second-order form Δμ = 2 ∂z(λ² Hz), with μ of the known surface as Dirichlet data.
    2. The orthonormal frame (e1, e2, n) = (φu/λ, φv/λ, n) from the Gauss–Weingarten
       equations, discretized edge by edge with the trapezoidal rule (a compact scheme with no
       odd-even decoupling), in least squares with the frame of the known surface outside.
    3. φ from φu = λ e1, φv = λ e2 (and φuu, φvv from the frame equations): each grid edge
       gets its increment by the corrected trapezoid rule, and φ is their least-squares fit
       with Dirichlet data (a Poisson solve). ``integrate="normal"`` instead solves
       Δhφ = 2λ²H n with the frame's normal n.

``"laplacian"``
    Δhφ = 2 λ² H n(φ) on the unknown nodes with φ fixed elsewhere: a fixed point iteration
    on n, reusing one sparse factorization of Δh.

Both return the exact surface up to O(h²) when λ and H are exact, and converge as O(h²).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from surfinpaint.errors import FillError, how_many
from surfinpaint.geometry.linalg import factorized_definite
from surfinpaint.lazy import lazy_module
from surfinpaint.representation.fields import (
    central_derivatives,
    check_spacing,
    domain_mask,
    hopf_differential,
    lambda_h,
    normals,
)

ndimage = lazy_module("scipy.ndimage")  # the grid world only: no mesh fill imports it

__all__ = ["METHODS", "NotConvergedWarning", "ReconstructionInfo", "reconstruct"]

METHODS = ("gauss-codazzi", "laplacian")



class NotConvergedWarning(RuntimeWarning):
    """An iterative rebuild stopped at its iteration limit without converging."""


@dataclass(frozen=True)
class ReconstructionInfo:
    """How a reconstruction went (``reconstruct(..., return_info=True)``).

    Attributes
    ----------
    converged : bool
        The iteration reached its tolerance (always True for the direct Gauss–Codazzi
        solve).
    iterations : int
        Iterations taken (0 for Gauss–Codazzi).
    change : float
        Last relative change of φ (0 for Gauss–Codazzi).
    message : str
    """

    converged: bool
    iterations: int
    change: float
    message: str


# ndimage.generate_binary_structure(2, 1) and (2, 2), spelled out: no import at start-up
_CROSS = np.array([[False, True, False], [True, True, True], [False, True, False]])
_BLOCK = np.ones((3, 3), dtype=bool)
_AXES = ((1, 0), (0, 1))  # grid offsets of the u and v directions


def reconstruct(
    lam: np.ndarray,
    H: np.ndarray,
    phi: np.ndarray,
    known: np.ndarray,
    h: float,
    method: str = "gauss-codazzi",
    **options,
) -> np.ndarray:
    """Rebuild the unknown positions of a conformal grid surface from (λ, H).

    Parameters
    ----------
    lam, H : (n, m) arrays
        Conformal factor and mean curvature (method.md §1 conventions). They are needed on
        the unknown nodes and, for ``"gauss-codazzi"``, on three rings of known nodes around
        them; NaN there is replaced by the values of the known surface (``lambda_h(phi)``).
    phi : (n, m, 3) array
        Positions; only the known nodes are read (the others may hold anything, e.g. NaN).
    known : (n, m) bool array
        True where the position is known (boundary data); False nodes inside ``domain`` are
        rebuilt.
    h : float
        Grid spacing.
    method : {"gauss-codazzi", "laplacian"}
    **options
        ``domain`` : (n, m) bool array, the nodes that exist (default all). Nodes outside it
        are neither known nor unknown and come back as given in ``phi``.
        ``max_iter`` (100) and ``tol`` (1e-12, relative change of φ) for ``"laplacian"``.
        ``integrate`` ("gradient" or "normal") for ``"gauss-codazzi"``: how φ is obtained
        from the rebuilt frame (see the module notes).
        ``return_info`` (False): also return a :class:`ReconstructionInfo`.

    Returns
    -------
    (n, m, 3) array
        ``phi`` with the unknown nodes rebuilt; known nodes are bitwise unchanged.
    ReconstructionInfo
        Only with ``return_info=True``.

    Warns
    -----
    NotConvergedWarning
        When the ``"laplacian"`` iteration stops at ``max_iter``.

    Raises
    ------
    ValueError
        On bad shapes, unknown method or options, non-finite known positions, or an unknown
        region without enough known rings around it inside the domain and the grid (one ring
        for ``"laplacian"``, three for ``"gauss-codazzi"``).
    FillError
        If the fixed point iteration of ``"laplacian"`` diverges.

    Examples
    --------
    >>> from surfinpaint.representation.analytic import grid, enneper
    >>> u, v, h = grid(33)
    >>> phi, lam, H = enneper(u, v)
    >>> known = (u - 0.1) ** 2 + v**2 > 0.3**2
    >>> out = reconstruct(lam, H, phi, known, h)
    >>> bool(np.abs(out - phi).max() < 1e-3)
    True
    """
    domain = options.pop("domain", None)
    return_info = bool(options.pop("return_info", False))
    lam, H, phi, known, domain, h = _check_inputs(lam, H, phi, known, domain, h)
    unknown = domain & ~known
    out = phi.copy()
    info = ReconstructionInfo(True, 0, 0.0, "nothing to rebuild")
    if not unknown.any():
        return (out, info) if return_info else out
    if method == "laplacian":
        max_iter = int(options.pop("max_iter", 100))
        tol = float(options.pop("tol", 1e-12))
        _no_more(options)
        values, info = _laplacian_rebuild(lam, H, phi, known & domain, unknown, h, max_iter,
                                          tol)
    elif method == "gauss-codazzi":
        integrate = options.pop("integrate", "gradient")
        if integrate not in ("gradient", "normal"):
            raise ValueError(f"integrate must be 'gradient' or 'normal', got {integrate!r}")
        _no_more(options)
        values = _gauss_codazzi_rebuild(lam, H, phi, known & domain, unknown, h, integrate)
        info = ReconstructionInfo(True, 0, 0.0, "gauss-codazzi: direct solves")
    else:
        raise ValueError(f"unknown reconstruction method {method!r}; choose from {METHODS}")
    if not np.all(np.isfinite(values)):
        raise FillError(f"{method} reconstruction produced non-finite positions")
    out[unknown] = values
    return (out, info) if return_info else out


# --------------------------------------------------------------------------- input checks


def _no_more(options: dict) -> None:
    if options:
        raise ValueError(f"unknown reconstruction options: {sorted(options)}")


def _check_inputs(lam, H, phi, known, domain, h):
    phi = np.asarray(phi, dtype=float)
    if phi.ndim != 3 or phi.shape[2] != 3:
        raise ValueError(f"phi must have shape (n, m, 3), got {phi.shape}")
    shape = phi.shape[:2]
    lam = np.asarray(lam, dtype=float)
    H = np.asarray(H, dtype=float)
    known = np.asarray(known)
    for name, a in (("lam", lam), ("H", H), ("known", known)):
        if a.shape != shape:
            raise ValueError(f"{name} must have shape {shape} like phi, got {a.shape}")
    if known.dtype != bool:
        raise ValueError(f"known must be a boolean mask, got dtype {known.dtype}")
    domain = domain_mask(domain, shape)
    h = check_spacing(h)
    bad = np.argwhere(known & domain & ~np.all(np.isfinite(phi), axis=-1))
    if len(bad):
        raise ValueError(
            f"{len(bad)} known nodes have non-finite positions, e.g. {_nodes(bad)}"
        )
    return lam, H, phi, known, domain, h


def _nodes(idx: np.ndarray, limit: int = 5) -> str:
    head = ", ".join(f"({i}, {j})" for i, j in idx[:limit])
    return head + (f" and {len(idx) - limit} more" if len(idx) > limit else "")


def dilate(mask: np.ndarray, rings: int, structure: np.ndarray | None = None) -> np.ndarray:
    """``mask`` grown by ``rings`` grid nodes (8-neighbour by default; ``structure`` as for
    :func:`scipy.ndimage.binary_dilation`)."""
    if rings <= 0:
        return mask.copy()
    if structure is None:
        structure = np.ones((3, 3), dtype=bool)
    return ndimage.binary_dilation(mask, structure=structure, iterations=rings)


def _require_support(
    unknown: np.ndarray, known: np.ndarray, rings: int, structure: np.ndarray, method: str
) -> None:
    """Every node within ``rings`` of the unknown region must be a grid node that is known
    or unknown (inside the domain); otherwise the stencils cannot be closed."""
    n, m = unknown.shape
    if min(n, m) < 2 * rings + 1:
        raise ValueError(
            f"grid {n}x{m} is too small for the {method} stencils "
            f"(needs at least {2 * rings + 1} nodes per side)"
        )
    padded = np.pad(unknown, rings)
    need = dilate(padded, rings, structure)
    ok = np.pad(known | unknown, rings)
    bad = need & ~ok
    if bad.any():
        idx = np.argwhere(bad) - rings
        outside = (idx[:, 0] < 0) | (idx[:, 0] >= n) | (idx[:, 1] < 0) | (idx[:, 1] >= m)
        where = "the grid border" if outside.any() else "nodes outside the domain"
        kind = "4-neighbour" if structure.sum() == 5 else "8-neighbour"
        raise ValueError(
            f"the unknown region needs {how_many(rings, 'ring', 'rings')} ({kind}) of known "
            "nodes around it for "
            f"the {method} method, but it comes within reach of {where} at "
            f"{how_many(len(idx), 'node', 'nodes')}, "
            f"e.g. {_nodes(idx)}; add known data around the region or shrink it"
        )


def _filled(field: np.ndarray, fallback: np.ndarray, need: np.ndarray, name: str) -> np.ndarray:
    out = np.where(np.isfinite(field), field, fallback)
    bad = np.argwhere(need & ~np.isfinite(out))
    if len(bad):
        raise ValueError(
            f"{name} is not finite at {len(bad)} nodes where the reconstruction needs it, "
            f"e.g. {_nodes(bad)}"
        )
    return out


# --------------------------------------------------------------------- sparse grid systems


class _Index:
    """Numbering of the nodes of a mask, for assembling sparse systems."""

    def __init__(self, mask: np.ndarray):
        self.mask = mask
        self.id = np.full(mask.shape, -1, dtype=np.int64)
        self.nodes = np.argwhere(mask)
        self.id[mask] = np.arange(len(self.nodes))
        self.size = len(self.nodes)


def _laplacian_system(unknown: np.ndarray, h: float):
    """Δh on the unknown nodes: the (u × u) matrix and, per direction, the neighbour ids
    (−1 where the neighbour is known) so the Dirichlet part can be moved to the RHS."""
    idx = _Index(unknown)
    ii, jj = idx.nodes.T
    rows = [np.arange(idx.size)]
    cols = [np.arange(idx.size)]
    vals = [np.full(idx.size, -4.0 / h**2)]
    neighbours = []
    for di, dj in ((1, 0), (-1, 0), (0, 1), (0, -1)):
        ni, nj = ii + di, jj + dj
        nid = idx.id[ni, nj]
        inside = nid >= 0
        rows.append(np.flatnonzero(inside))
        cols.append(nid[inside])
        vals.append(np.full(inside.sum(), 1.0 / h**2))
        neighbours.append((ni, nj, inside))
    A = sp.csc_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(idx.size, idx.size),
    )
    return idx, A, neighbours


def _dirichlet_rhs(phi: np.ndarray, neighbours, h: float) -> np.ndarray:
    """Contribution of the known neighbours to Δh on the unknown nodes (to subtract)."""
    b = 0.0
    for ni, nj, inside in neighbours:
        b = b + np.where(inside[:, None], 0.0, phi[ni, nj]) / h**2
    return b


# ------------------------------------------------------------------------- laplacian form


def _laplacian_rebuild(lam, H, phi, known, unknown, h, max_iter, tol):
    _require_support(unknown, known, 1, _CROSS, "laplacian")
    lam = _filled(lam, np.nan, unknown, "lam")
    H = _filled(H, np.nan, unknown, "H")
    idx, A, neighbours = _laplacian_system(unknown, h)
    solve = factorized_definite(A)
    b_known = _dirichlet_rhs(np.where(known[..., None], phi, 0.0), neighbours, h)
    w = (2 * lam**2 * H)[unknown]
    work = np.where(known[..., None], phi, 0.0)
    x = np.column_stack([solve(-b_known[:, k]) for k in range(3)])  # harmonic start
    scale = max(np.ptp(phi[known], axis=0).max(), np.finfo(float).tiny)
    change = np.inf
    for it in range(max_iter):
        work[unknown] = x
        n = normals(work, h)[unknown]
        if not np.all(np.isfinite(n)):
            raise FillError("laplacian reconstruction: normal undefined (degenerate surface)")
        rhs = w[:, None] * n - b_known
        x_new = np.column_stack([solve(rhs[:, k]) for k in range(3)])
        change = np.abs(x_new - x).max() / scale
        x = x_new
        if not np.isfinite(change) or change > 1e6:
            raise FillError("laplacian reconstruction diverged")
        if change <= tol:
            return x, ReconstructionInfo(True, it + 1, float(change),
                                         f"laplacian: converged in {it + 1} iterations")
    message = (f"laplacian reconstruction stopped after {max_iter} iterations with relative "
               f"change {change:.2e} > tol {tol:.1e}")
    warnings.warn(message, NotConvergedWarning, stacklevel=3)
    return x, ReconstructionInfo(False, max_iter, float(change), message)


# ---------------------------------------------------------------------- gauss-codazzi form


def _gauss_codazzi_rebuild(lam, H, phi, known, unknown, h, integrate="gradient"):
    _require_support(unknown, known, 3, _BLOCK, "gauss-codazzi")
    phi_known = np.where(known[..., None], phi, np.nan)
    lam_phi, H_phi = lambda_h(phi_known, h)
    need = dilate(unknown, 3, _BLOCK)
    lam = _filled(lam, lam_phi, need, "lam")
    H = _filled(H, H_phi, dilate(unknown, 2, _BLOCK), "H")
    mu = _codazzi_mu(lam, H, hopf_differential(phi_known, h), unknown, h)
    e1, e2, n, (lu, lv, L, N) = _frame(lam, H, mu, phi_known, unknown, h)
    if integrate == "normal":
        return _integrate_normal(lam, H, n, phi_known, unknown, h)
    # Second derivatives of φ from the frame, for the Hermite correction of the edges.
    puu = lu[..., None] * e1 - lv[..., None] * e2 + L[..., None] * n
    pvv = -lu[..., None] * e1 + lv[..., None] * e2 + N[..., None] * n
    return _integrate(lam[..., None] * e1, lam[..., None] * e2, puu, pvv, phi_known, unknown, h)


def _codazzi_mu(lam, H, mu_known, unknown, h):
    """μ on the nodes whose Hopf stencil touches the unknown region, from Δμ = 2∂z(λ²Hz).

    Real form with g = λ²: 2∂z(g Hz) = ½[(gHu)u − (gHv)v] − ½ i [(gHv)u + (gHu)v], each
    term with compact (3 × 3) differences.
    """
    region = dilate(unknown, 1, _BLOCK)
    g = lam**2

    def s(f, di, dj):
        return np.roll(f, (-di, -dj), axis=(0, 1))  # only read where the stencil is inside

    def flux(f, gf, di, dj):  # (g f_a)_a with a the axis (di, dj), compact
        gp = 0.5 * (gf + s(gf, di, dj))
        gm = 0.5 * (gf + s(gf, -di, -dj))
        return (gp * (s(f, di, dj) - f) - gm * (f - s(f, -di, -dj))) / h**2

    Huu = flux(H, g, 1, 0)
    Hvv = flux(H, g, 0, 1)
    Hv = (s(H, 0, 1) - s(H, 0, -1)) / (2 * h)
    Hu = (s(H, 1, 0) - s(H, -1, 0)) / (2 * h)
    gHv = g * Hv
    gHu = g * Hu
    mixed = (s(gHv, 1, 0) - s(gHv, -1, 0) + s(gHu, 0, 1) - s(gHu, 0, -1)) / (2 * h)
    rhs = (0.5 * (Huu - Hvv) - 0.5j * mixed)[region]
    idx, A, neighbours = _laplacian_system(region, h)
    boundary = dilate(region, 1, _CROSS) & ~region
    bad = np.argwhere(boundary & ~np.isfinite(mu_known))
    if len(bad):  # guarded by _require_support; a NaN here means degenerate known data
        raise ValueError(f"Hopf differential of the known surface undefined at {_nodes(bad)}")
    b = _dirichlet_rhs(np.where(boundary, mu_known, 0.0)[..., None], neighbours, h)[:, 0]
    solve = factorized_definite(A.astype(complex))
    mu = np.where(region, 0.0, mu_known)
    mu[region] = solve(rhs - b)
    return mu


def _frame(lam, H, mu, phi_known, unknown, h):
    """Frame (e1, e2, n) on the nodes whose central differences touch the unknown region.

    Gauss–Weingarten in the orthonormal frame, with a = λu/λ, b = λv/λ, L, M, N the second
    fundamental form (L = λ²H + 2 Re μ, N = λ²H − 2 Re μ, M = −2 Im μ):

        ∂u (e1, e2, n) = (−b e2 + L/λ n,  b e1 + M/λ n,  −L/λ e1 − M/λ e2)
        ∂v (e1, e2, n) = ( a e2 + M/λ n, −a e1 + N/λ n,  −M/λ e1 − N/λ e2)

    Each grid edge p → q gives (X(q) − X(p))/h = ½(C(p)X(p) + C(q)X(q)) (trapezoid rule).
    The three coordinates of space decouple, so one least-squares matrix serves all three.
    """
    frame_unknown = dilate(unknown, 1, _CROSS)
    pu, pv = central_derivatives(phi_known, h)
    lam_phi = np.sqrt(0.5 * (np.sum(pu**2, -1) + np.sum(pv**2, -1)))
    with np.errstate(invalid="ignore", divide="ignore"):
        known_frame = np.stack(
            [pu / lam_phi[..., None], pv / lam_phi[..., None], normals(phi_known, h)], axis=2
        )  # (n, m, 3 frame vectors, 3 coords)
    lu, lv = central_derivatives(lam, h)
    a, b = lu / lam, lv / lam
    L = lam**2 * H + 2 * mu.real
    N = lam**2 * H - 2 * mu.real
    M = -2 * mu.imag
    zero = np.zeros_like(lam)
    C = (
        np.stack(  # C[d][X, Y]: coefficient of Y in ∂d X
            [
                np.stack([zero, -b, L / lam]),
                np.stack([b, zero, M / lam]),
                np.stack([-L / lam, -M / lam, zero]),
            ]
        ),
        np.stack(
            [
                np.stack([zero, a, M / lam]),
                np.stack([-a, zero, N / lam]),
                np.stack([-M / lam, -N / lam, zero]),
            ]
        ),
    )  # each (3, 3, n, m)

    idx = _Index(frame_unknown)
    rows, cols, vals, rhs_parts = [], [], [], []
    n_rows = 0
    for d, (di, dj) in enumerate(_AXES):
        # edges p -> q = p + (di, dj) with at least one end in the frame-unknown set
        p_mask = frame_unknown | np.roll(frame_unknown, (-di, -dj), axis=(0, 1))
        p_nodes = np.argwhere(p_mask)
        pi, pj = p_nodes.T
        qi, qj = pi + di, pj + dj
        n_edges = len(p_nodes)
        ends = []
        for ei, ej, sign in ((pi, pj, -1.0), (qi, qj, 1.0)):
            eid = idx.id[ei, ej]
            ends.append((ei, ej, eid, sign))
        rhs = np.zeros((n_edges, 3, 3))  # (edge, X, coord)
        for ei, ej, eid, sign in ends:
            coef = C[d][:, :, ei, ej]  # (X, Y, edges)
            free = eid >= 0
            for X in range(3):
                row = n_rows + 3 * np.arange(n_edges) + X
                for Y in range(3):
                    val = -0.5 * coef[X, Y] + (sign / h if X == Y else 0.0)
                    rows.append(row[free])
                    cols.append(3 * eid[free] + Y)
                    vals.append(val[free])
                    kf = known_frame[ei[~free], ej[~free], Y]  # (k, coord)
                    rhs[~free, X] -= val[~free, None] * kf
        rhs_parts.append(rhs.reshape(-1, 3))
        n_rows += 3 * n_edges
    rhs = np.concatenate(rhs_parts)
    if not (np.all(np.isfinite(rhs)) and all(np.all(np.isfinite(v)) for v in vals)):
        raise ValueError(
            "frame equations have non-finite coefficients or boundary frame (degenerate known "
            "surface or λ = 0 near the unknown region)"
        )
    A = sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(n_rows, 3 * idx.size),
    )
    AtA = (A.T @ A).tocsc()
    solve = factorized_definite(AtA)
    Atb = A.T @ rhs
    sol = np.column_stack([solve(Atb[:, k]) for k in range(3)]).reshape(idx.size, 3, 3)
    frame = known_frame.copy()
    frame[frame_unknown] = sol
    return frame[:, :, 0], frame[:, :, 1], frame[:, :, 2], (lu, lv, L, N)


def _integrate(pu, pv, puu, pvv, phi_known, unknown, h):
    """φ on the unknown nodes from its first and second derivatives on the grid edges.

    Each edge p → q = p + h e_u gets the increment of the Hermite (corrected trapezoid)
    rule, φ(q) − φ(p) = h/2 (φu(p) + φu(q)) − h²/12 (φuu(q) − φuu(p)) + O(h⁵), likewise along
    v; φ is their least-squares fit with Dirichlet data: h²Δhφ(p) = δ(p) − δ(p − e) summed
    over both directions. Every edge that touches an unknown node has both ends in the
    frame-unknown set, so only rebuilt derivatives are used.
    """
    div = 0.0
    for g, gg, (di, dj) in ((pu, puu, _AXES[0]), (pv, pvv, _AXES[1])):
        gq = np.roll(g, (-di, -dj), axis=(0, 1))
        ggq = np.roll(gg, (-di, -dj), axis=(0, 1))
        delta = 0.5 * h * (g + gq) - h * h / 12 * (ggq - gg)  # on the edge p -> p + e
        div = div + delta - np.roll(delta, (di, dj), axis=(0, 1))
    idx, A, neighbours = _laplacian_system(unknown, h)
    b = _dirichlet_rhs(np.where(unknown[..., None], 0.0, phi_known), neighbours, h)
    solve = factorized_definite(A)
    rhs = div[unknown] / h**2 - b
    return np.column_stack([solve(rhs[:, k]) for k in range(3)])


def _integrate_normal(lam, H, n, phi_known, unknown, h):
    """φ on the unknown nodes from Δhφ = 2λ²H n with the frame's normal (unit-normalized)."""
    n = n / np.linalg.norm(n, axis=-1, keepdims=True)
    idx, A, neighbours = _laplacian_system(unknown, h)
    b = _dirichlet_rhs(np.where(unknown[..., None], 0.0, phi_known), neighbours, h)
    solve = factorized_definite(A)
    rhs = (2 * lam**2 * H)[unknown][:, None] * n[unknown] - b
    return np.column_stack([solve(rhs[:, k]) for k in range(3)])
