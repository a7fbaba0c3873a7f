"""An OBJ's material libraries (``mtllib``) and the textures they name, copied beside a
written OBJ so that it still shows its texture when opened.

An OBJ names its ``.mtl`` files relative to its own folder, and a ``.mtl`` its texture
images relative to its own. :func:`copy_materials` copies those found beside the input to
the same relative places beside the output, each through the atomic writer (a complete
file or none). It never touches the inputs, never writes outside the output's folder (a
name with ``..`` or an absolute name is left as it is, with a warning where the file is not
reachable from the output), and never replaces an existing file whose content differs (a
warning names it) unless it is the copy an earlier call made, unchanged since (``ours``:
the SHA-1 it recorded), and the input's file changed: a file with the same content is
left alone.
"""

from __future__ import annotations

import filecmp
import hashlib
import os
import shutil
import warnings
from collections.abc import Iterable, Mapping
from pathlib import Path, PurePosixPath

from surfinpaint.io.atomic import atomic_open, atomic_path
from surfinpaint.io.base import MeshWarning, decode_text
from surfinpaint.io.obj import COPIES_COMMENT, COPIES_KEY, material_libraries

__all__ = ["CopiedMaterials", "changed_materials", "copy_materials", "libraries_of",
           "material_files", "recorded_copies", "rewrite_recorded_copies"]

# MTL statements whose last argument is an image file (after options such as "-s 1 1 1"):
# every map_* (map_Kd, map_Ks, map_Bump, map_d, map_Pr, ...) and these
_IMAGE_STATEMENTS = {"bump", "disp", "decal", "refl", "norm"}


def _relative(name: str) -> PurePosixPath | None:
    """``name`` as a path below its folder (OBJ and MTL files use ``/``, some ``\\``);
    None when it is absolute or climbs out of the folder (``..``)."""
    path = PurePosixPath(name.strip().replace("\\", "/"))
    if not str(path) or path.is_absolute() or ".." in path.parts or \
            (path.parts and ":" in path.parts[0]):  # C:/textures/...
        return None
    return path


def _image_names(library: Path) -> list[str]:
    """The image files a ``.mtl`` names, as written (each once, in order). A name with
    spaces is taken whole when that file exists beside the library; else the last word."""
    try:
        lines = library.read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError:
        return []
    names: list[str] = []
    for line in lines:
        words = line.split()
        if len(words) < 2 or not (words[0].lower().startswith("map_")
                                  or words[0].lower() in _IMAGE_STATEMENTS):
            continue
        arguments = words[1:]
        name = next((" ".join(arguments[k:]) for k in range(len(arguments))
                     if (_relative(" ".join(arguments[k:])) is not None
                         and (library.parent / " ".join(arguments[k:])).is_file())),
                    arguments[-1])
        if name not in names:
            names.append(name)
    return names


def material_files(source: str | os.PathLike, libraries: str) -> tuple[list[PurePosixPath],
                                                                       list[str]]:
    """The files an OBJ at ``source`` needs for its materials: the ``mtllib`` names of
    ``libraries`` (one a line, as :func:`surfinpaint.io.read_mesh_data` keeps them in
    ``metadata["mtllib"]``) and the textures each of those names, as paths relative to
    the OBJ's folder, those found there; and a note per file named but not found there,
    or named outside that folder."""
    folder = Path(source).parent
    found: list[PurePosixPath] = []
    notes: list[str] = []

    def add(name: str, base: PurePosixPath, what: str) -> PurePosixPath | None:
        relative = _relative(name)
        if relative is None:
            if not Path(name).is_absolute():  # an absolute name reaches the file from anywhere
                notes.append(f"{what} {name!r} is outside the input's folder: not copied")
            return None
        path = base / relative
        if not (folder / path).is_file():
            if base != PurePosixPath() or what != "material library":  # the writer says it
                notes.append(f"{what} {name!r} is not beside the input: not copied")
            return None
        if path not in found:
            found.append(path)
        return path

    for line in libraries.splitlines():
        # "mtllib a.mtl b.mtl" names two; a name with a space is taken whole when it exists
        names = [line.strip()] if (folder / line.strip()).is_file() else line.split()
        for library in names:
            path = add(library, PurePosixPath(), "material library")
            if path is None:
                continue
            for image in _image_names(folder / path):
                add(image, path.parent, f"texture of {str(path)!r}")
    return found, notes


