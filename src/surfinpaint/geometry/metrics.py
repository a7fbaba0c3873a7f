"""Distances between surfaces, to score a filled hole against the patch that was cut out."""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from surfinpaint.compiled import Kernel, run
from surfinpaint.geometry.closest_point import closest_point_on_triangles
from surfinpaint.geometry.cutting import compact
from surfinpaint.geometry.mesh import face_areas
from surfinpaint.geometry.rows import row_max, row_means, row_sums

__all__ = ["SurfaceDistance", "hole_patch_of", "mean_surface_distances", "point_mesh_distance",
           "point_mesh_distances", "sample_surface", "surface_distance",
           "surface_distance_samples"]


def _min_distance_numpy(points: np.ndarray, tri: np.ndarray, cand: np.ndarray,
                        start: np.ndarray) -> np.ndarray:
    """``min over j in [start[i], start[i+1]) of dist(points[i], tri[cand[j]])``."""
    owner = np.repeat(np.arange(len(points)), np.diff(start))
    t = tri[cand]
    p = points[owner]
    q = closest_point_on_triangles(p, t[:, 0], t[:, 1], t[:, 2])
    return np.minimum.reduceat(np.linalg.norm(q - p, axis=1), start[:-1])


def _min_distance_loops(points, tri, cand, start, out):  # pragma: no cover - compiled
    """Plain-loop version of :func:`_min_distance_numpy`, compiled by numba when present,
    written into ``out`` (an ``np.empty`` in the kernel would be one more compilation)."""
    m = len(points)
    for i in range(m):
        px, py, pz = points[i, 0], points[i, 1], points[i, 2]
        best = np.inf
        for j in range(start[i], start[i + 1]):
            t = cand[j]
            ax, ay, az = tri[t, 0, 0], tri[t, 0, 1], tri[t, 0, 2]
            bx, by, bz = tri[t, 1, 0], tri[t, 1, 1], tri[t, 1, 2]
            cx, cy, cz = tri[t, 2, 0], tri[t, 2, 1], tri[t, 2, 2]
            abx, aby, abz = bx - ax, by - ay, bz - az
            acx, acy, acz = cx - ax, cy - ay, cz - az
            d1 = abx * (px - ax) + aby * (py - ay) + abz * (pz - az)
            d2 = acx * (px - ax) + acy * (py - ay) + acz * (pz - az)
            d3 = abx * (px - bx) + aby * (py - by) + abz * (pz - bz)
            d4 = acx * (px - bx) + acy * (py - by) + acz * (pz - bz)
            d5 = abx * (px - cx) + aby * (py - cy) + abz * (pz - cz)
            d6 = acx * (px - cx) + acy * (py - cy) + acz * (pz - cz)
            va = d3 * d6 - d5 * d4
            vb = d5 * d2 - d1 * d6
            vc = d1 * d4 - d3 * d2
            nx, ny, nz = aby * acz - abz * acy, abz * acx - abx * acz, abx * acy - aby * acx
            ab2 = abx * abx + aby * aby + abz * abz
            ac2 = acx * acx + acy * acy + acz * acz
            if nx * nx + ny * ny + nz * nz <= 1e-20 * ab2 * ac2:  # degenerate (closest_point)
                for e in range(3):  # nearest point of its three edges
                    if e == 0:
                        ux, uy, uz, wx, wy, wz = ax, ay, az, bx, by, bz
                    elif e == 1:
                        ux, uy, uz, wx, wy, wz = bx, by, bz, cx, cy, cz
                    else:
                        ux, uy, uz, wx, wy, wz = cx, cy, cz, ax, ay, az
                    ex, ey, ez = wx - ux, wy - uy, wz - uz
                    ee = ex * ex + ey * ey + ez * ez
                    s = ((px - ux) * ex + (py - uy) * ey + (pz - uz) * ez) / ee if ee > 0 else 0.0
                    s = min(max(s, 0.0), 1.0)
                    d = (ux + s * ex - px) ** 2 + (uy + s * ey - py) ** 2 + (uz + s * ez - pz) ** 2
                    if d < best:
                        best = d
                continue
            if d1 <= 0 and d2 <= 0:
                qx, qy, qz = ax, ay, az
            elif d3 >= 0 and d4 <= d3:
                qx, qy, qz = bx, by, bz
            elif d6 >= 0 and d5 <= d6:
                qx, qy, qz = cx, cy, cz
            elif vc <= 0 and d1 >= 0 and d3 <= 0:
                den = d1 - d3  # |ab|²: zero on a degenerate edge (its point is a)
                s = min(max(d1 / den, 0.0), 1.0) if den > 0.0 else 0.0
                qx, qy, qz = ax + s * abx, ay + s * aby, az + s * abz
            elif vb <= 0 and d2 >= 0 and d6 <= 0:
                den = d2 - d6  # |ac|²
                s = min(max(d2 / den, 0.0), 1.0) if den > 0.0 else 0.0
                qx, qy, qz = ax + s * acx, ay + s * acy, az + s * acz
            elif va <= 0 and d4 - d3 >= 0 and d5 - d6 >= 0:
                den = (d4 - d3) + (d5 - d6)  # |bc|²
                s = min(max((d4 - d3) / den, 0.0), 1.0) if den > 0.0 else 0.0
                qx, qy, qz = bx + s * (cx - bx), by + s * (cy - by), bz + s * (cz - bz)
            else:
                den = va + vb + vc
                if den != 0.0:
                    v = vb / den
                    w = vc / den
                    qx = ax + v * abx + w * acx
                    qy = ay + v * aby + w * acy
                    qz = az + v * abz + w * acz
                else:  # degenerate triangle: nearest corner
                    qx, qy, qz = ax, ay, az
            d = (qx - px) ** 2 + (qy - py) ** 2 + (qz - pz) ** 2
            if d < best:
                best = d
        out[i] = np.sqrt(best)
    return out


