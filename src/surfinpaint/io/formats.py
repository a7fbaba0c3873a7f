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
significant digits, and prints tracebacks on stderr for a malformed ascii STL. nibabel
reads and writes GIFTI and FreeSurfer. :func:`check_file` checks a file's header alone
(:mod:`~surfinpaint.io.filetypes`: with the format by name, the bytes read and a reader's
errors worded, which the readers here share).

One module per format family (:mod:`~surfinpaint.io.ply`, :mod:`~surfinpaint.io.obj`,
:mod:`~surfinpaint.io.off`, :mod:`~surfinpaint.io.stl`, :mod:`~surfinpaint.io.brain`); this one
picks the module by file name and checks what comes back. Writing goes through the package's
one atomic writer (:mod:`surfinpaint.io.atomic`): a failure leaves no partial output and an
existing file is either fully replaced or left as it was.
"""

from __future__ import annotations

import contextlib
import os
import warnings
from collections.abc import Callable, Mapping, Sequence
from contextlib import ExitStack
from pathlib import Path
from typing import IO

import numpy as np

from surfinpaint.errors import MeshError, agreeing, how_many
from surfinpaint.geometry.validation import check_arrays
from surfinpaint.io.atomic import atomic_open
from surfinpaint.io.base import (
    DataNotReturnedWarning,
    MeshWarning,
    Parsed,
    describe,
    ids,
    triangulate,
)
from surfinpaint.io.brain import (
    overlay_outputs,
    overlays_beside,
    read_freesurfer,
    read_gifti,
    read_overlays,
    subject_overlays,
    unstored_brain,
    unstored_freesurfer,
    write_freesurfer,
    write_gifti,
    write_gifti_gz,
)
from surfinpaint.io.brain_checks import FREESURFER_MAGIC
from surfinpaint.io.filetypes import (
    SUPPORTED_FORMATS,
    ascii_like,
    check_file,
    format_of,
    format_read,
    output_format,
    parsing,
    read_bytes,
    unknown_format,
)
from surfinpaint.io.meshdata import MeshData, per_vertex, seam_vertices
from surfinpaint.io.obj import missing_libraries, read_obj, unstored_obj, write_obj
from surfinpaint.io.off import read_off, unstored_off, write_off
from surfinpaint.io.ply import read_ply, unstored_ply, write_ply
from surfinpaint.io.stl import read_stl, unstored_stl, warn_stl_numbering, write_stl

__all__ = ["SUPPORTED_FORMATS", "DataNotReturnedWarning", "MeshData", "MeshWarning",
           "ascii_like", "check_file", "files_read", "files_written", "output_format",
           "overlays_with", "read_mesh", "read_mesh_data", "write_mesh", "write_mesh_data"]

# --------------------------------------------------------------------------------- reading


def read_mesh(path: str | os.PathLike, *,
              data_warning: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Read a triangle mesh, vertices exactly as stored in the file and in its order.

    Parameters
    ----------
    path : str or path-like
        A file with one of the extensions in :data:`SUPPORTED_FORMATS`. FreeSurfer surfaces
        are also recognised by their magic bytes whatever their name.
    data_warning : bool, optional
        Warn (:class:`DataNotReturnedWarning`) naming the per-vertex, per-face or per-corner
        data the file carries, which this function does not return. False for a caller that
        writes no mesh from what it reads (listing holes, drawing pictures), where nothing
        is lost; the other warnings stay.

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
        When polygons with more than three corners were triangulated, or the file holds what
        no reader carries.
    DataNotReturnedWarning
        A :class:`MeshWarning` naming the per-vertex, per-face or per-corner data the file
        carries, which this function does not return (:func:`read_mesh_data` does); not with
        ``data_warning=False``.

    Examples
    --------
    >>> vertices, faces = read_mesh("bunny.ply")  # doctest: +SKIP
    """
    mesh, dropped, _ = _read(path, overlays=False)
    carried = [f"{kind} {', '.join(arrays)}" for kind, arrays in (
        ("per-vertex", mesh.attributes), ("per-face", mesh.face_attributes),
        ("per-corner", mesh.corner_attributes)) if arrays]
    for message in dropped:
        warnings.warn(f"{path}: {message}", MeshWarning, stacklevel=2)
    if carried and data_warning:
        warnings.warn(f"{path}: {'; '.join(carried)} not returned by read_mesh "
                      "(read_mesh_data keeps them)", DataNotReturnedWarning, stacklevel=2)
    return mesh.vertices, mesh.faces


