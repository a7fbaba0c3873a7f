"""The analytic Jacobian of the λ-H fill's lagged update on the mesh
(:meth:`surfinpaint.representation.on_mesh._CoupledSystem.jacobian`), used by the
least-squares stage (docs/convergence.md, session 12), and the derivative of the mixed
Voronoi areas it needs. Checked against central differences in tests/test_convergence.py."""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from surfinpaint.geometry.mesh import vertex_areas
from surfinpaint.geometry.rows import rows_any
from surfinpaint.representation.face_derivatives import kept_blocks, update_rhs
from surfinpaint.representation.mesh_lambda_h import (
    area_vectors,
)

_GETRS = sla.get_lapack_funcs("getrs", dtype=np.float64)
_GETRF = sla.get_lapack_funcs("getrf", dtype=np.float64)

__all__ = ["FaceBlocks", "UpdateDerivative", "dense_jacobian", "kept_on", "lagged_update_jacobian",
           "stencil_terms", "voronoi_area_derivative"]


def dense_jacobian(system) -> _DenseJacobian:
    """The system's dense Jacobian (:class:`_DenseJacobian`), made at its first use."""
    return _DenseJacobian.of(system)


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
    return _DenseJacobian.of(system).at(phi)


class UpdateDerivative:
    """The lagged update's derivative at ``phi``, made once: :meth:`apply` gives its products
    with any block of directions, :meth:`residual_product` the matrix-free product Newton–Krylov
    steps use on large patches.

    Why: the dense Jacobian's cost is its ``(3n, 3m)`` intermediates (0.39 s at 584 free
    vertices, docs/convergence.md session 13), so above ``on_mesh.NEWTON_ANALYTIC_MAX`` free
    vertices Newton's steps took GMRES on finite-difference products (one lagged update
    each, 1e-3 relative); a product here is the same chain rule with one right-hand side,
    exact, for a fraction of an update (session 14)."""

    def __init__(self, system, phi):
        self.system, self.phi = system, phi
        self.state = system._lagged(phi)[1]
        f, m = system.f, system.moving
        self.P = 3 * len(f)
        # (3 len m, P) and (len m, P), rows in m's order: assembled at index arrays made once
        # a system (the sparse matrices' sums in another order than the whole mesh's
        # derivatives sliced, which cost most of a Newton–Krylov step's set-up: session 30)
        self.d_unit, self.d_area = FaceBlocks.of(system, m).sparse(phi)
        # a vertex's row among the moving ones, the ring (m without f) and the rows of the
        # ring, tied and free vertices, Q_fk's columns on the ring (d λ is zero on the other
        # fixed vertices): no position changes them, made once a system (_ProductIndex)
        index = _ProductIndex.of(system)
        self.where, self.ring, self.rows = index.where, index.ring, index.rows
        # what the natural border's term takes at phi, made once, not at each product
        self.stencil_terms = (stencil_terms(system, phi, self.state[0])
                              if len(system.natural_data) else None)
        self._woodbury = None
        # what no direction changes, made once (session 30): λ's scales on the ring, and
        # Z_t (d_n,c H_f)
        ring, tied, area, lam = self.ring, system.tied, system.area, system.lam
        normals, s, _, d_n, _, H, _ = self.state
        a_t = area[tied] * s[tied]
        self.fixed_terms = (index.Q_ring, (2.0 * lam[ring] * area[ring])[:, None],
                            index.tied_in_ring, a_t, (a_t**2 / area[tied])[:, None],
                            system.Z_t @ (d_n * H[:len(f), None]), (area[f] * s[f])[:, None, None])
        # and the gathers and broadcasts of the state every product took again (session 32
        # helper: the same values, made once)
        self.gathered = (4.0 * lam[f, None], 4.0 * lam[tied, None], a_t[:, None, None],
                         normals[tied][:, :, None], normals[f][:, :, None], area[f][:, None],
                         system.L_t_phi + self.fixed_terms[5], H[:len(f), None, None],
                         d_n[:, :, None])

    def residual_product(self, v):
        """``(J − I) v`` for one direction ``v`` (P,) (rows ``3 i + c``)."""
        v = np.asarray(v).ravel()
        return self.apply(v.reshape(self.P, 1)).ravel() - v

    def apply(self, V):
        """``J V`` for directions ``V`` (P, k) (rows ``3 i + c``), or ``J`` itself for
        ``None`` (the same operations as a product with the identity, on sparse columns:
        the reference :func:`lagged_update_jacobian`'s faster path is tested against)."""
        system, phi = self.system, self.phi
        f, m = system.f, system.moving
        normals, s, w_n, d_n, K, H, C = self.state
        n_free = len(f)
        k = self.P if V is None else V.shape[1]
        if V is None:
            d_unit, d_area = self.d_unit.toarray(), self.d_area.toarray()
        else:
            d_unit, d_area = self.d_unit @ V, self.d_area @ V
        where = self.where

        def d_normals(ids):  # (len(ids), 3, k)
            return d_unit.reshape(len(m), 3, k)[where[ids]]

        # λ: sqrt(area_3D / area) at the moving vertices, biharmonic over the free ones
        Q_ring, lam_scale, tied_in_ring, a_t, st, Z_dnH, as_f = self.fixed_terms
        lam4_f, lam4_t, a_t3, n_t3, n_f3, area_f, beta, H_f3, d_n3 = self.gathered
        rows = self.rows
        d_lam_ring = d_area[rows["ring"]] / lam_scale
        d_s_f = lam4_f * system.lam_lu.solve(-(Q_ring @ d_lam_ring))
        d_s_t = lam4_t * d_lam_ring[tied_in_ring]
        d_unit3 = d_unit.reshape(len(m), 3, k)
        dn_t, dn_f = d_unit3[rows["tied"]], d_unit3[rows["f"]]
        d_st = d_s_t / st  # ds / (area s²)
        d_wn = dn_t / a_t3 - n_t3 * d_st[:, None, :]
        d_dn = system.curvature * (dn_f * as_f + n_f3 * (area_f * d_s_f)[:, None, :])
        # d(K H) = Σ_c dw_n,c ∘ Z_t (d_n,c H_f) + w_n,c ∘ Z_t (dd_n,c H_f); with L_tφ·dw_n
        z = np.einsum("tc,tcp->tp", beta, d_wn)
        z += np.einsum("tc,tcp->tp", w_n, (system.Z_t @ (d_dn * H_f3).reshape(
            n_free, 3 * k)).reshape(-1, 3, k))
        d_b = -(system.Q_ft @ z)
        if len(system.natural_data):
            d_b -= system.Q_fs @ _d_stencil_H(system, phi, normals, d_normals, d_area, V,
                                              self.stencil_terms)
        y = system.Q_lu.solve(d_b)  # (Q_ff + Q_ft K)⁻¹ by Woodbury
        d_H = y - system.Y @ self._capacitance(K, C, y, V is None)
        rhs = d_dn * H_f3 + d_n3 * d_H[:n_free][:, None, :]
        return system.L_lu.solve(rhs.reshape(n_free, 3 * k)).reshape(3 * n_free, k)

    def _capacitance(self, K, C, y, dense):
        """``(I + K Y)⁻¹ K y`` (``C = I + K Y``, the lagged solve's): a dense solve for the
        Jacobian, one LU for the products."""
        if dense:
            return np.linalg.solve(C, K @ y)
        if self._woodbury is None:
            self._woodbury = sla.lu_factor(C)  # a copy: C is the state's
        # LAPACK's getrs as sla.lu_solve calls it, without its checks (a tenth of a product)
        lu, piv = self._woodbury
        x, info = _GETRS(lu, piv, K @ y)
        if info:
            raise ValueError(f"getrs: illegal value in argument {-info}")
        return x


