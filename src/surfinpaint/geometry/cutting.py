"""Cut holes with known ground truth: remove geodesic disks from a mesh.

Used to make test and benchmark cases: the removed patch is the truth a hole filler should
reproduce. Distances are Dijkstra distances along the mesh edges (an upper bound of the
geodesic distance, close to it on regular meshes).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components as _cc
from scipy.sparse.csgraph import dijkstra

from surfinpaint.errors import MeshError, how_many
from surfinpaint.geometry.edges import EdgeTable, edge_keys
from surfinpaint.geometry.mesh import boundary_loops, faces_at, unique_edges, vertex_faces
from surfinpaint.geometry.rows import row_norms, rows_all, rows_any

__all__ = ["CutHole", "CutResult", "compact", "cut_geodesic_disk", "cut_holes", "edge_graph",
           "renumber", "ring_distances", "submesh"]


@dataclass(frozen=True)
class CutHole:
    """One cut hole and the ground truth that was removed.

    Attributes
    ----------
    loop : (k,) int array
        The new boundary loop, in the cut mesh's vertex ids, oriented like its faces.
    truth_vertices, truth_faces : arrays
        The removed patch including its border ring (the faces removed, with all their
        vertices), so it can be compared with a filled patch directly.
    truth_ids : (m,) int array
        Original vertex ids of ``truth_vertices``.
    diameter : float
        Largest Euclidean distance between two vertices of the loop.
    center : int
        Original id of the centre vertex.
    radius : float
        The geodesic radius asked for.
    """

    loop: np.ndarray
    truth_vertices: np.ndarray
    truth_faces: np.ndarray
    truth_ids: np.ndarray
    diameter: float
    center: int
    radius: float


@dataclass(frozen=True)
class CutResult:
    """A mesh with holes cut out (see :func:`cut_holes`).

    Attributes
    ----------
    vertices, faces : arrays
        The mesh with the holes; removed vertices are deleted and the remaining ones keep
        their original relative order.
    holes : list of CutHole
    kept : (n',) int array
        Original id of each remaining vertex.
    """

    vertices: np.ndarray
    faces: np.ndarray
    holes: list[CutHole] = field(default_factory=list)
    kept: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))

    def _single(self) -> CutHole:
        if len(self.holes) != 1:
            raise AttributeError(f"this cut has {len(self.holes)} holes: use .holes[i]")
        return self.holes[0]

    @property
    def loop(self) -> np.ndarray:
        """Boundary loop of the (single) hole, in the cut mesh's ids."""
        return self._single().loop

    @property
    def truth_vertices(self) -> np.ndarray:
        return self._single().truth_vertices

    @property
    def truth_faces(self) -> np.ndarray:
        return self._single().truth_faces

    @property
    def diameter(self) -> float:
        return self._single().diameter


class _Topology:
    """Edge graph, face adjacency and incidences of a mesh, computed once for all its cuts."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        self.n = len(vertices)
        self.faces = faces
        table = EdgeTable.build(faces, self.n)
        edges, count = table.edges, table.count
        if (count > 2).any():
            bad = edges[count > 2][:10]
            raise MeshError("mesh is not edge-manifold", edges=[tuple(e) for e in bad.tolist()])
        length = row_norms(vertices[edges[:, 0]] - vertices[edges[:, 1]])
        # zero-length edges would vanish from the sparse graph; keep them connected
        length = np.maximum(length, 1e-300)
        self.graph = sp.coo_matrix((length, (edges[:, 0], edges[:, 1])),
                                   shape=(self.n, self.n)).tocsr()
        self.edge_key, self.edge_count = edge_keys(edges[:, 0], edges[:, 1], self.n), count
        self.whole = _Patch.of_table(faces, table, np.ones(len(faces), bool))
        self.on_boundary = np.zeros(self.n, bool)
        self.on_boundary[edges[count == 1].ravel()] = True
        self.face_component = _cc(self.whole.face_graph(np.ones(len(faces), bool)),
                                  directed=False)[1]
        self.component_size = np.bincount(self.face_component)
        self.incidence = vertex_faces(faces, self.n)
        self.degree = np.diff(self.incidence.indptr)

    def window(self, reached: np.ndarray, rings: int, component: int
               ) -> tuple[np.ndarray, _Patch]:
        """The faces within ``rings`` vertex rings of the faces at ``reached`` (sorted ids)
        and their patch, with what the cleanup needs to know of the mesh beyond it."""
        ids = faces_at(self.incidence, reached)
        for _ in range(rings):
            ids = faces_at(self.incidence, np.unique(self.faces[ids]))
        faces = self.faces[ids]
        vertex, local = renumber(faces)
        table = EdgeTable.build(local, len(vertex))
        same = self.face_component[ids] == component
        patch = _Patch.of_table(faces, table, same, vertex)
        # faces beside an interior edge of the mesh whose other face is beyond the window
        cut = table.halfedges[table.start[:-1][table.count == 1]]
        key = edge_keys(vertex[table.tails(cut)], vertex[table.heads(cut)], self.n)
        at = np.searchsorted(self.edge_key, key)
        patch.border = np.zeros(len(ids), bool)
        patch.border[cut[self.edge_count[at] == 2] // 3] = True
        # faces with a vertex some of whose faces are beyond the window
        patch.open = (np.bincount(local.ravel(), minlength=len(vertex))
                      < self.degree[vertex])[local].any(axis=1)
        patch.outside = int(self.component_size[component] - np.count_nonzero(same))
        return ids, patch


@dataclass
class _Patch:
    """Faces the cleanup of one hole works on: the whole mesh, or a window of it.

    ``pairs`` are the two faces (patch ids) of each interior edge and ``pair_half`` the edge
    as a half-edge of the first face (the second has it reversed); ``same`` marks the faces
    of the centre's component. A window also has ``border`` (faces with an edge whose other
    face is beyond it), ``open`` (faces with a vertex whose star leaves it) and ``outside``
    (the centre component's faces beyond it); the whole mesh has none of these.
    """

    faces: np.ndarray
    pairs: np.ndarray
    pair_half: np.ndarray
    same: np.ndarray
    border: np.ndarray | None = None
    open: np.ndarray | None = None
    outside: int = 0

    @classmethod
    def of_table(cls, faces: np.ndarray, table: EdgeTable, same: np.ndarray,
                 vertex: np.ndarray | None = None) -> _Patch:
        h1, h2 = table.interior_pairs()
        tails, heads = table.tails(h1), table.heads(h1)
        if vertex is not None:  # the table is over compact ids
            tails, heads = vertex[tails], vertex[heads]
        return cls(faces, np.column_stack([h1 // 3, h2 // 3]), np.column_stack([tails, heads]),
                   same)

    def face_graph(self, mask: np.ndarray) -> sp.csr_matrix:
        p = self.pairs[rows_all(mask[self.pairs])]
        m = len(self.faces)
        return sp.coo_matrix((np.ones(len(p)), (p[:, 0], p[:, 1])), shape=(m, m)).tocsr()

    def face_labels(self, mask: np.ndarray) -> np.ndarray:
        """Edge-connected component label per face of the subset ``mask`` (-1 outside)."""
        labels = _cc(self.face_graph(mask), directed=False)[1]
        return np.where(mask, labels, -1)

    def leaves(self, removed: np.ndarray) -> bool:
        """Whether the faces around ``removed`` may reach beyond the patch (a window too
        small to clean the hole in: the caller takes a larger one)."""
        return self.open is not None and bool((removed & self.open).any())

    def largest(self, labels: np.ndarray, kept: np.ndarray) -> int | None:
        """The label of the largest kept piece of the centre's component (the first of
        equal ones, as :func:`numpy.argmax` picks), None when a window cannot tell."""
        sizes = np.bincount(labels[kept])
        beyond = np.unique(labels[kept & self.border]) if self.border is not None else []
        if len(beyond) == 0:  # every kept piece lies inside
            return int(np.argmax(sizes)) if self.outside == 0 else None
        if len(beyond) > 1:  # pieces that may join beyond the window, or not
            return None
        piece = int(beyond[0])
        others = np.delete(sizes, piece)
        # inside pieces are whole pieces of the mesh; the outer one goes on beyond
        return piece if not len(others) or sizes[piece] + self.outside > others.max() else None


def _center_vertex(vertices: np.ndarray, center) -> int:
    c = np.asarray(center)
    if c.ndim == 0:
        i = int(c)
        if not 0 <= i < len(vertices):
            raise ValueError(f"center vertex {i} out of range [0, {len(vertices)})")
        return i
    if c.shape != (3,):
        raise ValueError(f"center must be a vertex id or a 3D point, got shape {c.shape}")
    return int(np.argmin(((vertices - c) ** 2).sum(axis=1)))


# vertex rings around the disk a window takes in, tried in turn before the whole mesh
WINDOW_RINGS = (3, 12)


def _region(topo: _Topology, center: int, radius: float) -> np.ndarray:
    """Sorted ids of the faces to remove for one geodesic disk, cleaned into a topological
    disk. The cleanup runs on a window around the disk (the cost follows the hole), and on
    the whole mesh when no window decides it: the same faces either way."""
    if not radius > 0:
        raise ValueError(f"radius must be positive, got {radius}")
    dist = dijkstra(topo.graph, directed=False, indices=center, limit=radius)
    reached = np.flatnonzero(dist <= radius)
    at_center = faces_at(topo.incidence, [center])
    if not len(at_center):
        raise ValueError(
            f"radius {radius:g} around vertex {center} contains no whole face: make it larger")
    component = topo.face_component[at_center[0]]
    removed = None
    for rings in WINDOW_RINGS:
        ids, patch = topo.window(reached, rings, component)
        removed = _clean(patch, center, radius, dist)
        if removed is not None:
            removed = ids[removed]
            break
    if removed is None:
        removed = np.flatnonzero(_clean(topo.whole, center, radius, dist))
    touched = np.unique(topo.faces[removed])
    if topo.on_boundary[touched].any():
        raise ValueError(
            f"the hole around vertex {center} with radius {radius:g} reaches the mesh "
            "boundary: use a smaller radius or another centre")
    return removed


def _clean(patch: _Patch, center: int, radius: float, dist: np.ndarray) -> np.ndarray | None:
    """Mask over ``patch``'s faces of the faces to remove (None: the window is too small)."""
    faces = patch.faces
    removed = rows_all((dist <= radius)[faces])
    touching = rows_any(faces == center)
    if not (removed & touching).any():
        raise ValueError(
            f"radius {radius:g} around vertex {center} contains no whole face: make it larger")
    same = patch.same
    for _ in range(100):
        if patch.leaves(removed):
            return None
        before = removed.copy()
        # 1. keep only the removed piece that contains the centre
        labels = patch.face_labels(removed)
        centre_labels = np.unique(labels[removed & touching])
        removed = np.isin(labels, centre_labels) & removed
        if len(centre_labels) > 1:  # the centre itself is a pinch: take its whole star
            removed |= touching
        # 2. kept islands (in the centre's connected component) go too
        kept = same & ~removed
        labels = patch.face_labels(kept)
        if kept.any():
            largest = patch.largest(labels, kept)
            if largest is None:
                return None
            removed |= kept & (labels != largest)
        if patch.leaves(removed):
            return None
        # 3. pinched vertices (several hole-boundary edges leave them): remove their star
        r1, r2 = removed[patch.pairs[:, 0]], removed[patch.pairs[:, 1]]
        tails = np.concatenate([patch.pair_half[~r1 & r2, 0], patch.pair_half[r1 & ~r2, 1]])
        tails, count = np.unique(tails, return_counts=True)
        pinched = tails[count > 1]
        if len(pinched):
            removed |= np.isin(faces, pinched).any(axis=1)
        if (removed == before).all():
            return removed
    raise RuntimeError("hole cleanup did not converge")  # pragma: no cover - it only grows


