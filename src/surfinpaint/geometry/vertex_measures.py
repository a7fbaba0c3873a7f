"""The area-weighted vertex normals and the Voronoi vertex areas of a mesh from one pass over
its corners: the same bits as :func:`surfinpaint.geometry.mesh.vertex_normals` and
:func:`~surfinpaint.geometry.mesh.vertex_areas` (tested), in about a third of their time.

Why: the λ-H fill's lagged solve takes both at every residual of its Newton steps, on a few
hundred faces, where the two calls' dozens of small gathers, ``np.cross`` and ``np.add.at``
were most of a solve (session 30). The arithmetic is theirs, reordered only where IEEE
rounding is symmetric: ``p_j − p_i = −(p_i − p_j)`` and a product or sum of negated terms is
the negated one, exactly; ``np.bincount`` adds in the order ``np.add.at`` did.

Compiled (:func:`_measures_loops`, the same operations face by face and the sums in
``np.bincount``'s order: the same bits, tested) it is about a tenth again: the lagged solves
call it hundreds of times a hole (session 30)."""

from __future__ import annotations

import numpy as np

from surfinpaint.compiled import Kernel, run
from surfinpaint.geometry.rows import rows_any

__all__ = ["vertex_normals_and_areas"]


def vertex_normals_and_areas(vertices: np.ndarray, faces: np.ndarray
                             ) -> tuple[np.ndarray, np.ndarray]:
    """``(vertex_normals(vertices, faces), vertex_areas(vertices, faces))`` of a 3D mesh:
    (n, 3) unit normals (zero at unreferenced vertices) and (n,) mixed Voronoi areas."""
    v = np.ascontiguousarray(vertices, dtype=float)
    f = np.ascontiguousarray(faces, dtype=np.int64)
    return run(_MEASURES_KERNEL.get(), lambda kernel: _compiled(kernel, v, f),
               lambda: _measures_numpy(v, f), cost=2e-4 + 1e-6 * len(f))


def _compiled(kernel, v, f):
    normals, areas = np.zeros(v.shape), np.zeros(len(v))
    kernel(v, f, np.empty((len(f), 3)), np.empty((len(f), 3)), normals, areas)
    return normals, areas


def _measures_numpy(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`vertex_normals_and_areas` in numpy (the kernel's reference)."""
    n = len(v)
    p = v[f]  # (f, corner, 3)
    A = np.empty_like(p)  # A_k = p_{k+1} − p_k; corner k's other edge is p_{k+2} − p_k = −A_{k+2}
    np.subtract(p[:, 1:], p[:, :2], out=A[:, :2])
    np.subtract(p[:, 0], p[:, 2], out=A[:, 2])
    R = A[:, [2, 0, 1]]
    dot = -np.einsum("fkc,fkc->fk", A, R)  # (p_{k+1} − p_k) · (p_{k+2} − p_k)
    x = A[..., 1] * R[..., 2] - A[..., 2] * R[..., 1]  # −(a × b) per corner, (f, 3) each
    y = A[..., 2] * R[..., 0] - A[..., 0] * R[..., 2]
    z = A[..., 0] * R[..., 1] - A[..., 1] * R[..., 0]
    cot = dot / np.maximum(np.sqrt(x * x + y * y + z * z), 1e-300)
    cross = [-x[:, 0], -y[:, 0], -z[:, 0]]  # (p1 − p0) × (p2 − p0): mesh.face_cross
    ids = f.T.ravel()
    N = np.column_stack([np.bincount(ids, np.tile(c, 3), minlength=n) for c in cross])
    norm = np.sqrt(N[:, 0] * N[:, 0] + N[:, 1] * N[:, 1] + N[:, 2] * N[:, 2])[:, None]
    normals = np.divide(N, norm, out=np.zeros(N.shape), where=norm > 0)
    area = 0.5 * np.sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2])
    # the squared length of the edge opposite corner k, A_{k+1}, as mesh.edge_lengths ** 2
    length2 = np.sqrt(A[..., 0] * A[..., 0] + A[..., 1] * A[..., 1] + A[..., 2] * A[..., 2]
                      )[:, [1, 2, 0]] ** 2
    corner = (length2[:, [2, 0, 1]] * cot[:, [2, 0, 1]]
              + length2[:, [1, 2, 0]] * cot[:, [1, 2, 0]]) / 8.0
    obtuse = cot < 0
    any_obtuse = rows_any(obtuse)
    corner[any_obtuse] = np.where(obtuse[any_obtuse], area[any_obtuse, None] / 2,
                                  area[any_obtuse, None] / 4)
    return normals, np.bincount(ids, corner.T.ravel(), minlength=n).astype(float, copy=False)


