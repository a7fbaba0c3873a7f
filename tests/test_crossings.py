"""A written fill that crosses the surface around its hole is counted and warned about."""

import warnings

import numpy as np
import pytest

from surfinpaint import ConformalOptions, data, fill_holes
from surfinpaint.app.fill_report import HoleRecord, hole_lines
from surfinpaint.errors import HoleWarning
from surfinpaint.fill.parallel import crossing_triangles
from surfinpaint.fill.results import Fill
from surfinpaint.geometry.cutting import cut_geodesic_disk


def _square_with_hole():
    """A flat 4x4 grid of squares with the middle 2x2 block removed: a loop of 8 edges."""
    g = np.stack(np.meshgrid(np.arange(5.0), np.arange(5.0), indexing="ij"), -1).reshape(-1, 2)
    vertices = np.column_stack([g, np.zeros(len(g))])
    faces = []
    for i in range(4):
        for j in range(4):
            if 1 <= i <= 2 and 1 <= j <= 2:
                continue
            a, b, c, d = 5 * i + j, 5 * (i + 1) + j, 5 * (i + 1) + j + 1, 5 * i + j + 1
            faces += [[a, b, c], [a, c, d]]
    loop = np.array([6, 11, 16, 17, 18, 13, 8, 7])
    return vertices, np.array(faces), loop


def test_a_fan_fill_of_a_flat_hole_crosses_nothing():
    vertices, faces, loop = _square_with_hole()
    fan = np.array([[loop[k], loop[(k + 1) % 8], 25] for k in range(8)])
    fill = Fill(np.array([[2.0, 2.0, 0.0]]), fan, "fair")
    assert len(crossing_triangles(vertices, faces, loop, fill)) == 0


def test_a_fill_triangle_through_the_surface_is_counted():
    vertices, faces, loop = _square_with_hole()
    fan = np.array([[loop[k], loop[(k + 1) % 8], 25] for k in range(8)])
    # one more triangle from a loop vertex down through the known face at (0.5, 0.5)
    spike = np.array([[6, 26, 27]])
    new_v = np.array([[2.0, 2.0, 0.0], [0.3, 0.6, -1.0], [0.6, 0.3, 1.0]])
    fill = Fill(new_v, np.vstack([fan, spike]), "fair")
    assert crossing_triangles(vertices, faces, loop, fill).tolist() == [8]  # the spike


@pytest.mark.parametrize("method", ["fair", "conformal"])
def test_a_hole_over_a_cube_corner_warns_that_its_fill_crosses_the_surface(method):
    # the geodesic disk over the corner cuts a loop that folds over the corner: a smooth
    # fill of it crosses the faces along two of the edges (measured: 2 fill triangles, both
    # methods; the conformal one without its crease search, which rebuilds the corner)
    cut = cut_geodesic_disk(*data.cube(40), np.array([1.0, 0.85, 1.0]), 0.2845)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        smooth = ConformalOptions(creases=False) if method == "conformal" else None
        result = fill_holes(cut.vertices, cut.faces, method=method, jobs=1, options=smooth)
    (report,) = [r for r in result.reports if not r.skipped]
    assert report.crossings >= 1
    said = [str(w.message) for w in caught if issubclass(w.category, HoleWarning)]
    assert any("cross" in s and f"hole {report.index}" in s for s in said)
    assert f"{report.crossings} of them crossing the surface" in hole_lines(report)[0]
    assert HoleRecord.of(report).to_json()["crossings"] == report.crossings


def test_the_default_fill_rebuilds_that_corner_without_crossing():
    # the three edges that meet at the corner are continued to it and each face filled on
    # its own (session 29): the cube comes back, nothing crosses, nothing is warned
    cut = cut_geodesic_disk(*data.cube(40), np.array([1.0, 0.85, 1.0]), 0.2845)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(cut.vertices, cut.faces, jobs=1)
    (report,) = [r for r in result.reports if not r.skipped]
    assert report.crossings == 0 and report.crease.startswith("a corner of 3 creases")
    assert not any("cross" in str(w.message) for w in caught)
    new = result.vertices[len(cut.vertices):]
    assert np.minimum(new, 1 - new).min(axis=1).max() < 1e-9


def test_a_clean_fill_reports_no_crossing_and_no_warning():
    cut = cut_geodesic_disk(*data.sphere(), np.array([0.0, 0.0, 1.0]), 0.4)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(cut.vertices, cut.faces, method="fair", jobs=1)
    assert [r.crossings for r in result.reports] == [0]
    assert not any("cross" in str(w.message) for w in caught)
