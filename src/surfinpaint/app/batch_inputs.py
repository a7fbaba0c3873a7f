"""Batch filling's inputs: the mesh files named by files, folders and glob patterns, the
outputs that mirror their layout, whether an output is up to date, and the order the
workers take the files in."""

from __future__ import annotations

import glob
import os
import re
import string
import warnings
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from surfinpaint.errors import InputError, MeshError, how_many, preview
from surfinpaint.io.brain import OVERLAY_SUFFIXES, is_gifti_data, is_morphometry, surface_base
from surfinpaint.io.formats import SUPPORTED_FORMATS, files_read, output_format, overlays_with

__all__ = ["COMPANION_SUFFIXES", "HEMISPHERE_CONVENTIONS", "HEMI_WAYS", "OVERLAY_PLACEHOLDERS",
           "FileJob", "Inputs", "UnknownFile", "hemisphere_in_name",
           "UnknownFilesWarning", "check_overlay_patterns", "find_inputs",
           "largest_cost_first", "picture_path", "up_to_date"]


@dataclass(frozen=True)
class FileJob:
    """One input file and the output it is filled into (both absolute), and their names
    as the summary shows them: the input as given (or found under a folder given), the
    output relative to the output folder; and ``picture``, the before/after picture drawn
    beside the output (absolute; :func:`picture_path`), or None when none is asked for."""

    source: Path
    target: Path
    name: str
    output: str
    picture: Path | None = None
    #: ``batch --overlay`` patterns (:func:`check_overlay_patterns`), filled in for this
    #: input by :meth:`overlay_files`.
    overlays: tuple[str, ...] = ()
    #: The material files an earlier run copied beside the output (paths relative to the
    #: OBJ's folder) with the SHA-1 of what it wrote: ``materials`` of its summary row.
    copied: tuple[tuple[str, str], ...] = ()

    @property
    def picture_output(self) -> str | None:
        """The picture's path relative to the output folder, as the summary names it."""
        if self.picture is None:
            return None
        return Path(self.output).with_name(self.picture.name).as_posix()

    def overlay_files(self) -> dict[Path, str]:
        """The overlay files of :attr:`overlays` for this input, each pattern filled in
        (:data:`OVERLAY_PLACEHOLDERS`) and taken from the input's folder, as read (absolute)
        and as messages name them (from where the input's name is, ``..`` resolved).

        Raises
        ------
        MeshError
            When a pattern has ``{hemi}`` and the input's name says no hemisphere
            (:func:`hemisphere_in_name`).
        """
        values = {"name": self.source.name, "stem": surface_base(self.source),
                  "hemi": hemisphere_in_name(self.source.name)}
        files: dict[Path, str] = {}
        for pattern in self.overlays:
            if values["hemi"] is None and "hemi" in _placeholders(pattern):
                raise MeshError(f"--overlay {pattern!r}: the name says no hemisphere ({HEMI_WAYS})"
                                ", so {hemi} stands for nothing", path=self.name)
            relative = pattern.format(**values)
            files[self.source.parent / relative] = os.path.normpath(
                Path(self.name).parent / relative)
        return files

    def overlays_read(self) -> bool | list[Path]:
        """``read_mesh_data``'s ``overlays`` for this input: True (those beside it) without
        :attr:`overlays`; else those beside it and the given ones (a :class:`MeshError` for
        an input that is no GIFTI or FreeSurfer surface, or as :meth:`overlay_files`)."""
        if not self.overlays:
            return True
        return overlays_with(self.source, list(self.overlay_files()))


@dataclass(frozen=True)
class UnknownFile:
    """A file of unknown type that an input argument named and that was not filled
    (:func:`find_inputs`): ``path`` as the summary names files (the input as given, or
    found under a folder given), ``relative`` its path relative to the folder or the glob's
    base (as the :class:`UnknownFilesWarning` names it), ``argument`` the input argument."""

    path: str
    relative: str
    argument: str


