"""The edge table of a triangle mesh: the one place where undirected edges are keyed,
sorted and counted.

A mesh's whole-mesh checks (validation, boundary loops, components, the outer-border test)
all start from the same sort of its ``3 f`` half-edges by undirected edge. :class:`EdgeTable`
does that sort once, in vectorized O(E log E) numpy (one stable sort of int64 keys, cheap on
meshes whose faces are stored in spatial order), and every later pass over it is O(E).
Build it once with :meth:`EdgeTable.build` and hand it to ``validate_mesh``, ``find_holes``
and ``boundary_loops`` to skip rebuilding it.

Half-edge ``h = 3 t + k`` is the edge opposite corner ``k`` of face ``t``, running from
``faces[t, (k + 1) % 3]`` to ``faces[t, (k + 2) % 3]`` (the face's own orientation).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

__all__ = ["EdgeTable", "edge_keys", "stable_key_sort"]


def edge_keys(a: np.ndarray, b: np.ndarray, n: int) -> np.ndarray:
    """One int64 key per vertex pair, the same for ``(a, b)`` and ``(b, a)``:
    ``min * n + max``, so sorting the keys sorts the edges by (smaller id, larger id).

    Parameters
    ----------
    a, b : int arrays of the same shape
        Vertex ids, all below ``n``.
    n : int
        A bound on the vertex ids (usually the vertex count).

    Examples
    --------
    >>> edge_keys(np.array([3, 1]), np.array([1, 3]), 10).tolist()
    [13, 13]
    """
    a = np.asarray(a, dtype=np.int64)
    b = np.asarray(b, dtype=np.int64)
    return np.minimum(a, b) * np.int64(n) + np.maximum(a, b)


def stable_key_sort(key: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``order = np.argsort(key, kind="stable")`` and ``key[order]``, for non-negative
    int64 keys. ``key`` is consumed: its memory may hold the sorted keys (one whole-mesh
    array less).

    Stable, so each edge's half-edges stay in face order. When each key shifted left by the
    bits of the largest index still fits in an int64, the index is packed into the low bits
    and the packed values sorted instead: they are distinct, so their order is the stable
    order of the keys, and sorting values moves less memory than sorting indices (the 651k
    case's 3.9M half-edges: about 1.5x faster). Being distinct, they have one sorted order
    whatever the algorithm, so numpy's default sort does it (introsort, vectorized on
    AVX2/AVX-512 machines): 31 ms against timsort's 112 ms on those 3.9M values (session
    20). Otherwise the argsort itself (timsort, which profits from the runs of a spatially
    ordered mesh: ~2x faster than quicksort).
    """
    n = len(key)
    shift = max(int(n - 1).bit_length(), 1)
    if n and int(key.max()) < (1 << (63 - shift)):
        packed = key
        packed <<= shift
        order = np.arange(n, dtype=np.int64)
        packed |= order
        packed.sort()  # distinct values: the same order as a stable sort
        np.bitwise_and(packed, (1 << shift) - 1, out=order)  # the index's memory reused
        packed >>= shift
        return order, packed
    order = np.argsort(key, kind="stable")
    return order, key[order]


