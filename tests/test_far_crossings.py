"""Fills that reach through surface far from their hole along the mesh but near in space
(:mod:`surfinpaint.fill.far_crossings`): counted and warned after the fill, fills unchanged."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra

from surfinpaint.data import default_demo_mesh, fsaverage5, sphere
from surfinpaint.errors import HoleWarning
from surfinpaint.fill.far_crossings import far_crossing_counts
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.degenerate import triangle_incidence


def _pial_disk_hole():
    """fsaverage5's left pial surface with the faces within 7 mean edge lengths (along the
    edges, by their corners' mean distance) of the vertex nearest (-60, -20, 20) removed:
    the λ-H fill of that hole reaches through a fold at 10 triangles (session 37)."""
    v, f = fsaverage5("pial", "left")
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    length = np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1)
    graph = sp.coo_matrix((length, (e[:, 0], e[:, 1])), shape=(len(v), len(v))).tocsr()
    centre = int(np.argmin(np.linalg.norm(v - [-60.0, -20.0, 20.0], axis=1)))
    d = dijkstra(graph, directed=False, indices=centre)[f].mean(axis=1)
    return v, f[d >= 7 * length.mean()]


def test_a_fill_through_a_fold_is_counted_and_warned():
    v, f = _pial_disk_hole()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(v, f, jobs=1)
    (report,) = result.reports
    assert report.outcome == "lambda-h"
    # 10 of its triangles cross the surface, all beyond the rings checked as it was made
    assert report.crossings == 10
    texts = [str(w.message) for w in caught if issubclass(w.category, HoleWarning)]
    assert [t for t in texts if "farther out than the rings" in t] == [
        "hole 0: 10 triangles of the fill cross the surface farther out than the rings "
        "around the hole checked as it was filled (a fold or a thin part, near in space): "
        "check the result"]


def test_crossing_counts_of_clean_fills_and_of_a_fill_pushed_through():
    # the demo's two λ-H fills cross nothing
    v, f = default_demo_mesh()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = fill_holes(v, f, jobs=1)
    incidence = triangle_incidence(f, len(v))
    loops = [r.loop for r in result.reports]
    assert far_crossing_counts(result.vertices, f, incidence, result.hole_faces(),
                               loops) == [0, 0]
    assert [r.crossings for r in result.reports] == [0, 0]
    # a sphere's hole filled, then its new vertices pushed through the far side: every
    # new face that reaches the other side crosses it; touching the loop does not count
    v, f = sphere(3)
    cut = cut_holes(v, f, [int(np.argmax(v[:, 2]))], 0.4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = fill_holes(cut.vertices, cut.faces, method="fair", jobs=1)
    incidence = triangle_incidence(cut.faces, len(cut.vertices))
    loops = [r.loop for r in result.reports]
    assert far_crossing_counts(result.vertices, cut.faces, incidence, result.hole_faces(),
                               loops) == [0]
    pushed = result.vertices.copy()
    new = np.arange(result.n_original_vertices, len(pushed))
    # below the sphere: the faces from the loop down cross its far side, where the rings
    # around the loop do not reach
    pushed[new, 2] = -2.0
    (count,) = far_crossing_counts(pushed, cut.faces, incidence, result.hole_faces(), loops)
    on_loop = np.isin(result.hole_faces()[0], np.arange(result.n_original_vertices)).any(1)
    assert np.count_nonzero(on_loop) <= count <= len(result.hole_faces()[0])
    assert far_crossing_counts(pushed, cut.faces, incidence, [np.empty((0, 3), int)],
                               loops) == [0]


@pytest.mark.parametrize("method", ["fair", "conformal"])
def test_no_warning_where_no_fill_crosses(method):
    v, f = sphere(3)
    cut = cut_holes(v, f, [0, 40], [0.3, 0.3])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(cut.vertices, cut.faces, method=method, jobs=1)
    assert [r.crossings for r in result.reports] == [0, 0]
    assert not [w for w in caught if "farther out than the rings" in str(w.message)]
