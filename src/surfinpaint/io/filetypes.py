"""A mesh file's type, its bytes and the check of its header: what
:mod:`surfinpaint.io.formats` reads a file as (by its name, or FreeSurfer's magic bytes), why
a file has no bytes to read (missing, a folder, unreadable, empty), how a reader's failure
is worded, and :func:`check_file`, the pre-flight of ``batch``, which raises what the reader
would raise for a bad header from a file's first (and, for a large OBJ, last) bytes, or for
a GIFTI file from all of it. The reader and the check share each step here, so that both
say the same words.
"""

from __future__ import annotations

import contextlib
import os
import stat
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

from surfinpaint.errors import MeshError, MissingFileError
from surfinpaint.io.base import describe
from surfinpaint.io.brain_checks import (
    FREESURFER_MAGIC,
    freesurfer_header,
    gifti_header,
)
from surfinpaint.io.obj import obj_header, obj_ids_plain, read_obj
from surfinpaint.io.off import off_header
from surfinpaint.io.ply import HEADER_BYTES, ply_is_ascii, ply_layout
from surfinpaint.io.stl import stl_header, stl_is_ascii

__all__ = ["SUPPORTED_FORMATS", "ascii_like", "check_file", "format_of", "format_read",
           "output_format", "parsing", "read_bytes", "read_tail", "unknown_format"]

_FREESURFER_SUFFIXES = (".pial", ".white", ".inflated", ".sphere", ".orig", ".smoothwm")


#: File extensions understood by :func:`~surfinpaint.io.formats.read_mesh` and
#: :func:`~surfinpaint.io.formats.write_mesh`, with a description.
SUPPORTED_FORMATS: dict[str, str] = {
    ".ply": "PLY, ascii or binary (written binary unless ascii=True)",
    ".obj": "Wavefront OBJ (v and f records)",
    ".stl": "STL, ascii or binary (a triangle soup: equal corners are merged on reading; "
            "written binary unless ascii=True)",
    ".off": "OFF (Geomview object file format)",
    ".gii": "GIFTI surface (pointset and triangle arrays, float32)",
    ".gii.gz": "gzip-compressed GIFTI surface",
    **{s: "FreeSurfer surface (float32; also lh.*/rh.* names and FF FF FE magic)"
       for s in _FREESURFER_SUFFIXES},
}


def format_of(path: Path) -> str | None:
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
    """The format :func:`~surfinpaint.io.formats.write_mesh` would write ``path`` in.

    Raises
    ------
    MeshError
        When the file name selects no supported format (checked before long work starts).
    """
    p = Path(path)
    fmt = format_of(p)
    if fmt is None:
        raise unknown_format(p)
    return fmt


def ascii_like(source: str | os.PathLike, target: str | os.PathLike) -> bool:
    """Whether to write ``target`` as ascii to keep ``source``'s encoding: ``target`` has
    ``source``'s format, PLY or STL, and ``source`` is stored as ascii (what ``fill`` and
    ``batch`` pass to :func:`~surfinpaint.io.formats.write_mesh_data`: an ascii scan stays
    ascii). False when ``source`` cannot be read (its reader reports that), and when it is
    no regular file: a named pipe read once already would be opened again, waiting for ever
    for a second writer (session 47)."""
    fmt = format_of(Path(source))
    if fmt not in ("ply", "stl") or format_of(Path(target)) != fmt:
        return False
    try:
        if not stat.S_ISREG(os.stat(source).st_mode):
            return False
        with open(source, "rb") as fh:
            head = fh.read(4096)
            size = os.fstat(fh.fileno()).st_size
    except OSError:
        return False
    return stl_is_ascii(head, size) if fmt == "stl" else ply_is_ascii(head)


def unknown_format(path: Path) -> MeshError:
    """The error for a file name that selects no supported format."""
    return MeshError(
        f"unknown mesh format {''.join(path.suffixes) or '(no extension)'!r}; supported: "
        + ", ".join(SUPPORTED_FORMATS),
        path=str(path),
    )


_LABELS = {"ply": "PLY", "obj": "OBJ", "stl": "STL", "off": "OFF", "gii": "GIFTI",
           "gii.gz": "gzip-compressed GIFTI", "freesurfer": "a FreeSurfer surface"}


def read_bytes(p: Path, limit: int = -1) -> bytes:
    """The bytes of the mesh file ``p`` (its first ``limit``), or the reason it has none."""
    name = str(p)
    if not p.exists():
        raise MissingFileError(name)
    if p.is_dir():
        raise MeshError("is a directory, not a mesh file", path=name)
    try:
        with p.open("rb") as fh:
            data = fh.read(limit)
    except PermissionError:
        raise MeshError("permission denied: the file cannot be read", path=name) from None
    except OSError as exc:
        raise MeshError(f"cannot read the file: {exc.strerror or exc}", path=name) from None
    if not data:
        raise MeshError("file is empty", path=name)
    return data


