"""The plane test (``geometry.flatness``) on analytic cases, the fill laid on a plane
(``fill.liepa.baseline.laid_on_plane``), and the conformal fill's use of both
(``ConformalOptions.plane_test``, docs/candidates.md "Session 26")."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import grid_mesh

from surfinpaint import ConformalOptions
from surfinpaint.fill.conformal import conformal_fill
from surfinpaint.fill.liepa.baseline import faired_fills, laid_on_plane
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.flatness import morans_i, plane_test, trimmed_plane_test

ALPHA = 0.01


def annulus(seed: int, height, noise: float = 0.01) -> tuple[np.ndarray, np.ndarray]:
    """The vertices of a 41 x 41 grid over [-1, 1]^2 in the annulus 0.5 <= r <= 1 (a ring of
    known surface around a hole), lifted to ``height(u, v)`` plus Gaussian noise, tilted and
    shifted (the test must not depend on the axes), and the grid edges between them."""
    v, f = grid_mesh(40, 40)
    uv = 2.0 * v[:, :2] - 1.0
    r = np.linalg.norm(uv, axis=1)
    keep = (r >= 0.5) & (r <= 1.0)
    local = np.full(len(v), -1)
    local[keep] = np.arange(keep.sum())
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    e = np.unique(np.sort(e[keep[e].all(axis=1)], axis=1), axis=0)
    w = height(uv[keep, 0], uv[keep, 1])
    w = w + np.random.default_rng(seed).normal(0, noise, len(w))
    a = np.radians(35.0)
    rot = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    points = np.column_stack([uv[keep], w]) @ rot.T + np.array([3.0, -1.0, 2.0])
    return points, local[e]


@pytest.mark.parametrize("seed", range(5))
def test_a_noisy_plane_is_flat(seed):
    t = plane_test(*annulus(seed, lambda u, v: 0.2 * u - 0.1 * v), alpha=ALPHA)
    assert t.flat and t.p_curvature >= ALPHA and t.p_pattern >= ALPHA
    assert t.noise == pytest.approx(0.01, rel=0.2)  # the noise, from the residual
    # the plane: the tilted z = 0.2 u - 0.1 v through (3, -1, 2)
    a = np.radians(35.0)
    rot = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    expected = rot @ np.array([-0.2, 0.1, 1.0])
    expected /= np.linalg.norm(expected)
    assert abs(t.normal @ expected) == pytest.approx(1.0, abs=1e-4)


@pytest.mark.parametrize("seed", range(5))
def test_a_noisy_sphere_patch_is_curved(seed):
    radius = 4.0  # sagitta at the rim 1/8 of a unit: 12 noise levels
    t = plane_test(*annulus(seed, lambda u, v: radius - np.sqrt(radius**2 - u * u - v * v)),
                   alpha=ALPHA)
    assert not t.flat and t.p_curvature < 1e-6


def test_folds_no_quadric_fits_are_not_flat():
    # ripples: the quadric fits no better than the plane (the F-test alone says flat), but
    # the plane's residuals are alike between neighbours (Moran's I: not noise)
    points, edges = annulus(0, lambda u, v: 0.05 * np.sin(9 * u) * np.cos(9 * v), noise=0.0)
    t = plane_test(points, edges, alpha=ALPHA)
    assert t.p_curvature >= ALPHA and not t.flat and t.p_pattern < 1e-6
    assert plane_test(points, alpha=ALPHA).flat  # without the edges: the F-test alone


@pytest.mark.parametrize(("case", "flat"), [
    ("an exact plane", True),  # a plane to rounding: flat, noise 0
    ("six points", False),  # as many unknowns as points: nothing to test
])
def test_degenerate_inputs(case, flat):
    if case == "an exact plane":
        t = plane_test(*annulus(0, lambda u, v: 0.0 * u, noise=0.0))
        assert t.noise == 0.0
    else:
        t = plane_test(np.random.default_rng(0).random((6, 3)))
        assert np.isnan(t.p_curvature)
    assert t.flat is flat


@pytest.mark.parametrize("bad", [0.0, 1.0, -0.5])
def test_a_significance_level_outside_0_1_is_an_error(bad):
    with pytest.raises(ValueError, match="alpha"):
        plane_test(np.zeros((10, 3)), alpha=bad)


def test_moran_s_i_tells_a_smooth_field_from_noise():
    points, edges = annulus(0, lambda u, v: 0.0 * u, noise=0.0)
    smooth = points[:, 0]  # a linear field: neighbours alike
    noise = np.random.default_rng(1).standard_normal(len(points))
    assert morans_i(smooth, edges)[1] < 1e-12
    assert morans_i(noise, edges)[1] > 0.01
    assert morans_i(np.ones(len(points)), edges) == (0.0, 1.0)


def _noisy_plane_hole(noise: float, bump: float = 0.0, seed: int = 0):
    """A hole in a tilted 31 x 31 grid with noise normal to it (and a bump of height
    ``bump`` over the whole grid): the cut, and the plane's unit normal."""
    v, f = grid_mesh(30, 30)
    u, w = 2.0 * v[:, 0] - 1.0, 2.0 * v[:, 1] - 1.0
    z = bump * (1.0 - u * u - w * w) + np.random.default_rng(seed).normal(0, noise, len(v))
    v = np.column_stack([u, w, 0.3 * u + z])
    cut = cut_geodesic_disk(v, f, np.array([0.0, 0.0, 0.0]), 0.3)
    normal = np.array([-0.3, 0.0, 1.0]) / np.linalg.norm([-0.3, 0.0, 1.0])
    return cut, normal