@dataclass(frozen=True, eq=False)
class EdgeTable:
    """Sorted unique undirected edges of a triangle mesh and the maps between edges, faces
    and half-edges (see the module docstring for the half-edge numbering).

    Attributes
    ----------
    faces : (f, 3) int64 array
        The faces the table was built from (not copied: do not modify them afterwards).
    n_vertices : int
        The vertex-id bound used for the keys (at least ``faces.max() + 1``).
    edges : (e, 2) int64 array
        Each undirected edge once as (smaller id, larger id), sorted lexicographically.
    count : (e,) int32 array (int64 past 2**31 half-edges)
        Faces on each edge: 1 on the boundary, 2 inside, more where non-manifold.
    face_edge : (f, 3) int32 array (int64 past 2**31 half-edges)
        ``face_edge[t, k]``: the edge opposite corner ``k`` of face ``t``.
    halfedges : (3 f,) int32 array (int64 past 2**31 half-edges)
        Half-edge ids grouped by edge (``halfedges[start[e]:start[e + 1]]`` are edge ``e``'s,
        in increasing id, hence increasing face, order).
    start : (e + 1,) int32 array (int64 past 2**31 half-edges)
        Offsets of each edge's group in ``halfedges``.
    forward : (3 f,) bool array
        Whether half-edge ``h`` runs from the smaller vertex id to the larger: two
        half-edges of one edge traverse it in opposite directions iff these differ.

    Examples
    --------
    >>> t = EdgeTable.build(np.array([[0, 1, 2], [2, 1, 3]]))
    >>> t.edges.tolist(), t.count.tolist()
    ([[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]], [1, 1, 2, 1, 1])
    >>> t.edge_faces(2).tolist(), t.boundary_halfedges().tolist()
    ([0, 1], [[2, 0], [0, 1], [1, 3], [3, 2]])
    """

    faces: np.ndarray
    n_vertices: int
    edges: np.ndarray
    count: np.ndarray
    face_edge: np.ndarray
    halfedges: np.ndarray
    start: np.ndarray
    forward: np.ndarray

    @classmethod
    def build(cls, faces: np.ndarray, n_vertices: int | None = None) -> EdgeTable:
        """Sort the half-edges of ``faces`` by undirected edge.

        Parameters
        ----------
        faces : (f, 3) int array
            Vertex ids in ``0 .. n_vertices - 1`` (not checked: validate first).
        n_vertices : int, optional
            The vertex count; ``faces.max() + 1`` when omitted.
        """
        f = np.asarray(faces, dtype=np.int64)
        n = int(f.max()) + 1 if f.size else 1
        if n_vertices is not None:
            n = max(n, int(n_vertices))
        # take, not f[:, [1, 2, 0]]: that gives a column-major copy which ravel copies again
        tails = np.take(f, [1, 2, 0], axis=1).ravel()
        heads = np.take(f, [2, 0, 1], axis=1).ravel()
        forward = tails < heads
        # edge_keys(tails, heads, n), in place: no whole-mesh temporaries
        key = np.minimum(tails, heads)
        np.maximum(tails, heads, out=heads)
        del tails
        key *= np.int64(n)
        key += heads
        del heads
        order, sorted_key = stable_key_sort(key)
        del key
        m = len(order)
        # where a new edge starts, and one past the end: its offsets are the edges' starts
        new = np.empty(m + 1, dtype=bool)
        new[0] = new[m] = True
        np.not_equal(sorted_key[1:], sorted_key[:-1], out=new[1:m])
        start = np.flatnonzero(new)
        unique = sorted_key[start[:-1]]
        # each half-edge's edge, in sorted order, in the sorted keys' memory (used up)
        rank = np.cumsum(new[:m], dtype=np.int64, out=sorted_key)
        del sorted_key
        rank -= 1
        # half-edge and edge ids in int32 where they fit: the table's four largest arrays
        # at half the memory (651k case: 129 -> 82 MB by their sizes; the fill's peak
        # 475 -> 446 MB, docs/scale.md session 24)
        ids = np.int32 if m < 2**31 else np.int64
        face_edge = np.empty(m, dtype=ids)
        face_edge[order] = rank
        del rank
        halfedges = order.astype(ids)
        del order
        # (smaller, larger) written in place: no whole-mesh temporaries (a fresh process
        # pays for each new array's pages)
        edges = np.empty((len(unique), 2), dtype=np.int64)
        np.divmod(unique, n, out=(edges[:, 0], edges[:, 1]))
        del unique
        start = start.astype(ids)
        return cls(faces=f, n_vertices=n, edges=edges, count=np.diff(start),
                   face_edge=face_edge.reshape(-1, 3), halfedges=halfedges, start=start,
                   forward=forward)

    @property
    def n_edges(self) -> int:
        return len(self.edges)

    def check_faces(self, faces: np.ndarray) -> None:
        """Raise ``ValueError`` when ``faces`` cannot be the faces this table was built from
        (a different count), so a stale table is not used silently."""
        if len(faces) != len(self.faces):
            raise ValueError(f"the edge table was built for {len(self.faces)} faces, "
                             f"not {len(faces)}")

    def tails(self, h: np.ndarray) -> np.ndarray:
        """Start vertex of half-edges ``h``."""
        edge = self.face_edge.ravel()[h]
        return np.where(self.forward[h], self.edges[edge, 0], self.edges[edge, 1])

    def heads(self, h: np.ndarray) -> np.ndarray:
        """End vertex of half-edges ``h``."""
        edge = self.face_edge.ravel()[h]
        return np.where(self.forward[h], self.edges[edge, 1], self.edges[edge, 0])

    def interior_pairs(self) -> tuple[np.ndarray, np.ndarray]:
        """The two half-edges ``(h1, h2)``, ``h1 < h2``, of each edge with exactly two faces,
        in edge order."""
        inner = self.start[:-1][self.count == 2]
        first = self.halfedges[inner]
        inner += 1  # in place: one whole-mesh array less
        return first, self.halfedges[inner]

    def edge_faces(self, e: int) -> np.ndarray:
        """The faces on edge ``e``, in increasing order."""
        return self.halfedges[self.start[e]:self.start[e + 1]] // 3

    @cached_property
    def owners(self) -> np.ndarray:
        """(e, 2) int64: the first two faces on each edge, -1 where there is none."""
        out = np.full((self.n_edges, 2), -1, dtype=np.int64)
        out[:, 0] = self.halfedges[self.start[:-1]] // 3
        two = self.count >= 2
        out[two, 1] = self.halfedges[self.start[:-1][two] + 1] // 3
        return out

    def boundary_halfedges(self) -> np.ndarray:
        """(b, 2) int64: the directed boundary edges (edges with one face), oriented as in
        their face, in increasing half-edge order."""
        h = np.sort(self.halfedges[self.start[:-1][self.count == 1]])
        return np.column_stack([self.tails(h), self.heads(h)])

    def find(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """Edge id of each vertex pair ``(a[i], b[i])`` (either direction), -1 where the pair
        is not an edge of the mesh."""
        a = np.asarray(a, dtype=np.int64)
        b = np.asarray(b, dtype=np.int64)
        out = np.full(a.shape, -1, dtype=np.int64)
        inside = (a >= 0) & (b >= 0) & (a < self.n_vertices) & (b < self.n_vertices)
        if not self.n_edges or not inside.any():
            return out
        keys = edge_keys(self.edges[:, 0], self.edges[:, 1], self.n_vertices)
        query = edge_keys(a[inside], b[inside], self.n_vertices)
        pos = np.minimum(np.searchsorted(keys, query), len(keys) - 1)
        out[inside] = np.where(keys[pos] == query, pos, -1)
        return out

    @cached_property
    def vertex_components(self) -> tuple[int, np.ndarray]:
        """Connected components of the vertices through the edges: ``(count, label per
        vertex)``, labels numbered in order of each component's smallest vertex; vertices
        on no edge are components of their own."""
        e, n = self.edges, self.n_vertices
        # the edges are sorted by (smaller, larger) id and distinct: they are the upper
        # triangle's CSR rows as they stand (scipy's COO conversion would sort them again)
        indptr = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(np.bincount(e[:, 0], minlength=n), out=indptr[1:])
        graph = sp.csr_matrix((np.ones(len(e), np.int8), e[:, 1].copy(), indptr), shape=(n, n))
        count, label = connected_components(graph, directed=False)
        return int(count), label