class Inputs(list[FileJob]):
    """What :func:`find_inputs` returns: the files to fill, a list of :class:`FileJob`, and
    ``unknown``, the files of unknown type that were not filled (each once, in the inputs'
    order; named in the warnings and in ``summary.json``)."""

    def __init__(self, jobs: Iterable[FileJob] = (), unknown: Iterable[UnknownFile] = ()):
        super().__init__(jobs)
        self.unknown: tuple[UnknownFile, ...] = tuple(unknown)


def picture_path(target: Path) -> Path:
    """The before/after picture of the output ``target``: beside it, its mesh extension
    replaced by ``.png`` (``sub/scan.ply`` → ``sub/scan.png``, ``lh.pial.gii.gz`` →
    ``lh.pial.png``). A FreeSurfer surface's suffix is its name (``lh.pial``, ``lh.white``:
    replacing it would draw both to ``lh.png``), so it gets ``.png`` added:
    ``lh.pial.png``."""
    try:
        fmt = output_format(target)
    except MeshError:  # no format by its name: the fill fails on writing it, drawing nothing
        fmt = "freesurfer"
    name = target.name if fmt == "freesurfer" else target.name[:-len(fmt) - 1]
    return target.with_name(name + ".png")


#: Files that go with a mesh and are not meshes themselves: GIFTI overlays (read with their
#: surface), FreeSurfer labels and annotations, OBJ material libraries and texture images.
#: A folder's such files (and FreeSurfer morphometry files, ``lh.sulc``, and GIFTI data files
#: that hold no surface, ``sulc_left.gii.gz``, both known by their
#: content) are left out without a word; any other file that is not a mesh is named in an
#: :class:`UnknownFilesWarning`.
COMPANION_SUFFIXES = (*OVERLAY_SUFFIXES, ".label", ".annot", ".mtl", ".png", ".jpg", ".jpeg",
                      ".tga", ".bmp", ".gif", ".tif", ".tiff", ".webp", ".exr", ".hdr",
                      ".dds", ".ktx", ".ktx2")


#: The placeholders of a ``batch --overlay`` pattern, filled in per input file: its name
#: (``lh.white``), its name without the format's suffix (``lh.pial`` for ``lh.pial.gii``)
#: and its hemisphere as the name writes it (:func:`hemisphere_in_name`).
OVERLAY_PLACEHOLDERS = {"name": "the input's file name",
                        "stem": "its name without the format's suffix",
                        "hemi": "its hemisphere as its name writes it: lh/rh (FreeSurfer "
                                "lh.white), L/R (BIDS hemi-L, Workbench .L.), left/right "
                                "(nilearn pial_left)"}

#: How names say the hemisphere, by convention, tried in this order: the first match's
#: group is ``{hemi}``, as written (a pattern in the same convention then names the
#: companion file: ``{hemi}.thickness`` for FreeSurfer, ``hemi-{hemi}`` for BIDS).
HEMISPHERE_CONVENTIONS = (
    ("FreeSurfer lh./rh.", re.compile(r"^(lh|rh)\.")),
    ("BIDS hemi-L/R", re.compile(r"(?:^|_)hemi-(L|R)(?=[_.])")),
    ("nilearn _left/_right", re.compile(r"_(left|right)(?=\.)")),
    ("Workbench .L./.R.", re.compile(r"\.(L|R)\.")),
)
HEMI_WAYS = ", ".join(way for way, _ in HEMISPHERE_CONVENTIONS)


def hemisphere_in_name(name: str) -> str | None:
    """The hemisphere a file's name gives, as written (:data:`HEMISPHERE_CONVENTIONS`), or
    None.

    Examples
    --------
    >>> [hemisphere_in_name(n) for n in ("lh.white", "sub-01_hemi-L_pial.surf.gii",
    ...  "pial_left.gii.gz", "S1200.R.midthickness.32k_fs_LR.surf.gii", "bunny.ply")]
    ['lh', 'L', 'left', 'R', None]
    """
    for _, convention in HEMISPHERE_CONVENTIONS:
        found = convention.search(name)
        if found:
            return found.group(1)
    return None


def _placeholders(pattern: str) -> list[str]:
    return [field for _, field, _, _ in string.Formatter().parse(pattern) if field is not None]


