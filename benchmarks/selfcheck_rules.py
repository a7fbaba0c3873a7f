"""The conformal method's self-check: how well selection rules choose among its candidates.

For every hole of ``accuracy.py``, each candidate fill (``fair2``: bilaplacian fairing, the
baseline; ``fair3``: trilaplacian; ``conformal``: the λ-H fill) is made and scored three
ways: its true error (two-sided mean distance to the removed surface, % of the hole
diameter), the hidden-ring test and the sibling-hole test (:mod:`surfinpaint.fill.selfcheck`,
both always run here, with the same test settings as ``conformal_fill``). Selection rules
are then replayed on these scores; each row is the median and worst ratio of the chosen
fill's true error to the baseline's, over the holes where the baseline is not exact. The
default rule is the library's own (:func:`surfinpaint.fill.conformal.choose`, with the
sibling test left out where :func:`~surfinpaint.fill.conformal.sibling_test_plan` skips it);
the others are the rules it was measured against.

    python benchmarks/selfcheck_rules.py [--cases torus,bunny] [--json scores.json]

The same replay on the validation benchmark's holes, one half at a time, with issue 14's
measures: ``selfcheck_table.py`` (the scores, cached) and ``selfcheck_replay.py``.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import accuracy  # noqa: E402

from surfinpaint.errors import FillError  # noqa: E402
from surfinpaint.fill.conformal import ConformalOptions, choose, sibling_test_plan  # noqa: E402
from surfinpaint.fill.conformal.candidates import Candidates  # noqa: E402
from surfinpaint.fill.conformal.selection import DECISIVE  # noqa: E402
from surfinpaint.fill.selfcheck import hidden_ring_scores, sibling_scores  # noqa: E402
from surfinpaint.geometry.metrics import surface_distance  # noqa: E402

CASES = "bunny,face,pial,white,sphere,torus,cube,snowman,tooth"
INF = float("inf")


def hole_scores(cut) -> dict:
    """The candidates as ``conformal_fill`` makes them with the default options (its test
    holes too), their true errors and both tests' scores."""
    candidates = Candidates.for_hole(cut.vertices, cut.faces, cut.loop, ConformalOptions())
    fills = candidates.faired(cut.vertices, cut.faces, cut.loop)
    s0 = candidates.initial(cut.vertices, cut.faces, cut.loop, fills)
    try:
        fills["conformal"] = candidates.lambda_h(cut.vertices, cut.faces, cut.loop, s0)
    except FillError as exc:
        fills["conformal"] = exc
    true = {}
    for name, fill in fills.items():
        if isinstance(fill, Exception):
            true[name] = INF
            continue
        d = surface_distance(np.vstack([cut.vertices, fill.vertices]), fill.faces,
                             cut.truth_vertices, cut.truth_faces, n_samples=4000)
        true[name] = 100.0 * d.mean / cut.diameter
    tests = candidates.for_tests()
    rings = candidates.options.rings_in_patch
    return {"true": true, "crossed": candidates.crossed,
            "hidden": hidden_ring_scores(cut.vertices, cut.faces, cut.loop, tests,
                                         patch_rings=rings),
            "sibling": sibling_scores(cut.vertices, cut.faces, cut.loop, tests,
                                      patch_rings=rings)}


def _beats(scores, a, b):
    return a in scores and scores[a] < scores[b]


def _holds(scores, a, b):
    return a in scores and scores[a] <= scores[b]


def _wins(hidden, sibling, a, b, tie_holds=False):
    if hidden:
        second = _holds if tie_holds else _beats
        return _beats(hidden, a, b) and (not sibling or second(sibling, a, b))
    return bool(sibling) and _beats(sibling, a, b)


def _faired(h, s, tie_holds=False):
    return "fair3" if h and _wins(h, s, "fair3", "fair2", tie_holds) else "fair2"


def rule_all_faired(h, s):
    """Session 3: the λ-H fill must beat both faired fills on every test that ran."""
    tests = [t for t in (h, s) if t]
    if tests and all(t.get("conformal", INF) <= min(t["fair2"], t["fair3"]) for t in tests):
        return "conformal"
    return _faired(h, s)


def rule_against_bilaplacian(h, s):
    """The λ-H fill against the bilaplacian fill only (win test 1, do not lose test 2)."""
    return "conformal" if _wins(h, s, "conformal", "fair2") else _faired(h, s)