def read_mesh_data(path: str | os.PathLike, *,
                   overlays: bool | Sequence[str | os.PathLike] = True) -> MeshData:
    """Read a mesh with its per-vertex, per-face and per-corner data and file metadata.

    What each format carries, under which names (see :mod:`surfinpaint.io.meshdata`):

    - PLY: every vertex and face property of any name and type, types kept (``red green
      blue [alpha]`` -> ``color``, ``nx ny nz`` -> ``normal``, ``u v`` -> ``uv``, ``s t`` ->
      ``st``, ``texture_u texture_v`` -> ``texture_uv``, ``q_0 .. q_k`` -> ``q``); per-corner
      face lists (``texcoord``) as corner data; comments as metadata.
    - OFF / COFF / NOFF / STOFF: vertex ``normal``, ``color`` (uint8 when integral, else
      float), ``uv``; face ``color``.
    - OBJ: ``vt`` -> ``uv``, ``vn`` -> ``normal``, ``v x y z r g b`` -> ``color`` (float).
      Per vertex when each vertex has one value on all its corners; where a vertex has
      several (a UV seam) the data is kept per corner and a :class:`MeshWarning` says so.
      ``o``, ``g``, ``usemtl`` -> face labels ``object``, ``group``, ``material``;
      ``mtllib`` -> metadata.
    - STL: a binary STL's non-zero 16-bit facet attributes -> face ``stl_attribute``.
    - GIFTI / FreeSurfer: extra per-vertex data arrays of the GIFTI file and overlays beside
      the surface (see ``overlays``); GIFTI metadata.

    Parameters
    ----------
    path : str or path-like
        As for :func:`read_mesh`.
    overlays : bool or sequence of paths, default True
        GIFTI and FreeSurfer surfaces only. True: read the overlays found beside the surface
        (:func:`surfinpaint.io.brain.overlays_beside`: ``SURFACE.NAME.shape.gii`` /
        ``.func.gii`` / ``SURFACE.NAME``, and FreeSurfer's ``lh.curv``, ``lh.thickness``,
        ``lh.sulc``, ... beside a FreeSurfer surface ``lh.*``, not a GIFTI one); False:
        none; or the overlay files to read, each a GIFTI data file or a FreeSurfer
        morphometry file with one value per vertex.

    Returns
    -------
    MeshData
        Unpacks as ``vertices, faces`` exactly as :func:`read_mesh` returns them.

    Raises
    ------
    MeshError
        As :func:`read_mesh`; and for an overlay that cannot be read or does not have one
        value per vertex (naming the overlay file).

    Warns
    -----
    MeshWarning
        Naming everything the file holds that is not carried (other PLY elements, PLY list
        properties of vertices, OBJ smoothing groups and lines, GIFTI arrays of another size,
        ...),
        and per-corner data kept per corner at UV seams.
    """
    mesh, dropped, seams = _read(path, overlays=overlays)
    for message in dropped + seams:
        warnings.warn(f"{path}: {message}", MeshWarning, stacklevel=2)
    return mesh


