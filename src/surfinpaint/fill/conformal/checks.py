"""Checks of a λ-H fill before it is accepted: finite, no degenerate triangles, no fold-over,
no intersection with the surface around it or with itself."""

from __future__ import annotations

import numpy as np

from surfinpaint.errors import FillError
from surfinpaint.geometry.intersection import patch_intersects_surroundings, self_intersections
from surfinpaint.geometry.mesh import edge_faces, face_areas, face_normals

__all__ = ["FOLD_ANGLE", "check_patch"]

# neighbouring triangles whose normals turn by more than this are a fold-over
FOLD_ANGLE = 120.0


def check_patch(vertices: np.ndarray, patch_faces: np.ndarray, n_fill_faces: int, *,
                self_crossing: bool = True, crease: np.ndarray | None = None) -> None:
    """Reject a filled patch (its first ``n_fill_faces`` faces are the fill).

    Raises
    ------
    FillError
        For non-finite positions, degenerate triangles, fold-overs (two neighbouring
        triangles, in the fill or a fill triangle and the surface next to it, whose normals
        turn by more than ``FOLD_ANGLE``, except across the ``crease`` edges), or
        intersections with the surrounding rings or (with ``self_crossing``) with itself.
    """
    fill = patch_faces[:n_fill_faces]
    if not np.isfinite(vertices[np.unique(fill)]).all():
        raise FillError("the filled patch has non-finite coordinates")
    area = face_areas(vertices, fill)
    if (area <= 1e-12 * max(float(np.median(area)), 1e-300)).any():
        raise FillError("the filled patch has degenerate triangles")
    edges, owner, count = edge_faces(patch_faces)
    normals = face_normals(vertices, patch_faces)
    two = count == 2
    checked = two & ((owner[:, 0] < n_fill_faces) | (owner[:, 1] < n_fill_faces))
    if crease is not None and len(crease):
        # a crease is meant to turn sharply
        base = int(max(edges.max(), np.max(crease))) + 1
        sharp = np.sort(np.asarray(crease, dtype=np.int64), axis=1)
        checked &= ~np.isin(edges[:, 0] * base + edges[:, 1], sharp[:, 0] * base + sharp[:, 1])
    pairs = owner[checked]
    cos = np.einsum("ij,ij->i", normals[pairs[:, 0]], normals[pairs[:, 1]])
    folds = int((cos < np.cos(np.radians(FOLD_ANGLE))).sum())
    if folds:
        raise FillError(f"the filled patch folds over at {folds} edges")
    crossing = patch_intersects_surroundings(vertices, fill, patch_faces[n_fill_faces:])
    if len(crossing):
        raise FillError(f"the filled patch cuts through the surrounding surface "
                        f"({len(crossing)} triangle pairs)")
    crossing = self_intersections(vertices, fill) if self_crossing else ()
    if len(crossing):
        raise FillError(f"the filled patch intersects itself ({len(crossing)} triangle pairs)")
