"""numpy's reductions over a short last axis (the 3 corners of a face, the 3 coordinates of a
point), column by column: the same numbers, several times faster.

``mask[faces].any(axis=1)`` (the faces with a corner in a vertex set) and
``np.linalg.norm(d, axis=1)`` (lengths of (n, 3) vectors) are everywhere on the fill's path.
numpy reduces a short last axis row by row, with a loop set up per row: on (n, 3) arrays it
costs 5-25 times what combining the three columns does (numpy 2.4, 30,000 rows: ``any`` 0.93
against 0.04 ms, ``norm`` of 10,000 rows 0.39 against 0.02 ms). The self-check's test holes
make thousands of such arrays: about a tenth of a conformal fill's CPU went to them
(docs/scale.md, session 46).

The booleans are the same by definition, and so are maxima and minima. A sum is the same
only in the same order: numpy adds a last axis of fewer than 8 elements left to right
(``(x0 + x1) + x2``, then the square root for a norm), as these do; with 8 or more it sums
pairwise, so these hand such rows to numpy. ``tests/test_rows.py`` checks them against
numpy bit for bit.
"""

from __future__ import annotations

import numpy as np

__all__ = ["row_cross", "row_max", "row_means", "row_min", "row_norms", "row_sums",
           "rows_all", "rows_any"]

# numpy sums a reduced axis of fewer elements than this left to right (pairwise beyond)
_LEFT_TO_RIGHT = 8


def rows_any(a: np.ndarray) -> np.ndarray:
    """``a.any(axis=-1)``: whether each row of ``a`` (..., k) has a nonzero entry (bool).

    >>> rows_any(np.array([[True, False, False], [False, False, False]])).tolist()
    [True, False]
    """
    return _folded(np.logical_or, np.asarray(a).astype(bool, copy=False), False)


def rows_all(a: np.ndarray) -> np.ndarray:
    """``a.all(axis=-1)``: whether every entry of each row of ``a`` (..., k) is nonzero.

    >>> rows_all(np.array([[True, True], [True, False]])).tolist()
    [True, False]
    """
    return _folded(np.logical_and, np.asarray(a).astype(bool, copy=False), True)


def row_max(a: np.ndarray) -> np.ndarray:
    """``a.max(axis=-1)`` (a NaN in a row gives NaN, as numpy's)."""
    return _folded(np.maximum, _nonempty(a), None)


def row_min(a: np.ndarray) -> np.ndarray:
    """``a.min(axis=-1)`` (a NaN in a row gives NaN, as numpy's)."""
    return _folded(np.minimum, _nonempty(a), None)


def row_sums(a: np.ndarray) -> np.ndarray:
    """``a.sum(axis=-1)`` of a float array, to the bit.

    >>> row_sums(np.array([[0.1, 0.2, 0.3]])).tolist() == [np.sum([0.1, 0.2, 0.3])]
    True
    """
    a = _floats(a)
    if a.shape[-1] >= _LEFT_TO_RIGHT:
        return a.sum(axis=-1)
    return _folded(np.add, a, 0.0)


def row_means(a: np.ndarray) -> np.ndarray:
    """``a.mean(axis=-1)`` of a float array, to the bit (the sum divided by the count)."""
    a = _nonempty(_floats(a))
    return np.true_divide(row_sums(a), a.shape[-1])


def row_norms(a: np.ndarray) -> np.ndarray:
    """``np.linalg.norm(a, axis=-1)``: the Euclidean length of each row, to the bit.

    >>> row_norms(np.array([[3.0, 4.0], [0.0, 0.0]])).tolist()
    [5.0, 0.0]
    """
    a = _floats(a)
    if a.shape[-1] >= _LEFT_TO_RIGHT:
        return np.linalg.norm(a, axis=-1)
    squares = _folded(np.add, a * a, 0.0)
    return np.sqrt(squares, out=squares)


def row_cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.cross(a, b)`` of (..., 3) arrays, by the same products and differences in the
    same order (the same bits), without its axis handling (most of its time on the
    self-check's small arrays: 28 against 5 us for 50 rows).

    >>> row_cross(np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]])).tolist()
    [[0.0, 0.0, 1.0]]
    """
    a, b = np.asarray(a), np.asarray(b)
    if a.shape[-1:] != (3,) or b.shape[-1:] != (3,):
        raise ValueError(f"row_cross needs rows of 3, got shapes {a.shape} and {b.shape}")
    out = np.empty(np.broadcast_shapes(a.shape, b.shape), np.result_type(a, b))
    for k in range(3):  # out_k = a_i b_j - a_j b_i, as np.cross computes it
        i, j = (k + 1) % 3, (k + 2) % 3
        np.multiply(a[..., i], b[..., j], out=out[..., k])
        out[..., k] -= a[..., j] * b[..., i]
    return out


def _floats(a) -> np.ndarray:
    """``a`` as the floats numpy's norm and sums reduce (integers and booleans as float64)."""
    a = np.asarray(a)
    return a if np.issubdtype(a.dtype, np.inexact) else a.astype(float)


def _nonempty(a) -> np.ndarray:
    a = np.asarray(a)
    if a.ndim and a.shape[-1] == 0:
        raise ValueError("zero-size rows have no maximum, minimum or mean")
    return a


def _folded(ufunc: np.ufunc, a: np.ndarray, empty) -> np.ndarray:
    """``ufunc`` folded left to right over the last axis of ``a`` into a fresh array
    (``empty`` where that axis has length 0, as numpy's reductions give)."""
    if a.ndim == 0:
        raise ValueError("a reduction over rows needs an array with at least one axis")
    if a.shape[-1] == 0:
        return np.full(a.shape[:-1], empty, dtype=a.dtype)
    out = a[..., 0].copy()  # the columns are combined in place, not in the input
    for j in range(1, a.shape[-1]):
        ufunc(out, a[..., j], out=out)
    return out