def _read(path: str | os.PathLike, *, overlays: bool | Sequence
          ) -> tuple[MeshData, list[str], list[str]]:
    """The mesh, what the file holds that is not carried, and the notes on seams."""
    p = Path(path)
    name = str(path)
    data = read_bytes(p)
    fmt = format_read(p, data)
    with parsing(fmt, name):
        parsed = _READERS[fmt](data, p)
    flat = np.asarray(parsed.flat, dtype=np.int64)
    counts = np.asarray(parsed.counts)
    if len(counts) and counts.min() == 3 == counts.max() and len(flat) == 3 * len(counts):
        # all triangles: the faces are the flat list in order (a view when the parser's list
        # is our own writable array), and no corner or owner index is made (651k case: the
        # read 0.101 -> 0.076 s with the PLY reader's single conversion of the face list)
        corners = owner = None
        faces = flat.reshape(-1, 3) if flat.flags.writeable else flat.reshape(-1, 3).copy()
    else:
        corners, owner = triangulate(counts, name)
        faces = flat[corners]
    check_arrays(parsed.vertices, faces, path=name)
    mesh, seams = _assemble(parsed, corners, owner, faces)
    dropped = list(parsed.dropped)
    files = _overlay_files(p, fmt, overlays)
    if files is not None:
        guessed = subject_overlays(p, fmt) if overlays is True else ()
        extra, tables, lost = read_overlays(files, len(mesh.vertices), p, guessed=guessed)
        dropped += lost
        mesh = MeshData(mesh.vertices, mesh.faces, {**mesh.attributes, **extra},
                        mesh.face_attributes, mesh.corner_attributes,
                        {**mesh.metadata, **tables})
    return mesh, dropped, seams


def _overlay_files(path: Path, fmt: str, overlays: bool | Sequence) -> list[Path] | None:
    """The overlay files read with a surface of format ``fmt``: None for a format that has
    none (or ``overlays=False``)."""
    if overlays is False or fmt not in ("gii", "gii.gz", "freesurfer"):
        return None
    return overlays_beside(path, fmt) if overlays is True else [Path(o) for o in overlays]


def files_read(path: str | os.PathLike, *,
               overlays: bool | Sequence[str | os.PathLike] = True) -> list[Path]:
    """Every file ``read_mesh_data(path, overlays=overlays)`` reads: the mesh file, and the
    overlays beside a GIFTI or FreeSurfer surface. What an output made from them must be
    newer than to be up to date.

    Examples
    --------
    >>> files_read("scan.ply")
    [PosixPath('scan.ply')]
    """
    p = Path(path)
    fmt = format_of(p)
    if fmt is None:
        with contextlib.suppress(OSError), open(p, "rb") as fh:
            fmt = "freesurfer" if fh.read(3) == FREESURFER_MAGIC else None
    return [p, *(_overlay_files(p, fmt, overlays) or [])]


def overlays_with(path: str | os.PathLike, given: Sequence[str | os.PathLike]) -> list[Path]:
    """The overlays ``fill --overlay`` and ``batch --overlay`` read with a surface: those
    found beside it (:func:`files_read`) and ``given``, each once.

    Raises
    ------
    MeshError
        When ``path`` is not a GIFTI or FreeSurfer surface (other formats carry their
        per-vertex data in the file).
    """
    if len(files_read(path, overlays=given)) == 1:
        raise MeshError("not a GIFTI or FreeSurfer surface, which overlays go with (other "
                        "formats carry their per-vertex data in the file)", path=str(path))
    beside = files_read(path)[1:]
    return [*beside, *(Path(g) for g in given if Path(g) not in beside)]


def files_written(path: str | os.PathLike, mesh: MeshData) -> list[Path]:
    """Every file ``write_mesh_data(path, mesh)`` writes: the mesh file, then the overlays
    beside a GIFTI or FreeSurfer surface (one a per-vertex array), for the user to be told.

    Examples
    --------
    >>> import numpy as np
    >>> mesh = MeshData(np.eye(3), np.array([[0, 1, 2]]), {"sulc": np.zeros(3)})
    >>> files_written("lh.filled.pial", mesh)
    [PosixPath('lh.filled.pial'), PosixPath('lh.filled.pial.sulc')]
    >>> files_written("out.ply", mesh)
    [PosixPath('out.ply')]
    """
    p = Path(path)
    fmt = format_of(p)
    beside = overlay_outputs(p, mesh, fmt) if fmt in ("gii", "gii.gz", "freesurfer") else []
    return [p, *(target for target, _ in beside)]


