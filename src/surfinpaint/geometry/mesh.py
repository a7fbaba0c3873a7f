"""Triangle-mesh primitives shared by every step: edges, boundary loops, rings, areas,
normals and the cotangent operators.

All functions take plain arrays: ``vertices`` is an ``(n, 3)`` float array, ``faces`` an
``(f, 3)`` integer array of vertex ids. Nothing here modifies its inputs.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp

from surfinpaint.errors import MeshError, agreeing, preview
from surfinpaint.geometry.cycles import simple_cycles
from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.geometry.linalg import laplacian_from_weights
from surfinpaint.geometry.rows import row_cross, row_norms, rows_any

__all__ = [
    "boundary_halfedges",
    "boundary_loops",
    "edge_faces",
    "faces_near",
    "halfedge_faces",
    "orient_loop",
    "connected_components",
    "cotangent_laplacian",
    "edge_lengths",
    "face_areas",
    "face_cross",
    "face_normals",
    "k_ring",
    "laplacian_and_areas",
    "mass_matrix",
    "mean_edge_length",
    "unique_edges",
    "vertex_adjacency",
    "vertex_areas",
    "vertex_normals",
]


def unique_edges(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Undirected edges of a triangle mesh (from its :class:`EdgeTable`).

    Parameters
    ----------
    faces : (f, 3) int array

    Returns
    -------
    edges : (e, 2) int array
        Each undirected edge once, as (smaller id, larger id), sorted.
    face_edge : (f, 3) int array
        ``face_edge[t, k]`` is the edge opposite corner ``k`` of face ``t``, i.e. the edge
        ``(faces[t, (k+1)%3], faces[t, (k+2)%3])``.
    count : (e,) int array
        Number of faces on each edge: 1 on the boundary, 2 inside, more where non-manifold.

    Examples
    --------
    >>> e, fe, c = unique_edges(np.array([[0, 1, 2], [2, 1, 3]]))
    >>> e.tolist(), c.tolist()
    ([[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]], [1, 1, 2, 1, 1])
    """
    table = EdgeTable.build(faces)
    return table.edges, table.face_edge, table.count


