"""The session 38 study's replay (``benchmarks/smooth_selfcheck_study.py``): the library's
choice replayed from a row's evidence, the rules tried, and how a pick becomes an error, on
hand-made rows. No mesh is loaded and no fill is made."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
study = pytest.importorskip("smooth_selfcheck_study")


def evidence(hidden, sibling=None, adv2=None, adv3=None, n_edges=30, **extra):
    return {"hidden": hidden, "sibling": sibling or {}, "shallower": False, "crossed": False,
            "n_edges": n_edges, "adv2": adv2 or {}, "adv3": adv3 or {}, "sigma": 0.0,
            "edge": 1.0, **extra}


# the λ-H fill decisively closer than fair2 on the hidden rings, significantly (10 se)
DECISIVE = evidence({"fair2": 1.0, "fair3": 0.3, "conformal": 0.4},
                    adv2={"hidden": {"conformal": (0.6, 0.06), "fair3": (0.7, 0.07)}},
                    adv3={"hidden": {"conformal": (-0.1, 0.01)}})
# the λ-H fill closer than fair2 on the hidden rings, not significantly: demoted to fair2
# (fair3 closer too, not significantly)
DEMOTED = evidence({"fair2": 1.0, "fair3": 0.9, "conformal": 0.8},
                   {"fair2": 1.0, "fair3": 0.9, "conformal": 0.9},
                   adv2={"hidden": {"conformal": (0.2, 0.1), "fair3": (0.1, 0.1)},
                         "sibling": {"conformal": (0.1, 0.01), "fair3": (0.1, 0.01)}})
# fair2 first on both tests
FAIR2 = evidence({"fair2": 1.0, "fair3": 1.2, "conformal": 1.3},
                 adv2={"hidden": {"conformal": (-0.3, 0.1), "fair3": (-0.2, 0.1)}})


def test_the_library_rule_replayed():
    assert study.library_rule(DECISIVE) == "conformal"
    assert study.library_rule(DEMOTED) == "fair2"
    assert study.library_rule(FAIR2) == "fair2"
    # no test: fair2
    assert study.library_rule(evidence({})) == "fair2"


@pytest.mark.parametrize(("rule", "picks"), [
    # (DECISIVE, DEMOTED, FAIR2)
    (study.rule_lh_beats_fair3, ("fair3", "fair2", "fair2")),
    (study.rule_lh_beats_fair3_significant, ("fair3", "fair2", "fair2")),
    (study.rule_demoted_to_fair3, ("conformal", "fair3", "fair2")),
    (study.rule_fair3_when_small, ("conformal", "fair2", "fair2")),
    (study.rule_faired_by_means, ("conformal", "fair3", "fair2")),
    (study.rule_a_and_b, ("fair3", "fair3", "fair2")),
])
def test_the_rules_tried(rule, picks):
    assert tuple(rule(e) for e in (DECISIVE, DEMOTED, FAIR2)) == picks


# the λ-H fill failed on the hidden-ring hole; the siblings keep it (fair3 first of the faired
# fills on the hidden rings, significantly)
FAILED_HIDDEN = evidence({"fair2": 1.0, "fair3": 0.5, "conformal": np.inf},
                         {"fair2": 1.0, "fair3": 0.6, "conformal": 0.4},
                         adv2={"hidden": {"fair3": (0.5, 0.05)},
                               "sibling": {"fair3": (0.4, 0.04), "conformal": (0.6, 0.06)}},
                         adv3={"sibling": {"conformal": (0.2, 0.1)}})


def test_a_lh_fill_that_failed_on_the_hidden_rings():
    assert study.library_rule(FAILED_HIDDEN) == "conformal"  # the siblings decide
    assert study.rule_failed_hidden_not_kept(FAILED_HIDDEN) == "fair3"
    # beats fair3 on the siblings by 2 se only: not enough for (c')
    assert study.rule_failed_hidden_beat_fair3(FAILED_HIDDEN) == "fair3"
    sure = dict(FAILED_HIDDEN, adv3={"sibling": {"conformal": (0.3, 0.1)}})
    assert study.rule_failed_hidden_beat_fair3(sure) == "conformal"
    # a crease fill of a crossed hole is left to the library's rule
    assert study.rule_failed_hidden_not_kept(dict(FAILED_HIDDEN, crossed=True)) == "conformal"


def test_clean_ring_rule_reads_the_noise():
    assert study.rule_clean_ring_fair3(DEMOTED) == "fair3"  # σ 0: clean
    assert study.rule_clean_ring_fair3(dict(DEMOTED, sigma=0.05)) == "fair2"  # a scan's noise
    assert study.rule_clean_ring_fair3(FAIR2) == "fair2"  # the hidden rings rank fair2 first


def test_siblings_break_a_hidden_ring_tie():
    # DEMOTED: fair3's hidden-ring advantage 1 se (a tie), the siblings' 10 se
    assert study.rule_siblings_break_the_tie(DEMOTED) == "fair3"
    assert study.rule_siblings_break_the_tie_clean(DEMOTED) == "fair3"
    assert study.rule_siblings_break_the_tie_clean(dict(DEMOTED, sigma=0.05)) == "fair2"
    # FAIR2: fair3 2 se worse on the hidden rings (a tie), no sibling record
    assert study.rule_siblings_break_the_tie(FAIR2) == "fair2"


def test_small_holes_rule_reads_the_hole_size():
    small = dict(DEMOTED, n_edges=17)
    assert study.rule_fair3_when_small(small) == "fair3"
    assert study.rule_fair3_when_small(dict(DEMOTED, n_edges=25)) == "fair2"


def row(errors, ev, lh_status="ok"):
    return {"set": "s", "mesh": "m", "hole": 0, "errors": errors, "evidence": ev,
            "status": {"conformal_raw": lh_status}}


ERRORS = {"fair": 2.0, "fair3": 1.0, "conformal_raw": 0.5, "conformal": 0.5, "cgal": 1.0}


def test_outcome_of_a_pick():
    r = row(ERRORS, DECISIVE)
    assert [study.outcome(r, p) for p in ("fair2", "fair3", "conformal")] == [2.0, 1.0, 0.5]
    # a λ-H fill that fell back on the hole writes the library's fallback
    fell = row(dict(ERRORS, conformal=2.0, conformal_raw=2.0), DECISIVE, "fallback")
    assert study.outcome(fell, "conformal") == 2.0
    # no self-check (a plane): the row's written fill whatever the rule
    assert study.outcome(row(ERRORS, None), "fair3") == 0.5


def test_measures_of_hand_made_rows():
    rows = [row(ERRORS, DECISIVE),  # λ-H 0.5, best
            row(dict(ERRORS, conformal=2.0), DEMOTED),  # fair2 2.0 = 2× fair3: above 1.5×
            row(dict(ERRORS, fair=1.0, conformal=1.0, cgal=0.5), FAIR2)]  # fair2 1.0, best
    m = study.measures(rows, study.library_rule)
    assert m["above15"] == 1 and m["above"][0][0] == pytest.approx(2.0)
    assert (m["best_pick"], m["chooser"]) == (1, 3)  # the third: λ-H 0.5 was best
    assert m["median_cgal"] == pytest.approx(2.0)  # 0.5, 2.0, 2.0
    assert m["log_regret"] == pytest.approx(np.mean(np.log([1.0, 4.0, 2.0])))
    fixed = study.measures(rows, study.rule_demoted_to_fair3)
    assert fixed["above15"] == 0


def test_signals_of_a_row():
    """Session 40's truth-free signals, read from a row's evidence (nan where a test did not
    run); the study's numbers are in σ and edge units."""
    ev = evidence({"fair2": 1.0, "fair3": 1.5}, {}, adv2={"hidden": {"fair3": (-0.5, 0.25)}},
                  sigma=0.2, edge=0.5, p_curvature=1e-3, fair23_rms=0.1, fair23_max=0.4)
    s = study.signals({"evidence": ev, "radius_h": 4, "near_border": True})
    assert s["hidden f3/f2"] == pytest.approx(1.5) and np.isnan(s["sibling f3/f2"])
    assert s["t hidden f3"] == pytest.approx(-2.0) and np.isnan(s["t sibling f3"])
    assert s["log10 p curvature"] == pytest.approx(-3.0)
    assert s["sigma / edge"] == pytest.approx(0.4)
    assert s["fair2-fair3 rms / sigma"] == pytest.approx(0.5)
    assert s["fair2-fair3 max / sigma"] == pytest.approx(2.0)
    assert s["fair2-fair3 rms / edge"] == pytest.approx(0.2)
    assert s["radius / sigma"] == pytest.approx(10.0)  # 4 edges of 0.5 over σ 0.2
    assert (s["boundary edges"], s["near border"]) == (30.0, 1.0)