def test_the_fill_laid_on_a_plane_is_its_projection_onto_it():
    v, f = grid_mesh(16, 16)
    cut = cut_geodesic_disk(v, f, np.array([0.5, 0.5, 0.0]), 0.3)
    w = cut.vertices.copy()
    w[cut.loop, 2] = 0.01  # the loop raised off the plane z = 0: the fill is not
    nv, patch, _ = faired_fills(w, cut.faces, cut.loop, (2,))[2]
    normal = np.array([0.0, 0.6, 0.8])  # a tilted plane through (0, 0, 0.05)
    out = laid_on_plane(nv, np.array([0.0, 0.0, 0.05]), normal)
    assert len(out) == len(nv) > 0
    np.testing.assert_allclose((out - [0.0, 0.0, 0.05]) @ normal, 0.0, atol=1e-15)
    # moved along the normal only: each vertex's nearest point of the plane
    moved = out - nv
    np.testing.assert_allclose(np.cross(moved, normal), 0.0, atol=1e-15)
    assert len(laid_on_plane(np.zeros((0, 3)), np.zeros(3), normal)) == 0


@pytest.mark.parametrize(("noise", "bump", "laid"), [
    (0.004, 0.0, True),  # a noisy plane: the faired fill laid on it
    (0.004, 0.3, False),  # a noisy dome: curved, the self-check decides as before
])
def test_the_conformal_fill_lays_a_noisy_flat_hole_on_its_plane(noise, bump, laid):
    cut, normal = _noisy_plane_hole(noise, bump)
    fill = conformal_fill(cut.vertices, cut.faces, cut.loop)
    off = conformal_fill(cut.vertices, cut.faces, cut.loop, ConformalOptions(plane_test=False))
    assert (fill.plane is not None) is laid and off.plane is None
    if laid:
        assert fill.kind == "fair" and fill.plane.flat and "plane" in fill.selection
        # closer to the noise-free plane than the faired fill the self-check writes
        height = np.abs(fill.vertices @ normal)  # the noise-free plane: z = 0.3 x
        height_off = np.abs(off.vertices @ normal)
        assert height.mean() < height_off.mean()
    else:
        np.testing.assert_array_equal(fill.vertices, off.vertices)


def test_the_command_line_lays_a_flat_hole_on_its_plane_unless_told_not_to(tmp_path, capsys):
    import json

    from surfinpaint.app.cli import main
    from surfinpaint.fill.pipeline import fill_holes
    from surfinpaint.io.formats import read_mesh, write_mesh

    cut, _ = _noisy_plane_hole(0.004)
    path = tmp_path / "scan.ply"
    write_mesh(path, cut.vertices, cut.faces)
    written = {}
    for flags, options in (([], ConformalOptions()),
                           (["--no-plane-test"], ConformalOptions(plane_test=False))):
        out, report = tmp_path / "out.ply", tmp_path / "report.json"
        assert main(["fill", str(path), "-o", str(out), "-q", "--json", str(report),
                     *flags]) == 0
        expected = fill_holes(cut.vertices, cut.faces, options=options).vertices
        written[bool(flags)] = read_mesh(out)[0]
        np.testing.assert_allclose(written[bool(flags)], expected, rtol=0, atol=1e-6)
        (hole,) = json.loads(report.read_text())["holes"]
        assert (hole["plane"] is None) is bool(flags)
        if not flags:
            assert hole["plane"]["p_curvature"] >= ALPHA and hole["outcome"] == "faired"
    assert not np.allclose(written[False], written[True])
    assert main(["fill", str(path), "-o", str(tmp_path / "x.ply"), "--method", "fair",
                 "--no-plane-test"]) == 2
    assert "--no-plane-test" in capsys.readouterr().err