class CopiedMaterials(list[Path]):
    """What :func:`copy_materials` returns: the files it wrote (a list), and ``record``:
    for each material file whose copy beside the output now holds the input's content, its
    path relative to the OBJ's folder and that content's SHA-1 (what a later call's ``ours``
    takes, so that it replaces the copy when the input's file changes and the copy did
    not). ``batch`` keeps it in its summary; the OBJ written keeps it too, as comments
    (:attr:`metadata`, :func:`recorded_copies`), for a later ``fill`` into the same file."""

    def __init__(self, written: Iterable[Path] = (), record: Mapping[str, str] | None = None):
        super().__init__(written)
        self.record: dict[str, str] = dict(record or {})

    @property
    def metadata(self) -> dict[str, str]:
        """The record as the metadata of the mesh written beside the copies
        (:data:`surfinpaint.io.obj.COPIES_KEY`; none without copies)."""
        if not self.record:
            return {}
        return {COPIES_KEY: "\n".join(f"{sha1} {path}" for path, sha1 in self.record.items())}


def recorded_copies(obj: str | os.PathLike) -> dict[str, str]:
    """The record of the material files copied beside the OBJ file ``obj`` when
    surfinpaint wrote it (:attr:`CopiedMaterials.metadata`, read back from its header's
    comments: what :func:`copy_materials` takes as ``ours``); empty when it is no such OBJ
    (another format, none there, unreadable, or written without copies or by another
    program, which keeps no such comments)."""
    record: dict[str, str] = {}
    if Path(obj).suffix.lower() != ".obj":
        return record
    try:
        with open(obj, "rb") as handle:
            for raw in handle:  # the header only: comments and mtllib lines come first
                line = raw.decode("utf-8", errors="replace").rstrip("\r\n")
                if line.startswith(COPIES_COMMENT):
                    sha1, _, path = line[len(COPIES_COMMENT):].partition(" ")
                    if len(sha1) == 40 and path:
                        record[path] = sha1
                elif not line.startswith(("#", "mtllib")):
                    break
    except OSError:
        return {}
    return record


def rewrite_recorded_copies(obj: str | os.PathLike, record: Mapping[str, str]) -> bool:
    """Make the record of copied material files in the header of the OBJ ``obj`` (written by
    surfinpaint: :func:`recorded_copies`) ``record``, a :class:`CopiedMaterials` ``record``:
    its ``# surfinpaint copied`` comments replaced, after the ``mtllib`` lines, and the rest
    of the file kept byte for byte; through the atomic writer (the file whole, old or new).
    For ``batch``, which copies an OBJ's changed materials again without writing the mesh:
    a later ``fill`` into the OBJ then knows the copies as they are. Returns whether the file
    was written (not when its record is ``record`` already).

    Raises
    ------
    OSError
        When the file cannot be read or replaced.
    """
    comments = [f"{COPIES_COMMENT}{line}\n".encode()
                for line in CopiedMaterials(record=record).metadata.get(COPIES_KEY,
                                                                        "").splitlines()]
    if recorded_copies(obj) == dict(record):
        return False
    with open(obj, "rb") as source:
        header, first_body_line = [], b""
        while line := source.readline():  # the header: comments and mtllib lines first
            if not line.startswith((b"#", b"mtllib")):
                first_body_line = line
                break
            if not line.startswith(COPIES_COMMENT.encode()):
                header.append(line)
        after = 1 + max((k for k, line in enumerate(header) if line.startswith(b"mtllib")),
                        default=len(header) - 1)
        with atomic_open(obj) as target:
            target.writelines([*header[:after], *comments, *header[after:], first_body_line])
            shutil.copyfileobj(source, target)
    return True


def _sha1(path: Path) -> str:
    digest = hashlib.sha1()
    with open(path, "rb") as handle:
        while chunk := handle.read(1 << 20):
            digest.update(chunk)
    return digest.hexdigest()


