"""Is a piece of surface a plane under noise? Two significance tests on its vertices, with no
distance threshold: the noise level is estimated from the points themselves.

Used by the conformal fill (:func:`surfinpaint.fill.conformal.conformal_fill`) on the known
vertices around a hole: on a range scan's flat face the faired fills take their slopes from
the noisy ring around the loop and carry that noise into the fill, while a fill laid on the
fitted plane averages it (docs/candidates.md, "Session 26"). Next to a sharp edge of a
scanned part a few of those vertices lie across the edge, off the face's plane:
:func:`trimmed_plane_test` tests the rest (docs/candidates.md, "Session 28").
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from surfinpaint.errors import how_many
from surfinpaint.geometry.rows import rows_all
from surfinpaint.lazy import lazy_module

# the F and normal tails (fdtrc, ndtr, ndtri; scipy.stats would cost 1 s): imported at the
# first plane test, not at start, since the faired fill imports this module for
# meeting_line (scipy.special is 45 ms of the command line's start; a large default fill
# imports it on the kernels' loading thread, under scipy.spatial)
special = lazy_module("scipy.special")

__all__ = ["PlaneTest", "TwoPlanes", "meeting_line", "morans_i", "part_plane_test", "plane_test",
           "trimmed_plane_test", "two_plane_test"]

# the trimmed fit (:func:`trimmed_plane_test`) gives up where it leaves out more than
# TRIM_MOST of the points (fixed before any run; docs/candidates.md, "Session 28")
TRIM_MOST = 0.2
# ... and at most this fraction of the points that must stay (the hole's loop): a loop
# vertex on a scan's shadow edge or a part's edge, off the plane, is met by the laid fill's
# triangles along the loop (fixed before any run; docs/candidates.md, "Session 29")
TRIM_KEEP_MOST = 0.1
# two planes (:func:`two_plane_test`) are tried only where each holds at least this share of
# the points and they meet at this angle (degrees) or more: a part's edge, not a bend (both
# fixed before any run; docs/candidates.md, "Session 29")
TWO_PLANES_SHARE = 0.15
TWO_PLANES_ANGLE = 30.0
# ... and where each plane's points lie on its own side of the line where the planes meet,
# but for this fraction (noise at the edge): at an edge they do; two planes fitted to a
# smooth bump cross through its points instead (on the tuning side, edges of scanned parts
# leave at most 1.1 % across, the coarse egg crates and quadruped 32-57 %; docs/
# candidates.md, "Session 29")
TWO_PLANES_ACROSS = 0.05


@dataclass(frozen=True)
class PlaneTest:
    """The verdict of :func:`plane_test`.

    Attributes
    ----------
    flat : bool
        Neither test is significant at the level asked for: no curvature and no shape in the
        plane's residuals can be told from independent noise.
    p_curvature : float
        The F-test's p-value: a quadric height field against the plane.
    p_pattern : float
        Moran's I's one-sided p-value: the plane's residuals alike between neighbours.
    centre, normal : (3,) float arrays
        The least-squares plane (a point on it and its unit normal).
    noise : float
        The noise level (standard deviation, mesh units) the quadric's residual gives.
    points : int
        How many points were tested.
    left_out : int
        How many more points a trimmed fit left out, all on one side
        (:func:`trimmed_plane_test`); 0 for :func:`plane_test`.
    past_edges : int
        How many more points were not tested because they lie past a sharp edge of the
        surface, away from the hole (set by the caller that chose the points; 0 here).
    """

    flat: bool
    p_curvature: float
    p_pattern: float
    centre: np.ndarray
    normal: np.ndarray
    noise: float
    points: int
    left_out: int = 0
    past_edges: int = 0

    def sentence(self) -> str:
        """The verdict in words, for a hole's report."""
        trimmed = (f"; {how_many(self.left_out, 'vertex', 'vertices')} off it on one side "
                   "left out" if self.left_out else "")
        if self.past_edges:
            trimmed += (f"; {how_many(self.past_edges, 'vertex', 'vertices')} past the part's "
                        "sharp edges left out")
        return (f"the known surface around the hole is a plane within its noise "
                f"(σ = {self.noise:.3g}; curvature p = {self.p_curvature:.2g}, pattern "
                f"p = {self.p_pattern:.2g}, "
                f"{how_many(self.points, 'vertex', 'vertices')}{trimmed})")



