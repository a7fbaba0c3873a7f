"""Truth-free tests of hole fillers (method.md §8, "an honest safety net").

A filler that is to be trusted on a hole should do well on holes like it whose truth is
known: the rings of known surface around the hole, hidden and predicted again
(:func:`hidden_ring_scores`), and sibling holes as wide as it cut out of the known surface
nearby (:func:`sibling_scores`). Each test takes ``fill(vertices, faces, loop)`` returning
several candidate fills by name and scores every candidate, so one test run compares them
all. :func:`surfinpaint.fill.conformal.conformal_fill` uses them to choose between its λ-H fill and
the faired fills (:func:`surfinpaint.fill.conformal.choose`).
"""

from __future__ import annotations

from collections.abc import Callable
from itertools import islice

import numpy as np

from surfinpaint.errors import NUMERICAL_ERRORS, MeshError
from surfinpaint.fill.holes import loop_diameter
from surfinpaint.geometry.cutting import cut_geodesic_disk, edge_graph, ring_distances, submesh
from surfinpaint.geometry.mesh import boundary_loops
from surfinpaint.geometry.metrics import (
    hole_patch_of,
    point_mesh_distances,
    sample_surface,
    surface_distance_samples,
)
from surfinpaint.geometry.rows import row_norms, rows_any

__all__ = ["advantages_over", "hidden_band", "hidden_ring_scores", "hidden_ring_test",
           "mean_scores", "paired_advantage", "sibling_reach", "sibling_scores"]


def _spread_centres(vertices, faces, loop, gap_rings, graph=None):
    """Vertices ``gap_rings`` edge rings away from the hole, spread around it: each next one
    the farthest from all before it, until every vertex of the ring has been given."""
    rings = ring_distances(faces, len(vertices), loop, gap_rings + 0.5, graph=graph)
    candidates = np.flatnonzero(rings == gap_rings)
    if len(candidates) == 0:
        return
    points = vertices[candidates]
    # the first is the ring's lowest vertex id, as before the fallbacks (session 24): the
    # sibling holes of a hole that was scored then are the same holes now
    first = 0
    nearest = np.linalg.norm(points - points[first], axis=1)
    yield int(candidates[first])
    for _ in range(len(candidates) - 1):
        k = int(np.argmax(nearest))
        if nearest[k] == 0.0:
            return
        yield int(candidates[k])
        nearest = np.minimum(nearest, np.linalg.norm(points - points[k], axis=1))


def _sibling_centres(vertices, faces, loop, gap_rings, count, graph=None):
    """The first ``count`` of :func:`_spread_centres` (fewer when the ring has fewer)."""
    return list(islice(_spread_centres(vertices, faces, loop, gap_rings, graph=graph),
                       count))


def sibling_reach(vertices: np.ndarray, loop: np.ndarray, gap_rings: int) -> tuple[float, int]:
    """The sibling holes' geodesic radius (half the hole's diameter) and the edge ring of
    the hole their centres are placed on (``gap_rings`` beyond the hole's radius in edge
    lengths of its loop)."""
    points = vertices[loop]
    radius = 0.5 * loop_diameter(points)
    edge = float(np.linalg.norm(points - np.roll(points, -1, axis=0), axis=1).mean())
    return radius, gap_rings + int(np.ceil(radius / max(edge, 1e-300)))