class _ProductIndex:
    """What :class:`UpdateDerivative` takes of a system whatever the positions, made at its
    first use (:meth:`of`): ``where`` (a vertex's row among the moving ones, -1 elsewhere),
    ``ring`` (the moving vertices that are not free), ``rows`` (the rows of the ring, the
    tied and the free vertices), ``tied_in_ring`` (the tied vertices' places in the ring) and
    ``Q_ring`` (``Q_fk``'s columns on the ring).

    Why: every Newton–Krylov step made them again (the ring's set difference and Q_fk's
    columns a fifth of a step's set-up at 681 free vertices; session 47 helper)."""

    def __init__(self, system):
        n, m, f = len(system.points), system.moving, system.f
        self.where = np.full(n, -1)
        self.where[m] = np.arange(len(m))
        self.ring = ring = np.setdiff1d(m, f)
        self.rows = {"ring": self.where[ring], "tied": self.where[system.tied],
                     "f": self.where[f]}
        in_fixed, in_ring = np.full(n, -1), np.full(n, -1)
        in_fixed[system.fixed] = np.arange(len(system.fixed))
        in_ring[ring] = np.arange(len(ring))
        self.tied_in_ring = in_ring[system.tied]
        self.Q_ring = system.Q_fk[:, in_fixed[ring]]

    @classmethod
    def of(cls, system):
        """The system's, made at its first use (its vertex sets do not change)."""
        return kept_on(system, "product_index", cls)


