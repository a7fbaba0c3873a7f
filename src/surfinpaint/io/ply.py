"""PLY, ascii and binary (either byte order): the header, the elements, the writer."""

from __future__ import annotations

import re
import struct
from pathlib import Path

import numpy as np

from surfinpaint.errors import MeshError, how_many
from surfinpaint.io.base import Parsed, describe, write_rows
from surfinpaint.io.meshdata import MeshData, group_columns, split_columns

_PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}


_END_HEADER = re.compile(rb"^[ \t]*end_header[ \t]*(?:\r\n|\n|\r|$)", re.MULTILINE)
#: How far into a PLY file its ``end_header`` line is looked for.
HEADER_BYTES = 1 << 20


def _ply_header(data: bytes) -> tuple[str, list, int, list[str], list[str]]:
    """Parse the PLY header: (format, [(element, count, [(name, type, list count type)])],
    offset of the body, comment and obj_info lines, and the lines of free text that start
    with no PLY keyword, kept with the comments (Blender 2.4's exporter writes its
    "Created by Blender3D ..." without ``comment``; other readers take such files))."""
    if not data.startswith(b"ply"):
        raise MeshError("not a PLY file (does not start with 'ply')")
    # the line that is exactly end_header (a comment may mention the word)
    end = _END_HEADER.search(data, 0, HEADER_BYTES)
    if end is None:
        raise MeshError("PLY header has no 'end_header' line (truncated or not PLY)")
    body = end.end()
    head = data[:end.start()]
    try:
        header = head.decode("utf-8").splitlines()[1:]
    except UnicodeDecodeError:
        header = head.decode("latin-1").splitlines()[1:]
    fmt = None
    elements: list = []
    notes: list[str] = []
    free_text: list[str] = []
    for line in header:
        parts = line.split()
        if parts and parts[0] in ("comment", "obj_info"):
            notes.append(line.strip())
            continue
        if not parts:
            continue
        if parts[0] not in ("format", "element", "property"):
            notes.append(line.strip())
            free_text.append(line.strip())
            continue
        if parts[0] == "format" and len(parts) >= 2:
            fmt = parts[1]
        elif parts[0] == "element" and len(parts) == 3:
            try:
                count = int(parts[2])
            except ValueError:
                raise MeshError(f"PLY header: bad element count in {line!r}") from None
            if count < 0:
                raise MeshError(f"PLY header: negative element count in {line!r}")
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
    return fmt, elements, body, notes, free_text


def ply_is_ascii(head: bytes) -> bool:
    """Whether a PLY file whose first bytes are ``head`` says ``format ascii``."""
    found = re.search(rb"^format[ \t]+(\S+)", head.split(b"end_header", 1)[0], re.M)
    return found is not None and found.group(1) == b"ascii"


def ply_layout(head: bytes) -> tuple[str, list, int, list[str], list[str], str]:
    """The header of a PLY file whose first bytes are ``head`` (its first
    :data:`HEADER_BYTES`, or all of it) as :func:`_ply_header` parses it, and the name of
    the faces' list of vertex ids; raises :class:`MeshError` for a header :func:`read_ply`
    cannot read (no ``end_header``, no vertex or face element, no ``x, y, z``, no list of
    vertex ids): also the header check of :func:`surfinpaint.io.formats.check_file`."""
    fmt, elements, offset, notes, free_text = _ply_header(head)
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
    return fmt, elements, offset, notes, free_text, key


def read_ply(data: bytes, path: Path) -> Parsed:
    fmt, elements, offset, notes, free_text, key = ply_layout(data)
    if fmt == "ascii":
        tokens = data[offset:].split()
        try:
            values = np.array(tokens, dtype=np.float64)
        except ValueError as exc:
            raise MeshError(f"PLY body has a non-numeric entry ({describe(exc)})") from None
        reader = _PlyAscii(values)
    else:
        reader = _PlyBinary(data, offset, "<" if fmt == "binary_little_endian" else ">")
    parsed = {}
    for name, count, props in elements:
        parsed[name] = reader.element(name, count, props)
    trailing = reader.trailing()
    if trailing:
        announced = ", ".join(f"element {name} {count}" for name, count, _ in elements)
        raise MeshError(f"trailing data: {trailing} after the last element (the header "
                        f"announces {announced}; more records than announced?)")
    v = parsed["vertex"]
    vertices = np.empty((len(v["x"]), 3))
    for k, axis in enumerate("xyz"):  # one pass a column, no float64 temporaries
        vertices[:, k] = v[axis]
    counts, flat = parsed["face"][key]
    if flat.dtype.kind == "f" and flat.size and not np.all(np.isfinite(flat)
                                                            & (flat == np.round(flat))):
        raise MeshError("PLY face list has non-integer vertex indices")
    out = Parsed(vertices, counts, flat.astype(np.int64).reshape(-1),
                 metadata={"comments": "\n".join(notes)} if notes else {})
    _ply_data(out, elements, parsed, key)
    out.dropped += [f"PLY header line {line!r} starts with no PLY keyword: read as a "
                    "comment" for line in free_text]
    return out


