"""λ and H at the vertices of a conformally mapped mesh (method.md §1, §8), and the vertices
on a mesh's border (moved out of :mod:`surfinpaint.representation.on_mesh`, whose coupled
system takes the border too)."""

from __future__ import annotations

import numpy as np

from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.geometry.mesh import (
    boundary_loops,
    laplacian_and_areas,
    vertex_areas,
    vertex_normals,
)

__all__ = ["border_vertices", "vertex_lambda_h"]


def vertex_lambda_h(points: np.ndarray, faces: np.ndarray, uv: np.ndarray
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Conformal factor λ and mean curvature H at the vertices of a conformally mapped mesh.

    Parameters
    ----------
    points : (n, 3) float array
        Vertex positions.
    faces : (f, 3) int array
        Triangles, counter-clockwise in the parameter plane.
    uv : (n, 2) float array
        A conformal map of the mesh (e.g. :func:`surfinpaint.geometry.parameterization.lscm`).

    Returns
    -------
    lam, H : (n,) float arrays
        ``λ = sqrt(A_3D / A_uv)`` (Voronoi areas) and ``H = n · Δ_uv φ / (2λ²)`` with ``n``
        the area-weighted vertex normal (``φ_u × φ_v``, method.md §1: H = +1 on the unit
        sphere whose normal points inward). H is NaN on the mesh's border, where the
        Laplacian is one-sided.
    """
    L, area_uv = laplacian_and_areas(uv, faces)
    lam2 = vertex_areas(points, faces) / area_uv
    normals = vertex_normals(points, faces)
    H = np.einsum("ij,ij->i", L @ points, normals) / (2.0 * lam2 * area_uv)
    H[border_vertices(faces)] = np.nan
    return np.sqrt(lam2), H


def border_vertices(faces: np.ndarray, table: EdgeTable | None = None) -> np.ndarray:
    """The vertices of the border loops of ``faces``, loop after loop (``table``: the faces'
    :class:`~surfinpaint.geometry.edges.EdgeTable`, when made)."""
    loops = boundary_loops(faces, table)
    return np.concatenate(loops) if loops else np.zeros(0, dtype=np.int64)
