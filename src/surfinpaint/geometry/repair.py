"""Minimal repair of non-manifold meshes: remove faces so that the rest is a manifold surface
whose new holes the filler can close.

Raw scans often carry a few non-manifold spots: an edge shared by three or more faces (a fin,
a doubled sheet) or a vertex where separate fans of faces meet (a bow-tie). No hole filler can
work across them. :func:`remove_nonmanifold_faces` deletes the faces at those spots, and only
those, so the damage becomes ordinary holes; :func:`surfinpaint.fill_holes` then fills them
like any other hole. :func:`repair_faces` then also reorients the faces of each piece
consistently (:func:`surfinpaint.geometry.orientation.orient_faces`), and each closed piece
outward (:func:`surfinpaint.geometry.orientation.turn_outward`). Vertices are never moved,
deleted or renumbered.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from surfinpaint.errors import MeshError, how_many
from surfinpaint.geometry.edges import edge_keys
from surfinpaint.geometry.orientation import (
    orient_faces,
    orientation_note,
    outward_note,
    turn_outward,
)
from surfinpaint.geometry.validation import check_arrays

__all__ = ["Repair", "corner_fans", "remove_nonmanifold_faces", "repair_faces",
           "unjoined_bowties"]


def _halfedges(faces: np.ndarray, n: int):
    """Half-edges h = 3 t + k (corner k -> k + 1 of face t): tail, head, undirected key."""
    tail = faces.ravel()
    head = faces[:, [1, 2, 0]].ravel()
    key = edge_keys(tail, head, n)
    return tail, head, key


def _edge_counts(key: np.ndarray) -> np.ndarray:
    """Number of half-edges sharing each half-edge's undirected edge."""
    _, inverse, count = np.unique(key, return_inverse=True, return_counts=True)
    return count[inverse]


def corner_fans(faces: np.ndarray) -> tuple[int, np.ndarray]:
    """Fans of faces around each vertex, as a label per corner.

    Corner ``3 t + k`` is vertex ``faces[t, k]`` in face ``t``. Two corners of the same vertex
    are in one fan when a chain of faces around the vertex, each sharing an edge through the
    vertex with the next, joins them. Edges with more than two faces do not join fans. A
    manifold vertex has one fan; a bow-tie vertex has several.

    Parameters
    ----------
    faces : (f, 3) int array

    Returns
    -------
    n_fans : int
    fan : (3 f,) int array
        Fan label of each corner (labels are global: a fan belongs to a single vertex).

    Examples
    --------
    >>> n_fans, fan = corner_fans(np.array([[0, 1, 2], [0, 2, 3], [0, 4, 5]]))
    >>> n_fans, fan.reshape(-1, 3)[:, 0].tolist()  # vertex 0: two fans
    (7, [0, 0, 4])
    """
    f = np.asarray(faces, dtype=np.int64)
    m = 3 * len(f)
    if m == 0:
        return 0, np.zeros(0, dtype=np.int64)
    n = int(f.max()) + 1
    tail, head, key = _halfedges(f, n)
    order = np.argsort(key, kind="stable")
    sk = key[order]
    starts = np.flatnonzero(np.r_[True, sk[1:] != sk[:-1]])
    counts = np.diff(np.r_[starts, len(sk)])
    pair = starts[counts == 2]
    a, b = order[pair], order[pair + 1]
    h = np.arange(m)
    head_corner = h - h % 3 + (h % 3 + 1) % 3
    # the corner of a half-edge's tail vertex is the half-edge itself; of its head, the next one
    # join a's tail corner with b's corner of the same vertex, and a's head corner likewise
    b_same = np.where(tail[b] == tail[a], b, head_corner[b])
    b_other = np.where(tail[b] == tail[a], head_corner[b], b)
    rows = np.concatenate([a, head_corner[a]])
    cols = np.concatenate([b_same, b_other])
    graph = sp.csr_matrix((np.ones(len(rows), np.int8), (rows, cols)), shape=(m, m))
    n_fans, fan = connected_components(graph, directed=True, connection="weak")
    return int(n_fans), fan.astype(np.int64)


def _minor_fan_faces(faces: np.ndarray) -> np.ndarray:
    """Faces in every fan but the largest one at each bow-tie vertex (boolean over faces).

    The largest fan (most faces; the lowest label on ties) stays: it is the surface the vertex
    belongs to, the others merely touch it there.
    """
    n_fans, fan = corner_fans(faces)
    if n_fans == 0:
        return np.zeros(len(faces), dtype=bool)
    vertex_of_fan = np.empty(n_fans, dtype=np.int64)
    vertex_of_fan[fan] = faces.ravel()
    size = np.bincount(fan, minlength=n_fans)
    fans_per_vertex = np.bincount(vertex_of_fan)
    on_bowtie = fans_per_vertex[vertex_of_fan] > 1
    if not on_bowtie.any():
        return np.zeros(len(faces), dtype=bool)
    # per vertex, pick its largest fan: sort fans by (vertex, -size, label), first per vertex
    fans = np.flatnonzero(on_bowtie)
    order = np.lexsort((fans, -size[fans], vertex_of_fan[fans]))
    fans = fans[order]
    first = np.r_[True, vertex_of_fan[fans[1:]] != vertex_of_fan[fans[:-1]]]
    minor = np.zeros(n_fans, dtype=bool)
    minor[fans[~first]] = True
    return minor[fan].reshape(-1, 3).any(axis=1)