def sibling_scores(
    vertices: np.ndarray,
    faces: np.ndarray,
    loop: np.ndarray,
    fill,
    *,
    siblings: int = 2,
    gap_rings: int = 3,
    n_samples: int = 2000,
    patch_rings: int | None = None,
    each: bool = False,
    graph=None,
    tries: int | None = None,
    detail: list | None = None,
) -> dict[str, float] | list[dict[str, float]]:
    """How well each filler does on holes like this one cut from the known surface nearby.

    Geodesic disks as wide as the hole are cut ``gap_rings`` rings beyond it (``siblings``
    of them, spread around), filled by ``fill`` (function(vertices, faces, loop) → dict
    name → :class:`~surfinpaint.fill.results.Fill`, or the exception of a failed
    candidate), and
    each candidate is scored by the two-sided mean distance between its fill and the removed
    surface (infinite when it failed there). No ground truth of the hole itself is used.

    With ``patch_rings`` (the most rings of surface ``fill`` looks at around a hole), each
    sibling is cut and filled on the part of the mesh around it that can matter, when that
    provably gives the same cut (else on the whole mesh): the same scores, less work.

    ``graph``: the mesh's :func:`~surfinpaint.geometry.cutting.edge_graph`, when already
    made (the hidden-ring test of the same hole uses it too).

    ``tries``: the most centres tried on the ring (spread around it, each the farthest from
    those before) until ``siblings`` holes could be cut and filled; a centre whose hole
    cannot be cut (near a border) or filled gives no score and the next one is tried. Where
    the first ``siblings`` centres all give a score, no other is tried. None (default): the
    first ``siblings`` centres only. Measured on the tuning side (docs/selfcheck.md, session
    24), ``tries=8`` finds more siblings near borders but the fills chosen with them are not
    better, so it is not the default.

    ``detail``: a list, to which each scored sibling's per-sample record is appended
    (``{"distances": name -> (n_samples,) array, "groups": (n_samples,) int array}``: sample
    ``i``'s distance is the mean of the ``i``-th distances of both sides, so a candidate's
    score on the sibling is its mean; ``groups`` is the truth face of the ``i``-th truth
    sample; for :func:`paired_advantage`). None (default): nothing is recorded.

    Returns
    -------
    dict or list of dict
        Mean score per filler over the siblings that could be cut (empty if none could);
        with ``each``, the scores of every sibling that could be cut, in the order they were
        placed (:func:`mean_scores` of them is the mean).
    """

    radius, gap = sibling_reach(vertices, loop, gap_rings)
    if graph is None:
        graph = edge_graph(faces, len(vertices))

    found = []
    centres = _spread_centres(vertices, faces, loop, gap, graph=graph)
    # a centre whose hole cannot be cut (it reaches the border, or is not a disk) gives no
    # evidence: with ``tries``, the next centre of the ring, farthest from those tried, is
    # tried instead (the first ``siblings`` are the centres tried without)
    for centre in islice(centres, max(tries or 0, siblings)):
        if len(found) == siblings:
            break
        record = {} if detail is not None else None
        results = _sibling_score(vertices, faces, centre, radius, fill, n_samples=n_samples,
                                 patch_rings=patch_rings, graph=graph, record=record)
        if results:
            found.append(results)
            if record is not None:
                detail.append(record)
    return found if each else mean_scores(found)


def _local_cut(vertices, faces, centre, radius, patch_rings, graph):
    """The sibling hole at ``centre`` cut from the faces within ``reach`` rings of it, or
    None when that could differ from the cut of the whole mesh. Dijkstra distances are at
    least Euclidean, so the disk lies among the vertices within ``radius`` of the centre
    (ring <= r0) and, with the rim beyond r0, its distances are those of the whole mesh;
    the cleanup and the fill's patch must stay ``patch_rings + 2`` rings inside."""
    ring = ring_distances(faces, len(vertices), centre, graph=graph)
    close = (row_norms(vertices - vertices[centre]) <= radius)
    close &= np.isfinite(ring)
    r0 = float(ring[close].max())
    reach = r0 + patch_rings + 4
    keep = ring <= reach
    if keep[faces].all():
        return None
    sv, sf, ids = submesh(vertices, faces, keep)
    try:
        cut = cut_geodesic_disk(sv, sf, int(np.searchsorted(ids, centre)), radius)
    except (ValueError, MeshError):
        return None
    if ring[ids[cut.holes[0].truth_ids]].max() > reach - patch_rings - 2:
        return None
    return cut