def check_overlay_patterns(patterns: Sequence[str]) -> tuple[str, ...]:
    """``batch --overlay`` patterns, checked: each a path taken from the folder of every
    input file, with placeholders of :data:`OVERLAY_PLACEHOLDERS` in braces
    (``../label/{hemi}.aparc.annot``, ``{stem}.thickness.shape.gii``).

    Raises
    ------
    surfinpaint.errors.InputError
        A ``ValueError``: for an unknown placeholder or an unmatched brace.
    """
    known = ", ".join(f"{{{name}}}" for name in OVERLAY_PLACEHOLDERS)
    for pattern in patterns:
        try:
            fields = _placeholders(pattern)
        except ValueError as exc:
            raise InputError(f"--overlay {pattern!r}: {exc} (placeholders: {known})") from None
        unknown = [f for f in fields if f not in OVERLAY_PLACEHOLDERS]
        if unknown:
            raise InputError(f"--overlay {pattern!r}: unknown placeholder {{{unknown[0]}}} "
                             f"(placeholders: {known})")
    return tuple(str(p) for p in patterns)


class UnknownFilesWarning(UserWarning):
    """Files of a folder (or matches of a glob) given to batch filling that are neither
    mesh files by their names nor files that go with one: not filled
    (:func:`find_inputs`)."""


def _is_mesh_name(name: str) -> bool:
    """A name with a mesh extension, not hidden, and not a GIFTI overlay (an overlay is read
    with its surface, not filled as one)."""
    lower = name.lower()
    return not name.startswith(".") and any(lower.endswith(s) for s in SUPPORTED_FORMATS) \
        and not lower.endswith(OVERLAY_SUFFIXES)


def _is_unknown(path: Path) -> bool:
    """Whether a file that is not a mesh by its name is worth a word: not hidden (the
    system's and editors' files, the atomic writer's temporary files), not a companion of a
    mesh (:data:`COMPANION_SUFFIXES`, FreeSurfer morphometry files)."""
    return not (path.name.startswith(".") or path.name.lower().endswith(COMPANION_SUFFIXES)
                or is_morphometry(path) or is_gifti_data(path))


def _is_mesh(path: Path) -> bool:
    """A mesh file by its name (:func:`_is_mesh_name`) that is not a GIFTI data file (an
    overlay named as nilearn names them, ``sulc_left.gii.gz``: a companion, not a failed
    file; session 34)."""
    return _is_mesh_name(path.name) and not is_gifti_data(path)


def _meshes_under(folder: Path, unknown: list[Path]) -> Iterator[Path]:
    """Mesh files under ``folder`` (recursively; hidden files and folders left out); the
    files of unknown type (:func:`_is_unknown`) are added to ``unknown``."""
    for root, dirs, files in os.walk(folder):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        for name in sorted(files):
            if _is_mesh(Path(root) / name):
                yield Path(root) / name
            elif _is_unknown(Path(root) / name):
                unknown.append(Path(root) / name)


def _glob_base(pattern: str) -> Path:
    """The folder part of a glob pattern before its first wildcard."""
    parts = Path(pattern).parts
    first = next(i for i, part in enumerate(parts) if glob.has_magic(part))
    return Path(*parts[:first]) if first else Path(".")


def _expand(item: str, unknown: list[tuple[Path, Path]]) -> Iterator[tuple[Path, Path]]:
    """(file, path relative to the output folder) for one input argument; the files of
    unknown type it names, (file, path relative to the folder or the glob's base), are
    added to ``unknown``."""
    path = Path(item)
    strays: list[Path] = []
    if path.is_dir():
        for found in _meshes_under(path, strays):
            yield found, found.relative_to(path)
        unknown += [(p, p.relative_to(path)) for p in strays]
    elif glob.has_magic(item) and not path.exists():
        base = _glob_base(item)
        for match in sorted(glob.glob(item, recursive=True)):
            found = Path(match)
            if found.is_dir():
                for inner in _meshes_under(found, strays):
                    yield inner, inner.relative_to(base)
            elif _is_mesh(found):
                yield found, found.relative_to(base)
            elif _is_unknown(found):
                strays.append(found)
        unknown += [(p, p.relative_to(base)) for p in strays]
    else:
        yield path, Path(path.name)  # a missing file becomes a failed row, not a crash


