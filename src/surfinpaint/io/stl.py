"""STL, binary and ascii: a triangle soup whose equal corners are merged on reading."""

from __future__ import annotations

import io
import struct
import warnings
from pathlib import Path

import numpy as np

from surfinpaint.errors import MeshError
from surfinpaint.geometry.mesh import face_normals
from surfinpaint.io.base import MeshWarning, decode_text


def read_stl(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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

    text = decode_text(data, "STL")
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



def warn_stl_numbering(faces: np.ndarray, n_vertices: int, name: str) -> None:
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



def write_stl(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    rec = np.zeros(len(f), dtype=_STL_DTYPE)
    rec["normal"] = face_normals(v, f)
    rec["corners"] = v[f]
    fh.write(b"binary STL written by surfinpaint".ljust(80, b" "))
    fh.write(struct.pack("<I", len(f)))
    fh.write(rec.tobytes())

