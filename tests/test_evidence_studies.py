"""Session 25's studies of the self-check's evidence: the hedging study
(``benchmarks/hedge_study.py``: the simplex grid, the weights put on it, the tests' evidence
per candidate, the true error of a convex combination of fills on a planar hole whose errors
are known), the score table's distances between candidates
(``benchmarks/selfcheck_table.py``) and the mesh-wide prior
(``benchmarks/mesh_prior_study.py``: where probes are cut, the prior, the veto)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import grid_mesh

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
hedge = pytest.importorskip("hedge_study")
table = pytest.importorskip("selfcheck_table")

from surfinpaint.fill.pipeline import fill_holes  # noqa: E402
from surfinpaint.fill.results import Fill  # noqa: E402
from surfinpaint.geometry.cutting import cut_geodesic_disk  # noqa: E402
from surfinpaint.geometry.mesh import mean_edge_length  # noqa: E402

INF = np.inf


def test_the_simplex_grid():
    points = hedge.simplex(4)
    assert len(points) == 15 and all(sum(p) == 4 and min(p) >= 0 for p in points)
    assert len(set(points)) == 15 and {(4, 0, 0), (0, 4, 0), (0, 0, 4)} <= set(points)


@pytest.mark.parametrize("weights, point", [
    ((1, 0, 0), "8,0,0"),
    ((0, 2, 2), "0,4,4"),
    ((0.75, 0.25, 0), "6,2,0"),
    ((1, 1, 1), "3,3,2"),  # 8/3 each: the two largest remainders (ties: first) round up
    ((0.1, 0.1, 0.8), "1,1,6"),  # 0.8 each for the first two, 6.4 for the last
])
def test_weights_go_to_the_nearest_grid_point(weights, point):
    assert hedge._grid(weights) == point


def row(hidden, sibling, conformal=1.0):
    return {"hidden": hidden, "sibling": sibling,
            "true": {"fair2": 1.0, "fair3": 1.0, "conformal": conformal}, "crossed": False}


def test_evidence_is_the_geometric_mean_of_scores_relative_to_each_tests_best():
    e = hedge.evidence(row({"fair2": 2, "fair3": 1, "conformal": 4},
                           {"fair2": 3, "fair3": 3, "conformal": 3}))
    assert e == pytest.approx({"fair2": np.sqrt(2), "fair3": 1.0, "conformal": 2.0})
    # a λ-H failure on the test hole says nothing: the λ-H fill gets that test's worst
    e = hedge.evidence(row({"fair2": 2, "fair3": 1, "conformal": INF},
                           {"fair2": 1, "fair3": 2, "conformal": 0.5}))
    assert e == pytest.approx({"fair2": np.sqrt(4), "fair3": np.sqrt(4),
                               "conformal": np.sqrt(2)})
    # no test: every candidate alike
    assert hedge.evidence(row({}, {})) == {"fair2": 1.0, "fair3": 1.0, "conformal": 1.0}


def test_softmax_weights():
    r = row({"fair2": 2, "fair3": 1, "conformal": 4}, {"fair2": 2, "fair3": 1, "conformal": 4})
    w = np.array(hedge.softmax_rule(1.0)(r))
    assert w / w.sum() == pytest.approx(np.array([0.5, 1.0, 0.25]) / 1.75)
    # a λ-H fill that failed on the hole gets no weight
    assert hedge.softmax_rule(1.0)(row(r["hidden"], r["sibling"], conformal=INF))[2] == 0


def test_hedged_choice_blends_only_a_close_runner_up():
    # fair2 and the λ-H fill within 1.1 of each other on the geometric mean
    close = {"fair2": 1.0, "fair3": 3.0, "conformal": 1.05}
    r = row(close, close)
    pick = hedge.replay.rule_library(r)[0]
    w = dict(zip(hedge.NAMES, hedge.hedged_choice(1.1, 0.25)(r), strict=True))
    assert pick == "fair2" and w == {"fair2": 0.75, "fair3": 0.0, "conformal": 0.25}
    assert hedge.hedged_choice(1.01, 0.25)(r) is None  # not close enough: today's choice


@pytest.fixture(scope="module")
def planar_hole():
    """A planar grid with a hole cut and its faired fill (exact: the plane)."""
    v, f = grid_mesh(16, 16)
    cut = cut_geodesic_disk(v, f, np.array([0.5, 0.5, 0.0]), 0.2)
    hole = cut.holes[0]
    n = len(cut.vertices)
    filled = fill_holes(cut.vertices, cut.faces, holes=[hole.loop], method="fair")
    new = np.asarray(filled.vertices)[n:]
    faces = np.asarray(filled.faces)[len(cut.faces):]
    return cut, hole, new, faces


def test_blends_are_convex_combinations_of_the_candidates(planar_hole):
    cut, hole, new, faces = planar_hole
    up, down = new + [0, 0, 0.01], new - [0, 0, 0.01]
    fills = {"fair2": Fill(up, faces, "fair"), "fair3": Fill(down, faces, "fair"),
             "conformal": Fill(new, faces, "conformal")}
    args = (cut.vertices, cut.faces, fills, hole.truth_vertices, hole.truth_faces,
            hole.diameter, 4000)
    blends = hedge.blend_errors(*args)["blends"]
    assert len(blends) == len(hedge.simplex())
    # the grid's corners are the candidates themselves
    for key, name in (("8,0,0", "fair2"), ("0,8,0", "fair3"), ("0,0,8", "conformal")):
        assert blends[key] == pytest.approx(table._true_error(
            cut.vertices, cut.faces, fills[name], hole.truth_vertices, hole.truth_faces,
            hole.diameter, 4000))
    # the plane is exact; half up and half down is the plane again
    assert blends["0,0,8"] < 1e-9 and blends["4,4,0"] < 1e-9
    assert blends["8,0,0"] > 1e-3 and blends["2,2,4"] < 1e-9
    # a λ-H fill that failed, or one on other triangles, gives no blends
    assert hedge.blend_errors(cut.vertices, cut.faces, {**fills, "conformal": RuntimeError()},
                              *args[3:])["blends"] is None
    assert hedge.blend_errors(cut.vertices, cut.faces, {
        **fills, "conformal": Fill(new, faces[::-1], "conformal")}, *args[3:])["blends"] is None


def test_distances_between_candidates(planar_hole):
    cut, hole, new, faces = planar_hole
    fills = {"fair2": Fill(new + [0, 0, 0.01], faces, "fair"), "fair3": Fill(new, faces, "fair"),
             "conformal": RuntimeError("failed")}
    between = table._between(cut.vertices, cut.faces, fills, hole.diameter, 4000)
    # the failed candidate is left out; two parallel patches 0.01 apart inside the hole,
    # the same surface outside it
    assert set(between) == {"fair2|fair3"}
    assert 0 < between["fair2|fair3"] < 100 * 0.01 / hole.diameter


# --------------------------------------------------------------------------- the mesh prior

prior_study = pytest.importorskip("mesh_prior_study")


def test_probe_sites_keep_clear_of_every_benchmark_hole():
    v, f = grid_mesh(20, 20)
    mesh = type("Mesh", (), {"vertices": v, "faces": f})()
    entry = {"holes": [{"centre": [0.5, 0.5, 0.0], "radius": 0.1},
                       {"centre": [0.2, 0.8, 0.0], "radius": 0.05}]}
    sites = prior_study.probe_sites(mesh, entry, 10, np.random.default_rng(0))
    h = mean_edge_length(v, f)
    assert len(sites) == 10
    for s in sites:
        for hole in entry["holes"]:
            gap = np.linalg.norm(np.subtract(s["centre"], hole["centre"]))
            assert gap > hole["radius"] + s["radius"] + prior_study.GAP * h
        assert s["radius"] in (0.1, 0.05)
        assert np.allclose(v[s["vertex"]], s["centre"])


def test_the_prior_is_each_candidates_median_over_the_probes_best():
    probes = [{"mesh": "m", "fair2": 2.0, "fair3": 1.0, "conformal": 1.5},
              {"mesh": "m", "fair2": 1.0, "fair3": 3.0, "conformal": 1.0},
              {"mesh": "m", "fair2": 4.0, "fair3": 2.0, "conformal": INF},
              {"mesh": "m", "fair2": 0.0, "fair3": 0.0, "conformal": 0.0}]  # exact: left out
    prior = prior_study.priors(probes)["m"]
    # relative: (2, 1, 1.5), (1, 3, 1), (2, 1, inf)
    assert prior == pytest.approx({"fair2": 2.0, "fair3": 1.0, "conformal": 1.5})


def test_the_prior_veto():
    kept = {"hidden": {"fair2": 1.0, "fair3": 1.0, "conformal": 0.8},
            "sibling": {"fair2": 1.0, "fair3": 1.0, "conformal": 0.9}, "crossed": False}
    assert prior_study.replay.rule_library(kept)[0] == "conformal"
    veto = prior_study.prior_veto(1.1)
    assert veto(kept, {"fair2": 1.0, "fair3": 1.0, "conformal": 1.05})[0] == "conformal"
    assert veto(kept, {"fair2": 1.0, "fair3": 1.0, "conformal": 1.2})[0] == "fair2"
    decisive = {**kept, "hidden": {"fair2": 1.0, "fair3": 1.0, "conformal": 0.4}}
    assert veto(decisive, {"fair2": 1.0, "fair3": 1.0, "conformal": 1.2})[0] == "conformal"
    assert prior_study.prior_veto(1.1, decisive=False)(
        decisive, {"fair2": 1.0, "fair3": 1.0, "conformal": 1.2})[0] == "fair2"


# --------------------------------------------------------------------------- the gallery

gallery = pytest.importorskip("failure_gallery")


def test_the_gallery_draws_the_holes_the_library_writes_above_1_5_times_worst_first():
    decisive = {"fair2": 1.0, "fair3": 1.0, "conformal": 0.1}  # the λ-H fill is kept
    rows = [{"mesh": "a", "hole": 0, "true": {"fair2": 1.0, "fair3": 2.0, "conformal": 1.6},
             "hidden": decisive, "sibling": {}, "crossed": False},
            {"mesh": "a", "hole": 1, "true": {"fair2": 1.0, "fair3": 0.5, "conformal": 2.0},
             "hidden": decisive, "sibling": {}, "crossed": False},
            {"mesh": "b", "hole": 0, "true": {"fair2": 1.0, "fair3": 2.0, "conformal": 1.4},
             "hidden": decisive, "sibling": {}, "crossed": False}]
    holes = gallery.losing_holes(rows)
    assert [(r["mesh"], r["hole"]) for r in holes] == [("a", 1), ("a", 0)]
    assert [r["ratio"] for r in holes] == pytest.approx([4.0, 1.6])
