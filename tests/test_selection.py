"""The self-check's rule, pinned by a table of score cases: ``choose`` and
``sibling_test_plan`` are pure, so no fill is needed (and nothing is monkeypatched).

A rule that always keeps the λ-H fill, never does, ignores the sibling test, or lets a failed
test speak fails this table.
"""

import dataclasses

import numpy as np
import pytest

from surfinpaint.fill.conformal import Verdict, choose, sibling_test_plan
from surfinpaint.fill.conformal.selection import DECISIVE, hidden_rings_shallower

INF = np.inf


def s(fair2, fair3, conformal=None):
    """Scores of one test; ``conformal=None``: the λ-H fill was not scored."""
    out = {"fair2": fair2, "fair3": fair3}
    if conformal is not None:
        out["conformal"] = conformal
    return out


# (hidden-ring scores, sibling scores, keep the λ-H fill, make it, faired fill written else)
KEEP_CASES = {
    "wins hidden, wins siblings": (s(1, 1.2, 0.8), s(1, 1.2, 0.9), True, True, "fair2"),
    "wins hidden, ties siblings (a tie is no loss)": (s(1, 1.2, 0.8), s(1, 1.2, 1.0),
                                                      True, True, "fair2"),
    "wins hidden, loses siblings": (s(1, 1.2, 0.8), s(1, 1.2, 1.1), False, False, "fair2"),
    "loses hidden, wins siblings": (s(1, 1.2, 1.1), s(1, 1.2, 0.5), False, False, "fair2"),
    "ties hidden": (s(1, 1.2, 1.0), {}, False, False, "fair2"),
    "wins hidden, siblings not run": (s(1, 1.2, 0.8), {}, True, True, "fair2"),
    "decisive hidden win overrules lost siblings": (s(1, 1.2, 0.4), s(1, 1.2, 2.0),
                                                    True, True, "fair2"),
    "just short of decisive: the siblings decide": (s(1, 1.2, 0.6), s(1, 1.2, 2.0),
                                                    False, False, "fair2"),
    "failed on the sibling holes: the hidden rings decide (win)": (
        s(1, 1.2, 0.8), s(1, 1.2, INF), True, True, "fair2"),
    "failed on the sibling holes: the hidden rings decide (loss)": (
        s(1, 1.2, 1.1), s(1, 1.2, INF), False, True, "fair2"),
    "failed on the hidden-ring hole: the siblings decide (win)": (
        s(1, 1.2, INF), s(1, 1.2, 0.9), True, True, "fair2"),
    "failed on the hidden-ring hole: the siblings decide (tie is not a win)": (
        s(1, 1.2, INF), s(1, 1.2, 1.0), False, True, "fair2"),
    "failed on both: no evidence": (s(1, 1.2, INF), s(1, 1.2, INF), False, True, "fair2"),
    "no hidden test: must win the siblings": ({}, s(1, 1.2, 0.9), True, True, "fair2"),
    "no hidden test: a tie on the siblings is not enough": ({}, s(1, 1.2, 1.0),
                                                            False, False, "fair2"),
    "no test at all": ({}, {}, False, False, "fair2"),
    "trilaplacian passes both tests": (s(1, 0.8, 1.5), s(1, 0.9, 1.5), False, False, "fair3"),
    "trilaplacian loses the siblings": (s(1, 0.8, 1.5), s(1, 1.1, 1.5), False, False, "fair2"),
    "trilaplacian without a hidden-ring test is not chosen": (
        {}, s(1, 0.5, 1.5), False, False, "fair2"),
    "λ-H wins, trilaplacian is the fallback": (s(1, 0.8, 0.7), s(1, 0.9, 0.85),
                                               True, True, "fair3"),
}


@pytest.mark.parametrize("case", list(KEEP_CASES))
def test_choose(case):
    hidden, sibling, keep, make, faired = KEEP_CASES[case]
    verdict = choose(hidden, sibling)
    assert isinstance(verdict, Verdict)
    assert (verdict.keep, verdict.make, verdict.faired) == (keep, make, faired), verdict
    assert verdict.hidden == hidden and verdict.sibling == sibling


