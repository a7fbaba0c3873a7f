"""Fills that reach through surface far from their hole along the mesh but near in space
(:mod:`surfinpaint.fill.far_crossings`): counted and warned after the fill, fills unchanged;
and, since session 39, two holes' fills that cross each other."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra

from surfinpaint.data import default_demo_mesh, fsaverage5, sphere
from surfinpaint.errors import HoleWarning
from surfinpaint.fill import pipeline
from surfinpaint.fill.far_crossings import crossing_fill_pairs, far_crossing_triangles
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.degenerate import triangle_incidence
from surfinpaint.io import MeshWarning


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
    assert [len(t) for t in far_crossing_triangles(result.vertices, f, incidence,
                                                   result.hole_faces(), loops)] == [0, 0]
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
    assert [len(t) for t in far_crossing_triangles(result.vertices, cut.faces, incidence,
                                                   result.hole_faces(), loops)] == [0]
    pushed = result.vertices.copy()
    new = np.arange(result.n_original_vertices, len(pushed))
    # below the sphere: the faces from the loop down cross its far side, where the rings
    # around the loop do not reach
    pushed[new, 2] = -2.0
    (crossing,) = far_crossing_triangles(pushed, cut.faces, incidence, result.hole_faces(),
                                         loops)
    on_loop = np.isin(result.hole_faces()[0], np.arange(result.n_original_vertices)).any(1)
    assert np.count_nonzero(on_loop) <= len(crossing) <= len(result.hole_faces()[0])
    assert np.all(np.diff(crossing) > 0) and crossing.max() < len(result.hole_faces()[0])
    assert [len(t) for t in far_crossing_triangles(pushed, cut.faces, incidence,
                                                   [np.empty((0, 3), int)], loops)] == [0]


@pytest.mark.parametrize("method", ["fair", "conformal"])
def test_no_warning_where_no_fill_crosses(method):
    v, f = sphere(3)
    cut = cut_holes(v, f, [0, 40], [0.3, 0.3])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(cut.vertices, cut.faces, method=method, jobs=1)
    assert [r.crossings for r in result.reports] == [0, 0]
    assert not [w for w in caught if "farther out than the rings" in str(w.message)]


# ------------------------------------------------ two fills that cross each other (session 39)


def _two_spheres(gap: float, cap: float = 30.0):
    """Two unit spheres, their centres ``gap`` apart along z, each with a hole of ``cap``
    degrees around the pole that faces the other. At ``gap`` 1.9 the spheres would cross
    at 18 degrees from those poles, inside both holes: what is left of them does not cross,
    but the fills, each continuing its sphere over its hole, cross each other (and nothing
    else); at 2.3 the spheres are apart."""
    v, f = sphere(3)
    centre = v[f].mean(axis=1)
    height = centre[:, 2] / np.linalg.norm(centre, axis=1)
    top, bottom = f[height < np.cos(np.radians(cap))], f[height > -np.cos(np.radians(cap))]
    return np.vstack([v, v + [0.0, 0.0, gap]]), np.vstack([top, bottom + len(v)])


@pytest.mark.parametrize("method", ["fair", "conformal"])
def test_two_fills_that_cross_each_other_are_warned_naming_both_holes(method, monkeypatch):
    v, f = _two_spheres(1.9)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(v, f, method=method, jobs=1)
    said = [w for w in caught if str(w.message).startswith("holes 0 and 1:")]
    assert len(said) == 1 and said[0].category is MeshWarning  # not said by hole lines
    first, second = result.reports
    assert first.crossings > 0 and second.crossings > 0  # nothing else crosses: all theirs
    assert str(said[0].message) == (
        f"holes 0 and 1: {first.crossings} triangles of hole 0's fill cross "
        f"{second.crossings} of hole 1's (two holes near in space, each filled without the "
        "other's fill): check the result")
    assert not [w for w in caught if "farther out than the rings" in str(w.message)]
    # the check only looks: without it, the same fills, bit for bit
    monkeypatch.setattr(pipeline, "crossing_fill_pairs", lambda vertices, hole_faces: [])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        unchecked = fill_holes(v, f, method=method, jobs=1)
    assert unchecked.vertices.tobytes() == result.vertices.tobytes()
    assert unchecked.faces.tobytes() == result.faces.tobytes()
    assert [r.crossings for r in unchecked.reports] == [0, 0]


@pytest.mark.parametrize("method", ["fair", "conformal"])
def test_two_fills_near_but_apart_are_not_warned(method):
    v, f = _two_spheres(2.3)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(v, f, method=method, jobs=1)
    assert [r.outcome for r in result.reports] == (
        ["faired"] * 2 if method == "fair" else ["lambda-h"] * 2)
    assert [r.crossings for r in result.reports] == [0, 0]
    assert not [w for w in caught if str(w.message).startswith("holes ")]


def _triangle(corner, normal_axis: int = 2, size: float = 1.0) -> np.ndarray:
    """A right triangle at ``corner`` in the plane across ``normal_axis``."""
    a, b = [k for k in range(3) if k != normal_axis]
    t = np.zeros((3, 3))
    t[1, a], t[2, b] = size, size
    return t + np.asarray(corner, float)


# fills as lists of triangles (corner positions), and the crossing pairs expected
PAIR_CASES = {
    "none": ([], []),
    "one fill": ([[_triangle((0, 0, 0))]], []),
    "far apart": ([[_triangle((0, 0, 0))], [_triangle((5, 5, 5))]], []),
    # the boxes overlap, the triangles do not meet
    "boxes only": ([[_triangle((0, 0, 0))], [_triangle((0.8, 0.8, -0.5), 0)]], []),
    "crossing": ([[_triangle((0, 0, 0))], [_triangle((0.2, -0.5, -0.5), 0, 2)]],
                 [(0, 1, 1, 1)]),
    # the second and third fills' boxes start inside the first's, the third's x range
    # after the second's: the sweep must pair the first with both
    "first with two": ([[_triangle((-1, -1, 0), size=4)], [_triangle((0.5, 0, -0.5), 0)],
                        [_triangle((2, 0, -0.5), 0)], [_triangle((9, 9, 9))]],
                       [(0, 1, 1, 1), (0, 2, 1, 1)]),
    # two triangles of one fill cross the other's one
    "counted per fill": ([[_triangle((0, 0, 0)), _triangle((0, 0, 0.2))],
                          [_triangle((0.2, -0.5, -0.5), 0, 2)]], [(0, 1, 2, 1)]),
}


def _pairs(found):
    """The pairs of fills found, each with how many triangles of each cross the other's."""
    return [(p.first, p.second, len(p.first_triangles), len(p.second_triangles)) for p in found]