def test_the_text_report_says_the_fill_was_laid_on_its_plane():
    from surfinpaint.app.fill_report import hole_lines, written
    from surfinpaint.fill.pipeline import fill_holes

    cut, _ = _noisy_plane_hole(0.004)
    (report,) = fill_holes(cut.vertices, cut.faces).reports
    assert written(report) == "faired fill (bilaplacian, laid on its plane)"
    assert "a plane within its noise" in hole_lines(report)[1]
    (off,) = fill_holes(cut.vertices, cut.faces,
                        options=ConformalOptions(plane_test=False)).reports
    assert "plane" not in written(off)


def test_the_report_page_says_a_hole_was_laid_on_its_plane():
    from surfinpaint.app.report_page import HoleComparison, hole_title

    laid = HoleComparison(index=1, n_edges=24, diameter=0.58, kept=False, fair_order=2,
                          fallback="the known surface around the hole is a plane ...",
                          on_plane=True)
    assert "plane within its noise" in hole_title(laid)
    assert "failed" not in hole_title(laid) and "rejected" not in hole_title(laid)
    failed = HoleComparison(index=1, n_edges=24, diameter=0.58, kept=False, fair_order=2,
                            fallback="FillError: the λ-H fill diverges")
    assert "the λ-H fill failed" in hole_title(failed)


def test_the_report_draws_the_fill_laid_on_its_plane_as_written(tmp_path, monkeypatch):
    # `surfinpaint report`: panel (C) of a hole laid on its plane draws the fill `fill`
    # writes (not the λ-H fill the plane test made unnecessary), the titles say so, and
    # the page's "conformal" error is the laid fill's
    monkeypatch.delenv("DISPLAY", raising=False)
    from surfinpaint.app import report
    from surfinpaint.app.report_page import WRITTEN_ERROR, table_rows
    from surfinpaint.fill.pipeline import fill_holes
    from surfinpaint.geometry.metrics import surface_distance

    cut, _ = _noisy_plane_hole(0.004)
    truth = (cut.truth_vertices, cut.truth_faces)
    (c,), fills = report.compare_holes(cut.vertices, cut.faces, [cut.loop], truth=[truth])
    assert c.on_plane and not c.kept
    written = fill_holes(cut.vertices, cut.faces, method="conformal")
    n = len(cut.vertices)
    drawn = report.panel_fills(fills, 0)
    assert c.written_panel == drawn.written_in == "C" and drawn.written is None
    shown_v, shown_f = drawn.conformal
    np.testing.assert_array_equal(shown_v[n:], written.vertices[n:])
    np.testing.assert_array_equal(shown_f, written.new_faces)
    raw_v, _ = fills.lambda_h_fills[0]  # the λ-H fill, still made for (E)/(G)
    assert not np.allclose(raw_v[n:], written.vertices[n:])
    assert fills.diagnostics[0] is not None
    # the error of what is written: the laid fill against the removed patch
    ids, inverse = np.unique(written.new_faces, return_inverse=True)
    d = surface_distance(written.vertices[ids], inverse.reshape(-1, 3), *truth,
                         n_samples=10000)
    assert c.errors["conformal"].mean == pytest.approx(100 * d.mean / c.diameter)
    assert c.errors["conformal"] != c.errors["conformal raw"]
    header, (row,) = table_rows([c])
    assert "laid on its plane" in row[header.index("conformal outcome")]

    drawn = []
    hole_panel = report.hole_panel

    def spy(*args, **kwargs):  # draws, and records what it was given
        drawn.append((args, kwargs))
        return hole_panel(*args, **kwargs)

    monkeypatch.setattr(report, "hole_panel", spy)
    report.panels_for(cut.vertices, cut.faces, [c], fills, tmp_path)
    ((args, kwargs),) = drawn
    assert args[4] is fills.written_fills[0]  # (C): the written fill
    titles = kwargs["titles"]
    assert titles["C"] == "(C) conformal: faired fill laid on its plane (written)"
    assert "not written" in titles["E"] and "not written" in titles["G"]
    title = kwargs["suptitle"]
    assert "plane within its noise; the faired fill (order 2) laid on it is written" in title
    # the error (C) is labelled with: the page's "conformal" one, the written fill's
    assert f"(C, written) {row[header.index(WRITTEN_ERROR)]}," in title
    assert (tmp_path / c.picture).is_file()