@pytest.mark.parametrize(("values", "ratios", "expected"), [
    # fair3 1.5x closer on the two largest values, fair2 1.5x closer on the rest: >= 5
    ([1, 2, 3, 5, 6], [0.5, 0.5, 0.6, 2.0, 1.6], (">=", 5.0, 2, 2, 0)),
    # the same below: <= 2
    ([1, 2, 3, 5, 6], [2.0, 1.6, 0.5, 0.5, 1.0], ("<=", 2.0, 2, 2, 0)),
    # a missed hole between right ones: catching it breaks one either way (the first side
    # found is kept on a tie)
    ([1, 2, 3], [0.5, 2.0, 0.5], (">=", 2.0, 2, 1, 1)),
    # nothing to catch
    ([1, 2], [0.5, 1.0], None),
])
def test_best_threshold(values, ratios, expected):
    best = study.best_threshold(np.array(values, float), np.array(ratios))
    if expected is None:
        assert best is None
        return
    got = (best["side"], best["threshold"], best["switched"], best["caught"], best["broken"])
    assert got == expected


def test_screen_reads_only_scan_holes_where_fair2_is_written():
    scan = {"kind": "range_scan", "radius_h": 3, "near_border": False}
    rows = [dict(row(dict(ERRORS, fair=2.0, fair3=1.0), FAIR2), **scan),  # missed
            dict(row(dict(ERRORS, fair=1.0, fair3=2.0), FAIR2), **scan),  # fair2 right
            dict(row(dict(ERRORS, fair=2.0, fair3=1.0), DECISIVE), **scan),  # λ-H written
            dict(row(dict(ERRORS, fair=2.0, fair3=1.0), FAIR2), kind="organic", radius_h=3)]
    text = study.screen(rows)
    assert text.startswith("2 scan holes where fair2 is written: fair3 1.5x closer on 1, "
                           "fair2 1.5x closer on 1")
    assert "| radius / sigma |" in text


