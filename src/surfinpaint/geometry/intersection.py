"""Triangle–triangle intersection tests, vectorized, for checking filled patches.

A fill must not pierce the surface around it. :func:`patch_intersects_surroundings` finds the
pairs of (fill triangle, surrounding triangle) that intersect; :func:`intersecting_pairs` does
the same for any two sets of triangles of one mesh, and :func:`self_intersections` within
one set. All three first keep only pairs whose bounding spheres meet (a k-d tree on the
centroids), then test the candidates with :func:`triangles_intersect`.

The test is the interval-overlap test of T. Möller, "A fast triangle-triangle intersection
test", Journal of Graphics Tools 2(2), 1997: two triangles in general position intersect
exactly when the intervals they cut out of the line where their planes meet overlap; coplanar
(or nearly coplanar) triangles are tested in their common plane with separating axes.

Triangles of one mesh share vertices, and touching at a shared vertex or along a shared edge
is not an intersection: for pairs that share vertices only an overlap beyond the shared
vertex or edge counts. Pairs that share no vertex and merely touch do count.
"""

from __future__ import annotations

import numpy as np

from surfinpaint.geometry.rows import (
    row_cross,
    row_max,
    row_means,
    row_min,
    row_norms,
    rows_all,
    rows_any,
)
from surfinpaint.lazy import lazy_module

# imported at its first use (see fill/holes.py)
spatial = lazy_module("scipy.spatial")

__all__ = [
    "intersecting_pairs",
    "patch_intersects_surroundings",
    "self_intersections",
    "triangles_intersect",
]

# lengths below REL_TOL times the pair's longest edge are zero (a vertex on the other plane,
# intervals that only touch); far above float64 round-off and far below any real overlap
REL_TOL = 1e-9
# sine of the angle between the planes below which a pair is tested as coplanar: then the
# line where the planes meet is too ill-conditioned to carry the interval test
COPLANAR_SIN = 1e-6


