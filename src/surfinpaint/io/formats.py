"""Reading and writing triangle meshes, keeping the file's vertices exactly as they are.

Supported formats (chosen by file extension, see :data:`SUPPORTED_FORMATS`): PLY (ascii and
binary), Wavefront OBJ, STL (ascii and binary), OFF, GIFTI (``.gii`` and gzip-compressed
``.gii.gz``) and FreeSurfer surface files (``lh.pial``, ``rh.white``, ``*.inflated``, ...;
also recognised on reading by the triangle-file magic bytes ``FF FF FE``).

Users rely on the vertices being returned untouched and in the file's order, unreferenced
vertices included: the hole filler adds vertices after them and never renumbers. The loaders
therefore never merge, drop or reorder vertices, with one exception: STL stores a triangle
soup (three separate corners per face), so exactly equal corners are merged, numbered in order
of first occurrence. Polygons (quads, n-gons) are fan-triangulated in place, with a
:class:`MeshWarning`.

PLY, OBJ, OFF and ascii STL are parsed here rather than by trimesh: with ``process=False``
trimesh still drops unreferenced OBJ vertices, splits vertices on texture seams, leaves
negative OBJ indices unresolved with ``maintain_order=True``, regroups polygon faces
(triangles first), misreads binary PLY with mixed polygon sizes, writes OBJ/OFF with ten
significant digits, and prints tracebacks on stderr for a malformed ascii STL. nibabel reads
and writes GIFTI and FreeSurfer.

One module per format family (:mod:`~surfinpaint.io.ply`, :mod:`~surfinpaint.io.obj`,
:mod:`~surfinpaint.io.off`, :mod:`~surfinpaint.io.stl`, :mod:`~surfinpaint.io.brain`); this one
picks the module by file name and checks what comes back. Writing goes through the package's
one atomic writer (:mod:`surfinpaint.io.atomic`): a failure leaves no partial output and an
existing file is either fully replaced or left as it was.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

import numpy as np

from surfinpaint.errors import MeshError
from surfinpaint.geometry.validation import check_arrays
from surfinpaint.io.atomic import atomic_open
from surfinpaint.io.base import MeshWarning, describe, triangulate
from surfinpaint.io.brain import (
    FREESURFER_MAGIC,
    read_freesurfer,
    read_gifti,
    write_freesurfer,
    write_gifti,
    write_gifti_gz,
)
from surfinpaint.io.obj import read_obj, write_obj
from surfinpaint.io.off import read_off, write_off
from surfinpaint.io.ply import read_ply, write_ply
from surfinpaint.io.stl import read_stl, warn_stl_numbering, write_stl

__all__ = ["SUPPORTED_FORMATS", "MeshWarning", "output_format", "read_mesh", "write_mesh"]

_FREESURFER_SUFFIXES = (".pial", ".white", ".inflated", ".sphere", ".orig", ".smoothwm")


#: File extensions understood by :func:`read_mesh` and :func:`write_mesh`, with a description.
SUPPORTED_FORMATS: dict[str, str] = {
    ".ply": "PLY, ascii or binary (written binary unless ascii=True)",
    ".obj": "Wavefront OBJ (v and f records)",
    ".stl": "STL, ascii or binary (a triangle soup: equal corners are merged on reading)",
    ".off": "OFF (Geomview object file format)",
    ".gii": "GIFTI surface (pointset and triangle arrays, float32)",
    ".gii.gz": "gzip-compressed GIFTI surface",
    **{s: "FreeSurfer surface (float32; also lh.*/rh.* names and FF FF FE magic)"
       for s in _FREESURFER_SUFFIXES},
}


def _format_of(path: Path) -> str | None:
    """Format key for a file name, or None when the name says nothing."""
    name = path.name.lower()
    if name.endswith(".gii.gz"):
        return "gii.gz"
    suffix = path.suffix.lower()
    if suffix in (".ply", ".obj", ".stl", ".off", ".gii"):
        return suffix[1:]
    if suffix in _FREESURFER_SUFFIXES:
        return "freesurfer"
    return None


def output_format(path: str | os.PathLike) -> str:
    """The format :func:`write_mesh` would write ``path`` in.

    Raises
    ------
    MeshError
        When the file name selects no supported format (checked before long work starts).
    """
    p = Path(path)
    fmt = _format_of(p)
    if fmt is None:
        raise _unknown_format(p)
    return fmt


def _unknown_format(path: Path) -> MeshError:
    return MeshError(
        f"unknown mesh format {''.join(path.suffixes) or '(no extension)'!r}; supported: "
        + ", ".join(SUPPORTED_FORMATS),
        path=str(path),
    )


# --------------------------------------------------------------------------------- reading


def read_mesh(path: str | os.PathLike) -> tuple[np.ndarray, np.ndarray]:
    """Read a triangle mesh, vertices exactly as stored in the file and in its order.

    Parameters
    ----------
    path : str or path-like
        A file with one of the extensions in :data:`SUPPORTED_FORMATS`. FreeSurfer surfaces
        are also recognised by their magic bytes whatever their name.

    Returns
    -------
    vertices : (n, 3) float64 array
        Every vertex of the file in file order, unreferenced ones included (STL: the distinct
        corners in order of first occurrence).
    faces : (f, 3) int64 array
        Triangles in file order; a polygon with k corners becomes k - 2 fan triangles
        ``(p0, p_i, p_i+1)`` in its place.

    Raises
    ------
    MeshError
        Naming the file, when it is missing, unreadable, empty, truncated or not a mesh of
        its format, has an unknown extension, has no vertices or no faces, has face indices
        out of range (naming faces) or non-finite coordinates (naming vertices).

    Warns
    -----
    MeshWarning
        When polygons with more than three corners were triangulated.

    Examples
    --------
    >>> vertices, faces = read_mesh("bunny.ply")  # doctest: +SKIP
    """
    p = Path(path)
    name = str(path)
    data = _read_bytes(p)
    fmt = _format_of(p)
    if data[:3] == FREESURFER_MAGIC and fmt in (None, "freesurfer"):
        fmt = "freesurfer"
    if fmt is None:
        raise _unknown_format(p)
    try:
        vertices, counts, flat = _READERS[fmt](data, p)
    except MeshError as err:
        raise err.with_path(name) from None
    except Exception as exc:  # any parser failure means a bad file
        raise MeshError(f"cannot read as {_LABELS[fmt]}: {describe(exc)}", path=name) from None
    faces = triangulate(counts, flat, name)
    check_arrays(vertices, faces, path=name)
    return vertices, faces


_LABELS = {"ply": "PLY", "obj": "OBJ", "stl": "STL", "off": "OFF", "gii": "GIFTI",
           "gii.gz": "gzip-compressed GIFTI", "freesurfer": "a FreeSurfer surface"}



def _read_bytes(p: Path) -> bytes:
    name = str(p)
    if not p.exists():
        raise MeshError("no such file", path=name)
    if p.is_dir():
        raise MeshError("is a directory, not a mesh file", path=name)
    try:
        data = p.read_bytes()
    except PermissionError:
        raise MeshError("permission denied: the file cannot be read", path=name) from None
    except OSError as exc:
        raise MeshError(f"cannot read the file: {exc.strerror or exc}", path=name) from None
    if not data:
        raise MeshError("file is empty", path=name)
    return data



_READERS: dict[str, Callable[[bytes, Path], tuple[np.ndarray, np.ndarray, np.ndarray]]] = {
    "ply": read_ply, "obj": read_obj, "off": read_off, "stl": read_stl,
    "gii": read_gifti, "gii.gz": read_gifti, "freesurfer": read_freesurfer,
}

_WRITERS = {
    "ply": write_ply, "obj": write_obj, "off": write_off, "stl": write_stl,
    "gii": write_gifti, "gii.gz": write_gifti_gz, "freesurfer": write_freesurfer,
}


# --------------------------------------------------------------------------------- writing


def write_mesh(path: str | os.PathLike, vertices: np.ndarray, faces: np.ndarray, *,
               ascii: bool = False) -> None:
    """Write a triangle mesh, atomically, in the format given by the file name.

    Parameters
    ----------
    path : str or path-like
        Target file; its extension picks the format (:data:`SUPPORTED_FORMATS`). FreeSurfer
        names (``lh.pial``, ``*.white``, ...) write a FreeSurfer surface, ``.gii.gz`` a
        gzip-compressed GIFTI.
    vertices : (n, 3) float array
        Written in the given order. OBJ, OFF and PLY keep float64 exactly (17 significant
        digits in text); STL, GIFTI and FreeSurfer store float32.
    faces : (f, 3) int array
    ascii : bool, default False
        PLY only: write ascii instead of binary little-endian. STL is always binary.

    Raises
    ------
    MeshError
        Naming the file, for an unknown extension, a missing target directory, bad arrays
        (empty, non-finite coordinates, indices out of range) or a failed write. Nothing is
        left behind on failure: the target is untouched and the temporary file removed.

    Warns
    -----
    MeshWarning
        For STL, when the vertex numbering cannot be stored (unreferenced vertices, or
        vertices not first used in index order); reading it back renumbers them.
    """
    p = Path(path)
    name = str(path)
    fmt = _format_of(p)
    if fmt is None:
        raise _unknown_format(p)
    vertices = np.asarray(vertices)
    faces = np.asarray(faces)
    check_arrays(vertices, faces, path=name)
    vertices = vertices.astype(np.float64, copy=False)
    faces = faces.astype(np.int64, copy=False)
    directory = p.parent if str(p.parent) else Path(".")
    if not directory.is_dir():
        raise MeshError(f"directory {str(directory)!r} does not exist", path=name)
    if fmt == "stl":
        warn_stl_numbering(faces, len(vertices), name)
    created = False
    try:
        with atomic_open(p) as fh:
            created = True
            _WRITERS[fmt](fh, fh.name, vertices, faces, ascii)
    except MeshError as err:
        raise err.with_path(name) from None
    except Exception as exc:
        if not created and isinstance(exc, OSError):
            raise MeshError(f"cannot create a file here: {exc.strerror or exc}",
                            path=name) from None
        raise MeshError(f"writing failed: {describe(exc)}", path=name) from None

