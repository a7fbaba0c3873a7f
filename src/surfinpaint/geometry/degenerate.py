"""Faces that use a vertex twice: no triangles. Their two edges between the same two
vertices run both ways and join nothing, so every pass over the surface's topology (edge
table, checks, holes, a fill's neighbourhood) takes the triangles only, and a fill keeps
such faces in its output as they are (docs/robustness.md, "Degenerate faces")."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from surfinpaint.geometry.mesh import vertex_faces

__all__ = ["repeated_vertex_faces", "triangle_incidence", "triangle_rows"]


def repeated_vertex_faces(faces: np.ndarray) -> np.ndarray:
    """Ids of the faces that use a vertex twice (or three times): no triangles."""
    f = np.asarray(faces, dtype=np.int64)
    return np.flatnonzero((f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 2] == f[:, 0]))


def triangle_rows(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """The faces that are triangles, the ids of those that repeat a vertex
    (:func:`repeated_vertex_faces`), and the ids of the triangles among the faces (None
    when every face is one: the triangles are then ``faces`` itself)."""
    f = np.asarray(faces)
    repeated = repeated_vertex_faces(f)
    if not repeated.size:
        return f, repeated, None
    kept = np.ones(len(f), dtype=bool)
    kept[repeated] = False
    rows = np.flatnonzero(kept)
    return f[rows], repeated, rows


def triangle_incidence(faces: np.ndarray, n_vertices: int, rows: np.ndarray | None = None,
                       *, known: bool = False) -> sp.csr_matrix:
    """The :func:`~surfinpaint.geometry.mesh.vertex_faces` incidence of the triangles among
    ``faces``, by the faces' ids: a face that repeats a vertex is in no vertex's row, so no
    neighbourhood found through it holds that face (the same matrix when there is none).
    With ``known``, ``rows`` are the triangles' ids as :func:`triangle_rows` gives them
    (None: every face), not found again."""
    if not known:
        _, _, rows = triangle_rows(faces)
    if rows is None:
        return vertex_faces(faces, n_vertices)
    incidence = vertex_faces(faces[rows], n_vertices)
    return sp.csr_matrix((incidence.data, rows[incidence.indices].astype(
        incidence.indices.dtype), incidence.indptr), shape=(n_vertices, len(faces)))
