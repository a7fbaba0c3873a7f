"""Selection rules that read more evidence than the old self-check gathered, replayed on the
tuning half (docs/selfcheck.md, session 10): each sibling hole's own scores and more of them
(``selfcheck_evidence.py``: 6 siblings, 1 to 3 hidden rings), and the candidates' stability on
the hole itself (``selfcheck_stability.py``), joined to the score table of
``selfcheck_table.py`` (true errors, the default two tests), with the measures of
``selfcheck_replay.py``.

    python benchmarks/selfcheck_table.py --split tuning --cache /tmp/scores.jsonl
    python benchmarks/selfcheck_evidence.py --split tuning --cache /tmp/evidence.jsonl
    python benchmarks/selfcheck_stability.py --split tuning --cache /tmp/stability.jsonl
    python benchmarks/selfcheck_evidence_replay.py --scores /tmp/scores.jsonl \\
        --evidence /tmp/evidence.jsonl --stability /tmp/stability.jsonl \\
        --baseline /work/bench_baseline/s10_combined.json.partial.jsonl --split tuning

``--baseline``: CGAL's error per hole from a ``validation.py`` run (the score table's own
column when it was built without one). Session 10's candidate rule is "veto 2 × fair3,
faired vote" (built as ``selection.choose(..., each=)`` on branch s10chooser-rule, not the
default: docs/selfcheck.md); ``--check ROWS`` compares a ``validation.py`` run of a default
with it, hole by hole.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import selfcheck_replay as rp  # noqa: E402
import selfcheck_table  # noqa: E402
import validation  # noqa: E402

from surfinpaint.fill.selfcheck import mean_scores  # noqa: E402


def joined(scores, evidence, stability, baseline, split) -> list[dict]:
    """The score table's rows of ``split`` with their evidence (and CGAL's error)."""
    ev = {(r["mesh"], r["hole"]): r for r in selfcheck_table.read_cache(Path(evidence))}
    st = {} if not stability else {(r["mesh"], r["hole"]): r["stability"] for r in
                                   selfcheck_table.read_cache(Path(stability))}
    base = selfcheck_table.baseline_errors(Path(baseline)) if baseline else {}
    rows = [r for r in selfcheck_table.read_cache(Path(scores)) if r["split"] == split]
    for r in rows:
        key = (r["mesh"], r["hole"])
        r["by_rings"] = ev[key]["hidden_by_rings"]
        r["each"] = [s for s in ev[key]["siblings_each"] if s]
        r["stability"] = st.get(key, {})
        if base:
            r["cgal"] = base.get(("cgal", *key), float("nan"))
    return rows


def test_holes(r, hide=("2",), siblings=6) -> list[dict]:
    """The scores of each test hole (λ-H left out where it failed there)."""
    return ([rp._said(r["by_rings"][k]) for k in hide if r["by_rings"].get(k)] +
            [rp._said(s) for s in r["each"][:siblings]])


def _mean(r, siblings):
    return mean_scores(r["each"][:siblings])


def faired_vote(r, fallback, **kw) -> str:
    """fair3 or fair2 by the majority of the test holes (a tie in a hole: fair2; a tie of
    the votes: ``fallback``)."""
    votes = sum(1 if t["fair3"] < t["fair2"] else -1 for t in test_holes(r, **kw)
                if "fair2" in t and "fair3" in t)
    return fallback if votes == 0 else "fair3" if votes > 0 else "fair2"


def vetoed(r, veto, against="fair3", **kw) -> bool:
    """On some test hole the λ-H fill is more than ``veto`` × ``against``'s score."""
    return any("conformal" in t and against in t and t[against] > 0 and
               t["conformal"] > veto * t[against] for t in test_holes(r, **kw))