@dataclass(frozen=True)
class TwoPlanes:
    """The verdict of :func:`two_plane_test`: the points as two planes meeting at an edge.

    Attributes
    ----------
    first, second : PlaneTest
        :func:`plane_test` of each plane's points.
    second_side : (n,) bool array
        Which tested points belong to the second plane.
    angle : float
        The angle between the planes' normals, degrees (90 at a box's edge).
    """

    first: PlaneTest
    second: PlaneTest
    second_side: np.ndarray
    angle: float

    @property
    def flat(self) -> bool:
        """Both planes are planes within their noise."""
        return self.first.flat and self.second.flat

    @property
    def p_curvature(self) -> float:
        return min(self.first.p_curvature, self.second.p_curvature)

    @property
    def p_pattern(self) -> float:
        return min(self.first.p_pattern, self.second.p_pattern)

    @property
    def noise(self) -> float:
        return max(self.first.noise, self.second.noise)

    @property
    def points(self) -> int:
        return self.first.points + self.second.points

    left_out = 0  # as PlaneTest's: no point is left out
    past_edges = 0

    def sentence(self) -> str:
        """The verdict in words, for a hole's report."""
        return (f"the known surface around the hole is two planes meeting at "
                f"{self.angle:.0f}°, each within its noise (σ = {self.first.noise:.3g} and "
                f"{self.second.noise:.3g}; curvature p ≥ {self.p_curvature:.2g}, pattern "
                f"p ≥ {self.p_pattern:.2g}; {self.first.points} and {self.second.points} "
                "vertices)")

def morans_i(values: np.ndarray, edges: np.ndarray) -> tuple[float, float]:
    """Moran's I of ``values`` on a graph, and its one-sided p-value for positive
    autocorrelation.

    Parameters
    ----------
    values : (n,) float array
    edges : (e, 2) int array
        The graph's edges (each once; weights 1 both ways).

    Returns
    -------
    I, p : float
        ``p`` is small when neighbours' values are alike, as a smooth shape's are and
        independent noise's are not (normal approximation under the normality null, Cliff &
        Ord 1981). ``(0, 1)`` for constant values or no edges.
    """
    values = np.asarray(values, dtype=float)
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    n = len(values)
    z = values - values.mean()
    weight = 2.0 * len(edges)  # both directions
    if weight == 0 or not np.any(z):
        return 0.0, 1.0
    degree = np.bincount(edges.ravel(), minlength=n).astype(float)
    moran = (n / weight) * 2.0 * np.sum(z[edges[:, 0]] * z[edges[:, 1]]) / np.sum(z * z)
    expected = -1.0 / (n - 1)
    s1, s2 = 2.0 * weight, float(np.sum((2.0 * degree) ** 2))
    variance = ((n * n * s1 - n * s2 + 3.0 * weight * weight)
                / ((n * n - 1.0) * weight * weight) - expected**2)
    score = (moran - expected) / np.sqrt(max(variance, 1e-300))
    return float(moran), float(special.ndtr(-score))


