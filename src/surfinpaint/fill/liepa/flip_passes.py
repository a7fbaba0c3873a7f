"""CGAL's variant of Liepa's refinement (``refine_patch(..., style="cgal")``) and the flip
geometry it shares with the default refinement.

CGAL's ``refine`` (``Polygon_mesh_processing/internal/refine_impl.h``, used by
``triangulate_and_refine_hole``) splits triangles by Liepa's test, with Liepa's scales σ
(mean length of the mesh edges at each loop vertex) and density factor α, like
:func:`surfinpaint.fill.liepa.refinement.refine_patch`. It differs in how it relaxes:

- right after a triangle is split, its three old edges are relaxed;
- after each split round, every interior edge of the original triangles and of the
  triangles made in that round is visited **once**, in order (one sequential pass), instead
  of flipping to convergence;
- an edge flips when either opposite vertex lies inside *or on* the other triangle's
  diametral ball; the new diagonal is not required to pass the test (the single pass is what
  keeps it from cycling);
- the refinement stops after 10 rounds, or when a round splits nothing, or when its pass
  flips nothing (even if more triangles would split).

Here a round's splits are made together (CGAL splits one triangle at a time and relaxes its
edges before testing the next, so a later triangle is tested after its neighbours' flips);
the passes themselves are the sequential ones, computed exactly in vectorized rounds (see
:func:`flip_pass`). Unlike CGAL, a flip that would fold the two triangles over each other is
refused, as in :func:`surfinpaint.fill.liepa.refinement.delaunay_flip`.
"""

from __future__ import annotations

import numpy as np

from surfinpaint.geometry.edges import edge_keys

__all__ = ["CGAL_ROUNDS", "flip_pass", "inside_diametral_ball", "inside_either_ball",
           "proper_flip", "refine_rounds_cgal", "sorted_contains"]

CGAL_ROUNDS = 10  # CGAL's cap on split-and-relax rounds
# A point this close to a diametral ball's sphere (relative to its radius) counts as on it.
_ON_SPHERE = 1e-9
# Edge keys of local ids: a bound above any id a patch reaches.
_KEY_BASE = np.int64(1) << 31