def _assemble(parsed: Parsed, corners: np.ndarray | None, owner: np.ndarray | None,
              faces: np.ndarray) -> tuple[MeshData, list[str]]:
    """The triangulated mesh with the parsed data (polygon rows repeated on their fan
    triangles, per-corner data per vertex where each vertex has one value), and a note for
    each per-corner array kept per corner. ``corners`` and ``owner`` as :func:`triangulate`
    gives them, or None when every polygon is a triangle (each its own row)."""
    seams = []
    attributes = dict(parsed.attributes)
    corner_attributes = {}
    flat = np.asarray(parsed.flat, dtype=np.int64)
    for key, values in parsed.corner_values.items():
        dtype = values.dtype if values.dtype.kind == "f" else np.float64  # NaN: no value
        values = np.asarray(values, dtype=np.float64)
        single = per_vertex(flat, values, len(parsed.vertices))
        if single is not None:
            attributes[key] = single.astype(dtype, copy=False)
            continue
        where = seam_vertices(flat, values, len(parsed.vertices))
        per_face = (values.reshape(len(faces), 3, *values.shape[1:]) if corners is None
                    else values[corners])
        corner_attributes[key] = per_face.astype(dtype, copy=False)
        seams.append(f"{key} differs between the faces around "
                     f"{how_many(len(where), 'vertex', 'vertices')} (a seam; e.g. "
                     f"{agreeing(len(where), 'vertex', 'vertices')} {ids(where, 5)}): kept per "
                     f"face corner (corner_attributes[{key!r}]), not per vertex")
    return MeshData(parsed.vertices, faces, attributes,
                    {k: np.array(a) if owner is None else np.asarray(a)[owner]
                     for k, a in parsed.face_attributes.items()},
                    corner_attributes, parsed.metadata), seams


_READERS: dict[str, Callable[[bytes, Path], Parsed]] = {
    "ply": read_ply, "obj": read_obj, "off": read_off, "stl": read_stl,
    "gii": read_gifti, "gii.gz": read_gifti, "freesurfer": read_freesurfer,
}

_WRITERS: dict[str, Callable[[IO[bytes], str, MeshData, bool], None]] = {
    "ply": write_ply, "obj": write_obj, "off": write_off, "stl": write_stl,
    "gii": write_gifti, "gii.gz": write_gifti_gz, "freesurfer": write_freesurfer,
}

# what each format cannot store of a MeshData, as messages
_UNSTORED: dict[str, Callable[[MeshData], list[str]]] = {
    "ply": unstored_ply, "obj": unstored_obj, "off": unstored_off, "stl": unstored_stl,
    "gii": unstored_brain, "gii.gz": unstored_brain, "freesurfer": unstored_freesurfer,
}


# --------------------------------------------------------------------------------- writing