def plane_test(points: np.ndarray, edges: np.ndarray | None = None, *,
               alpha: float = 0.01) -> PlaneTest:
    """Test whether ``points`` lie on a plane up to independent noise.

    In the points' principal frame a plane and a quadric height field are fitted by least
    squares. Two tests at level ``alpha``:

    - an F-test of the quadric's three extra terms, ``F = ((RSS_plane − RSS_quadric) / 3) /
      (RSS_quadric / (n − 6))`` against F(3, n − 6): curvature above the noise, whose level
      is the quadric's own residual;
    - with ``edges``, Moran's I of the plane's residuals (:func:`morans_i`): a shape that no
      quadric fits (a crease, folds) leaves residuals alike between neighbours, which the
      F-test would take for noise.

    Parameters
    ----------
    points : (n, 3) float array
    edges : (e, 2) int array, optional
        Mesh edges between the points (ids into ``points``); without them only the F-test.
    alpha : float
        Significance level of both tests, in (0, 1).

    Returns
    -------
    PlaneTest
        ``flat`` when neither test is significant; points on a plane to rounding are flat;
        6 points or fewer are not (nothing to test: the p-values are NaN).

    Raises
    ------
    ValueError
        For ``alpha`` outside (0, 1) or points that are not (n, 3).
    """
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"points must be an (n, 3) array, got shape {points.shape}")
    if not 0.0 < alpha < 1.0:
        raise ValueError(f"alpha must be in (0, 1), got {alpha!r}")
    n = len(points)
    if n == 0:
        raise ValueError("no points to test")
    centroid = points.mean(axis=0)
    axes = np.linalg.svd(points - centroid, full_matrices=False)[2]  # in-plane, in-plane, normal
    u, v, w = ((points - centroid) @ axes.T).T
    plane = np.column_stack([np.ones(n), u, v])
    quadric = np.column_stack([plane, u * u, u * v, v * v])
    coefficients = np.linalg.lstsq(plane, w, rcond=None)[0]
    residual = w - plane @ coefficients
    rss_plane = float(residual @ residual)
    rss_quadric = float(np.sum((w - quadric @ np.linalg.lstsq(quadric, w, rcond=None)[0])**2))
    normal = axes[2] - coefficients[1] * axes[0] - coefficients[2] * axes[1]
    normal /= np.linalg.norm(normal)
    centre = centroid + coefficients[0] * axes[2]
    if n <= 6:  # as many unknowns as points: nothing to test
        return PlaneTest(False, float("nan"), float("nan"), centre, normal, float("nan"), n)
    if rss_plane <= (1e-12 * float(np.ptp(u) + np.ptp(v))) ** 2 * n:  # a plane to rounding
        return PlaneTest(True, 1.0, 1.0, centre, normal, 0.0, n)
    dof = n - 6
    F = ((rss_plane - rss_quadric) / 3.0) / max(rss_quadric / dof, 1e-300)
    p_curvature = float(special.fdtrc(3, dof, F))
    p_pattern = morans_i(residual, edges)[1] if edges is not None else 1.0
    return PlaneTest(bool(p_curvature >= alpha and p_pattern >= alpha), p_curvature,
                     p_pattern, centre, normal, float(np.sqrt(rss_quadric / dof)), n)


def trimmed_plane_test(points: np.ndarray, edges: np.ndarray | None = None, *,
                       keep: np.ndarray | None = None, alpha: float = 0.01,
                       most: float = TRIM_MOST, keep_most: float = TRIM_KEEP_MOST
                       ) -> PlaneTest | None:
    """:func:`plane_test` of the points a trimmed plane fit keeps, where a few points on one
    side lie off a plane the others fit (a part's face next to its sharp edge).

    The plane is fitted by least squares, the points farther from it than n points of
    Gaussian noise would be at level ``alpha`` (Bonferroni: ``ndtri(1 − alpha / 2n)`` robust
    standard deviations, 1.4826 × the residuals' median absolute deviation) are left out,
    and the plane fitted again to the rest until nothing changes (at most 10 fits). So
    noise alone leaves out no point, at the tests' own level.
    The test applies only where that leaves out some points but at most a fraction ``most``
    of them, at most a fraction ``keep_most`` of the ``keep`` points (the hole's own loop,
    which the fill laid on the plane meets: a few of its vertices may lie off the plane, a
    loop mostly off it may not), and all left-out points on one side of the kept ``keep``
    points' centre: in a half-plane through it, in the plane's frame. A dome around a hole,
    whose outer points fall off the plane all around, is therefore not trimmed flat.

    Parameters
    ----------
    points : (n, 3) float array
    edges : (e, 2) int array, optional
        Mesh edges between the points; those between kept points go to Moran's I.
    keep : int array, optional
        Ids of points that must mostly stay (default: the test's own centre is the
        points' centroid and no point is required).
    alpha : float
        Significance level, as :func:`plane_test`'s.
    most : float
        The largest fraction of points left out.
    keep_most : float
        The largest fraction of the ``keep`` points left out (0: none may be; session 28's
        rule).

    Returns
    -------
    PlaneTest or None
        The kept points' test (``points`` counts them, ``left_out`` the others), or None
        where the trimmed fit does not apply.

    Raises
    ------
    ValueError
        As :func:`plane_test`.
    """
    points = np.asarray(points, dtype=float)
    if points.ndim != 2 or points.shape[1] != 3:
        raise ValueError(f"points must be an (n, 3) array, got shape {points.shape}")
    n = len(points)
    cut = float(special.ndtri(1.0 - alpha / (2.0 * n)))
    inliers = np.ones(n, dtype=bool)
    for _ in range(10):
        centroid = points[inliers].mean(axis=0)
        axes = np.linalg.svd(points[inliers] - centroid, full_matrices=False)[2]
        residual = (points - centroid) @ axes[2]
        middle = np.median(residual[inliers])
        spread = 1.4826 * np.median(np.abs(residual[inliers] - middle))
        fitted = np.abs(residual - middle) <= cut * spread
        if np.array_equal(fitted, inliers) or fitted.sum() <= 6:
            break
        inliers = fitted
    left_out = int(n - inliers.sum())
    required = np.zeros(n, dtype=bool) if keep is None else np.isin(np.arange(n), keep)
    if (left_out == 0 or left_out > most * n
            or (required & ~inliers).sum() > keep_most * required.sum()
            or not _on_one_side(points, inliers, required & inliers, axes)):
        return None
    local = np.full(n, -1)
    local[inliers] = np.arange(n - left_out)
    kept_edges = None
    if edges is not None:
        edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
        kept_edges = local[edges[rows_all(inliers[edges])]]
    test = plane_test(points[inliers], kept_edges, alpha=alpha)
    return PlaneTest(test.flat, test.p_curvature, test.p_pattern, test.centre, test.normal,
                     test.noise, test.points, left_out)


