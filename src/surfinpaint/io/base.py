"""What the format readers share: the warning class, polygon fan triangulation, messages."""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import IO

import numpy as np

from surfinpaint.errors import MeshError, agreeing, how_many, preview

__all__ = ["DataNotReturnedWarning", "MeshWarning"]


class MeshWarning(UserWarning):
    """Something about a mesh file worth knowing that does not stop reading or writing it."""


class RenumberedWarning(MeshWarning):
    """A mesh written to STL, which stores only triangles, will not read back with its vertex
    numbering (:func:`~surfinpaint.io.stl.first_use_order`). Its own category so that a
    caller that knows the numbering it matters for is kept (a filled STL scan: its
    original vertices keep their ids) can leave it out."""


class DataNotReturnedWarning(MeshWarning):
    """:func:`~surfinpaint.io.formats.read_mesh` read per-vertex, per-face or per-corner data
    (colours, normals, UVs, ...) that it does not return (``read_mesh_data`` does). Its own
    category so that a caller that writes no mesh (listing holes, drawing pictures) can
    ignore it while other warnings about the file still show."""


def describe(exc: BaseException) -> str:
    """The exception's type and first line, for a message."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0][:200]}" if text else type(exc).__name__


@dataclass
class Parsed:
    """What a format reader found, before polygons are triangulated.

    ``counts`` and ``flat`` are the polygons (corner counts, concatenated vertex ids);
    ``face_attributes`` have one row per polygon, ``corner_values`` one ``(c, k)`` float row
    per corner of ``flat`` (NaN: none); ``dropped`` names what the file holds that cannot be
    carried (each becomes a :class:`MeshWarning`).
    """

    vertices: np.ndarray
    counts: np.ndarray
    flat: np.ndarray
    attributes: dict[str, np.ndarray] = field(default_factory=dict)
    face_attributes: dict[str, np.ndarray] = field(default_factory=dict)
    corner_values: dict[str, np.ndarray] = field(default_factory=dict)
    metadata: dict[str, str] = field(default_factory=dict)
    dropped: list[str] = field(default_factory=list)


def triangulate(counts: np.ndarray, name: str) -> tuple[np.ndarray, np.ndarray]:
    """Fan-triangulate polygons given by their corner counts.

    Returns
    -------
    corners : (t, 3) int array
        Each triangle's corners as positions in the concatenated corner list: a polygon with
        k corners ``p0 .. p(k-1)`` becomes ``(p0, p_i, p_i+1)``, i = 1 .. k-2, in its place.
    owner : (t,) int array
        The polygon of each triangle.
    """
    counts = np.asarray(counts, dtype=np.int64)
    if counts.size and counts.min() < 3:
        bad = np.flatnonzero(counts < 3)
        raise MeshError(f"faces with fewer than three corners: {ids(bad)}", path=name,
                        faces=bad[:50].tolist())
    if counts.size == 0 or counts.max() == 3:
        return np.arange(3 * len(counts)).reshape(-1, 3), np.arange(len(counts))
    n_poly = int(np.count_nonzero(counts > 3))
    warnings.warn(
        f"{name}: {how_many(n_poly, 'polygon face', 'polygon faces')} with more than three "
        f"corners {agreeing(n_poly, 'was', 'were')} fan-triangulated",
        MeshWarning,
        stacklevel=4,
    )
    start = np.concatenate([[0], np.cumsum(counts)[:-1]])
    n_tri = counts - 2
    owner = np.repeat(np.arange(len(counts)), n_tri)
    # j = 1 .. k-2 within each polygon
    j = np.arange(owner.size) - np.repeat(np.cumsum(n_tri) - n_tri, n_tri) + 1
    s = start[owner]
    return np.column_stack([s, s + j, s + j + 1]), owner


def ids(values: np.ndarray, limit: int = 10) -> str:
    """A short preview of ids for a message."""
    return preview(np.asarray(values).tolist(), limit)


def decode_text(data: bytes, what: str) -> str:
    """The text of a text-format file: UTF-8 (a leading byte-order mark dropped), or Latin-1
    when it is not UTF-8 (accented comments and group names from older exporters; numbers and
    keywords are ASCII either way). A NUL byte means a binary file."""
    nul = data.find(b"\0")
    if nul >= 0:
        raise MeshError(f"not a text {what} file (a NUL byte at offset {nul})")
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return data.decode("latin-1")



def tokens_per_line(lines: list[str]) -> np.ndarray:
    """Whitespace-separated tokens on each line."""
    return np.fromiter(map(len, map(str.split, lines)), dtype=np.int64, count=len(lines))


def xyz_rows(lines: list[str]) -> np.ndarray:
    """The first three numbers of each line (OBJ w or OFF colour columns are skipped)."""
    ntok = tokens_per_line(lines)
    if np.any(ntok < 3):
        k = int(np.flatnonzero(ntok < 3)[0])
        raise MeshError(f"vertex {k} has fewer than three coordinates", vertices=[k])
    try:
        values = np.array(" ".join(lines).split(), dtype=np.float64)
    except ValueError as exc:
        raise MeshError(f"non-numeric vertex coordinate ({describe(exc)})") from None
    if np.all(ntok == 3):
        return values.reshape(-1, 3)
    # colour or normal columns after x y z
    start = np.cumsum(ntok) - ntok
    return values[start[:, None] + np.arange(3)]



def write_rows(fh: IO[bytes], row: str, a: np.ndarray, chunk: int = 65536) -> None:
    """Text rows via one %-format per chunk (much faster than np.savetxt's row loop).
    %.17g round-trips float64 exactly."""
    for k in range(0, len(a), chunk):
        block = a[k:k + chunk]
        fh.write((row * len(block) % tuple(block.ravel().tolist())).encode("ascii"))