def remove_nonmanifold_faces(
    vertices: np.ndarray,
    faces: np.ndarray,
    *,
    bowties: bool = True,
    max_rounds: int = 100,
) -> tuple[np.ndarray, np.ndarray]:
    """Remove the faces at non-manifold edges and vertices, leaving holes to fill.

    The rule, chosen to be simple, local and order-independent:

    1. Every face on an edge shared by more than two faces is removed. Which of the faces at
       such an edge is the "right" sheet cannot be decided locally, and removing them all
       only opens a small hole around the edge, which the filler then closes.
    2. At every bow-tie vertex (the faces around it form several fans, either in the input or
       after step 1) the faces of all fans but the largest one that touch the vertex are
       removed. Removing a fan's faces at the vertex can pinch a neighbouring vertex, so
       step 2 repeats until no bow-tie is left (each round removes at least one face).

    Removing faces never creates an edge with more than two faces, nor two faces traversing
    an edge in the same direction, so the result is an edge-manifold, vertex-manifold mesh
    whose orientation is consistent wherever the input's was. Faces are kept in their order;
    vertices are not touched (vertices of removed faces may become unreferenced).

    Parameters
    ----------
    vertices : (n, 3) float array
        Only checked (shapes, finite coordinates, index range); never modified.
    faces : (f, 3) int array
    bowties : bool
        Also resolve bow-tie vertices (step 2). With False only step 1 is done, and the
        result may still have bow-tie vertices.
    max_rounds : int
        Safety bound on the rounds of step 2.

    Returns
    -------
    faces_kept : (f', 3) int64 array
        The remaining faces, in their original order.
    removed : (f - f',) int64 array
        Ids (into ``faces``) of the removed faces, sorted.

    Raises
    ------
    MeshError
        When the arrays themselves are broken (see
        :func:`surfinpaint.geometry.validation.check_arrays`).

    Examples
    --------
    A fin: a third triangle on a spoke of a hexagonal fan.

    >>> t = np.linspace(0, 2 * np.pi, 7)[:-1]
    >>> v = np.vstack([[0, 0, 0], np.column_stack([np.cos(t), np.sin(t), 0 * t]), [.5, 0, 1]])
    >>> f = np.array([[0, i, i % 6 + 1] for i in range(1, 7)] + [[0, 1, 7]])
    >>> kept, removed = remove_nonmanifold_faces(v, f)
    >>> removed.tolist()  # the fin and the two fan triangles on its edge
    [0, 5, 6]
    """
    check_arrays(vertices, faces)
    f = np.asarray(faces, dtype=np.int64)
    n = len(vertices)
    _, _, key = _halfedges(f, n)
    keep = ~(_edge_counts(key) > 2).reshape(-1, 3).any(axis=1)
    if bowties:
        for _ in range(max_rounds):
            kept_ids = np.flatnonzero(keep)
            minor = _minor_fan_faces(f[kept_ids])
            if not minor.any():
                break
            keep[kept_ids[minor]] = False
    return f[keep], np.flatnonzero(~keep)


class Repair(NamedTuple):
    """What :func:`repair_faces` did (face ids into the faces given)."""

    #: The remaining faces, in their original order, some with their last two vertex ids
    #: swapped (flipped).
    faces: np.ndarray
    #: Ids of the removed faces, sorted.
    removed: np.ndarray
    #: Ids of the faces flipped in the end, sorted.
    flipped: np.ndarray
    #: The face ids of each closed piece turned outward (wound inward), each sorted.
    turned: list[np.ndarray]

    def notes(self) -> list[str]:
        """The words for what the orientation did: the faces flipped to orient each piece
        consistently (a face of a piece then turned outward is flipped back), and the
        closed pieces turned outward."""
        turned = np.concatenate(self.turned) if self.turned else np.empty(0, np.int64)
        consistent = np.setxor1d(self.flipped, turned)
        return ([orientation_note(consistent)] if len(consistent) else []) + \
            ([outward_note(self.turned)] if self.turned else [])