def _ply_data(out: Parsed, elements: list, parsed: dict, key: str) -> None:
    """The properties beside x, y, z and the face indices, in their declared types."""
    for name, count, props in elements:
        if name not in ("vertex", "face"):
            if count:
                out.dropped.append(f"PLY element {name!r} "
                                   f"({how_many(count, 'record', 'records')}) is not kept")
            continue
        columns = {}
        for prop, t, c in props:
            if name == "vertex" and prop in ("x", "y", "z") or name == "face" and prop == key:
                continue
            if c is None:
                columns[prop] = np.asarray(parsed[name][prop]).astype(np.dtype(t))
                continue
            lengths, values = parsed[name][prop]
            k, rem = np.divmod(lengths, np.maximum(out.counts, 1))
            if name == "face" and len(k) and np.all(rem == 0) and np.all(k == k[0]) and k[0]:
                out.corner_values[prop] = np.asarray(values).astype(np.dtype(t)).reshape(
                    -1, int(k[0]))
            else:
                out.dropped.append(f"PLY {name} list property {prop!r} is not kept")
        grouped = group_columns(columns)
        (out.attributes if name == "vertex" else out.face_attributes).update(grouped)


class _PlyBinary:
    def __init__(self, data: bytes, offset: int, endian: str) -> None:
        self.data, self.offset, self.endian = data, offset, endian

    def _need(self, nbytes: int, name: str) -> None:
        if self.offset + nbytes > len(self.data):
            raise MeshError(f"PLY file is truncated in element {name!r} "
                            f"(needs {self.offset + nbytes} bytes, has {len(self.data)})")

    def trailing(self) -> str:
        """What is left after the last element ('' when nothing but whitespace)."""
        rest = self.data[self.offset:]
        return f"{len(rest)} bytes" if rest.strip() else ""

    def element(self, name: str, count: int, props: list) -> dict:
        e = self.endian
        lists = [p for p in props if p[2] is not None]
        if not lists:
            dtype = np.dtype([(p, e + t) for p, t, _ in props])
            self._need(count * dtype.itemsize, name)
            rec = np.frombuffer(self.data, dtype, count=count, offset=self.offset)
            self.offset += count * dtype.itemsize
            return {p: rec[p] for p, _, _ in props}
        if count == 0:
            return {p: (np.zeros(0, np.int64), np.zeros(0)) if c is not None else np.zeros(0)
                    for p, _, c in props}
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
        if self.offset + count * dtype.itemsize <= len(self.data):
            rec = np.frombuffer(self.data, dtype, count=count, offset=self.offset)
            if all(np.all(rec[p + "\0n"] == sizes[p]) for p, _, _ in lists):
                self.offset += count * dtype.itemsize
                out = {p: rec[p] for p, _, c in props if c is None}
                for p, _, _ in lists:
                    # the (count, size) field as it lies in the records: the reader's one
                    # conversion copies it (a ravel here would copy it once more); the
                    # lengths, all the same, one value seen as many (read-only): no array
                    # of a count per face (651k case: 10 MB of fresh pages, ~5 ms)
                    out[p] = (np.broadcast_to(np.int64(sizes[p]), count), rec[p])
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

    def trailing(self) -> str:
        """What is left after the last element ('' when nothing)."""
        left = len(self.values) - self.pos
        return f"{left} values" if left else ""

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
        if count == 0:
            return {p: (np.zeros(0, np.int64), np.zeros(0)) if c is not None else np.zeros(0)
                    for p, _, c in props}
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



_PLY_NAMES = {"i1": "char", "u1": "uchar", "i2": "short", "u2": "ushort", "i4": "int",
              "u4": "uint", "f4": "float", "f8": "double"}


def _storable(a: np.ndarray) -> np.ndarray | None:
    """The array in a PLY type with the same values, or None (64-bit integers that do not
    fit 32 bits, strings, objects, complex numbers)."""
    if a.dtype == np.bool_:
        return a.astype("u1")
    if a.dtype.kind in "iu" and a.dtype.itemsize == 8:
        for t in ("i4", "u4"):
            if a.size == 0 or (a.min() >= np.iinfo(t).min and a.max() <= np.iinfo(t).max):
                return a.astype(t)
        return None
    if a.dtype == np.float16:
        return a.astype("f4")
    key = a.dtype.newbyteorder("=").str[1:]
    return a.astype(key) if key in _PLY_NAMES else None