def write_mesh(path: str | os.PathLike, vertices: np.ndarray, faces: np.ndarray, *,
               ascii: bool = False, attributes: Mapping[str, np.ndarray] | None = None,
               face_attributes: Mapping[str, np.ndarray] | None = None) -> None:
    """Write a triangle mesh, atomically, in the format given by the file name.

    Parameters
    ----------
    path : str or path-like
        Target file; its extension picks the format (:data:`SUPPORTED_FORMATS`). FreeSurfer
        names (``lh.pial``, ``*.white``, ...) write a FreeSurfer surface, ``.gii.gz`` a
        gzip-compressed GIFTI.
    vertices : (n, 3) float array
        Written in the given order. OBJ, OFF and PLY keep float64 exactly (17 significant
        digits in text, as an ascii STL); binary STL, GIFTI and FreeSurfer store float32.
    faces : (f, 3) int array
    ascii : bool, default False
        PLY and STL: write ascii instead of binary (little-endian); the other formats have
        one encoding. :func:`ascii_like` says whether a file is stored as ascii.
    attributes, face_attributes : dict of str to array, optional
        Per-vertex and per-face data to write with the mesh, as :func:`write_mesh_data`
        writes a :class:`MeshData`'s (e.g. a ``FillResult``'s ``.attributes``).

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
        vertices not first used in index order); reading it back renumbers them. Naming
        every attribute the format cannot store (it is not written).
    """
    _write(path, MeshData(vertices, faces, dict(attributes or {}), dict(face_attributes or {})),
           ascii=ascii)


def write_mesh_data(path: str | os.PathLike, mesh: MeshData, *, ascii: bool = False) -> None:
    """Write a :class:`MeshData`, atomically, with all the data its format can store.

    What each format stores: PLY every per-vertex and per-face array of numbers (1-D or
    2-D; 64-bit integers as 32-bit when their values fit) and per-corner arrays as face
    lists; OFF vertex ``normal``, ``color``, ``uv`` and face ``color``; OBJ ``uv`` and
    ``normal`` (per vertex or per corner) and a float ``color`` per vertex; STL a uint16
    face ``stl_attribute``; GIFTI and FreeSurfer each per-vertex array as an overlay file
    beside the surface (``OUT.NAME.shape.gii``; FreeSurfer ``OUT.NAME``, 1-D arrays), named
    so that :func:`read_mesh_data` finds them again. Metadata: PLY comments, GIFTI metadata.

    Raises
    ------
    MeshError
        As :func:`write_mesh`. Nothing is left behind on failure.

    Warns
    -----
    MeshWarning
        Naming every array or metadata the format cannot store.
    """
    if not isinstance(mesh, MeshData):
        raise TypeError(f"write_mesh_data writes a MeshData, got {type(mesh).__name__}")
    _write(path, mesh, ascii=ascii)


def _write(path: str | os.PathLike, mesh: MeshData, *, ascii: bool) -> None:
    p = Path(path)
    name = str(path)
    fmt = format_of(p)
    if fmt is None:
        raise unknown_format(p)
    check_arrays(mesh.vertices, mesh.faces, path=name)
    mesh = MeshData(np.asarray(mesh.vertices).astype(np.float64, copy=False),
                    np.asarray(mesh.faces).astype(np.int64, copy=False), mesh.attributes,
                    mesh.face_attributes, mesh.corner_attributes, mesh.metadata)
    directory = p.parent if str(p.parent) else Path(".")
    if not directory.is_dir():
        raise MeshError(f"directory {str(directory)!r} does not exist", path=name)
    if fmt == "stl":
        warn_stl_numbering(mesh.faces, len(mesh.vertices), name)
    notes = _UNSTORED[fmt](mesh) + (missing_libraries(mesh, directory) if fmt == "obj" else [])
    for message in notes:
        warnings.warn(f"{name}: {message}", MeshWarning, stacklevel=3)
    beside = overlay_outputs(p, mesh, fmt) if fmt in ("gii", "gii.gz", "freesurfer") else []
    created = False
    try:
        with ExitStack() as stack:
            # overlays first: their content is complete before anything is moved into place
            for target, write in beside:
                write(stack.enter_context(atomic_open(target)))
            fh = stack.enter_context(atomic_open(p))
            created = True
            _WRITERS[fmt](fh, fh.name, mesh, ascii)
    except MeshError as err:
        raise err.with_path(name) from None
    except Exception as exc:
        if not created and isinstance(exc, OSError):
            raise MeshError(f"cannot create a file here: {exc.strerror or exc}",
                            path=name) from None
        raise MeshError(f"writing failed: {describe(exc)}", path=name) from None

