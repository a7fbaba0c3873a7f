"""STL, binary and ascii: a triangle soup whose equal corners are merged on reading."""

from __future__ import annotations

import re
import struct
import warnings
from pathlib import Path

import numpy as np

from surfinpaint.errors import MeshError, how_many
from surfinpaint.geometry.mesh import face_normals
from surfinpaint.io.base import Parsed, RenumberedWarning, decode_text
from surfinpaint.io.meshdata import MeshData


def read_stl(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    stl_header(data, len(data))
    corners, facet_attributes = _binary_corners(data)
    if corners is None:
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
    out = Parsed(vertices, np.full(len(corners) // 3, 3, np.int64), flat)
    if facet_attributes is not None and np.any(facet_attributes):
        out.face_attributes["stl_attribute"] = facet_attributes
    return out


_STL_DTYPE = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attr", "<u2")])


def _binary_corners(data: bytes) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The corners of a binary STL and its facets' 16-bit attributes, or None, None when the
    size does not fit one.

    A few bytes after the announced triangles (less than one 50-byte record: some exporters
    pad to an even or aligned length) are accepted, unless the file reads as ascii STL.
    """
    if not _binary_fits(data, len(data)):
        return None, None
    n = struct.unpack_from("<I", data, 80)[0]
    rec = np.frombuffer(data, _STL_DTYPE, count=n, offset=84)
    return rec["corners"].reshape(-1, 3).astype(np.float64), rec["attr"].astype(np.uint16)


def _binary_fits(head: bytes, size: int) -> bool:
    """Whether an STL file of ``size`` bytes starting with ``head`` (its first 4096 bytes,
    or all of it) is read as binary: its size is what the triangle count in its header
    announces, or a few bytes more unless it reads as ascii (:func:`_binary_corners`)."""
    if size < 84:
        return False
    excess = size - (84 + 50 * struct.unpack_from("<I", head, 80)[0])
    return excess == 0 or (0 < excess < 50 and not _looks_ascii(head))


def stl_is_ascii(head: bytes, size: int) -> bool:
    """Whether an STL file of ``size`` bytes starting with ``head`` (its first 4096 bytes, or
    all of it) is ascii, by the rule :func:`read_stl` reads it with."""
    return not _binary_fits(head, size) and _says_solid(head)


def stl_header(head: bytes, size: int) -> None:
    """Raise the :class:`MeshError` :func:`read_stl` raises for an STL file of ``size``
    bytes starting with ``head`` (its first 4096 bytes, or all of it) that is neither a
    binary STL of its size nor says ``solid`` (a truncated binary STL, not an STL)."""
    if not _binary_fits(head, size) and not _says_solid(head):
        raise MeshError(_not_binary(head, size))


def _says_solid(data: bytes) -> bool:
    return data.lstrip()[:5].lower() == b"solid"


def _looks_ascii(data: bytes) -> bool:
    return _says_solid(data) and re.search(rb"(?i)(?<!\S)facet(?!\S)", data[:4096]) is not None


def _not_binary(head: bytes, size: int) -> str:
    if size < 84:
        return f"not an STL file (only {size} bytes, no 'solid' keyword)"
    n = struct.unpack_from("<I", head, 80)[0]
    need = 84 + 50 * n
    if size < need:
        return (f"not an STL file, or a truncated binary STL (the header announces {n} "
                f"triangles = {need} bytes, the file has {size})")
    return (f"not an STL file, or a binary STL with trailing data ({size - need} bytes "
            f"after the {n} triangles its header announces)")


_NUM = r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[-+]?(?:nan|inf(?:inity)?))"
_FACET = re.compile(
    r"facet\s+normal" + r"\s+" + r"\s+".join([_NUM] * 3) + r"\s+outer\s+loop"
    + "".join(r"\s+vertex\s+" + r"\s+".join([_NUM] * 3) for _ in range(3))
    + r"\s+endloop\s+endfacet(?!\S)",
    re.IGNORECASE,
)
_KEYWORD = re.compile(r"(?i)(?<!\S)(facet|endsolid)(?!\S)")


def _read_stl_ascii(data: bytes) -> np.ndarray:
    """Corners of an ascii STL, parsed here: every facet must be exactly ``facet normal n n n /
    outer loop / vertex x y z (three times) / endloop / endfacet``; the first that is not is
    named by its line. (trimesh prints tracebacks on stderr for such files.)"""
    text = decode_text(data, "STL")
    corners = _ascii_fast(text)
    return corners if corners is not None else _ascii_checked(text)


_FACET_TOKENS = 21  # facet normal n n n outer loop (vertex x y z) x 3 endloop endfacet
_KEYWORD_COLUMNS = {0: "facet", 1: "normal", 5: "outer", 6: "loop", 7: "vertex", 11: "vertex",
                    15: "vertex", 19: "endloop", 20: "endfacet"}
_CORNER_COLUMNS = [8, 9, 10, 12, 13, 14, 16, 17, 18]


def _ascii_fast(text: str) -> np.ndarray | None:
    """Corners of one well-formed solid, in vectorized passes; None for anything else."""
    tokens = text.lower().split()
    if not tokens or tokens[0] != "solid" or "facet" not in tokens[:64]:
        return None
    first = tokens.index("facet", 0, 64)
    tail = next((k for k in range(len(tokens) - 1, max(first, len(tokens) - 64) - 1, -1)
                 if tokens[k] == "endsolid"), None)
    if tail is None or (tail - first) % _FACET_TOKENS:
        return None
    body = np.array(tokens[first:tail], dtype=object).reshape(-1, _FACET_TOKENS)
    if any(np.any(body[:, c] != word) for c, word in _KEYWORD_COLUMNS.items()):
        return None
    try:
        np.asarray(body[:, 2:5].ravel(), dtype=np.float64)  # the normals must be numbers
        values = np.asarray(body[:, _CORNER_COLUMNS].ravel(), dtype=np.float64)
    except ValueError:
        return None
    return values.reshape(-1, 3)


def _ascii_checked(text: str) -> np.ndarray:
    """Facet by facet (several solids, odd spacing), naming the first malformed facet."""
    facets = list(_FACET.finditer(text))
    starts = {m.start() for m in facets}
    keywords = list(_KEYWORD.finditer(text))
    for key in keywords:
        if key.group(1).lower() == "facet" and key.start() not in starts:
            line = text.count("\n", 0, key.start()) + 1
            content = text[key.start():].split("\n", 1)[0].strip()
            raise MeshError(f"ascii STL: malformed facet at line {line} ({content[:60]!r}; "
                            "expected 'facet normal nx ny nz', 'outer loop', three 'vertex x y "
                            "z', 'endloop', 'endfacet')")
    if not keywords or keywords[-1].group(1).lower() != "endsolid":
        raise MeshError("ascii STL is truncated (no 'endsolid' after the last facet)")
    if not facets:
        return np.zeros((0, 3))
    values = np.array([x for m in facets for x in m.groups()[3:]], dtype=np.float64)
    return values.reshape(-1, 3)


def first_use_order(faces: np.ndarray) -> np.ndarray:
    """The vertex ids in the order the faces first use them: reading the faces back from an
    STL numbers the vertices so (id ``k`` of the file read back is ``order[k]``)."""
    _, first = np.unique(faces.ravel(), return_index=True)
    return faces.ravel()[np.sort(first)]


def warn_stl_numbering(faces: np.ndarray, n_vertices: int, name: str) -> None:
    used = first_use_order(faces)
    if len(used) != n_vertices or np.any(used != np.arange(n_vertices)):
        dropped = n_vertices - len(used)
        lost = (f"{how_many(dropped, 'unreferenced vertex is', 'unreferenced vertices are')} "
                "dropped and " if dropped else "")
        warnings.warn(
            f"{name}: STL stores only triangles; {lost}vertices will be renumbered by first "
            "use on reading",
            RenumberedWarning,
            stacklevel=4,
        )



def unstored_stl(mesh: MeshData) -> list[str]:
    """What :func:`write_stl` cannot store: everything but a 16-bit ``stl_attribute``."""
    names = [f"per-vertex {k}" for k in mesh.attributes]
    names += [f"per-face {k}" for k, a in mesh.face_attributes.items()
              if not (k == "stl_attribute" and _fits_u16(a))]
    names += [f"per-corner {k}" for k in mesh.corner_attributes]
    if not names:
        return []
    return [f"STL stores triangles only: {', '.join(names)} not written"]


def _fits_u16(a: np.ndarray) -> bool:
    a = np.asarray(a)
    return (a.ndim == 1 and a.dtype.kind in "iub"
            and (a.size == 0 or (a.min() >= 0 and a.max() <= 0xFFFF)))


def write_stl(fh, tmp: str, mesh: MeshData, ascii: bool) -> None:
    v, f = mesh.vertices, mesh.faces
    if ascii:
        _write_ascii(fh, face_normals(v, f), v[f])
        return
    rec = np.zeros(len(f), dtype=_STL_DTYPE)
    rec["normal"] = face_normals(v, f)
    rec["corners"] = v[f]
    attr = mesh.face_attributes.get("stl_attribute")
    if attr is not None and _fits_u16(attr):
        rec["attr"] = attr
    fh.write(b"binary STL written by surfinpaint".ljust(80, b" "))
    fh.write(struct.pack("<I", len(f)))
    fh.write(rec.tobytes())


#: One ascii facet; corners with 17 significant digits: read back, they are the same float64s
_ASCII_FACET = ("facet normal {} {} {}\n outer loop\n"
                + "  vertex {} {} {}\n" * 3 + " endloop\nendfacet\n").replace("{}", "%.17g")


def _write_ascii(fh, normals: np.ndarray, corners: np.ndarray, chunk: int = 65536) -> None:
    fh.write(b"solid surfinpaint\n")
    rows = np.concatenate([normals[:, None, :], corners], axis=1).reshape(len(normals), 12)
    for start in range(0, len(rows), chunk):  # chunks of facets: the text in bounded memory
        block = rows[start:start + chunk]
        fh.write(((_ASCII_FACET * len(block)) % tuple(block.ravel().tolist())).encode("ascii"))
    fh.write(b"endsolid surfinpaint\n")
