"""A mesh with everything a file carries per vertex, per face and per face corner.

:class:`MeshData` is what :func:`~surfinpaint.io.read_mesh_data` returns and
:func:`~surfinpaint.io.write_mesh_data` writes: vertices and triangles as
:func:`~surfinpaint.io.read_mesh` returns them, plus

``attributes``
    per-vertex arrays, ``n`` rows (colours, normals, texture coordinates, scalars, overlays);
``face_attributes``
    per-triangle arrays, ``f`` rows (a polygon's value is repeated on its fan triangles);
``corner_attributes``
    per-corner arrays, shape ``(f, 3, k)``: data that differs between the faces around one
    vertex (texture coordinates across a UV seam);
``metadata``
    file-level strings (PLY comments, GIFTI metadata, OBJ material libraries).

Names follow one convention in every format, so a fill and a writer can tell what an array
is: ``"color"`` ``(n, 3|4)`` (uint8 0..255 or float 0..1), ``"normal"`` ``(n, 3)``, ``"uv"``
``(n, 2)`` (texture coordinates), other names as the file spells them.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field

import numpy as np

__all__ = ["MeshData"]


def _rows(kind: str, arrays: Mapping[str, np.ndarray], n: int) -> dict[str, np.ndarray]:
    out = {}
    for name, a in arrays.items():
        a = np.asarray(a)
        if a.ndim == 0 or len(a) != n:
            raise ValueError(f"{kind} {name!r} has {a.shape[0] if a.ndim else 0} rows, "
                             f"expected {n}")
        out[str(name)] = a
    return out


@dataclass(frozen=True)
class MeshData:
    """Vertices, triangles and what the file carries beside them.

    Unpacks like the pair :func:`~surfinpaint.io.read_mesh` returns:
    ``vertices, faces = read_mesh_data(path)``.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
    attributes : dict of str to (n, ...) array
        Per-vertex data.
    face_attributes : dict of str to (f, ...) array
        Per-triangle data.
    corner_attributes : dict of str to (f, 3, k) array
        Per-face-corner data (a vertex may have several values).
    metadata : dict of str to str
        File-level metadata.

    Raises
    ------
    ValueError
        When an array does not have one row per vertex, face or (face, corner).
    """

    vertices: np.ndarray
    faces: np.ndarray
    attributes: dict[str, np.ndarray] = field(default_factory=dict)
    face_attributes: dict[str, np.ndarray] = field(default_factory=dict)
    corner_attributes: dict[str, np.ndarray] = field(default_factory=dict)
    metadata: dict[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        n, f = len(self.vertices), len(self.faces)
        object.__setattr__(self, "attributes", _rows("attribute", self.attributes, n))
        object.__setattr__(self, "face_attributes",
                           _rows("face attribute", self.face_attributes, f))
        corners = _rows("corner attribute", self.corner_attributes, f)
        for name, a in corners.items():
            if a.ndim != 3 or a.shape[1] != 3:
                raise ValueError(f"corner attribute {name!r} has shape {a.shape}, "
                                 "expected (f, 3, k)")
        object.__setattr__(self, "corner_attributes", corners)
        object.__setattr__(self, "metadata", {str(k): str(v) for k, v in self.metadata.items()})

    def __iter__(self) -> Iterator[np.ndarray]:
        yield self.vertices
        yield self.faces

    def appended(self, vertices: np.ndarray, faces: np.ndarray, *,
                 attributes: Mapping[str, np.ndarray] | None = None,
                 face_attributes: Mapping[str, np.ndarray] | None = None,
                 corner_attributes: Mapping[str, np.ndarray] | None = None) -> MeshData:
        """A copy with new vertices and faces appended after the existing ones.

        Parameters
        ----------
        vertices : (k, 3) float array
            New vertices, numbered ``n .. n + k - 1``.
        faces : (g, 3) int array
            New triangles, in the combined numbering.
        attributes, face_attributes, corner_attributes : dict of str to array
            The new rows of every existing attribute (``k``, ``g`` and ``g`` rows): each
            attribute must be given, so none is extended with invented values.

        Raises
        ------
        ValueError
            Naming a missing, unknown or wrongly shaped attribute.
        """
        vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
        faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
        grown = {}
        for kind, old, new in (("attribute", self.attributes, attributes),
                               ("face attribute", self.face_attributes, face_attributes),
                               ("corner attribute", self.corner_attributes,
                                corner_attributes)):
            new = dict(new or {})
            missing, unknown = sorted(set(old) - set(new)), sorted(set(new) - set(old))
            if missing or unknown:
                raise ValueError(f"new rows: {kind}s missing {missing}, unknown {unknown}")
            rows = len(vertices) if kind == "attribute" else len(faces)
            grown[kind] = {}
            for name, a in old.items():
                b = np.asarray(new[name])
                if b.shape[1:] != a.shape[1:] or len(b) != rows:
                    raise ValueError(f"new rows of {kind} {name!r}: shape {b.shape}, expected "
                                     f"({rows}, {', '.join(map(str, a.shape[1:]))})")
                grown[kind][name] = np.concatenate([a, b.astype(a.dtype, copy=False)])
        return MeshData(np.concatenate([self.vertices, vertices]),
                        np.concatenate([self.faces, faces]), grown["attribute"],
                        grown["face attribute"], grown["corner attribute"], dict(self.metadata))


# ------------------------------------------------------------ columns of a file <-> arrays

#: Named column groups stored as one array: (array name, its columns in file order).
COLUMN_GROUPS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("color", ("red", "green", "blue", "alpha")),
    ("color", ("red", "green", "blue")),
    ("normal", ("nx", "ny", "nz")),
    ("uv", ("u", "v")),
    ("st", ("s", "t")),
    ("texture_uv", ("texture_u", "texture_v")),
)


def group_columns(columns: Mapping[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Arrays from a file's named scalar columns (PLY properties), in the file's order.

    ``red, green, blue[, alpha]`` -> ``color``; ``nx, ny, nz`` -> ``normal``; ``u, v`` ->
    ``uv`` (``s, t`` -> ``st``, ``texture_u, texture_v`` -> ``texture_uv``); ``name_0 ..
    name_{k-1}`` -> ``name`` with ``k`` columns; members of one group must share a dtype.
    Everything else stays a 1-D array under its own name. :func:`split_columns` inverts it.
    """
    names = list(columns)
    taken: dict[str, tuple[str, tuple[str, ...]]] = {}
    for group, members in COLUMN_GROUPS:
        if (group not in {g for g, _ in taken.values()} and group not in columns
                and all(m in columns and m not in taken for m in members)
                and len({columns[m].dtype for m in members}) == 1):
            for m in members:
                taken[m] = (group, members)
    for name in names:
        base, _, index = name.rpartition("_")
        if name in taken or not base or index != "0":
            continue
        members = []
        while f"{base}_{len(members)}" in columns:
            members.append(f"{base}_{len(members)}")
        members = tuple(members)
        if (len(members) > 1 and base not in columns and not any(m in taken for m in members)
                and len({columns[m].dtype for m in members}) == 1):
            for m in members:
                taken[m] = (base, members)
    out: dict[str, np.ndarray] = {}
    for name in names:
        if name not in taken:
            out[name] = np.asarray(columns[name])
        elif taken[name][0] not in out:
            group, members = taken[name]
            out[group] = np.column_stack([columns[m] for m in members])
    return out


