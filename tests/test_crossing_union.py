"""A fill triangle that crosses the surface both around its hole and farther out (or another
hole's fill) is one triangle: ``HoleReport.crossings`` counts distinct triangles, each
warning its own (session 48; session 47's fuzz campaign saw 58 reported for 56)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from surfinpaint.app.fill_report import HoleRecord, hole_lines
from surfinpaint.errors import HoleWarning
from surfinpaint.fill import parallel, pipeline

# the spike's two corners: from the loop corner at (1, 1, 0) it goes down through the known
# faces at about (0.5, 0.5, 0) (within the rings checked as the hole is filled) and on
# through the sheet at z = -0.5 below them (another piece: farther out along the mesh)
SPIKE = np.array([[0.3, 0.6, -1.0], [0.6, 0.3, 1.0]])
CORNER = np.array([1.0, 1.0, 0.0])


def _grid_over_a_sheet(shift: float):
    """A flat 4 x 4 grid of squares with its middle 2 x 2 removed (an 8-edge hole), and a
    square sheet of two triangles under its corner at z = -0.5, both moved ``shift`` along x;
    the vertices, faces and the hole's loop."""
    g = np.stack(np.meshgrid(np.arange(5.0), np.arange(5.0), indexing="ij"), -1).reshape(-1, 2)
    grid = np.column_stack([g, np.zeros(len(g))])
    faces = []
    for i in range(4):
        for j in range(4):
            if not (1 <= i <= 2 and 1 <= j <= 2):
                a, b, c, d = 5 * i + j, 5 * (i + 1) + j, 5 * (i + 1) + j + 1, 5 * i + j + 1
                faces += [[a, b, c], [a, c, d]]
    sheet = np.array([[-0.5, -0.5, -0.5], [1.5, -0.5, -0.5], [1.5, 1.5, -0.5],
                      [-0.5, 1.5, -0.5]])
    vertices = np.vstack([grid, sheet]) + [shift, 0.0, 0.0]
    faces = np.vstack([faces, [[25, 26, 27], [25, 27, 28]]])
    return vertices, faces, np.array([6, 11, 16, 17, 18, 13, 8, 7])


def _spiked(real):
    """``faired_fills`` with a spike triangle added to each fill, at its grid's (1, 1, 0):
    the loop's corner of least x + y."""
    def fills(vertices, faces, loop, orders, **kwargs):
        made = {}
        for order, (new_v, new_f, used) in real(vertices, faces, loop, orders, **kwargs).items():
            at = loop[np.argmin(vertices[loop].sum(axis=1))]
            n = len(vertices) + len(new_v)
            made[order] = (np.vstack([new_v, SPIKE + vertices[at] - CORNER]),
                           np.vstack([new_f, [[at, n, n + 1]]]), used)
        return made
    return fills


@pytest.fixture
def spiked(monkeypatch):
    monkeypatch.setattr(parallel, "faired_fills", _spiked(parallel.faired_fills))


def _fill(pieces: int, jobs: int):
    parts = [_grid_over_a_sheet(10.0 * k) for k in range(pieces)]
    offsets = np.cumsum([0] + [len(v) for v, _, _ in parts])
    vertices = np.vstack([v for v, _, _ in parts])
    faces = np.vstack([f + o for (_, f, _), o in zip(parts, offsets, strict=False)])
    loops = [loop + o for (_, _, loop), o in zip(parts, offsets, strict=False)]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = pipeline.fill_holes(vertices, faces, holes=loops, method="fair", jobs=jobs)
    return result, [str(w.message) for w in caught if issubclass(w.category, HoleWarning)]


def test_a_triangle_crossing_near_and_far_is_counted_once(spiked):
    result, said = _fill(1, 1)
    (report,) = result.reports
    assert report.outcome == "faired"
    spike = len(result.hole_faces()[0]) - 1  # the last of the fill's triangles
    # each check saw the one triangle, and says so
    assert [s for s in said if "around the hole (its" in s] == [
        f"hole {report.index}: 1 triangle of the fill crosses the surface around the hole "
        "(its boundary loop folds over itself there): check the result"]
    assert [s for s in said if "farther out" in s] == [
        f"hole {report.index}: 1 triangle of the fill crosses the surface farther out than "
        "the rings around the hole checked as it was filled (a fold or a thin part, near in "
        "space): check the result"]
    # the report counts it once, and names it (its row among the hole's new faces)
    assert report.crossings == 1
    assert report.crossing_triangles.tolist() == [spike]
    assert "1 of them crossing the surface" in hole_lines(report)[0]
    assert HoleRecord.of(report).to_json()["crossings"] == 1


@pytest.mark.parametrize("jobs", [1, 2])
def test_the_triangles_crossing_come_back_from_workers(spiked, on_forked_workers, jobs):
    # three holes on workers (forked: they inherit the spike)
    result, said = _fill(3, jobs)
    assert len(on_forked_workers) == (jobs > 1)
    assert len(said) == 6
    spikes = [len(f) - 1 for f in result.hole_faces()]
    assert [r.crossings for r in result.reports] == [1, 1, 1]
    assert [r.crossing_triangles.tolist() for r in result.reports] == [[s] for s in spikes]


def _spiked_with_a_slit(real):
    """:func:`_spiked`, and a zero-area triangle along the loop's first edge (a new vertex
    at its middle): the fill crosses the surface and cannot be stitched in."""
    def fills(vertices, faces, loop, orders, **kwargs):
        made = {}
        for order, (new_v, new_f, used) in _spiked(real)(vertices, faces, loop, orders,
                                                         **kwargs).items():
            n = len(vertices) + len(new_v)
            middle = (vertices[loop[0]] + vertices[loop[1]]) / 2
            made[order] = (np.vstack([new_v, middle]),
                           np.vstack([new_f, [[loop[1], loop[0], n]]]), used)
        return made
    return fills


@pytest.mark.parametrize("jobs", [1, 2])
def test_a_fill_stitched_out_reports_no_crossing_triangles(monkeypatch, on_forked_workers,
                                                           jobs):
    # its near crossings are ids into faces never written: the report lists what was
    # written (nothing), says why it was not, and warns of no crossing
    monkeypatch.setattr(parallel, "faired_fills", _spiked_with_a_slit(parallel.faired_fills))
    result, said = _fill(3, jobs)
    assert len(on_forked_workers) == (jobs > 1)
    assert [r.outcome for r in result.reports] == ["failed"] * 3
    assert [r.crossings for r in result.reports] == [0] * 3
    assert [r.crossing_triangles.tolist() for r in result.reports] == [[]] * 3
    assert len(result.faces) == 3 * (24 + 2)  # nothing written
    assert [s for s in said if "cross" in s] == []
    assert [s.split(":")[0] for s in said if "zero-area triangle" in s] == [
        f"hole {r.index}" for r in result.reports]
    for r in result.reports:
        assert "crossing" not in hole_lines(r)[0]
        assert HoleRecord.of(r).to_json()["crossings"] == 0
