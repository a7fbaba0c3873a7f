"""Wavefront OBJ: ``v`` (with optional ``r g b``), ``vt``, ``vn`` and ``f`` records, vertex
ids kept in file order; texture coordinates and normals per face corner."""

from __future__ import annotations

import itertools
import re
import warnings
from collections.abc import Iterable
from pathlib import Path

import numpy as np

from surfinpaint.errors import MeshError, agreeing, how_many, preview
from surfinpaint.io.base import Parsed, decode_text, tokens_per_line, write_rows, xyz_rows
from surfinpaint.io.meshdata import MeshData

_RECORD = re.compile(r"^[ \t]*(v|vt|vn|f)[ \t]+([^\r\n]*)", re.MULTILINE)
# the records that label the faces after them, scanned only when there is one
_LABEL_OR_FACE = re.compile(r"^[ \t]*(usemtl|g|o|mtllib|f)(?![^ \t\r\n])[ \t]*([^\r\n]*)",
                            re.MULTILINE)
# the keywords of all records but the many v and f ones (a scan that returns few matches)
_KEYWORD = re.compile(r"^[ \t]*(?!v[ \t]|f[ \t])([A-Za-z_]\w*)", re.MULTILINE)
_CORNER = re.compile(r"(?<!\S)(-?\d+)(?:/(-?\d*))?(?:/(-?\d*))?(?!\S)")
#: where each face record starts (the ``f`` records of ``_RECORD``)
_FACE_START = re.compile(r"^[ \t]*f[ \t]+", re.MULTILINE)
_KNOWN = {"v", "vt", "vn", "f", "usemtl", "g", "o", "mtllib"}
#: The ``metadata`` of a mesh written as OBJ that records the material files copied beside
#: it: one ``SHA1 path`` a line (:func:`surfinpaint.io.materials.recorded_copies`), written
#: as the comments ``# surfinpaint copied SHA1 path`` after the ``mtllib`` lines.
COPIES_KEY = "copied_materials"
COPIES_COMMENT = "# surfinpaint copied "
_MTLLIB = re.compile(r"^[ \t]*mtllib(?![^ \t\r\n])[ \t]*([^\r\n]*)", re.MULTILINE)
#: face labels from the state records before each face: attribute name -> record
_LABELS = {"object": "o", "group": "g", "material": "usemtl"}


def obj_header(head: bytes, size: int, tail: bytes = b"") -> None:
    """Raise the :class:`MeshError` :func:`read_obj` raises first for an OBJ file of ``size``
    bytes starting with ``head`` and ending with ``tail``: a binary file, or (``head`` the
    whole file) one that ends in a line cut short (:func:`obj_last_line`) or has no vertex
    or no face line (a text file named ``.obj``): the check of
    :func:`surfinpaint.io.formats.check_file`, given a small file whole. A large file whose
    last line (in ``tail``) is cut short raises too, without the line's number: the check
    then gives it whole, for the reader's words."""
    text = decode_text(head, "OBJ")
    if len(head) >= size:
        obj_last_line(head)
        _records(text)
    elif _cut_short(tail) is not None:
        raise MeshError("OBJ file ends in a line cut short")


def obj_last_line(data: bytes) -> None:
    """Raise for an OBJ file's bytes ``data`` (all of them) that end in a record cut short
    (the file does not end with a newline and its last line is a face with fewer than
    three corners, or a vertex with fewer than three coordinates or one that is not a
    number), naming the line by its number (from 1): a file cut short mid-line, found
    before its faces are read."""
    problem = _cut_short(data)
    if problem is not None:
        line = data.count(b"\n") + 1
        raise MeshError(f"OBJ file ends in a line cut short (line {line}, with no newline "
                        f"after it, is {problem})")


def _cut_short(data: bytes) -> str | None:
    """What the last line of an OBJ file ending with ``data`` is when the reader rejects it
    (a face of fewer than three corners, a vertex of fewer than three coordinates or one
    not a number) and the file ends in it (no newline after it); else None."""
    last = data[data.rfind(b"\n") + 1:].decode("latin-1")
    record = _RECORD.match(last)
    if record is None:
        return None
    kind, values = record[1], record[2].partition("#")[0].split()
    if kind == "f" and len(values) < 3:
        return f"a face with fewer than three corners: {last!r}"
    if kind == "v" and len(values) < 3:
        return f"a vertex with fewer than three coordinates: {last!r}"
    if kind == "v":
        try:
            np.array(values, dtype=np.float64)
        except ValueError:
            return f"a vertex with a coordinate that is not a number: {last!r}"
    return None