def edge_faces(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The faces on each undirected edge.

    Returns
    -------
    edges : (e, 2) int array
        As :func:`unique_edges`.
    owners : (e, 2) int array
        The first two faces on each edge (by face index); -1 where there is none (the
        border). Non-manifold edges list only two of theirs.
    count : (e,) int array
        Number of faces on each edge.

    Examples
    --------
    >>> edges, owners, count = edge_faces(np.array([[0, 1, 2], [2, 1, 3]]))
    >>> owners[count == 2].tolist()
    [[0, 1]]
    """
    table = EdgeTable.build(faces)
    return table.edges, table.owners, table.count


def boundary_halfedges(faces: np.ndarray, table: EdgeTable | None = None) -> np.ndarray:
    """Directed boundary edges ``(a, b)``, oriented as in their single face.

    An edge used by exactly one face is a boundary edge. For a consistently oriented mesh the
    returned half-edges chain head to tail around each hole. ``table``: the faces' edge
    table, if already built.
    """
    faces = np.asarray(faces, dtype=np.int64)
    if len(faces) == 0:
        return np.empty((0, 2), dtype=np.int64)
    if table is None:
        table = EdgeTable.build(faces)
    else:
        table.check_faces(faces)
    return table.boundary_halfedges()


def boundary_loops(faces: np.ndarray, table: EdgeTable | None = None) -> list[np.ndarray]:
    """Ordered boundary loops of a triangle mesh.

    Each loop follows the orientation of the faces next to it (for a consistently oriented
    mesh that is the boundary orientation of the surface). Loops that touch themselves at a
    vertex (a boundary vertex with several outgoing boundary edges) are split into simple
    loops at that vertex.

    Parameters
    ----------
    faces : (f, 3) int array
    table : EdgeTable, optional
        The faces' edge table, if already built (saves the whole-mesh sort).

    Returns
    -------
    list of (k,) int arrays, one per loop, longest first.

    Raises
    ------
    MeshError
        When the boundary edges do not close into loops, which happens when the faces around
        the boundary are not consistently oriented.

    Examples
    --------
    >>> [l.tolist() for l in boundary_loops(np.array([[0, 1, 2], [0, 2, 3]]))]
    [[0, 1, 2, 3]]
    """
    half = boundary_halfedges(faces, table)
    if len(half) == 0:
        return []
    # successors per tail; a vertex can start several boundary edges (pinched loops)
    order = np.argsort(half[:, 0], kind="stable")
    half = half[order]
    cycles = simple_cycles(half)
    if cycles is not None:
        return cycles
    # the walk on Python ints and lists: numpy scalars cost several times more per step
    tails, heads = half[:, 0].tolist(), half[:, 1].tolist()
    m = len(tails)
    used = [False] * m
    first_of: dict[int, int] = {}
    for k, tail in enumerate(tails):  # sorted: the first edge leaving each vertex
        first_of.setdefault(tail, k)
    loops: list[np.ndarray] = []
    for e0 in range(m):
        if used[e0]:
            continue
        chain = [e0]
        used[e0] = True
        while True:
            head = heads[chain[-1]]
            if head == tails[chain[0]]:
                break
            k = first_of.get(head)
            if k is None:
                raise MeshError(
                    f"boundary edge ({tails[chain[-1]]}, {head}) does not continue: "
                    "faces around this boundary are not consistently oriented",
                    edges=[(int(tails[chain[-1]]), int(head))],
                )
            while k < m and tails[k] == head and used[k]:
                k += 1
            if k >= m or tails[k] != head:
                raise MeshError(
                    f"boundary at vertex {head} does not close into a loop",
                    vertices=[int(head)],
                )
            used[k] = True
            chain.append(k)
        loops.extend(_split_pinched(half[chain, 0]))
    loops.sort(key=len, reverse=True)
    return loops


def _split_pinched(loop: np.ndarray) -> list[np.ndarray]:
    """Split a closed vertex sequence that visits a vertex twice into simple loops."""
    out: list[np.ndarray] = []
    stack: list[int] = []
    position: dict[int, int] = {}
    for v in loop.tolist():
        if v in position:
            p = position[v]
            piece = stack[p:]
            out.append(np.array(piece, dtype=np.int64))
            for w in piece[1:]:
                del position[w]
            del stack[p + 1 :]
        else:
            position[v] = len(stack)
            stack.append(v)
    if stack:
        out.append(np.array(stack, dtype=np.int64))
    return [p for p in out if len(p) >= 3] or [np.asarray(loop, dtype=np.int64)]


def halfedge_faces(faces: np.ndarray, loop: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The faces on either side of each edge of a closed loop of vertices.

    Parameters
    ----------
    faces : (f, 3) int array
    loop : (k,) int array
        Vertex ids in order; edge ``i`` runs from ``loop[i]`` to ``loop[(i + 1) % k]``.

    Returns
    -------
    forward, backward : (k,) int64 arrays
        For each loop edge: the face holding it as a half-edge in the loop's direction, and
        the face holding it reversed; -1 where there is none (the last such face where
        several do, on a non-manifold or inconsistently oriented mesh).

    Examples
    --------
    >>> f = np.array([[0, 1, 2], [0, 2, 3]])
    >>> [side.tolist() for side in halfedge_faces(f, np.array([0, 1, 2, 3]))]
    [[0, 0, 1, 1], [-1, -1, -1, -1]]
    """
    faces = np.asarray(faces, dtype=np.int64)
    loop = np.asarray(loop, dtype=np.int64)
    k = len(loop)
    a, b = loop, np.roll(loop, -1)
    # only faces touching the loop matter; keeps the search local on big meshes
    n = int(max(faces.max(initial=-1), loop.max())) + 1
    on_loop = np.zeros(n, dtype=bool)
    on_loop[loop] = True
    near = np.flatnonzero(rows_any(on_loop[faces]))
    f = faces[near]
    tail = f.ravel()
    head = f[:, [1, 2, 0]].ravel()
    owner = np.repeat(near, 3)
    key = tail * n + head
    order = np.argsort(key, kind="stable")
    key, owner = key[order], owner[order]

    def lookup(q: np.ndarray) -> np.ndarray:
        pos = np.clip(np.searchsorted(key, q), 0, max(len(key) - 1, 0))
        hit = (key[pos] == q) if len(key) else np.zeros(k, dtype=bool)
        return np.where(hit, owner[pos] if len(key) else -1, -1)

    return lookup(a * n + b), lookup(b * n + a)


def orient_loop(faces: np.ndarray, loop: np.ndarray | Sequence[int], *,
                boundary: bool = True) -> np.ndarray:
    """A closed loop of vertices (any start, either direction), reversed if needed so that
    it follows the half-edges of the faces beside it: the orientation
    :func:`boundary_loops` returns.

    Parameters
    ----------
    faces : (f, 3) int array
    loop : (k,) int sequence
        Vertex ids in order, k >= 3, none repeated.
    boundary : bool
        True (a hole's loop, e.g. one a caller gives): every loop edge must be a boundary
        edge, with a face on one side only. False: any edge of the mesh will do, for a loop
        that only needs the direction of the faces along it (the Liepa fill checks the
        boundary itself, with its own message).

    Returns
    -------
    (k,) int64 array
        ``loop`` itself or a reversed copy.

    Raises
    ------
    MeshError
        When the loop is shorter than 3 or repeats a vertex, when consecutive ids are not
        joined by an edge of the mesh (by a boundary edge, with ``boundary``), or when the
        loop's edges disagree on the direction.

    Examples
    --------
    >>> f = np.array([[0, 1, 2], [0, 2, 3]])
    >>> orient_loop(f, [3, 2, 1, 0]).tolist()
    [0, 1, 2, 3]
    """
    loop = np.asarray(loop, dtype=np.int64).ravel()
    if len(loop) < 3:
        raise MeshError(f"a hole loop needs at least 3 vertices, got {len(loop)}")
    if len(np.unique(loop)) != len(loop):
        raise MeshError("a hole loop must not repeat a vertex", vertices=loop.tolist())
    forward, backward = halfedge_faces(faces, loop)

    def edges_at(bad: np.ndarray) -> list[tuple[int, int]]:
        return [(int(loop[i]), int(loop[(i + 1) % len(loop)])) for i in bad]

    if boundary:
        # a boundary edge has a face on one side only
        bad = edges_at(np.flatnonzero((forward >= 0) == (backward >= 0)))
        if bad:
            raise MeshError(
                f"vertices {bad[0][0]} and {bad[0][1]} of the given loop are not joined by a "
                "boundary edge of the mesh", edges=bad[:10])
    bad = edges_at(np.flatnonzero((forward < 0) & (backward < 0)))
    if bad:
        raise MeshError(f"loop {agreeing(len(bad), 'edge', 'edges')} {preview(bad)} "
                        f"{agreeing(len(bad), 'is not an edge', 'are not edges')} of the mesh",
                        edges=bad[:10])
    if (forward >= 0).all():
        return loop
    if (backward >= 0).all():
        return loop[::-1].copy()
    bad = edges_at(np.flatnonzero(forward < 0))
    raise MeshError(f"loop is not consistently oriented with the mesh faces at "
                    f"{agreeing(len(bad), 'edge', 'edges')} {preview(bad)}", edges=bad[:10])


def vertex_adjacency(faces: np.ndarray, n_vertices: int) -> sp.csr_matrix:
    """Symmetric 0/1 vertex adjacency matrix (n, n) of the mesh edges."""
    edges, _, _ = unique_edges(faces)
    data = np.ones(2 * len(edges), dtype=np.int8)
    rows = np.concatenate([edges[:, 0], edges[:, 1]])
    cols = np.concatenate([edges[:, 1], edges[:, 0]])
    return sp.csr_matrix((data, (rows, cols)), shape=(n_vertices, n_vertices))


def k_ring(faces: np.ndarray, seeds: np.ndarray, k: int, n_vertices: int) -> np.ndarray:
    """Vertices within ``k`` edges of ``seeds`` (the seeds included), as a boolean mask,
    grown through the faces at the mask (a triangle's vertices share edges): no adjacency
    matrix. ``k_ring([[0, 1, 2], [1, 3, 2]], [0], 1, 4)`` holds 0, 1 and 2."""
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    mask = np.zeros(n_vertices, dtype=bool)
    mask[np.asarray(seeds, dtype=np.int64)] = True
    for _ in range(k):
        count = int(mask.sum())
        mask[f[rows_any(mask[f])]] = True
        if mask.sum() == count:
            break
    return mask


def faces_near(faces: np.ndarray, seeds: np.ndarray, rings: int, n_vertices: int) -> np.ndarray:
    """The faces within ``rings`` rings of the seeds' one-ring (``rings=0``: the faces
    touching a seed), grown by vertex masks: the cost follows the region, with no adjacency
    matrix over the whole mesh.

    Examples
    --------
    >>> faces = np.array([[0, 1, 2], [1, 3, 2], [3, 4, 2]])
    >>> faces_near(faces, np.array([0]), 0, 5).tolist(), len(faces_near(faces, [0], 1, 5))
    ([[0, 1, 2]], 3)
    """
    mask = np.zeros(n_vertices, dtype=bool)
    mask[np.asarray(seeds, dtype=np.int64)] = True
    for _ in range(rings):
        mask[faces[rows_any(mask[faces])].ravel()] = True
    return faces[rows_any(mask[faces])]


def vertex_faces(faces: np.ndarray, n_vertices: int) -> sp.csr_matrix:
    """(n, f) incidence: row ``i`` holds the faces at vertex ``i`` (for :func:`faces_at`)."""
    f = np.asarray(faces)
    # scipy's own index type given: no int64 arrays for it to copy down (651k case: 0.08 ->
    # 0.05 s, 76 -> 44 MB of temporaries)
    ids = np.int32 if max(n_vertices, len(f)) < 2**31 else np.int64
    rows = f.ravel().astype(ids)
    cols = np.repeat(np.arange(len(f), dtype=ids), 3)
    return sp.csr_matrix((np.ones(len(rows), dtype=np.int8), (rows, cols)),
                         shape=(n_vertices, len(f)))


def faces_at(incidence: sp.csr_matrix, vertex_ids: np.ndarray) -> np.ndarray:
    """The faces at any of ``vertex_ids`` (sorted, once each), read from
    :func:`vertex_faces`' incidence: the cost follows the vertices, not the mesh.

    Examples
    --------
    >>> faces_at(vertex_faces(np.array([[0, 1, 2], [1, 3, 2], [3, 4, 2]]), 5), [0, 4])
    array([0, 2])
    """
    vertex_ids = np.asarray(vertex_ids, dtype=np.int64)
    starts = incidence.indptr[vertex_ids]
    counts = incidence.indptr[vertex_ids + 1] - starts
    if counts.sum() == 0:
        return np.empty(0, dtype=np.int64)
    offsets = np.repeat(starts - np.cumsum(counts) + counts, counts) + np.arange(counts.sum())
    return np.unique(incidence.indices[offsets]).astype(np.int64, copy=False)


def connected_components(faces: np.ndarray, n_vertices: int) -> tuple[int, np.ndarray]:
    """Connected components of the vertices through the edges: ``(count, label per vertex)``.

    Unreferenced vertices are components of their own.
    """
    return EdgeTable.build(faces, n_vertices).vertex_components


def edge_lengths(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(f, 3) lengths of the edge opposite each corner."""
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    p0, p1, p2 = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    return np.stack(
        [row_norms(p2 - p1), row_norms(p0 - p2), row_norms(p1 - p0)],
        axis=1,
    )


def mean_edge_length(vertices: np.ndarray, faces: np.ndarray,
                     table: EdgeTable | None = None) -> float:
    """Mean length of the undirected edges (``table``: the faces' edge table, if built)."""
    v = np.asarray(vertices, dtype=float)
    if table is None:
        edges, _, _ = unique_edges(faces)
    else:
        table.check_faces(faces)
        edges = table.edges
    if len(edges) == 0:
        return 0.0
    return float(row_norms(v[edges[:, 0]] - v[edges[:, 1]]).mean())


def _face_cross_columns(vertices: np.ndarray, faces: np.ndarray) -> list[np.ndarray]:
    """The three components of ``(p1 - p0) x (p2 - p0)`` per face, computed on 1-D
    coordinate arrays (the same arithmetic as ``np.cross``, so the same bits, at about a
    quarter of the time of its (f, 3) gathers on large meshes)."""
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    a, b = [], []
    for k in range(v.shape[1]):
        c = np.ascontiguousarray(v[:, k])
        c0 = c[f[:, 0]]
        a.append(c[f[:, 1]] - c0)
        b.append(c[f[:, 2]] - c0)
    if len(a) == 2:
        a.append(np.zeros(len(f)))
        b.append(a[2])
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def face_cross(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(f, 3) ``(p1 - p0) x (p2 - p0)`` per face: twice the area times the unit normal
    (the vertex normals' area weights)."""
    return np.column_stack(_face_cross_columns(vertices, faces))


# faces per block of a whole-mesh per-face pass: the temporaries of a block stay in the
# cache and are reused, where whole-mesh temporaries would each be fresh memory
FACE_BLOCK = 1 << 16


def face_blocks(n_faces: int) -> list[slice]:
    """Slices of at most ``FACE_BLOCK`` faces covering ``range(n_faces)``, in order: a
    per-face formula applied block by block gives the same bits as on all faces at once,
    with temporaries of a block's size instead of the mesh's.

    Examples
    --------
    >>> face_blocks(3)
    [slice(0, 3, None)]
    """
    return [slice(s, min(s + FACE_BLOCK, n_faces)) for s in range(0, n_faces, FACE_BLOCK)]


def face_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(f,) triangle areas; works for 2D or 3D vertices (2D areas are unsigned)."""
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    out = np.empty(len(f))
    for block in face_blocks(len(f)):
        x, y, z = _face_cross_columns(v, f[block])
        out[block] = 0.5 * np.sqrt(x * x + y * y + z * z)
    return out


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(f, 3) unit normals, right-handed with the face order; zero for degenerate faces."""
    c = face_cross(vertices, faces)
    norm = row_norms(c)[:, None]
    return np.divide(c, norm, out=np.zeros_like(c), where=norm > 0)


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(n, 3) area-weighted unit vertex normals; zero at unreferenced vertices."""
    c = face_cross(vertices, faces)
    f = np.asarray(faces, dtype=np.int64)
    n = np.zeros((len(vertices), 3))
    for k in range(3):
        np.add.at(n, f[:, k], c)
    norm = row_norms(n)[:, None]
    return np.divide(n, norm, out=np.zeros_like(n), where=norm > 0)


def _cotangents(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(f, 3) cotangent of the angle at each corner."""
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    cot = np.empty((len(f), 3))
    for k in range(3):
        a = v[f[:, (k + 1) % 3]] - v[f[:, k]]
        b = v[f[:, (k + 2) % 3]] - v[f[:, k]]
        dot = np.einsum("ij,ij->i", a, b)
        if v.shape[1] == 2:
            cross = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
        else:
            cross = row_norms(row_cross(a, b))
        cot[:, k] = dot / np.maximum(cross, 1e-300)
    return cot


# CGAL's fairing weights (Weights::Secure_cotangent_weight_with_voronoi_area): each
# corner's cotangent with its cosine clamped to ±0.999, then bounded below by zero
_CLAMPED_COS = 0.999
_CLAMPED_COT = _CLAMPED_COS / np.sqrt(1.0 - _CLAMPED_COS**2)


def cotangent_laplacian(vertices: np.ndarray, faces: np.ndarray, *,
                        nonnegative: bool = False) -> sp.csr_matrix:
    """Cotangent Laplacian ``L`` (n, n), symmetric, negative semi-definite.

    ``L[i, j] = (cot α_ij + cot β_ij) / 2`` for an edge ij, ``L[i, i] = -Σ_j L[i, j]``; so
    ``M⁻¹ L f`` approximates Δf and ``L x`` (x the positions) approximates ``2 H n A`` times
    the vertex area ``A`` with H the mean curvature (Pinkall–Polthier, Meyer et al. 2003).
    Works for planar (n, 2) vertices as well.

    ``nonnegative``: each corner's cotangent is clamped to [0, cot(2.56°)] first, as CGAL's
    fairing weights are (an obtuse corner adds nothing, a needle corner a bounded weight):
    no negative weights, at the cost of linear precision on obtuse triangles.
    """
    return _laplacian(len(vertices), faces, _cotangents(vertices, faces), nonnegative)


def laplacian_and_areas(vertices: np.ndarray, faces: np.ndarray, *,
                        nonnegative: bool = False) -> tuple[sp.csr_matrix, np.ndarray]:
    """``cotangent_laplacian(...)`` and the Voronoi ``vertex_areas(...)`` from one pass
    over the corners' cotangents (the same bits as the two calls)."""
    cot = _cotangents(vertices, faces)
    return (_laplacian(len(vertices), faces, cot, nonnegative),
            _corner_sums(len(vertices), faces, _voronoi_corners(vertices, faces, cot)))


def _laplacian(n: int, faces: np.ndarray, cot: np.ndarray, nonnegative: bool) -> sp.csr_matrix:
    f = np.asarray(faces, dtype=np.int64)
    if nonnegative:
        cot = np.clip(cot, 0.0, _CLAMPED_COT)
    i = np.concatenate([f[:, 1], f[:, 2], f[:, 0]])
    j = np.concatenate([f[:, 2], f[:, 0], f[:, 1]])
    w = 0.5 * np.concatenate([cot[:, 0], cot[:, 1], cot[:, 2]])
    return laplacian_from_weights(i, j, w, n)


def mass_matrix(vertices: np.ndarray, faces: np.ndarray, kind: str = "voronoi") -> sp.dia_matrix:
    """Lumped mass matrix (n, n): the area each vertex stands for, :func:`vertex_areas` on
    the diagonal."""
    return sp.diags(vertex_areas(vertices, faces, kind))


def vertex_areas(vertices: np.ndarray, faces: np.ndarray, kind: str = "voronoi") -> np.ndarray:
    """The area each vertex stands for (n,): the lumped mass matrix's diagonal.

    ``kind="barycentric"`` gives a third of each incident face; ``kind="voronoi"`` the mixed
    Voronoi area of Meyer et al. 2003 (obtuse triangles split by halves and quarters).
    """
    if kind == "barycentric":
        corner = np.repeat(face_areas(vertices, faces)[:, None] / 3.0, 3, axis=1)
    elif kind == "voronoi":
        corner = _voronoi_corners(vertices, faces, _cotangents(vertices, faces))
    else:
        raise ValueError(f"unknown mass matrix kind {kind!r}: use 'voronoi' or 'barycentric'")
    return _corner_sums(len(vertices), faces, corner)


def _voronoi_corners(vertices: np.ndarray, faces: np.ndarray, cot: np.ndarray) -> np.ndarray:
    """(f, 3) Voronoi area of each corner, from the corners' cotangents."""
    area = face_areas(vertices, faces)
    length2 = edge_lengths(vertices, faces) ** 2
    corner = np.empty_like(cot)
    for k in range(3):
        # Voronoi share of corner k: edges k->k+1 (opposite k+2) and k->k+2 (opposite k+1)
        corner[:, k] = (length2[:, (k + 2) % 3] * cot[:, (k + 2) % 3]
                        + length2[:, (k + 1) % 3] * cot[:, (k + 1) % 3]) / 8.0
    obtuse = cot < 0
    any_obtuse = rows_any(obtuse)
    corner[any_obtuse] = np.where(obtuse[any_obtuse], area[any_obtuse, None] / 2,
                                  area[any_obtuse, None] / 4)
    return corner


def _corner_sums(n: int, faces: np.ndarray, corner: np.ndarray) -> np.ndarray:
    f = np.asarray(faces, dtype=np.int64)
    m = np.zeros(n)
    for k in range(3):
        np.add.at(m, f[:, k], corner[:, k])
    return m
