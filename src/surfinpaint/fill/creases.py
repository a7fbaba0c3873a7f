"""Sharp creases across a hole: found, continued over it, and cut along.

λ and H describe a smooth surface. Along a sharp crease (a cube's edge) H is a line
singularity, which biharmonic inpainting spreads into a blob, and the initial fill's
triangles do not follow the crease, so no inpainting on them can make it sharp again
(measured on the cube-edge hole: README, "Creases"). Image inpainting meets the same problem
at image edges and answers it with structure propagation (J. Sun, L. Yuan, J. Jia, H.-Y.
Shum, "Image completion with structure propagation", SIGGRAPH 2005): continue the edge
curves across the hole first, then inpaint each side on its own. Here:

- :func:`hole_crease` finds two chains of sharp edges that run from the known surface into
  the hole's loop from opposite sides and face each other;
- :func:`crease_curve` joins their ends across the hole (a cubic Hermite curve that leaves
  each end along its chain);
- :func:`split_fill` splits the hole along that curve and fills each side (triangulate,
  refine, fair) with the curve fixed;
- :func:`cut_along` cuts the mesh along the crease, so that fairing and λ-H inpainting see
  each side as its own surface, the crease as its border (natural boundary conditions).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from surfinpaint.errors import FillError, MeshError
from surfinpaint.fill.liepa.fairing import fair
from surfinpaint.fill.liepa.refinement import boundary_scales, refine_patch
from surfinpaint.fill.liepa.triangulation import minimum_weight_triangulation
from surfinpaint.geometry.edges import edge_keys
from surfinpaint.geometry.mesh import edge_faces, face_normals, faces_near, orient_loop

__all__ = ["Crease", "crease_curve", "cut_along", "hole_crease", "sharp_edges",
           "split_fill"]

# a known edge whose two faces' normals turn by more than this (degrees) is sharp
CREASE_ANGLE = 60.0
# sharp edges a chain needs beyond the loop to count as a crease (noise makes shorter ones)
CREASE_EDGES = 2
# a chain turns by less than this (degrees) from edge to edge, and the two ends' directions
# into the hole point at each other within it
CREASE_TURN = 35.0


@dataclass
class Crease:
    """A crease that crosses a hole.

    Attributes
    ----------
    ends : (2,) int array
        Positions in the loop (as given) where the crease enters and leaves.
    chains : list of two int arrays
        Vertex ids of each sharp chain, from its loop vertex outward.
    directions : (2, 3) float array
        Unit directions into the hole at the two ends.
    angle : float
        Mean turn (degrees) between the faces along the chains.
    """

    ends: np.ndarray
    chains: list
    directions: np.ndarray
    angle: float


def sharp_edges(vertices: np.ndarray, faces: np.ndarray, angle: float = CREASE_ANGLE
                ) -> tuple[np.ndarray, np.ndarray]:
    """Interior edges whose two faces' normals turn by more than ``angle`` degrees.

    Returns
    -------
    edges : (s, 2) int array
        As (smaller id, larger id).
    turn : (s,) float array
        Their turn angles in degrees.

    Examples
    --------
    >>> from surfinpaint.data import cube
    >>> v, f = cube(2)
    >>> edges, turn = sharp_edges(v, f)
    >>> len(edges), float(turn.max())  # 12 cube edges of 2 mesh edges each
    (24, 90.0)
    """
    faces = np.asarray(faces, dtype=np.int64)
    edges, owner, count = edge_faces(faces)
    two = np.flatnonzero(count == 2)
    normals = face_normals(vertices, faces)
    cos = np.einsum("ij,ij->i", normals[owner[two, 0]], normals[owner[two, 1]])
    turn = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    keep = turn > angle
    return edges[two[keep]], turn[keep]


def _chain(start: int, adjacency: sp.csr_matrix, points: np.ndarray, blocked: np.ndarray,
           length: int) -> list[int]:
    """Follow sharp edges from ``start`` while they go on nearly straight (a short walk along
    one crease, not a loop over vertices)."""
    chain, direction = [start], None
    cos_turn = np.cos(np.radians(CREASE_TURN))
    while len(chain) <= length:
        here = chain[-1]
        nxt = adjacency.indices[adjacency.indptr[here]:adjacency.indptr[here + 1]]
        nxt = nxt[~blocked[nxt] & ~np.isin(nxt, chain)]
        if len(nxt) == 0:
            break
        step = points[nxt] - points[here]
        step /= np.linalg.norm(step, axis=1, keepdims=True)
        if direction is None:
            if len(nxt) > 1:  # a corner or a branching: not one crease
                break
            best = 0
        else:
            best = int(np.argmax(step @ direction))
            if step[best] @ direction < cos_turn:
                break
        direction = step[best]
        chain.append(int(nxt[best]))
    return chain


def hole_crease(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, *,
                angle: float = CREASE_ANGLE, min_edges: int = CREASE_EDGES) -> Crease | None:
    """The crease that crosses a hole, if exactly one does.

    A crease is a chain of at least ``min_edges`` sharp edges (normals turning by more than
    ``angle`` degrees), nearly straight, that ends at a loop vertex. The hole is crossed by
    one when exactly two such chains reach its loop, from loop vertices not next to each
    other, and their directions into the hole point at each other. Corners (three or more
    chains), creases that end inside the hole, and fold-like bends below ``angle`` give
    None: those holes are filled as smooth ones.

    Parameters
    ----------
    vertices, faces : arrays
        The mesh with the hole.
    loop : (k,) int array
        The hole's boundary loop.
    angle, min_edges :
        See above.

    Returns
    -------
    Crease or None
    """
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    loop = np.asarray(loop, dtype=np.int64)
    n = len(v)
    local = faces_near(faces, loop, min_edges, n)
    if len(local) == 0:
        return None
    edges, turn = sharp_edges(v, local, angle)
    if len(edges) == 0:
        return None
    adjacency = sp.csr_matrix((np.ones(2 * len(edges)), (edges.ravel(), edges[:, ::-1].ravel())),
                              shape=(n, n))
    on_loop = np.zeros(n, dtype=bool)
    on_loop[loop] = True
    starts = np.flatnonzero(np.diff(adjacency.indptr)[loop] > 0)
    chains = []
    for i in starts:
        chain = _chain(int(loop[i]), adjacency, v, on_loop, min_edges + 2)
        if len(chain) - 1 >= min_edges:
            chains.append((int(i), np.asarray(chain)))
    if len(chains) != 2:
        return None
    k = len(loop)
    cos_turn = np.cos(np.radians(CREASE_TURN))

    def tangent(chain):
        # the chain's tangent into the hole at its loop vertex, by the one-sided second-order
        # difference (a chord would bend the continuation of a curved crease)
        if len(chain) > 2:
            d = 3 * v[chain[0]] - 4 * v[chain[1]] + v[chain[2]]
        else:  # a single edge (allowed with min_edges=1): its direction
            d = v[chain[0]] - v[chain[1]]
        return d / np.linalg.norm(d)

    ends = []
    for i, chain in chains:
        # where the crease runs on along the loop's edges, it enters the hole further on
        for _ in range(k):
            direction = tangent(chain)
            steps = [(j, v[loop[j]] - v[loop[i]]) for j in ((i - 1) % k, (i + 1) % k)]
            ahead = [j for j, step in steps if int(loop[j]) not in chain
                     and step @ direction > cos_turn * np.linalg.norm(step)]
            if not ahead:
                break
            i, chain = ahead[0], np.concatenate([[loop[ahead[0]]], chain])
        ends.append((i, chain))
    (ia, ca), (ib, cb) = ends
    if min((ia - ib) % k, (ib - ia) % k) < 2:
        return None
    directions = np.array([tangent(ca), tangent(cb)])
    across = v[cb[0]] - v[ca[0]]
    across /= np.linalg.norm(across)
    if directions[0] @ across < cos_turn or -(directions[1] @ across) < cos_turn:
        return None
    key = edge_keys(edges[:, 0], edges[:, 1], n)
    chain_edges = np.concatenate([np.column_stack([c[:-1], c[1:]]) for c in (ca, cb)])
    # (the chains' edges along the loop have one face: no turn to measure there)
    mean_turn = float(turn[np.isin(key, edge_keys(chain_edges[:, 0], chain_edges[:, 1],
                                                  n))].mean())
    return Crease(ends=np.array([ia, ib]), chains=[ca, cb], directions=directions,
                  angle=mean_turn)


def crease_curve(start: np.ndarray, start_direction: np.ndarray, end: np.ndarray,
                 end_direction: np.ndarray, spacing: float) -> np.ndarray:
    """Points of the cubic Hermite curve from ``start`` to ``end`` that leaves ``start``
    along ``start_direction`` and arrives at ``end`` against ``end_direction`` (both unit,
    pointing into the hole), about ``spacing`` apart; the two ends excluded.

    A straight crease is continued exactly (the curve is then the segment).

    Returns
    -------
    (m, 3) float array, m ≥ 1.

    Examples
    --------
    >>> crease_curve(np.zeros(3), np.array([1., 0, 0]), np.array([1., 0, 0]),
    ...              np.array([-1., 0, 0]), 0.25).round(2).tolist()
    [[0.25, 0.0, 0.0], [0.5, 0.0, 0.0], [0.75, 0.0, 0.0]]
    """
    start, end = np.asarray(start, float), np.asarray(end, float)
    chord = float(np.linalg.norm(end - start))
    m = max(int(round(chord / spacing)) - 1, 1)
    s = (np.arange(1, m + 1) / (m + 1))[:, None]
    h00, h10 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s
    h01, h11 = -2 * s**3 + 3 * s**2, s**3 - s**2
    return (h00 * start + h10 * chord * np.asarray(start_direction)
            + h01 * end - h11 * chord * np.asarray(end_direction))


def cut_along(faces: np.ndarray, edges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The mesh cut open along ``edges``: a vertex gets one copy per fan of faces that the
    cut edges separate around it.

    Parameters
    ----------
    faces : (f, 3) int array
    edges : (c, 2) int array
        Edges to cut (either order); edges not in ``faces`` are ignored.

    Returns
    -------
    cut_faces : (f, 3) int array
        The same faces in the same order over the copies' ids.
    parent : (v', ) int array
        The original id of each copy (``parent[cut_faces] == faces``); on an uncut mesh
        the identity.

    Examples
    --------
    >>> square = np.array([[0, 1, 2], [0, 2, 3]])
    >>> cut, parent = cut_along(square, np.array([[0, 2]]))
    >>> len(parent)  # the diagonal's two ends are split
    6
    """
    faces = np.asarray(faces, dtype=np.int64)
    n_faces = len(faces)
    all_edges, owner, count = edge_faces(faces)
    n = int(faces.max()) + 1
    edges = np.sort(np.asarray(edges, dtype=np.int64).reshape(-1, 2), axis=1)
    is_cut = np.isin(edge_keys(all_edges[:, 0], all_edges[:, 1], n),
                     edge_keys(edges[:, 0], edges[:, 1], n))
    # the two faces of each interior uncut edge share the corners at its two ends
    join = np.flatnonzero((count == 2) & ~is_cut)
    fa, fb = owner[join, 0], owner[join, 1]
    rows, cols = [], []
    for end in (0, 1):
        u = all_edges[join, end]
        rows.append(3 * fa + np.argmax(faces[fa] == u[:, None], axis=1))
        cols.append(3 * fb + np.argmax(faces[fb] == u[:, None], axis=1))
    rows, cols = np.concatenate(rows), np.concatenate(cols)
    graph = sp.coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(3 * n_faces,) * 2)
    _, label = connected_components(graph, directed=False)
    copies, first_corner, corner_copy = np.unique(label, return_index=True,
                                                  return_inverse=True)
    parent = faces.ravel()[first_corner]
    # copies in the order of their original vertex, so an uncut mesh keeps its ids
    order = np.lexsort((first_corner, parent))
    rank = np.empty(len(order), dtype=np.int64)
    rank[order] = np.arange(len(order))
    return rank[corner_copy].reshape(-1, 3), parent[order]