#: Byte classes of the pre-flight's face-id screen: what a face line's corners may hold
_DIGIT, _MINUS, _SLASH, _BLANK = 1, 2, 3, 4
_CLASS = np.zeros(256, np.int8)
_CLASS[np.frombuffer(b"0123456789", np.uint8)] = _DIGIT
_CLASS[[ord("-"), ord("/")]] = _MINUS, _SLASH
_CLASS[np.frombuffer(b" \t\r\n", np.uint8)] = _BLANK


def obj_ids_plain(chunks: Iterable[bytes]) -> bool:
    """Whether an OBJ file's faces certainly name only its vertices (ids 1 to the number of
    ``v`` records), from its bytes in ``chunks``, read in turn (numpy over each, no line
    parsed in Python): the pre-flight's screen of a file's face ids, which costs a small
    part of :func:`read_obj`. False when an id is 0, negative or past the vertex count, or
    when the screen cannot tell (a line indented, a comment or anything but digits, ``-``
    and ``/`` on a face line, an id of more than 18 digits): then only the reader can say."""
    vertices, largest, rest, start = 0, 0, b"", True
    for chunk in itertools.chain(chunks, [None]):
        data = rest + chunk if chunk is not None else rest  # None: the last line
        if start and len(data) < 3 and chunk is not None:  # not yet past a byte-order mark
            rest = data
            continue
        data, start = (data.removeprefix(b"\xef\xbb\xbf") if start else data), False
        cut = data.rfind(b"\n") + 1 if chunk is not None else len(data)
        rest, data = data[cut:], data[:cut]
        counts = _chunk_ids(np.frombuffer(data, np.uint8)) if data else (0, 0)
        if counts is None:
            return False
        vertices, largest = vertices + counts[0], max(largest, counts[1])
    return largest <= vertices


def _chunk_ids(data: np.ndarray) -> tuple[int, int] | None:
    """The ``v`` records and the largest face vertex id (0: none) of whole OBJ lines
    ``data``; None when a face has an id below 1 or the screen cannot tell
    (:func:`obj_ids_plain`)."""
    starts = np.r_[0, np.flatnonzero(data[:-1] == 10) + 1]
    lengths = np.diff(np.r_[starts, len(data)])
    kind = data[starts]
    if np.any((kind == 32) | (kind == 9)):  # indented: the reader's regex is needed
        return None
    blank_after = np.zeros(len(starts), bool)
    two = lengths > 1
    blank_after[two] = _CLASS[data[starts[two] + 1]] == _BLANK
    vertices = int(np.count_nonzero((kind == ord("v")) & blank_after))
    faces = (kind == ord("f")) & blank_after
    if not np.any(faces):
        return vertices, 0
    text = data.copy()
    text[starts[faces]] = 32  # the keyword
    text = text[np.repeat(faces, lengths)]
    ids = _first_components(text)
    if ids is None or len(ids) == 0 or ids.min() < 1:
        return None
    return vertices, int(ids.max())


def _first_components(text: np.ndarray) -> np.ndarray | None:
    """The first number of each corner (``7`` of ``7/3/1``) of face lines' bytes ``text``
    (keywords blanked), or None when a byte or a number's form is not plain."""
    cls = _CLASS[text]
    if not cls.all():
        return None
    blank = cls == _BLANK
    edges = np.flatnonzero(blank[1:] != blank[:-1]) + 1  # where corners start and end
    starts = edges[::2] if blank[0] else np.r_[0, edges[1::2]]
    if np.any(cls[starts] == _SLASH):
        return None
    slash = cls == _SLASH
    if slash.any():  # blank each corner from its first slash on
        at = np.where(blank | slash, np.arange(len(cls), dtype=np.int32), -1)
        cut = slash[np.maximum.accumulate(at)]
        text = np.where(cut, np.uint8(32), text)
    ends = np.r_[edges, len(cls)][1::2] if blank[0] else edges[::2]
    if len(starts) and np.max(ends[:len(starts)] - starts) > 18:  # past int64: the reader's
        return None
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            ids = np.fromstring(text.tobytes(), dtype=np.int64, sep=" ")
        except (ValueError, DeprecationWarning):
            return None
    return ids if len(ids) == len(starts) else None