def _sibling_score(vertices, faces, centre, radius, fill, *, n_samples, patch_rings, graph,
                   record=None) -> dict[str, float] | None:
    """The candidates' scores on the sibling hole at ``centre`` (:func:`sibling_scores`),
    or None when it cannot be cut or filled."""
    try:
        cut = (_local_cut(vertices, faces, centre, radius, patch_rings, graph)
               if patch_rings is not None else None)
        if cut is None:
            cut = cut_geodesic_disk(vertices, faces, centre, radius)
        candidates = fill(cut.vertices, cut.faces, cut.loop)
    except NUMERICAL_ERRORS:
        return None
    # a candidate that failed on a hole like this one scores infinity
    results = {name: np.inf for name, c in candidates.items() if isinstance(c, Exception)}
    made = {name: c for name, c in candidates.items() if not isinstance(c, Exception)}
    # the fill's faces alone: the cut's own faces are never part of the patch, and
    # leaving them out of the test spares sorting them once per candidate
    patches = [hole_patch_of(np.concatenate([cut.vertices, new_v]), new_f,
                             len(cut.vertices), cut.faces) for new_v, new_f in
               ((c.vertices, c.faces) for c in made.values())]
    both = surface_distance_samples(patches, cut.truth_vertices, cut.truth_faces,
                                    n_samples=n_samples)
    results.update(zip(made, (float(0.5 * (ab.mean() + ba.mean())) for ab, ba in both),
                       strict=True))
    if record is not None:
        record["distances"] = {name: 0.5 * (ab + ba) for name, (ab, ba) in
                               zip(made, both, strict=True)}
        record["groups"] = sample_surface(cut.truth_vertices, cut.truth_faces, n_samples,
                                          return_faces=True)[1]
    return results


def mean_scores(each: list[dict[str, float]]) -> dict[str, float]:
    """The mean score per filler over test holes (each filler over the holes it was scored
    on), as :func:`sibling_scores` reports it."""
    scores: dict[str, list[float]] = {}
    for results in each:
        for name, value in results.items():
            scores.setdefault(name, []).append(value)
    return {name: float(np.mean(v)) for name, v in scores.items() if v}


def hidden_band(faces: np.ndarray, ring: np.ndarray, hide_rings: int):
    """The faces hidden by the hidden-ring test and the loops they leave.

    Parameters
    ----------
    faces : (f, 3) int array
    ring : (n,) float array
        Each vertex's edge-ring distance from the hole's loop (at least up to
        ``hide_rings``; :func:`~surfinpaint.geometry.cutting.ring_distances`).
    hide_rings : int

    Returns
    -------
    hidden : (f,) bool array
        The faces with a vertex within ``hide_rings - 1`` rings of the loop.
    kept : (k, 3) int array
        The other faces.
    border : (n,) bool array
        The vertices ``hide_rings`` rings out: the enlarged hole's loop runs through them.
    loops : list of int arrays or None
        The boundary loops of ``kept`` (None when they do not close).
    """
    near = ring <= hide_rings - 1
    hidden = rows_any(near[faces])
    kept = faces[~hidden]
    border = (ring <= hide_rings) & ~near
    try:
        loops = boundary_loops(kept)
    except MeshError:
        loops = None
    return hidden, kept, border, loops


