"""Options are validated once, at construction; unknown names and misplaced options are an
error at the entry point; fills come back as typed results."""

import dataclasses

import numpy as np
import pytest

import surfinpaint
from surfinpaint import (
    METHODS,
    ConformalOptions,
    Fill,
    GridOptions,
    Verdict,
    fill_holes,
)
from surfinpaint.data import sphere
from surfinpaint.fill.conformal import conformal_fill
from surfinpaint.fill.results import LambdaHDiagnostics, MeshLambdaH
from surfinpaint.geometry.cutting import cut_geodesic_disk


@pytest.fixture(scope="module")
def sphere_hole():
    v, f = sphere(3)
    return cut_geodesic_disk(v, f, 0, 0.5)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"start": "flat"}, "start must be one of"),
    ({"discretization": "voxels"}, "discretization must be one of"),
    ({"patch_rings": 0}, "patch_rings"),
    ({"patch_rings": 2}, "patch_rings must be an integer >= 3"),  # the mesh keeps 3
    ({"patch_rings": 2.5, "discretization": "grid"}, "patch_rings"),
    ({"passes": 0}, "passes"),
    ({"solver_iterations": 0}, "solver_iterations"),
    ({"solver_tol": -1e-3}, "solver_tol"),
    ({"solver_tol": float("nan")}, "solver_tol"),
    ({"hide_rings": 0}, "hide_rings"),
    ({"siblings": -1}, "siblings"),
    ({"gap_rings": -1}, "gap_rings"),
    ({"select": "yes"}, "select must be True or False"),
    ({"creases": 1}, "creases must be True or False"),
    ({"crease_angle": 0.0}, "crease_angle must be between 0 and 180"),
    ({"crease_angle": 180.0}, "crease_angle must be between 0 and 180"),
    ({"crease_angle": -5.0}, "crease_angle must be between 0 and 180"),
    ({"grid": GridOptions()}, "grid options apply to discretization='grid' only"),
    ({"discretization": "grid", "grid": {"spacing": 0.3}}, "grid must be a GridOptions"),
    ({"s0_search": "greedy"}, "s0_search must be one of"),
    ({"s0_refinement": "isotropic"}, "s0_refinement must be one of"),
    ({"fair_smoothing": 0.0}, "fair_smoothing"),
    ({"fair_smoothing": -1.0}, "fair_smoothing"),
    ({"fair_smoothing": "always"}, "fair_smoothing must be a positive number, 'auto' or None"),
])
def test_bad_conformal_options(kwargs, match):
    with pytest.raises(ValueError, match=match):
        ConformalOptions(**kwargs)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"spacing": 0.0}, "spacing"),
    ({"fit_radius": 0}, "fit_radius"),
    ({"fit_sigma": -1.0}, "fit_sigma"),
    ({"dilate": -1}, "dilate"),
    ({"inpaint": "magic"}, "inpaint must be one of"),
    ({"fidelity": 0.0}, "fidelity"),
    ({"reconstruct": "poisson"}, "reconstruct must be one of"),
    ({"max_nodes": 0}, "max_nodes"),
])
def test_bad_grid_options(kwargs, match):
    with pytest.raises(ValueError, match=match):
        GridOptions(**kwargs)


def test_options_defaults_names_and_freezing():
    o = ConformalOptions()
    assert (o.discretization, o.rings_in_patch, o.passes, o.select, o.grid) == \
        ("mesh", 4, 1, True, None)
    grid = ConformalOptions(discretization="grid")
    assert grid.grid == GridOptions() and grid.rings_in_patch == 10
    assert ConformalOptions(patch_rings=6).rings_in_patch == 6
    with pytest.raises(dataclasses.FrozenInstanceError):
        o.select = False
    with pytest.raises(TypeError, match="iterations"):
        ConformalOptions(iterations=2)  # the old name of two things: passes and solver steps
    with pytest.raises(TypeError, match="tol"):
        GridOptions(tol=1e-3)


def test_neighbourhood_rings_cover_the_patch_and_the_siblings():
    o = ConformalOptions()
    # patch + 3 without siblings; with them, the gap, the sibling's width twice and a patch
    assert ConformalOptions(select=False).neighbourhood_rings(30) == 4 + 3
    assert ConformalOptions(siblings=0).neighbourhood_rings(30) == 4 + 3
    hole_rings = int(np.ceil(30 / (2 * np.pi))) + 1
    assert o.neighbourhood_rings(30) == 3 + 2 * hole_rings + 4 + 3
    assert ConformalOptions(discretization="grid").neighbourhood_rings(30) == \
        3 + 2 * hole_rings + 10 + 3