def part_plane_test(points: np.ndarray, edges: np.ndarray | None, kept: np.ndarray, *,
                    keep: np.ndarray | None = None, alpha: float = 0.01) -> PlaneTest | None:
    """:func:`plane_test` of the ``kept`` points (a boolean mask) that the caller chose,
    where the others lie on one side of the kept ``keep`` points' centre (in a half-plane
    through it, in the kept points' plane), as :func:`trimmed_plane_test` asks of the points
    it leaves out; None where none or all are left out or they lie all around.

    Parameters
    ----------
    points : (n, 3) float array
    edges : (e, 2) int array or None
        Mesh edges between the points; those between kept points go to Moran's I.
    kept : (n,) bool array
    keep : int array, optional
        Ids of the points whose centre the left-out ones are seen from (default: all kept).
    alpha : float
        Significance level, as :func:`plane_test`'s.

    Returns
    -------
    PlaneTest or None
        The kept points' test, ``left_out`` counting the others.
    """
    points = np.asarray(points, dtype=float)
    kept = np.asarray(kept, dtype=bool)
    n, m = len(points), int(kept.sum())
    if m in (0, n):
        return None
    centroid = points[kept].mean(axis=0)
    axes = np.linalg.svd(points[kept] - centroid, full_matrices=False)[2]
    required = np.zeros(n, dtype=bool) if keep is None else np.isin(np.arange(n), keep)
    if not _on_one_side(points, kept, required & kept, axes):
        return None
    local = np.full(n, -1)
    local[kept] = np.arange(m)
    kept_edges = None
    if edges is not None:
        edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
        kept_edges = local[edges[rows_all(kept[edges])]]
    return replace(plane_test(points[kept], kept_edges, alpha=alpha), left_out=n - m)


def _on_one_side(points, inliers, required, axes) -> bool:
    """Whether the left-out points lie in a half-plane through the centre of the required
    kept points (all kept points where none is), seen along the plane's normal: their
    directions from it leave a gap of at least half a turn."""
    centre = points[required if required.any() else inliers].mean(axis=0)
    offset = (points[~inliers] - centre) @ axes[:2].T
    angle = np.sort(np.arctan2(offset[:, 1], offset[:, 0]))
    gaps = np.diff(np.concatenate([angle, angle[:1] + 2.0 * np.pi]))
    return bool(gaps.max() >= np.pi)


