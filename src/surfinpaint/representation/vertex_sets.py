"""The vertex sets of the coupled λ-H solve on the mesh
(:class:`surfinpaint.representation.on_mesh._CoupledSystem`) around the free vertices, and the
error raised where its biharmonic stencil reaches a border that is not a natural one (moved
here from ``on_mesh`` in session 30, unchanged)."""

from __future__ import annotations

import numpy as np

from surfinpaint.errors import FillError

__all__ = ["ThinPatchError", "coupled_vertex_sets"]


class ThinPatchError(FillError):
    """The biharmonic stencil around the free vertices reaches the patch's border, which
    is not a natural one."""


def coupled_vertex_sets(A, f, border, on_natural):
    """The vertex sets of the coupled solve around the free vertices ``f`` on the mesh of
    adjacency ``A``: ``reach`` (fixed vertices sharing a face with a free one), ``crease``
    (those of the biharmonic stencil, two edges, on a natural border), ``tied`` (``reach``
    off it), ``U`` (the unknown H: ``f`` and ``crease``) and ``stencil`` (the rest: H data).

    H at the tied vertices is tied to φ; H further out is data, which must not be on the
    border. On a natural border (a crease, the surface's own border) H near the free
    vertices is unknown instead. Not L's nonzeros: λ, the normal and H at a vertex move with
    every vertex of its faces, also one that a zero cotangent weight leaves out of L.
    """
    # sets of vertex ids as masks over the patch (the same sorted ids as set operations)
    n = A.shape[0]
    in_f = np.isin(np.arange(n), f)
    reach = _ids(n, A[f].indices, np.intp, ~in_f)
    two = (A @ A + A).tocsr()  # int32: no count wraps to zero
    crease = _ids(n, two[f].indices, two.indices.dtype, ~in_f & on_natural)
    tied = reach[~on_natural[reach]]
    U = np.concatenate([f, crease])
    known = in_f.copy()
    known[crease] = known[tied] = True  # U and tied
    stencil = _ids(n, two[U].indices, two.indices.dtype, ~known)
    outer = np.isin(np.arange(n), border[~on_natural[border]])
    if outer[stencil].any() or outer[tied].any():
        raise ThinPatchError("the patch is too thin around the hole: the biharmonic "
                             "stencil reaches its border")
    return reach, crease, tied, U, stencil


def _ids(n: int, ids: np.ndarray, dtype, where: np.ndarray) -> np.ndarray:
    """The distinct ``ids`` (below ``n``) at which ``where`` holds, sorted, as ``dtype``."""
    mask = np.zeros(n, dtype=bool)
    mask[ids] = True
    return np.flatnonzero(mask & where).astype(dtype, copy=False)
