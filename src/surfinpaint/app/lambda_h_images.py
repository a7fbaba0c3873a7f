"""λ and H of a conformal fill as images over its patch's parameter domain (panels D–G of
the report): as they are for the grid discretization, rasterized from the per-vertex values
of the mesh discretization."""

from __future__ import annotations

import numpy as np

from surfinpaint.fill.results import GridLambdaH, LambdaHDiagnostics, MeshLambdaH
from surfinpaint.representation.grid import grid_over, resample
from surfinpaint.representation.on_mesh import vertex_lambda_h

__all__ = ["lambda_h_images"]


def lambda_h_images(diagnostics: LambdaHDiagnostics | None,
                    resolution: int = 160) -> GridLambdaH | None:
    """The λ, H images of a conformal fill's last λ-H pass; None without any (no conformal
    fill, or nothing moved).

    "Before" (``lam0``, ``H0``) is only what the known surface says: NaN where the values
    see the initial fill (its own λ, H are not data the method uses).
    """
    if diagnostics is None:
        return None
    if diagnostics.grid is not None:
        return diagnostics.grid
    if diagnostics.mesh is None:
        return None
    return _raster(diagnostics.mesh, resolution)


def _raster(patch: MeshLambdaH, resolution: int) -> GridLambdaH:
    """Per-vertex λ, H of a parameterized patch as grid images."""
    uv, faces, free = patch.uv, patch.faces, patch.free
    lam0, H0 = vertex_lambda_h(patch.before, faces, uv)
    lam, H = vertex_lambda_h(patch.after, faces, uv)
    # before: no vertex whose Laplacian sees the fill
    touched = np.zeros(len(uv), bool)
    touched[faces[free[faces].any(axis=1)].ravel()] = True
    lam0[touched], H0[touched] = np.nan, np.nan
    grid = grid_over(uv, resolution=resolution)
    # NaN (the border, where H has no two-sided Laplacian) stays NaN: drawn grey
    sampled, inside, face_index = resample(uv, faces, np.column_stack([lam0, H0, lam, H]),
                                           grid)
    # a node is unknown "before" when any corner of its triangle is
    corner_unknown = touched[faces].any(axis=1)
    region = inside & np.where(face_index >= 0, corner_unknown[face_index], False)
    images = [np.where(inside, sampled[..., k], np.nan) for k in range(4)]
    images[0] = np.where(region, np.nan, images[0])
    images[1] = np.where(region, np.nan, images[1])
    return GridLambdaH(h=grid.h, lam0=images[0], H0=images[1], lam=images[2], H=images[3],
                       hole=inside & (face_index < patch.n_fill_faces), region=region,
                       domain=inside)