def rule(veto=None, vote=True, against="fair3", hide=("2",), siblings=6, mean=6):
    """The old rule on the hidden rings and the mean of the first ``mean`` siblings, the
    faired fill by a vote of the test holes, and the λ-H fill vetoed above ``veto``."""
    kw = {"hide": hide, "siblings": siblings}

    def chooser(r):
        pick, faired = rp.rule_before({**r, "sibling": _mean(r, mean)})
        faired = faired_vote(r, faired, **kw) if vote else faired
        if pick == "conformal" and veto and vetoed(r, veto, against, **kw):
            return faired, faired
        return (pick if pick == "conformal" else faired), faired
    return chooser


def rule_stability(k, margin):
    """The old rule, the λ-H fill vetoed where its fill of the hole moves more than
    ``margin`` × the steadier faired fill's when ``k`` more rings are hidden."""
    def chooser(r):
        pick, faired = rp.rule_before(r)
        s = r["stability"].get(k, {})
        if pick == "conformal" and s and math.isfinite(s.get("conformal", math.inf)) and \
                s["conformal"] > margin * min(s["fair2"], s["fair3"]):
            return faired, faired
        return pick, faired
    return chooser


def rules() -> dict:
    out = {"before (main 590a9d8)": rp.rule_before,
           "6 siblings' mean, no veto, no vote": rule(vote=False),
           "faired vote: hidden + 6 siblings": rule(),
           "faired vote: hidden 1-3 rings + 2 siblings": rule(hide=("1", "2", "3"),
                                                               siblings=2, mean=2),
           "faired vote: hidden 1-2 rings + 2 siblings": rule(hide=("1", "2"), siblings=2,
                                                               mean=2)}
    for veto in (1.5, 2.0, 2.5, 3.0, 4.0):
        out[f"veto {veto:g} × fair3, faired vote"] = rule(veto)
    out["veto 2 × fair3, no vote"] = rule(2.0, vote=False)
    out["veto 2 × fair3, first 2 siblings only"] = rule(2.0, siblings=2, mean=2)
    out["veto 2 × fair3, mean of 2 for the old rule"] = rule(2.0, mean=2)
    out["veto 2 × fair2, faired vote"] = rule(2.0, against="fair2")
    out["veto 2 × fair3, hidden 1-3 rings + 6 siblings"] = rule(2.0, hide=("1", "2", "3"))
    for k, margin in (("1", 1.0), ("1", 1.5), ("2", 1.5)):
        out[f"stability veto: {k} ring(s), {margin:g} × steadier faired"] = \
            rule_stability(k, margin)
    return out


def check(rows, run_rows) -> str:
    """Holes where a ``validation.py`` run's default differs from the replay of "veto 2 ×
    fair3, faired vote" by more than 1 %."""
    got = validation._errors([json.loads(line) for line in Path(run_rows).read_text()
                              .splitlines() if line.strip()])
    out = []
    for r, c in zip(rows, rp.chosen_errors(rows, rule(2.0)), strict=True):
        g = got.get(("conformal", r["mesh"], r["hole"]))
        if g is None or abs(g - c) > 0.01 * abs(c) + 1e-9:
            out.append(f"{r['mesh']} #{r['hole']}: replay {c:.4g}, run {g}")
    return f"{len(rows) - len(out)} of {len(rows)} holes as replayed\n" + "\n".join(out)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scores", required=True)
    parser.add_argument("--evidence", required=True)
    parser.add_argument("--stability", default=None)
    parser.add_argument("--baseline", default=None)
    parser.add_argument("--split", default="tuning")
    parser.add_argument("--above", default=None, help="list the holes above 1.3× the "
                        "better faired fill for this rule (a label of the table)")
    parser.add_argument("--check", default=None, help="a validation.py run's rows")
    args = parser.parse_args(argv)
    rows = joined(args.scores, args.evidence, args.stability, args.baseline, args.split)
    print(f"{args.split}: {len(rows)} holes\n")
    table = rules()
    if not args.stability:
        table = {k: v for k, v in table.items() if not k.startswith("stability")}
    print(rp.replay(rows, table))
    if args.above:
        print("\n" + rp.holes_above(rows, table[args.above], limit=1.3))
    if args.check:
        print("\n" + check(rows, args.check))
    return rows


if __name__ == "__main__":
    np.seterr(all="ignore")
    main()
