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

PLY, OBJ and OFF are parsed here rather than by trimesh: with ``process=False`` trimesh still
drops unreferenced OBJ vertices, splits vertices on texture seams, leaves negative OBJ indices
unresolved with ``maintain_order=True``, regroups polygon faces (triangles first), misreads
binary PLY with mixed polygon sizes, and writes OBJ/OFF with ten significant digits. trimesh is
used for ascii STL; nibabel for GIFTI and FreeSurfer.

Writing is atomic: the file is written to a temporary file next to the target and moved into
place with :func:`os.replace`, so a failure leaves no partial output and an existing file
is either fully replaced or left as it was.
"""

from __future__ import annotations

import gzip
import io
import os
import re
import struct
import tempfile
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np

from surfinpaint.errors import MeshError
from surfinpaint.geometry.validation import check_arrays

__all__ = ["SUPPORTED_FORMATS", "MeshWarning", "read_mesh", "write_mesh"]


class MeshWarning(UserWarning):
    """Something about a mesh file worth knowing that does not stop reading or writing it."""


_FREESURFER_SUFFIXES = (".pial", ".white", ".inflated", ".sphere", ".orig", ".smoothwm")
_FREESURFER_MAGIC = b"\xff\xff\xfe"

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
    if data[:3] == _FREESURFER_MAGIC and fmt in (None, "freesurfer"):
        fmt = "freesurfer"
    if fmt is None:
        raise _unknown_format(p)
    try:
        vertices, counts, flat = _READERS[fmt](data, p)
    except MeshError as err:
        raise err.with_path(name) from None
    except Exception as exc:  # any parser failure means a bad file
        raise MeshError(f"cannot read as {_LABELS[fmt]}: {_describe(exc)}", path=name) from None
    faces = _triangulate(counts, flat, name)
    check_arrays(vertices, faces, path=name)
    return vertices, faces


_LABELS = {"ply": "PLY", "obj": "OBJ", "stl": "STL", "off": "OFF", "gii": "GIFTI",
           "gii.gz": "gzip-compressed GIFTI", "freesurfer": "a FreeSurfer surface"}


def _describe(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0][:200]}" if text else type(exc).__name__


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


def _triangulate(counts: np.ndarray, flat: np.ndarray, name: str) -> np.ndarray:
    """Fan-triangulate polygons given as corner counts and concatenated corner ids."""
    counts = np.asarray(counts, dtype=np.int64)
    flat = np.asarray(flat, dtype=np.int64)
    if counts.size and counts.min() < 3:
        bad = np.flatnonzero(counts < 3)
        raise MeshError(f"faces with fewer than three corners: {_ids(bad)}", path=name,
                        faces=bad[:50].tolist())
    if counts.size == 0 or counts.max() == 3:
        return flat.reshape(-1, 3)
    n_poly = int(np.count_nonzero(counts > 3))
    warnings.warn(
        f"{name}: {n_poly} polygon face(s) with more than three corners were fan-triangulated",
        MeshWarning,
        stacklevel=3,
    )
    start = np.concatenate([[0], np.cumsum(counts)[:-1]])
    n_tri = counts - 2
    owner = np.repeat(np.arange(len(counts)), n_tri)
    # j = 1 .. k-2 within each polygon
    j = np.arange(owner.size) - np.repeat(np.cumsum(n_tri) - n_tri, n_tri) + 1
    s = start[owner]
    return np.column_stack([flat[s], flat[s + j], flat[s + j + 1]])


def _ids(ids: np.ndarray, limit: int = 10) -> str:
    from surfinpaint.errors import preview

    return preview(np.asarray(ids).tolist(), limit)


def _text(data: bytes, what: str) -> str:
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise MeshError(f"not a text {what} file (undecodable byte at offset {exc.start})"
                        ) from None


def _polygons(faces: list[list[int]]) -> tuple[np.ndarray, np.ndarray]:
    """Counts and flat corner array from a list of index lists (fast path if all equal)."""
    if not faces:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    try:
        arr = np.array(faces, dtype=np.int64)
        if arr.ndim == 2:
            return np.full(len(arr), arr.shape[1], np.int64), arr.ravel()
    except ValueError:
        pass
    counts = np.fromiter((len(f) for f in faces), dtype=np.int64, count=len(faces))
    flat = np.fromiter((i for f in faces for i in f), dtype=np.int64, count=int(counts.sum()))
    return counts, flat


# OBJ ------------------------------------------------------------------------------------


def _read_obj(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    text = _text(data, "OBJ")
    # only v and f records matter; the regex keeps the scan in C
    records = _OBJ_RECORD.findall(text)
    vlines = [rest for kind, rest in records if kind == "v"]
    flines = [rest for kind, rest in records if kind == "f"]
    if any("#" in ln for ln in vlines):
        vlines = [ln.partition("#")[0] for ln in vlines]
    vertices = _xyz_rows(vlines)
    # drop texture/normal references ("7/3/7", "7//7") and comments, keep vertex ids
    ftext = "\n".join(flines)
    if "#" in ftext:
        ftext = "\n".join(ln.partition("#")[0] for ln in flines)
    ftext = _OBJ_SLASH.sub("", ftext)
    flines = ftext.split("\n") if flines else []
    counts = np.fromiter(map(len, map(str.split, flines)), dtype=np.int64, count=len(flines))
    try:
        flat = np.array(ftext.split(), dtype=np.int64)
    except ValueError:
        raise MeshError("a face has a non-integer vertex index") from None
    if np.any(flat == 0):
        face = int(np.searchsorted(np.cumsum(counts), np.flatnonzero(flat == 0)[0], "right"))
        raise MeshError(f"face {face} uses vertex index 0 (OBJ counts from 1)", faces=[face])
    if np.any(flat < 0):
        # negative ids count back from the last vertex defined before the face
        is_v = np.array([kind == "v" for kind, _ in records])
        nv_before = np.cumsum(is_v)[~is_v]
        nv_corner = np.repeat(nv_before, counts)
        flat = np.where(flat < 0, flat + nv_corner, flat - 1)
        # an index reaching before the first vertex stays negative and is reported later
    else:
        flat = flat - 1
    return vertices, counts, flat


_OBJ_RECORD = re.compile(r"^[ \t]*([vf])[ \t]+([^\r\n]*)", re.MULTILINE)
_OBJ_SLASH = re.compile(r"/[^\s]*")


# OFF ------------------------------------------------------------------------------------


def _read_off(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    text = _text(data, "OFF")
    if "#" in text:
        text = re.sub(r"#[^\r\n]*", "", text)
    lines = [ln for ln in text.splitlines() if ln and not ln.isspace()]
    if not lines:
        raise MeshError("no OFF header")
    first = lines[0].split()
    keyword = first[0]
    if not keyword.endswith("OFF") or keyword.startswith("4") or "n" in keyword[:-3]:
        raise MeshError(f"not an OFF file (first word {keyword[:20]!r}, expected 'OFF')")
    # the counts may follow the keyword on the same line
    rest = first[1:] if len(first) > 1 else lines[1].split() if len(lines) > 1 else []
    body = lines[1:] if len(first) > 1 else lines[2:]
    if len(rest) < 2:
        raise MeshError("missing the 'vertices faces edges' count line")
    try:
        nv, nf = int(rest[0]), int(rest[1])
    except ValueError:
        raise MeshError(f"bad count line {' '.join(rest)[:60]!r}") from None
    if nv < 0 or nf < 0:
        raise MeshError(f"negative counts in the header ({nv} vertices, {nf} faces)")
    if len(body) < nv + nf:
        raise MeshError(f"file is truncated: header announces {nv} vertices and {nf} faces, "
                        f"found {len(body)} data lines")
    vertices = _xyz_rows(body[:nv])
    counts, flat = _off_faces(body[nv:nv + nf])
    return vertices, counts, flat


def _tokens_per_line(lines: list[str]) -> np.ndarray:
    return np.fromiter(map(len, map(str.split, lines)), dtype=np.int64, count=len(lines))


def _xyz_rows(lines: list[str]) -> np.ndarray:
    """The first three numbers of each line (OBJ w or OFF colour columns are skipped)."""
    ntok = _tokens_per_line(lines)
    if np.any(ntok < 3):
        k = int(np.flatnonzero(ntok < 3)[0])
        raise MeshError(f"vertex {k} has fewer than three coordinates", vertices=[k])
    try:
        values = np.array(" ".join(lines).split(), dtype=np.float64)
    except ValueError as exc:
        raise MeshError(f"non-numeric vertex coordinate ({_describe(exc)})") from None
    if np.all(ntok == 3):
        return values.reshape(-1, 3)
    # colour or normal columns after x y z
    start = np.cumsum(ntok) - ntok
    return values[start[:, None] + np.arange(3)]


def _off_faces(lines: list[str]) -> tuple[np.ndarray, np.ndarray]:
    ntok = _tokens_per_line(lines)
    try:
        values = np.array(" ".join(lines).split(), dtype=np.float64)
    except ValueError as exc:
        raise MeshError(f"bad face line ({_describe(exc)})") from None
    if len(ntok) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    start = np.cumsum(ntok) - ntok
    counts = values[start]
    short = np.flatnonzero((counts != np.round(counts)) | (counts > ntok - 1))
    if short.size:
        raise MeshError(f"faces with fewer corner ids than their count announces: "
                        f"{_ids(short)}", faces=short[:50].tolist())
    counts = counts.astype(np.int64)
    if np.all(counts == ntok - 1):
        idx = np.delete(values, start)
    else:  # colour columns after the corner ids
        owner = np.repeat(np.arange(len(counts)), counts)
        within = np.arange(owner.size) - np.repeat(np.cumsum(counts) - counts, counts)
        idx = values[start[owner] + 1 + within]
    if not np.all(idx == np.round(idx)):
        raise MeshError("a face has a non-integer vertex index")
    return counts, idx.astype(np.int64)


# PLY ------------------------------------------------------------------------------------

_PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}


def _ply_header(data: bytes) -> tuple[str, list, int]:
    """Parse the PLY header: (format, [(element, count, [(name, type, list count type)])],
    offset of the body)."""
    if not data.startswith(b"ply"):
        raise MeshError("not a PLY file (does not start with 'ply')")
    end = data.find(b"end_header", 0, 1 << 20)
    if end < 0:
        raise MeshError("PLY header has no 'end_header' line (truncated or not PLY)")
    body = data.index(b"\n", end) + 1 if b"\n" in data[end:end + 64] else len(data)
    header = data[:end].decode("ascii", errors="replace").splitlines()[1:]
    fmt = None
    elements: list = []
    for line in header:
        parts = line.split()
        if not parts or parts[0] in ("comment", "obj_info"):
            continue
        if parts[0] == "format" and len(parts) >= 2:
            fmt = parts[1]
        elif parts[0] == "element" and len(parts) == 3:
            try:
                count = int(parts[2])
            except ValueError:
                raise MeshError(f"PLY header: bad element count in {line!r}") from None
            elements.append((parts[1], count, []))
        elif parts[0] == "property" and elements:
            if parts[1] == "list" and len(parts) == 5:
                ctype, itype = _PLY_TYPES.get(parts[2]), _PLY_TYPES.get(parts[3])
                if ctype is None or itype is None:
                    raise MeshError(f"PLY header: unknown type in {line!r}")
                elements[-1][2].append((parts[4], itype, ctype))
            elif len(parts) == 3 and parts[1] in _PLY_TYPES:
                elements[-1][2].append((parts[2], _PLY_TYPES[parts[1]], None))
            else:
                raise MeshError(f"PLY header: cannot parse {line!r}")
        else:
            raise MeshError(f"PLY header: cannot parse {line!r}")
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise MeshError(f"PLY header: unknown format {fmt!r}")
    return fmt, elements, body


def _read_ply(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    fmt, elements, offset = _ply_header(data)
    names = [e[0] for e in elements]
    if "vertex" not in names:
        raise MeshError("PLY file has no vertex element")
    if "face" not in names:
        raise MeshError("PLY file has no face element (a point cloud, not a mesh)")
    vprops = [p[0] for p in elements[names.index("vertex")][2]]
    if not {"x", "y", "z"} <= set(vprops):
        raise MeshError(f"PLY vertex element lacks x, y, z (has {', '.join(vprops)})")
    fprops = [p[0] for p in elements[names.index("face")][2] if p[2] is not None]
    key = next((k for k in ("vertex_indices", "vertex_index") if k in fprops),
               fprops[0] if len(fprops) == 1 else None)
    if key is None:
        raise MeshError("PLY face element has no vertex_indices list")
    last = max(names.index("vertex"), names.index("face"))
    if fmt == "ascii":
        tokens = data[offset:].split()
        try:
            values = np.array(tokens, dtype=np.float64)
        except ValueError as exc:
            raise MeshError(f"PLY body has a non-numeric entry ({_describe(exc)})") from None
        reader = _PlyAscii(values)
    else:
        reader = _PlyBinary(data, offset, "<" if fmt == "binary_little_endian" else ">")
    parsed = {}
    for name, count, props in elements[:last + 1]:
        parsed[name] = reader.element(name, count, props)
    v = parsed["vertex"]
    vertices = np.column_stack([np.asarray(v["x"], np.float64), np.asarray(v["y"], np.float64),
                                np.asarray(v["z"], np.float64)]).reshape(-1, 3)
    counts, flat = parsed["face"][key]
    if flat.size and not np.all(np.isfinite(flat) & (flat == np.round(flat))):
        raise MeshError("PLY face list has non-integer vertex indices")
    return vertices, counts, flat.astype(np.int64)


class _PlyBinary:
    def __init__(self, data: bytes, offset: int, endian: str) -> None:
        self.data, self.offset, self.endian = data, offset, endian

    def _need(self, nbytes: int, name: str) -> None:
        if self.offset + nbytes > len(self.data):
            raise MeshError(f"PLY file is truncated in element {name!r} "
                            f"(needs {self.offset + nbytes} bytes, has {len(self.data)})")

    def element(self, name: str, count: int, props: list) -> dict:
        e = self.endian
        lists = [p for p in props if p[2] is not None]
        if not lists:
            dtype = np.dtype([(p, e + t) for p, t, _ in props])
            self._need(count * dtype.itemsize, name)
            rec = np.frombuffer(self.data, dtype, count=count, offset=self.offset)
            self.offset += count * dtype.itemsize
            return {p: rec[p] for p, _, _ in props}
        # fast path: every list as long as in the first record (all triangles, all quads)
        sizes, pos = {}, self.offset
        for p, t, c in props:
            if c is None:
                pos += np.dtype(t).itemsize
                continue
            self._need(pos - self.offset + np.dtype(c).itemsize, name)
            n = int(np.frombuffer(self.data, e + c, count=1, offset=pos)[0])
            sizes[p] = n
            pos += np.dtype(c).itemsize + n * np.dtype(t).itemsize
        fields = []
        for p, t, c in props:
            if c is None:
                fields.append((p, e + t))
            else:
                fields += [(p + "\0n", e + c), (p, e + t, (sizes[p],))]
        dtype = np.dtype(fields)
        if count == 0:
            return {p: (np.zeros(0, np.int64), np.zeros(0)) for p, _, c in lists}
        if self.offset + count * dtype.itemsize <= len(self.data):
            rec = np.frombuffer(self.data, dtype, count=count, offset=self.offset)
            if all(np.all(rec[p + "\0n"] == sizes[p]) for p, _, _ in lists):
                self.offset += count * dtype.itemsize
                out = {p: rec[p] for p, _, c in props if c is None}
                for p, _, _ in lists:
                    out[p] = (np.full(count, sizes[p], np.int64), rec[p].ravel())
                return out
        return self._slow(name, count, props)

    def _slow(self, name: str, count: int, props: list) -> dict:
        """Record by record, for mixed polygon sizes."""
        e, data = self.endian, self.data
        cols: dict = {p: [] for p, _, _ in props}
        lens: dict = {p: [] for p, _, c in props if c is not None}
        pos = self.offset
        try:
            for _ in range(count):
                for p, t, c in props:
                    if c is None:
                        cols[p].append(struct.unpack_from(e + _STRUCT[t], data, pos)[0])
                        pos += np.dtype(t).itemsize
                    else:
                        n = struct.unpack_from(e + _STRUCT[c], data, pos)[0]
                        pos += np.dtype(c).itemsize
                        cols[p].extend(struct.unpack_from(f"{e}{n}{_STRUCT[t]}", data, pos))
                        lens[p].append(n)
                        pos += n * np.dtype(t).itemsize
        except struct.error:
            raise MeshError(f"PLY file is truncated in element {name!r}") from None
        self.offset = pos
        out = {}
        for p, _, c in props:
            if c is None:
                out[p] = np.array(cols[p])
            else:
                out[p] = (np.array(lens[p], np.int64), np.array(cols[p], np.int64))
        return out


_STRUCT = {"i1": "b", "u1": "B", "i2": "h", "u2": "H", "i4": "i", "u4": "I", "f4": "f",
           "f8": "d"}


class _PlyAscii:
    def __init__(self, values: np.ndarray) -> None:
        self.values, self.pos = values, 0

    def _need(self, n: int, name: str) -> None:
        if self.pos + n > len(self.values):
            raise MeshError(f"PLY file is truncated in element {name!r}")

    def element(self, name: str, count: int, props: list) -> dict:
        v = self.values
        lists = [p for p in props if p[2] is not None]
        if not lists:
            k = len(props)
            self._need(count * k, name)
            block = v[self.pos:self.pos + count * k].reshape(count, k)
            self.pos += count * k
            return {p: block[:, i] for i, (p, _, _) in enumerate(props)}
        # fast path: constant list lengths, judged from the first record
        layout, width, q = [], 0, self.pos
        for p, _, c in props:
            if c is None:
                layout.append((p, width, None))
                width += 1
                q += 1
            else:
                self._need(q - self.pos + 1, name)
                n = int(v[q])
                layout.append((p, width, n))
                width += 1 + n
                q += 1 + n
        if count and self.pos + count * width <= len(v):
            block = v[self.pos:self.pos + count * width].reshape(count, width)
            if all(np.all(block[:, w] == n) for _, w, n in layout if n is not None):
                self.pos += count * width
                out = {}
                for p, w, n in layout:
                    if n is None:
                        out[p] = block[:, w]
                    else:
                        out[p] = (np.full(count, n, np.int64), block[:, w + 1:w + 1 + n].ravel())
                return out
        cols: dict = {p: [] for p, _, _ in props}
        lens: dict = {p: [] for p, _, c in props if c is not None}
        pos = self.pos
        for _ in range(count):
            for p, _, c in props:
                self._need(pos - self.pos + 1, name)
                if c is None:
                    cols[p].append(v[pos])
                    pos += 1
                else:
                    n = int(v[pos])
                    if pos + 1 + n > len(v):
                        raise MeshError(f"PLY file is truncated in element {name!r}")
                    cols[p].append(v[pos + 1:pos + 1 + n])
                    lens[p].append(n)
                    pos += 1 + n
        self.pos = pos
        out = {}
        for p, _, c in props:
            if c is None:
                out[p] = np.array(cols[p])
            else:
                flat = np.concatenate(cols[p]) if cols[p] else np.zeros(0)
                out[p] = (np.array(lens[p], np.int64), flat)
        return out


# STL ------------------------------------------------------------------------------------


def _read_stl(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    corners = None
    if len(data) >= 84:
        n = struct.unpack_from("<I", data, 80)[0]
        if len(data) == 84 + 50 * n:
            rec = np.frombuffer(data, _STL_DTYPE, count=n, offset=84)
            corners = rec["corners"].reshape(-1, 3).astype(np.float64)
    if corners is None:
        if not data.lstrip()[:5].lower() == b"solid":
            if len(data) >= 84:
                n = struct.unpack_from("<I", data, 80)[0]
                raise MeshError(f"not an STL file, or a truncated binary STL (the header "
                                f"announces {n} triangles = {84 + 50 * n} bytes, the file has "
                                f"{len(data)})")
            raise MeshError(f"not an STL file (only {len(data)} bytes, no 'solid' keyword)")
        corners = _read_stl_ascii(data)
    if len(corners) == 0:
        raise MeshError("STL file has no triangles")
    # merge exactly equal corners, numbering vertices by first occurrence
    # (a stable lexsort is much faster than np.unique(axis=0); -0.0 and 0.0 merge as in unique)
    order = np.lexsort((corners[:, 2], corners[:, 1], corners[:, 0]))
    s = corners[order]
    new_group = np.r_[True, np.any(s[1:] != s[:-1], axis=1)]
    group = np.cumsum(new_group) - 1
    first = order[new_group]  # stable sort: the first occurrence leads each group
    rank = np.empty(len(first), dtype=np.int64)
    rank[np.argsort(first, kind="stable")] = np.arange(len(first))
    flat = np.empty(len(corners), dtype=np.int64)
    flat[order] = rank[group]
    vertices = corners[np.sort(first)]
    return vertices, np.full(len(corners) // 3, 3, np.int64), flat


_STL_DTYPE = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attr", "<u2")])


def _read_stl_ascii(data: bytes) -> np.ndarray:
    from trimesh.exchange.stl import load_stl

    text = _text(data, "STL")
    n_facets = text.lower().count("endfacet")
    loaded = load_stl(io.BytesIO(data))
    if "vertices" not in loaded or "faces" not in loaded:
        raise MeshError("ascii STL file has no readable facets (truncated or not STL)")
    v = np.asarray(loaded["vertices"], dtype=np.float64)
    f = np.asarray(loaded["faces"], dtype=np.int64)
    if len(f) != n_facets:
        raise MeshError(f"ascii STL is malformed or truncated ({n_facets} complete facets, "
                        f"{len(f)} read)")
    return v[f].reshape(-1, 3)


# GIFTI / FreeSurfer ---------------------------------------------------------------------


def _read_gifti(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    import nibabel as nib

    if data[:2] == b"\x1f\x8b":
        try:
            data = gzip.decompress(data)
        except (OSError, EOFError) as exc:
            raise MeshError(f"corrupt gzip data ({_describe(exc)})") from None
    image = nib.gifti.GiftiImage.from_bytes(data)
    points = image.get_arrays_from_intent("NIFTI_INTENT_POINTSET")
    triangles = image.get_arrays_from_intent("NIFTI_INTENT_TRIANGLE")
    if not points:
        raise MeshError("GIFTI file has no NIFTI_INTENT_POINTSET array (not a surface)")
    if not triangles:
        raise MeshError("GIFTI file has no NIFTI_INTENT_TRIANGLE array (not a surface)")
    vertices = np.asarray(points[0].data, dtype=np.float64)
    faces = np.asarray(triangles[0].data)
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise MeshError(f"GIFTI pointset has shape {vertices.shape}, expected (n, 3)")
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise MeshError(f"GIFTI triangle array has shape {faces.shape}, expected (f, 3)")
    return vertices, np.full(len(faces), 3, np.int64), faces.astype(np.int64).ravel()


def _read_freesurfer(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    from nibabel.freesurfer import read_geometry

    if data[:3] not in (_FREESURFER_MAGIC, b"\xff\xff\xff"):
        raise MeshError("not a FreeSurfer surface (magic bytes are not FF FF FE)")
    if data[:3] == _FREESURFER_MAGIC:
        # the two creation lines end in "\n\n"; the counts follow as big-endian int32
        end = data.find(b"\n\n", 3, 3 + 4096)
        if end < 0 or end + 10 > len(data):
            raise MeshError("FreeSurfer surface is truncated (no header)")
        nv, nf = struct.unpack_from(">ii", data, end + 2)
        need = end + 10 + 12 * nv + 12 * nf
        if nv < 0 or nf < 0 or len(data) < need:
            raise MeshError(f"FreeSurfer surface is truncated (header announces {nv} vertices "
                            f"and {nf} faces = {need} bytes, the file has {len(data)})")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # nibabel warns about missing volume info footers
        vertices, faces = read_geometry(str(path))
    return (np.asarray(vertices, dtype=np.float64), np.full(len(faces), 3, np.int64),
            np.asarray(faces, dtype=np.int64).ravel())


_READERS: dict[str, Callable[[bytes, Path], tuple[np.ndarray, np.ndarray, np.ndarray]]] = {
    "ply": _read_ply, "obj": _read_obj, "off": _read_off, "stl": _read_stl,
    "gii": _read_gifti, "gii.gz": _read_gifti, "freesurfer": _read_freesurfer,
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
        _warn_stl_numbering(faces, len(vertices), name)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{p.name}.", suffix=".tmp", dir=directory)
    except OSError as exc:
        raise MeshError(f"cannot create a file here: {exc.strerror or exc}", path=name) from None
    try:
        with os.fdopen(fd, "wb") as fh:
            _WRITERS[fmt](fh, tmp, vertices, faces, ascii)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, _new_file_mode(p))
        os.replace(tmp, p)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        if isinstance(exc, MeshError):
            raise exc.with_path(name) from None
        if isinstance(exc, Exception):
            raise MeshError(f"writing failed: {_describe(exc)}", path=name) from None
        raise


def _new_file_mode(p: Path) -> int:
    """Keep an existing file's permissions; otherwise the usual 0o666 minus the umask
    (mkstemp creates 0o600)."""
    try:
        return p.stat().st_mode & 0o7777
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


def _warn_stl_numbering(faces: np.ndarray, n_vertices: int, name: str) -> None:
    _, first = np.unique(faces.ravel(), return_index=True)
    used = faces.ravel()[np.sort(first)]
    if len(used) != n_vertices or np.any(used != np.arange(n_vertices)):
        dropped = n_vertices - len(used)
        lost = f"{dropped} unreferenced vertices are dropped and " if dropped else ""
        warnings.warn(
            f"{name}: STL stores only triangles; {lost}vertices will be renumbered by first "
            "use on reading",
            MeshWarning,
            stacklevel=3,
        )


def _write_ply(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    fmt = "ascii" if ascii else "binary_little_endian"
    header = (
        f"ply\nformat {fmt} 1.0\ncomment written by surfinpaint\n"
        f"element vertex {len(v)}\nproperty double x\nproperty double y\nproperty double z\n"
        f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    fh.write(header.encode("ascii"))
    if ascii:
        _write_rows(fh, "%.17g %.17g %.17g\n", v)
        _write_rows(fh, "3 %d %d %d\n", f)
        return
    fh.write(np.ascontiguousarray(v, dtype="<f8").tobytes())
    rec = np.empty(len(f), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    rec["n"] = 3
    rec["i"] = f
    fh.write(rec.tobytes())


def _write_rows(fh, row: str, a: np.ndarray, chunk: int = 65536) -> None:
    """Text rows via one %-format per chunk (much faster than np.savetxt's row loop).
    %.17g round-trips float64 exactly."""
    for k in range(0, len(a), chunk):
        block = a[k:k + chunk]
        fh.write((row * len(block) % tuple(block.ravel().tolist())).encode("ascii"))


def _write_obj(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    fh.write(b"# written by surfinpaint\n")
    _write_rows(fh, "v %.17g %.17g %.17g\n", v)
    _write_rows(fh, "f %d %d %d\n", f + 1)


def _write_off(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    fh.write(f"OFF\n{len(v)} {len(f)} 0\n".encode("ascii"))
    _write_rows(fh, "%.17g %.17g %.17g\n", v)
    _write_rows(fh, "3 %d %d %d\n", f)


def _write_stl(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    from surfinpaint.geometry.mesh import face_normals

    rec = np.zeros(len(f), dtype=_STL_DTYPE)
    rec["normal"] = face_normals(v, f)
    rec["corners"] = v[f]
    fh.write(b"binary STL written by surfinpaint".ljust(80, b" "))
    fh.write(struct.pack("<I", len(f)))
    fh.write(rec.tobytes())


def _gifti_bytes(v: np.ndarray, f: np.ndarray) -> bytes:
    import nibabel as nib

    points = nib.gifti.GiftiDataArray(v.astype(np.float32), intent="NIFTI_INTENT_POINTSET",
                                      datatype="NIFTI_TYPE_FLOAT32")
    triangles = nib.gifti.GiftiDataArray(f.astype(np.int32), intent="NIFTI_INTENT_TRIANGLE",
                                         datatype="NIFTI_TYPE_INT32")
    return nib.gifti.GiftiImage(darrays=[points, triangles]).to_bytes()


def _write_gifti(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    fh.write(_gifti_bytes(v, f))


def _write_gifti_gz(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    fh.write(gzip.compress(_gifti_bytes(v, f)))


def _write_freesurfer(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    from nibabel.freesurfer import write_geometry

    # nibabel writes by file name; it goes to the same temporary file
    write_geometry(tmp, v.astype(np.float32), f.astype(np.int32))


_WRITERS = {
    "ply": _write_ply, "obj": _write_obj, "off": _write_off, "stl": _write_stl,
    "gii": _write_gifti, "gii.gz": _write_gifti_gz, "freesurfer": _write_freesurfer,
}
