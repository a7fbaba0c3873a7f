"""Newton's step on the λ-H fixed-point residual with a sparse factorization: the matrix
``R − L̃`` of :meth:`~surfinpaint.representation.coupled_jacobian._DenseJacobian.step` split
into a sparse part and a low-rank one, solved by SuperLU and the Woodbury identity
(docs/convergence.md, session 48 helper).

The split: with the dense Jacobian's names, ``R = (α H_f) dn_f + n_f ⊗ q`` where ``dn_f`` (the
free vertices' unit normals' derivatives) is sparse and ``q = u d_s_f + α d_H_f`` is a linear
map of two small blocks of rows: ``d_s_f = A_s d_λ_ring`` (``A_s = 4 λ_f Q_ff⁻¹ Q_ring``, a
dense (free, ring) matrix made once a system) and ``d_H_f = −Y_f C⁻¹ z`` (``z`` (tied, P)).
So ``R − L̃ = S + U X`` with ``S = (α H_f) dn_f − L̃`` sparse (P, P), ``X = [d_λ_ring; z]``
(r, P) and ``U = n_f ⊗ [u A_s, −α Y_f C⁻¹]`` (P, r), r = ring + tied vertices, and

    (S + U X)⁻¹ b = S⁻¹ b − S⁻¹ U (I + X S⁻¹ U)⁻¹ X S⁻¹ b.

Why: the dense step's LU costs ``2/3 P³`` and its matrix ``P²`` entries of products; here
the factorization is sparse and the dense work is ``P r²`` (r, about the patch's border,
is a third of P at 120–160 free vertices and a smaller share on larger patches), so it is
faster from about 140 free vertices (``SPARSE_STEP_MIN_FREE``; below, SuperLU's set-up and
its r right-hand sides cost more than the dense LU). The same step to rounding (tested
against the dense one: 1e-11 relative at most over the tuning side's steps), not the same
bits.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from surfinpaint.representation.coupled_jacobian import dense_jacobian, kept_on

__all__ = ["SPARSE_STEP_MIN_FREE", "SparseNewtonStep", "newton_step"]

# the sparse step on patches of at least this many free vertices: below, the dense step is
# faster (both timed at every step of the tuning side's fills: 1.1-1.9 times the dense step's
# CPU on its patches of 63-121 free vertices; 0.74 at 156, 0.66 at 144 on an egg-crate:
# docs/convergence.md, session 48 helper)
SPARSE_STEP_MIN_FREE = 140


class SparseNewtonStep:
    """:meth:`step`, with what no position changes made once a system (:meth:`of`): the
    sparse matrix ``S``'s pattern and each entry's slot, the entries of the tied vertices'
    normals' derivatives in ``z`` and the ring's area derivatives in ``d_λ_ring``."""

    def __init__(self, system):
        self.system = system
        dense = self.dense = dense_jacobian(system)
        n_free, n_tied = len(system.f), len(system.tied)
        P = self.P = 3 * n_free
        blocks = dense.blocks  # rows: free, tied, the rest; entries in ``flat``'s order
        row, col = np.divmod(blocks.flat, P)
        self.in_f = row < P
        self.in_t = (row >= P) & (row < P + 3 * n_tied)
        # S = diag(α H_f ⊗ 1₃) dn_f − L̃ in CSC: dn_f's entries, then L̃'s
        L_flat, L_values = dense.stiffness_entries()
        L_row, L_col = np.divmod(L_flat, P)
        keys = np.concatenate([col[self.in_f] * P + row[self.in_f], L_col * P + L_row])
        entries, slot = np.unique(keys, return_inverse=True)
        n_f_entries = int(self.in_f.sum())
        self.unit_slot, self.L_slot = slot[:n_f_entries], slot[n_f_entries:]
        self.minus_L = -L_values
        self.unit_vertex = row[self.in_f] // 3  # the free vertex of each dn_f entry
        columns, rows = np.divmod(entries, P)
        self.S_pattern = (rows.astype(np.int32), np.concatenate(
            [[0], np.cumsum(np.bincount(columns, minlength=P))]).astype(np.int32))
        self.n_slots = len(entries)
        # dn_f as CSR for W dn_f: its slots and pattern
        f_entries, self.f_slot = np.unique(blocks.flat[self.in_f], return_inverse=True)
        f_rows, f_cols = np.divmod(f_entries, P)
        self.f_pattern = (f_cols.astype(np.int32), np.concatenate(
            [[0], np.cumsum(np.bincount(f_rows, minlength=P))]).astype(np.int32))
        # Σ_c (β / a_t)_c dn_t,c: each tied entry's place in (tied, P) and its (t, c)
        t_row = row[self.in_t] - P
        self.t_vertex, self.t_coordinate = np.divmod(t_row, 3)
        self.z_flat = self.t_vertex * P + col[self.in_t]
        # d_λ_ring: the area derivative's entries on the ring's rows, at (ring, P)
        in_ring = np.full(blocks.n_moving, -1)
        in_ring[dense.ring_rows] = np.arange(len(dense.ring_rows))
        area_row, area_col = np.divmod(blocks.area_flat, P)
        ring_of = in_ring[area_row]
        self.on_ring = ring_of >= 0
        self.ring_flat = ring_of[self.on_ring] * P + area_col[self.on_ring]
        self.n_ring = len(dense.ring_rows)

    @classmethod
    def of(cls, system):
        """The system's, made at its first step (its matrices do not change)."""
        return kept_on(system, "sparse_newton_step", cls)

    def step(self, phi, r):
        """The Newton step ``−(J − I)⁻¹ r`` at ``phi`` for the residual ``r`` (P,): the
        dense step's ``(R − L̃) dx = −L̃ r`` solved as ``(S + U X) dx`` by Woodbury (module
        docstring). Returns None where ``S`` or the capacitance ``I + X S⁻¹ U`` is exactly
        singular (the caller then takes the dense step)."""
        system = self.system
        unit, d_area = self.dense.blocks.blocks(phi)
        lu, U, X = self._factored(phi, unit), *self._low_rank(phi, unit, d_area)
        if lu is None:
            return None
        y0 = lu.solve(-(system.L_ff @ r.reshape(len(system.f), 3)).ravel())
        V = lu.solve(U)
        capacitance = X @ V
        capacitance[np.diag_indices_from(capacitance)] += 1.0
        try:
            w = np.linalg.solve(capacitance, X @ y0)
        except np.linalg.LinAlgError:
            return None
        return y0 - V @ w

    def _factored(self, phi, unit):
        """SuperLU's factors of ``S = (α H_f ⊗ 1₃) dn_f − L̃`` at ``phi`` (``unit``: the
        face blocks' normal derivatives), or None where it is exactly singular."""
        system, P = self.system, self.P
        f, (_, s, *_, H, _) = system.f, system._lagged(phi)[1]
        alpha_H = system.curvature * system.area[f] * s[f] * H[:len(f)]
        values = np.bincount(self.unit_slot, unit[self.in_f] * alpha_H[self.unit_vertex],
                             self.n_slots)
        values[self.L_slot] += self.minus_L
        try:
            return spla.splu(sp.csc_matrix((values, *self.S_pattern), shape=(P, P)),
                             permc_spec="MMD_AT_PLUS_A")
        except RuntimeError:  # SuperLU: exactly singular
            return None

    def _low_rank(self, phi, unit, d_area):
        """``U`` (P, r), Fortran order for SuperLU's solve, and ``X`` (r, P) at ``phi``:
        ``n_f ⊗ q = U X`` with ``q = u d_s_f + α d_H_f`` (the dense step's)."""
        system, dense, P = self.system, self.dense, self.P
        f, area, lam, kappa = system.f, system.area, system.lam, system.curvature
        normals, s, w_n, d_n, K, H, C = system._lagged(phi)[1]
        n_free, ring = len(f), dense.ring
        d_lam_ring = np.bincount(self.ring_flat, d_area[self.on_ring], self.n_ring * P).reshape(
            self.n_ring, P) / (2.0 * lam[ring] * area[ring])[:, None]
        A_s = 4.0 * lam[f, None] * dense.lam_map  # d_s_f = A_s d_λ_ring
        alpha, H_f, n_f = kappa * area[f] * s[f], H[:n_free], normals[f]
        YC = np.linalg.solve(C.T, system.Y[:n_free].T).T  # Y_f C⁻¹: d_H_f = −Y_f C⁻¹ z
        G = np.hstack([(kappa * area[f] * H_f)[:, None] * A_s, -alpha[:, None] * YC])
        U = (G.T[:, :, None] * n_f[None]).reshape(-1, P).T  # rows 3 i + c: n_f,c G_i
        z = self._z(phi, unit, d_lam_ring, A_s)
        return U, np.vstack([d_lam_ring, z])

    def _z(self, phi, unit, d_lam_ring, A_s):
        """``z`` (tied, P) of :meth:`_DenseJacobian.right_hand_side` from the sparse
        derivatives: ``Σ_c β_c dw_n,c + W dn_f + (Z_t …) d_s_f``, the same terms
        (``d_s_f = A_s d_λ_ring``)."""
        system, dense, P = self.system, self.dense, self.P
        f, tied, area, lam, kappa = (system.f, system.tied, system.area, system.lam,
                                     system.curvature)
        normals, s, w_n, d_n, _, H, _ = system._lagged(phi)[1]
        n_tied, H_f = len(tied), H[:len(f)]
        a_t = area[tied] * s[tied]
        beta = system.L_t_phi + system.Z_t @ (d_n * H_f[:, None])
        bt = beta / a_t[:, None]
        z = np.bincount(self.z_flat, unit[self.in_t] * bt[self.t_vertex, self.t_coordinate],
                        n_tied * P).reshape(n_tied, P)
        d_s_t = 4.0 * lam[tied, None] * d_lam_ring[dense.tied_in_ring]
        z -= (np.einsum("tc,tc->t", beta, normals[tied])[:, None]
              * (d_s_t / (a_t**2 / area[tied])[:, None]))
        alpha = kappa * area[f] * s[f]
        W = (w_n[:, None, :] * (system.Z_t * (alpha * H_f))[:, :, None]).reshape(n_tied, P)
        dn_f = sp.csr_matrix((np.bincount(self.f_slot, unit[self.in_f], len(self.f_pattern[0])),
                              *self.f_pattern), shape=(P, P))
        z += (dn_f.T @ W.T).T
        z += ((system.Z_t * (w_n @ normals[f].T) * (kappa * area[f] * H_f)) @ A_s) @ d_lam_ring
        return z


