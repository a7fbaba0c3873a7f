"""The analytic Jacobian of the λ-H fill's lagged update on the mesh
(:meth:`surfinpaint.representation.on_mesh._CoupledSystem.jacobian`), used by the
least-squares stage (docs/convergence.md, session 12), and the derivative of the mixed
Voronoi areas it needs. Checked against central differences in tests/test_convergence.py."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from surfinpaint.geometry.mesh import vertex_areas
from surfinpaint.representation.mesh_lambda_h import normals_with_jacobian

__all__ = ["lagged_update_jacobian", "newton_step", "voronoi_area_derivative"]


def lagged_update_jacobian(system, phi):
    """The (3m, 3m) Jacobian of the system's lagged update in the free positions (rows
    and columns ``3 i + c``: free vertex i, coordinate c), analytic: one pass of the chain rule
    through the lagged solve with the factorizations :meth:`_CoupledSystem.update` uses.

    Why: the update is ``φ_f = g + L_ff⁻¹ (d_n H_f)`` with ``H`` from the linear
    coupled system; only the normals and the vertex areas (so λ) depend on φ, and
    locally, so their derivatives are sparse and the rest is a few solves with many
    right-hand sides. Forward differences cost one update per column (3m updates a
    Jacobian, 2/3 of the least-squares stage's time: docs/convergence.md, session 12).
    """
    f, tied, area, lam, m = system.f, system.tied, system.area, system.lam, system.moving
    _, (normals, s, w_n, d_n, K, H) = system._lagged(phi)
    n_free, P = len(f), 3 * len(f)
    H_f = H[:n_free]
    columns = (3 * f[:, None] + np.arange(3)).ravel()
    d_unit = normals_with_jacobian(phi, system.near)[1][:, columns].tocsr()  # (3n, P)
    d_area = voronoi_area_derivative(phi, system.near, f)  # (n, P)

    def d_normals(ids):  # (len(ids), 3, P)
        rows = (3 * ids[:, None] + np.arange(3)).ravel()
        return d_unit[rows].toarray().reshape(len(ids), 3, P)

    # λ: sqrt(area_3D / area) at the moving vertices, biharmonic over the free ones
    d_lam = np.zeros((len(phi), P))
    ring = np.setdiff1d(m, f)
    d_lam[ring] = d_area[ring].toarray() / (2.0 * lam[ring] * area[ring])[:, None]
    d_lam[f] = system.lam_lu.solve(-(system.Q_fk @ d_lam[system.fixed]))
    d_s = 4.0 * lam[:, None] * d_lam
    dn_t, dn_f = d_normals(tied), d_normals(f)
    a_t = area[tied] * s[tied]
    d_st = d_s[tied] / (a_t**2 / area[tied])[:, None]  # ds / (area s²)
    d_wn = dn_t / a_t[:, None, None] - normals[tied][:, :, None] * d_st[:, None, :]
    d_dn = system.curvature * (dn_f * (area[f] * s[f])[:, None, None]
                             + normals[f][:, :, None] * (area[f][:, None] * d_s[f])[:, None, :])
    d_b = -(system.Q_ft @ np.einsum("tc,tcp->tp", system.L_t_phi, d_wn))
    if len(system.natural_data):
        d_b -= system.Q_fs @ _d_stencil_H(system, phi, normals, d_normals, d_area)
    # d(K H) = Σ_c dw_n,c ∘ Z_t (d_n,c H_f) + w_n,c ∘ Z_t (dd_n,c H_f)
    d_KH = sum(d_wn[:, c, :] * (system.Z_t @ (d_n[:, c] * H_f))[:, None]
               + w_n[:, [c]] * (system.Z_t @ (d_dn[:, c, :] * H_f[:, None]))
               for c in range(3))
    y = system.Q_lu.solve(d_b - system.Q_ft @ d_KH)  # (Q_ff + Q_ft K)⁻¹ by Woodbury
    d_H = y - system.Y @ np.linalg.solve(np.eye(len(tied)) + K @ system.Y, K @ y)
    rhs = d_dn * H_f[:, None, None] + d_n[:, :, None] * d_H[:n_free][:, None, :]
    return system.L_lu.solve(rhs.reshape(n_free, 3 * P)).reshape(P, P)

def newton_step(system, points, x, r):
    """The Newton step ``−(J − I)⁻¹ r`` on the fixed-point residual ``r`` (in edge lengths)
    at the free positions ``x`` (the rest of ``points`` fixed), with ``J`` the update's
    analytic Jacobian (:func:`lagged_update_jacobian`), solved densely (by least squares
    where ``J − I`` is singular)."""
    phi = points.copy()
    phi[system.f] = x
    J = lagged_update_jacobian(system, phi)
    J[np.diag_indices_from(J)] -= 1.0
    try:
        return np.linalg.solve(J, -r)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(J, -r, rcond=None)[0]


def _d_stencil_H(system, phi, normals, d_normals, d_area):
    """The derivative of :meth:`_CoupledSystem.stencil_H` in the free positions (on a natural border
    its H is the mean of inner neighbours', some of which the free vertices move)."""
    m, P = system.moving, 3 * len(system.f)
    areas = vertex_areas(phi, system.near)[m]
    Lphi = (system.L[m] @ phi)
    H = np.einsum("ij,ij->i", Lphi, normals[m]) / (2.0 * areas)
    L_mf = system.L[m][:, system.f].toarray()
    d_Lphi_n = (L_mf[:, :, None] * normals[m][:, None, :]).reshape(len(m), P)
    d_H = ((np.einsum("ic,icp->ip", Lphi, d_normals(m)) + d_Lphi_n) / (2.0 * areas)[:, None]
           - H[:, None] * d_area[m].toarray() / areas[:, None])
    out = np.zeros((len(system.stencil), P))
    out[system.on_natural_stencil] = (system.adjacency[:, m] @ (system.inner[m][:, None] * d_H)
                                    / system.weight[:, None])
    return out


def voronoi_area_derivative(phi, faces, free):
    """The derivative of the vertices' Voronoi areas (:func:`vertex_areas`, Meyer et al.'s
    mixed areas, summed over ``faces``; rows: vertices) in the positions of the ``free``
    vertices (columns ``3 i + c``: free vertex i, coordinate c), sparse."""
    column = np.full(len(phi), -1)
    column[free] = np.arange(len(free))
    p = phi[faces]  # (F, 3 corners, 3)
    edge = [p[:, (k + 2) % 3] - p[:, (k + 1) % 3] for k in range(3)]  # opposite corner k
    cross = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    norm = np.linalg.norm(cross, axis=1)
    unit = cross / np.maximum(norm, 1e-300)[:, None]
    # d cross / d p_k = [e_k]ₓ with e_k = p_{k+2} − p_{k+1}, so d|cross| / d p_k = ĉ × e_k
    d_norm = np.stack([np.cross(unit, edge[k]) for k in range(3)], axis=1)  # (F, k, 3)
    length2 = np.stack([np.einsum("ij,ij->i", e, e) for e in edge], axis=1)
    a = [p[:, (k + 1) % 3] - p[:, k] for k in range(3)]
    b = [p[:, (k + 2) % 3] - p[:, k] for k in range(3)]
    dot = np.stack([np.einsum("ij,ij->i", a[k], b[k]) for k in range(3)], axis=1)
    # gradients (F, quantity k, corner j, 3) of corner k's dot product and of length2_k
    d_dot = np.zeros((len(faces), 3, 3, 3))
    d_len2 = np.zeros_like(d_dot)
    for k in range(3):
        d_dot[:, k, (k + 1) % 3] = b[k]
        d_dot[:, k, (k + 2) % 3] = a[k]
        d_dot[:, k, k] = -(a[k] + b[k])
        d_len2[:, k, (k + 2) % 3] = 2.0 * edge[k]
        d_len2[:, k, (k + 1) % 3] = -2.0 * edge[k]
    # corner k's area: (l²_{k+2} dot_{k+2} + l²_{k+1} dot_{k+1}) / (8 |cross|) (cot = dot /
    # |cross|), or |cross| / 4 (an obtuse corner), |cross| / 8 (the others of its face)
    d_corner = np.empty_like(d_dot)
    for k in range(3):
        j, i = (k + 2) % 3, (k + 1) % 3
        top = length2[:, j] * dot[:, j] + length2[:, i] * dot[:, i]
        d_top = (length2[:, j, None, None] * d_dot[:, j] + dot[:, j, None, None] * d_len2[:, j]
                 + length2[:, i, None, None] * d_dot[:, i] + dot[:, i, None, None] * d_len2[:, i])
        d_corner[:, k] = (d_top / (8.0 * norm)[:, None, None]
                          - (top / (8.0 * norm**2))[:, None, None] * d_norm)
    obtuse = dot < 0
    any_obtuse = obtuse.any(axis=1)
    share = np.where(obtuse, 0.25, 0.125)[any_obtuse]  # of |cross|, twice the face's area
    d_corner[any_obtuse] = share[:, :, None, None] * d_norm[any_obtuse][:, None]
    rows, cols, values = [], [], []
    for j in range(3):  # corner j's position moves every corner's area
        has = column[faces[:, j]] >= 0
        col = (3 * column[faces[has, j]][:, None] + np.arange(3)).ravel()
        for k in range(3):
            rows.append(np.repeat(faces[has, k], 3))
            cols.append(col)
            values.append(d_corner[has, k, j].ravel())
    return sp.csr_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(len(phi), 3 * len(free)))
