"""OFF (Geomview object file format), with or without colour columns."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from surfinpaint.errors import MeshError
from surfinpaint.io.base import decode_text, describe, ids, tokens_per_line, write_rows, xyz_rows


def read_off(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    text = decode_text(data, "OFF")
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
    if len(body) > nv + nf:
        raise MeshError(f"trailing data: the header announces {nv} vertices and {nf} faces, "
                        f"the file has {len(body) - nv - nf} more data lines (more vertices or "
                        "faces than announced?)")
    vertices = xyz_rows(body[:nv])
    counts, flat = _off_faces(body[nv:nv + nf])
    return vertices, counts, flat



def _off_faces(lines: list[str]) -> tuple[np.ndarray, np.ndarray]:
    ntok = tokens_per_line(lines)
    try:
        values = np.array(" ".join(lines).split(), dtype=np.float64)
    except ValueError as exc:
        raise MeshError(f"bad face line ({describe(exc)})") from None
    if len(ntok) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    start = np.cumsum(ntok) - ntok
    counts = values[start]
    short = np.flatnonzero((counts != np.round(counts)) | (counts > ntok - 1))
    if short.size:
        raise MeshError(f"faces with fewer corner ids than their count announces: "
                        f"{ids(short)}", faces=short[:50].tolist())
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



def write_off(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    fh.write(f"OFF\n{len(v)} {len(f)} 0\n".encode("ascii"))
    write_rows(fh, "%.17g %.17g %.17g\n", v)
    write_rows(fh, "3 %d %d %d\n", f)