def _annulus_uv(points: np.ndarray) -> np.ndarray:
    """The (u, v) of :func:`annulus`'s points, untilted."""
    a = np.radians(35.0)
    rot = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    return ((points - np.array([3.0, -1.0, 2.0])) @ rot)[:, :2]


def _next_to_an_edge(u, v):
    # a face z = 0 whose points beyond u = 0.85 rise across a sharp edge (a 76° wall)
    return 4.0 * np.maximum(u - 0.85, 0.0)


@pytest.mark.parametrize("seed", range(5))
def test_a_noisy_face_next_to_a_sharp_edge_is_flat_once_trimmed(seed):
    points, edges = annulus(seed, _next_to_an_edge)
    uv = _annulus_uv(points)
    inner = np.flatnonzero(np.linalg.norm(uv, axis=1) < 0.55)  # the hole's loop
    assert not plane_test(points, edges, alpha=ALPHA).flat  # the plain test sees the edge
    t = trimmed_plane_test(points, edges, keep=inner, alpha=ALPHA)
    assert t is not None and t.flat and t.left_out + t.points == len(points)
    assert 0 < t.left_out <= 0.2 * len(points)
    a = np.radians(35.0)
    rot = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    assert abs(t.normal @ (rot @ np.array([0.0, 0.0, 1.0]))) == pytest.approx(1.0, abs=1e-3)
    assert "left out" in t.sentence()


@pytest.mark.parametrize(("case", "height", "applies"), [
    # outer points lifted all around the hole (a dome's, a rim's): not on one side
    ("a rim all around", lambda u, v: 0.1 * (np.hypot(u, v) > 0.95), False),
    # a quarter of the ring across the edge: more than the 20 % a trim may leave out
    ("too much across the edge", lambda u, v: 4.0 * np.maximum(u - 0.3, 0.0), False),
    # a bump across more than a tenth of the hole's own loop: the hole is not on the plane
    # (without the loop required, the same points are trimmed flat)
    ("a bump on the loop", lambda u, v: 0.2 * np.exp(-((u - 0.5)**2 + v * v) / 0.02), False),
    # a smooth curved patch: what the trim keeps is curved too
    ("a sphere", lambda u, v: 4.0 - np.sqrt(16.0 - u * u - v * v), None),
])
def test_the_trimmed_test_does_not_call_these_flat(case, height, applies):
    points, edges = annulus(0, height)
    inner = np.flatnonzero(np.linalg.norm(_annulus_uv(points), axis=1) < 0.55)
    t = trimmed_plane_test(points, edges, keep=inner, alpha=ALPHA)
    if applies is False:
        assert t is None, case
        if case == "a bump on the loop":
            assert trimmed_plane_test(points, edges, alpha=ALPHA).flat
    else:
        assert t is None or not t.flat, case


def test_a_few_loop_vertices_off_the_plane_may_be_trimmed():
    # a narrow bump on the loop (a scan's shadow edge at one loop vertex, say): at most a
    # tenth of the loop's vertices left out, and the laid fill's triangles along the loop
    # meet them; the same bump with no loop vertex allowed out is not trimmed
    points, edges = annulus(0, lambda u, v: 0.2 * np.exp(-((u - 0.5)**2 + v * v) / 0.01))
    inner = np.flatnonzero(np.linalg.norm(_annulus_uv(points), axis=1) < 0.55)
    t = trimmed_plane_test(points, edges, keep=inner, alpha=ALPHA)
    assert t is not None and t.flat and t.left_out > 0
    kept = trimmed_plane_test(points, edges, keep=inner, alpha=ALPHA, keep_most=0.0)
    assert kept is None


