"""Two planes meeting at an edge (``geometry.flatness.two_plane_test``), the fill laid on
them (``fill.liepa.baseline.laid_on_two_planes``), and the conformal fill's use of both on a
noisy scan of an edge (docs/candidates.md, "Session 29"); the hole split along the line where
they meet (``fill.two_planes.split_on_two_planes``, session 30) and its fallback."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import grid_mesh

from surfinpaint import ConformalOptions
from surfinpaint.errors import FillError
from surfinpaint.fill.conformal import conformal_fill
from surfinpaint.fill.liepa.baseline import faired_fills, laid_on_two_planes
from surfinpaint.fill.two_planes import split_on_two_planes
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.flatness import TwoPlanes, two_plane_test
from surfinpaint.geometry.mesh import boundary_loops, unique_edges, vertex_normals

ALPHA = 0.01


def _surface(height, noise=0.004, seed=0, n=30):
    """A noisy height field over a grid on [-1, 1]^2 (noise along z), as a mesh."""
    v, f = grid_mesh(n, n)
    u, w = 2.0 * v[:, 0] - 1.0, 2.0 * v[:, 1] - 1.0
    z = height(u, w) + np.random.default_rng(seed).normal(0, noise, len(v))
    return np.column_stack([u, w, z]), f


def _ring_test(height, **kwargs):
    v, f = _surface(height, **kwargs)
    keep = np.linalg.norm(v[:, :2], axis=1) > 0.3  # the ring around a hole at the centre
    local = np.full(len(v), -1)
    local[keep] = np.arange(keep.sum())
    edges = local[unique_edges(f[keep[f].all(axis=1)])[0]]
    return two_plane_test(v[keep], vertex_normals(v, f)[keep], edges, alpha=ALPHA)


@pytest.mark.parametrize(("case", "height", "verdict"), [
    # a roof of slope 0.5 on each side: planes at 53°, each a plane within its noise
    ("a noisy edge, 53°", lambda u, w: 0.5 * np.abs(u), True),
    # a step's edge: a level face and a steep one
    ("a noisy edge, 90°", lambda u, w: 1.0 * np.maximum(u, 0.0), True),
    # a gentle bend: the planes meet at 17°, under the 30° of an edge
    ("a bend, 17°", lambda u, w: 0.15 * np.abs(u), None),
    # a plane: any split gives two nearly parallel halves
    ("a plane", lambda u, w: 0.2 * u - 0.1 * w, None),
    # a cylinder: the halves are curved
    ("a cylinder", lambda u, w: np.sqrt(2.0 - u * u), False),
    # an edge near the ring's rim: the smaller side under 15 % of the points
    ("an edge at the rim", lambda u, w: 1.0 * np.maximum(u - 0.85, 0.0), None),
])
def test_two_plane_test_cases(case, height, verdict):
    t = _ring_test(height)
    if verdict is None:
        assert t is None, case
    else:
        assert t is not None and t.flat is verdict, case


def test_the_two_planes_of_a_noisy_edge():
    t = _ring_test(lambda u, w: 0.5 * np.abs(u), seed=3)
    assert t.angle == pytest.approx(2 * np.degrees(np.arctan(0.5)), abs=1.0)
    expected = {(0.5, 0.0, 1.0), (-0.5, 0.0, 1.0)}
    for plane in (t.first, t.second):
        n = plane.normal * np.sign(plane.normal[2])
        assert min(np.linalg.norm(n - np.array(e) / np.linalg.norm(e)) for e in expected) < 0.02
        assert plane.noise == pytest.approx(0.004, rel=0.3)
    assert t.points == t.first.points + t.second.points and t.left_out == 0
    assert "two planes meeting at 53°" in t.sentence()


def test_laid_on_two_planes_projects_each_vertex_onto_its_side():
    # planes z = x (x > 0 side) and z = -x (x < 0 side): a roof along y
    first = (np.array([0.5, 0.0, 0.5]), np.array([-1.0, 0.0, 1.0]) / np.sqrt(2))
    second = (np.array([-0.5, 0.0, 0.5]), np.array([1.0, 0.0, 1.0]) / np.sqrt(2))
    points = np.array([[0.4, 0.3, 0.0], [-0.4, -0.2, 0.1], [0.0, 0.5, 1.0], [0.0, 0.1, -1.0]])
    out = laid_on_two_planes(points, first, second)
    np.testing.assert_allclose(out[:, 2], np.abs(out[:, 0]), atol=1e-12)  # on the roof
    assert out[0, 0] > 0 and out[1, 0] < 0  # each on its own side
    np.testing.assert_allclose(out[3], [0.0, 0.1, 0.0], atol=1e-12)  # under the ridge: on it
    np.testing.assert_allclose(out[:, 1], points[:, 1], atol=1e-12)  # along the line: kept
    with pytest.raises(ValueError, match="parallel"):
        laid_on_two_planes(points, first, first)


def test_the_conformal_fill_lays_a_hole_across_a_scanned_edge_on_its_two_planes():
    # a noisy roof (53°: under the crease angle, so no crease is found in the noise)
    v, f = _surface(lambda u, w: 0.5 * np.abs(u), seed=1)
    cut = cut_geodesic_disk(v, f, np.array([0.0, 0.0, 0.0]), 0.3)
    fill = conformal_fill(cut.vertices, cut.faces, cut.loop)
    smooth = conformal_fill(cut.vertices, cut.faces, cut.loop,
                            ConformalOptions(plane_test=False))
    assert fill.kind == "fair" and fill.plane is not None and fill.plane.flat
    assert "two planes meeting at" in fill.selection and fill.crease is None

    def off_roof(points):
        return np.abs(points[:, 2] - 0.5 * np.abs(points[:, 0])).mean()

    # closer to the noise-free roof than what the self-check writes without the test
    assert off_roof(fill.vertices) < 0.5 * off_roof(smooth.vertices)
    # and said so in the JSON record
    from surfinpaint.app.fill_report import HoleRecord, hole_lines
    from surfinpaint.fill.pipeline import fill_holes

    (report,) = fill_holes(cut.vertices, cut.faces, jobs=1).reports
    record = HoleRecord.of(report).to_json()["plane"]
    assert record["planes"] == 2 and record["vertices"] == fill.plane.points
    assert "laid on its two planes" in hole_lines(report)[0]


def test_two_planes_crossing_through_a_bump_are_not_an_edge(monkeypatch):
    # a coarse egg crate (the tuning-side family): two planes fitted to the ring around this
    # hole pass the flatness test, but they cross through the bumps (a third or more of the
    # points lie on the other plane's side of their line), so no edge is claimed; the fill
    # laid on them was 2.5x the smooth fill's error there
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from eggcrate import egg_crate

    from surfinpaint.fill.conformal.method import known_two_planes
    from surfinpaint.geometry import flatness

    cut = egg_crate(20, 4, 7, 2.5, 0.4, 4)
    assert known_two_planes(cut.vertices, cut.faces, cut.loop) is None
    monkeypatch.setattr(flatness, "TWO_PLANES_ACROSS", 1.0)
    crossing = known_two_planes(cut.vertices, cut.faces, cut.loop)
    assert crossing is not None and crossing.flat


def _c_shaped_hole(n=40):
    """A clean roof (53°) with a C-shaped hole whose arms cross the ridge: the meeting line
    enters and leaves the hole twice (mesh, loop)."""
    v, f = _surface(lambda u, w: 0.5 * np.abs(u), noise=0.0, n=n)
    inside = np.linalg.norm(v[:, :2], axis=1)
    inside = (inside > 0.2) & (inside < 0.5) & ~((v[:, 0] > 0.1) & (np.abs(v[:, 1]) < 0.15))
    f = f[~inside[f].any(axis=1)]
    used = np.unique(f)
    ids = np.full(len(v), -1)
    ids[used] = np.arange(len(used))
    v, f = v[used], ids[f]
    (loop,) = [c for c in boundary_loops(f) if np.abs(v[c, :2]).max() < 0.9]
    return v, f, loop


@pytest.mark.parametrize(("case", "slope", "options"), [
    # 53°: under the crease angle, the two-plane test's own case
    ("a clean roof, 53°", 0.5, ConformalOptions()),
    # 90°: the crease search would find it; without it, the two planes
    ("a clean roof, 90°, creases off", 1.0, ConformalOptions(creases=False)),
])
def test_the_fill_of_a_clean_edge_is_split_along_it_exactly(case, slope, options):
    # a hole across the ridge of a noise-free roof z = slope |x|, the ridge on grid vertices:
    # the fill must lie on the two planes and contain the ridge's segment across the hole
    # (laying the faired fill's vertices on the planes cut it off: a bevel)
    v, f = _surface(lambda u, w: slope * np.abs(u), noise=0.0)
    cut = cut_geodesic_disk(v, f, np.array([0.05, 0.02, 0.0]), 0.35)
    fill = conformal_fill(cut.vertices, cut.faces, cut.loop, options)
    assert fill.kind == "fair" and isinstance(fill.plane, TwoPlanes), case
    assert "split along the line where they meet" in fill.selection, case
    points = np.vstack([cut.vertices, fill.vertices])
    x = points[:, 0]
    np.testing.assert_allclose(fill.vertices[:, 2], slope * np.abs(fill.vertices[:, 0]),
                               atol=1e-9, err_msg=case)
    corners = x[fill.faces]  # every triangle on one side of the ridge
    assert ((corners >= -1e-9).all(axis=1) | (corners <= 1e-9).all(axis=1)).all(), case
    ridge = np.intersect1d(np.flatnonzero(np.abs(x) <= 1e-9), fill.faces)
    ridge = ridge[np.argsort(points[ridge, 1])]
    assert np.isin(ridge[[0, -1]], cut.loop).all() and len(ridge) > 3, case
    edges = set(map(tuple, unique_edges(fill.faces)[0].tolist()))
    steps = zip(ridge[:-1], ridge[1:], strict=True)
    assert all((min(a, b), max(a, b)) in edges for a, b in steps), case


_ROOF = [(np.array([0.5, 0.0, 0.25]), np.array([-0.5, 0.0, 1.0]) / np.sqrt(1.25)),
         (np.array([-0.5, 0.0, 0.25]), np.array([0.5, 0.0, 1.0]) / np.sqrt(1.25))]


def _hole_beside_the_ridge():
    """A clean roof (53°) with a round hole on one of its planes (mesh, loop)."""
    v, f = _surface(lambda u, w: 0.5 * np.abs(u), noise=0.0)
    cut = cut_geodesic_disk(v, f, np.array([0.6, 0.0, 0.3]), 0.2)
    return cut.vertices, cut.faces, cut.loop


@pytest.mark.parametrize(("case", "hole", "planes", "words"), [
    ("the ridge enters and leaves the loop twice", _c_shaped_hole, _ROOF,
     "crosses the loop more than twice"),
    ("the ridge misses the hole", _hole_beside_the_ridge, _ROOF, "does not change plane"),
    ("parallel planes", _c_shaped_hole,
     [(np.array([0.0, 0.0, 5.0]), np.array([0.0, 0.0, 1.0])),
      (np.array([0.0, 0.0, -5.0]), np.array([0.0, 0.0, 1.0]))], "parallel"),
])
def test_split_on_two_planes_refuses_what_it_cannot_split(case, hole, planes, words):
    with pytest.raises(FillError, match=words):
        split_on_two_planes(*hole(), *planes)


def test_a_hole_the_meeting_line_crosses_four_times_is_laid_on_the_planes_unsplit():
    # the fallback: today's projection of the faired fill, and the fill says why
    v, f, loop = _c_shaped_hole()
    fill = conformal_fill(v, f, loop)
    assert isinstance(fill.plane, TwoPlanes)
    assert "not split: the meeting line crosses the loop more than twice" in fill.selection
    new, faces, order = faired_fills(v, f, loop, (2,))[2]
    planes = [(p.centre, p.normal) for p in (fill.plane.first, fill.plane.second)]
    np.testing.assert_array_equal(fill.faces, faces)
    np.testing.assert_allclose(fill.vertices, laid_on_two_planes(new, *planes), atol=1e-12)