def split_columns(arrays: Mapping[str, np.ndarray]) -> list[tuple[str, np.ndarray]]:
    """Named 1-D columns for a file, the inverse of :func:`group_columns`.

    Raises
    ------
    ValueError
        For an array with more than two dimensions (it is per corner, not per row).
    """
    out = []
    for name, a in arrays.items():
        a = np.asarray(a)
        if a.ndim == 1:
            out.append((name, a))
            continue
        if a.ndim != 2:
            raise ValueError(f"{name!r} has shape {a.shape}: one value or one row per element")
        members = next((m for g, m in COLUMN_GROUPS if g == name and len(m) == a.shape[1]),
                       tuple(f"{name}_{k}" for k in range(a.shape[1])))
        out += [(m, a[:, k]) for k, m in enumerate(members)]
    return out


def per_vertex(flat: np.ndarray, values: np.ndarray, n: int) -> np.ndarray | None:
    """Per-corner values as per-vertex ones when every vertex has one value on all its
    corners (NaN corners count as no value; a vertex with none gets NaN), else None.

    Parameters
    ----------
    flat : (c,) int array
        The vertex of each corner.
    values : (c, k) float array
        The value of each corner.
    n : int
        Number of vertices.
    """
    known = ~np.isnan(values).any(axis=1)
    out = np.full((n, values.shape[1]), np.nan)
    out[flat[known]] = values[known]
    same = np.all(out[flat[known]] == values[known], axis=1)
    return out if np.all(same) else None


def seam_vertices(flat: np.ndarray, values: np.ndarray, n: int) -> np.ndarray:
    """Vertices whose corners carry different values (where :func:`per_vertex` fails)."""
    known = ~np.isnan(values).any(axis=1)
    out = np.full((n, values.shape[1]), np.nan)
    out[flat[known]] = values[known]
    differ = ~np.all(out[flat[known]] == values[known], axis=1)
    return np.unique(flat[known][differ])