def test_fill_holes_rejects_unknown_names_and_misplaced_options(sphere_hole):
    cut = sphere_hole
    assert METHODS == surfinpaint.METHODS == ("conformal", "fair")
    for method in METHODS:
        with pytest.raises(TypeError, match="select"):
            fill_holes(cut.vertices, cut.faces, method=method, select=False)
    with pytest.raises(ValueError, match="options apply to method='conformal'"):
        fill_holes(cut.vertices, cut.faces, method="fair",
                   options=ConformalOptions(select=False))
    with pytest.raises(ValueError, match="options must be a ConformalOptions"):
        fill_holes(cut.vertices, cut.faces, options={"select": False})
    for debug_stage in ("initial", "triangulate"):  # not public methods
        with pytest.raises(ValueError, match="unknown method"):
            fill_holes(cut.vertices, cut.faces, method=debug_stage)
    for bad in (0, 4, 2.5, True):
        with pytest.raises(ValueError, match="fair_order"):
            fill_holes(cut.vertices, cut.faces, fair_order=bad)
        with pytest.raises(ValueError, match="fair_order"):
            conformal_fill(cut.vertices, cut.faces, cut.loop, fair_order=bad)
    with pytest.raises(ValueError, match="neighbourhood_rings"):
        fill_holes(cut.vertices, cut.faces, neighbourhood_rings=0)


def test_typed_results_of_the_conformal_fill(sphere_hole):
    cut = sphere_hole
    fill = conformal_fill(cut.vertices, cut.faces, cut.loop)
    assert isinstance(fill, Fill) and isinstance(fill.verdict, Verdict)
    assert fill.kind == ("conformal" if fill.verdict.keep else "fair")
    assert fill.failure is None and fill.selection.startswith("self-check")
    assert fill.verdict.hidden and set(fill.verdict.hidden) == {"fair2", "fair3", "conformal"}
    n = len(cut.vertices)
    assert fill.vertices.shape[1] == 3 and fill.faces.max() == n + len(fill.vertices) - 1
    result = fill_holes(cut.vertices, cut.faces)
    (report,) = result.reports
    assert np.array_equal(result.vertices[n:], fill.vertices)
    assert report.method == fill.kind and report.verdict == fill.verdict
    assert report.note == fill.selection and report.fallback is None
    if fill.kind == "conformal":
        d = report.diagnostics
        assert isinstance(d, LambdaHDiagnostics) and isinstance(d.mesh, MeshLambdaH)
        assert d.discretization == "mesh" and d.rings == 4 and report.fair_order is None
        assert d.mesh.free.sum() == len(fill.vertices)
        # the patch's free vertices are the new ones, in order: their positions after the pass
        assert np.array_equal(d.mesh.after[d.mesh.free], fill.vertices)


def test_typed_results_of_the_raw_and_the_faired_fill(sphere_hole):
    cut = sphere_hole
    raw = fill_holes(cut.vertices, cut.faces, options=ConformalOptions(select=False))
    (r,) = raw.reports
    assert r.method == "conformal" and r.verdict is None and r.note is None
    assert r.diagnostics.discretization == "mesh"
    grid = fill_holes(cut.vertices, cut.faces, options=ConformalOptions(
        select=False, discretization="grid"))
    d = grid.reports[0].diagnostics
    assert d.discretization == "grid" and d.reconstruct == "gauss-codazzi"
    assert d.grid.lam.shape == d.grid.domain.shape and d.grid.hole.any() and d.mesh is None
    fair = fill_holes(cut.vertices, cut.faces, method="fair", fair_order=3)
    (f,) = fair.reports
    assert (f.method, f.fair_order, f.verdict, f.diagnostics, f.crease) == \
        ("fair", 3, None, None, None)
    notes = Fill(np.zeros((0, 3)), np.zeros((0, 3), int), "conformal", selection="a",
                 crease_failure="b")
    assert notes.notes == "a; b"
    assert Fill(np.zeros((0, 3)), np.zeros((0, 3), int), "fair").notes is None


@pytest.mark.parametrize("s0", [{"s0_search": "cdt"}, {"s0_refinement": "cgal"},
                                {"s0_search": "delaunay"}, {"fair_smoothing": 0.35}])
def test_the_raw_fill_falls_back_on_the_triangulation_its_options_ask_for(sphere_hole, s0,
                                                                          monkeypatch):
    # without a verdict (select=False) a failed λ-H fill is replaced by the bilaplacian fill
    # of the options' own S0 search and refinement, as the faired candidates are made
    from surfinpaint.errors import FillError
    from surfinpaint.fill.conformal.candidates import Candidates
    from surfinpaint.fill.liepa.baseline import faired_fills

    def fails(self, *args, **kwargs):
        raise FillError("made to fail")

    monkeypatch.setattr(Candidates, "lambda_h", fails)
    cut = sphere_hole
    options = ConformalOptions(select=False, **s0)
    fill = conformal_fill(cut.vertices, cut.faces, cut.loop, options=options)
    want_v, want_f, _ = faired_fills(cut.vertices, cut.faces, cut.loop, (2,),
                                     search=options.s0_search,
                                     refinement=options.s0_refinement,
                                     smoothing=options.fair_smoothing)[2]
    assert fill.kind == "fair" and fill.failure == "FillError: made to fail"
    assert np.array_equal(fill.vertices, want_v) and np.array_equal(fill.faces, want_f)


