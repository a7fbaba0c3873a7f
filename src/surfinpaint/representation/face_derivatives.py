"""Compiled pieces of the λ-H fill's analytic Jacobian
(:mod:`surfinpaint.representation.coupled_jacobian`), each the same bits as its numpy
version (tested):

- :func:`kept_blocks`, the faces' 3 × 3 blocks of the unit vertex normals' and the Voronoi
  areas' derivatives that :class:`~surfinpaint.representation.coupled_jacobian.FaceBlocks`
  assembles, at its kept corner pairs only;
- :func:`update_rhs`, the dense Jacobian's right-hand side before its product with
  ``L_ff⁻¹``.

Why: every dense Jacobian of the λ-H fill's Newton steps and every Newton–Krylov step's
set-up makes the blocks, on a few hundred faces; in numpy that is dozens of calls on
(F, 3, 3, 3) temporaries, about 0.6 ms a Jacobian at 121 free vertices, a fifth of it, and
the right-hand side four passes over (m, 3, P) arrays, 0.3 ms (session 32 helper). The
kernels do the arithmetic as numpy does it, operation by operation: ``np.cross``'s products
and differences, ``np.linalg.norm``'s sums ``(x0² + x1²) + x2²``, ``np.einsum``'s three-term
dot products ``(x0 y0 + x2 y2) + x1 y1`` (its two-lane sums, as
:mod:`surfinpaint.geometry.vertex_measures` found), ``np.add.at``'s and the chain rule's sums
left to right, and no fused multiply-adds (numba does not contract without fastmath).
"""

from __future__ import annotations

import numpy as np

from surfinpaint.compiled import Kernel, run

__all__ = ["kept_blocks", "update_rhs", "warm"]


def kept_blocks(phi: np.ndarray, faces: np.ndarray, vertex_i: np.ndarray,
                face_j: tuple[np.ndarray, np.ndarray], with_free: np.ndarray,
                kept: np.ndarray, numpy_version) -> tuple[np.ndarray, np.ndarray]:
    """The normals' blocks ``P_i [p_{j+2} − p_{j+1}]×`` of the kept pairs (vertex ``i`` =
    ``vertex_i``, corner ``j`` of face ``face_j``; ``P_i = (I − u uᵀ) / |N|`` with ``N`` the
    area vector summed over ``faces`` as ``mesh_lambda_h.area_vectors`` does, u its unit)
    and the corner areas' derivatives
    (:func:`~surfinpaint.representation.coupled_jacobian._corner_area_derivative`) of the
    faces ``with_free`` at their ``kept`` (face, 9) corner pairs, both raveled in the
    numpy version's order; ``numpy_version()`` gives them while the kernel is not compiled.

    Parameters
    ----------
    phi : (n, 3) float array
    faces : (F, 3) int array
    vertex_i : (k,) int array
    face_j : pair of (k,) int arrays
        The kept pairs' faces (rows of ``faces``) and corners.
    with_free : (F,) bool array
    kept : (F', 9) bool array
        Of the faces ``with_free``, the corner pairs (3 i + j) kept.
    numpy_version : callable
    """
    args = (np.ascontiguousarray(phi, dtype=float), np.ascontiguousarray(faces, dtype=np.int64),
            np.ascontiguousarray(vertex_i, dtype=np.int64),
            np.ascontiguousarray(face_j[0], dtype=np.int64),
            np.ascontiguousarray(face_j[1], dtype=np.int64),
            np.ascontiguousarray(np.flatnonzero(with_free), dtype=np.int64),
            np.ascontiguousarray(kept, dtype=np.bool_))

    def compiled(kernel):
        normals = np.empty(9 * len(vertex_i))
        areas = np.empty(3 * int(kept.sum()))
        kernel(*args, np.zeros((len(phi), 3)), normals, areas)
        return normals, areas

    return run(_BLOCKS_KERNEL.get(), compiled, numpy_version,
               cost=1e-4 + 1.5e-6 * len(faces))