def hidden_ring_scores(
    vertices: np.ndarray,
    faces: np.ndarray,
    loop: np.ndarray,
    fill,
    *,
    hide_rings: int = 2,
    n_samples: int = 2000,
    patch_rings: int | None = None,
    graph=None,
    min_hide_rings: int | None = None,
    detail: dict | None = None,
) -> dict[str, float]:
    """How well each filler predicts known surface hidden around the hole.

    The faces within ``hide_rings`` rings of the loop are removed, the larger hole is filled
    by ``fill`` (as in :func:`sibling_scores`), and each candidate is scored by the mean
    distance from the hidden faces (area-sampled) to its fill (infinite when it failed).

    With ``patch_rings`` (the most rings of surface ``fill`` looks at around a hole), the
    test runs on the faces within ``hide_rings + patch_rings + 3`` rings of the loop when
    that provably gives the same enlarged hole (else on the whole mesh): the same scores,
    less work.

    ``graph``: the mesh's :func:`~surfinpaint.geometry.cutting.edge_graph`, when already
    made (made here otherwise).

    ``min_hide_rings``: where the ``hide_rings`` rings do not leave one simple hole (on a
    thin part the hidden band can wrap around it; near a border it can reach the border)
    or ``fill`` raises there, one ring fewer is hidden, down to ``min_hide_rings``: the
    test's hole is then shallower, but it scores where the deeper one gives nothing. Where
    ``hide_rings`` rings score, nothing else is tried. None (default): ``hide_rings`` only.
    Measured on the tuning side (docs/selfcheck.md, session 24), ``min_hide_rings=1``
    scores on thin limbs and near borders but the fills chosen with it are not better, so
    it is not the default.

    ``detail``: a dict, filled (when the test scores) with ``"distances"`` (name ->
    (n_samples,) array, each sample's distance; a candidate's score is their mean) and
    ``"groups"`` (the hidden face each sample lies on), for :func:`paired_advantage`.
    None (default): nothing is recorded.

    Returns
    -------
    dict
        Score per filler (empty when no depth tried leaves one simple hole that ``fill``
        fills).
    """
    return hidden_ring_test(vertices, faces, loop, fill, hide_rings=hide_rings,
                            n_samples=n_samples, patch_rings=patch_rings, graph=graph,
                            min_hide_rings=min_hide_rings, detail=detail)()


def hidden_ring_test(
    vertices: np.ndarray,
    faces: np.ndarray,
    loop: np.ndarray,
    fill,
    *,
    hide_rings: int = 2,
    n_samples: int = 2000,
    patch_rings: int | None = None,
    graph=None,
    min_hide_rings: int | None = None,
    detail: dict | None = None,
) -> Callable[[], dict[str, float]]:
    """:func:`hidden_ring_scores` in two steps: the test hole is cut and filled now, and its
    fills are scored (and ``detail`` filled) when the function returned is called; the
    arguments and the scores are those of :func:`hidden_ring_scores`.

    Why: the self-check runs the test again one ring shallower where the test's λ-H fill
    was a crease fill (:func:`~surfinpaint.fill.conformal.selection.hidden_rings_shallower`),
    which only the fills say, and the deeper test's scores are then used only where the
    shallower test cannot score: their distances are not searched where it can (session 37
    helper).
    """

    def run(vertices, faces, loop, ring, rim, depth):
        """The test with ``depth`` rings hidden; None when a loop next to the hidden faces
        reaches the ``rim`` vertices (then it is not the loop of the whole mesh)."""
        hidden, kept, border, loops = hidden_band(faces, ring, depth)
        if loops is None:
            return None if rim is not None else {}
        if rim is not None and any(border[l].any() and rim[l].any() for l in loops):
            return None
        enlarged = [l for l in loops if border[l].mean() > 0.5]
        if len(enlarged) != 1:
            return {}
        try:
            candidates = fill(vertices, kept, enlarged[0])
        except NUMERICAL_ERRORS:
            return {}

        def scores():
            samples, sampled = sample_surface(vertices, faces[hidden], n_samples, seed=0,
                                              return_faces=True)
            made = {name: c for name, c in candidates.items() if not isinstance(c, Exception)}
            found = dict(zip(made, point_mesh_distances(samples, [
                (np.concatenate([vertices, c.vertices]), c.faces) for c in made.values()]),
                strict=True))
            if detail is not None:
                detail["distances"] = found
                detail["groups"] = sampled
            return {name: float(found[name].mean()) if name in found else
                    np.inf  # failed on a hole like this one
                    for name in candidates}
        return scores if candidates else {}  # (a test with no candidate does not score)

    def at_depth(depth):
        if patch_rings is not None:
            reach = depth + patch_rings + 3
            ring = ring_distances(faces, len(vertices), loop, reach + 1, graph=graph)
            keep = ring <= reach
            if not keep[faces].all():
                sv, sf, ids = submesh(vertices, faces, keep)
                scores = run(sv, sf, np.searchsorted(ids, loop), ring[ids],
                             ring[ids] >= reach, depth)
                if scores is not None:
                    return scores
        ring = ring_distances(faces, len(vertices), loop, depth + 0.5, graph=graph)
        return run(vertices, faces, loop, ring, None, depth)

    if graph is None:  # one adjacency for all searches below
        graph = edge_graph(faces, len(vertices))
    # fewer rings hidden where ``hide_rings`` leave no one simple hole (the hidden band
    # wraps around a thin part, or reaches a border) or a fill fails on it: a shallower test
    # hole still gives evidence, where the deeper one gives none
    shallowest = hide_rings if min_hide_rings is None else max(min_hide_rings, 1)
    for depth in range(hide_rings, shallowest - 1, -1):
        scores = at_depth(depth)
        if scores:
            return scores
    return dict