def _euler(faces: np.ndarray) -> int:
    edges, _, _ = unique_edges(faces)
    return len(np.unique(faces)) - len(edges) + len(faces)


def cut_holes(vertices: np.ndarray, faces: np.ndarray, centers: Sequence,
              radii: Sequence[float] | float) -> CutResult:
    """Cut several disjoint geodesic disks out of a mesh.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        An edge-manifold, consistently oriented mesh.
    centers : sequence
        Centre of each hole: a vertex id or a 3D point (the nearest vertex is used).
    radii : float or sequence of float
        Geodesic radius of each hole (mesh units), measured by Dijkstra on the edge graph.

    Returns
    -------
    CutResult
        See :func:`cut_geodesic_disk`; ``holes`` are in the order of ``centers``.

    Raises
    ------
    ValueError
        When holes overlap or touch (share a vertex), reach the mesh boundary, or when a
        radius is so large the removed region is not a disk (e.g. it wraps a handle).
    MeshError
        When the mesh is not edge-manifold.
    """
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    centers = list(centers)
    radii_arr = np.broadcast_to(np.asarray(radii, dtype=float), (len(centers),))
    topo = _Topology(v, f)
    ids = [_center_vertex(v, c) for c in centers]
    regions = [_region(topo, c, r) for c, r in zip(ids, radii_arr, strict=True)]
    owner = np.full(len(v), -1)
    for k, reg in enumerate(regions):
        verts = np.unique(f[reg])
        clash = owner[verts] >= 0
        if clash.any():
            other = int(owner[verts][clash][0])
            raise ValueError(f"holes {other} and {k} overlap or touch (they share vertex "
                             f"{int(verts[clash][0])}): move them apart or shrink them")
        owner[verts] = k
        if _euler(f[reg]) != 1:
            raise ValueError(f"hole {k} (radius {radii_arr[k]:g}) is not a disk (Euler "
                             f"characteristic {_euler(f[reg])}): use a smaller radius")
    removed = np.zeros(len(f), bool)
    for reg in regions:
        removed[reg] = True
    kept_faces = f[~removed]
    referenced = np.zeros(len(v), bool)
    referenced[f.ravel()] = True
    keep_v = ~referenced
    keep_v[kept_faces.ravel()] = True
    new_id = np.cumsum(keep_v) - 1
    out_v = v[keep_v]
    out_f = new_id[kept_faces]
    kept = np.flatnonzero(keep_v)
    loops = boundary_loops(out_f) if len(out_f) else []
    holes = []
    for k, reg in enumerate(regions):
        border = new_id[np.unique(f[reg])[keep_v[np.unique(f[reg])]]]
        mine = [lp for lp in loops if np.isin(lp, border).all()]
        if len(mine) != 1:
            raise ValueError(f"hole {k} (radius {radii_arr[k]:g}) leaves "
                             f"{how_many(len(mine), 'boundary loop', 'boundary loops')} "
                             "instead of one: use a smaller radius")
        loop = mine[0]
        tid, truth_faces = renumber(f[reg])
        p = out_v[loop]
        if len(p) > 2000:  # keep the pairwise distances small: the diameter is on the hull
            p = p[:: len(p) // 2000 + 1]
        diameter = float(np.sqrt(((p[:, None] - p[None]) ** 2).sum(-1).max()))
        holes.append(CutHole(loop=loop, truth_vertices=v[tid],
                             truth_faces=truth_faces, truth_ids=tid,
                             diameter=diameter, center=ids[k], radius=float(radii_arr[k])))
    return CutResult(vertices=out_v, faces=out_f, holes=holes, kept=kept)


def cut_geodesic_disk(vertices: np.ndarray, faces: np.ndarray, center,
                      radius: float) -> CutResult:
    """Remove a geodesic disk from a mesh, leaving one clean hole.

    Faces with all three vertices within ``radius`` (Dijkstra distance along edges from the
    centre vertex) are removed; vertices left without a face are deleted. The region is then
    cleaned so the result is one simple hole: only the removed piece containing the centre
    is kept, kept islands inside it are removed too, and the star of any vertex that would be
    pinched (two hole-boundary edges leaving it) is removed, repeating until stable.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        An edge-manifold, consistently oriented mesh.
    center : int or (3,) array
        Centre vertex id, or a point (its nearest vertex is used).
    radius : float
        Geodesic radius in mesh units.

    Returns
    -------
    CutResult
        ``vertices``/``faces``: the mesh with the hole (remaining vertices keep their relative
        order); ``loop``: the hole's boundary loop in the new ids; ``truth_vertices`` and
        ``truth_faces``: the removed patch with its border ring; ``diameter``: the hole's
        diameter; ``kept``: original id of each remaining vertex.

    Raises
    ------
    ValueError
        When the radius is too small to remove a face, the hole reaches the mesh boundary, or
        the removed region is not a disk.

    Examples
    --------
    >>> from surfinpaint.data import sphere
    >>> v, f = sphere(3)
    >>> cut = cut_geodesic_disk(v, f, 0, 0.4)
    >>> len(cut.faces) + len(cut.truth_faces) == len(f)
    True
    """
    return cut_holes(vertices, faces, [center], [radius])


def edge_graph(faces: np.ndarray, n_vertices: int) -> sp.csr_matrix:
    """Vertex adjacency through the face edges, for unweighted graph searches such as
    :func:`ring_distances` (pass it as ``graph`` to search one mesh many times). Entries are
    edge multiplicities, only the pattern matters: cheaper than
    :func:`surfinpaint.geometry.mesh.vertex_adjacency`, which sorts the edges to count each
    once."""
    f = np.asarray(faces, dtype=np.int64)
    rows = f[:, [0, 1, 2, 1, 2, 0]].ravel()
    cols = f[:, [1, 2, 0, 0, 1, 2]].ravel()
    return sp.csr_matrix((np.ones(len(rows), dtype=np.float32), (rows, cols)),
                         shape=(n_vertices, n_vertices))


def ring_distances(faces: np.ndarray, n_vertices: int, seeds, limit: float = np.inf, *,
                   graph: sp.csr_matrix | None = None) -> np.ndarray:
    """Edge-ring distance of every vertex from ``seeds`` (0 on the seeds, ``inf`` beyond
    ``limit`` or unreachable): the ``k``-ring of the seeds is ``distance <= k``.

    ``graph`` may pass a precomputed adjacency (:func:`edge_graph` of the mesh) for repeated
    searches on one mesh; it must be symmetric, as :func:`edge_graph`'s is.
    """
    if graph is None:
        graph = edge_graph(faces, n_vertices)
    seeds = np.atleast_1d(np.asarray(seeds, dtype=np.int64))
    # the graph holds both directions of every edge: searched as directed, the same
    # distances without scipy transposing it for an undirected search on each call
    return dijkstra(graph, directed=True, indices=seeds, min_only=True, unweighted=True,
                    limit=limit)


def submesh(vertices: np.ndarray, faces: np.ndarray, keep: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The faces whose three vertices are all in the mask ``keep``, with their vertices.

    Vertices and faces keep their relative order, so every computation that depends on the
    order of ids (sorting, tie-breaking) gives the same result on the submesh.

    Returns
    -------
    vertices, faces : arrays
        The submesh, compactly indexed.
    ids : (k,) int array
        Original id of each submesh vertex (sorted).
    """
    f = np.asarray(faces, dtype=np.int64)
    ids, sub = renumber(f[rows_all(keep[f])])
    return np.asarray(vertices)[ids], sub, ids


# renumber marks the ids used in an array as long as the largest id while that is at most
# this many times the faces' corners, else sorts the corners: the faster of the two (session
# 43, random faces, 300 to 30,000 of them, timed in turn: the mask 1.7-12x faster at 2 and
# 8 times, the two about even at 32, the sort 1.3-7.8x faster at 128)
_SCATTER_SPAN = 16


def renumber(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The vertices the faces use and the faces renumbered onto them.

    Parameters
    ----------
    faces : (m, 3) int array
        Faces in any vertex numbering (an empty array gives empty results).

    Returns
    -------
    ids : (k,) int array
        The distinct vertex ids of ``faces``, sorted: local vertex ``i`` is ``ids[i]``.
    local_faces : (m, 3) int array
        ``faces`` in local ids (``ids[local_faces] == faces``).
    """
    f = np.asarray(faces, dtype=np.int64)
    n = int(f.max()) + 1 if f.size else 0
    if n > _SCATTER_SPAN * f.size:  # a few faces of a large mesh: sort them
        ids, local = np.unique(f, return_inverse=True)
        return ids, local.reshape(-1, 3)
    used = np.zeros(n, dtype=bool)
    used[f] = True
    ids = np.flatnonzero(used)
    at = np.empty(n, dtype=np.int64)
    at[ids] = np.arange(len(ids))
    return ids, at[f].reshape(-1, 3)


def compact(vertices: np.ndarray, faces: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The faces with only the vertices they use, numbered in the order of their ids.

    Returns
    -------
    vertices, faces : arrays
        The faces' vertices (in increasing original id) and the faces in their numbering.
    ids : (k,) int array
        Original id of each returned vertex (sorted).
    """
    ids, local = renumber(faces)
    return np.asarray(vertices)[ids], local, ids
