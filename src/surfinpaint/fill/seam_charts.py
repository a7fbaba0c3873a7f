"""Corner values of a hole whose loop a seam reaches: the seam continued across the hole.

A per-corner attribute (texture coordinates) is continuous along the loop except where a seam
(an edge whose two faces give its ends different values) meets it. Those loop vertices cut
the loop into *arcs*, runs of loop edges along which the values are continuous; each arc lies
in one chart of the texture atlas. Continuing one chart across the whole hole (extrapolating
it to the other arcs' vertices, session 36) draws texels from outside that chart near the
other arcs and can mirror faces there; instead the hole's new faces are split among the arcs
and each part takes the values of its own arc's chart, so the seam runs on into the hole
between the parts, its vertices with one value per part (as per-corner values allow).

Each new face goes to the arc whose faces' harmonic indicator on the fill's dual graph is
largest (:func:`labels_across_loop`: the random-walker rule of the per-face attributes, so
each part is connected to its arc). A part's values are its arc's chart continued
biharmonically over the patch (:func:`~surfinpaint.fill.attributes.inpaint_values`, the
per-vertex rule, from the vertices with one value on the chart's faces and the arc's own),
so each part extrapolates its chart only as far as its own share of the hole. Where that
mirrors new faces against the arc's faces, the part's inside is placed again by Floater's
mean-value map with its border fixed (:func:`~surfinpaint.geometry.mean_value.
convex_combination`: no fold inside a convex border), kept where it mirrors fewer.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from surfinpaint.fill.attributes import (
    DirichletSolve,
    channel_ranges,
    inpaint_operators,
    labels_by_indicators,
)
from surfinpaint.geometry.mean_value import convex_combination, mean_value_weights
from surfinpaint.geometry.mesh import edge_faces
from surfinpaint.geometry.parameterization import signed_areas

__all__ = ["LoopArcs", "chart_labels", "labels_across_loop", "loop_arcs", "single_values",
           "split_at_seams"]


def labels_across_loop(vertices: np.ndarray, known_faces: np.ndarray, fill_faces: np.ndarray,
                       known_labels: list[np.ndarray]) -> list[np.ndarray]:
    """Labels of a fill's faces copied from the faces across its loop: for each array of
    ``known_labels`` (one row per ``known_faces`` face), each new face takes the label whose
    harmonic indicator is largest on the dual graph of ``known_faces`` and ``fill_faces``
    (joined across shared edges with weight edge length over centroid distance; only edges
    of the fill), so each label's new faces are connected to the known faces that carry it.

    Parameters
    ----------
    vertices : (n, 3) float array
    known_faces : (t, 3) int array
        Original faces touching the loop.
    fill_faces : (m, 3) int array
    known_labels : list of (t,) or (t, c) arrays

    Returns
    -------
    list of (m,) or (m, c) arrays, one per ``known_labels`` array.
    """
    local = np.concatenate([known_faces, fill_faces])
    edges, owners, count = edge_faces(local)
    pair = (count == 2) & (owners.max(axis=1) >= len(known_faces))  # an edge of the fill
    left, right = owners[pair].T
    centroids = vertices[local].mean(axis=1)
    weight = (np.linalg.norm(vertices[edges[pair, 0]] - vertices[edges[pair, 1]], axis=1)
              / np.maximum(np.linalg.norm(centroids[left] - centroids[right], axis=1), 1e-300))
    W = sp.coo_matrix((np.concatenate([weight, weight]),
                       (np.concatenate([left, right]), np.concatenate([right, left]))),
                      shape=(len(local), len(local))).tocsr()
    graph = (sp.diags(np.asarray(W.sum(axis=1)).ravel()) - W).tocsr()
    known = np.arange(len(local)) < len(known_faces)
    return labels_by_indicators(DirichletSolve(graph, known), known_labels)


class LoopArcs:
    """The runs of a hole's loop edges along which a corner attribute is continuous.

    Attributes
    ----------
    face : (q,) int array
        The face along each loop edge ``(loop[i], loop[i + 1])``.
    arc : (q,) int array
        Each edge's arc, 0 ... ``count - 1``.
    start, end : (q, k) float arrays
        The values of ``loop[i]`` and ``loop[i + 1]`` on the face along edge ``i``.
    count : int
    """

    def __init__(self, face: np.ndarray, arc: np.ndarray, start: np.ndarray,
                 end: np.ndarray) -> None:
        self.face, self.arc, self.start, self.end = face, arc, start, end
        self.count = int(arc.max()) + 1

    def vertices(self, loop: np.ndarray, which: int) -> tuple[np.ndarray, np.ndarray]:
        """Arc ``which``'s loop vertices in loop order and their values on it."""
        edges = np.flatnonzero(self.arc == which)
        # an arc that wraps past the loop's end starts after the gap in its edge ids
        gap = np.flatnonzero(np.diff(edges) > 1)
        if len(gap):
            edges = np.roll(edges, -(gap[0] + 1))
        ids = np.append(loop[edges], loop[(edges[-1] + 1) % len(loop)])
        return ids, np.vstack([self.start[edges], self.end[edges[-1]]])