def _columns(arrays: dict) -> list[tuple[str, np.ndarray]]:
    out = []
    for name, a in arrays.items():
        if np.asarray(a).ndim > 2:
            continue
        for column, values in split_columns({name: a}):
            stored = _storable(np.asarray(values))
            if stored is not None:
                out.append((column, stored))
    return out


def unstored_ply(mesh: MeshData) -> list[str]:
    """What :func:`write_ply` cannot store: arrays of non-numbers or over 2 dimensions."""
    out = []
    for kind, arrays in (("per-vertex", mesh.attributes), ("per-face", mesh.face_attributes)):
        for name, a in arrays.items():
            a = np.asarray(a)
            if a.ndim > 2 or any(_storable(np.asarray(c)) is None
                                 for _, c in split_columns({name: a})):
                out.append(f"{kind} {name} ({a.dtype}, shape {a.shape}) cannot be stored in "
                           "PLY and is not written")
    for name, a in mesh.corner_attributes.items():
        if _storable(np.asarray(a)) is None:
            out.append(f"per-corner {name} ({a.dtype}) cannot be stored in PLY and is not "
                       "written")
    out += [f"metadata {key!r} is not stored in PLY" for key in mesh.metadata
            if key != "comments"]
    return out


def write_ply(fh, tmp: str, mesh: MeshData, ascii: bool) -> None:
    v, f = mesh.vertices, mesh.faces
    vcols = [("x", v[:, 0]), ("y", v[:, 1]), ("z", v[:, 2])] + _columns(mesh.attributes)
    fcols = _columns(mesh.face_attributes)
    corners = [(name, c.reshape(len(f), -1)) for name, a in mesh.corner_attributes.items()
               if (c := _storable(np.asarray(a))) is not None]
    fmt = "ascii" if ascii else "binary_little_endian"
    comments = [line if line.split(" ", 1)[0] in ("comment", "obj_info") else f"comment {line}"
                for line in mesh.metadata.get("comments", "").splitlines()]
    comments = comments or ["comment written by surfinpaint"]
    lines = ["ply", f"format {fmt} 1.0", *comments, f"element vertex {len(v)}"]
    lines += [f"property {_PLY_NAMES[a.dtype.str[1:]]} {n}" for n, a in vcols]
    lines += [f"element face {len(f)}", "property list uchar int vertex_indices"]
    lines += [f"property {_PLY_NAMES[a.dtype.str[1:]]} {n}" for n, a in fcols]
    lines += [f"property list uchar {_PLY_NAMES[a.dtype.str[1:]]} {n}" for n, a in corners]
    fh.write(("\n".join(lines) + "\nend_header\n").encode("utf-8"))
    face_cols = ([("\0n", np.full(len(f), 3, np.uint8)), ("\0i", f)] + fcols
                 + [c for n, a in corners
                    for c in ((f"{n}\0n", np.full(len(f), a.shape[1], np.uint8)), (n, a))])
    for cols in (vcols, face_cols):
        if ascii:
            _ascii_rows(fh, cols)
        else:
            _binary_rows(fh, cols, {"\0i": "<i4"})  # the corners' ids as the header's int


# rows encoded and written per block of this many: a block's record buffer (1.5 MB for
# x y z doubles) is reused, where one record array per element was fresh memory the size of
# the element's bytes (32 MB for the 651k case's output: 47 -> 30 ms CPU, session 39)
BINARY_BLOCK_ROWS = 65536


def _binary_rows(fh, cols: list[tuple[str, np.ndarray]], types: dict[str, str]) -> None:
    """Little-endian binary rows: the columns interleaved, one record per row, the columns
    in the record types ``types`` where named there (cast as numpy's ``astype`` does), else
    in their own."""
    fields = [(n, types.get(n, "<" + a.dtype.str[1:]), a.shape[1:]) for n, a in cols]
    n_rows = len(cols[0][1])
    records = np.empty(min(n_rows, BINARY_BLOCK_ROWS), dtype=fields)
    for start in range(0, n_rows, BINARY_BLOCK_ROWS):
        block = records[:min(BINARY_BLOCK_ROWS, n_rows - start)]
        for n, a in cols:
            block[n] = a[start:start + len(block)]
        fh.write(block.view(np.uint8))  # its bytes, without a copy of them


def _ascii_rows(fh, cols: list[tuple[str, np.ndarray]]) -> None:
    """Rows of text: integers as such, float32 with 9 and float64 with 17 significant digits
    (both read back exactly)."""
    codes, blocks = [], []
    for _, a in cols:
        a = a.reshape(len(a), -1)
        code = "%d" if a.dtype.kind in "iu" else "%.9g" if a.dtype.itemsize == 4 else "%.17g"
        codes += [code] * a.shape[1]
        blocks.append(a.astype(np.float64))
    write_rows(fh, " ".join(codes) + "\n", np.column_stack(blocks))
