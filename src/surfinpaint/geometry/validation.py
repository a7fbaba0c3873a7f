"""Checks that a triangle mesh can be processed, with messages naming the offending ids.

:func:`validate_mesh` rejects what no later step can work with (broken arrays, duplicate
faces, non-manifold edges, inconsistent orientation) and reports the rest (components,
unreferenced vertices, boundary loops, bow-tie vertices, degenerate faces) in a
:class:`MeshReport`. Everything is vectorized: a million-face mesh validates in seconds.

Degenerate faces are reported, not refused. A face that uses a vertex twice is no triangle:
its two edges between the same two vertices run both ways and join nothing, so it is left
out of the topology (:mod:`surfinpaint.geometry.degenerate`: the edges, holes and checks); a
fill keeps it in the output as it is. A face of three distinct vertices with zero area
(:func:`zero_area_faces`) is a triangle of the surface, joined to its neighbours; only a
fill's numerics break on it (cotangent weights, normals, the conformal map), so a hole
whose fill's neighbourhood holds one is filled from fewer rings where it can, else left
open (:mod:`surfinpaint.fill.hole_steps`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from surfinpaint.errors import MeshError, agreeing, how_many, mesh_size, preview
from surfinpaint.geometry.degenerate import repeated_vertex_faces, triangle_rows
from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.geometry.mesh import boundary_loops, face_blocks
from surfinpaint.geometry.orientation import orient_faces

__all__ = ["MeshReport", "check_arrays", "check_loop", "check_topology", "degenerate_notes",
           "face_ids", "face_text", "nonmanifold_vertices", "validate_mesh", "zero_area_faces"]

# A face is degenerate when its area is below this times its longest edge squared, i.e. its
# height is below 2e-12 of its longest edge: far above float64 round-off (~1e-16) and far
# below any triangle the cotangent weights can use.
ZERO_AREA_RTOL = 1e-12


@dataclass
class MeshReport:
    """What :func:`validate_mesh` found in a mesh that passed.

    Attributes
    ----------
    n_vertices, n_faces, n_edges : int
        Counts; ``n_vertices`` includes unreferenced vertices.
    n_components : int
        Edge-connected components of the faces (unreferenced vertices not counted).
    unreferenced_vertices : (k,) int array
        Vertices used by no face; kept untouched by every step.
    boundary_loop_lengths : list of int
        Number of vertices of each boundary loop (holes and outer borders), longest first.
    nonmanifold_vertices : (k,) int array
        Bow-tie vertices, where the faces around the vertex form more than one fan.
    euler_characteristic : int
        ``V - E + F`` over referenced vertices (the faces that repeat a vertex left out).
    path : str or None
        The file the mesh came from, if given.
    repeated_vertex_faces, zero_area_faces : (k,) int arrays
        Degenerate faces (:func:`degenerate_notes`): those that use a vertex twice (left
        out of the topology: edges, components, boundary loops) and those of three distinct
        vertices with zero area.
    """

    n_vertices: int
    n_faces: int
    n_edges: int
    n_components: int
    unreferenced_vertices: np.ndarray
    boundary_loop_lengths: list[int]
    nonmanifold_vertices: np.ndarray
    euler_characteristic: int
    path: str | None = None
    notes: list[str] = field(default_factory=list)
    repeated_vertex_faces: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    zero_area_faces: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))

    @property
    def n_boundary_loops(self) -> int:
        return len(self.boundary_loop_lengths)

    @property
    def is_closed(self) -> bool:
        return not self.boundary_loop_lengths

    def summary(self) -> str:
        """A few lines of text for the CLI."""
        head = f"{self.path}: " if self.path else ""
        loops = how_many(self.n_boundary_loops, "boundary loop", "boundary loops")
        return "\n".join([f"{head}{mesh_size(self.n_vertices, self.n_faces)}, "
                          f"{how_many(self.n_components, 'component', 'components')}, {loops}",
                          *self.notes])


def _fail(message: str, path: str | None, **ids) -> MeshError:
    return MeshError(message, path=path, **ids)


def face_ids(faces, *, path: str | None = None) -> np.ndarray:
    """``faces`` as an int64 array of vertex ids, never truncated.

    Integer arrays are taken as they are; float arrays (what ``np.loadtxt``, MATLAB or a
    JSON reader give) when every id is a whole number, which is then exact. Anything else
    is refused: a float id that is not a whole number would otherwise be truncated to
    another vertex.

    Raises
    ------
    MeshError
        For ids that are not whole numbers (naming the faces), ids past the int64 range,
        rows of different lengths (naming the odd faces), and booleans, complex numbers or
        other non-numbers.
    """
    try:
        f = np.asarray(faces)
    except ValueError:  # rows of different lengths ("inhomogeneous shape")
        raise _fail(_ragged(faces), path) from None
    if f.dtype == object:  # numpy < 2 makes an object array of ragged rows
        raise _fail(_ragged(faces), path)
    if np.issubdtype(f.dtype, np.integer):
        if f.dtype == np.uint64 and f.size and int(f.max()) > np.iinfo(np.int64).max:
            raise _fail(f"faces use vertex ids past the int64 range (largest {int(f.max())})",
                        path)
        return f.astype(np.int64, copy=False)
    if not np.issubdtype(f.dtype, np.floating):
        raise _fail(f"faces must be integer vertex ids, got dtype {f.dtype}", path)
    whole = np.isfinite(f) & (f == np.round(f)) & (np.abs(f) < 2.0**62)
    rows = whole.reshape(len(f), -1).all(axis=1) if f.ndim else whole.reshape(1)
    bad = np.flatnonzero(~rows)
    if bad.size:
        shown = ", ".join(f"{int(i)} {f[i].tolist()}" for i in bad[:5])
        more = f" and {bad.size - 5} more" if bad.size > 5 else ""
        raise _fail(f"{how_many(bad.size, 'face has', 'faces have')} vertex ids that are not "
                    f"whole numbers: {shown}{more}", path, faces=bad[:100].tolist())
    return f.astype(np.int64)


def _ragged(faces) -> str:
    """What is wrong with a face list whose rows have different lengths."""
    try:
        lengths = [len(row) for row in faces]
    except TypeError:
        return "faces must be an (f, 3) array of vertex ids, got rows that are not sequences"
    common = max(set(lengths), key=lambda n: (lengths.count(n), n == 3))
    odd = [i for i, n in enumerate(lengths) if n != common]
    shown = ", ".join(f"{i} ({lengths[i]} ids)" for i in odd[:5])
    more = f" and {len(odd) - 5} more" if len(odd) > 5 else ""
    return (f"faces must be an (f, 3) array of vertex ids: most faces have {common} ids, "
            f"faces {shown}{more} do not")


def check_arrays(vertices: np.ndarray, faces: np.ndarray, *, path: str | None = None) -> None:
    """Basic checks every mesh must pass: shapes, emptiness, finite coordinates, index range.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
    path : str, optional
        File name to put in the error message.

    Raises
    ------
    MeshError
        For wrong shapes or dtypes, no vertices, no faces, NaN/inf coordinates (naming the
        vertices) and negative, too large or non-whole face indices (naming the faces;
        whole-number floats are taken, see :func:`face_ids`).
    """
    v = np.asarray(vertices)
    f = face_ids(faces, path=path)  # rows of different lengths are named here
    if v.ndim != 2 or v.shape[1] != 3:
        raise _fail(f"vertices must be an (n, 3) array, got shape {v.shape}", path)
    if f.ndim != 2 or f.shape[1] != 3:
        raise _fail(f"faces must be an (f, 3) array of triangles, got shape {f.shape}", path)
    if not np.issubdtype(v.dtype, np.number) or np.issubdtype(v.dtype, np.complexfloating):
        raise _fail(f"vertices must be real numbers, got dtype {v.dtype}", path)
    if len(v) == 0:
        raise _fail("mesh has no vertices", path)
    if len(f) == 0:
        raise _fail("mesh has no faces", path)
    # one reduction over each whole array first (this runs on every read, fill and write
    # of a mesh: the per-row masks cost ~30x more); the rows only to name the offenders
    if not np.isfinite(v).all():
        bad = np.flatnonzero(~np.isfinite(v).all(axis=1))
        raise _fail(f"{how_many(bad.size, 'vertex has', 'vertices have')} NaN or infinite "
                    f"coordinates: {preview(bad)}",
                    path, vertices=bad[:100].tolist())
    if f.min() < 0:
        negative = np.flatnonzero((f < 0).any(axis=1))
        raise _fail(f"{how_many(negative.size, 'face has', 'faces have')} negative vertex "
                    f"ids: {preview(negative)}",
                    path, faces=negative[:100].tolist())
    if f.max() >= len(v):
        high = np.flatnonzero((f >= len(v)).any(axis=1))
        raise _fail(f"{how_many(high.size, 'face uses', 'faces use')} vertex ids >= the "
                    f"vertex count {len(v)} "
                    f"(largest {int(f.max())}): {preview(high)}", path,
                    faces=high[:100].tolist())


def zero_area_faces(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Ids of faces whose area is at most ``ZERO_AREA_RTOL`` times their longest edge squared
    (collinear or coincident corners)."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    columns = [np.ascontiguousarray(v[:, k]) for k in range(3)]
    found = [np.flatnonzero(_zero_area(columns, f[block])) + block.start
             for block in face_blocks(len(f))]
    return np.concatenate(found) if found else np.zeros(0, np.int64)


def _zero_area(columns: list[np.ndarray], f: np.ndarray) -> np.ndarray:
    """Per face of ``f``: whether it has zero area (see :func:`zero_area_faces`)."""
    a, b = [], []
    for c in columns:
        c0 = c[f[:, 0]]
        a.append(c[f[:, 1]] - c0)
        b.append(c[f[:, 2]] - c0)
    # in units of each face's largest edge component: scale-free, no overflow at 1e+200 and
    # no underflow at 1e-200 when squared
    unit = np.maximum.reduce([np.abs(x) for x in a + b])
    unit[unit == 0] = 1.0
    a, b = [x / unit for x in a], [x / unit for x in b]
    area2 = np.sqrt((a[1] * b[2] - a[2] * b[1]) ** 2 + (a[2] * b[0] - a[0] * b[2]) ** 2
                    + (a[0] * b[1] - a[1] * b[0]) ** 2)
    longest2 = np.maximum(np.maximum(a[0] ** 2 + a[1] ** 2 + a[2] ** 2,
                                     b[0] ** 2 + b[1] ** 2 + b[2] ** 2),
                          (b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2 + (b[2] - a[2]) ** 2)
    return 0.5 * area2 <= ZERO_AREA_RTOL * longest2


def degenerate_notes(faces: np.ndarray, repeated: np.ndarray, flat: np.ndarray) -> list[str]:
    """What a fill does with the degenerate faces of ``faces`` (ids ``repeated``: a vertex
    twice; ``flat``: zero area), one sentence for each kind found, naming them."""
    notes = []
    if repeated.size:
        notes.append(f"{how_many(repeated.size, 'face uses', 'faces use')} the same vertex "
                     "twice (no triangles: kept as they are, left out of the holes and the fills): "
                     f"{face_text(repeated, faces)}")
    if flat.size:
        notes.append(f"{how_many(flat.size, 'face has', 'faces have')} zero area (collinear "
                     "or coincident corners; "
                     "kept as they are; a hole whose fill would reach them is filled from "
                     f"fewer rings where it can, else left open): {face_text(flat, faces)}")
    return notes


def validate_mesh(vertices: np.ndarray, faces: np.ndarray, *, path: str | None = None,
                  table: EdgeTable | None = None) -> MeshReport:
    """Check a triangle mesh and describe it.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
    path : str, optional
        File name used in messages and stored in the report.
    table : EdgeTable, optional
        The edge table of the faces that are triangles (``degenerate.triangle_rows``), if
        built (it is reused by ``find_holes``): the checks are then O(E) passes over it.

    Returns
    -------
    MeshReport
        Counts, components, unreferenced vertices, boundary loops, bow-tie vertices and
        degenerate faces. Several components and unreferenced vertices are fine (reported,
        kept untouched); so are degenerate faces (reported in the notes: faces that use a
        vertex twice are left out of the edges, components and loops; zero-area faces are
        in them).

    Raises
    ------
    MeshError
        Naming the offending ids, for: wrong array shapes, an empty mesh, NaN/inf coordinates,
        out-of-range or negative indices, duplicate faces (same three vertices), non-manifold
        edges (more than two faces) and inconsistently oriented neighbouring faces (a shared
        edge traversed in the same direction by both).

    Examples
    --------
    >>> v = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    >>> r = validate_mesh(v, np.array([[0, 1, 2], [2, 1, 3]]))
    >>> r.n_components, r.boundary_loop_lengths
    (1, [4])
    """
    check_arrays(vertices, faces, path=path)
    v = np.asarray(vertices, dtype=np.float64)
    every = np.asarray(faces, dtype=np.int64)
    f, repeated, rows = triangle_rows(every)
    n = len(v)
    table, flat = check_topology(v, f, table, path=path)
    if rows is not None:
        flat = rows[flat]

    referenced = np.zeros(n, dtype=bool)
    referenced[f.ravel()] = True
    unreferenced = np.flatnonzero(~referenced)
    _, labels = table.vertex_components
    n_components = int(np.count_nonzero(np.bincount(labels[np.flatnonzero(referenced)])))
    bowtie = _bowtie(table)
    loop_lengths: list[int] = []
    if np.any(table.count == 1):
        loop_lengths = [len(loop) for loop in boundary_loops(f, table)]
    n_edges = table.n_edges

    report = MeshReport(
        n_vertices=n, n_faces=len(every), n_edges=n_edges, n_components=n_components,
        unreferenced_vertices=unreferenced, boundary_loop_lengths=loop_lengths,
        nonmanifold_vertices=bowtie,
        euler_characteristic=int(referenced.sum()) - n_edges + len(f), path=path,
        repeated_vertex_faces=repeated, zero_area_faces=flat,
    )
    if n_components > 1:
        report.notes.append(f"{n_components} separate components")
    if unreferenced.size:
        said = how_many(unreferenced.size, "unreferenced vertex", "unreferenced vertices")
        report.notes.append(f"{said} (kept untouched): {preview(unreferenced)}")
    if bowtie.size:
        report.notes.append(how_many(bowtie.size, "non-manifold (bow-tie) vertex",
                                     "non-manifold (bow-tie) vertices") + f": {preview(bowtie)}")
    report.notes += degenerate_notes(every, repeated, flat)
    return report


def check_topology(vertices: np.ndarray, faces: np.ndarray, table: EdgeTable | None = None,
                   *, path: str | None = None) -> tuple[EdgeTable, np.ndarray]:
    """The checks of :func:`validate_mesh` that follow :func:`check_arrays` (which the
    caller has run), without the report: a caller that needs only the errors (``fill_holes``)
    does not pay for the bow-tie walk, the components and the boundary loops. ``faces``
    are triangles: the faces that repeat a vertex left out (``degenerate.triangle_rows``).

    Returns
    -------
    EdgeTable
        ``table``, or the one built here.
    (k,) int array
        The ids of the zero-area faces (:func:`zero_area_faces`), which are not refused.

    Raises
    ------
    MeshError
        As :func:`validate_mesh`, for duplicate faces, non-manifold edges and inconsistent
        orientation, in that order; and for faces repeating a vertex (the caller's to
        leave out).
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    repeated = repeated_vertex_faces(f)
    if repeated.size:
        raise _fail(f"{how_many(repeated.size, 'face uses', 'faces use')} the same vertex "
                    "twice (leave them out: "
                    f"triangle_rows): {face_text(repeated, f)}", path,
                    faces=repeated[:100].tolist())

    if table is None:
        table = EdgeTable.build(f, len(v))
    else:
        table.check_faces(f)
    pairs = table.interior_pairs()  # for both edge checks
    _check_duplicates(table, path, pairs)
    _check_edges(table, path, pairs)
    # per coordinate on 1-D arrays: several times faster than np.cross on (f, 3) gathers
    return table, zero_area_faces(v, f)