def _records(text: str) -> tuple[list, set[str], dict[str, list[str]]]:
    """The v/vt/vn/f records of an OBJ's text, its other keywords, and the lines of each
    record kind; raises for a file with no vertex or no face line (not a mesh)."""
    records = _RECORD.findall(text)
    present = set(_KEYWORD.findall(text))
    lines = {kind: _lines(records, kind) if kind in present | {"v", "f"} else []
             for kind in ("v", "vt", "vn", "f")}
    for kind, what in (("v", "vertices"), ("f", "faces")):
        if not lines[kind]:
            raise MeshError(f"OBJ file has no {what} (no '{kind}' line)")
    return records, present, lines


def read_obj(data: bytes, path: Path) -> Parsed:
    text = decode_text(data, "OBJ")
    obj_last_line(data)
    records, present, lines = _records(text)
    vertices = xyz_rows(lines["v"])
    flines = lines["f"]
    counts = tokens_per_line(flines)
    ftext = "\n".join(flines)
    if "/" in ftext:
        corners = _CORNER.findall(ftext)
        if len(corners) != counts.sum():
            raise MeshError("a face has a non-integer vertex index")
        columns = [" ".join(c[k] or "0" for c in corners) for k in range(3)]
    else:
        columns = [ftext, "", ""]
    try:
        vid, tid, nid = (np.array(c.split(), dtype=np.int64) for c in columns)
    except ValueError:
        raise MeshError("a face has a non-integer vertex index") from None
    except OverflowError:  # said as the reader's own words, not numpy's (session 38)
        raise MeshError(f"a face has an index beyond any vertex of the file ({len(vertices)} "
                        "vertices): it does not fit in 64 bits") from None
    out = Parsed(vertices, counts, _resolve(vid, records, "v", counts))
    _check_vertex_ids(vid, out.flat, counts, len(vertices), text)
    ntok = tokens_per_line(lines["v"])
    if len(ntok) and np.all(ntok == 6):
        values = np.array(" ".join(lines["v"]).split(), dtype=np.float64).reshape(-1, 6)
        out.attributes["color"] = values[:, 3:]
    elif len(ntok) and np.any(ntok > 4):
        out.dropped.append("extra numbers on v lines (not all 'x y z r g b') are not kept")
    for kind, ids, key, width in (("vt", tid, "uv", 2), ("vn", nid, "normal", 3)):
        _corner_values(out, lines[kind], ids, records, counts, kind, key, width)
    if present & {"o", "g", "usemtl", "mtllib"}:
        _labels(out, _LABEL_OR_FACE.findall(text))
    if "mtllib" in present:
        out.metadata["mtllib"] = material_libraries(text)
    other = sorted(present - _KNOWN)
    if other:
        out.dropped.append(f"OBJ records {', '.join(other)} (smoothing groups, lines, "
                           "points, ...) are not kept")
    return out


def _corner_values(out: Parsed, lines: list[str], ids: np.ndarray, records: list,
                   counts: np.ndarray, kind: str, key: str, width: int) -> None:
    """The faces' corner values ``key`` from the ``kind`` records (``lines``; ``ids``, the
    faces' ids of them, 0 where a corner names none) into ``out``, what is not kept said."""
    if not lines:
        if ids.size and np.any(ids):  # "f 1/5 2/6 3/7" with no vt: said, not silent
            out.dropped.append(f"faces name {kind} records the file has none of: "
                               f"no {key} is kept")
        return
    if not ids.size or not np.any(ids):
        out.dropped.append(f"{kind} records not referenced by any face are not kept")
        return
    table = _columns(lines, width, kind, out)
    index = _resolve(ids, records, kind, counts)
    bad = (ids != 0) & ((index < 0) | (index >= len(table)))
    if np.any(bad):
        face = int(np.searchsorted(np.cumsum(counts), np.flatnonzero(bad)[0], "right"))
        raise MeshError(f"face {face} uses a {kind} index out of range", faces=[face])
    values = np.full((len(ids), width), np.nan)
    values[ids != 0] = table[index[ids != 0]]
    out.corner_values[key] = values
    unused = len(table) - len(np.unique(index[ids != 0]))
    if unused:
        counted = how_many(len(table), f"{kind} record", f"{kind} records")
        verb = agreeing(unused, "is", "are")
        out.dropped.append(f"{unused} of {counted} {verb} not referenced by any face and "
                           f"{verb} not kept")


