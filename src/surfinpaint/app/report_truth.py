"""The ground truth of each hole of a mesh cut from a complete one (``surfinpaint report
--truth``): the removed patch each fill is measured against."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy.spatial import cKDTree

from surfinpaint.errors import MeshError
from surfinpaint.geometry.cutting import compact
from surfinpaint.geometry.mesh import connected_components

__all__ = ["hole_truths"]


def hole_truths(vertices: np.ndarray, faces: np.ndarray, loops: Sequence[np.ndarray],
                truth_vertices: np.ndarray,
                truth_faces: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """The patch of a complete mesh that fills each hole of a mesh cut from it.

    The holed mesh's vertices are found among the truth's by position; the truth faces that
    the holed mesh lacks are grouped into connected pieces, and each hole gets the piece
    through its boundary vertices.

    Returns
    -------
    list of (vertices, faces) or None
        One truth patch per hole; None for a hole the truth has as well.

    Raises
    ------
    MeshError
        When a boundary vertex of a hole is not a vertex of the truth (the truth must be the
        mesh the holes were cut from).
    """
    tv = np.asarray(truth_vertices, float)
    tf = np.asarray(truth_faces, np.int64)
    scale = float(np.ptp(tv, axis=0).max()) or 1.0
    dist, match = cKDTree(tv).query(np.asarray(vertices, float))
    found = dist <= 1e-6 * scale
    used = np.unique(np.asarray(faces))
    if not found[used].any():
        raise MeshError("none of the mesh's vertices is a vertex of the truth: --truth must "
                        "be the complete mesh the holes were cut from")
    missing = [int(v) for loop in loops for v in loop if not found[v]]
    if missing:
        raise MeshError("boundary vertices of the holes are not vertices of the truth mesh "
                        "(--truth must be the mesh the holes were cut from)",
                        vertices=missing[:20])
    # faces of the holed mesh in truth ids; faces with an unmatched vertex match nothing
    mapped = np.sort(np.where(found[faces], match[faces], -1), axis=1)
    key = np.sort(tf, axis=1)
    base = len(tv) + 1
    if base < 2**20:  # one int64 code per face
        present = np.unique(((mapped[:, 0] * base) + mapped[:, 1]) * base + mapped[:, 2])
        codes = (key[:, 0] * base + key[:, 1]) * base + key[:, 2]
        absent = tf[~np.isin(codes, present)]
    else:  # codes would overflow
        known = set(map(tuple, mapped.tolist()))
        absent = tf[np.array([tuple(k) not in known for k in key.tolist()], bool)]
    _, label = connected_components(absent, len(tv))
    out = []
    for loop in loops:
        pieces = np.unique(label[match[loop]])
        piece_faces = absent[np.isin(label[absent[:, 0]], pieces)] if len(absent) else absent
        # a hole the truth has too (a scanner's own hole) has no truth: None
        out.append(compact(tv, piece_faces)[:2] if len(piece_faces) else None)
    return out