def _listing(shown: list[str], total: int) -> str:
    """Comma list of the shown items and how many more there are."""
    more = f" and {total - len(shown)} more" if total > len(shown) else ""
    return ", ".join(shown) + more


def face_text(ids: np.ndarray, f: np.ndarray) -> str:
    """The first ten faces of ``ids`` with their corners, and how many more."""
    return _listing([f"{int(i)} {tuple(int(x) for x in f[i])}" for i in ids[:10]], len(ids))


def _check_duplicates(table: EdgeTable, path: str | None, pairs=None) -> None:
    """Raise for faces with the same three vertices as another, naming each later copy with
    the face it repeats (in the order of the faces' sorted vertex triples). ``pairs``: the
    table's ``interior_pairs()``, when made."""
    # Two such faces share every edge and have the same vertex opposite it, so comparing the
    # opposite corners (corner k of face t is opposite half-edge 3 t + k) of the faces on
    # each edge finds them all in O(E); only edges with three or more faces need a sort.
    corner_vertex = table.faces.ravel()
    h1, h2 = table.interior_pairs() if pairs is None else pairs
    # compared block by block: the gathers' temporaries stay small (whole-mesh ones would
    # each be fresh memory)
    twin = np.empty(len(h1), dtype=bool)
    for block in face_blocks(len(h1)):
        np.equal(corner_vertex[h1[block]], corner_vertex[h2[block]], out=twin[block])
    suspects = [h1[twin] // 3, h2[twin] // 3]
    crowded = np.flatnonzero(table.count > 2)
    if crowded.size:
        h = np.concatenate([table.halfedges[table.start[e]:table.start[e + 1]]
                            for e in crowded])
        edge, opposite = table.face_edge.ravel()[h], corner_vertex[h]
        order = np.lexsort((opposite, edge))
        same = np.flatnonzero((edge[order[1:]] == edge[order[:-1]])
                              & (opposite[order[1:]] == opposite[order[:-1]]))
        suspects.append(h[order[np.r_[same, same + 1]]] // 3)
    faces_bad = np.unique(np.concatenate(suspects))
    if not faces_bad.size:
        return
    # the message as a sort of the sorted vertex triples of the faces involved gives it
    s = np.sort(table.faces[faces_bad], axis=1)
    order = np.lexsort((s[:, 2], s[:, 1], s[:, 0]))
    same = np.flatnonzero((s[order[1:]] == s[order[:-1]]).all(axis=1))
    first, dup = faces_bad[order[same]], faces_bad[order[same + 1]]
    text = _listing([f"{int(b)} (same vertices as {int(a)})"
                     for a, b in zip(first[:10], dup[:10], strict=True)], len(dup))
    # their edges are shared by three or more faces where the copies meet others: what
    # --repair removes (a lone doubled triangle it leaves, so the hint says where)
    raise _fail(f"{how_many(dup.size, 'duplicate face', 'duplicate faces')}: {text}; where the "
                "copies meet other faces, --repair (repair=True) removes the faces around "
                "them and fills the holes that leaves", path, faces=dup[:100].tolist())


def _check_edges(table: EdgeTable, path: str | None, pairs=None) -> None:
    """Raise for non-manifold edges and for interior edges whose two faces traverse them
    in the same direction (inconsistent orientation), naming the edges and faces.
    ``pairs``: the table's ``interior_pairs()``, when made."""
    count = table.count
    nonmanifold = np.flatnonzero(count > 2)
    if nonmanifold.size:
        edges = [(int(a), int(b)) for a, b in table.edges[nonmanifold[:100]]]
        text = _listing([f"({a}, {b}) in {int(count[i])} faces"
                         for (a, b), i in zip(edges[:10], nonmanifold[:10], strict=True)],
                        nonmanifold.size)
        raise _fail(f"{how_many(nonmanifold.size, 'non-manifold edge', 'non-manifold edges')} "
                    f"(shared by more than two faces): {text}; --repair (repair=True) removes "
                    "the faces around them and fills the holes that leaves", path, edges=edges)
    # interior edge: its two half-edges must run in opposite directions
    h1, h2 = table.interior_pairs() if pairs is None else pairs
    clash = np.flatnonzero(table.forward[h1] == table.forward[h2])
    if clash.size:
        h1, h2 = h1[clash], h2[clash]
        edges = [(int(a), int(b)) for a, b in zip(table.tails(h1[:100]), table.heads(h1[:100]),
                                                   strict=True)]
        faces_bad = np.unique(np.concatenate([h1, h2]) // 3)
        text = _listing([f"({a}, {b}) in faces {int(p // 3)} and {int(q // 3)}"
                         for (a, b), p, q in zip(edges[:10], h1[:10], h2[:10], strict=True)],
                        clash.size)
        said = how_many(clash.size, "shared edge is", "shared edges are")
        raise _fail(f"inconsistent face orientation: {said} traversed in the same direction "
                    f"by both faces: {text}; {_reorient_hint(table)}", path, edges=edges,
                    faces=faces_bad[:100].tolist())


def _reorient_hint(table: EdgeTable) -> str:
    """How to fix the orientation error: ``--repair`` for orientable pieces, nothing for the
    non-orientable ones (named)."""
    _, flipped, bad = orient_faces(table.faces)
    hint = ("--repair (repair=True) reorients each piece consistently, flipping "
            f"{how_many(len(flipped), 'face', 'faces')} (as trimesh.repair.fix_winding or "
            "MeshLab's Re-Orient all faces coherently do)")
    if not bad:
        return hint
    pieces = _listing([f"{how_many(len(p), 'face', 'faces')} ({', '.join(map(str, p[:5]))}"
                       f"{', ...' if len(p) > 5 else ''})" for p in bad[:10]], len(bad))
    told = (f"{how_many(len(bad), 'non-orientable piece', 'non-orientable pieces')} (like a Möbius "
            f"strip: no orientation of it is consistent, --repair leaves it as it is): {pieces}")
    return f"{told}; elsewhere {hint}" if len(flipped) else told


def _bowtie(table: EdgeTable) -> np.ndarray:
    """Bow-tie vertices from the edge table (see :func:`nonmanifold_vertices`): walk the fan
    of one corner of each vertex and compare its size with the vertex's corner count."""
    # Corner c = 3 t + k is vertex faces[t, k]; half-edge h = 3 t + k leaves corner
    # 3 t + (k + 1) % 3 (its tail corner) and arrives at corner 3 t + (k + 2) % 3.
    corner_vertex = table.faces.ravel()
    m = len(corner_vertex)
    if m == 0:
        return np.zeros(0, np.int64)
    # corner ids fit in int32 for any mesh this size, which halves the memory traffic
    ids = np.int32 if m < 2**31 - 1 else np.int64
    first = np.arange(0, m, 3, dtype=ids)[:, None]
    tail_corner = (first + np.array([1, 2, 0], dtype=ids)).ravel()
    head_corner = (first + np.array([2, 0, 1], dtype=ids)).ravel()
    del first
    # across[s][c]: the corner of the same vertex in the face across corner c's outgoing
    # (s = 0) or incoming (s = 1) edge; -1 on the border and across non-manifold edges
    h1, h2 = table.interior_pairs()
    at, ah, bt, bh = tail_corner[h1], head_corner[h1], tail_corner[h2], head_corner[h2]
    del tail_corner, head_corner, h1, h2
    reversed_ = corner_vertex[at] != corner_vertex[bt]  # b runs the other way (oriented)
    across = np.full((2, m), -1, dtype=ids)
    across[0, at] = np.where(reversed_, bh, bt)
    across[1, ah] = np.where(reversed_, bt, bh)
    across[0, bt] = np.where(reversed_, ah, at)
    across[1, bh] = np.where(reversed_, at, ah)
    del at, ah, bt, bh, reversed_
    n_corners = np.bincount(corner_vertex)
    start = np.empty(len(n_corners), dtype=ids)
    start[corner_vertex] = np.arange(m, dtype=ids)  # any one corner of each vertex
    used = np.flatnonzero(n_corners)
    start = start[used]
    ahead, closed = _walk_fans(across, start, across[0, start])
    behind, _ = _walk_fans(across, start, np.where(closed, -1, across[1, start]))
    return used[1 + ahead + behind != n_corners[used]]


def _walk_fans(across: np.ndarray, start: np.ndarray, step: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """From each corner ``start[i]``, first to ``step[i]`` (-1: nowhere), walk corner to
    corner across the edges, never straight back: the corners reached (``start`` not
    counted) and whether the walk came back to ``start`` (a closed fan)."""
    reached = np.zeros(len(start), dtype=np.int64)
    closed = np.zeros(len(start), dtype=bool)
    live = np.flatnonzero(step >= 0)
    cur, prev, home = step[live], start[live], start[live]
    while live.size:
        back = cur == home
        closed[live[back]] = True
        keep = ~back
        live, cur, prev, home = live[keep], cur[keep], prev[keep], home[keep]
        reached[live] += 1
        ahead = across[0, cur]
        cur, prev = np.where(ahead != prev, ahead, across[1, cur]), cur
        keep = cur >= 0
        live, cur, prev, home = live[keep], cur[keep], prev[keep], home[keep]
    return reached, closed


def nonmanifold_vertices(faces: np.ndarray) -> np.ndarray:
    """Bow-tie vertices: the faces around the vertex form more than one fan.

    Two faces at a vertex belong to the same fan when a chain of faces around the vertex,
    each sharing an edge through the vertex with the next, joins them; an edge with more than
    two faces joins none of them (so the ends of a non-manifold edge count here too). At a
    manifold vertex all its faces form one fan (a closed disk inside, an open one on the
    boundary). O(E): each vertex's fan is walked from one of its corners.

    Parameters
    ----------
    faces : (f, 3) int array

    Returns
    -------
    (k,) int64 array of vertex ids, sorted.

    Examples
    --------
    >>> nonmanifold_vertices(np.array([[0, 1, 2], [0, 3, 4]])).tolist()
    [0]
    """
    f = np.asarray(faces, dtype=np.int64)
    if f.size == 0:
        return np.zeros(0, np.int64)
    return _bowtie(EdgeTable.build(f))


def check_loop(faces: np.ndarray, loop: np.ndarray, *, path: str | None = None) -> None:
    """Check that ``loop`` is a simple boundary loop a hole filler can close.

    Parameters
    ----------
    faces : (f, 3) int array
    loop : (k,) int array
        Vertex ids in order around the hole (closing edge ``loop[-1] -> loop[0]`` implied).
    path : str, optional
        File name for the message.

    Raises
    ------
    MeshError
        When the loop has fewer than three vertices, visits a vertex twice, uses an edge that
        is not a boundary edge (naming the edges), or passes through a bow-tie vertex (naming
        it: filling there would make the surface non-manifold).
    """
    f = np.asarray(faces, dtype=np.int64)
    loop = np.asarray(loop, dtype=np.int64).ravel()
    if len(loop) < 3:
        raise _fail(f"boundary loop needs at least 3 vertices, has {len(loop)}", path,
                    vertices=loop.tolist())
    values, counts = np.unique(loop, return_counts=True)
    if np.any(counts > 1):
        twice = values[counts > 1]
        raise _fail(f"boundary loop visits vertices more than once: {preview(twice)}", path,
                    vertices=twice[:100].tolist())
    # on compact ids: the cost is that of the faces given (a hole's neighbourhood), not of
    # the largest vertex id (a large mesh's)
    ids = np.unique(np.concatenate([f.ravel(), loop]))
    compact = np.searchsorted(ids, loop)
    table = EdgeTable.build(np.searchsorted(ids, f), len(ids))
    a, b = loop, np.roll(loop, -1)
    edge = table.find(compact, np.roll(compact, -1))
    on_boundary = (edge >= 0) & (table.count[edge] == 1)
    if not on_boundary.all():
        bad = np.flatnonzero(~on_boundary)
        edges = [(int(a[i]), int(b[i])) for i in bad[:100]]
        said = how_many(bad.size, "loop edge is not a boundary edge",
                        "loop edges are not boundary edges")
        raise _fail(f"{said} of the mesh: {preview(edges)}", path, edges=edges)
    bowtie = np.intersect1d(ids[_bowtie(table)], loop)
    if bowtie.size:
        raise _fail("hole boundary passes through non-manifold (bow-tie) "
                    f"{agreeing(bowtie.size, 'vertex', 'vertices')} {preview(bowtie)}: the "
                    "faces there form several fans, so filling the hole would leave a "
                    "non-manifold surface (--repair, repair=True, removes the faces of all but "
                    "the largest fan there first)", path, vertices=bowtie[:100].tolist())