def two_plane_test(points: np.ndarray, normals: np.ndarray, edges: np.ndarray | None = None,
                   *, alpha: float = 0.01, share: float = TWO_PLANES_SHARE,
                   angle: float = TWO_PLANES_ANGLE) -> TwoPlanes | None:
    """:func:`plane_test` of each side of ``points`` split into two planes: a part's face on
    each side of its sharp edge, seen by a noisy scan (where the edge's sharp turn is lost
    in the noise and the crease search finds nothing).

    The split: the points whose ``normals`` are farthest apart seed two groups (2-means on
    the normals), then each point goes to the plane it is nearer and the planes are fitted
    again until nothing changes (at most 15 fits).

    Parameters
    ----------
    points, normals : (n, 3) float arrays
        The points and their unit (vertex) normals.
    edges : (e, 2) int array, optional
        Mesh edges between the points; those within one side go to its Moran's I.
    alpha : float
        Significance level of each side's :func:`plane_test`.
    share, angle : float
        The smaller side holds at least ``share`` of the points, and the planes meet at
        ``angle`` degrees or more; else None. Also None where more than
        ``TWO_PLANES_ACROSS`` of the points lie across the line where the planes meet,
        on the other plane's side by more than three of its plane's noise (planes crossing
        through a bump, not meeting at an edge).

    Returns
    -------
    TwoPlanes or None
        The two sides' tests (``flat`` when both are planes within their noise), or None
        where no such split exists.

    Examples
    --------
    >>> u, w = np.meshgrid(np.linspace(-1, 1, 11), np.linspace(-1, 1, 11))
    >>> roof = np.column_stack([u.ravel(), w.ravel(), np.abs(u.ravel())])
    >>> n = np.column_stack([-np.sign(roof[:, 0]), np.zeros(121), np.ones(121)])
    >>> t = two_plane_test(roof, n / np.linalg.norm(n, axis=1, keepdims=True))
    >>> round(t.angle), t.flat
    (90, True)
    """
    points = np.asarray(points, dtype=float)
    normals = np.asarray(normals, dtype=float)
    n = len(points)
    if n < 2 * 7:  # a side needs more points than the quadric has terms
        return None
    first = normals[np.argmax(np.linalg.norm(normals - normals.mean(axis=0), axis=1))]
    second = normals[np.argmax(np.linalg.norm(normals - first, axis=1))]
    side = np.linalg.norm(normals - second, axis=1) < np.linalg.norm(normals - first, axis=1)
    for _ in range(15):
        if min(side.sum(), n - side.sum()) < 7:
            return None
        planes = []
        for group in (~side, side):
            centre = points[group].mean(axis=0)
            planes.append((centre, np.linalg.svd(points[group] - centre,
                                                 full_matrices=False)[2][2]))
        distance = np.column_stack([np.abs((points - c) @ m) for c, m in planes])
        nearer = distance[:, 1] < distance[:, 0]
        if np.array_equal(nearer, side):
            break
        side = nearer
    between = float(np.degrees(np.arccos(min(1.0, abs(planes[0][1] @ planes[1][1])))))
    if min(side.mean(), 1.0 - side.mean()) < share or between < angle:
        return None
    on_line, _, away = meeting_line(*planes[0], *planes[1])
    tests = []
    for group in (~side, side):
        local = np.full(n, -1)
        local[group] = np.arange(int(group.sum()))
        group_edges = None
        if edges is not None:
            edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
            group_edges = local[edges[rows_all(group[edges])]]
        tests.append(plane_test(points[group], group_edges, alpha=alpha))
    # across the line by more than three of its plane's noise (or rounding)
    extent = float(np.ptp(points, axis=0).max())
    across = sum(int(((points[group] - on_line) @ out
                      < -max(3.0 * test.noise, 1e-9 * extent)).sum())
                 for group, out, test in zip((~side, side), away, tests, strict=True))
    if across > TWO_PLANES_ACROSS * n:
        return None
    return TwoPlanes(tests[0], tests[1], side, between)


def meeting_line(first_centre: np.ndarray, first_normal: np.ndarray,
                 second_centre: np.ndarray, second_normal: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """Where two planes meet, each given by a point and its unit normal: a point of the line
    (the one nearest the points' midpoint along it), its unit direction, and for each plane
    the unit direction within it away from the line towards its given point (the plane's
    side of the edge).

    Raises
    ------
    ValueError
        For parallel planes.

    Examples
    --------
    >>> point, direction, (a, b) = meeting_line(np.array([1.0, 0, 1]), np.array([0, 0, 1.0]),
    ...                                         np.array([0.0, 1, 0]), np.array([1.0, 0, 0]))
    >>> [(x + 0.0).tolist() for x in (point, np.abs(direction), a, b)]
    [[0.0, 0.5, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]]
    """
    ca, na = np.asarray(first_centre, float), np.asarray(first_normal, float)
    cb, nb = np.asarray(second_centre, float), np.asarray(second_normal, float)
    direction = np.cross(na, nb)
    if np.linalg.norm(direction) < 1e-9:
        raise ValueError("the two planes are parallel: they meet at no edge")
    direction /= np.linalg.norm(direction)
    point = np.linalg.solve(np.array([na, nb, direction]),
                            [na @ ca, nb @ cb, direction @ (ca + cb) / 2.0])
    away = []
    for c, m in ((ca, na), (cb, nb)):
        out = np.cross(m, direction)
        away.append(out * (np.sign((c - point) @ out) or 1.0))
    return point, direction, (away[0], away[1])