def loop_arcs(faces: np.ndarray, values: np.ndarray, loop: np.ndarray) -> LoopArcs | None:
    """The loop's arcs (:class:`LoopArcs`): its edges cut at each loop vertex whose value
    differs on the faces along the loop edges before and after it (a seam meets the loop
    there). None with fewer than two such vertices (nothing to split), where a loop edge has
    no face or a face along the loop has no value (NaN).

    Parameters
    ----------
    faces : (p, 3) int array
        The faces around the loop (every face with a loop edge among them).
    values : (p, 3, k) float array
        Their corner values.
    loop : (q,) int array
    """
    loop = np.asarray(loop, dtype=np.int64)
    ahead = np.roll(loop, -1)
    size = int(max(faces.max(), loop.max())) + 1
    keys = (np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2)
            @ [size, 1])  # corner c's edge to corner c + 1
    order = np.argsort(keys)

    def corner_of(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        key = a * size + b
        at = np.minimum(np.searchsorted(keys[order], key), len(keys) - 1)
        return np.where(keys[order][at] == key, order[at], -1)

    forward, backward = corner_of(loop, ahead), corner_of(ahead, loop)
    corner = np.where(forward >= 0, forward, backward)
    if (corner < 0).any():
        return None
    face, first = corner // 3, corner % 3
    second = (first + 1) % 3
    a, b = values[face, first], values[face, second]
    start = np.where((forward >= 0)[:, None], a, b)
    end = np.where((forward >= 0)[:, None], b, a)
    if np.isnan(start).any() or np.isnan(end).any():
        return None
    cut = (end != np.roll(start, -1, axis=0)).any(axis=1)  # after edge i, at loop[i + 1]
    if cut.sum() < 2:
        return None
    arc = (np.cumsum(np.roll(cut, 1)) - 1) % int(cut.sum())  # the last arc wraps round
    return LoopArcs(face, arc, start, end)


def chart_labels(faces: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Each face's chart: faces joined across edges whose two ends have the same values in
    both faces (a seam cuts the faces into charts); -1 for a face without values (NaN).

    Parameters
    ----------
    faces : (p, 3) int array
    values : (p, 3, k) float array
        Each face's corner values.
    """
    corner_edges = np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2)
    corner_values = np.concatenate([values, np.roll(values, -1, axis=1)],
                                   axis=2).reshape(len(corner_edges), -1)
    owner = np.repeat(np.arange(len(faces)), 3)
    key = np.sort(corner_edges, axis=1)
    order = np.lexsort(key.T[::-1])
    key, owner, corner_values = key[order], owner[order], corner_values[order]
    twin = np.flatnonzero((key[1:] == key[:-1]).all(axis=1))  # two faces on one edge
    k = values.shape[2]
    # the second face runs the edge the other way: its values at (b, a) are at (a, b)
    swapped = np.concatenate([corner_values[twin + 1, k:], corner_values[twin + 1, :k]], axis=1)
    joined = twin[(corner_values[twin] == swapped).all(axis=1)]
    graph = sp.coo_matrix((np.ones(len(joined)), (owner[joined], owner[joined + 1])),
                          shape=(len(faces), len(faces)))
    _, chart = connected_components(graph, directed=False)
    chart[np.isnan(values).any(axis=(1, 2))] = -1
    return chart


def single_values(n: int, faces: np.ndarray, values: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Which of ``n`` vertices have one value on all their corners among ``faces`` (not
    where a seam ends inside them), and that value (rows of the others: 0)."""
    k = values.shape[2]
    low = np.full((n, k), np.inf)
    high = np.full((n, k), -np.inf)
    np.minimum.at(low, faces.ravel(), values.reshape(-1, k))
    np.maximum.at(high, faces.ravel(), values.reshape(-1, k))
    single = np.all(low == high, axis=1)
    low[~single] = 0.0
    return single, low


def _mirrored(faces: np.ndarray, uv: np.ndarray, chart: float) -> np.ndarray:
    """Which of ``faces`` (in ``uv``) are oriented against ``chart`` (its sign)."""
    return signed_areas(faces, uv) * chart < 0


def _part_values(domain: np.ndarray, bilaplacian: sp.csr_matrix, known: np.ndarray,
                 data: np.ndarray, part: np.ndarray, chart: float) -> np.ndarray:
    """One arc's chart continued biharmonically over the patch (``bilaplacian``: the
    patch's, as :func:`~surfinpaint.fill.attributes.inpaint_values` uses) from ``data`` at
    ``known`` (vertex values, rows of the patch), clamped to the chart's range unless that
    mirrors more of its ``part``'s faces against ``chart`` (two channels: a clamp can
    flatten a face), and with the part's inside placed again by the mean-value map where
    that mirrors fewer."""
    filled = data.copy()
    filled[~known] = DirichletSolve(bilaplacian, known)(data[known])
    limits = channel_ranges(data[known])
    clamped = np.clip(filled, limits[0], limits[1])
    if filled.shape[1] != 2 or chart == 0:
        return clamped
    mirrored = int(_mirrored(part, clamped, chart).sum())
    if mirrored > _mirrored(part, filled, chart).sum():
        mirrored = int(_mirrored(part, filled, chart).sum())
    else:
        filled = clamped
    if mirrored == 0:
        return filled
    edges, _, count = edge_faces(part)
    placed = filled.copy()
    convex_combination(mean_value_weights(domain, part), placed,
                       np.setdiff1d(np.unique(part), edges[count == 1]))
    return placed if _mirrored(part, placed, chart).sum() < mirrored else filled


def _chart_sign(corners: np.ndarray) -> float:
    """The orientation of most of the UV triangles ``(f, 3, 2)`` (0: as many each way)."""
    flat = corners.reshape(-1, 2)
    return float(np.sign(np.sign(signed_areas(np.arange(len(flat)).reshape(-1, 3),
                                              flat)).sum()))


def split_at_seams(positions: np.ndarray, domain: np.ndarray, patch_faces: np.ndarray,
                   faces: np.ndarray, values: np.ndarray, loop: np.ndarray,
                   fill_faces: np.ndarray) -> tuple[np.ndarray, int] | None:
    """The new faces' corner values with the seams that meet the loop continued across the
    hole (the module docstring's rule), and how many new faces are mirrored against their
    arc's faces (two channels only; 0 otherwise). None where no two seam vertices cut the
    loop (:func:`loop_arcs`).

    A new face its part's chart mirrors goes to the part of a face beside it whose chart
    does not (a face between the three loop vertices of a concave run of the arc cannot be
    helped: its values are the arc's).

    Parameters
    ----------
    positions : (n, 3) float array
        The patch's vertices.
    domain : (n, 2) or (n, 3) float array
        The patch's domain (:class:`~surfinpaint.fill.attributes.HoleDomain`).
    patch_faces : (r, 3) int array
        The patch's faces (the domain's).
    faces : (p, 3) int array
        The original faces of the patch (patch ids).
    values : (p, 3, c) float array
        Their corner values.
    loop : (q,) int array
        The loop, in patch ids.
    fill_faces : (m, 3) int array
        The new faces, in patch ids.

    Returns
    -------
    values : (m, 3, c) float array
    mirrored : int
    """
    arcs = loop_arcs(faces, values, loop)
    if arcs is None:
        return None
    along, first = np.unique(arcs.face, return_index=True)
    part_of = labels_across_loop(positions, faces[along], fill_faces, [arcs.arc[first]])[0]
    chart = chart_labels(faces, values)
    _, bilaplacian = inpaint_operators(domain, patch_faces)
    uv = values.shape[2] == 2
    parts = np.unique(part_of)
    continued, signs = [], np.zeros(len(parts))
    for j, which in enumerate(parts):
        own = arcs.face[arcs.arc == which]
        in_chart = np.isin(chart, chart[own])
        known, data = single_values(len(domain), faces[in_chart], values[in_chart])
        ids, arc_values = arcs.vertices(loop, which)
        known[ids], data[ids] = True, arc_values
        signs[j] = _chart_sign(values[own]) if uv else 0.0
        continued.append(_part_values(domain, bilaplacian, known, data,
                                      fill_faces[part_of == which], signs[j]))
    label = np.searchsorted(parts, part_of)
    if uv and len(parts) > 1:
        # (parts, m): each new face mirrored in each part's chart
        against = np.stack([_mirrored(fill_faces, c, sign)
                            for c, sign in zip(continued, signs, strict=True)])
        edges, owners, count = edge_faces(fill_faces)
        pairs = owners[count == 2]
        beside = np.zeros((len(parts), len(fill_faces)), dtype=bool)
        beside[label[pairs[:, 0]], pairs[:, 1]] = True
        beside[label[pairs[:, 1]], pairs[:, 0]] = True
        better = beside & ~against
        moved = against[label, np.arange(len(fill_faces))] & better.any(axis=0)
        label[moved] = np.argmax(better[:, moved], axis=0)
    out = np.empty((len(fill_faces), 3, values.shape[2]))
    mirrored = 0
    for j, values_j in enumerate(continued):
        mine = label == j
        out[mine] = values_j[fill_faces[mine]]
        if uv:
            mirrored += int(_mirrored(fill_faces[mine], values_j, signs[j]).sum())
    return out, mirrored
