"""surfinpaint: fill holes in triangle meshes by conformal surface inpainting.

Lui, Wen, Gu, "A Conformal Approach for Surface Inpainting": a surface is represented by its
conformal factor λ and mean curvature H on a conformal parameter domain; a hole is filled by
inpainting λ and H and rebuilding the surface from them.

The main entry points work on plain numpy arrays::

    >>> import surfinpaint
    >>> holes = surfinpaint.find_holes(vertices, faces)                  # doctest: +SKIP
    >>> result = surfinpaint.fill_holes(vertices, faces)                 # doctest: +SKIP
    >>> result.vertices, result.faces, result.reports                    # doctest: +SKIP
"""

from surfinpaint.baseline import conventional_fill
from surfinpaint.errors import FillError, MeshError
from surfinpaint.estimation import robust_lambda_h
from surfinpaint.holes import Hole, find_holes
from surfinpaint.inpainting import inpaint
from surfinpaint.io import SUPPORTED_FORMATS, MeshWarning, read_mesh, write_mesh
from surfinpaint.lambda_h import lambda_h
from surfinpaint.metrics import surface_distance
from surfinpaint.parameterization import lscm, rectangular_conformal_map
from surfinpaint.pipeline import FillResult, HoleReport, fill_holes
from surfinpaint.reconstruction import reconstruct
from surfinpaint.representation import LambdaH, rebuild, represent
from surfinpaint.validation import MeshReport, validate_mesh

__version__ = "0.1.0"

__all__ = [
    "SUPPORTED_FORMATS",
    "FillError",
    "FillResult",
    "Hole",
    "HoleReport",
    "LambdaH",
    "MeshError",
    "MeshReport",
    "MeshWarning",
    "__version__",
    "conventional_fill",
    "fill_holes",
    "find_holes",
    "inpaint",
    "lambda_h",
    "lscm",
    "read_mesh",
    "rebuild",
    "reconstruct",
    "rectangular_conformal_map",
    "represent",
    "robust_lambda_h",
    "surface_distance",
    "validate_mesh",
    "write_mesh",
]
