"""surfinpaint: fill holes in triangle meshes by conformal surface inpainting.

Lui, Wen, Gu, "A Conformal Approach for Surface Inpainting": a surface is represented by its
conformal factor λ and mean curvature H on a conformal parameter domain; a hole is filled by
inpainting λ and H and rebuilding the surface from them.

The main entry points work on plain numpy arrays::

    >>> import surfinpaint
    >>> holes = surfinpaint.find_holes(vertices, faces)                  # doctest: +SKIP
    >>> result = surfinpaint.fill_holes(vertices, faces)                 # doctest: +SKIP
    >>> result.vertices, result.faces, result.reports                    # doctest: +SKIP
    >>> rows = surfinpaint.fill_files(["scans/"], "filled/")              # doctest: +SKIP

With the file's colours, normals, UVs and overlays carried to the new vertices::

    >>> mesh = surfinpaint.read_mesh_data("scan.ply")                      # doctest: +SKIP
    >>> result, filled = surfinpaint.fill_mesh_data(mesh)                  # doctest: +SKIP
    >>> surfinpaint.write_mesh_data("filled.ply", filled)                  # doctest: +SKIP
"""

from surfinpaint.app.batch import FileRow, fill_files
from surfinpaint.errors import FillError, HoleWarning, MeshError
from surfinpaint.fill.conformal import ConformalOptions, GridOptions, Verdict, choose
from surfinpaint.fill.holes import Hole, find_holes
from surfinpaint.fill.liepa.baseline import conventional_fill
from surfinpaint.fill.objects import fill_mesh_data
from surfinpaint.fill.pipeline import METHODS, FillResult, HoleReport, fill_holes
from surfinpaint.fill.results import Fill
from surfinpaint.fill.seams import SlitWarning
from surfinpaint.geometry.metrics import surface_distance
from surfinpaint.geometry.parameterization import lscm, rectangular_conformal_map
from surfinpaint.geometry.validation import MeshReport, validate_mesh
from surfinpaint.io.formats import (
                                   SUPPORTED_FORMATS,
                                   MeshWarning,
                                   read_mesh,
                                   read_mesh_data,
                                   write_mesh,
                                   write_mesh_data,
)
from surfinpaint.io.meshdata import MeshData
from surfinpaint.representation.estimation import robust_lambda_h
from surfinpaint.representation.fields import lambda_h
from surfinpaint.representation.inpainting import inpaint
from surfinpaint.representation.reconstruction import reconstruct
from surfinpaint.representation.represent import LambdaH, MeshLambdaH, rebuild, represent

__version__ = "0.1.0"

__all__ = [
    "METHODS",
    "SUPPORTED_FORMATS",
    "ConformalOptions",
    "FileRow",
    "Fill",
    "FillError",
    "FillResult",
    "GridOptions",
    "Hole",
    "HoleReport",
    "HoleWarning",
    "LambdaH",
    "MeshData",
    "MeshLambdaH",
    "MeshError",
    "MeshReport",
    "MeshWarning",
    "SlitWarning",
    "Verdict",
    "__version__",
    "choose",
    "conventional_fill",
    "fill_files",
    "fill_holes",
    "fill_mesh_data",
    "find_holes",
    "inpaint",
    "lambda_h",
    "lscm",
    "read_mesh",
    "read_mesh_data",
    "rebuild",
    "reconstruct",
    "rectangular_conformal_map",
    "represent",
    "robust_lambda_h",
    "surface_distance",
    "validate_mesh",
    "write_mesh",
    "write_mesh_data",
]