def test_a_hole_next_to_a_scanned_edge_is_laid_on_its_plane():
    # a noisy grid bent up across a sharp edge two edge lengths outside the hole's second ring
    v, f = grid_mesh(30, 30)
    u, w = 2.0 * v[:, 0] - 1.0, 2.0 * v[:, 1] - 1.0
    noise = np.random.default_rng(0).normal(0, 0.004, len(v))
    v = np.column_stack([u, w, 0.8 * np.maximum(u - 0.36, 0.0) + noise])
    cut = cut_geodesic_disk(v, f, np.array([0.0, 0.0, 0.0]), 0.3)
    fill = conformal_fill(cut.vertices, cut.faces, cut.loop)
    assert fill.plane is not None and fill.plane.flat and fill.plane.left_out > 0
    assert abs(fill.plane.normal[2]) == pytest.approx(1.0, abs=1e-2)
    assert np.abs(fill.vertices[:, 2]).max() < 0.01  # on the face, not bent toward the edge
    # the reports say so: the sentence, and the JSON record's count
    from surfinpaint.app.fill_report import HoleRecord, hole_lines
    from surfinpaint.fill.pipeline import fill_holes

    (report,) = fill_holes(cut.vertices, cut.faces, jobs=1).reports
    assert f"{fill.plane.left_out} vertices off it on one side left out" in hole_lines(report)[1]
    assert HoleRecord.of(report).to_json()["plane"]["left_out"] == fill.plane.left_out


# ---- the hole's own face (session 30): rings that reach past a part's edges all around


def _hole_in_top_face(n: int, lift=None, size: int = 1):
    """A cube of n × n squares per side, the faces within ``size`` rings of the top face's
    centre vertex cut out (``size`` 1: its star, a hole of 8 edges); ``lift(x, y)`` raises
    the top face's inner vertices."""
    from surfinpaint.data import cube
    from surfinpaint.geometry.mesh import boundary_loops, k_ring

    v, f = cube(n)
    top = np.isclose(v[:, 2], 1.0)
    if lift is not None:
        inner = top & (v[:, 0] > 1e-9) & (v[:, 0] < 1 - 1e-9) & (v[:, 1] > 1e-9) \
            & (v[:, 1] < 1 - 1e-9)
        v[inner, 2] += lift(v[inner, 0], v[inner, 1])
    centre = np.flatnonzero(top & np.isclose(v[:, 0], 0.5) & np.isclose(v[:, 1], 0.5))[0]
    f = f[~k_ring(f, [centre], size - 1, len(v))[f].any(axis=1)]
    return v, f, boundary_loops(f)[0]


@pytest.mark.parametrize("case, n, lift, flat, past", [
    # 2 rings past the loop reach the cube's sides all around: neither the plain test nor
    # the trimmed fit (one side only) calls it flat; the top face alone is a plane
    ("narrow face", 4, None, True, True),
    # the rings end on the face's edges: the plain test says flat, nothing left out
    ("wide face", 6, None, True, False),
    # the face itself is a dome: its own vertices are curved too
    ("domed face", 4, lambda x, y: 0.3 * (x * (1 - x) + y * (1 - y)), False, False),
])
def test_a_hole_on_a_narrow_face_is_tested_on_its_own_face(case, n, lift, flat, past):
    from surfinpaint.fill.conformal.method import known_plane

    v, f, loop = _hole_in_top_face(n, lift)
    test = known_plane(v, f, loop)
    assert test.flat is flat, case
    assert (test.past_edges > 0) is past, case
    if flat:  # the top face's plane
        assert np.allclose(np.abs(test.normal), [0, 0, 1]) and np.isclose(test.centre[2], 1)
    if past:
        assert "past the part's sharp edges left out" in test.sentence()


def test_the_conformal_fill_of_a_hole_on_a_narrow_face_lies_in_it():
    v, f, loop = _hole_in_top_face(6, size=2)  # 2 rings past the loop: the sides
    fill = conformal_fill(v, f, loop)
    assert len(fill.vertices) > 0
    assert fill.plane is not None and fill.plane.past_edges > 0
    assert np.abs(fill.vertices[:, 2] - 1.0).max() < 1e-12


def test_the_own_face_stops_at_the_crease_angle_asked_for():
    # the cube's 90° edges are sharp at the default 60°, not at 95°: then the rings past
    # them are the face's own, the surface around the hole is curved and a faired fill
    # (not laid on a plane) is written
    v, f, loop = _hole_in_top_face(6, size=2)
    assert conformal_fill(v, f, loop).plane is not None
    fill = conformal_fill(v, f, loop, ConformalOptions(crease_angle=95.0))
    assert fill.plane is None


# ---- a face beside a fillet (session 31): no sharp edge bounds it on that side


