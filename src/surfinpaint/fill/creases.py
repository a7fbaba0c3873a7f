"""Sharp creases across a hole: found, continued over it, and cut along.

λ and H describe a smooth surface. Along a sharp crease (a cube's edge) H is a line
singularity, which biharmonic inpainting spreads into a blob, and the initial fill's
triangles do not follow the crease, so no inpainting on them can make it sharp again
(measured on the cube-edge hole: README, "Creases"). Image inpainting meets the same problem
at image edges and answers it with structure propagation (J. Sun, L. Yuan, J. Jia, H.-Y.
Shum, "Image completion with structure propagation", SIGGRAPH 2005): continue the edge
curves across the hole first, then inpaint each side on its own. Here:

- :func:`hole_creases` finds pairs of chains of sharp edges that run from the known surface
  into the hole's loop from opposite sides and face each other (one crease, or several side
  by side, as a thin plate's two edges);
- :func:`crease_curve` joins their ends across the hole (a cubic Hermite curve that leaves
  each end along its chain);
- :func:`split_fill` splits the hole along those curves and fills each region (triangulate,
  refine, fair) with the curves fixed;
- :func:`cut_along` cuts the mesh along the creases, so that fairing and λ-H inpainting see
  each region as its own surface, the creases as its border (natural boundary conditions).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from surfinpaint.errors import FillError, MeshError
from surfinpaint.fill.liepa.fairing import fair
from surfinpaint.fill.liepa.refinement import boundary_scales, refine_patch
from surfinpaint.fill.liepa.triangulation import (
    existing_diagonals,
    minimum_weight_triangulation,
)
from surfinpaint.geometry.edges import edge_keys
from surfinpaint.geometry.mesh import edge_faces, face_normals, faces_near, orient_loop

__all__ = ["Crease", "corner_point", "crease_curve", "cut_along", "hole_creases",
           "paired_ends", "sharp_edge_rows", "sharp_edges", "split_fill"]

# a known edge whose two faces' normals turn by more than this (degrees) is sharp
CREASE_ANGLE = 60.0
# sharp edges a chain needs beyond the loop to count as a crease (noise makes shorter ones)
CREASE_EDGES = 2
# a chain turns by less than this (degrees) from edge to edge, and the two ends' directions
# into the hole point at each other within it
CREASE_TURN = 35.0
# a loop edge continues a crease that runs along the loop when it turns from the crease's
# direction by less than this (degrees): a loop edge on the crease lies along it, one that
# only zigzags near it (at up to CREASE_TURN) would bend the crease's tangent into the hole
# (fixed before any run, session 29)
CREASE_ALONG_LOOP = 10.0
# three or more creases meet at a corner in the hole where their lines pass within this
# many mean loop edge lengths of one point (a machined corner: they meet exactly; fixed
# before any run, session 29)
CORNER_TOLERANCE = 0.25


@dataclass
class Crease:
    """A crease that crosses a hole, or creases that meet at a corner in it.

    Attributes
    ----------
    ends : (m,) int array
        Positions in the loop (as given) where the creases enter: two for a crease across
        the hole, m ≥ 3 (in loop order) for a corner.
    chains : list of m int arrays
        Vertex ids of each sharp chain, from its loop vertex outward.
    directions : (m, 3) float array
        Unit directions into the hole at the ends.
    angle : float
        Mean turn (degrees) between the faces along the chains.
    corner : (3,) float array, optional
        Where the creases meet (a corner); None for one crease across the hole.
    line : (point, unit direction) pair of (3,) float arrays, optional
        The straight line the crease lies on, where it is known (two planes' meeting line,
        :func:`surfinpaint.fill.liepa.baseline.split_on_two_planes`): its points across
        the hole are laid on it. None (the crease search's): the Hermite curve as it is.
    """

    ends: np.ndarray
    chains: list
    directions: np.ndarray
    angle: float
    corner: np.ndarray | None = None
    line: tuple[np.ndarray, np.ndarray] | None = None


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
    table = edge_faces(faces)
    rows, turn = sharp_edge_rows(vertices, faces, table, angle)
    return table[0][rows], turn


def sharp_edge_rows(vertices: np.ndarray, faces: np.ndarray, table: tuple,
                    angle: float = CREASE_ANGLE) -> tuple[np.ndarray, np.ndarray]:
    """:func:`sharp_edges` as rows of ``table``, the caller's ``edge_faces(faces)``
    (:func:`~surfinpaint.geometry.mesh.edge_faces`), in its order, and their turn angles.

    Examples
    --------
    >>> from surfinpaint.data import cube
    >>> from surfinpaint.geometry.mesh import edge_faces
    >>> v, f = cube(2)
    >>> table = edge_faces(f)
    >>> rows, turn = sharp_edge_rows(v, f, table)
    >>> bool((table[0][rows] == sharp_edges(v, f)[0]).all()), len(rows)
    (True, 24)
    """
    _, owner, count = table
    two = np.flatnonzero(count == 2)
    normals = face_normals(vertices, faces)
    cos = np.einsum("ij,ij->i", normals[owner[two, 0]], normals[owner[two, 1]])
    turn = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    keep = turn > angle
    return two[keep], turn[keep]


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


def hole_creases(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, *,
                 angle: float = CREASE_ANGLE, min_edges: int = CREASE_EDGES) -> list[Crease]:
    """The creases that cross a hole: one, or several side by side (a hole over a thin
    plate's side crosses its two edges).

    A crease is a chain of at least ``min_edges`` sharp edges (normals turning by more than
    ``angle`` degrees), nearly straight, that ends at a loop vertex (where it runs on along
    the loop, at the last loop vertex on it). The hole is crossed when the chains' ends pair
    up by :func:`paired_ends`: two ends not next to each other that point at each other,
    every end paired, no two continuations crossing. Where they do not pair, three or more
    chains whose lines meet ahead of their ends are a corner (:func:`corner_point`),
    returned as one Crease. Anything else gives an empty list: creases that end inside the
    hole without a corner, curved creases whose ends do not point at each other, and
    fold-like bends below ``angle``; those holes are filled as smooth ones.

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
    list of Crease
        In the order of their first end along the loop; empty when the hole is not crossed.
    """
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    loop = np.asarray(loop, dtype=np.int64)
    n = len(v)
    local = faces_near(faces, loop, min_edges, n)
    if len(local) == 0:
        return []
    edges, turn = sharp_edges(v, local, angle)
    if len(edges) == 0:
        return []
    ends = _crease_ends(v, loop, _loop_chains(v, loop, edges, min_edges))
    pairs = paired_ends(np.array([i for i, _, _ in ends]), len(loop),
                        v[[c[0] for _, c, _ in ends]], np.array([d for _, _, d in ends]))
    key = edge_keys(edges[:, 0], edges[:, 1], n)
    creases = [Crease(ends=np.array([ends[a][0], ends[b][0]]),
                      chains=[ends[a][1], ends[b][1]],
                      directions=np.array([ends[a][2], ends[b][2]]),
                      angle=_mean_turn(turn, key, [ends[a][1], ends[b][1]], n))
               for a, b in pairs]
    if creases or len(ends) < 3:
        return creases
    ends.sort(key=lambda e: e[0])
    corner = corner_point(v[[c[0] for _, c, _ in ends]], np.array([d for _, _, d in ends]),
                          float(np.linalg.norm(v[loop] - v[np.roll(loop, 1)], axis=1).mean()))
    if corner is None:
        return []
    chains_ = [c for _, c, _ in ends]
    return [Crease(ends=np.array([i for i, _, _ in ends]), chains=chains_,
                   directions=np.array([d for _, _, d in ends]),
                   angle=_mean_turn(turn, key, chains_, n), corner=corner)]


def _loop_chains(v: np.ndarray, loop: np.ndarray, edges: np.ndarray, min_edges: int
                 ) -> list[tuple[int, np.ndarray]]:
    """The chains of sharp ``edges`` that start at a vertex of ``loop`` (:func:`_chain`),
    long enough to be a crease: ``(the loop position, the chain's vertices)`` each."""
    n = len(v)
    adjacency = sp.csr_matrix((np.ones(2 * len(edges)), (edges.ravel(), edges[:, ::-1].ravel())),
                              shape=(n, n))
    on_loop = np.zeros(n, dtype=bool)
    on_loop[loop] = True
    starts = np.flatnonzero(np.diff(adjacency.indptr)[loop] > 0)
    chains = []
    sharp_degree = np.diff(adjacency.indptr)
    for i in starts:
        chain = _chain(int(loop[i]), adjacency, v, on_loop, min_edges + 2)
        # a shorter chain counts where it runs into a corner of the part (three or more
        # sharp edges meet at its far end): an edge, not noise, cut short by the corner
        if len(chain) - 1 >= min_edges or (len(chain) > 1 and sharp_degree[chain[-1]] >= 3):
            chains.append((int(i), np.asarray(chain)))
    return chains


def _chain_tangent(v: np.ndarray, chain: np.ndarray) -> np.ndarray:
    """The chain's unit tangent into the hole at its loop vertex (its first)."""
    # by the one-sided second-order difference (a chord would bend the continuation of a
    # curved crease)
    if len(chain) > 2:
        d = 3 * v[chain[0]] - 4 * v[chain[1]] + v[chain[2]]
    else:  # a single edge (allowed with min_edges=1): its direction
        d = v[chain[0]] - v[chain[1]]
    return d / np.linalg.norm(d)


def _crease_ends(v: np.ndarray, loop: np.ndarray, chains: list[tuple[int, np.ndarray]]
                 ) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """Where each chain enters the hole: ``(the loop position, the chain, its tangent)``."""
    k = len(loop)
    cos_along = np.cos(np.radians(CREASE_ALONG_LOOP))
    ends = []
    for i, chain in chains:
        # where the crease runs on along the loop's edges, it enters the hole further on
        for _ in range(k):
            direction = _chain_tangent(v, chain)
            steps = [(j, v[loop[j]] - v[loop[i]]) for j in ((i - 1) % k, (i + 1) % k)]
            ahead = [j for j, step in steps if int(loop[j]) not in chain
                     and step @ direction > cos_along * np.linalg.norm(step)]
            if not ahead:
                break
            i, chain = ahead[0], np.concatenate([[loop[ahead[0]]], chain])
        ends.append((i, chain, _chain_tangent(v, chain)))
    return ends


def _mean_turn(turn: np.ndarray, key: np.ndarray, chains: list[np.ndarray], n: int) -> float:
    """The mean turn of the sharp edges (``turn``, by their ``key``) along ``chains``."""
    # (the chains' edges along the loop have one face: no turn to measure there)
    chain_edges = np.concatenate([np.column_stack([c[:-1], c[1:]]) for c in chains])
    return float(turn[np.isin(key, edge_keys(chain_edges[:, 0], chain_edges[:, 1], n))].mean())


def corner_point(points: np.ndarray, directions: np.ndarray, scale: float
                 ) -> np.ndarray | None:
    """Where three or more creases that enter a hole meet: the point nearest their lines
    (least squares), if every line passes within ``CORNER_TOLERANCE`` × ``scale`` of it and
    it lies ahead of every end, no farther than the ends are apart.

    Parameters
    ----------
    points, directions : (m, 3) float arrays
        The creases' ends on the loop and their unit directions into the hole, m ≥ 3.
    scale : float
        The loop's mean edge length.

    Returns
    -------
    (3,) float array, or None

    Examples
    --------
    >>> corner_point(np.eye(3), -np.eye(3), 0.1).round(12).tolist()  # a cube's corner
    [0.0, 0.0, 0.0]
    """
    across = np.eye(3)[None] - directions[:, :, None] * directions[:, None, :]  # (m, 3, 3)
    x = np.linalg.lstsq(across.sum(axis=0), np.einsum("mij,mj->i", across, points),
                        rcond=None)[0]
    off_line = np.linalg.norm(np.einsum("mij,mj->mi", across, x - points), axis=1)
    ahead = np.einsum("mi,mi->m", x - points, directions)
    extent = np.linalg.norm(points[:, None] - points[None], axis=2).max()
    if (off_line > CORNER_TOLERANCE * scale).any() or (ahead <= 0).any() or \
            (ahead > extent).any():
        return None
    return x


def paired_ends(at: np.ndarray, k: int, points: np.ndarray, directions: np.ndarray
                ) -> list[tuple[int, int]]:
    """Pair crease ends on a hole's loop into creases across it (the rule of
    :func:`hole_creases`).

    Two ends pair when they are not next to each other on the loop and point at each other
    within ``CREASE_TURN``, each at the other better than at any third end (parallel
    creases over a thin plate's side also face each other's ends, obliquely: the best match
    decides). Every end must pair, and the pairs' continuations must not cross (their ends do
    not interleave along the loop); otherwise nothing pairs.

    Parameters
    ----------
    at : (m,) int array
        The ends' positions in the loop, distinct.
    k : int
        The loop's length.
    points, directions : (m, 3) float arrays
        The ends' positions, and their unit directions into the hole.

    Returns
    -------
    list of (a, b)
        Indices into the ends, ``at[a] < at[b]``, in the order of ``at[a]``; empty when the
        ends do not pair.

    Examples
    --------
    >>> along_x = np.array([[1.0, 0, 0], [-1.0, 0, 0]])
    >>> paired_ends(np.array([0, 5]), 10, np.array([[0.0, 0, 0], [1, 0, 0]]), along_x)
    [(0, 1)]
    """
    m = len(at)
    if m < 2 or m % 2 or len(np.unique(at)) < m:
        return []
    across = points[None, :] - points[:, None]  # from end a to end b
    length = np.linalg.norm(across, axis=2)
    np.fill_diagonal(length, 1.0)
    across /= length[..., None]
    # how well a and b point at each other: the smaller cosine of the two
    score = np.minimum(np.einsum("ad,abd->ab", directions, across),
                       -np.einsum("bd,abd->ab", directions, across))
    gap = np.abs(at[:, None] - at[None, :])
    score[np.minimum(gap, k - gap) < 2] = -1.0  # the diagonal and loop neighbours
    best = score.argmax(axis=1)
    cos_turn = np.cos(np.radians(CREASE_TURN))
    if (best[best] != np.arange(m)).any() or (score[np.arange(m), best] < cos_turn).any():
        return []
    pairs = sorted({tuple(sorted((a, int(best[a])), key=lambda c: at[c])) for a in range(m)},
                   key=lambda ab: at[ab[0]])
    spans = [(at[a], at[b]) for a, b in pairs]
    for x, (a0, a1) in enumerate(spans):  # continuations that would cross: not creases
        for b0, b1 in spans[x + 1:]:
            if (a0 < b0 < a1) != (a0 < b1 < a1):
                return []
    return [(int(a), int(b)) for a, b in pairs]


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


def split_fill(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
               creases: Sequence[Crease], *, order: int = 3, angle: float = CREASE_ANGLE
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fill a hole crossed by ``creases``: each continued across it by :func:`crease_curve`,
    each region between them triangulated (Liepa's minimum-weight triangulation), refined
    and faired (order ``order``, natural boundary at the creases) on its own.

    Parameters
    ----------
    vertices, faces, loop :
        The mesh and the hole (loop oriented as :func:`surfinpaint.geometry.mesh.boundary_loops`
        gives it).
    creases : sequence of Crease
        From :func:`hole_creases` on the same loop (not empty).
    order : int
        Fairing order; falls back to 2 where the regions are too narrow for it.

    Returns
    -------
    new_vertices : (m, 3) float array
        The crease curves' points first, then the regions' inner vertices (ids ``n ..``).
    new_faces : (p, 3) int array
        The fill, oriented like the mesh.
    cut_edges : (c, 2) int array
        The edges to cut the filled mesh along so that each region is a surface of its own:
        the curves', and the sharp edges (``angle`` of the crease search) around the hole,
        the creases' chains among them.

    Raises
    ------
    FillError
        When a region cannot be triangulated or faired.
    """
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    given = np.asarray(loop, dtype=np.int64)
    n = len(v)
    try:
        loop = orient_loop(faces, given, boundary=False)
    except MeshError as err:
        raise FillError(f"cannot fill the sides of the crease: {err}") from err
    reversed_loop = loop[0] != given[0] or (len(loop) > 1 and loop[1] != given[1])
    scales = boundary_scales(v, faces, loop)
    spacing = float(np.mean(scales))
    ends = [np.asarray(c.ends) if not reversed_loop else len(loop) - 1 - np.asarray(c.ends)
            for c in creases]
    points, paths = _crease_paths(v, loop, creases, ends, spacing)
    scale_of = np.full(len(points), spacing)
    scale_of[loop] = scales
    regions = _split_along(loop, paths)
    n_curves = len(points) - n
    # no diagonal between two points of a crease: its triangles would be flat slivers
    chords = np.array([(p, q) for path in paths for i, p in enumerate(path)
                       for q in path[i + 2:]], dtype=np.int64).reshape(-1, 2)
    # nor one that is a mesh edge already: a loop along two sides of a face would get the
    # face again from its third side, a duplicate (session 46's fuzz campaign, PyVista's nut)
    chords = np.vstack([chords, loop[np.argwhere(existing_diagonals(faces, loop, n))]])
    fill_faces = []
    try:
        for region in regions:
            patch = minimum_weight_triangulation(points, region, avoid=chords)
            new_v, patch = refine_patch(points, patch, region, scales=scale_of[region])
            points = np.vstack([points, new_v])
            fill_faces.append(patch)
    except MeshError as err:
        raise FillError(f"cannot fill the sides of the crease: {err}") from err
    fill = np.vstack(fill_faces)
    near = faces_near(faces, loop, order, n)
    cut_edges = np.concatenate([*(np.column_stack([p[:-1], p[1:]]) for p in paths),
                                sharp_edges(v, near, angle)[0],
                                *(np.column_stack([c[:-1], c[1:]]) for crease in creases
                                  for c in crease.chains)])
    # fair each region with the creases fixed, on the mesh cut along them
    cut, parent = cut_along(np.vstack([fill, near]), cut_edges)
    inner = parent >= n + n_curves
    for used in dict.fromkeys((order, 2)):
        try:
            faired = fair(points[parent], cut, inner, order=used,
                          cut=np.isin(parent, cut_edges))
            break
        except MeshError as err:
            if used == 2:
                raise FillError(f"cannot fair the sides of the crease: {err}") from err
    points[parent[inner]] = faired[inner]
    return points[n:], fill, cut_edges


def _crease_paths(v: np.ndarray, loop: np.ndarray, creases: Sequence[Crease], ends,
                  spacing: float) -> tuple[np.ndarray, list[np.ndarray]]:
    """The creases continued across the hole: the points with the curves' points appended,
    and the paths, each from a loop vertex to a loop vertex or a corner through new points
    (``ends``: each crease's ends as positions in ``loop``)."""
    points = v
    paths = []

    def continued(a: int, direction: np.ndarray, target: np.ndarray, back: np.ndarray,
                  line=None):
        nonlocal points
        curve = crease_curve(v[a], direction, target, back, spacing)
        if line is not None:  # a straight crease whose line is known: its points on it
            curve = line[0] + np.outer((curve - line[0]) @ line[1], line[1])
        points = np.vstack([points, curve])
        return np.arange(len(points) - len(curve), len(points))

    for crease, at in zip(creases, ends, strict=True):
        ids = [int(loop[i]) for i in at]
        d = crease.directions
        if crease.corner is None:
            paths.append(np.concatenate([[ids[0]], continued(ids[0], d[0], v[ids[1]], d[1],
                                                             crease.line), [ids[1]]]))
            continue
        # a corner: each crease continued straight to it (``back`` = its own direction
        # reversed), the first two as one path across the hole, the others ending at it
        points = np.vstack([points, crease.corner])
        corner = len(points) - 1
        legs = [continued(a, d[j], crease.corner, -d[j]) for j, a in enumerate(ids)]
        paths.append(np.concatenate([[ids[0]], legs[0], [corner], legs[1][::-1], [ids[1]]]))
        paths += [np.concatenate([[a], leg, [corner]]) for a, leg in zip(ids[2:], legs[2:],
                                                                           strict=True)]
    return points, paths


def _split_along(loop: np.ndarray, paths: list[np.ndarray]) -> list[np.ndarray]:
    """The hole's regions once ``loop`` is split along each path in turn (a path's ends on
    one region's boundary); each region's vertex ids in the loop's orientation."""
    regions = [loop]
    for path in paths:
        a, b = int(path[0]), int(path[-1])
        ids = regions.pop(next(r for r, ids in enumerate(regions) if a in ids and b in ids))
        rolled = np.roll(ids, -int(np.flatnonzero(ids == a)[0]))
        jb = int(np.flatnonzero(rolled == b)[0])
        regions += [np.concatenate([rolled[:jb + 1], path[-2:0:-1]]),
                    np.concatenate([rolled[jb:], rolled[:1], path[1:-1]])]
    return regions
