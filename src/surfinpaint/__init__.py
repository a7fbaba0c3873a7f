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

import importlib

# the public names, imported at their first use (PEP 562): `import surfinpaint` alone then
# costs no submodule, and a fill run from the CLI imports only what it uses (a faired fill
# none of the representation, the λ-H fill or the batch runner; docs/scale.md, session 14)
_EXPORTS = {
    "FileRow": "surfinpaint.app.batch",
    "FileRows": "surfinpaint.app.batch",
    "fill_files": "surfinpaint.app.batch",
    "before_after": "surfinpaint.app.figures",
    "before_after_figure": "surfinpaint.app.figures",
    "FillError": "surfinpaint.errors",
    "HoleWarning": "surfinpaint.errors",
    "MeshError": "surfinpaint.errors",
    "InputError": "surfinpaint.errors",
    "ConformalOptions": "surfinpaint.fill.conformal",
    "GridOptions": "surfinpaint.fill.conformal",
    "Verdict": "surfinpaint.fill.conformal",
    "choose": "surfinpaint.fill.conformal",
    "Hole": "surfinpaint.fill.holes",
    "find_holes": "surfinpaint.fill.holes",
    "conventional_fill": "surfinpaint.fill.liepa.baseline",
    "fill_mesh_data": "surfinpaint.fill.objects",
    "METHODS": "surfinpaint.fill.pipeline",
    "FillResult": "surfinpaint.fill.pipeline",
    "HoleReport": "surfinpaint.fill.pipeline",
    "fill_holes": "surfinpaint.fill.pipeline",
    "Fill": "surfinpaint.fill.results",
    "SlitWarning": "surfinpaint.fill.seams",
    "SurfaceDistance": "surfinpaint.geometry.metrics",
    "surface_distance": "surfinpaint.geometry.metrics",
    "lscm": "surfinpaint.geometry.parameterization",
    "rectangular_conformal_map": "surfinpaint.geometry.parameterization",
    "MeshReport": "surfinpaint.geometry.validation",
    "validate_mesh": "surfinpaint.geometry.validation",
    "SUPPORTED_FORMATS": "surfinpaint.io.formats",
    "MeshWarning": "surfinpaint.io.formats",
    "DataNotReturnedWarning": "surfinpaint.io.formats",
    "read_mesh": "surfinpaint.io.formats",
    "read_mesh_data": "surfinpaint.io.formats",
    "write_mesh": "surfinpaint.io.formats",
    "write_mesh_data": "surfinpaint.io.formats",
    "MeshData": "surfinpaint.io.meshdata",
    "robust_lambda_h": "surfinpaint.representation.estimation",
    "lambda_h": "surfinpaint.representation.fields",
    "inpaint": "surfinpaint.representation.inpainting",
    "reconstruct": "surfinpaint.representation.reconstruction",
    "LambdaH": "surfinpaint.representation.represent",
    "MeshLambdaH": "surfinpaint.representation.represent",
    "QuadtreeLambdaH": "surfinpaint.representation.represent",
    "grid_export": "surfinpaint.representation.exports",
    "load_representation": "surfinpaint.representation.represent",
    "quadtree_export": "surfinpaint.representation.exports",
    "rebuild": "surfinpaint.representation.represent",
    "resampled_export": "surfinpaint.representation.exports",
    "represent": "surfinpaint.representation.represent",
}


__version__ = "0.1.0"

__all__ = [
    "METHODS",
    "SUPPORTED_FORMATS",
    "ConformalOptions",
    "DataNotReturnedWarning",
    "FileRow",
    "FileRows",
    "Fill",
    "FillError",
    "FillResult",
    "GridOptions",
    "Hole",
    "HoleReport",
    "HoleWarning",
    "InputError",
    "LambdaH",
    "MeshData",
    "MeshLambdaH",
    "MeshError",
    "MeshReport",
    "MeshWarning",
    "QuadtreeLambdaH",
    "SlitWarning",
    "SurfaceDistance",
    "Verdict",
    "__version__",
    "choose",
    "conventional_fill",
    "fill_files",
    "fill_holes",
    "fill_mesh_data",
    "find_holes",
    "grid_export",
    "inpaint",
    "lambda_h",
    "load_representation",
    "lscm",
    "quadtree_export",
    "read_mesh",
    "read_mesh_data",
    "rebuild",
    "reconstruct",
    "rectangular_conformal_map",
    "represent",
    "resampled_export",
    "robust_lambda_h",
    "surface_distance",
    "validate_mesh",
    "write_mesh",
    "write_mesh_data",
]


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'surfinpaint' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # once: the next look-up is a plain attribute
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