def _floor_by_fillet(lift=None, n: int = 20, size: int = 3):
    """A channel's floor, 1/n a grid cell: in the profile's arc length s, a wall down to a
    sharp edge at s = 0.3, the floor z = 0 up to s = 0.67, a fillet of radius 0.3 turning
    90° up, a wall; extruded along y over [0, 1]. The faces within ``size`` rings of the
    floor's vertex at s = 0.5, y = 0.5 are cut out: 2 rings past the loop reach past the
    sharp edge on one side and onto the fillet on the other. ``lift(x, y)`` raises the
    floor's inner vertices."""
    from surfinpaint.geometry.mesh import boundary_loops, k_ring

    v, f = grid_mesh(2 * n, n)
    s, y = 2.0 * v[:, 0], v[:, 1]
    start, radius = 0.67, 0.3
    x, z = np.where(s < 0.3, 0.0, s - 0.3), np.minimum(s - 0.3, 0.0)
    arc = (s > start) & (s <= start + radius * np.pi / 2)
    x[arc] = start - 0.3 + radius * np.sin((s[arc] - start) / radius)
    z[arc] = radius * (1 - np.cos((s[arc] - start) / radius))
    up = s > start + radius * np.pi / 2
    x[up], z[up] = start - 0.3 + radius, radius + s[up] - start - radius * np.pi / 2
    floor = (s > 0.3 + 1e-9) & (s < start - 1e-9)
    if lift is not None:
        z[floor] += lift(x[floor], y[floor])
    v = np.column_stack([x, y, z])
    centre = np.flatnonzero(np.isclose(s, 0.5) & np.isclose(y, 0.5))[0]
    f = f[~k_ring(f, [centre], size - 1, len(v))[f].any(axis=1)]
    return v, f, min(boundary_loops(f), key=len)


def _hole_in_a_cap(height, rings: int = 24, size: int = 5):
    """A disk of ``rings`` rings of vertices around a centre (radius 1) lifted to
    ``height(r)``, the faces within ``size`` rings of the centre cut out: the loop is a
    circle of vertices at one height, a plane to rounding."""
    from surfinpaint.data import bumpy_disk
    from surfinpaint.geometry.mesh import boundary_loops, k_ring

    v, f = bumpy_disk(rings)
    v[:, 2] = height(np.hypot(v[:, 0], v[:, 1]))
    f = f[~k_ring(f, [0], size - 1, len(v))[f].any(axis=1)]
    return v, f, min(boundary_loops(f), key=len)


def _fillet_all_around(r):
    """A flat disk of radius 0.23 with a fillet of radius 0.3 around it (the loop at 5/24,
    2 rings past it at 7/24)."""
    out = np.clip(r - 0.23, 0.0, 0.3)
    return 0.3 - np.sqrt(0.09 - out * out)


@pytest.mark.parametrize("case, mesh, flat", [
    # the vertices on the fillet, off the loop's plane on one side, and those past the
    # sharp edge on the other: the rest is the floor's plane
    ("floor beside a fillet", lambda: _floor_by_fillet(), True),
    # the floor itself bends: its loop is no plane
    ("floor bent", lambda: _floor_by_fillet(lambda x, y: -(x - 0.25) ** 2 / 6), False),
    ("domed floor", lambda: _floor_by_fillet(lambda x, y: 0.05 * x * (0.37 - x)), False),
    # the loop is a planar circle; every vertex past it is off its plane, all around
    ("cap of a sphere", lambda: _hole_in_a_cap(lambda r: 3 - np.sqrt(9 - r * r)), False),
    # ... so a flat disk with a fillet all around it is not told from such a cap
    ("disk in a fillet all around", lambda: _hole_in_a_cap(_fillet_all_around), False),
])
def test_a_hole_beside_a_fillet_is_tested_on_the_loop_s_plane(case, mesh, flat):
    from surfinpaint.fill.conformal.method import known_plane

    v, f, loop = mesh()
    test = known_plane(v, f, loop)
    assert test.flat is flat, case
    if flat:  # the floor's plane, the fillet's vertices left out, the wall's past the edge
        assert np.allclose(np.abs(test.normal), [0, 0, 1]) and abs(test.centre[2]) < 1e-12
        assert test.left_out > 0 and test.past_edges > 0
        assert "off it on one side left out" in test.sentence()


def test_the_conformal_fill_of_a_hole_beside_a_fillet_lies_in_its_face():
    v, f, loop = _floor_by_fillet()
    fill = conformal_fill(v, f, loop)
    assert len(fill.vertices) > 0
    assert fill.plane is not None and fill.plane.left_out > 0
    assert np.abs(fill.vertices[:, 2]).max() < 1e-12