def kept_on(system, name: str, make):
    """``make(system)``, made at the first call and kept on the system as ``name`` (what
    depends only on a system's matrices and vertex sets, which do not change)."""
    made = getattr(system, name, None)
    if made is None:
        made = make(system)
        setattr(system, name, made)
    return made


def stencil_terms(system, phi, normals):
    """What :func:`_d_stencil_H` takes at ``phi`` whatever the directions: the moving
    vertices' areas, ``L φ`` and ``n · L φ / 2 area`` there, and ``L``'s block (moving, free)
    (made once a system)."""
    m = system.moving
    areas = vertex_areas(phi, system.near)[m]
    Lphi = (system.L[m] @ phi)
    H = np.einsum("ij,ij->i", Lphi, normals[m]) / (2.0 * areas)
    L_mf = getattr(system, "L_mf", None)
    if L_mf is None:
        L_mf = system.L_mf = system.L[m][:, system.f]
    return areas, Lphi, H, L_mf


def _d_stencil_H(system, phi, normals, d_normals, d_area, V, terms=None):
    """The derivative of :meth:`_CoupledSystem.stencil_H` in the free positions (on a natural border
    its H is the mean of inner neighbours', some of which the free vertices move), applied to
    the directions ``V`` (None: all; ``d_area`` the moving vertices' area derivative, applied;
    ``terms``: :func:`stencil_terms` at ``phi``, made when not given)."""
    m, P = system.moving, 3 * len(system.f)
    areas, Lphi, H, L_mf = terms or stencil_terms(system, phi, normals)
    if V is None:
        L_mf = L_mf.toarray()
        d_Lphi_n = (L_mf[:, :, None] * normals[m][:, None, :]).reshape(len(m), P)
    else:  # d(L φ)·n = n · L_mf V
        k = V.shape[1]
        moved = (L_mf @ V.reshape(len(system.f), 3 * k)).reshape(-1, 3, k)
        d_Lphi_n = np.einsum("ic,ick->ik", normals[m], moved)
    d_H = ((np.einsum("ic,icp->ip", Lphi, d_normals(m)) + d_Lphi_n) / (2.0 * areas)[:, None]
           - H[:, None] * d_area / areas[:, None])
    out = np.zeros((len(system.stencil), d_H.shape[1]))
    adjacency_m, inner_m = _adjacency_moving(system)
    out[system.on_natural_stencil] = (adjacency_m @ (inner_m * d_H) / system.weight[:, None])
    return out


def _adjacency_moving(system):
    """The natural data's adjacency to the moving vertices, ``adjacency[:, m]``, and
    ``inner[m]`` as a column, made where the adjacency is new (a test replaces it). Why:
    slicing the sparse matrix's columns at every Newton–Krylov product cost about as much
    as the product's other work on a natural border (session 32 helper)."""
    made = getattr(system, "_adjacency_m", None)
    if made is None or made[0] is not system.adjacency:
        m = system.moving
        made = system._adjacency_m = (system.adjacency, system.adjacency[:, m],
                                      system.inner[m][:, None])
    return made[1], made[2]