def repair_faces(vertices: np.ndarray, faces: np.ndarray) -> Repair:
    """What ``--repair`` (``repair=True``) does: :func:`remove_nonmanifold_faces`, then
    :func:`~surfinpaint.geometry.orientation.orient_faces` on the faces kept (the majority
    winding of each piece), then
    :func:`~surfinpaint.geometry.orientation.turn_outward` (each closed piece wound inward,
    its signed volume negative, turned outward; open pieces keep the majority winding).

    A piece that cannot be oriented (a Möbius strip) is left as it is; the mesh's check
    then refuses it (:func:`surfinpaint.geometry.validation.validate_mesh`).

    Returns
    -------
    Repair
        ``faces`` (the faces kept), ``removed``, ``flipped``, ``turned``.

    Examples
    --------
    >>> f = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 1, 4]])
    >>> kept, removed, flipped, turned = repair_faces(np.zeros((5, 3)), f)
    >>> removed.tolist(), flipped.tolist(), kept[3].tolist(), turned
    ([], [3], [0, 4, 1], [])
    """
    kept, removed = remove_nonmanifold_faces(vertices, faces)
    kept, flipped, unorientable = orient_faces(kept)
    kept, turned = turn_outward(vertices, kept, unorientable)
    if turned:
        flipped = np.setxor1d(flipped, np.concatenate(turned))
    if len(removed):  # the ids into the input faces
        ids = np.delete(np.arange(len(kept) + len(removed)), removed)
        flipped, turned = ids[flipped], [ids[t] for t in turned]
    return Repair(kept, removed, flipped, turned)


def unjoined_bowties(faces: np.ndarray, loop: np.ndarray) -> np.ndarray:
    """Bow-tie vertices of a hole's loop that filling the hole would leave pinched.

    A loop that passes through a bow-tie vertex arrives along a boundary edge of one fan and
    leaves along a boundary edge of another, or of the same one. When the fans differ (a
    loop pinched at the vertex, split by :func:`surfinpaint.geometry.mesh.boundary_loops`), the fill
    joins them: filling every piece of such a loop in turn leaves a manifold vertex. When
    the fan is the same (two surfaces touching at the vertex), the fill only closes that
    fan and the vertex stays a bow-tie.

    Parameters
    ----------
    faces : (f, 3) int array
        The faces around the loop (all faces at its vertices must be included).
    loop : (k,) int array
        A boundary loop, in either direction.

    Returns
    -------
    (m,) int64 array
        The loop's bow-tie vertices at which the fill would not join two fans; empty when
        filling the loop is safe and helps.

    Raises
    ------
    MeshError
        When consecutive loop vertices are not joined by a boundary edge (naming them).

    Examples
    --------
    An octahedron missing two opposite faces at its top vertex 0: the hole is pinched
    there, and filling either piece joins the two fans left at the top.

    >>> f = np.array([[0, 2, 3], [0, 4, 1], [5, 2, 1], [5, 3, 2], [5, 4, 3], [5, 1, 4]])
    >>> unjoined_bowties(f, [0, 2, 1]).tolist()
    []

    Two octahedra touching at that vertex: filling one's hole leaves the other's fan.

    >>> g = np.vstack([f[2:], [[0, 2, 3], [0, 3, 4], [0, 4, 1]], f[2:] + 6,
    ...                [[0, 8, 9], [0, 9, 10], [0, 10, 7]]])
    >>> unjoined_bowties(g, [0, 2, 1]).tolist()
    [0]
    """
    f = np.asarray(faces, dtype=np.int64)
    loop = np.asarray(loop, dtype=np.int64).ravel()
    n = int(max(f.max(), loop.max())) + 1
    tail, head, key = _halfedges(f, n)
    order = np.argsort(key, kind="stable")
    sk = key[order]
    nxt = np.roll(loop, -1)
    wanted = edge_keys(loop, nxt, n)
    pos = np.clip(np.searchsorted(sk, wanted), 0, len(sk) - 1)
    right = np.clip(np.searchsorted(sk, wanted, side="right"), 0, len(sk))
    bad = np.flatnonzero((sk[pos] != wanted) | (right - pos != 1))
    if bad.size:
        edges = [(int(loop[i]), int(nxt[i])) for i in bad[:100]]
        said = how_many(bad.size, "loop edge is not a boundary edge",
                        "loop edges are not boundary edges")
        raise MeshError(f"{said} of the mesh: {edges[:10]}", edges=edges)
    h = order[pos]  # the one half-edge of each loop edge (loop[i], loop[i + 1])
    head_corner = h - h % 3 + (h % 3 + 1) % 3
    # corners of loop[i] and of loop[i + 1] in the face holding that edge
    at_start = np.where(tail[h] == loop, h, head_corner)
    at_end = np.where(tail[h] == loop, head_corner, h)
    n_fans, fan = corner_fans(f)
    vertex_of_fan = np.empty(n_fans, dtype=np.int64)
    vertex_of_fan[fan] = f.ravel()
    fans_at = np.bincount(vertex_of_fan, minlength=n)
    leaving = fan[at_start]                 # fan of loop[i] along the edge leaving it
    arriving = np.roll(fan[at_end], 1)      # fan of loop[i] along the edge arriving at it
    return loop[(fans_at[loop] > 1) & (leaving == arriving)]