# the per-pair region test is branchy: compiled it is ~30x faster than numpy
_MIN_DISTANCE_KERNEL = Kernel(_min_distance_loops, nogil=True)


def _ball_loops(points, reach, rho, rho_max, margin, axis, order, sorted_x, centroid, start,
                cand):  # pragma: no cover - compiled
    """The ids of the centroids ``t`` within ``(reach[i] + rho[t]) (1 + 1e-9) + margin`` of
    ``points[i]`` (``rho`` zero: a ball of radius ``reach[i]``), compiled by numba: those in
    a window around the point along ``axis`` (``sorted_x``: the centroids' coordinates on it
    in increasing order, ``order`` their ids) as wide as the largest of those radii
    (``rho_max`` at least every ``rho``), then the full test. With an empty ``cand`` each
    point's count is written to ``start[i + 1]``; else its ids from ``start[i]`` on. The
    window is wider than the radius by far more than the rounding of its ends, so that it
    leaves out no centroid the full test keeps."""
    fill = len(cand) > 0
    n = len(sorted_x)
    for i in range(len(points)):
        px, py, pz = points[i, 0], points[i, 1], points[i, 2]
        x = points[i, axis]
        widest = (reach[i] + rho_max) * (1.0 + 1e-9) + margin
        half = widest * (1.0 + 1e-6) + 1e-9 * abs(x)
        low, high = 0, n
        while low < high:  # the first centroid at or beyond x - half
            mid = (low + high) // 2
            if sorted_x[mid] < x - half:
                low = mid + 1
            else:
                high = mid
        k = start[i] if fill else 0
        end = x + half
        for j in range(low, n):
            if sorted_x[j] > end:
                break
            t = order[j]
            r = (reach[i] + rho[t]) * (1.0 + 1e-9) + margin
            dx, dy, dz = centroid[t, 0] - px, centroid[t, 1] - py, centroid[t, 2] - pz
            if dx * dx + dy * dy + dz * dz <= r * r:
                if fill:
                    cand[k] = t
                k += 1
        if not fill:
            start[i + 1] = k


# a ball query of thousands of points: in a compiled loop it makes no Python lists
_BALL_KERNEL = Kernel(_ball_loops, nogil=True)


def _numba_kernel():
    """The compiled min-distance kernel, or None without numba."""
    return _MIN_DISTANCE_KERNEL.get()