def newton_step(system, points, x, r):
    """The Newton step ``−(J − I)⁻¹ r`` on the fixed-point residual ``r`` (in edge lengths)
    at the free positions ``x`` (the rest of ``points`` fixed), with ``J`` the update's
    analytic Jacobian (:func:`.coupled_jacobian.lagged_update_jacobian`), solved as
    ``(R − L̃) dx = −L̃ r``: with a sparse factorization (:class:`SparseNewtonStep`) on
    patches of at least ``SPARSE_STEP_MIN_FREE`` free vertices without a natural border,
    densely otherwise (:meth:`_DenseJacobian.step`) and where the sparse one meets an exactly
    singular matrix; where ``R − L̃`` is exactly singular, with ``J − I`` itself (by least
    squares where that is singular too)."""
    phi = points.copy()
    phi[system.f] = x
    if len(system.f) >= SPARSE_STEP_MIN_FREE and not len(system.natural_data):
        dx = SparseNewtonStep.of(system).step(phi, r)
        if dx is not None:
            return dx
    dense = dense_jacobian(system)
    try:
        return dense.step(phi, r)
    except np.linalg.LinAlgError:
        J = dense.at(phi)
    J[np.diag_indices_from(J)] -= 1.0
    try:
        return np.linalg.solve(J, -r)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(J, -r, rcond=None)[0]