def _noisy_sphere_hole(seed: int = 0):
    """sphere(3) with normal noise of 0.03 mean edges (a range scan's), a hole cut in it."""
    from surfinpaint.geometry.mesh import mean_edge_length, vertex_normals

    v, f = sphere(3)
    noise = 0.03 * mean_edge_length(v, f) * np.random.default_rng(seed).standard_normal(len(v))
    return cut_geodesic_disk(v + vertex_normals(v, f) * noise[:, None], f, 0, 0.5)


@pytest.mark.parametrize(("noisy", "smoothing"), [(True, 0.35), (False, None)])
def test_auto_smoothing_is_decided_once_per_hole_from_its_noise(sphere_hole, noisy, smoothing,
                                                                 monkeypatch):
    # every faired fill of the hole's self-check (the candidates and the test holes') is
    # made with the length its own surroundings' noise gives: the smoothing fill on the
    # noisy sphere, the bilaplacian fill on the clean one
    import surfinpaint.fill.conformal.candidates as candidates
    from surfinpaint.errors import FillError
    from surfinpaint.fill.conformal.candidates import Candidates

    asked = []
    made = candidates.faired_fills

    def spy(*args, smoothing=None, **kwargs):
        asked.append(smoothing)
        return made(*args, smoothing=smoothing, **kwargs)

    def fails(self, *args, **kwargs):
        raise FillError("made to fail")

    monkeypatch.setattr(candidates, "faired_fills", spy)
    monkeypatch.setattr(Candidates, "lambda_h", fails)  # the faired fills are what is tested
    cut = _noisy_sphere_hole() if noisy else sphere_hole
    fill = conformal_fill(cut.vertices, cut.faces, cut.loop,
                          options=ConformalOptions(fair_smoothing="auto", plane_test=False))
    assert asked and set(asked) == {smoothing}
    fixed = conformal_fill(cut.vertices, cut.faces, cut.loop,
                           options=ConformalOptions(fair_smoothing=smoothing,
                                                    plane_test=False))
    assert np.array_equal(fill.vertices, fixed.vertices)


def test_the_zero_area_fallback_fills_with_the_conformal_options_smoothing():
    # fill_holes writes the faired fill where zero-area faces lie in the self-check's rings
    # (hole_steps.around_zero_area): a fallback of the conformal method, with its smoothing;
    # method="fair" itself (the baseline) takes no options
    from surfinpaint.fill.liepa.baseline import faired_fills
    from surfinpaint.fill.parallel import fill_local

    cut = _noisy_sphere_hole()
    smoothed = faired_fills(cut.vertices, cut.faces, cut.loop, (2,), smoothing=0.35)[2][0]
    plain = faired_fills(cut.vertices, cut.faces, cut.loop, (2,))[2][0]
    assert np.abs(smoothed - plain).max() > 1e-6
    for smoothing, want in ((0.35, smoothed), ("auto", smoothed), (None, plain)):
        fill = fill_local(cut.vertices, cut.faces, cut.loop, "fair",
                          ConformalOptions(fair_smoothing=smoothing), None)
        assert np.array_equal(fill.vertices, want)
    with pytest.raises(ValueError, match="options apply to method='conformal'"):
        fill_holes(cut.vertices, cut.faces, method="fair",
                   options=ConformalOptions(fair_smoothing=0.35))


def test_the_fair_method_is_the_bilaplacian_baseline_whatever_the_conformal_default(
        monkeypatch):
    # method="fair" is the conventional fill the benchmarks compare with: never smoothed,
    # also if the conformal method's default were "auto" (made so here)
    import surfinpaint.fill.pipeline as pipeline
    from surfinpaint.fill.liepa.baseline import faired_fills

    cut = _noisy_sphere_hole()
    monkeypatch.setattr(pipeline, "ConformalOptions",
                        lambda **kw: ConformalOptions(**{"fair_smoothing": "auto", **kw}))
    result = fill_holes(cut.vertices, cut.faces, method="fair")
    plain = faired_fills(cut.vertices, cut.faces, cut.loop, (2,))[2][0]
    assert np.allclose(np.sort(result.vertices[len(cut.vertices):], axis=0),
                       np.sort(plain, axis=0), atol=1e-12)