def _check_vertex_ids(ids: np.ndarray, index: np.ndarray, counts: np.ndarray, count: int,
                      text: str) -> None:
    """Raise for faces whose vertex ids (as written, ``ids``; from 0, ``index``) name no
    vertex of the file's ``count``: 0, a negative id counting back past the first vertex, or
    an id past the last. The message names the first such face (from 0), its line (from 1)
    and id, and how many faces do so."""
    bad = (ids == 0) | (index < 0) | (index >= count)
    if not np.any(bad):
        return
    corners = np.flatnonzero(bad)
    faces = np.unique(np.searchsorted(np.cumsum(counts), corners, "right"))
    value, first = int(ids[corners[0]]), int(index[corners[0]])
    why = ("0 (OBJ counts from 1)" if value == 0 else
           f"{value}, a negative index past the first vertex (it counts back from the "
           f"{how_many(first - value, 'vertex', 'vertices')} before the face)"
           if first < 0 else f"{value}, past the file's {how_many(count, 'vertex', 'vertices')}")
    more = f"; {how_many(len(faces), 'face does', 'faces do')}: {preview(faces)}" \
        if len(faces) > 1 else ""
    raise MeshError(f"face {faces[0]} (line {_face_line(text, int(faces[0]))}) uses vertex "
                    f"index {why}{more}", faces=faces[:100].tolist())


def _face_line(text: str, face: int) -> int:
    """The line (from 1) of the OBJ text's face ``face`` (from 0): for a message only."""
    start = next(itertools.islice(_FACE_START.finditer(text), face, None)).start()
    return text.count("\n", 0, start) + 1


def _lines(records: list, kind: str) -> list[str]:
    """The text after the keyword of each record of ``kind``, comments cut."""
    found = [rest for k, rest in records if k == kind]
    if any("#" in line for line in found):
        found = [line.partition("#")[0] for line in found]
    return found


def _labels(out: Parsed, records: list) -> None:
    """Object, group and material of each face (the last ``o``, ``g``, ``usemtl`` before
    it; "" before any) as face labels."""
    kinds = np.array([k for k, _ in records])
    names = np.array([rest.partition("#")[0].strip() for _, rest in records], dtype=object)
    for label, record in _LABELS.items():
        at = kinds == record
        if not np.any(at):
            continue
        last = np.maximum.accumulate(np.where(at, np.arange(len(kinds)), -1))[kinds == "f"]
        out.face_attributes[label] = np.where(last >= 0, names[np.maximum(last, 0)],
                                              "").astype(str)


def material_libraries(text: str) -> str:
    """What an OBJ's ``mtllib`` statements name (comments cut), one statement a line: the
    ``metadata["mtllib"]`` of :func:`read_obj` (:func:`surfinpaint.io.read_mesh_data`),
    found without reading the mesh."""
    return "\n".join(rest.partition("#")[0].strip() for rest in _MTLLIB.findall(text))


def _resolve(ids: np.ndarray, records: list, kind: str, counts: np.ndarray) -> np.ndarray:
    """0-based indices of 1-based OBJ ids; negative ids count back from the last record of
    ``kind`` before the face (an id before the first stays negative and is reported later)."""
    if not np.any(ids < 0):
        return ids - 1
    kinds = np.array([k for k, _ in records])
    before = np.cumsum(kinds == kind)[kinds == "f"]
    return np.where(ids < 0, ids + np.repeat(before, counts), ids - 1)


def _columns(lines: list[str], width: int, kind: str, out: Parsed) -> np.ndarray:
    ntok = tokens_per_line(lines)
    if np.any(ntok < width):
        k = int(np.flatnonzero(ntok < width)[0])
        raise MeshError(f"{kind} record {k} has fewer than {width} numbers")
    try:
        values = np.array(" ".join(lines).split(), dtype=np.float64)
    except ValueError:
        raise MeshError(f"a {kind} record has a non-numeric entry") from None
    start = np.cumsum(ntok) - ntok
    if np.any(ntok > width):
        extra = values[np.repeat(start + width, ntok - width)
                       + np.arange(int((ntok - width).sum()))
                       - np.repeat(np.cumsum(ntok - width) - (ntok - width), ntok - width)]
        if np.any(extra != 0):
            out.dropped.append(f"{kind} components after the first {width} are not kept")
    return values[start[:, None] + np.arange(width)]