def libraries_of(obj: str | os.PathLike) -> str:
    """The material libraries the OBJ file ``obj`` names (its ``mtllib`` statements, as
    :func:`surfinpaint.io.read_mesh_data` keeps them in ``metadata["mtllib"]``: the
    ``libraries`` of :func:`copy_materials`), read without parsing the mesh.

    Raises
    ------
    OSError
        When the file cannot be read.
    MeshError
        When it is no text file.
    """
    return material_libraries(decode_text(Path(obj).read_bytes(), "OBJ"))


def changed_materials(source: str | os.PathLike, record: Mapping[str, str],
                      since_ns: int | None = None) -> list[str]:
    """The files of ``record`` (a :class:`CopiedMaterials` ``record`` of copies made from
    beside the OBJ ``source``: paths relative to its folder, and the SHA-1 copied) whose
    file beside ``source`` is gone or holds other content now. A file not modified after
    ``since_ns`` (nanoseconds since the epoch: when the output was written) is taken as
    unchanged without reading it."""
    folder = Path(source).parent
    changed = []
    for relative, sha1 in record.items():
        origin = folder / relative
        try:
            if since_ns is not None and origin.stat().st_mtime_ns < since_ns:
                continue
            if _sha1(origin) == sha1:
                continue
        except OSError:  # gone, or unreadable: copy_materials says which
            pass
        changed.append(relative)
    return changed


def copy_materials(source: str | os.PathLike, target: str | os.PathLike, libraries: str, *,
                   reserved: tuple[str | os.PathLike, ...] = (),
                   ours: Mapping[str, str] | None = None) -> CopiedMaterials:
    """Copy the material libraries and textures of the OBJ ``source`` (:func:`material_files`
    of its ``libraries``) to the same places relative to the OBJ ``target``; returns the
    files written (those already there with the same content are not) and the record of
    the copies (:class:`CopiedMaterials`). Each is written atomically; the inputs are only
    read.

    ``ours``: an earlier call's ``record`` (``batch`` keeps it in its summary, the OBJ
    written beside the copies in its header: :func:`recorded_copies`). A copy whose
    content differs from the input's file is replaced when it is still what that call
    wrote (its SHA-1 recorded there): the input's file changed since, the copy did not. Any
    other file there is kept.

    Warns
    -----
    MeshWarning
        Naming each file not copied: not beside the input, outside its folder, at the
        place of an existing file with other content that no earlier call wrote or that
        changed since (kept, not replaced), or at one of ``reserved`` (other outputs, e.g.
        the ``--png`` picture).
    """
    if not libraries or Path(target).suffix.lower() != ".obj":
        return CopiedMaterials()  # another format has no use for them
    files, notes = material_files(source, libraries)
    into, source_folder = Path(target).parent, Path(source).parent
    taken = {os.path.abspath(p) for p in reserved}
    written = CopiedMaterials()
    for relative in files:
        origin, copy = source_folder / relative, into / relative
        key = relative.as_posix()
        if os.path.abspath(copy) in taken:
            notes.append(f"{str(relative)!r} not copied: another output takes its name "
                         f"({copy})")
            continue
        if copy.exists():
            if copy.is_file() and filecmp.cmp(origin, copy, shallow=False):
                written.record[key] = _sha1(copy)
                continue
            earlier = (ours or {}).get(key)
            if earlier is None or not copy.is_file() or _sha1(copy) != earlier:
                why = "changed since an earlier run copied it" if earlier is not None else \
                    "no earlier run recorded writing it"
                notes.append(f"{copy} exists with other content than {origin}: kept, not "
                             f"replaced ({why}); the output's materials may differ from the "
                             f"input's: to use the input's, copy {origin} over it")
                continue
        copy.parent.mkdir(parents=True, exist_ok=True)
        with atomic_path(copy) as tmp:
            shutil.copyfile(origin, tmp)
        written.append(copy)
        written.record[key] = _sha1(copy)
    for note in notes:
        warnings.warn(f"{target}: {note}", MeshWarning, stacklevel=2)
    return written
