"""A topological disk out of an open mesh such as a range scan, for the λ-H representation
(which needs a disk): the hole-filling convenience lives here, in the fill layer, because it
closes inner holes with the conventional fill."""

from __future__ import annotations

import numpy as np

from surfinpaint.fill.holes import spanned_area
from surfinpaint.fill.liepa.baseline import conventional_fill
from surfinpaint.geometry.cutting import compact
from surfinpaint.geometry.mesh import boundary_loops, connected_components, face_areas
from surfinpaint.geometry.parameterization import check_disk, pinched_vertices

__all__ = ["disk_from_mesh"]


def disk_from_mesh(vertices: np.ndarray, faces: np.ndarray, *, fill_holes: bool = True,
                   max_rounds: int = 20) -> tuple[np.ndarray, np.ndarray]:
    """Make a topological disk out of an open mesh such as a range scan.

    Keeps the largest connected component, removes the faces around pinched boundary
    vertices and slivers of zero area (repeating while that creates new ones), then closes
    every boundary loop but the one spanning the most area (the outer border, as
    :func:`~surfinpaint.fill.holes.find_holes` picks it: a scanned ring's opening can have
    more edges than its outer edge) with the conventional fill (Liepa's triangulate / refine
    / fair, :func:`surfinpaint.fill.liepa.baseline.conventional_fill`). Unused vertices are
    dropped.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        Consistently oriented, edge-manifold.
    fill_holes : bool
        Close the inner loops; otherwise a mesh with several loops raises.
    max_rounds : int
        Limit on the cleaning rounds.

    Returns
    -------
    vertices, faces
        A mesh that passes :func:`~surfinpaint.geometry.parameterization.check_disk`.

    Raises
    ------
    MeshError
        When no disk comes out (e.g. a closed mesh, or a handle), saying why.
    """
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    for _ in range(max_rounds):
        _, label = connected_components(f, len(v))
        biggest = np.argmax(np.bincount(label[f[:, 0]]))
        f = f[label[f[:, 0]] == biggest]
        area = face_areas(v, f)
        scale = float(np.ptp(v[np.unique(f)], axis=0).max())
        bad = area <= 1e-14 * scale**2
        pinched = pinched_vertices(f)
        if len(pinched):
            bad |= np.isin(f, pinched).any(axis=1)
        if not bad.any():
            break
        f = f[~bad]
    if fill_holes:
        loops = boundary_loops(f)
        border = max(range(len(loops)), key=lambda k: spanned_area(v[loops[k]]), default=0)
        for loop in loops[:border] + loops[border + 1:]:
            new_v, new_f = conventional_fill(v, f, loop)
            v = np.vstack([v, new_v])
            f = np.vstack([f, new_f])
    v, f, _ = compact(v, f)
    check_disk(v, f)
    return v, f