def read_tail(p: Path, count: int) -> bytes:
    """The last ``count`` bytes of the file ``p`` (one that :func:`read_bytes` has read)."""
    with p.open("rb") as fh:
        fh.seek(max(os.fstat(fh.fileno()).st_size - count, 0))
        return fh.read(count)


def format_read(p: Path, head: bytes) -> str:
    """The format ``p`` is read as: by its name, or FreeSurfer's by its magic bytes."""
    fmt = format_of(p)
    if head[:3] == FREESURFER_MAGIC and fmt in (None, "freesurfer"):
        return "freesurfer"
    if fmt is None:
        raise unknown_format(p)
    return fmt


@contextlib.contextmanager
def parsing(fmt: str, name: str) -> Iterator[None]:
    """A reader's error names the file; any other failure of a parser means a bad file."""
    try:
        yield
    except MeshError as err:
        raise err.with_path(name) from None
    except Exception as exc:
        raise MeshError(f"cannot read as {_LABELS[fmt]}: {describe(exc)}", path=name) from None


#: Per format, its reader's check of a header ``check(head, size, tail)``, the most bytes
#: given whole (OBJ: its v and f lines; GIFTI: its data, all), the most given when a check
#: of fewer fails (a large OBJ whose last line is cut short: all of it, for the line's
#: number), and the file's last bytes given as ``tail`` (OBJ: its last line; else none)
_HEADERS: dict[str, tuple[Callable[[bytes, int, bytes], object], int, int, int]] = {
    "ply": (lambda head, size, tail: ply_layout(head), 0, HEADER_BYTES, 0),
    "off": (lambda head, size, tail: off_header(head), 0, 1 << 16, 0),
    "stl": (lambda head, size, tail: stl_header(head, size), 0, 0, 0),
    "freesurfer": (lambda head, size, tail: freesurfer_header(head, size), 0, 0, 0),
    "obj": (obj_header, 1 << 18, sys.maxsize, 1 << 12),
    "gii": (lambda head, size, tail: gifti_header(head), sys.maxsize, 0, 0),
    "gii.gz": (lambda head, size, tail: gifti_header(head), sys.maxsize, 0, 0)}


def check_file(path: str | os.PathLike) -> None:
    """Raise the :class:`MeshError` :func:`~surfinpaint.io.formats.read_mesh` would raise,
    word for word, for a file missing, unreadable, empty, of unknown format or whose header
    its reader cannot parse (``_HEADERS``), from its first 8 KiB (PLY: up to 1 MiB, OFF:
    64 KiB where that is too short; an OBJ up to 256 KiB whole, its v and f lines, a larger
    one from its first 8 KiB and its last line; a GIFTI file whole, for its end and its
    data; the face ids of an OBJ read whole, :func:`check_obj_ids`): the pre-flight."""
    p = Path(path)
    head = read_bytes(p, 1 << 13)
    fmt, size = format_read(p, head), p.stat().st_size
    check, first, most, last = _HEADERS[fmt]
    head = read_bytes(p) if len(head) < size <= first else head  # small enough: whole
    with parsing(fmt, str(path)):
        tail = (read_tail(p, last) if len(head) < size else head[-last:]) if last else b""
        try:
            check(head, size, tail)
        except MeshError:  # a header longer than the first bytes: read as far as the reader
            if len(head) < min(size, most):
                head = read_bytes(p, most if most < size else -1)
            check(head, size, tail)
    # a larger OBJ's ids are left to its reader, which says the same words when its fill
    # reads it: screening them cost 49 ms a 4 MB file, 241x the pre-flight of an OBJ listing
    # (session 44), for a rare fault that fails that file alone, not the batch
    if fmt == "obj" and len(head) >= size:
        check_obj_ids(p, head)


def check_obj_ids(p: Path, data: bytes) -> None:
    """Raise what :func:`~surfinpaint.io.obj.read_obj` raises for the OBJ file ``p`` of
    bytes ``data`` whose faces name vertex ids that are 0, negative past the first vertex
    or past the last (the face, its line and the id): ``obj_ids_plain`` screens the bytes;
    a file it cannot clear (such an id, a negative id, anything but plain numbers on a face
    line) is read as the reader reads it, for the reader's words."""
    if obj_ids_plain([data]):
        return
    with parsing("obj", str(p)):
        read_obj(data, p)