@pytest.mark.parametrize("case", sorted(PAIR_CASES))
def test_crossing_fill_pairs(case):
    fills, expected = PAIR_CASES[case]
    positions, faces, n = [], [], 0
    for fill in fills:
        faces.append(np.arange(n, n + 3 * len(fill)).reshape(-1, 3))
        positions += fill
        n += 3 * len(fill)
    vertices = np.vstack(positions) if positions else np.zeros((0, 3))
    assert _pairs(crossing_fill_pairs(vertices, faces)) == expected
    # an empty fill (a zipped seam) in front changes nothing but the positions
    shifted = [(a + 1, b + 1, na, nb) for a, b, na, nb in expected]
    assert _pairs(crossing_fill_pairs(vertices, [np.empty((0, 3), int), *faces])) == shifted


def test_fills_that_share_a_loop_vertex_touch_there_without_crossing():
    # two fans around one vertex, on either side of it in one plane: they share a corner
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]])
    assert crossing_fill_pairs(v, [np.array([[0, 1, 2]]), np.array([[0, 3, 4]])]) == []
    # the same second fill turned into the first's plane: it overlaps beyond the corner
    v[3] = [0.5, 0.5, 0.0]
    v[4] = [0.5, -0.2, 0.0]
    assert _pairs(crossing_fill_pairs(
        v, [np.array([[0, 1, 2]]), np.array([[0, 3, 4]])])) == [(0, 1, 1, 1)]
