"""Checks on where a command will write, made before any work is done, and the one way
``fill`` and ``batch`` write a filled mesh (:func:`write_output`; an OBJ with its materials
copied beside it: :func:`write_with_materials`).

A fill can take minutes; finding only at the end that the output directory is missing or
read-only, or that ``-o`` names the input (which the atomic rename would silently replace),
wastes them or destroys the input. These checks run first.
"""

from __future__ import annotations

import dataclasses
import os
import stat
import tempfile
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from surfinpaint.io.base import RenumberedWarning
from surfinpaint.io.formats import MeshData, ascii_like, write_mesh_data
from surfinpaint.io.materials import CopiedMaterials, copy_materials, recorded_copies
from surfinpaint.io.stl import first_use_order


class OutputError(Exception):
    """An output that cannot be written where asked (the command line exits 1)."""


class OutputOverwritesInput(OutputError):
    """An output that names an input file, or another output (a usage error: exit 2)."""


def _probe_directory(directory: Path, shown: str) -> None:
    """Create a file in ``directory``: the only test that also sees read-only mounts, ACLs
    and pseudo file systems (``os.access`` does not, and root passes it). An anonymous
    temporary file, so that nothing is left behind even if the process is killed."""
    try:
        with tempfile.TemporaryFile(dir=directory):
            pass
    except OSError as exc:
        raise OutputError(f"{shown}: cannot write in directory {str(directory)!r} "
                          f"({exc.strerror or exc})") from None


def check_output_file(path: str | os.PathLike, option: str = "-o") -> None:
    """Raise :class:`OutputError` unless a file can be written (atomically) at ``path``.

    The directory must exist and accept new files (the atomic writers create a temporary
    file there and rename it); an existing ``path`` must be a regular file.
    """
    p = Path(path)
    shown = f"{option} {str(path)!r}"
    if p.is_dir():
        raise OutputError(f"{shown} is a directory, not a file name")
    if p.exists() and not stat.S_ISREG(p.stat().st_mode):
        raise OutputError(f"{shown} exists and is not a regular file (the rename that writes "
                          "the output atomically would replace it)")
    directory = p.parent if str(p.parent) else Path(".")
    if not directory.exists():
        raise OutputError(f"{shown}: directory {str(directory)!r} does not exist")
    if not directory.is_dir():
        raise OutputError(f"{shown}: {str(directory)!r} is not a directory")
    _probe_directory(directory, shown)


def check_output_directory(path: str | os.PathLike, option: str = "-o") -> None:
    """Raise :class:`OutputError` unless ``path`` is, or can be created as, a writable folder.

    For a folder that does not exist yet, its nearest existing ancestor must be a writable
    directory (the command creates the missing levels).
    """
    p = Path(path)
    shown = f"{option} {str(path)!r}"
    if p.exists() and not p.is_dir():
        raise OutputError(f"{shown} exists and is not a directory")
    existing = p
    while not existing.exists():
        if existing.parent == existing:
            break
        existing = existing.parent
    if not existing.is_dir():
        raise OutputError(f"{shown}: {str(existing)!r} is not a directory")
    _probe_directory(existing, shown)


def _same_file(a: Path, b: Path) -> bool:
    """Whether two names denote one file (hard links and symbolic links included)."""
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist yet
        return a.resolve() == b.resolve()


def check_outputs_distinct(outputs: Mapping[str, str], inputs: Sequence[str], *,
                           in_place: str | None = None) -> None:
    """Raise :class:`OutputOverwritesInput` if an output names an input or another output.

    Parameters
    ----------
    outputs : mapping of option name to path
    inputs : paths read by the command
    in_place : str, optional
        The option (e.g. ``"-o"``) allowed to name an input, for ``--in-place``.
    """
    names = list(outputs.items())
    for i, (option, path) in enumerate(names):
        for source in inputs:
            if option != in_place and _same_file(Path(path), Path(source)):
                hint = "; pass --in-place to replace it" if option == "-o" else ""
                raise OutputOverwritesInput(f"{option} {path!r} is the input file {source!r}: "
                                            f"writing it would replace the input{hint}")
        for other, other_path in names[i + 1:]:
            if _same_file(Path(path), Path(other_path)):
                raise OutputOverwritesInput(f"{option} and {other} name the same file "
                                            f"{path!r}")


def write_output(source: str | os.PathLike, target: str | os.PathLike, filled: MeshData,
                 n_original: int) -> None:
    """Write a filled mesh as ``fill`` and ``batch`` do: an ascii PLY or STL input as ascii
    again (:func:`~surfinpaint.io.formats.ascii_like`), and an STL filled into an STL without
    the note that its vertices will be renumbered when, read back, its ``n_original``
    vertices keep their ids (all of them used, first used in order, before any new vertex):
    the input's numbering was that first use already, only new vertices change, and no
    report names them by id (a note on each of thousands of scans would hide the others).
    """
    ascii = ascii_like(source, target)
    if Path(source).suffix.lower() == ".stl" == Path(target).suffix.lower():
        order = first_use_order(filled.faces)
        if len(order) >= n_original and np.array_equal(order[:n_original],
                                                       np.arange(n_original)):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RenumberedWarning)
                write_mesh_data(target, filled, ascii=ascii)
            return
    write_mesh_data(target, filled, ascii=ascii)


def write_with_materials(source: str | os.PathLike, target: str | os.PathLike,
                         filled: MeshData, n_original: int, *,
                         reserved: Sequence[str | os.PathLike] = (),
                         ours: Mapping[str, str] | None = None) -> CopiedMaterials:
    """Write a filled mesh (:func:`write_output`) after copying an OBJ's material library
    and textures beside it (:func:`~surfinpaint.io.materials.copy_materials`, not onto
    ``reserved``: the other outputs), with the record of the copies in the OBJ's header, so
    that a later ``fill`` into the same file replaces a copy the input's changed since,
    unless the copy changed too. The copies an earlier run made are known from that record
    in the OBJ already at ``target`` and from ``ours`` (``batch``'s summary), which takes
    precedence. Returns what was copied."""
    materials = copy_materials(source, target, filled.metadata.get("mtllib", ""),
                               reserved=tuple(reserved),
                               ours={**recorded_copies(target), **(ours or {})})
    if materials.metadata:
        filled = dataclasses.replace(filled, metadata={**filled.metadata,
                                                       **materials.metadata})
    write_output(source, target, filled, n_original)
    return materials