def split_fill(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, crease: Crease,
               *, order: int = 3, angle: float = CREASE_ANGLE
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fill a hole crossed by ``crease``: the crease continued across it by
    :func:`crease_curve`, each side triangulated (Liepa's minimum-weight triangulation),
    refined and faired (order ``order``, natural boundary at the crease) on its own.

    Parameters
    ----------
    vertices, faces, loop :
        The mesh and the hole (loop oriented as :func:`surfinpaint.geometry.mesh.boundary_loops`
        gives it).
    crease : Crease
        From :func:`hole_crease` on the same loop.
    order : int
        Fairing order; falls back to 2 where the sides are too narrow for it.

    Returns
    -------
    new_vertices : (m, 3) float array
        The crease curve's points first, then the sides' inner vertices (ids ``n ..``).
    new_faces : (p, 3) int array
        The fill, oriented like the mesh.
    cut_edges : (c, 2) int array
        The edges to cut the filled mesh along so that each side is a surface of its own:
        the curve's, and the sharp edges (``angle`` of the crease search) around the hole,
        the crease's chains among them.

    Raises
    ------
    FillError
        When a side cannot be triangulated or faired.
    """
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    given = np.asarray(loop, dtype=np.int64)
    n = len(v)
    try:
        loop = orient_loop(faces, given, boundary=False)
    except MeshError as err:
        raise FillError(f"cannot fill the two sides of the crease: {err}") from err
    ia, ib = (int(i) for i in crease.ends)
    if loop[0] != given[0] or (len(loop) > 1 and loop[1] != given[1]):
        ia, ib = len(loop) - 1 - ia, len(loop) - 1 - ib  # the loop was reversed
    a, b = int(loop[ia]), int(loop[ib])
    scales = boundary_scales(v, faces, loop)
    spacing = float(np.mean(scales))
    curve = crease_curve(v[a], crease.directions[0], v[b], crease.directions[1], spacing)
    curve_ids = np.arange(n, n + len(curve))
    rolled = np.roll(loop, -ia)
    rolled_scales = np.roll(scales, -ia)
    jb = (ib - ia) % len(loop)
    # each side keeps the loop's orientation: its arc of the loop, then the curve back
    sides = [(np.concatenate([rolled[:jb + 1], curve_ids[::-1]]),
              np.concatenate([rolled_scales[:jb + 1], np.full(len(curve), spacing)])),
             (np.concatenate([rolled[jb:], rolled[:1], curve_ids]),
              np.concatenate([rolled_scales[jb:], rolled_scales[:1],
                              np.full(len(curve), spacing)]))]
    points = np.vstack([v, curve])
    path = np.concatenate([[a], curve_ids, [b]])
    # no diagonal between two points of the crease: its triangles would be flat slivers
    chords = np.array([(p, q) for i, p in enumerate(path) for q in path[i + 2:]],
                      dtype=np.int64).reshape(-1, 2)
    fill_faces = []
    try:
        for side, side_scales in sides:
            patch = minimum_weight_triangulation(points, side, avoid=chords)
            new_v, patch = refine_patch(points, patch, side, scales=side_scales)
            points = np.vstack([points, new_v])
            fill_faces.append(patch)
    except MeshError as err:
        raise FillError(f"cannot fill the two sides of the crease: {err}") from err
    fill = np.vstack(fill_faces)
    near = faces_near(faces, loop, order, n)
    cut_edges = np.concatenate([np.column_stack([path[:-1], path[1:]]),
                                sharp_edges(v, near, angle)[0],
                                *(np.column_stack([c[:-1], c[1:]]) for c in crease.chains)])
    # fair both sides with the crease fixed, on the mesh cut along it
    cut, parent = cut_along(np.vstack([fill, near]), cut_edges)
    inner = parent >= n + len(curve)
    for used in dict.fromkeys((order, 2)):
        try:
            faired = fair(points[parent], cut, inner, order=used,
                          cut=np.isin(parent, cut_edges))
            break
        except MeshError as err:
            if used == 2:
                raise FillError(f"cannot fair the two sides of the crease: {err}") from err
    points[parent[inner]] = faired[inner]
    return points[n:], fill, cut_edges