class _TriangleIndex:
    """Nearest-triangle queries: a KD-tree on triangle centroids and an exact refinement.

    For a point ``p`` and a triangle with centroid ``g`` and circumscribing radius ``ρ``
    (largest centroid-to-corner distance), ``dist(p, T) >= |p − g| − ρ``. So with an upper
    bound ``u`` from a few nearest centroids, every triangle that can be closer has
    ``|p − g| <= u + ρ_max``; those are all checked exactly.
    """

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        self.faces = np.asarray(faces, np.int64)
        self.tri = np.asarray(vertices, float)[self.faces]
        self.centroid = row_means(self.tri.swapaxes(1, 2))
        self.rho = np.sqrt(row_sums((self.tri - self.centroid[:, None]) ** 2).max())
        self._rho_each = None  # each triangle's circumscribing radius, made at its first use
        self._tree = None
        self._by_x = None  # an axis, the centroids' order on it, their coordinates so ordered
        self.use_numba = True

    @property
    def tree(self) -> cKDTree:
        """The KD-tree of the centroids, made at its first query."""
        if self._tree is None:
            self._tree = cKDTree(self.centroid)
        return self._tree

    @property
    def rho_each(self) -> np.ndarray:
        """Each triangle's circumscribing radius (largest centroid-to-corner distance)."""
        if self._rho_each is None:
            self._rho_each = np.sqrt(row_max(row_sums((self.tri - self.centroid[:, None]) ** 2)))
        return self._rho_each

    def _min_exact(self, p: np.ndarray, cand: np.ndarray, start: np.ndarray) -> np.ndarray:
        return run(_numba_kernel() if self.use_numba else None,
                   lambda kernel: kernel(p, self.tri, cand, start, np.empty(len(p))),
                   lambda: _min_distance_numpy(p, self.tri, cand, start),
                   cost=4e-7 * len(cand) + 5e-4)  # numpy's seconds, estimated

    def distance(self, points: np.ndarray) -> np.ndarray:
        return self.nearest(points)[0]

    def nearest(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The distances of ``points`` (m,), and the ``k`` nearest centroids' distances
        (m, k) and ids (m, k) they were bounded by (:meth:`distance_after`)."""
        points = np.asarray(points, float)
        # 12 nearest centroids: fewer points left to the ball query than with 8 (measured
        # on the self-check's distances: 0.55 against 0.72 s CPU), the same minimum
        k = min(12, len(self.centroid))
        if len(points) == 0:
            return np.zeros(0), np.zeros((0, k)), np.zeros((0, k), np.int64)
        dist, near = self.tree.query(points, k=k)
        dist, near = dist.reshape(len(points), k), near.reshape(len(points), k)
        best = self._min_exact(points, near.ravel(), np.arange(len(points) + 1) * k)
        if k == len(self.centroid):
            return best, dist, near
        # complete unless a centroid beyond the k nearest can hide a closer triangle
        todo = np.flatnonzero(dist[:, -1] <= best + self.rho)
        if len(todo):
            best[todo] = self._nearer(points[todo], best[todo])
        return best, dist, near

    def within(self, points: np.ndarray, radius: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The triangles whose centroid is within ``radius`` of each point: ``(cand,
        start)``, point ``i``'s ids ``cand[start[i]:start[i + 1]]``.

        The compiled search keeps every centroid within the radius widened by 1e-9 of it
        and of the coordinates' size: the KD-tree's ball (its numpy version) and a few more
        at its edge, each farther than the radius to rounding. The minimum over those
        triangles is the minimum over the ball's (a triangle beyond the ball cannot be
        closer, :class:`_TriangleIndex`), to the bit: a minimum is exact.
        """
        return self._ball(points, radius, np.zeros(len(self.centroid)), 0.0)

    def _nearer(self, points: np.ndarray, best: np.ndarray) -> np.ndarray:
        """The distances of ``points`` given ``best``, distances to some triangles (upper
        bounds): the least of ``best`` and the distances to the triangles that can be nearer,
        those whose centroid is within ``best + ρ_T`` (their own circumscribing radius ρ_T,
        :attr:`rho_each`; widened as :meth:`within` widens) in the compiled search, within
        ``best + ρ_max`` in its numpy version (the KD-tree's ball).

        Why each triangle's ρ: with the largest one the ball held 180 of a test patch's 423
        triangles a sample (tenderizer #6's self-check, session 47 helper), each then
        measured exactly. The same bits: a triangle left out is farther than ``best`` by
        far more than rounding, and a minimum over any set that holds the nearest triangle is
        the same number."""
        cand, start = self._ball(points, best, self.rho_each, float(self.rho))
        return np.minimum(best, self._min_exact(points, cand, start))

    def _ball(self, points, reach, rho, rho_max):
        """:func:`_ball_loops`' search (the KD-tree's ball of radii ``reach + rho_max`` in
        its numpy version): ``(cand, start)``."""
        kernel = _BALL_KERNEL.get()

        def compiled(kernel):
            if self._by_x is None:  # along the longest side of the box: the fewest in a window
                axis = int(np.argmax(np.ptp(self.centroid, axis=0)))
                order = np.argsort(self.centroid[:, axis], kind="stable")
                self._by_x = axis, order, np.ascontiguousarray(self.centroid[order, axis])
            scale = float(np.nanmax(np.abs(self.centroid))) + float(np.abs(points).max())
            ball = (points, np.ascontiguousarray(reach, dtype=float), rho, rho_max,
                    1e-9 * scale, *self._by_x, self.centroid)
            start = np.zeros(len(points) + 1, np.int64)
            kernel(*ball, start, np.empty(0, np.int64))
            np.cumsum(start, out=start)
            cand = np.empty(start[-1], np.int64)
            if len(cand):
                kernel(*ball, start, cand)
            return cand, start

        def kd_tree():
            lists = self.tree.query_ball_point(points, reach + rho_max)
            counts = np.fromiter(map(len, lists), np.int64, len(lists))
            start = np.concatenate([[0], np.cumsum(counts)])
            return np.fromiter(itertools.chain.from_iterable(lists), np.int64, start[-1]), start

        return run(kernel if self.use_numba else None, compiled, kd_tree,
                   cost=1e-5 * len(points) + 5e-4)  # the KD-tree's seconds, estimated

    def distance_after(self, points: np.ndarray, dist: np.ndarray, near: np.ndarray,
                       slack, requery: bool = False) -> np.ndarray:
        """:meth:`distance` of ``points`` from nearest centroids ``(dist, near)`` found
        before (:meth:`nearest`, for other points or on another index of the same faces):
        the same numbers, mostly without a query.

        ``slack`` (scalar or per point) bounds how much closer than ``dist[:, -1]`` a
        triangle outside a point's ``near`` can be here; where the closest of ``near`` is
        nearer than ``dist[:, -1] − slack`` no other triangle can be closer. The other
        points are searched here in the ball that distance bounds (as :meth:`nearest`'s
        last step): a triangle closer than it has its centroid within it plus ``rho``.

        Why not :meth:`distance` of the others: the self-check's slack is the largest move
        of any centroid, so most points fail the test (1,000-2,000 of its 2,000 samples,
        session 44 helper), and each then paid a KD-tree query and the 12 nearest
        triangles' distances again for a bound its ``near`` gives already. The minimum over
        any set of triangles that holds the nearest is the same number.

        With ``requery`` (:meth:`distances_moving`: points far from those ``near`` was found
        for), the searched points' bounds are first lowered to the distance of the triangle
        of their nearest centroid here: a bound from stale ``near`` was 5-11 times the
        distance on a CAD part's fills (spanner #6 of holdout 10, session 52 helper), and
        its ball held ~190 of the patch's 430 triangles a point, against ~11 from this one;
        the minimum is the same number.
        """
        points = np.asarray(points, float)
        k = near.shape[1]
        best = self._min_exact(points, near.ravel(), np.arange(len(points) + 1) * k)
        if k == len(self.centroid):
            return best
        # a margin far above the round-off of these sums
        todo = np.flatnonzero(dist[:, -1] - slack <= best + 1e-9 * (dist[:, -1] + slack))
        if len(todo):
            bound = best[todo]
            if requery:
                nearest = self.tree.query(points[todo], k=1)[1]
                bound = np.minimum(bound, self._min_exact(points[todo], nearest,
                                                          np.arange(len(todo) + 1)))
            best[todo] = self._nearer(points[todo], bound)
        return best

    def slack_after(self, other: _TriangleIndex) -> float:
        """The ``slack`` of :meth:`distance_after` for centroids found in ``other``, an index
        of the same faces on moved vertices: a triangle ``T`` outside a point's ``near`` has
        its centroid at least ``dist[:, -1] − |Δg_T|`` from it here, so
        ``dist(p, T) >= dist[:, -1] − (|Δg_T| + ρ_T)``."""
        moved = np.sqrt(row_sums((self.centroid - other.centroid) ** 2))
        return float((moved + self.rho_each).max())

    def distances_moving(self, samples) -> list[np.ndarray]:
        """:meth:`distance` of each point set in ``samples`` (of equal sizes; the samples
        of candidate fills of one triangulation, which barely move from one to the next),
        each searched from the nearest centroids of the first: a triangle outside a point's
        ``near`` is at least ``dist[:, -1] − |Δp| − ρ`` from it."""
        out, first = [], None
        for points in samples:
            points = np.asarray(points, float)
            if first is None or len(points) != len(first[0]):
                best, dist, near = self.nearest(points)
                first = first or (points, dist, near)
                out.append(best)
                continue
            shift = np.sqrt(((points - first[0]) ** 2).sum(axis=1))
            out.append(self.distance_after(points, *first[1:], shift + self.rho, requery=True))
        return out


def point_mesh_distances(points: np.ndarray, meshes) -> list[np.ndarray]:
    """:func:`point_mesh_distance` of the same ``points`` to each of ``meshes`` (a sequence
    of (vertices, faces)): the same numbers; meshes with the faces of the first are searched
    from its nearest triangles (:meth:`_TriangleIndex.distance_after`)."""
    out, first = [], None
    for vertices, faces in meshes:
        if len(faces) == 0:
            raise ValueError("the mesh has no faces")
        index = _TriangleIndex(vertices, faces)
        if first is not None and np.array_equal(index.faces, first[0].faces):
            out.append(index.distance_after(points, *first[1:], index.slack_after(first[0])))
            continue
        best, dist, near = index.nearest(points)
        first = first or (index, dist, near)
        out.append(best)
    return out


def warm(vertices: np.ndarray, faces: np.ndarray) -> None:
    """Load (or compile) the distance kernels by one call each on a mesh
    (:mod:`surfinpaint.fill.warmup`; the calls' types are a real fill's)."""
    index = _TriangleIndex(vertices, faces)
    index.distance(vertices[:3])
    index.within(vertices[:3], np.ones(3))


def point_mesh_distance(points: np.ndarray, vertices: np.ndarray,
                        faces: np.ndarray) -> np.ndarray:
    """Exact unsigned distance from each point to a triangle mesh.

    Parameters
    ----------
    points : (m, 3) float array
    vertices : (n, 3) float array
    faces : (f, 3) int array

    Returns
    -------
    (m,) float array
    """
    if len(faces) == 0:
        raise ValueError("the mesh has no faces")
    return _TriangleIndex(vertices, faces).distance(points)


def sample_surface(vertices: np.ndarray, faces: np.ndarray, n_samples: int,
                   seed: int = 0, *, return_faces: bool = False):
    """Area-uniform random points on a triangle mesh (fixed seed: reproducible).

    Returns
    -------
    (n_samples, 3) float array
        The points; with ``return_faces``, also the (n_samples,) int array of the face each
        lies on (the same draw).
    """
    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    area = face_areas(v, f)
    total = area.sum()
    if not total > 0:
        raise ValueError("the mesh has zero area")
    rng = np.random.default_rng(seed)
    t = rng.choice(len(f), size=n_samples, p=area / total)
    r1 = np.sqrt(rng.random(n_samples))
    r2 = rng.random(n_samples)
    tri = v[f[t]]
    points = ((1 - r1)[:, None] * tri[:, 0] + (r1 * (1 - r2))[:, None] * tri[:, 1]
              + (r1 * r2)[:, None] * tri[:, 2])
    return (points, t) if return_faces else points


@dataclass(frozen=True)
class SurfaceDistance:
    """The two-sided distance between surfaces A and B (:func:`surface_distance`), in the
    meshes' units.

    Attributes
    ----------
    mean_ab, mean_ba : float
        Mean distance of A's samples to B, and of B's samples to A.
    mean : float
        ``(mean_ab + mean_ba) / 2``.
    hausdorff : float
        The largest distance either way, ``max(max_ab, max_ba)``.
    max_ab, max_ba : float
        The one-sided maxima, over the samples and the vertices.
    rms : float
        Root mean square over both sample sets.
    """

    mean_ab: float
    mean_ba: float
    mean: float
    hausdorff: float
    max_ab: float
    max_ba: float
    rms: float


def surface_distance(patch_vertices: np.ndarray, patch_faces: np.ndarray,
                     truth_vertices: np.ndarray, truth_faces: np.ndarray,
                     n_samples: int = 20000, seed: int = 0) -> SurfaceDistance:
    """Two-sided distance between two triangle meshes (a filled patch and its ground truth).

    Each surface is sampled area-uniformly (``n_samples`` points, fixed seed) and every
    sample's exact distance to the other surface is computed. The vertices are added to the
    samples for the maximum, so the Hausdorff estimate does not miss the corners.

    Parameters
    ----------
    patch_vertices, patch_faces : arrays
        Surface A (e.g. the filled patch).
    truth_vertices, truth_faces : arrays
        Surface B (e.g. the removed patch).
    n_samples : int
        Samples per surface.
    seed : int

    Returns
    -------
    SurfaceDistance
        The means, maxima and RMS of the distances A to B and B to A.

    Examples
    --------
    >>> from surfinpaint.data import sphere
    >>> v, f = sphere(3)
    >>> d = surface_distance(v, f, 1.1 * v, f)
    >>> bool(abs(d.mean - 0.1) < 0.005)
    True
    """
    means, maxima, sq = [], [], []
    for va, fa, vb, fb in ((patch_vertices, patch_faces, truth_vertices, truth_faces),
                           (truth_vertices, truth_faces, patch_vertices, patch_faces)):
        va = np.asarray(va, float)
        fa = np.asarray(fa, np.int64)
        index = _TriangleIndex(vb, fb)
        d = index.distance(sample_surface(va, fa, n_samples, seed))
        dv = index.distance(va[np.unique(fa)])
        means.append(float(d.mean()))
        maxima.append(float(max(d.max(), dv.max())))
        sq.append(d**2)
    return SurfaceDistance(mean_ab=means[0], mean_ba=means[1],
                           mean=0.5 * (means[0] + means[1]), hausdorff=max(maxima),
                           max_ab=maxima[0], max_ba=maxima[1],
                           rms=float(np.sqrt(np.concatenate(sq).mean())))


def mean_surface_distances(patches, truth_vertices: np.ndarray, truth_faces: np.ndarray,
                           n_samples: int = 20000, seed: int = 0) -> list[float]:
    """``surface_distance(patch, truth).mean`` for several patches against one truth,
    with the truth's samples and search structure made once (the same numbers, less work).

    Parameters
    ----------
    patches : sequence of (vertices, faces)
    truth_vertices, truth_faces : arrays
    n_samples, seed :
        As :func:`surface_distance`.

    Returns
    -------
    list of float
    """
    return [float(0.5 * (a.mean() + b.mean())) for a, b in
            surface_distance_samples(patches, truth_vertices, truth_faces, n_samples, seed)]


def surface_distance_samples(patches, truth_vertices: np.ndarray, truth_faces: np.ndarray,
                             n_samples: int = 20000, seed: int = 0
                             ) -> list[tuple[np.ndarray, np.ndarray]]:
    """The per-sample distances behind :func:`mean_surface_distances`: for each patch,
    ``(ab, ba)``, the distances of the patch's samples to the truth and of the truth's
    samples (the same for every patch; their faces: :func:`sample_surface` with
    ``return_faces``) to the patch.

    Returns
    -------
    list of (ab, ba) pairs of (n_samples,) float arrays
    """
    truth_index = _TriangleIndex(truth_vertices, truth_faces)
    truth_samples = sample_surface(truth_vertices, truth_faces, n_samples, seed)
    patches = list(patches)
    samples = [sample_surface(vertices, faces, n_samples, seed) for vertices, faces in patches]
    ba = point_mesh_distances(truth_samples, patches)
    ab = truth_index.distances_moving(samples)
    return list(zip(ab, ba, strict=True))


def hole_patch_of(result_vertices: np.ndarray, result_faces: np.ndarray, n_original: int,
                  original_faces: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The patch a hole filler added: its faces with their vertices, compactly indexed.

    A face belongs to the patch when it uses a new vertex (id >= ``n_original``) or, when
    ``original_faces`` is given, when it is not one of the original faces (so patch faces
    spanning only boundary vertices are found too).

    Parameters
    ----------
    result_vertices, result_faces : arrays
        The filled mesh: the original vertices first and unchanged, new vertices appended.
    n_original : int
        Number of vertices of the mesh before filling.
    original_faces : (f, 3) int array, optional
        The faces of the mesh before filling.

    Returns
    -------
    vertices, faces
        The patch, with its vertices in the order of the filled mesh.

    Notes
    -----
    Give ``original_faces`` whenever possible: without it a patch face whose three corners are
    all boundary vertices (common in small holes and along the border) is missed.
    """
    v = np.asarray(result_vertices, float)
    f = np.asarray(result_faces, np.int64)
    new = (f >= n_original).any(axis=1)
    if original_faces is not None:
        original = np.sort(np.asarray(original_faces, np.int64), axis=1)
        key = np.sort(f, axis=1)
        base = max(int(f.max(initial=0)), int(original.max(initial=0))) + 1
        if base < 2**20:
            code = (key[:, 0] * base + key[:, 1]) * base + key[:, 2]
            ocode = (original[:, 0] * base + original[:, 1]) * base + original[:, 2]
            new |= ~np.isin(code, ocode)
        else:  # codes would overflow int64
            known = set(map(tuple, original.tolist()))
            new |= np.array([tuple(k) not in known for k in key.tolist()], bool)
    return compact(v, f[new])[:2]