def _corner_area_derivative(phi, faces):
    """(F, corner k, corner j, 3): the derivative of corner k's share of its face's mixed
    area (:func:`voronoi_area_derivative`) in corner j's position."""
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
    any_obtuse = rows_any(obtuse)
    share = np.where(obtuse, 0.25, 0.125)[any_obtuse]  # of |cross|, twice the face's area
    d_corner[any_obtuse] = share[:, :, None, None] * d_norm[any_obtuse][:, None]
    return d_corner


def voronoi_area_derivative(phi, faces, free):
    """The derivative of the vertices' Voronoi areas (:func:`vertex_areas`, Meyer et al.'s
    mixed areas, summed over ``faces``; rows: vertices) in the positions of the ``free``
    vertices (columns ``3 i + c``: free vertex i, coordinate c), sparse."""
    column = np.full(len(phi), -1)
    column[free] = np.arange(len(free))
    d_corner = _corner_area_derivative(phi, faces)
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


class FaceBlocks:
    """The derivatives of the unit vertex normals and the Voronoi areas in the free
    positions, at the vertices ``rows`` (normals) and the moving ones (areas), assembled from
    every face's 3 × 3 blocks at index arrays made once a system and row order (:meth:`of`):
    rows ``3 r + a`` (the vertex ``rows[r]``, coordinate a), columns ``3 j + b`` (free
    vertex j, coordinate b). :meth:`dense` adds the blocks into dense arrays, :meth:`sparse`
    into CSR matrices of the same pattern, both in the faces' order.

    Why: :class:`UpdateDerivative` took the whole patch's derivatives (3n × 3n) and sliced
    them, at each Newton–Krylov step; the dense Jacobian's rows in ``rows``' order give its
    free and tied vertices' rows as slices (session 30)."""

    def __init__(self, system, rows):
        f, m, n = system.f, system.moving, len(system.points)
        self.where = np.full(n, -1)  # a vertex's row among ``rows``
        self.where[rows] = np.arange(len(rows))
        self.where_m = np.full(n, -1)  # and among the moving ones (the areas' rows)
        self.where_m[m] = np.arange(len(m))
        column = np.full(n, -1)
        column[f] = np.arange(len(f))
        self.shape = (3 * len(rows), 3 * len(f))
        faces = self.faces = system.near
        self.n_moving = len(m)
        # the flat entries (3 row + a, 3 column + b) every face's corner pair (i, j) adds to
        pair = np.array([(i, j) for i in range(3) for j in range(3)])
        i_row, j_col = self.where[faces[:, pair[:, 0]]], column[faces[:, pair[:, 1]]]
        kept = (i_row >= 0) & (j_col >= 0)  # ``rows`` are the moving vertices, in any order
        r = 3 * i_row[..., None, None] + np.arange(3)[:, None]
        c = 3 * j_col[..., None, None] + np.arange(3)
        self.flat = (r * self.shape[1] + c)[kept].ravel()  # (kept, 3, 3)
        i_m = self.where_m[faces[:, pair[:, 0]]]
        self.area_flat = (i_m[..., None] * self.shape[1] + 3 * j_col[..., None]
                          + np.arange(3))[kept].ravel()  # (kept, 3)
        # the kept pairs' faces, corners i (their vertex's normal) and j (the one moved)
        self.with_free = rows_any(kept)  # the faces with a free corner
        self.kept = kept[self.with_free]
        face, which = np.nonzero(kept)
        self.vertex_i, self.face_j = faces[face, pair[which, 0]], (face, pair[which, 1])
        self._csr = None

    @classmethod
    def of(cls, system, rows):
        """The system's for the row order ``rows``, made at its first use."""
        made = getattr(system, "face_blocks", None)
        if made is None:
            made = system.face_blocks = {}
        key = rows.tobytes()
        if key not in made:
            made[key] = cls(system, rows)
        return made[key]

    def blocks(self, phi):
        """The blocks' values at the kept entries, in the order of ``flat`` and ``area_flat``
        (the kept pairs' only, and the area's of the faces with a free corner: the same bits
        as all blocks' made and the kept ones taken), compiled where numba is
        (:func:`~surfinpaint.representation.face_derivatives.kept_blocks`, the same bits)."""
        return kept_blocks(phi, self.faces, self.vertex_i, self.face_j, self.with_free,
                           self.kept, lambda: self._blocks_numpy(phi))

    def _blocks_numpy(self, phi):
        """:meth:`blocks` in numpy (the kernel's reference)."""
        faces = self.faces
        p = phi[faces]
        N = area_vectors(phi, faces)
        length = np.linalg.norm(N, axis=1)
        length = np.where(length > 0, length, 1.0)
        unit = N / length[:, None]
        P = (np.eye(3)[None] - unit[:, :, None] * unit[:, None, :]) / length[:, None, None]
        # d n_i / d p_j over a face: P_i [p_{j+2} − p_{j+1}]× (normals_with_jacobian), whose
        # rows are P_i's rows × (p_{j+2} − p_{j+1})
        e = (p[:, [2, 0, 1]] - p[:, [1, 2, 0]])[self.face_j][:, None, :]  # (kept, 1, 3)
        Pi = P[self.vertex_i]  # (kept, 3, 3)
        blocks = np.empty_like(Pi)
        blocks[..., 0] = Pi[..., 1] * e[..., 2] - Pi[..., 2] * e[..., 1]
        blocks[..., 1] = Pi[..., 2] * e[..., 0] - Pi[..., 0] * e[..., 2]
        blocks[..., 2] = Pi[..., 0] * e[..., 1] - Pi[..., 1] * e[..., 0]
        d_corner = _corner_area_derivative(phi, faces[self.with_free])
        return blocks.ravel(), d_corner.reshape(len(d_corner), 9, 3)[self.kept].ravel()

    def dense(self, phi):
        """(3 len(rows), P) and (len(m), P) dense arrays."""
        unit, area = self.blocks(phi)
        size = self.shape[0] * self.shape[1]
        d_unit = np.bincount(self.flat, unit, size).reshape(self.shape)
        d_area = np.bincount(self.area_flat, area, self.n_moving * self.shape[1])
        return d_unit, d_area.reshape(self.n_moving, self.shape[1])

    def sparse(self, phi):
        """The same as CSR matrices (their pattern and each entry's slot made once)."""
        if self._csr is None:
            self._csr = [_pattern(flat, (rows, self.shape[1])) for flat, rows in (
                (self.flat, self.shape[0]), (self.area_flat, self.n_moving))]
        out = []
        for values, (slot, indices, indptr, shape) in zip(self.blocks(phi), self._csr,
                                                         strict=True):
            data = np.bincount(slot, values, len(indices))
            out.append(sp.csr_matrix((data, indices, indptr), shape=shape))
        return tuple(out)


