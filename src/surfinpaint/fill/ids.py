"""Id arrays: per-vertex or per-face integers that name an element, not a quantity.

VTK's ``vtkOriginalPointIds`` / ``vtkOriginalCellIds`` (what ``extract_cells`` and
``remove_cells`` leave), ``GlobalIds``, a ``vertex_index`` column: each value points at one
element of another mesh. A new vertex or face of a fill is no element of that mesh, so it
gets the "none" id, never an interpolated or copied one (a plausible-looking id would send
a lookup to the wrong element). The rule is the ``"id"`` kind of
:func:`surfinpaint.fill.attributes.attribute_kind`, documented there; this module holds the
name test and the none value.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ID_NAME_SUFFIXES", "is_id_name", "none_id", "none_ids"]

#: Ends of (lower-cased) names that mark an id or index array; ``Ids`` as written
#: (``vtkOriginalPointIds``, ``PedigreeIds``) too, and the names ``ids``, ``idx``. A bare
#: ``id`` is not one: as often an object's or a part's (a category, copied) as an element's.
ID_NAME_SUFFIXES = ("_ids", "-ids", ".ids", " ids", "index", "indices", "_idx")
# an index of a category (a material, a region) is a label, copied or continued, not an id
_CATEGORY_WORDS = ("material", "label", "region", "parcel", "class", "segment", "group",
                   "tissue", "part", "color", "colour")


def is_id_name(name: str) -> bool:
    """Whether ``name`` names an id or index array (see :data:`ID_NAME_SUFFIXES`).

    Examples
    --------
    >>> is_id_name("vtkOriginalPointIds"), is_id_name("vertex_ids"), is_id_name("PointIndex")
    (True, True, True)
    >>> is_id_name("material_index"), is_id_name("lipids"), is_id_name("id")
    (False, False, False)
    """
    key = name.lower()
    if any(word in key for word in _CATEGORY_WORDS):
        return False
    return (name.endswith(("Ids", "IDs")) or key in ("ids", "idx")
            or key.endswith(ID_NAME_SUFFIXES))


def none_id(dtype: np.dtype) -> int | float:
    """The "no element" value of an id array of ``dtype``: -1 for signed integers, the
    dtype's largest value for unsigned ones (-1 does not fit; ``uint32`` gives 4294967295,
    what ``numpy.uint32(-1)`` wraps to and VTK and CUDA use for "invalid"), NaN for floats.

    Raises
    ------
    ValueError
        For a dtype that holds no ids (booleans, strings).

    Examples
    --------
    >>> none_id(np.dtype(np.int64)), none_id(np.dtype(np.uint16))
    (-1, 65535)
    """
    dtype = np.dtype(dtype)
    if dtype.kind == "i":
        return -1
    if dtype.kind == "u":
        return int(np.iinfo(dtype).max)
    if dtype.kind == "f":
        return float("nan")
    raise ValueError(f"an id array must be integer or float, got {dtype}")


def none_ids(like: np.ndarray, count: int) -> np.ndarray:
    """``count`` rows of :func:`none_id`, shaped and typed like the rows of ``like``."""
    like = np.asarray(like)
    return np.full((count, *like.shape[1:]), none_id(like.dtype), dtype=like.dtype)
