"""Wavefront OBJ: ``v`` and ``f`` records, vertex ids kept in file order."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from surfinpaint.errors import MeshError
from surfinpaint.io.base import decode_text, write_rows, xyz_rows


def read_obj(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    text = decode_text(data, "OBJ")
    # only v and f records matter; the regex keeps the scan in C
    records = _OBJ_RECORD.findall(text)
    vlines = [rest for kind, rest in records if kind == "v"]
    flines = [rest for kind, rest in records if kind == "f"]
    if any("#" in ln for ln in vlines):
        vlines = [ln.partition("#")[0] for ln in vlines]
    vertices = xyz_rows(vlines)
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


def write_obj(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    fh.write(b"# written by surfinpaint\n")
    write_rows(fh, "v %.17g %.17g %.17g\n", v)
    write_rows(fh, "f %d %d %d\n", f + 1)