def _pattern(flat, shape):
    """A CSR pattern of the flat entries ``flat`` (row · columns + column) of a ``shape``
    matrix: each entry's slot, the indices and the row pointers."""
    entries, slot = np.unique(flat, return_inverse=True)
    rows, indices = np.divmod(entries, shape[1])
    indptr = np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=shape[0]))])
    return slot.ravel(), indices.astype(np.int32), indptr.astype(np.int32), shape


class _DenseJacobian:
    """:func:`lagged_update_jacobian`'s fast path: :meth:`UpdateDerivative.apply` with
    ``None`` rearranged for many right-hand sides, with what no position changes made once
    a system (:meth:`of`).

    Why: Newton's steps on patches of up to ``on_mesh.NEWTON_ANALYTIC_MAX`` free vertices
    take one Jacobian each, 2/3 of the continuation's time (docs/convergence.md, session
    28); there it took SuperLU solves with hundreds of right-hand sides and the 3n × 3n
    sparse derivatives of the normals. Here the solves are products with matrices made
    once (``L_ff⁻¹``; ``Q_ff⁻¹`` folded into ``Y = Q_ff⁻¹ Q_ft``, so the Woodbury update
    needs no solve with Q: ``d_H = −Y (I + K Y)⁻¹ z``), the derivatives are assembled
    densely at index arrays made once (:class:`FaceBlocks`), rows of the free vertices first,
    then the tied ones. The chain rule's terms are regrouped so that only the normals'
    derivatives are (3 free, P) arrays (session 30: a third of the time). The same Jacobian
    to rounding (tested)."""

    def __init__(self, system):
        self.system = system
        f, m, tied = system.f, system.moving, system.tied
        rest = np.setdiff1d(m, np.concatenate([f, tied]))  # on a natural border
        self.blocks = FaceBlocks.of(system, np.concatenate([f, tied, rest]))
        self.where = self.blocks.where  # a vertex's row of the normals' derivative
        index = _ProductIndex.of(system)  # the ring: λ's data next to the free vertices
        self.ring, self.tied_in_ring = index.ring, index.tied_in_ring
        self.ring_rows = self.blocks.where_m[index.ring]
        # d λ_f = −Q_ff⁻¹ Q_fk d λ_k, d λ_k nonzero on the ring only
        self.lam_map = -system.lam_lu.solve(index.Q_ring.toarray())
        self.L_inv = system.L_lu.solve(np.eye(len(f)))
        self.stencil_map = (system.Q_lu.solve(system.Q_fs.toarray())
                            if len(system.natural_data) else None)  # Q_ff⁻¹ Q_fs
        self.shape = (3 * len(m), 3 * len(f))

    @classmethod
    def of(cls, system):
        """The system's, made at its first Jacobian (its matrices do not change)."""
        return kept_on(system, "dense_jacobian", cls)

    def derivatives(self, phi):
        """The unit normals' (3 len(m), P) derivatives at the moving vertices in the free
        positions, rows in the order of :attr:`where` (free, tied, the rest), and the Voronoi
        areas' (len(m), P), rows in m's order: dense."""
        return self.blocks.dense(phi)

    def at(self, phi):
        """The (P, P) Jacobian at ``phi`` (:meth:`UpdateDerivative.apply` with ``None``)."""
        n_free, P = len(self.system.f), self.shape[1]
        rhs = self.right_hand_side(phi)
        return (self.L_inv @ rhs.reshape(n_free, 3 * P)).reshape(3 * n_free, P)

    def step(self, phi, r):
        """The Newton step ``−(J − I)⁻¹ r`` at ``phi`` for the residual ``r`` (P,), solved
        as ``(R − L̃) dx = −L̃ r``: ``J = L̃⁻¹ R`` with ``R`` :meth:`right_hand_side` (the
        same bits as :meth:`at`'s) and ``L̃ = L_ff ⊗ I₃``, so no product with ``L_ff⁻¹``.
        The same step to rounding (measured: 2e-12 relative at most over CAD channel #5's
        67 steps). Raises ``np.linalg.LinAlgError`` where ``R − L̃`` is exactly singular.

        Why: the product ``L_ff⁻¹ R`` cost as many flops as the LU of ``J − I``, a fifth of
        a step (session 33 helper). :meth:`at`, which Levenberg–Marquardt takes, is
        unchanged. (``R``'s products with the sparse derivatives taken as sparse products
        measured faster on 121 free vertices, slower on 80 and fewer: not kept.)"""
        n_free, P = len(self.system.f), self.shape[1]
        flat, values = self.stiffness_entries()
        R = np.ascontiguousarray(self.right_hand_side(phi)).reshape(3 * n_free, P)
        R.reshape(-1)[flat] -= values  # a view: R is contiguous
        # LAPACK on Rᵀ's memory (Fortran order, no copy), solved transposed
        lu, piv, info = _GETRF(R.T, overwrite_a=True)
        if info > 0:
            raise np.linalg.LinAlgError("R − L̃ is exactly singular")
        dx, info = _GETRS(lu, piv, -(self.system.L_ff @ r.reshape(n_free, 3)).ravel(),
                          trans=1)
        if info:
            raise ValueError(f"getrs: illegal value in argument {-info}")
        return dx

    def stiffness_entries(self):
        """``L_ff``'s entries as the flat entries of ``L̃ = L_ff ⊗ I₃`` in a dense (P, P)
        array (rows and columns ``3 i + c``) and their values, made at the first step."""
        made = getattr(self, "_made_stiffness", None)
        if made is None:
            L_ff = self.system.L_ff.tocoo()
            L_ff.sum_duplicates()  # one entry a position: added to R by assignment
            c, P = np.arange(3), self.shape[1]
            flat = ((3 * L_ff.row[:, None] + c) * P + 3 * L_ff.col[:, None] + c).ravel()
            made = self._made_stiffness = (flat, np.repeat(L_ff.data, 3))
        return made

    def right_hand_side(self, phi):
        """``R`` (free, 3, P), the Jacobian before its product with ``L_ff⁻¹``: ``J = L̃⁻¹ R``
        (:meth:`at`'s arithmetic)."""
        system = self.system
        f, tied, area = system.f, system.tied, system.area
        normals, s, w_n, d_n, K, H, C = system._lagged(phi)[1]
        lam, kappa = system.lam, system.curvature
        n_free, n_tied, P = len(f), len(tied), self.shape[1]
        H_f = H[:n_free]
        d_unit, d_area = self.derivatives(phi)
        d_unit = d_unit.reshape(-1, 3, P)
        dn_f, dn_t = d_unit[:n_free], d_unit[n_free:n_free + n_tied]  # views
        ring = self.ring
        d_lam_ring = d_area[self.ring_rows] / (2.0 * lam[ring] * area[ring])[:, None]
        d_s_f = 4.0 * lam[f, None] * (self.lam_map @ d_lam_ring)
        d_s_t = 4.0 * lam[tied, None] * d_lam_ring[self.tied_in_ring]
        a_t = area[tied] * s[tied]
        d_st = d_s_t / (a_t**2 / area[tied])[:, None]
        n_t, n_f = normals[tied], normals[f]
        # d_wn = dn_t / a_t − n_t d_st; d_dn = α dn_f + κ area_f n_f ⊗ d_s_f (α below)
        alpha = kappa * area[f] * s[f]  # d_n = α n_f
        # z = L_tφ·dw_n + d(K H) = Σ_c β_c dw_n,c + Σ_c w_n,c Z_t (H_f d_dn,c), with
        # β = L_tφ + Z_t (d_n H_f); d_b = −Q_ft z (− Q_fs dH_s on a natural border)
        beta = system.L_t_phi + system.Z_t @ (d_n * H_f[:, None])
        z = (np.einsum("tc,tcp->tp", beta / a_t[:, None], dn_t)
             - np.einsum("tc,tc->t", beta, n_t)[:, None] * d_st)
        W = w_n[:, None, :] * (system.Z_t * (alpha * H_f))[:, :, None]  # (t, free, 3)
        z += W.reshape(n_tied, 3 * n_free) @ dn_f.reshape(3 * n_free, P)
        z += (system.Z_t * (w_n @ n_f.T) * (kappa * area[f] * H_f)) @ d_s_f
        if self.stencil_map is None:
            d_H = -(system.Y @ np.linalg.solve(C, z))
        else:
            W = self.stencil_map @ _d_stencil_H(system, phi, normals, lambda ids: d_unit[
                self.where[ids]], d_area, None)
            d_H = -(system.Y @ np.linalg.solve(C, z - K @ W)) - W
        # rhs = d_dn H_f + d_n ⊗ d_H = (α H_f) dn_f + n_f ⊗ q,
        # q = (κ area_f H_f) d_s_f + α d_H_f
        return update_rhs(dn_f, n_f, alpha * H_f, kappa * area[f] * H_f, d_s_f, alpha,
                          d_H[:n_free])