def _obj_arrays(mesh: MeshData) -> dict[str, tuple[str, np.ndarray]]:
    """What OBJ stores: uv and normal per vertex or per corner, float rgb colour per vertex."""
    out = {}
    for key, width in (("uv", 2), ("normal", 3)):
        corner = mesh.corner_attributes.get(key)
        vertex = mesh.attributes.get(key)
        if corner is not None and corner.shape[2] == width and corner.dtype.kind in "fiu":
            out[key] = ("corner", corner)
        elif vertex is not None and vertex.shape[1:] == (width,) and vertex.dtype.kind in "fiu":
            out[key] = ("vertex", vertex)
    colour = _opaque_rgb(mesh.attributes.get("color"))
    if colour is not None and colour.shape[1:] == (3,) and colour.dtype.kind in "fiu":
        out["color"] = ("vertex", colour / 255.0 if colour.dtype == np.uint8 else colour)
    return out


def _opaque_rgb(colour: np.ndarray | None) -> np.ndarray | None:
    """``colour`` without its alpha column where every alpha is opaque (255 in 8 bits, 1.0
    in floats): OBJ's ``v x y z r g b`` has no alpha, and an opaque one loses nothing (a
    PLY's RGBA colours were not written at all, session 34); else ``colour`` as it is."""
    if colour is None or colour.ndim != 2 or colour.shape[1] != 4:
        return colour
    opaque = 255 if colour.dtype == np.uint8 else 1.0 if colour.dtype.kind == "f" else None
    return colour[:, :3] if opaque is not None and np.all(colour[:, 3] == opaque) else colour


def unstored_obj(mesh: MeshData) -> list[str]:
    """What :func:`write_obj` cannot store."""
    kept = _obj_arrays(mesh)
    names = [f"per-vertex {k}" for k in mesh.attributes
             if k not in kept or kept[k][0] != "vertex"]
    if "color" in mesh.attributes and "color" not in kept \
            and np.shape(mesh.attributes["color"])[1:] == (4,):  # say why
        names[names.index("per-vertex color")] = "per-vertex color (RGBA, not opaque)"
    names += [f"per-face {k}" for k, a in mesh.face_attributes.items()
              if k not in _LABELS or np.asarray(a).ndim != 1]
    names += [f"per-corner {k}" for k in mesh.corner_attributes
              if k not in kept or kept[k][0] != "corner"]
    out = [f"OBJ stores uv, normal and rgb color: {', '.join(names)} not written"] if names \
        else []
    out += _on_no_face(mesh, kept)
    out += [f"metadata {k!r} is not stored in OBJ" for k in mesh.metadata
            if k not in ("mtllib", COPIES_KEY)]
    if "color" in kept and mesh.attributes["color"].dtype == np.uint8:
        out.append("8-bit color is written as OBJ's float r g b (value / 255)")
    return out


def _on_no_face(mesh: MeshData, kept: dict) -> list[str]:
    """A note naming the vertices on no face whose per-vertex uv or normal has a value:
    OBJ stores them per face corner, so they are lost (session 46: a vertex whose faces
    ``fill --repair`` removed)."""
    used = np.zeros(len(mesh.vertices), dtype=bool)
    used[mesh.faces] = True
    lost = []
    for key in ("uv", "normal"):
        where, values = kept.get(key, ("", None))
        if where == "vertex":
            ids = np.flatnonzero(~used & ~np.isnan(np.asarray(values, float)).all(axis=1))
            if ids.size:
                lost.append(f"the {key} of {how_many(ids.size, 'vertex', 'vertices')} on no "
                            f"face ({preview(ids.tolist())}) not written")
    return [f"OBJ stores uv and normal per face corner: {', '.join(lost)}"] if lost else []


def missing_libraries(mesh: MeshData, directory: Path) -> list[str]:
    """A note per material library (``mtllib``) the written OBJ names that is not in its
    folder: the name is written as read (``fill`` and ``batch`` copy the files found beside
    the input first: :func:`surfinpaint.io.materials.copy_materials`)."""
    out = []
    for line in mesh.metadata.get("mtllib", "").splitlines():
        # "mtllib a.mtl b.mtl" names two; a name with a space is taken whole when it exists
        names = [line.strip()] if (directory / line.strip()).is_file() else line.split()
        for name in names:
            if not Path(name).is_absolute() and not (directory / name).is_file():
                out.append(f"material library {name!r} is not beside the output: its name "
                           "is written, and the materials show once it (and its textures) "
                           "is copied there")
    return out


