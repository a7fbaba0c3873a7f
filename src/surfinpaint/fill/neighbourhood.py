"""The neighbourhood of a hole in a mesh being filled: the faces within some vertex rings of
its loop, among the original faces and those added by earlier holes (the cut that
:mod:`surfinpaint.fill.pipeline` hands to a hole's filler), at a cost that follows the
neighbourhood, not the mesh; and the mesh as its holes are filled (:class:`FilledMesh`: cut,
stitch, result)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from surfinpaint.errors import how_many
from surfinpaint.fill.results import Fill, FillResult, HoleReport
from surfinpaint.geometry.cutting import renumber
from surfinpaint.geometry.degenerate import triangle_incidence
from surfinpaint.geometry.rows import rows_any
from surfinpaint.geometry.validation import face_text, zero_area_faces

__all__ = ["FilledMesh", "Local", "gather_positions", "neighbourhood_faces", "zero_area_reason"]


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
    faces are sorted once, at the end). The added faces are searched only in the rings
    whose new vertices hold one: in the others the added faces at the region are those
    found before (a small hole far from the earlier fills never searches them)."""
    n_original = incidence.shape[0]
    n_all = max(n_original, int(added.max()) + 1 if len(added) else 0, int(np.max(seeds)) + 1)
    in_region = np.zeros(n_all, dtype=bool)
    face_in = np.zeros(len(faces), dtype=bool)
    vertex_stamp = np.empty(n_all, dtype=np.int64)
    face_stamp = np.empty(len(faces), dtype=np.int64)
    frontier = np.unique(seeds)
    in_region[frontier] = True
    at_added = np.zeros(n_all, dtype=bool)  # the vertices of the added faces
    at_added[added.ravel()] = True
    picked, picked_added = [], []
    # grow from the newest ring only: the faces of the older rings are already picked
    for _ in range(rings):
        new = _incident(incidence, frontier[frontier < n_original])
        new = _distinct(new[~face_in[new]], face_stamp)
        face_in[new] = True
        picked.append(new)
        grown = faces[new].ravel()
        if at_added[frontier].any():
            new_added = np.flatnonzero(rows_any(in_region[added]))
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


@dataclass
class Local:
    """The neighbourhood of one hole, cut out of the mesh filled so far."""

    loop: np.ndarray  # the hole's loop, global ids
    ids: np.ndarray  # global ids of the local vertices (sorted)
    faces_global: np.ndarray
    vertices: np.ndarray
    faces: np.ndarray  # over local ids
    local_loop: np.ndarray
    # the zero-area faces among the original faces cut out, and them in words (ids, corners)
    zero_area: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=np.int64))
    zero_area_text: str = ""


def zero_area_reason(local_vertices: np.ndarray, fill: Fill) -> str | None:
    """Why ``fill`` (over the ids of a neighbourhood of ``local_vertices``) cannot be
    stitched in: it would add zero-area triangles; None when it can."""
    new_v = np.asarray(fill.vertices, dtype=np.float64).reshape(-1, 3)
    new_f = np.asarray(fill.faces, dtype=np.int64)
    degenerate = len(zero_area_faces(np.concatenate([local_vertices, new_v]), new_f))
    if degenerate:
        triangles = how_many(degenerate, "zero-area triangle", "zero-area triangles")
        return (f"the fill would add {triangles} (the loop spans no "
                "area: a slit or a T-junction)")
    return None


class FilledMesh:
    """The mesh as its holes are filled: the original arrays, unchanged, and the blocks of
    new vertices and faces appended hole by hole."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray,
                 incidence: sp.csr_matrix | None = None,
                 zero_area: np.ndarray | None = None) -> None:
        """``incidence``: ``triangle_incidence(faces, len(vertices))`` when already made;
        ``zero_area``: the ids of the faces of zero area (sorted), named by each cut that
        holds one (:attr:`Local.zero_area`)."""
        self.vertices, self.faces = vertices, faces
        self.vertex_faces = (triangle_incidence(faces, len(vertices)) if incidence is None
                             else incidence)
        self.zero_area = np.empty(0, dtype=np.int64) if zero_area is None else zero_area
        self.vertex_blocks: list[np.ndarray] = []
        self.face_blocks: list[np.ndarray] = []
        self.n_new = 0

    def cut(self, loop: np.ndarray, rings: int) -> Local:
        """The faces within ``rings`` vertex rings of ``loop``, the earlier fills included
        (the cost stays with the hole)."""
        added = (np.concatenate(self.face_blocks) if self.face_blocks
                 else np.empty((0, 3), dtype=np.int64))
        picked, picked_added = neighbourhood_faces(self.faces, self.vertex_faces, added, loop,
                                                   rings)
        faces_global = np.concatenate([self.faces[picked], added[picked_added]])
        ids, local_faces = renumber(faces_global)
        flat = picked[np.isin(picked, self.zero_area)] if len(self.zero_area) else \
            self.zero_area
        return Local(loop=loop, ids=ids, faces_global=faces_global,
                     vertices=gather_positions(self.vertices, self.vertex_blocks, ids),
                     faces=local_faces, local_loop=np.searchsorted(ids, loop),
                     zero_area=flat, zero_area_text=face_text(flat, self.faces))

    def stitch(self, local: Local, fill: Fill) -> str | None:
        """Append ``fill`` (over ``local``'s ids); the reason when it cannot be."""
        return zero_area_reason(local.vertices, fill) or self.append(local.ids, fill)

    def append(self, ids: np.ndarray, fill: Fill) -> None:
        """Append ``fill``, made over a neighbourhood whose vertices have the global ``ids``
        (:func:`zero_area_reason` checked)."""
        new_v = np.asarray(fill.vertices, dtype=np.float64).reshape(-1, 3)
        new_f = np.asarray(fill.faces, dtype=np.int64)
        n_local = len(ids)
        mapped = np.where(new_f < n_local, ids[np.minimum(new_f, n_local - 1)],
                          len(self.vertices) + self.n_new + (new_f - n_local))
        self.vertex_blocks.append(new_v)
        self.face_blocks.append(mapped)
        self.n_new += len(new_v)

    def result(self, reports: list[HoleReport], removed_faces: np.ndarray) -> FillResult:
        vertices = np.concatenate([self.vertices, *self.vertex_blocks])
        faces = np.concatenate([self.faces, *self.face_blocks])
        return FillResult(vertices, faces, reports, len(self.vertices), len(self.faces),
                          removed_faces)