def paired_advantage(reference: np.ndarray, candidate: np.ndarray, groups: np.ndarray
                     ) -> tuple[float, float]:
    """How much closer a candidate is than the reference on one test's samples, and the
    standard error of that advantage.

    The samples are paired (the same points, or the same truth points, measured to both
    fills), so the advantage is the mean of the per-sample differences ``reference -
    candidate``. Samples on one face share its (noisy) vertices: the standard error is
    the cluster-robust one with the faces (``groups``) as clusters, not the naive
    ``std / sqrt(n)`` of thousands of dependent samples.

    Parameters
    ----------
    reference, candidate : (n,) float arrays
        Per-sample distances (``detail`` of :func:`hidden_ring_scores` or
        :func:`sibling_scores`).
    groups : (n,) int array
        The cluster (face) of each sample.

    Returns
    -------
    advantage : float
        ``mean(reference) - mean(candidate)`` (positive: the candidate is closer).
    standard_error : float
        Of ``advantage`` (infinite with fewer than two clusters).
    """
    d = np.asarray(reference, float) - np.asarray(candidate, float)
    n = len(d)
    mean = float(d.mean())
    _, g = np.unique(np.asarray(groups), return_inverse=True)
    count = np.bincount(g)
    k = len(count)
    if k < 2:
        return mean, np.inf
    residual = np.bincount(g, weights=d) - count * mean  # each cluster's sum of residuals
    return mean, float(np.sqrt(k / (k - 1) * np.sum(residual ** 2)) / n)


def advantages_over(hidden_detail: dict, sibling_detail: list, reference: str = "fair2"
                    ) -> dict[str, dict[str, tuple[float, float]]]:
    """Each candidate's :func:`paired_advantage` over ``reference`` in the tests whose
    ``detail`` was recorded: ``{"hidden": {name: (advantage, se)}, "sibling": {...}}``
    (over several siblings, the mean of the advantages with the standard errors added in
    quadrature and divided by their number; a test without a record: no entry)."""
    out: dict[str, dict[str, tuple[float, float]]] = {}
    if hidden_detail and reference in hidden_detail["distances"]:
        d, g = hidden_detail["distances"], hidden_detail["groups"]
        out["hidden"] = {name: paired_advantage(d[reference], d[name], g)
                         for name in d if name != reference}
    per: dict[str, list[tuple[float, float]]] = {}
    for rec in sibling_detail or ():
        d, g = rec["distances"], rec["groups"]
        if reference in d:
            for name in d:
                if name != reference:
                    per.setdefault(name, []).append(paired_advantage(d[reference], d[name], g))
    if per:
        out["sibling"] = {name: (float(np.mean([a for a, _ in v])),
                                 float(np.sqrt(sum(s * s for _, s in v)) / len(v)))
                          for name, v in per.items()}
    return out
