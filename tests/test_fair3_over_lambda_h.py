"""``ConformalOptions.lambda_h_over_fair3``: a kept λ-H fill given up for fair3 where the
hidden rings do not rank it clearly ahead of fair3 (session 52 helper, docs/candidates.md).

The rule is pure (``selection.fair3_over_lambda_h``): a table of score cases pins it; one
fill checks that the option reaches the self-check and that off it nothing changes.
"""

import dataclasses

import numpy as np
import pytest

from surfinpaint import ConformalOptions, fill_holes
from surfinpaint.data import sphere
from surfinpaint.fill.conformal.selection import choose, fair3_over_lambda_h
from surfinpaint.geometry.cutting import cut_geodesic_disk

INF = np.inf


def s(fair2, fair3, conformal):
    return {"fair2": fair2, "fair3": fair3, "conformal": conformal}


# (hidden-ring scores, sibling scores, ratio, keyword arguments, λ-H kept after, faired after)
CASES = {
    "λ-H ahead of fair3 by more than the ratio: kept": (
        s(2.0, 1.0, 0.5), {}, 1.05, {}, True, "fair3"),
    "λ-H level with fair3, within the ratio: kept": (
        s(2.0, 1.0, 1.0), {}, 1.05, {}, True, "fair3"),
    "λ-H level with fair3 at ratio 1: fair3 written": (
        s(2.0, 1.0, 1.0), {}, 1.0, {}, False, "fair3"),
    "λ-H just below the ratio: kept": (s(2.0, 1.0, 1.0499), {}, 1.05, {}, True, "fair3"),
    "λ-H at the ratio: fair3 written": (s(2.0, 1.0, 1.05), {}, 1.05, {}, False, "fair3"),
    "λ-H behind fair3 though ahead of fair2, fair2 choose's fallback: fair3 written": (
        s(1.0, 0.7, 0.9), s(1.0, 1.1, 0.9), 1.05, {}, False, "fair3"),
    "a ratio below 1 gives up λ-H fills ahead of fair3": (
        s(2.0, 1.0, 0.9), {}, 0.8, {}, False, "fair3"),
    "shallower hidden rings: left as it is": (
        s(2.0, 1.0, 1.5), {}, 1.05, {"shallower": True}, True, "fair2"),
    "a crease crosses the hole: left as it is": (
        s(2.0, 1.0, 1.5), {}, 1.05, {"crossed": True}, True, "fair3"),
    "λ-H failed on the hidden-ring hole (kept by the siblings): left as it is": (
        s(2.0, 1.0, INF), s(1.0, 1.2, 0.9), 1.05, {}, True, "fair2"),
    "λ-H not kept: left as it is": (s(1.0, 0.8, 1.1), {}, 1.05, {}, False, "fair3"),
    "no hidden-ring test (kept by the siblings): left as it is": (
        {}, s(1.0, 1.2, 0.9), 1.05, {}, True, "fair2"),
}


@pytest.mark.parametrize("case", list(CASES))
def test_fair3_over_lambda_h(case):
    hidden, sibling, ratio, kwargs, keep, faired = CASES[case]
    shallower = kwargs.get("shallower", False)
    verdict = choose(hidden, sibling, shallower=shallower, crossed=kwargs.get("crossed", False))
    after = fair3_over_lambda_h(verdict, ratio, **kwargs)
    assert (after.keep, after.faired) == (keep, faired), (verdict, after)
    if after is not verdict:  # given up: said so, and the λ-H fill is not made for nothing
        assert verdict.keep and not after.keep and not after.make
        assert "trilaplacian fill written" in after.scores
        assert after.hidden == verdict.hidden and after.sibling == verdict.sibling


def test_the_table_has_both_outcomes_and_every_guard():
    """The cases separate the rule from one that always or never gives the λ-H fill up, and
    each guard has a case that would fire without it."""
    given_up = [CASES[c][4] is False and choose(CASES[c][0], CASES[c][1]).keep for c in CASES]
    assert any(given_up) and not all(given_up)
    for guard in ("shallower", "crossed"):
        case = next(c for c in CASES if guard in CASES[c][3])
        hidden, sibling, ratio, *_ = CASES[case]
        assert not fair3_over_lambda_h(choose(hidden, sibling), ratio).keep


def test_a_fairing_order_asked_for_is_left_as_it_is():
    verdict = choose(s(1.0, 0.8, 0.79), {}, reference="fair3", choose_faired=False)
    assert verdict.keep and fair3_over_lambda_h(verdict, 1.05) is verdict


@pytest.mark.parametrize("value", [0, -1.0, np.nan, np.inf, True, "1.05"])
def test_the_option_is_validated(value):
    with pytest.raises(ValueError, match="lambda_h_over_fair3"):
        ConformalOptions(lambda_h_over_fair3=value)


def test_the_option_defaults_to_off():
    assert ConformalOptions().lambda_h_over_fair3 is None
    assert ConformalOptions(lambda_h_over_fair3=1.05).lambda_h_over_fair3 == 1.05


@pytest.fixture(scope="module")
def sphere_hole():
    v, f = sphere(4)
    return cut_geodesic_disk(v, f, 0, 0.6)


def test_the_option_reaches_the_self_check(sphere_hole):
    """On a sphere the self-check keeps the λ-H fill; asked to keep it only below a
    vanishing multiple of fair3's hidden-ring score it writes fair3, and with a ratio no
    score reaches nothing changes, bit for bit."""
    cut = sphere_hole
    default = fill_holes(cut.vertices, cut.faces)
    assert default.reports[0].method == "conformal"
    options = ConformalOptions()
    never = fill_holes(cut.vertices, cut.faces,
                       options=dataclasses.replace(options, lambda_h_over_fair3=1e9))
    assert np.array_equal(never.vertices, default.vertices)
    assert np.array_equal(never.faces, default.faces)
    always = fill_holes(cut.vertices, cut.faces,
                        options=dataclasses.replace(options, lambda_h_over_fair3=1e-9))
    report = always.reports[0]
    assert report.method != "conformal" and report.fair_order == 3, report
    assert "trilaplacian fill written" in report.note
    assert report.verdict.hidden == default.reports[0].verdict.hidden