def write_obj(fh, tmp: str, mesh: MeshData, ascii: bool) -> None:
    v, f = mesh.vertices, mesh.faces
    kept = _obj_arrays(mesh)
    fh.write(b"# written by surfinpaint\n")
    for library in mesh.metadata.get("mtllib", "").splitlines():
        fh.write(f"mtllib {library}\n".encode())
    for copy in mesh.metadata.get(COPIES_KEY, "").splitlines():
        fh.write(f"{COPIES_COMMENT}{copy}\n".encode())
    if "color" in kept:
        write_rows(fh, "v" + " %.17g" * 6 + "\n", np.column_stack([v, kept["color"][1]]))
    else:
        write_rows(fh, "v %.17g %.17g %.17g\n", v)
    # per record: each corner's 1-based id, 0 where the corner has no value (NaN: a vertex
    # no face uses, a new corner across a UV seam); a face with such a corner is written
    # without that record ("f 1/2 3/4 5/6" beside "f 7 8 9"), never as "vt nan nan"
    ids = [f + 1]
    for key, record in (("uv", "vt"), ("normal", "vn")):
        if key not in kept:
            ids.append(None)
            continue
        where, a = kept[key]
        if where == "vertex":
            used = np.zeros(len(a), dtype=bool)
            used[f] = True  # O(n), not a sort of the face ids
            table, index = a[used], (np.cumsum(used) - 1)[f]
        else:
            table, inverse = np.unique(a.reshape(-1, a.shape[2]), axis=0, return_inverse=True)
            index = inverse.reshape(-1, 3)
        table = np.asarray(table, np.float64)
        valued = ~np.isnan(table).any(axis=1)
        number = np.cumsum(valued) * valued  # 1-based among the rows written, 0: no value
        write_rows(fh, record + " %.17g" * table.shape[1] + "\n", table[valued])
        ids.append(number[index])
    _write_faces(fh, ids, mesh)


def _face_rows(ids: list) -> tuple[np.ndarray, dict[int, tuple[str, np.ndarray]]]:
    """Per face its row kind, and per kind present the row format and the numbers of its
    faces (all faces' rows, read in runs): a face with a corner that has no uv (normal) is
    written without its vt (vn) ids."""
    lacks = [np.zeros(len(ids[0]), bool) if i is None else (i == 0).any(axis=1)
             for i in ids[1:]]
    kind = lacks[0].astype(np.int64) + 2 * lacks[1]
    rows = {}
    for k in np.unique(kind).tolist():
        uv = ids[1] is not None and not k & 1
        normal = ids[2] is not None and not k & 2
        corner = {(True, True): "%d/%d/%d", (True, False): "%d/%d",
                  (False, True): "%d//%d", (False, False): "%d"}[uv, normal]
        columns = [ids[0]] + [i for i, on in ((ids[1], uv), (ids[2], normal)) if on]
        rows[k] = ("f " + " ".join([corner] * 3) + "\n",
                   np.stack(columns, axis=2).reshape(len(kind), -1))
    return kind, rows


def _write_faces(fh, ids: list, mesh: MeshData) -> None:
    """Face rows in runs of one object, group and material, each run after its records, and
    of one row kind (:func:`_face_rows`)."""
    kind, rows = _face_rows(ids)
    labels = [(record, np.asarray(mesh.face_attributes[label]).astype(str))
              for label, record in _LABELS.items()
              if np.asarray(mesh.face_attributes.get(label, np.zeros((0, 0)))).ndim == 1]
    if not labels and not kind.any():
        write_rows(fh, *rows[0])
        return
    change = np.zeros(len(kind), dtype=bool)
    change[0] = True
    change[1:] |= kind[1:] != kind[:-1]
    for _, values in labels:
        change[1:] |= values[1:] != values[:-1]
    starts = np.flatnonzero(change).tolist() + [len(kind)]
    for a, b in zip(starts[:-1], starts[1:], strict=True):
        for record, values in labels:
            if a == 0 and values[a] == "" or a and values[a] == values[a - 1]:
                continue
            fh.write(f"{record} {values[a]}\n".encode())
        row, stacked = rows[kind[a]]
        write_rows(fh, row, stacked[a:b])