def _measures_loops(v, f, cross, corner, normals, areas):  # pragma: no cover - compiled
    """:func:`_measures_numpy` face by face, compiled by numba when present: each face's
    cross product (into ``cross``) and corner areas (``corner``), then the sums into the
    zeroed ``normals`` and ``areas`` in ``np.bincount``'s order (corner 0 of every face,
    then corner 1, then corner 2), then the normals made unit."""
    A = np.empty((3, 3))  # A_k = p_{k+1} − p_k
    cot, length2 = np.empty(3), np.empty(3)  # length2: of the edge opposite corner k, A_{k+1}
    for t in range(len(f)):
        for c in range(3):
            p0, p1, p2 = v[f[t, 0], c], v[f[t, 1], c], v[f[t, 2], c]
            A[0, c] = p1 - p0
            A[1, c] = p2 - p1
            A[2, c] = p0 - p2
        for k in range(3):
            r = (k + 2) % 3  # R_k = A_{k+2}
            # einsum's order (its two-lane sums: (x0 + x2) + x1), measured to be bit-equal
            dot = -((A[k, 0] * A[r, 0] + A[k, 2] * A[r, 2]) + A[k, 1] * A[r, 1])
            x = A[k, 1] * A[r, 2] - A[k, 2] * A[r, 1]
            y = A[k, 2] * A[r, 0] - A[k, 0] * A[r, 2]
            z = A[k, 0] * A[r, 1] - A[k, 1] * A[r, 0]
            size = np.sqrt(x * x + y * y + z * z)
            cot[k] = dot / (size if not size < 1e-300 else 1e-300)  # np.maximum: NaN kept
            if k == 0:
                cross[t, 0], cross[t, 1], cross[t, 2] = -x, -y, -z
        area = 0.5 * np.sqrt(cross[t, 0] * cross[t, 0] + cross[t, 1] * cross[t, 1]
                             + cross[t, 2] * cross[t, 2])
        for k in range(3):
            e = (k + 1) % 3
            s = np.sqrt(A[e, 0] * A[e, 0] + A[e, 1] * A[e, 1] + A[e, 2] * A[e, 2])
            length2[k] = s * s
        obtuse = cot[0] < 0 or cot[1] < 0 or cot[2] < 0
        for k in range(3):
            if obtuse:
                corner[t, k] = area / 2 if cot[k] < 0 else area / 4
            else:
                j, i = (k + 2) % 3, (k + 1) % 3
                corner[t, k] = (length2[j] * cot[j] + length2[i] * cot[i]) / 8.0
    for k in range(3):
        for t in range(len(f)):
            i = f[t, k]
            normals[i, 0] += cross[t, 0]
            normals[i, 1] += cross[t, 1]
            normals[i, 2] += cross[t, 2]
    for k in range(3):
        for t in range(len(f)):
            areas[f[t, k]] += corner[t, k]
    for i in range(len(normals)):
        norm = np.sqrt(normals[i, 0] * normals[i, 0] + normals[i, 1] * normals[i, 1]
                       + normals[i, 2] * normals[i, 2])
        if norm > 0:
            normals[i, 0] /= norm
            normals[i, 1] /= norm
            normals[i, 2] /= norm
        else:
            normals[i, 0] = normals[i, 1] = normals[i, 2] = 0.0


# a few hundred faces' dozens of numpy calls (0.3 ms) in one pass (session 30)
_MEASURES_KERNEL = Kernel(_measures_loops, nogil=True)
