"""OFF (Geomview object file format), with or without colour columns."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from surfinpaint.errors import MeshError
from surfinpaint.io.base import (
    Parsed,
    decode_text,
    describe,
    ids,
    tokens_per_line,
    write_rows,
    xyz_rows,
)
from surfinpaint.io.meshdata import MeshData


def off_header(head: bytes) -> tuple[str, int, int, list[str]]:
    """The keyword (``OFF``, ``COFF``, ...), vertex and face counts of an OFF file whose
    first bytes are ``head`` (or all of it), and its data lines after the header; raises
    :class:`MeshError` for a header :func:`read_off` cannot read (a binary file, no
    ``OFF`` keyword, no or a bad count line): also the header check of
    :func:`surfinpaint.io.formats.check_file`."""
    text = decode_text(head, "OFF")
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
    return keyword, nv, nf, body


def read_off(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    keyword, nv, nf, body = off_header(data)
    if len(body) < nv + nf:
        raise MeshError(f"file is truncated: header announces {nv} vertices and {nf} faces, "
                        f"found {len(body)} data lines")
    if len(body) > nv + nf:
        raise MeshError(f"trailing data: the header announces {nv} vertices and {nf} faces, "
                        f"the file has {len(body) - nv - nf} more data lines (more vertices or "
                        "faces than announced?)")
    counts, flat, face_data, dropped = _off_faces(body[nv:nv + nf])
    out = Parsed(xyz_rows(body[:nv]), counts, flat, face_attributes=face_data, dropped=dropped)
    _vertex_data(out, body[:nv], keyword[:-3])
    return out


def _colour(values: np.ndarray) -> np.ndarray:
    """8-bit when integral (0..255 with some value above 1), else float (0..1)."""
    if values.size and np.all(values == np.round(values)) and values.max() > 1 \
            and values.min() >= 0 and values.max() <= 255:
        return values.astype(np.uint8)
    return values


def _vertex_data(out: Parsed, lines: list[str], prefix: str) -> None:
    """Normals, colours and texture coordinates after x y z, as the keyword's prefix letters
    (``[ST][C][N]OFF``) say; extra columns under a plain ``OFF`` are a colour."""
    ntok = tokens_per_line(lines)
    extra = set((ntok - 3).tolist())
    if extra in ({0}, set()):
        return
    if len(extra) != 1:
        out.dropped.append("vertex lines have different numbers of columns after x y z: "
                           "the extra columns are not kept")
        return
    width = extra.pop()
    table = np.array(" ".join(lines).split(), dtype=np.float64).reshape(len(lines), -1)[:, 3:]
    normal, texture = 3 * ("N" in prefix), 2 * ("ST" in prefix)
    colour = width - normal - texture if "C" in prefix or not (normal or texture) else 0
    if colour not in (0, 3, 4) or normal + colour + texture != width:
        out.dropped.append(f"{width} vertex columns after x y z do not fit the keyword "
                           f"'{prefix}OFF': not kept")
        return
    if normal:
        out.attributes["normal"] = table[:, :3]
    if colour:
        out.attributes["color"] = _colour(table[:, normal:normal + colour])
    if texture:
        out.attributes["uv"] = table[:, normal + colour:]



def _off_faces(lines: list[str]) -> tuple[np.ndarray, np.ndarray, dict, list]:
    """Corner counts, corner ids, the face colours after the ids, what was not kept."""
    ntok = tokens_per_line(lines)
    try:
        values = np.array(" ".join(lines).split(), dtype=np.float64)
    except ValueError as exc:
        raise MeshError(f"bad face line ({describe(exc)})") from None
    if len(ntok) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64), {}, []
    start = np.cumsum(ntok) - ntok
    counts = values[start]
    short = np.flatnonzero((counts != np.round(counts)) | (counts > ntok - 1))
    if short.size:
        raise MeshError(f"faces with fewer corner ids than their count announces: "
                        f"{ids(short)}", faces=short[:50].tolist())
    counts = counts.astype(np.int64)
    face_data, dropped = {}, []
    if np.all(counts == ntok - 1):
        idx = np.delete(values, start)
    else:  # colour columns after the corner ids
        owner = np.repeat(np.arange(len(counts)), counts)
        within = np.arange(owner.size) - np.repeat(np.cumsum(counts) - counts, counts)
        idx = values[start[owner] + 1 + within]
        extra = ntok - 1 - counts
        if np.all(extra == extra[0]) and extra[0] in (3, 4):
            at = (start + 1 + counts)[:, None] + np.arange(extra[0])
            face_data["color"] = _colour(values[at])
        else:
            dropped.append("face columns after the corner ids (not one colour per face) "
                           "are not kept")
    if not np.all(idx == np.round(idx)):
        raise MeshError("a face has a non-integer vertex index")
    return counts, idx.astype(np.int64), face_data, dropped



def _off_arrays(mesh: MeshData) -> tuple[dict[str, np.ndarray], np.ndarray | None]:
    """The vertex columns OFF stores (normal, color, uv) and a face colour."""
    wanted = {"normal": (3,), "color": ((3,), (4,)), "uv": (2,)}
    kept = {}
    for key, shapes in wanted.items():
        a = mesh.attributes.get(key)
        shapes = shapes if isinstance(shapes[0], tuple) else (shapes,)
        if a is not None and a.shape[1:] in shapes and a.dtype.kind in "fiu":
            kept[key] = a
    colour = mesh.face_attributes.get("color")
    if colour is not None and not (colour.shape[1:] in ((3,), (4,)) and colour.dtype.kind in "fiu"):
        colour = None
    return kept, colour


def unstored_off(mesh: MeshData) -> list[str]:
    """What :func:`write_off` cannot store."""
    kept, colour = _off_arrays(mesh)
    names = [f"per-vertex {k}" for k in mesh.attributes if k not in kept]
    names += [f"per-face {k}" for k in mesh.face_attributes if k != "color" or colour is None]
    names += [f"per-corner {k}" for k in mesh.corner_attributes]
    out = [f"OFF stores normal, color, uv per vertex and color per face: {', '.join(names)} "
           "not written"] if names else []
    return out + [f"metadata {k!r} is not stored in OFF" for k in mesh.metadata]


def _formats(a: np.ndarray) -> list[str]:
    return ["%d" if a.dtype.kind in "iu" else "%.17g"] * a.shape[1]


def write_off(fh, tmp: str, mesh: MeshData, ascii: bool) -> None:
    v, f = mesh.vertices, mesh.faces
    kept, colour = _off_arrays(mesh)
    prefix = "ST" * ("uv" in kept) + "C" * ("color" in kept) + "N" * ("normal" in kept)
    fh.write(f"{prefix}OFF\n{len(v)} {len(f)} 0\n".encode("ascii"))
    columns = [v] + [kept[k] for k in ("normal", "color", "uv") if k in kept]
    codes = ["%.17g"] * 3 + [c for a in columns[1:] for c in _formats(a)]
    write_rows(fh, " ".join(codes) + "\n", np.column_stack([a.astype(np.float64)
                                                            for a in columns]))
    if colour is None:
        write_rows(fh, "3 %d %d %d\n", f)
    else:
        write_rows(fh, "3 %d %d %d " + " ".join(_formats(colour)) + "\n",
                   np.column_stack([f, colour.astype(np.float64)]))