def _warn_unknown(item: str, unknown: Sequence[UnknownFile]) -> None:
    """One warning for the files of unknown type under one input argument: how many, and
    the first few (paths relative to the folder or the glob's base)."""
    if not unknown:
        return
    n = len(unknown)
    where = f"in {item}" if Path(item).is_dir() else f"matched by {item!r}"
    warnings.warn(f"skipped {how_many(n, 'file', 'files')} of unknown type {where}: "
                  f"{preview([u.relative for u in unknown], 3)} (not filled: known mesh "
                  f"extensions: {', '.join(SUPPORTED_FORMATS)})",
                  UnknownFilesWarning, stacklevel=3)


def _glob_of(first: str, second: str) -> str:
    """The glob in quotes that names both paths, their differing folders a wildcard
    (``'subjects/*/surf/lh.pial.gii'`` for two subjects' files: a shell expanded it into
    file arguments); an example where they differ otherwise."""
    a, b = Path(first).parts, Path(second).parts
    if len(a) != len(b) or a[-1] != b[-1]:
        return "'subjects/*/lh.pial'"
    return repr(Path(*[x if x == y else "*" for x, y in zip(a, b, strict=True)]).as_posix())


def find_inputs(inputs: Sequence[str | os.PathLike], out_dir: str | os.PathLike, *,
                png: bool = False, overlays: Sequence[str] = ()) -> Inputs:
    """The files to fill and their outputs: ``out_dir`` mirrors the inputs' layout; with
    ``png``, each output's before/after picture too (:func:`picture_path`); ``overlays``,
    patterns of the overlay files read with each (:func:`check_overlay_patterns`). The result
    is a list of :class:`FileJob` whose ``unknown`` holds the files of unknown type (below).

    A file argument is written to ``out_dir/<its name>``; a folder is searched recursively
    for files with a known mesh extension (:data:`surfinpaint.io.SUPPORTED_FORMATS`; GIFTI
    overlays, ``.shape.gii`` and the like, are read with their surface), each written to
    the same relative path under ``out_dir``; a glob pattern (``*``, ``?``,
    ``[...]``, ``**``) mirrors the matches' paths below the pattern's first wildcard. Files
    inside ``out_dir`` are never inputs; a file named twice is filled once.

    Hidden files and folders are left out, and so are the files that go with a mesh
    (:data:`COMPANION_SUFFIXES`: overlays, labels, material libraries, textures; FreeSurfer
    morphometry files such as ``lh.sulc``); any other file a folder holds or a glob matches
    that is not a mesh by its name (``notes.txt``, ``lh.pial.bak``, ``lh.sphere.reg``) is
    not filled, and named: in a warning, and in the result's ``unknown``
    (:class:`UnknownFile`; each file once, none inside ``out_dir``).

    Warns
    -----
    UnknownFilesWarning
        Once per input argument with such files: how many, and the first three
        (``skipped 3 files of unknown type in scans/: lh.pial.bak, notes.txt, sub/a.csv``).

    Raises
    ------
    surfinpaint.errors.InputError
        A ``ValueError``: when an input names no mesh file, two inputs would be written
        to the same output (or picture: ``scan.ply`` and ``scan.obj`` with ``png``), or
        an input would be overwritten by its output.
    """
    patterns = check_overlay_patterns(overlays)
    out = Path(out_dir).absolute()
    out_real = os.path.realpath(out)
    jobs: list[FileJob] = []
    seen: set[str] = set()
    targets: dict[Path, str] = {}
    reported: set[str] = set()
    skipped: list[UnknownFile] = []
    for item in inputs:
        unknown: list[tuple[Path, Path]] = []
        expanded = list(_expand(os.fspath(item), unknown))
        strays = [UnknownFile(os.fspath(found), relative.as_posix(), os.fspath(item))
                  for found, relative in unknown if _new_stray(found, out_real, reported)]
        _warn_unknown(os.fspath(item), strays)
        skipped += strays
        if not expanded:
            raise InputError(f"{os.fspath(item)}: no mesh files there (known extensions: "
                             f"{', '.join(SUPPORTED_FORMATS)})")
        for found, relative in expanded:
            real = os.path.realpath(found)
            if real in seen or (found.exists() and Path(real).is_relative_to(out_real)
                                and os.fspath(found) != os.fspath(item)):
                continue
            seen.add(real)
            target = out / relative
            if target in targets:
                raise InputError(f"{targets[target]} and {found} would both be written to "
                                 f"{target}; a file argument is written under its name alone: "
                                 "pass their folder, or the glob in quotes "
                                 f"({_glob_of(targets[target], os.fspath(found))}), and the "
                                 "layout below it is kept, or fill them into different output "
                                 "folders")
            if os.path.realpath(target) == real:
                raise InputError(f"{found} would be overwritten by its output: choose an "
                                 "output folder other than the input's (inputs are never "
                                 "modified)")
            picture = picture_path(target) if png else None
            if picture in targets:
                raise InputError(f"{targets[picture]} and {found} would both be drawn to "
                                 f"{picture}; fill them into different output folders or "
                                 "rename one")
            targets[target] = os.fspath(found)
            if picture is not None:
                targets[picture] = os.fspath(found)
            jobs.append(FileJob(found.absolute(), target, os.fspath(found),
                                relative.as_posix(), picture, patterns))
    if not jobs:
        raise InputError("no input files given")
    return Inputs(jobs, skipped)