def test_the_table_tells_the_rule_from_simpler_ones():
    """The cases separate the rule from rules that always or never keep the λ-H fill, or
    that ignore the sibling test: each of those disagrees with some row."""
    keeps = [KEEP_CASES[c][2] for c in KEEP_CASES]
    assert any(keeps) and not all(keeps)
    ignoring_siblings = [choose(h, {}).keep for h, *_ in KEEP_CASES.values()]
    assert ignoring_siblings != keeps


def test_a_crossed_hole_keeps_its_crease_fill_when_no_test_can_speak():
    for hidden, sibling in ((s(1, 1, INF), s(1, 1, INF)), ({}, {}), (s(1, 1, INF), {})):
        verdict = choose(hidden, sibling, crossed=True)
        assert verdict.keep
        assert "no test hole is crossed by the crease" in verdict.scores
        assert not choose(hidden, sibling).keep
    # a test that speaks still decides for a crossed hole
    assert not choose(s(1, 1, 1.5), s(1, 1, 1.5), crossed=True).keep
    assert choose(s(1, 1, 0.8), {}, crossed=True).keep


def test_a_fairing_order_asked_for_is_the_reference_and_the_fallback():
    hidden = {"fair3": 1.0, "conformal": 0.9}
    verdict = choose(hidden, {"fair3": 1.0, "conformal": 1.1}, reference="fair3",
                     choose_faired=False)
    assert not verdict.keep and verdict.faired == "fair3" and verdict.reference == "fair3"
    assert choose(hidden, {}, reference="fair3", choose_faired=False).keep
    # measured against the bilaplacian fill, not the best faired one
    assert choose(s(1.0, 0.5, 0.8), {}).keep


def test_lost_tests_and_the_sentence():
    verdict = choose(s(1, 1.2, 0.8), s(1, 1.2, 1.1))
    assert verdict.lost == ("sibling holes",)
    # in the report's words (bilaplacian, trilaplacian, λ-H), mesh units
    assert verdict.scores == ("hidden rings: bilaplacian 1, trilaplacian 1.2, λ-H 0.8; "
                              "sibling holes: bilaplacian 1, trilaplacian 1.2, λ-H 1.1")
    text = verdict.sentence(kept=False, failed=False, fair_order=2)
    assert text == ("self-check (sibling holes) preferred the faired fill (order 2) "
                    f"({verdict.scores})")
    assert verdict.sentence(kept=True, failed=False).startswith("self-check kept the "
                                                                "λ-H fill (")
    assert verdict.sentence(kept=False, failed=True, fair_order=3).startswith(
        "the λ-H fill failed, used the faired fill (order 3)")
    # a hidden-ring loss is a loss; a sibling tie after a hidden-ring test is not
    assert choose(s(1, 1, 1.2), s(1, 1, 1.0)).lost == ("hidden rings",)
    nothing = choose({}, {})
    assert nothing.scores == "no test could be run here" and nothing.tests == {}
    assert nothing.sentence(kept=False, failed=False, fair_order=2) == \
        "self-check not possible here, kept the faired fill (order 2)"


def test_verdict_is_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        choose({}, {}).keep = True


# (hidden-ring scores, choose_faired, run the sibling test, with the λ-H candidate)
PLAN_CASES = {
    "λ-H ahead, not decisive": (s(1, 1.2, 0.8), True, True, True),
    "λ-H decisive": (s(1, 1.2, DECISIVE * 0.99), True, False, True),
    "λ-H behind, trilaplacian ahead": (s(1, 0.8, 1.2), True, True, False),
    "λ-H behind, trilaplacian behind": (s(1, 1.2, 1.2), True, False, False),
    "λ-H behind, order asked for": (s(1, 0.8, 1.2), False, False, False),
    "λ-H failed on the hidden-ring hole": (s(1, 1.2, INF), True, True, True),
    "no hidden-ring test": ({}, True, True, True),
}


@pytest.mark.parametrize("case", list(PLAN_CASES))
def test_sibling_test_plan(case):
    hidden, choose_faired, run, with_lambda_h = PLAN_CASES[case]
    assert sibling_test_plan(hidden, choose_faired=choose_faired) == (run, with_lambda_h)