def _unit(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    norm = row_norms(v)
    return np.divide(v, norm[..., None], out=np.zeros_like(v), where=norm[..., None] > 0), norm


def _interval(t: np.ndarray, d: np.ndarray, eps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Interval of the line parameter where a triangle meets the other plane.

    ``t`` (k, 3): the corners' projections on the line; ``d`` (k, 3): their signed distances
    to the other triangle's plane.
    """
    on = np.abs(d) <= eps[:, None]
    vals, valid = [t], [on]
    for i, j in ((0, 1), (1, 2), (2, 0)):
        di, dj = d[:, i], d[:, j]
        cross = (di * dj < 0) & ~on[:, i] & ~on[:, j]
        denom = np.where(cross, di - dj, 1.0)
        vals.append((t[:, i] + (t[:, j] - t[:, i]) * di / denom)[:, None])
        valid.append(cross[:, None])
    vals = np.concatenate(vals, axis=1)
    valid = np.concatenate(valid, axis=1)
    lo = row_min(np.where(valid, vals, np.inf))
    hi = row_max(np.where(valid, vals, -np.inf))
    return lo, hi


def _coplanar_overlap(a: np.ndarray, b: np.ndarray, normal: np.ndarray,
                      margin: np.ndarray) -> np.ndarray:
    """Separating-axis test of two triangles in the plane with ``normal``.

    Separated when, along some edge normal, one triangle ends at most ``margin`` past where
    the other begins.
    """
    e1, _ = _unit(a[:, 1] - a[:, 0])
    e2 = row_cross(normal, e1)
    origin = a[:, :1]
    pa = np.stack([np.einsum("kij,kj->ki", a - origin, e) for e in (e1, e2)], axis=-1)
    pb = np.stack([np.einsum("kij,kj->ki", b - origin, e) for e in (e1, e2)], axis=-1)
    separated = np.zeros(len(a), dtype=bool)
    for poly in (pa, pb):
        for i in range(3):
            edge = poly[:, (i + 1) % 3] - poly[:, i]
            axis, _ = _unit(np.stack([-edge[:, 1], edge[:, 0]], axis=-1))
            sa = np.einsum("kij,kj->ki", pa, axis)
            sb = np.einsum("kij,kj->ki", pb, axis)
            separated |= (sa.max(1) - sb.min(1) <= margin) | (sb.max(1) - sa.min(1) <= margin)
    return ~separated


def triangles_intersect(
    vertices: np.ndarray, faces_a: np.ndarray, faces_b: np.ndarray
) -> np.ndarray:
    """Whether triangle ``faces_a[i]`` intersects triangle ``faces_b[i]``, for every i.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces_a, faces_b : (k, 3) int arrays
        Row-aligned pairs of triangles of the same vertex array.

    Returns
    -------
    (k,) bool array
        True where the two triangles have a point in common other than what they share as
        vertex ids: touching at a shared vertex or along a shared edge is not an
        intersection, a shared triangle (all three vertices) is. Pairs where either triangle
        has zero area are never reported (their plane is undefined; degenerate faces are
        checked elsewhere).

    Examples
    --------
    >>> v = np.array([[0., 0, 0], [1, 0, 0], [0, 1, 0],
    ...               [.2, .2, -1], [.2, .2, 1], [1, 1, 0]])
    >>> triangles_intersect(v, np.array([[0, 1, 2], [0, 1, 2]]),
    ...                     np.array([[3, 4, 5], [1, 5, 2]])).tolist()
    [True, False]
    """
    v = np.asarray(vertices, dtype=float)
    fa = np.asarray(faces_a, dtype=np.int64).reshape(-1, 3)
    fb = np.asarray(faces_b, dtype=np.int64).reshape(-1, 3)
    if len(fa) != len(fb):
        raise ValueError(f"faces_a and faces_b must pair up row by row, got {len(fa)} and "
                         f"{len(fb)} rows")
    k = len(fa)
    if k == 0:
        return np.zeros(0, dtype=bool)
    # shared[i, p, q]: corner p of A is corner q of B
    shared = fa[:, :, None] == fb[:, None, :]
    shared_a = rows_any(shared)
    shared_b = rows_any(shared.swapaxes(1, 2))
    n_shared = shared_a.sum(axis=1)
    origin = v[fa[:, 0]]
    a = v[fa] - origin[:, None]
    b = v[fb] - origin[:, None]
    na, area_a = _unit(row_cross(a[:, 1] - a[:, 0], a[:, 2] - a[:, 0]))
    nb, area_b = _unit(row_cross(b[:, 1] - b[:, 0], b[:, 2] - b[:, 0]))
    longest = np.maximum(row_max(row_norms(a - np.roll(a, 1, axis=1))),
                         row_max(row_norms(b - np.roll(b, 1, axis=1))))
    eps = REL_TOL * longest
    # a pair that shares vertices intersects only by overlapping beyond them; one that shares
    # none intersects when it touches
    margin = np.where(n_shared > 0, eps, -eps)
    ok = (area_a > eps * longest) & (area_b > eps * longest)

    # signed distances to the other plane; exactly zero for shared corners
    db = np.einsum("kij,kj->ki", b - a[:, :1], na)
    da = np.einsum("kij,kj->ki", a - b[:, :1], nb)
    db[shared_b] = 0.0
    da[shared_a] = 0.0
    apart = (rows_all(db > eps[:, None]) | rows_all(db < -eps[:, None])
             | rows_all(da > eps[:, None]) | rows_all(da < -eps[:, None]))

    line, sine = _unit(row_cross(na, nb))
    coplanar = sine < COPLANAR_SIN
    result = np.zeros(k, dtype=bool)

    general = ok & ~apart & ~coplanar & (n_shared < 2)
    if general.any():
        g = np.flatnonzero(general)
        ta = np.einsum("kij,kj->ki", a[g], line[g])
        tb = np.einsum("kij,kj->ki", b[g], line[g])
        lo_a, hi_a = _interval(ta, da[g], eps[g])
        lo_b, hi_b = _interval(tb, db[g], eps[g])
        overlap = np.minimum(hi_a, hi_b) - np.maximum(lo_a, lo_b)
        result[g] = overlap > margin[g]
    # two triangles on one edge in different planes meet along that edge only
    flat = ok & ~apart & coplanar
    if flat.any():
        c = np.flatnonzero(flat)
        result[c] = _coplanar_overlap(a[c], b[c], na[c], margin[c])
    return result


def _candidates(vertices: np.ndarray, fa: np.ndarray, fb: np.ndarray,
                same: bool) -> tuple[np.ndarray, np.ndarray]:
    """Pairs whose bounding spheres (centroid, farthest corner) meet, then whose boxes do.

    The k-d tree search radius is set by the largest triangles of each set, so the candidate
    count (and the cost) grows when a few triangles are much larger than the rest.
    """
    v = np.asarray(vertices, dtype=float)
    pa, pb = v[fa], v[fb]
    ca, cb = row_means(pa.swapaxes(1, 2)), row_means(pb.swapaxes(1, 2))
    ra = row_max(row_norms(pa - ca[:, None]))
    rb = row_max(row_norms(pb - cb[:, None]))
    # a little slack so that touching spheres are kept
    reach = 1.0 + 1e-9
    tree_a = spatial.cKDTree(ca)
    tree_b = tree_a if same else spatial.cKDTree(cb)
    found = tree_a.sparse_distance_matrix(tree_b, max_distance=reach * (ra.max() + rb.max()),
                                          output_type="ndarray")
    i = found["i"].astype(np.int64)
    j = found["j"].astype(np.int64)
    keep = found["v"] <= reach * (ra[i] + rb[j])
    if same:
        keep &= i < j
    i, j = i[keep], j[keep]
    # corners' coordinates (m, axis, corner): their minima and maxima by axis
    qa, qb = pa[i].swapaxes(1, 2), pb[j].swapaxes(1, 2)
    box = (row_min(qa) <= row_max(qb) + 1e-12) & (row_min(qb) <= row_max(qa) + 1e-12)
    keep = rows_all(box)
    return i[keep], j[keep]


def intersecting_pairs(
    vertices: np.ndarray, faces_a: np.ndarray, faces_b: np.ndarray
) -> np.ndarray:
    """All intersecting pairs between two sets of triangles of one mesh.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces_a : (p, 3) int array
    faces_b : (q, 3) int array

    Returns
    -------
    (m, 2) int64 array
        Rows ``(i, j)``: ``faces_a[i]`` intersects ``faces_b[j]`` (see
        :func:`triangles_intersect` for what counts). Empty when none do.
    """
    fa = np.asarray(faces_a, dtype=np.int64).reshape(-1, 3)
    fb = np.asarray(faces_b, dtype=np.int64).reshape(-1, 3)
    if len(fa) == 0 or len(fb) == 0:
        return np.zeros((0, 2), dtype=np.int64)
    i, j = _candidates(vertices, fa, fb, same=False)
    hit = triangles_intersect(vertices, fa[i], fb[j])
    return np.column_stack([i[hit], j[hit]])


def self_intersections(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Intersecting pairs ``(i, j)``, ``i < j``, of triangles within one set of faces.

    Neighbours touching along their shared edge or at a shared vertex are not reported.
    """
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if len(f) < 2:
        return np.zeros((0, 2), dtype=np.int64)
    i, j = _candidates(vertices, f, f, same=True)
    hit = triangles_intersect(vertices, f[i], f[j])
    return np.column_stack([i[hit], j[hit]])


def patch_intersects_surroundings(
    vertices: np.ndarray, fill_faces: np.ndarray, ring_faces: np.ndarray
) -> np.ndarray:
    """Where a filled patch pierces or overlaps the surface around it.

    Parameters
    ----------
    vertices : (n, 3) float array
        Positions of the original and the new vertices.
    fill_faces : (p, 3) int array
        The fill's triangles.
    ring_faces : (q, 3) int array
        The surrounding triangles (e.g. a few rings around the hole).

    Returns
    -------
    (m, 2) int64 array
        Rows ``(i, j)``: ``fill_faces[i]`` intersects ``ring_faces[j]``; empty when the patch
        is clean. Touching at the hole's boundary (shared vertices and edges) does not count.

    Examples
    --------
    >>> from surfinpaint.data import sphere
    >>> v, f = sphere(2)
    >>> patch_intersects_surroundings(v, f[:10], f[10:]).shape
    (0, 2)
    """
    return intersecting_pairs(vertices, fill_faces, ring_faces)
