"""The replay of self-check rules on the validation benchmark's score table
(``benchmarks/selfcheck_replay.py``): its measures on a hand-made table whose numbers are
worked out below, and how a replayed choice is turned into an error. No mesh is loaded."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
replay = pytest.importorskip("selfcheck_replay")

INF = np.inf


def row(mesh, hole, fair2, fair3, conformal, cgal, hidden=None, sibling=None, **extra):
    return {"mesh": mesh, "hole": hole, "true": {"fair2": fair2, "fair3": fair3,
                                                 "conformal": conformal},
            "cgal": cgal, "hidden": hidden or {}, "sibling": sibling or {},
            "crossed": False, **extra}


# two meshes, two holes each; the chosen errors are given, not replayed
ROWS = [row("a", 0, 1.0, 2.0, 0.5, 1.0), row("a", 1, 1.0, 1.0, 1.0, 2.0),
        row("b", 0, 1.0, 0.5, 2.0, 4.0), row("b", 1, 2.0, 1.0, 1.0, 1.0)]
CHOSEN = [0.5, 1.0, 2.0, 1.0]


def test_measures_of_a_hand_made_table():
    m = replay.measures(ROWS, CHOSEN)
    # chosen / CGAL per hole: 0.5, 0.5, 0.5, 1.0
    assert m["over_cgal"] == pytest.approx(0.5)
    # mesh medians: a: chosen 0.75 / fair2 1.0; b: chosen 1.5 / fair2 1.5
    assert m["worst_mesh"] == ("b", pytest.approx(1.0))
    assert m["meshes_above_1.1"] == 0
    # chosen / min(fair2, fair3): 0.5, 1.0, 4.0, 1.0
    assert m["worst_hole"] == ("b #0", pytest.approx(4.0))
    assert m["above_1.5"] == ["b #0"]
    # best candidate: 0.5, 1.0, 0.5, 1.0 -> regret 1, 1, 4, 1
    assert m["pick_best"] == pytest.approx(0.75) and m["n"] == 4
    assert m["regret"] == pytest.approx(1.0)
    assert m["mean_log_regret"] == pytest.approx(np.log(4.0) / 4)


def test_the_ceiling_is_the_best_candidate():
    assert replay.chosen_errors(ROWS, None) == [0.5, 1.0, 0.5, 1.0]


def test_a_kept_lambda_h_fill_that_fails_on_the_hole_writes_the_faired_fill():
    failed = [row("a", 0, 1.0, 0.8, INF, 1.0, hidden={"fair2": 1, "fair3": 2,
                                                       "conformal": 0.1})]
    # the old rule keeps the λ-H fill (decisive on the hidden rings) with fair2 behind it
    assert replay.rule_before(failed[0]) == ("conformal", "fair2")
    assert replay.chosen_errors(failed, replay.rule_before) == [1.0]


def test_a_failure_on_a_test_hole_says_nothing():
    lost_there = row("a", 0, 1, 1, 1, 1, hidden={"fair2": 1, "fair3": 1, "conformal": INF},
                     sibling={"fair2": 1, "fair3": 1.2, "conformal": 0.9})
    assert replay.rule_before(lost_there)[0] == "conformal"  # the siblings decide
    assert replay.rule_argmin_hidden(lost_there)[0] == "conformal"  # the siblings decide


def test_three_way_measures_against_the_faired_fill_the_tests_pick():
    # λ-H beats fair2 on both tests but loses both to fair3, which beats fair2
    r = row("a", 0, 1, 1, 1, 1, hidden={"fair2": 1, "fair3": 0.6, "conformal": 0.8},
            sibling={"fair2": 1, "fair3": 0.7, "conformal": 0.9})
    assert replay.rule_before(r) == ("conformal", "fair3")
    assert replay.rule_three_way(r) == ("fair3", "fair3")


def test_the_grown_patch_guard():
    r = row("a", 0, 1, 1, 1, 1, hidden={"fair2": 1, "fair3": 1.2, "conformal": 0.3})
    guarded = replay.RULES["before + grown guard"]
    assert guarded({**r, "grown": False})[0] == "conformal"
    assert guarded({**r, "grown": True}) == ("fair2", "fair2")


def test_the_library_row_replays_choose():
    # the library's rule, siblings left out where sibling_test_plan skips them
    r = row("a", 0, 1, 1, 1, 1, hidden={"fair2": 1, "fair3": 1.2, "conformal": 0.8},
            sibling={"fair2": 1, "fair3": 1.2, "conformal": 1.1})
    assert replay.rule_library(r) == ("fair2", "fair2")  # lost the siblings
    r["hidden"]["conformal"] = 0.4  # decisive: the siblings are not run
    assert replay.rule_library(r) == ("conformal", "fair2")


def test_the_scans_default_point_is_the_old_rule():
    rows = [row("a", 0, 1, 1, 1, 1, hidden=h, sibling=s) for h, s in (
        ({"fair2": 1, "fair3": 1.2, "conformal": 0.8}, {"fair2": 1, "fair3": 1, "conformal": 1}),
        ({"fair2": 1, "fair3": 1.2, "conformal": 0.8}, {"fair2": 1, "fair3": 1, "conformal": 1.1}),
        ({"fair2": 1, "fair3": 1.2, "conformal": 0.4}, {"fair2": 1, "fair3": 1, "conformal": 2}),
        ({"fair2": 1, "fair3": 0.8, "conformal": 1.1}, {"fair2": 1, "fair3": 0.9}),
        ({}, {"fair2": 1, "fair3": 1, "conformal": 0.9}),
        ({"fair2": 1, "fair3": 1, "conformal": INF}, {"fair2": 1, "fair3": 1, "conformal": 1}))]
    default = replay.margin_rule()
    picks = [default(r) for r in rows]
    assert picks == [replay.rule_before(r) for r in rows]
    assert [p for p, _ in picks] == ["conformal", "fair2", "conformal", "fair3", "conformal",
                                     "fair2"]
    # a stricter sibling tolerance turns the sibling tie into a loss
    assert replay.margin_rule(sibling_tolerance=0.9)(rows[0])[0] == "fair2"


def test_changed_holes_lists_the_holes_whose_written_fill_moved():
    # the same two holes, tested twice: on the second table the first hole's hidden-ring
    # test speaks (the λ-H fill wins decisively), the second's scores are the same
    scores = {"fair2": 1.0, "fair3": 2.0, "conformal": 0.1}
    before = [row("a", 0, 1.0, 2.0, 4.0, 1.0), row("a", 1, 1.0, 2.0, 0.5, 1.0, hidden=scores)]
    after = [row("a", 0, 1.0, 2.0, 4.0, 1.0, hidden=scores, siblings_found=0),
             row("a", 1, 1.0, 2.0, 0.5, 1.0, hidden=scores)]
    text = replay.changed_holes(before, after, replay.rule_library)
    lines = [line for line in text.splitlines() if line.startswith("| a #")]
    # no test before: fair2 (1.0); after: the λ-H fill (4.0), 4× the better faired fill
    assert lines == ["| a #0 | 1 | 2 | 4 | fair2 1 | conformal 4 | 4.00 | 4.00 | fair2 1, "
                     "fair3 2, conformal 0.1 | — (0) |"]
    # geometric mean of 4 and 1
    assert text.endswith("2 holes, 1 changed; after / before: geometric mean 2.000, better "
                         "by 10 % 0, worse by 10 % 1")
