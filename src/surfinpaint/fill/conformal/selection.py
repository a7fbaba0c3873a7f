"""The self-check's rule: keep the λ-H fill or write a faired fill, from truth-free test
scores (method.md §8, "an honest safety net"; measured in benchmarks/selfcheck_rules.py on the
old accuracy set, and replayed against three-way, argmin and guarded rules on the validation
benchmark's tuning half in benchmarks/selfcheck_replay.py: none did better, docs/selfcheck.md).

Both functions are pure: scores in, decision out. The scores are those of
:func:`surfinpaint.fill.selfcheck.hidden_ring_scores` (the rings of known surface around the
hole, hidden and predicted again) and :func:`surfinpaint.fill.selfcheck.sibling_scores`
(holes as wide as it cut from the known surface nearby): candidate name (``"conformal"``,
``"fair2"``, ``"fair3"``) -> mean distance to the removed surface, infinite where the
candidate failed; an empty dict when the test could not run.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace

import numpy as np

__all__ = ["DECISIVE", "Verdict", "choose", "demoted", "fair3_over_lambda_h",
           "hidden_rings_shallower", "sibling_test_plan"]

# a λ-H fill this many times closer than the faired fill on the hidden rings is kept
# without the sibling test (on the benchmark the sibling test never overturned one)
DECISIVE = 0.5

Scores = Mapping[str, float]

# the candidates as the report names them (app/fill_report.py, docs/report.md)
CANDIDATE_WORDS = {"fair2": "bilaplacian", "fair3": "trilaplacian", "conformal": "λ-H"}


@dataclass(frozen=True)
class Verdict:
    """The self-check's decision for one hole.

    Attributes
    ----------
    keep : bool
        Keep the λ-H fill (when it can be made and passes its checks).
    make : bool
        Make the λ-H fill of the hole: when kept, or when it failed on a test hole (whether
        it fails on this hole too is then what the report must say).
    faired : str
        The faired fill to write otherwise: ``"fair2"``, ``"fair3"`` (or the one asked for).
    reference : str
        The faired fill the λ-H fill was measured against.
    hidden, sibling : dict
        The scores of the two tests (empty: not run).
    lost : tuple of str
        The tests the λ-H fill did not pass ("hidden rings", "sibling holes").
    scores : str
        The scores in words (with the reason when no test could speak).
    """

    keep: bool
    make: bool
    faired: str
    reference: str
    hidden: dict = field(default_factory=dict)
    sibling: dict = field(default_factory=dict)
    lost: tuple[str, ...] = ()
    scores: str = ""

    @property
    def tests(self) -> dict[str, dict]:
        """The tests that ran, by name, in the order they ran."""
        return {name: s for name, s in (("hidden rings", self.hidden),
                                        ("sibling holes", self.sibling)) if s}

    def sentence(self, *, kept: bool, failed: bool, fair_order: int | None = None) -> str:
        """The verdict in words, once the λ-H fill was kept, or a faired fill of
        ``fair_order`` written (``failed``: because the λ-H fill failed on this hole)."""
        if kept:
            return f"self-check kept the λ-H fill ({self.scores})"
        which = f"the faired fill (order {fair_order})"
        if failed:
            return f"the λ-H fill failed, used {which} ({self.scores})"
        if not self.tests:
            return f"self-check not possible here, kept {which}"
        return f"self-check ({', '.join(self.lost)}) preferred {which} ({self.scores})"


def _beats(scores: Scores, name: str, other: str) -> bool:
    return name in scores and scores[name] < scores[other]


def _holds(scores: Scores, name: str, other: str) -> bool:
    # a tie is not a loss: on sibling holes too small for inner vertices every fill is the
    # same triangulation
    return name in scores and scores[name] <= scores[other]


def _wins(hidden: Scores, sibling: Scores, name: str, other: str) -> bool:
    """Wins the hidden-ring test and does not lose the sibling test; without the former,
    must win the latter."""
    if hidden:
        return _beats(hidden, name, other) and (not sibling or _holds(sibling, name, other))
    return bool(sibling) and _beats(sibling, name, other)


def _said(scores: Scores) -> Scores:
    """The scores of a test, or none when the λ-H fill failed on its hole: a λ-H fill that
    fails on a test hole says nothing about how it fills this one (it fails on the enlarged
    hole of folded brain patches, measured), and the other test decides."""
    return scores if np.isfinite(scores.get("conformal", 0.0)) else {}


def _decisive(hidden_lh: Scores, reference: str) -> bool:
    return "conformal" in hidden_lh and hidden_lh["conformal"] < DECISIVE * hidden_lh[reference]


def sibling_test_plan(hidden: Scores, *, reference: str = "fair2",
                      choose_faired: bool = True, shallower: bool = False
                      ) -> tuple[bool, bool]:
    """Whether the (costly) sibling test is run after the hidden-ring test, and with the
    λ-H candidate: only when it can still change the outcome.

    Parameters
    ----------
    hidden : dict
        The hidden-ring scores.
    reference : str
        The faired fill the λ-H fill is measured against.
    choose_faired : bool
        The faired fill is chosen between "fair2" and "fair3" by the tests too.
    shallower : bool
        The hidden-ring scores are those of the shallower test (:func:`hidden_rings_shallower`):
        the faired fill is then the reference whatever the siblings say.

    Returns
    -------
    run : bool
    with_lambda_h : bool
        The λ-H fill is still in the race (else only the faired fills are scored).
    """
    hidden_lh = _said(hidden)
    racing = not hidden_lh or _beats(hidden_lh, "conformal", reference)
    faired_racing = (choose_faired and not shallower
                     and (not hidden or _beats(hidden, "fair3", "fair2")))
    return (racing or faired_racing) and not _decisive(hidden_lh, reference), racing


def choose(hidden_scores: Scores, sibling_scores: Scores, *, reference: str = "fair2",
           choose_faired: bool = True, crossed: bool = False,
           shallower: bool = False) -> Verdict:
    """Keep the λ-H fill or a faired fill, from the two tests' scores.

    The λ-H fill is kept when it beats ``reference`` on the hidden-ring test and does not
    lose the sibling test (a tie is not a loss); without a hidden-ring test it must win the
    sibling test; with less than ``DECISIVE`` times the reference's hidden-ring error it is
    kept whatever the siblings say. A test whose hole the λ-H fill failed on says nothing.
    A hole ``crossed`` by a crease where no test hole could speak keeps its crease fill
    (the two straight sharp chains that meet across the hole are the evidence). Otherwise
    the faired fill is ``"fair3"`` if it passes the same tests against ``"fair2"``
    (``choose_faired``), else ``"fair2"``, or ``reference`` when not ``choose_faired``.

    Parameters
    ----------
    hidden_scores, sibling_scores : dict
        Candidate name -> score (lower is better; inf: failed there); empty: not run.
    reference : str
        The faired fill the λ-H fill is measured against (the bilaplacian one unless a
        fairing order is asked for).
    choose_faired : bool
        Choose the faired fill between "fair2" and "fair3"; False: ``reference``.
    crossed : bool
        A crease crosses the hole.
    shallower : bool
        ``hidden_scores`` are those of the hidden-ring test one ring shallower, run because
        the deeper test's enlarged hole met a crease that the hole does not have
        (:func:`hidden_rings_shallower`): they decide on the λ-H fill as above, but the
        faired fill written otherwise is ``reference``. Neither test ranks fair2 against
        fair3 there: the deeper one ranks how they round the crease, and the one-ring band
        is thin (docs/selfcheck.md, session 31, "one ring shallower").

    Returns
    -------
    Verdict
    """
    hidden, sibling = dict(hidden_scores), dict(sibling_scores)
    hidden_lh, sibling_lh = _said(hidden), _said(sibling)
    tests = {name: s for name, s in (("hidden rings", hidden), ("sibling holes", sibling))
             if s}
    scores = "; ".join(f"{name}: " + ", ".join(f"{CANDIDATE_WORDS.get(k, k)} {v:.3g}"
                                               for k, v in s.items())
                       for name, s in tests.items()) or "no test could be run here"
    keep = _decisive(hidden_lh, reference) or _wins(hidden_lh, sibling_lh, "conformal",
                                                    reference)
    if crossed and not hidden_lh and not sibling_lh:
        keep = True
        scores += "; no test hole is crossed by the crease, the crease fill is kept"
    if shallower and choose_faired and hidden:
        scores += "; hidden rings one ring shallower (the deeper ones met a crease the hole " \
                  "does not have), the faired fill not chosen by them"
    if not choose_faired or (shallower and hidden):
        faired = reference
    elif hidden and _wins(hidden, sibling, "fair3", "fair2"):
        faired = "fair3"
    else:
        faired = "fair2"
    lost = tuple(name for name, s in tests.items()
                 if not (_holds if name == "sibling holes" and hidden else _beats)(
                     s, "conformal", reference))
    failed_on_a_test = any(np.isinf(s.get("conformal", 0.0)) for s in tests.values())
    return Verdict(keep=keep, make=keep or failed_on_a_test, faired=faired,
                   reference=reference, hidden=hidden, sibling=sibling, lost=lost,
                   scores=scores)


def hidden_rings_shallower(test_crease: bool, *, crossed: bool, hide_rings: int) -> bool:
    """Whether the hidden-ring test is run again one ring shallower: where its λ-H fill was
    a crease fill (``test_crease``) though no crease crosses the hole (``crossed`` False),
    the test's enlarged hole met a crease of the surface beside the hole, and its λ-H fill
    there says how well the crease fill rebuilds that crease, not how well the smooth λ-H
    fill the hole gets fits its own face. Its scores then stand only where the shallower
    test cannot score (:func:`choose`'s ``shallower`` otherwise).

    Measured on the tuning side (docs/selfcheck.md, session 31): on 114 holes cut on curved
    faces beside a sharp edge, 21 such holes: 14 better and 4 worse; none of the 196
    benchmark holes, the extra scans, the λ-H families, the animals or the flat holes
    beside an edge changed.

    Examples
    --------
    >>> hidden_rings_shallower(True, crossed=False, hide_rings=2)
    True
    >>> hidden_rings_shallower(True, crossed=True, hide_rings=2)  # the crease is the hole's
    False
    >>> hidden_rings_shallower(True, crossed=False, hide_rings=1)  # none shallower
    False
    """
    return bool(test_crease) and not crossed and hide_rings > 1


def demoted(verdict: Verdict, advantages: Mapping[str, Mapping[str, tuple[float, float]]],
            z: float, *, crossed: bool = False) -> Verdict:
    """The verdict with a choice other than the reference kept only where the test that
    decided it sees it closer than the reference by more than ``z`` standard errors
    (opt-in, ``ConformalOptions.significance``; docs/selfcheck.md, session 26).

    A kept λ-H fill is weighed in the hidden-ring test (the sibling test where the
    hidden-ring test says nothing for it); if its advantage there is not significant the
    faired choice is written instead; fair3 is weighed in the hidden-ring test, and if not
    significant the reference is written. A crease fill kept where no test spoke is left.

    Parameters
    ----------
    verdict : Verdict
        :func:`choose`'s.
    advantages : dict
        ``{"hidden": {name: (advantage, standard error)}, "sibling": {...}}`` over the
        reference (:func:`surfinpaint.fill.selfcheck.advantages_over`).
    z : float
        Standard errors an advantage must exceed.
    crossed : bool
        A crease crosses the hole (as for :func:`choose`).

    Returns
    -------
    Verdict
    """

    def significant(name: str, test: str) -> bool:
        adv, se = advantages.get(test, {}).get(name, (np.nan, np.inf))
        return bool(adv > z * se)

    keep, faired = verdict.keep, verdict.faired
    hidden_lh, sibling_lh = _said(verdict.hidden), _said(verdict.sibling)
    if keep and not (crossed and not hidden_lh and not sibling_lh):
        keep = significant("conformal", "hidden" if hidden_lh else "sibling")
    if faired == "fair3" and verdict.reference == "fair2" and not significant("fair3",
                                                                             "hidden"):
        faired = verdict.reference
    if (keep, faired) == (verdict.keep, verdict.faired):
        return verdict
    failed_on_a_test = any(np.isinf(s.get("conformal", 0.0)) for s in verdict.tests.values())
    return replace(verdict, keep=keep, make=keep or failed_on_a_test, faired=faired,
                   scores=verdict.scores + f"; not significant at {z:g} standard errors, "
                   f"{'the λ-H fill' if verdict.keep and not keep else 'fair3'} not kept")


def fair3_over_lambda_h(verdict: Verdict, ratio: float, *, shallower: bool = False,
                        crossed: bool = False) -> Verdict:
    """The verdict with a kept λ-H fill given up for fair3 where the hidden-ring test does
    not rank it clearly ahead of fair3: its score there at least ``ratio`` times fair3's
    (opt-in, ``ConformalOptions.lambda_h_over_fair3``; docs/candidates.md, "Session 52
    (helper): cortex holes").

    :func:`choose` measures the λ-H fill against fair2 only; on folded cortices fair3 is
    the closer fill on most holes where the hidden rings score it level with the λ-H fill
    or ahead. Left as it is: a verdict that does not keep the λ-H fill, one measured
    against another reference than fair2 (a fairing order asked for), hidden-ring scores
    of the shallower test (which rank no faired fill, :func:`choose`) or a test the λ-H
    fill failed on, and a hole a crease crosses (its λ-H fill is the crease fill).

    Parameters
    ----------
    verdict : Verdict
        :func:`choose`'s (after :func:`demoted`).
    ratio : float
        The λ-H fill's hidden-ring score must stay below this many times fair3's.
    shallower, crossed : bool
        As for :func:`choose`.

    Returns
    -------
    Verdict

    Examples
    --------
    >>> kept = choose({"fair2": 2.0, "fair3": 1.0, "conformal": 0.9}, {})
    >>> fair3_over_lambda_h(kept, 1.05).keep   # 0.9 < 1.05 x 1.0: kept
    True
    >>> v = fair3_over_lambda_h(kept, 0.8)     # 0.9 >= 0.8 x 1.0: fair3 written
    >>> v.keep, v.faired
    (False, 'fair3')
    """
    hidden = _said(verdict.hidden)
    if (not verdict.keep or shallower or crossed or verdict.reference != "fair2"
            or "fair3" not in hidden or "conformal" not in hidden
            or not np.isfinite(hidden["fair3"])
            or hidden["conformal"] < ratio * hidden["fair3"]):
        return verdict
    failed_on_a_test = any(np.isinf(s.get("conformal", 0.0)) for s in verdict.tests.values())
    return replace(verdict, keep=False, make=failed_on_a_test, faired="fair3",
                   scores=verdict.scores + f"; the λ-H fill not below {ratio:g} × the "
                   "trilaplacian fill's score on the hidden rings, the trilaplacian fill "
                   "written")