def test_the_plan_skips_siblings_only_where_they_cannot_change_the_verdict():
    # wherever the plan skips the siblings, any sibling scores give the verdict of none
    siblings = [s(1, 1.2, 0.1), s(1, 1.2, 5.0), s(1, 0.1, 5.0), s(1, 1.2, INF)]
    for hidden, choose_faired, run, with_lambda_h in PLAN_CASES.values():
        reference = "fair2"
        if run:
            continue
        alone = choose(hidden, {}, reference=reference, choose_faired=choose_faired)
        for sibling in siblings:
            if not with_lambda_h:
                sibling = {k: v for k, v in sibling.items() if k != "conformal"}
            verdict = choose(hidden, sibling, reference=reference,
                             choose_faired=choose_faired)
            assert (verdict.keep, verdict.faired) == (alone.keep, alone.faired), (hidden,
                                                                                 sibling)


# the hidden-ring test one ring shallower (its deeper band met a crease the hole lacks):
# (1-ring scores, sibling scores, keep, faired fill written else); the 1-ring scores of
# holes of session 31's curved near-edge set (docs/selfcheck.md), in mesh units
SHALLOWER_CASES = {
    "λ-H loses, trilaplacian ahead: the reference all the same (bracket #1)": (
        s(0.0012, 0.00097, 0.0013), s(0.0069, 0.0059, 0.0045), False, "fair2"),
    "λ-H loses, bilaplacian ahead (shaft #1)": (
        s(0.0018, 0.0020, 0.0028), {}, False, "fair2"),
    "λ-H decisive, trilaplacian ahead (ribplate #12)": (
        s(0.0054, 0.0035, 0.0017), {}, True, "fair2"),
    "λ-H wins and holds the siblings (tee #19)": (
        s(0.0013, 0.00086, 0.00086), s(0.0029, 0.0025, 0.00049), True, "fair2"),
    "trilaplacian passes both tests: the reference all the same": (
        s(1, 0.8, 1.5), s(1, 0.9, 1.5), False, "fair2"),
}


@pytest.mark.parametrize("case", list(SHALLOWER_CASES))
def test_choose_on_shallower_rings(case):
    hidden, sibling, keep, faired = SHALLOWER_CASES[case]
    verdict = choose(hidden, sibling, shallower=True)
    assert (verdict.keep, verdict.faired) == (keep, faired), verdict
    assert "one ring shallower" in verdict.scores
    # the λ-H fill is kept or not as on any hidden-ring scores; only the faired choice moves
    assert choose(hidden, sibling).keep == keep


def test_shallower_rings_leave_an_order_asked_for_and_no_test():
    assert choose(s(1, 0.8, 1.5), {}, reference="fair3", choose_faired=False,
                  shallower=True).faired == "fair3"
    nothing = choose({}, {}, shallower=True)
    assert nothing.faired == "fair2" and nothing.scores == "no test could be run here"


def test_the_table_tells_shallower_rings_from_a_faired_choice_by_them():
    # a rule that ranked fair2 against fair3 on the shallower rings disagrees with a row
    assert any(choose(h, sib).faired != faired
               for h, sib, _, faired in SHALLOWER_CASES.values())


# (the hidden-ring test's λ-H fill a crease fill, the hole crossed, rings hidden) -> rerun
SHALLOWER_WHEN = [
    (True, False, 2, True),    # the enlarged hole met a crease the hole lacks
    (True, True, 2, False),    # the crease crosses the hole: its crease fill is tested
    (False, False, 2, False),  # no crease met
    (False, True, 2, False),
    (True, False, 1, False),   # no shallower test
    (True, False, 3, True),
]


@pytest.mark.parametrize("creased, crossed, rings, rerun", SHALLOWER_WHEN)
def test_hidden_rings_shallower(creased, crossed, rings, rerun):
    assert hidden_rings_shallower(creased, crossed=crossed, hide_rings=rings) is rerun


def test_shallower_rings_skip_siblings_that_could_only_rank_the_faired_fills():
    hidden = s(1, 0.8, 1.2)  # λ-H behind, trilaplacian ahead
    assert sibling_test_plan(hidden) == (True, False)
    assert sibling_test_plan(hidden, shallower=True) == (False, False)
    assert sibling_test_plan(s(1, 1.2, 0.8), shallower=True) == (True, True)