def update_rhs(dn_f: np.ndarray, n_f: np.ndarray, c: np.ndarray, u: np.ndarray,
               d_s_f: np.ndarray, alpha: np.ndarray, d_H_f: np.ndarray) -> np.ndarray:
    """The dense Jacobian's right-hand side before ``L_ff⁻¹``
    (:meth:`~surfinpaint.representation.coupled_jacobian._DenseJacobian.at`):
    ``dn_f c + n_f ⊗ q`` with ``q = u d_s_f + α d_H_f``, (m, 3, P), as numpy makes it (the
    same bits; compiled where numba is: one pass instead of four (m, 3, P) temporaries).

    Parameters
    ----------
    dn_f : (m, 3, P) float array
        The free vertices' unit normals' derivatives.
    n_f : (m, 3) float array
    c, u, alpha : (m,) float arrays
    d_s_f, d_H_f : (m, P) float arrays
    """
    args = [np.ascontiguousarray(a, dtype=float) for a in (dn_f, n_f, c, u, d_s_f, alpha, d_H_f)]

    def numpy_version():
        q = u[:, None] * d_s_f + alpha[:, None] * d_H_f
        rhs = dn_f * c[:, None, None]
        rhs += n_f[:, :, None] * q[:, None, :]
        return rhs

    def compiled(kernel):
        out = np.empty(dn_f.shape)
        kernel(*args, out)
        return out

    return run(_RHS_KERNEL.get(), compiled, numpy_version, cost=1e-5 + 2e-9 * dn_f.size)


def _rhs_loops(dn_f, n_f, c, u, d_s_f, alpha, d_H_f, out):  # pragma: no cover - compiled
    """:func:`update_rhs` element by element (compiled by numba when present)."""
    m, P = d_s_f.shape
    for i in range(m):
        for p in range(P):
            q = u[i] * d_s_f[i, p] + alpha[i] * d_H_f[i, p]
            for a in range(3):
                out[i, a, p] = dn_f[i, a, p] * c[i] + n_f[i, a] * q


def warm(vertices: np.ndarray, faces: np.ndarray) -> None:
    """Load (or compile) the kernels by one call each on a mesh's faces, every corner pair
    kept (:mod:`surfinpaint.fill.warmup`; the calls' types are a real fill's)."""
    every = np.arange(len(faces))
    kept_blocks(vertices, faces, faces[:, 0], (every, np.zeros_like(every)),
                np.ones(len(faces), dtype=bool), np.ones((len(faces), 9), dtype=bool),
                lambda: None)
    one = np.ones(len(vertices))
    update_rhs(np.ones((len(vertices), 3, 2)), vertices, one, one, np.ones((len(vertices), 2)),
               one, np.ones((len(vertices), 2)))