def test_kept_signals_of_a_row():
    """Session 42's signals of a kept λ-H fill, read from its row's evidence (nan where a test
    did not score it)."""
    ev = evidence({"fair2": 1.0, "fair3": 0.5, "conformal": 0.25},
                  {"fair2": 1.0, "fair3": 2.0, "conformal": 1.0},
                  adv2={"hidden": {"conformal": (0.75, 0.25)}},
                  adv3={"hidden": {"conformal": (0.25, 0.125)},
                        "sibling": {"conformal": (-1.0, 0.5)}},
                  n_edges=52, sigma=0.2, edge=0.5, p_curvature=1e-3, fair23_rms=0.1)
    s = study.kept_signals({"evidence": ev})
    assert s["t hidden λ-H over fair2"] == pytest.approx(3.0)
    assert s["t hidden λ-H over fair3"] == pytest.approx(2.0)
    assert np.isnan(s["t siblings λ-H over fair2"])
    assert s["t siblings λ-H over fair3"] == pytest.approx(-2.0)
    assert s["hidden λ-H / better faired"] == pytest.approx(0.5)
    assert s["siblings λ-H / better faired"] == pytest.approx(1.0)
    assert s["log hidden / siblings ratio"] == pytest.approx(np.log(0.5))
    assert s["failed on the hidden rings"] == 0.0
    assert s["boundary edges"] == 52.0 and s["log10 p curvature"] == pytest.approx(-3.0)
    assert s["sigma / edge"] == pytest.approx(0.4)
    assert s["fair2-fair3 rms / edge"] == pytest.approx(0.2)
    failed = study.kept_signals({"evidence": evidence({"fair2": 1.0, "conformal": np.inf})})
    assert failed["failed on the hidden rings"] == 1.0
    assert np.isnan(failed["hidden λ-H / better faired"])


def test_screen_kept_reads_only_kept_lambda_h_fills():
    # DECISIVE keeps the λ-H fill; a veto writes fair2 (the library's faired fill without it)
    lost = row(dict(ERRORS, fair=1.0, conformal=2.0, conformal_raw=2.0), dict(DECISIVE,
                                                                             n_edges=60))
    won = row(dict(ERRORS, fair=2.0, conformal=0.5), dict(DECISIVE, n_edges=20))
    not_kept = row(dict(ERRORS, fair=1.0, conformal=1.0), dict(FAIR2, n_edges=70))
    text = study.screen_kept([lost, won, not_kept])
    assert text.startswith("2 holes where the λ-H fill is kept: 1.5x farther than the faired "
                           "fill a veto writes on 1, 1.5x closer on 1")
    assert "| boundary edges | >= 60 | 1 | 1 | 0 |" in text


def test_a_manifest_instead_of_a_set(monkeypatch, tmp_path):
    """``--manifest`` runs a holes manifest's holes as a set named after the file, and
    ``--holes`` limits the run to the listed holes."""
    calls = []
    monkeypatch.setattr(study, "run", lambda *a: calls.append(a))
    monkeypatch.setattr(study, "SETS", dict(study.SETS))
    manifest = tmp_path / "holdout17_manifest.json"
    study.main(["--manifest", str(manifest), "--holes", "penguin#3,mouse#6",
                "--out", str(tmp_path / "o.jsonl")])
    which, out, samples, meshes, holes = calls[0]
    assert which == "holdout17" and study.SETS["holdout17"] == manifest
    assert holes == {"penguin#3", "mouse#6"} and meshes == ["mouse", "penguin"]
