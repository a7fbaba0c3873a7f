"""The neighbourhood of a hole in a mesh being filled: the faces within some vertex rings of
its loop, among the original faces and those added by earlier holes (the cut that
:mod:`surfinpaint.fill.pipeline` hands to a hole's filler), at a cost that follows the
neighbourhood, not the mesh."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

__all__ = ["gather_positions", "neighbourhood_faces"]


def _distinct(ids: np.ndarray, stamp: np.ndarray) -> np.ndarray:
    """The distinct values of ``ids`` (in no particular order), without a sort: each value
    keeps the one position whose index the scatter into ``stamp`` (scratch, at least
    ``ids.max() + 1`` long, contents ignored) left there."""
    at = np.arange(len(ids))
    stamp[ids] = at
    return ids[stamp[ids] == at]


def _incident(incidence: sp.csr_matrix, vertex_ids: np.ndarray) -> np.ndarray:
    """The faces at ``vertex_ids`` in the incidence of
    :func:`~surfinpaint.geometry.mesh.vertex_faces`, with repeats (as
    :func:`~surfinpaint.geometry.mesh.faces_at` before its sort)."""
    starts = incidence.indptr[vertex_ids]
    counts = incidence.indptr[vertex_ids + 1] - starts
    total = int(counts.sum())
    offsets = np.repeat(starts - np.cumsum(counts) + counts, counts) + np.arange(total)
    return incidence.indices[offsets]


def neighbourhood_faces(
    faces: np.ndarray, incidence: sp.csr_matrix, added: np.ndarray, seeds: np.ndarray,
    rings: int,
) -> tuple[np.ndarray, np.ndarray]:
    """Faces within ``rings`` vertex rings of ``seeds``: ids into the original faces and into
    the faces added by earlier holes. Cost depends on the neighbourhood, not the mesh (the
    membership masks and scratch arrays are allocated lazily: their untouched pages are
    never mapped); each ring's faces and vertices are told apart by masks, not sorts (the
    faces are sorted once, at the end)."""
    n_original = incidence.shape[0]
    n_all = max(n_original, int(added.max()) + 1 if len(added) else 0, int(np.max(seeds)) + 1)
    in_region = np.zeros(n_all, dtype=bool)
    face_in = np.zeros(len(faces), dtype=bool)
    vertex_stamp = np.empty(n_all, dtype=np.int64)
    face_stamp = np.empty(len(faces), dtype=np.int64)
    frontier = np.unique(seeds)
    in_region[frontier] = True
    picked, picked_added = [], []
    # grow from the newest ring only: the faces of the older rings are already picked
    for _ in range(rings):
        new = _incident(incidence, frontier[frontier < n_original])
        new = _distinct(new[~face_in[new]], face_stamp)
        face_in[new] = True
        picked.append(new)
        grown = faces[new].ravel()
        if len(added):
            new_added = np.flatnonzero(in_region[added].any(axis=1))
            picked_added.append(new_added)
            grown = np.concatenate([grown, added[new_added].ravel()])
        frontier = _distinct(grown[~in_region[grown]], vertex_stamp)
        if len(frontier) == 0:
            break
        in_region[frontier] = True
    empty = np.empty(0, dtype=np.int64)
    return (np.unique(np.concatenate(picked)).astype(np.int64, copy=False) if picked
            else empty,
            np.unique(np.concatenate(picked_added)) if picked_added else empty)


def gather_positions(vertices: np.ndarray, blocks: list[np.ndarray], ids: np.ndarray) -> np.ndarray:
    """Positions of ``ids`` among the original vertices followed by the added blocks."""
    n = len(vertices)
    out = np.empty((len(ids), 3))
    original = ids < n
    out[original] = vertices[ids[original]]
    if (~original).any():
        out[~original] = np.concatenate(blocks)[ids[~original] - n]
    return out