def rule_failed_hidden_says_nothing(h, s):
    """As above, but a λ-H failure on test 1's larger hole leaves test 2 to decide."""
    h_lh = h if np.isfinite(h.get("conformal", 0.0)) else {}
    return "conformal" if _wins(h_lh, s, "conformal", "fair2") else _faired(h, s)


def rule_decisive(h, s):
    """As above, and a test-1 error below DECISIVE × the bilaplacian's wins without
    test 2."""
    h_lh = h if np.isfinite(h.get("conformal", 0.0)) else {}
    if h_lh and h_lh["conformal"] < DECISIVE * h_lh["fair2"]:
        return "conformal"
    return rule_failed_hidden_says_nothing(h, s)


def rule_failed_sibling_says_nothing(h, s, tie_holds=False):
    """As above, and a λ-H failure on a sibling hole says nothing either."""
    h_lh = h if np.isfinite(h.get("conformal", 0.0)) else {}
    s_lh = s if np.isfinite(s.get("conformal", 0.0)) else {}
    if h_lh and h_lh["conformal"] < DECISIVE * h_lh["fair2"]:
        return "conformal"
    if _wins(h_lh, s_lh, "conformal", "fair2", tie_holds):
        return "conformal"
    return _faired(h, s, tie_holds)


def default_verdict(h, s, crossed=False):
    """The library's verdict (``choose``), given the sibling scores it would have computed
    (none where ``sibling_test_plan`` skips the test, no λ-H score where it leaves it out)."""
    run, with_lambda_h = sibling_test_plan(h)
    sibling = {} if not run else s if with_lambda_h else {
        k: v for k, v in s.items() if k != "conformal"}
    return choose(h, sibling, crossed=crossed)


def rule_default(h, s, crossed=False):
    """The default, the library's rule: as above, and a tie on the sibling holes (the same
    fill, as on holes too small for inner vertices) is not a loss; a hole crossed by a
    crease keeps its crease fill when no test hole is crossed (all λ-H test scores are then
    infinite)."""
    verdict = default_verdict(h, s, crossed)
    return "conformal" if verdict.keep else verdict.faired


RULES = {
    "λ-H must beat both faired fills (session 3)": rule_all_faired,
    "λ-H against the bilaplacian fill": rule_against_bilaplacian,
    "… and a failed hidden-ring test says nothing": rule_failed_hidden_says_nothing,
    "… and a decisive hidden-ring win skips the siblings": rule_decisive,
    "… and a failed sibling test says nothing either": rule_failed_sibling_says_nothing,
    "… and a tie on the siblings is not a loss; crease fills kept when no test hole is "
    "crossed (default)": rule_default,
    "always the λ-H fill (select=False)": lambda h, s: "conformal",
    "the best candidate, chosen with the truth (ceiling)": None,
}


def replay(rows: list[dict]) -> str:
    rows = [r for r in rows if r["true"]["fair2"] > 1e-9]
    out = ["| rule | median error / baseline | worst | λ-H written | failed → faired |",
           "|---|---|---|---|---|"]
    for label, rule in RULES.items():
        ratios, written, failed = [], 0, 0
        for r in rows:
            true = r["true"]
            if rule is None:
                pick = min(true, key=true.get)
            elif rule is rule_default:
                pick = rule(r["hidden"], r["sibling"], r.get("crossed", False))
            else:
                pick = rule(r["hidden"], r["sibling"])
            if not np.isfinite(true[pick]):  # the λ-H fill failed on the hole itself
                failed += 1
                pick = (default_verdict(r["hidden"], r["sibling"], r.get("crossed", False))
                        .faired if rule is rule_default else _faired(r["hidden"], r["sibling"]))
            written += pick == "conformal"
            ratios.append(true[pick] / true["fair2"])
        ratios = np.array(ratios)
        out.append(f"| {label} | {np.median(ratios):.3f} | {ratios.max():.3f} | "
                   f"{written} of {len(rows)} | {failed} |")
    return "\n".join(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cases", default=CASES)
    parser.add_argument("--json", help="also write the per-hole scores here")
    args = parser.parse_args()
    rows = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name, k, cut in accuracy.benchmark_cuts(args.cases.split(",")):
            rows.append({"case": name, "hole": k, **hole_scores(cut)})
            print(f"{name} #{k}: " + ", ".join(f"{c} {v:.3g}"
                                               for c, v in rows[-1]["true"].items()),
                  file=sys.stderr, flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    print(replay(rows))


if __name__ == "__main__":
    main()
