"""Sparse direct solves shared by the parameterization, inpainting and reconstruction."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from surfinpaint.geometry.edges import stable_key_sort

__all__ = ["definite_lu", "factorized_definite", "factorized_definite_ordered",
           "factorized_ordered", "laplacian_from_weights", "nested_dissection"]


def definite_lu(A: sp.spmatrix) -> spla.SuperLU:
    """SuperLU's factors of a sparse symmetric or Hermitian definite (positive or negative)
    matrix: the minimum-degree ordering on A + Aᵀ and no pivoting, which is safe for
    definite matrices and 1.5–10× faster than SuperLU's defaults (COLAMD, partial
    pivoting) on the mesh and grid systems here (the λ-H fill's patch systems and the
    fairing systems: 0.09 -> 0.05 and 0.19 -> 0.09 s of CPU on the 651k case's ten holes,
    session 24). Small supernode relaxation and panels (relax=1, panel_size=4) measured
    another ~10 % faster on this project's grid and patch systems.

    Parameters
    ----------
    A : (n, n) sparse matrix
        Symmetric (real or complex) or Hermitian, and definite: no pivoting is needed
        (the cotangent Laplacian with fixed vertices, the stiffness matrix of linear finite
        elements, is, whatever the angles; so are ``L M⁻¹ L`` and ``L M⁻¹ L M⁻¹ L``).

    Returns
    -------
    scipy.sparse.linalg.SuperLU

    Raises
    ------
    RuntimeError
        From SuperLU, when the matrix is exactly singular.
    """
    return spla.splu(sp.csc_matrix(A), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                     options={"SymmetricMode": True}, relax=1, panel_size=4)


def factorized_definite(A: sp.spmatrix) -> Callable[[np.ndarray], np.ndarray]:
    """A solver for a sparse symmetric or Hermitian definite (positive or negative) matrix:
    :func:`definite_lu`'s ``solve``.

    Returns
    -------
    callable
        ``solve(b)`` for (n,) or (n, k) right-hand sides.

    Raises
    ------
    RuntimeError
        From SuperLU, when the matrix is exactly singular.

    Examples
    --------
    >>> A = sp.diags([2.0, 4.0])
    >>> factorized_definite(A)(np.array([2.0, 2.0])).tolist()
    [1.0, 0.5]
    """
    return definite_lu(A).solve


def nested_dissection(adjacency: sp.spmatrix, coords: np.ndarray, leaf: int = 64) -> np.ndarray:
    """A fill-reducing elimination order for a mesh's sparse matrix: geometric nested
    dissection.

    The vertices are split at the median of their widest coordinate; the vertices of the
    lower half with a neighbour in the upper half form the separator, ordered after both
    halves, which are ordered the same way until they have at most ``leaf`` vertices.
    On a 2D-like mesh this gives less fill than SuperLU's minimum degree (measured, the LSCM
    system of a 105k-vertex disk: 2.7e7 against 3.1e7 factor entries, factorization 2.4 s
    against 5.0 s of CPU; ``benchmarks/represent_speed.py --speed-only``).

    Parameters
    ----------
    adjacency : (n, n) sparse matrix
        Nonzero where two vertices share an entry of the matrix to factor.
    coords : (n, d) float array
        Vertex positions.
    leaf : int

    Returns
    -------
    (n,) int array
        The order: ``A[order][:, order]`` is the matrix to factor without reordering.
    """
    graph = (sp.csr_matrix(adjacency) != 0).astype(np.int8).tocsr()
    x = np.asarray(coords, dtype=float)
    pending = [np.arange(graph.shape[0])]
    blocks = []  # reversed: each separator, then its upper, then its lower part
    mark = np.zeros(graph.shape[0], dtype=np.int8)
    while pending:
        ids = pending.pop()
        if len(ids) <= leaf:
            blocks.append(ids)
            continue
        c = x[ids]
        axis = int(np.argmax(np.ptp(c, axis=0)))
        lower = c[:, axis] <= np.median(c[:, axis])
        if lower.all():  # all on the median: no split along this axis
            blocks.append(ids)
            continue
        mark[ids[~lower]] = 1
        touches = (graph[ids[lower]] @ mark) > 0
        mark[ids[~lower]] = 0
        blocks.append(ids[lower][touches])
        pending.append(ids[lower][~touches])
        pending.append(ids[~lower])
    return np.concatenate(blocks[::-1])


def factorized_definite_ordered(A: sp.spmatrix, order: np.ndarray
                                ) -> Callable[[np.ndarray], np.ndarray]:
    """:func:`factorized_definite` with a given elimination ``order`` (for example
    :func:`nested_dissection`'s) instead of SuperLU's minimum degree."""
    return _factorized_in_order(A, order, diag_pivot_thresh=0.0,
                                options={"SymmetricMode": True})


def factorized_ordered(A: sp.spmatrix, order: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """A solver for a general sparse square matrix with a structurally symmetric pattern,
    factored in a given elimination ``order`` (for example :func:`nested_dissection`'s)
    with SuperLU's partial pivoting (diagonal pivots preferred where they are large enough).

    Measured on the Newton Jacobian of a 105k-vertex disk's rebuild (310k unknowns, a
    vertex's three coordinates kept together): 5.4 s of CPU against 9.6 s with SuperLU's
    minimum degree on A + Aᵀ, the same solutions to 5e-14 (docs/representation.md,
    session 14).

    Raises
    ------
    RuntimeError
        From SuperLU, when the matrix is exactly singular.
    """
    return _factorized_in_order(A, order, options={"SymmetricMode": True})


def _factorized_in_order(A, order, **splu_options):
    order = np.asarray(order)
    lu = spla.splu(sp.csc_matrix(A)[order][:, order].tocsc(), permc_spec="NATURAL",
                   **splu_options)
    inverse = np.empty_like(order)
    inverse[order] = np.arange(len(order))

    def solve(b: np.ndarray) -> np.ndarray:
        return lu.solve(np.asarray(b)[order])[inverse]

    return solve


def laplacian_from_weights(i: np.ndarray, j: np.ndarray, w: np.ndarray, n: int
                           ) -> sp.csr_matrix:
    """The graph Laplacian ``W + Wᵀ − diag((W + Wᵀ) 1)`` of the weights ``W[i, j] = w``.

    The same matrix, entry for entry and bit for bit (exact zeros left out, indices sorted),
    as scipy's ``off = coo((w, (i, j))); off = off + off.T; (off - diags(off.sum(1)))``,
    assembled directly: that chain of sparse operations cost more than the weights on the
    small patches the fills and the self-check solve (about 5 ms a patch). Each
    ``(i, j)`` must appear at most once and off the diagonal (a consistently oriented
    mesh's directed edges); otherwise scipy's chain builds it.

    Parameters
    ----------
    i, j : (e,) int arrays
    w : (e,) float array
    n : int
        The matrix size.

    Returns
    -------
    (n, n) scipy.sparse.csr_matrix
    """
    i = np.asarray(i, dtype=np.int64)
    j = np.asarray(j, dtype=np.int64)
    w = np.asarray(w, dtype=float)
    e = len(i)
    key = i * n + j
    # W + Wᵀ: each key once or twice (w_ij and w_ji); a + b == b + a, so the order of the
    # two does not matter; zero sums are left out as scipy's addition leaves them out
    both = np.concatenate([key, j * n + i])
    value = np.concatenate([w, w])
    pair, both = stable_key_sort(both)  # the stable argsort and the sorted keys
    value = value[pair]
    first = np.ones(len(both), dtype=bool)
    first[1:] = both[1:] != both[:-1]
    start = np.flatnonzero(first)
    twin = np.flatnonzero(~first)
    # a repeated (i, j) shows as a key whose two entries come from the same half of
    # `both` (one sort for the check and the sums), or as a key more than twice
    from_w = pair < e
    if ((i == j).any() or (from_w[twin] == from_w[twin - 1]).any()
            or (len(twin) and (np.diff(twin) == 1).any())):
        off = sp.coo_matrix((w, (i, j)), shape=(n, n))
        off = off + off.T
        return (off - sp.diags(np.asarray(off.sum(axis=1)).ravel())).tocsr()
    total = value[start].copy()
    total[np.searchsorted(start, twin, side="right") - 1] += value[twin]
    keys = both[start]
    kept = total != 0
    keys, total = keys[kept], total[kept]
    rows, cols = keys // n, keys % n
    index = np.int32 if max(n, len(keys) + n) < np.iinfo(np.int32).max else np.int64
    indptr = np.zeros(n + 1, dtype=index)
    np.cumsum(np.bincount(rows, minlength=n), out=indptr[1:])
    sym = sp.csr_matrix((total, cols.astype(index), indptr), shape=(n, n))
    # the row sums as scipy makes them (the same call on the same matrix: same bits)
    diag = np.asarray(sym.sum(axis=1)).ravel()
    on = np.flatnonzero(diag != 0)
    # the diagonal merged into the sorted keys (no off-diagonal key equals one)
    at = np.searchsorted(keys, on * (n + 1))
    keys = np.insert(keys, at, on * (n + 1))
    value = np.insert(total, at, -diag[on])
    rows = keys // n
    np.cumsum(np.bincount(rows, minlength=n), out=indptr[1:])
    return sp.csr_matrix((value, (keys % n).astype(index), indptr), shape=(n, n))
