"""Whether any or all of each row of a short-rowed boolean array is True.

``mask[faces].any(axis=1)`` (the faces with a corner in a vertex set) is everywhere on the
fill's path. numpy reduces a short last axis row by row, with a loop set up per row: on
(n, 3) masks it costs 5-25 times what or-ing the three columns does (numpy 2.4: 30,000
faces 0.93 ms against 0.04 ms). These give the same booleans, column by column. The
self-check's test holes make thousands of such masks: about a tenth of a conformal fill's
CPU went to them (docs/scale.md, session 46).
"""

from __future__ import annotations

import numpy as np

__all__ = ["rows_all", "rows_any"]


def rows_any(a: np.ndarray) -> np.ndarray:
    """``a.any(axis=-1)``, column by column.

    Parameters
    ----------
    a : (..., k) array
        Truth values (any dtype: nonzero is True).

    Returns
    -------
    (...) bool array

    Examples
    --------
    >>> rows_any(np.array([[True, False, False], [False, False, False]])).tolist()
    [True, False]
    """
    return _reduced(np.logical_or, np.asarray(a), False)


def rows_all(a: np.ndarray) -> np.ndarray:
    """``a.all(axis=-1)``, column by column.

    Parameters
    ----------
    a : (..., k) array
        Truth values (any dtype: nonzero is True).

    Returns
    -------
    (...) bool array

    Examples
    --------
    >>> rows_all(np.array([[True, True], [True, False]])).tolist()
    [True, False]
    """
    return _reduced(np.logical_and, np.asarray(a), True)


def _reduced(ufunc: np.ufunc, a: np.ndarray, empty: bool) -> np.ndarray:
    """``ufunc`` over the last axis of ``a`` into a fresh bool array (``empty`` where that
    axis has length 0, as numpy's reductions give)."""
    if a.ndim == 0:
        raise ValueError("rows_any and rows_all need an array with at least one axis")
    if a.shape[-1] == 0:
        return np.full(a.shape[:-1], empty, dtype=bool)
    out = a[..., 0].astype(bool)  # a copy: the columns are combined in place
    for j in range(1, a.shape[-1]):
        ufunc(out, a[..., j], out=out)
    return out