def _cross(u: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Row-wise cross product of (k, 3) arrays: the same arithmetic as ``np.cross`` (so
    bit-identical results) without its axis handling, which dominates on the small arrays
    of a flip round."""
    out = np.empty_like(u)
    out[:, 0] = u[:, 1] * w[:, 2] - u[:, 2] * w[:, 1]
    out[:, 1] = u[:, 2] * w[:, 0] - u[:, 0] * w[:, 2]
    out[:, 2] = u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]
    return out


def inside_diametral_ball(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray,
                           s: np.ndarray) -> np.ndarray:
    """How far point s lies inside the smallest ball through triangle (a, b, c): the ball
    whose equator is the circumcircle. Returns 1 - |s - centre| / radius (> 0 inside); a
    degenerate triangle has an infinite ball (returns 1)."""
    pa = p[a]
    u = p[b] - pa
    w = p[c] - pa
    n = _cross(u, w)
    n2 = np.einsum("ij,ij->i", n, n)
    uu = np.einsum("ij,ij->i", u, u)
    ww = np.einsum("ij,ij->i", w, w)
    num = ww[:, None] * _cross(n, u) + uu[:, None] * _cross(w, n)
    ok = n2 > 1e-30 * np.maximum(uu, ww) ** 2
    centre = pa + num / np.where(ok, 2 * n2, 1.0)[:, None]
    radius = np.linalg.norm(centre - pa, axis=1)
    dist = np.linalg.norm(p[s] - centre, axis=1)
    return np.where(ok, 1.0 - dist / np.where(ok, radius, 1.0), 1.0)


def inside_either_ball(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray,
                d: np.ndarray) -> np.ndarray:
    """max(inside(a, b, c; d), inside(b, a, d; c)) in one vectorized call (half the calls)."""
    k = len(a)
    both = inside_diametral_ball(p, np.concatenate([a, b]), np.concatenate([b, a]),
                                  np.concatenate([c, d]), np.concatenate([d, c]))
    return np.maximum(both[:k], both[k:])


def sorted_contains(x: np.ndarray, sorted_keys: np.ndarray) -> np.ndarray:
    """``np.isin(x, sorted_keys)`` for a sorted key array, by binary search."""
    if len(sorted_keys) == 0:
        return np.zeros(len(x), dtype=bool)
    pos = np.minimum(np.searchsorted(sorted_keys, x), len(sorted_keys) - 1)
    return sorted_keys[pos] == x


def proper_flip(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray,
                 d: np.ndarray) -> np.ndarray:
    """Whether replacing triangles (a, b, c), (b, a, d) by (a, d, c), (d, b, c) gives two
    proper triangles that do not fold against the old pair."""
    old_n = _cross(p[b] - p[a], p[c] - p[a]) + _cross(p[a] - p[b], p[d] - p[b])
    n1 = _cross(p[d] - p[a], p[c] - p[a])
    n2 = _cross(p[b] - p[d], p[c] - p[d])
    scale = np.einsum("ij,ij->i", p[c] - p[d], p[c] - p[d])
    ok = (np.einsum("ij,ij->i", n1, old_n) > 0) & (np.einsum("ij,ij->i", n2, old_n) > 0)
    ok &= np.linalg.norm(n1, axis=1) > 1e-12 * scale
    ok &= np.linalg.norm(n2, axis=1) > 1e-12 * scale
    return ok


def _first_unique(keys: np.ndarray) -> np.ndarray:
    """``keys`` without repeats, each kept at its first position."""
    _, first = np.unique(keys, return_index=True)
    return keys[np.sort(first)]


def flip_pass(positions: np.ndarray, faces: np.ndarray, edges: np.ndarray, *,
              fixed_edges: np.ndarray | None = None,
              forbidden_edges: np.ndarray | None = None) -> tuple[np.ndarray, int]:
    """Visit ``edges`` once each, in order, flipping each that fails CGAL's test when its
    turn comes (a sequential, Gauss–Seidel pass), with the result of that sequential loop.

    Edge (a, b) between triangles (a, b, c) and (b, a, d) flips to (c, d) when d lies inside
    or on the diametral ball of (a, b, c), or c inside or on that of (b, a, d), the edge
    (c, d) is not already in the mesh (or in ``forbidden_edges``), and the two new triangles
    are proper and do not fold against the old pair. Fixed, boundary and repeated edges are
    skipped (a repeat is visited at its first position).

    The sequential loop is computed in vectorized rounds. An edge's two triangles change
    only when an edge of theirs flips, so an edge decides at its turn exactly what it would
    decide now if no earlier pending edge of its triangles can flip first. Each round marks
    the pending edges that fail now and, by propagation through shared triangles, those
    with an earlier such edge ("unstable"); the failing edges with no earlier unstable edge
    flip (no two share a triangle), the stable ones are visited without a flip, and the rest
    wait for the next round. The rounds end when no edge is pending.

    Parameters
    ----------
    positions : (n, 3) float array
    faces : (f, 3) int array
        A consistently oriented, edge-manifold triangle mesh.
    edges : (e, 2) int array
        The edges to visit, in order.
    fixed_edges, forbidden_edges : (k, 2) int arrays, optional
        Edges never flipped; edges never created.

    Returns
    -------
    faces : (f, 3) int array
        The flipped faces (same count and orientation; a flipped pair keeps its rows).
    flips : int
        How many edges flipped.
    """
    p = np.asarray(positions, dtype=float)
    f = np.asarray(faces, dtype=np.int64).copy()
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)

    def keys_of(e):
        e = np.asarray(e, dtype=np.int64).reshape(-1, 2)
        return np.unique(edge_keys(e[:, 0], e[:, 1], _KEY_BASE))

    fixed = keys_of(np.empty((0, 2)) if fixed_edges is None else fixed_edges)
    forbidden = keys_of(np.empty((0, 2)) if forbidden_edges is None else forbidden_edges)
    pending = _first_unique(edge_keys(edges[:, 0], edges[:, 1], _KEY_BASE))
    pending = pending[~sorted_contains(pending, fixed)]
    prio = np.arange(len(pending))
    flips = 0
    while len(pending):
        # half-edge entry 3t + k: the edge of face t opposite its corner k
        hk = edge_keys(f[:, [1, 2, 0]].ravel(), f[:, [2, 0, 1]].ravel(), _KEY_BASE)
        order = np.argsort(hk, kind="stable")
        sk = hk[order]
        at = np.searchsorted(sk, pending)
        nxt = np.minimum(at + 1, len(sk) - 1)
        inner = (at < len(sk)) & (sk[np.minimum(at, len(sk) - 1)] == pending) & \
            (sk[nxt] == pending) & (nxt > at)
        pending, prio, at = pending[inner], prio[inner], at[inner]  # boundary: nothing to do
        if not len(pending):
            break
        e1, e2 = order[at], order[at + 1]
        t1, k1, t2, k2 = e1 // 3, e1 % 3, e2 // 3, e2 % 3
        a, b, c, d = f[t1, (k1 + 1) % 3], f[t1, (k1 + 2) % 3], f[t1, k1], f[t2, k2]
        new_key = edge_keys(c, d, _KEY_BASE)
        failing = (inside_either_ball(p, a, b, c, d) > -_ON_SPHERE) & (c != d)
        failing &= ~sorted_contains(new_key, sk) & ~sorted_contains(new_key, forbidden)
        failing &= proper_flip(p, a, b, c, d)
        unstable = failing.copy()
        while True:  # an edge is unstable when it fails or an earlier unstable edge shares a face
            first = np.full(len(f), np.iinfo(np.int64).max, dtype=np.int64)
            np.minimum.at(first, t1[unstable], prio[unstable])
            np.minimum.at(first, t2[unstable], prio[unstable])
            waits = np.minimum(first[t1], first[t2]) < prio
            grown = unstable | waits
            if (grown == unstable).all():
                break
            unstable = grown
        ready = np.flatnonzero(failing & ~waits)
        # two quads could share the same new diagonal: the earlier one flips
        _, keep = np.unique(new_key[ready], return_index=True)
        ready = ready[keep]
        f[t1[ready]] = np.column_stack([a[ready], d[ready], c[ready]])
        f[t2[ready]] = np.column_stack([d[ready], b[ready], c[ready]])
        flips += len(ready)
        # visited: the stable edges (no flip), the flipped ones and a refused duplicate
        decided = ~unstable | (failing & ~waits)
        pending, prio = pending[~decided], prio[~decided]
    return f, flips


def refine_rounds_cgal(pos: np.ndarray, f: np.ndarray, sigma: np.ndarray,
                       fixed: np.ndarray, forbidden: np.ndarray | None, density: float
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """CGAL's split-and-relax rounds on a patch in local ids (the module docstring).

    Parameters
    ----------
    pos : (n, 3) float array
        The patch's vertices.
    f : (p, 3) int array
        The patch's triangles.
    sigma : (n,) float array
        Liepa's scale per vertex.
    fixed : (k, 2) int array
        The loop's edges (never flipped).
    forbidden : (e, 2) int array, optional
        Edges outside the patch between its vertices (never created).
    density : float
        Liepa's density factor α.

    Returns
    -------
    pos, f, sigma
        With the new vertices appended.
    """
    n_original = len(f)
    for _ in range(CGAL_ROUNDS):
        corners = pos[f]
        centroid = corners.mean(axis=1)
        sigma_c = sigma[f].mean(axis=1)
        dist = density * np.linalg.norm(corners - centroid[:, None, :], axis=2)
        split = np.flatnonzero(((dist > sigma_c[:, None]) & (dist > sigma[f])).all(axis=1))
        if not len(split):
            break
        x = len(pos) + np.arange(len(split))
        pos = np.vstack([pos, centroid[split]])
        sigma = np.concatenate([sigma, sigma_c[split]])
        a, b, c = f[split, 0], f[split, 1], f[split, 2]
        made = len(f) + np.arange(2 * len(split))
        f = f.copy()
        f[split] = np.column_stack([a, b, x])  # the split triangle keeps its row, as in CGAL
        f = np.vstack([f, np.column_stack([b, c, x]), np.column_stack([c, a, x])])
        old_edges = np.column_stack([a, b, c, a, b, c]).reshape(-1, 2)  # ab, ca, bc per split
        f, _ = flip_pass(pos, f, old_edges, fixed_edges=fixed, forbidden_edges=forbidden)
        rows = np.concatenate([np.arange(n_original), made])
        f, flips = flip_pass(pos, f, f[rows][:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2),
                             fixed_edges=fixed, forbidden_edges=forbidden)
        if flips == 0:
            break
    return pos, f, sigma