def _blocks_loops(phi, faces, vertex_i, face, corner, free_faces, kept, N, normals,
                  areas):  # pragma: no cover - compiled
    """:func:`kept_blocks` pair by pair and face by face (compiled by numba when present):
    the area vectors summed into the zeroed ``N`` in ``np.add.at``'s order (corner 0 of
    every face, then 1, then 2), ``normals`` (9 a pair: row a, column b) and ``areas`` (3 a
    kept corner pair)."""
    for k in range(3):
        for t in range(len(faces)):
            i0, i1, i2 = faces[t, 0], faces[t, 1], faces[t, 2]
            a0, a1, a2 = phi[i1, 0] - phi[i0, 0], phi[i1, 1] - phi[i0, 1], phi[i1, 2] - phi[i0, 2]
            b0, b1, b2 = phi[i2, 0] - phi[i0, 0], phi[i2, 1] - phi[i0, 1], phi[i2, 2] - phi[i0, 2]
            v = faces[t, k]
            N[v, 0] += a1 * b2 - a2 * b1
            N[v, 1] += a2 * b0 - a0 * b2
            N[v, 2] += a0 * b1 - a1 * b0
    P = np.empty((3, 3))
    for q in range(len(vertex_i)):
        t, j = face[q], corner[q]
        a, b = faces[t, (j + 2) % 3], faces[t, (j + 1) % 3]
        e0 = phi[a, 0] - phi[b, 0]
        e1 = phi[a, 1] - phi[b, 1]
        e2 = phi[a, 2] - phi[b, 2]
        v = vertex_i[q]
        length = np.sqrt((N[v, 0] * N[v, 0] + N[v, 1] * N[v, 1]) + N[v, 2] * N[v, 2])
        length = length if length > 0 else 1.0
        for r in range(3):
            for s in range(3):
                P[r, s] = ((1.0 if r == s else 0.0) - (N[v, r] / length) * (N[v, s] / length)
                           ) / length
        for r in range(3):
            normals[9 * q + 3 * r] = P[r, 1] * e2 - P[r, 2] * e1
            normals[9 * q + 3 * r + 1] = P[r, 2] * e0 - P[r, 0] * e2
            normals[9 * q + 3 * r + 2] = P[r, 0] * e1 - P[r, 1] * e0
    p = np.empty((3, 3))
    edge = np.empty((3, 3))  # opposite corner k: p_{k+2} − p_{k+1}
    a_, b_ = np.empty((3, 3)), np.empty((3, 3))  # p_{k+1} − p_k, p_{k+2} − p_k
    d_norm = np.empty((3, 3))  # (corner moved, coordinate)
    length2, dot = np.empty(3), np.empty(3)
    d_dot = np.empty((3, 3, 3))  # (quantity k, corner j, coordinate)
    d_len2 = np.empty((3, 3, 3))
    d_corner = np.empty((3, 3, 3))  # (corner k's area, corner j moved, coordinate)
    unit = np.empty(3)
    out = 0
    for row in range(len(free_faces)):
        t = free_faces[row]
        for k in range(3):
            for c in range(3):
                p[k, c] = phi[faces[t, k], c]
        for k in range(3):
            for c in range(3):
                edge[k, c] = p[(k + 2) % 3, c] - p[(k + 1) % 3, c]
                a_[k, c] = p[(k + 1) % 3, c] - p[k, c]
                b_[k, c] = p[(k + 2) % 3, c] - p[k, c]
        u0, u1, u2 = p[1, 0] - p[0, 0], p[1, 1] - p[0, 1], p[1, 2] - p[0, 2]
        w0, w1, w2 = p[2, 0] - p[0, 0], p[2, 1] - p[0, 1], p[2, 2] - p[0, 2]
        c0 = u1 * w2 - u2 * w1
        c1 = u2 * w0 - u0 * w2
        c2 = u0 * w1 - u1 * w0
        norm = np.sqrt((c0 * c0 + c1 * c1) + c2 * c2)
        den = norm if not norm < 1e-300 else 1e-300  # np.maximum: a NaN is kept
        unit[0], unit[1], unit[2] = c0 / den, c1 / den, c2 / den
        for k in range(3):
            x0, x1, x2 = edge[k, 0], edge[k, 1], edge[k, 2]
            d_norm[k, 0] = unit[1] * x2 - unit[2] * x1
            d_norm[k, 1] = unit[2] * x0 - unit[0] * x2
            d_norm[k, 2] = unit[0] * x1 - unit[1] * x0
            length2[k] = (x0 * x0 + x2 * x2) + x1 * x1
            dot[k] = (a_[k, 0] * b_[k, 0] + a_[k, 2] * b_[k, 2]) + a_[k, 1] * b_[k, 1]
        for k in range(3):
            for c in range(3):
                d_dot[k, (k + 1) % 3, c] = b_[k, c]
                d_dot[k, (k + 2) % 3, c] = a_[k, c]
                d_dot[k, k, c] = -(a_[k, c] + b_[k, c])
                d_len2[k, (k + 2) % 3, c] = 2.0 * edge[k, c]
                d_len2[k, (k + 1) % 3, c] = -2.0 * edge[k, c]
                d_len2[k, k, c] = 0.0
        obtuse = dot[0] < 0 or dot[1] < 0 or dot[2] < 0
        for k in range(3):
            jj, ii = (k + 2) % 3, (k + 1) % 3
            if obtuse:
                share = 0.25 if dot[k] < 0 else 0.125
                for m in range(3):
                    for c in range(3):
                        d_corner[k, m, c] = share * d_norm[m, c]
                continue
            top = length2[jj] * dot[jj] + length2[ii] * dot[ii]
            scale = 8.0 * norm
            ratio = top / (8.0 * (norm * norm))
            for m in range(3):
                for c in range(3):
                    d_top = (((length2[jj] * d_dot[jj, m, c] + dot[jj] * d_len2[jj, m, c])
                              + length2[ii] * d_dot[ii, m, c]) + dot[ii] * d_len2[ii, m, c])
                    d_corner[k, m, c] = d_top / scale - ratio * d_norm[m, c]
        for pair in range(9):
            if kept[row, pair]:
                k, m = pair // 3, pair % 3
                for c in range(3):
                    areas[out] = d_corner[k, m, c]
                    out += 1


# the normals' and the areas' blocks of a Jacobian in one pass (session 32 helper); a
# degenerate face divides by zero as numpy does (inf, NaN), not raising
_BLOCKS_KERNEL = Kernel(_blocks_loops, nogil=True, error_model="numpy")
# the dense Jacobian's right-hand side in one pass (session 32 helper)
_RHS_KERNEL = Kernel(_rhs_loops, nogil=True, error_model="numpy")
