"""surfinpaint: fill holes in triangle meshes by conformal surface inpainting.

Lui, Wen, Gu, "A Conformal Approach for Surface Inpainting": a surface is represented by its
conformal factor λ and mean curvature H on a conformal parameter domain; a hole is filled by
inpainting λ and H and rebuilding the surface from them.
"""

from surfinpaint.errors import FillError, MeshError

__version__ = "0.1.0"

__all__ = ["FillError", "MeshError", "__version__"]