def _new_stray(found: Path, out_real: str, reported: set[str]) -> bool:
    """Whether a file of unknown type is yet to be reported: not inside the output folder
    (its summary), not reported for an earlier input argument."""
    real = os.path.realpath(found)
    if real in reported or Path(real).is_relative_to(out_real):
        return False
    reported.add(real)
    return True


def up_to_date(job: FileJob) -> bool:
    """Whether the output, and its picture when the job has one, exist and are newer than
    every file the fill reads: the input and, for a GIFTI or FreeSurfer surface, the
    overlays beside it (:func:`surfinpaint.io.formats.files_read`) and those of
    ``--overlay`` (a missing one: not up to date, its fill fails naming it), so that an
    overlay changed alone is filled again. A missing picture refills the file: the picture
    is drawn from the fill. An OBJ's material library and textures do not count: the fill
    does not read them (a rerun copies a changed one again:
    :func:`surfinpaint.app.batch_reruns.rerun_row`)."""
    try:
        written = min(path.stat().st_mtime_ns for path in (job.target, job.picture)
                      if path is not None)
        read = files_read(job.source, overlays=job.overlays_read())
        return all(written > source.stat().st_mtime_ns for source in read)
    except (OSError, MeshError):
        return False


def _size(job: FileJob) -> int:
    """The bytes of the input file (0 when it is not a readable file: its fill fails at
    once)."""
    try:
        return job.source.stat().st_size
    except OSError:
        return 0


def largest_cost_first(jobs: Sequence[FileJob], measured: Mapping[str, float]
                       ) -> list[FileJob]:
    """``jobs`` in the order the workers should start them: the costliest first, so that
    they run out of work at about the same time (the longest-processing-time rule).

    A file's cost is the seconds an earlier run took to fill it (``measured``, by the
    file's name in the summary; a rerun with ``--overwrite`` knows them all), else its size
    in bytes times the seconds per byte of the measured files (its size alone when none
    is measured). The file size is a weak guess: a small mesh with large holes can take
    longer than a large one with small holes; the measured seconds are not. Ties keep the
    inputs' order.
    """
    sizes = {job.name: _size(job) for job in jobs}
    known = {job.name: measured[job.name] for job in jobs
             if measured.get(job.name, 0.0) > 0.0}
    known_bytes = sum(sizes[name] for name in known)
    rate = sum(known.values()) / known_bytes if known and known_bytes else 1.0
    cost = {job.name: known.get(job.name, sizes[job.name] * rate) for job in jobs}
    return sorted(jobs, key=lambda job: -cost[job.name])
