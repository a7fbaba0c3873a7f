"""Selection rules replayed on the self-check's score table of the validation benchmark
(``benchmarks/selfcheck_table.py``), with issue 14's measures, one half at a time.

Each rule sees only what the library sees (both tests' scores, whether a crease crosses the
hole, whether the λ-H fill's patch was grown unevenly) and names the fill it writes, and the
faired fill written when the λ-H fill it keeps fails on the hole itself. The measures, over
the half's holes: the per-hole median of the chosen fill's error over CGAL's, the worst mesh
median over the bilaplacian fill's (fair2), the worst hole over the better faired fill, the
holes above 1.5× that, how often the chosen fill is the best candidate (within 1 %) and the
median regret (chosen / best candidate). Rules are chosen on the tuning half only.

    python benchmarks/selfcheck_replay.py --cache /tmp/scores.jsonl --split tuning
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import selfcheck_table  # noqa: E402

from surfinpaint.fill.conformal import choose, sibling_test_plan  # noqa: E402

INF = float("inf")
FAIRED = ("fair2", "fair3")
CANDIDATES = ("fair2", "fair3", "conformal")


# --------------------------------------------------------------------------- helpers


def _said(t: dict) -> dict:
    """A test's scores, without the λ-H fill's where it failed on the test hole (a failure
    there says nothing about this hole)."""
    return t if np.isfinite(t.get("conformal", 0.0)) else {k: v for k, v in t.items()
                                                          if k != "conformal"}


def _beats(t, a, b):
    return a in t and b in t and t[a] < t[b]


def _holds(t, a, b):
    return a in t and b in t and t[a] <= t[b]


def _wins(h, s, a, b):
    """Wins the hidden rings and does not lose the siblings (a tie is no loss); without
    hidden-ring scores of both, must win the siblings."""
    if a in h and b in h:
        return _beats(h, a, b) and (a not in s or b not in s or _holds(s, a, b))
    return _beats(s, a, b)


def _no_test_speaks(h, s):
    return "conformal" not in _said(h) and "conformal" not in _said(s)


def _crossed_keep(row, h, s):
    """A crease fill is kept when no test hole is crossed (the library's rule)."""
    return row["crossed"] and _no_test_speaks(h, s)


# --------------------------------------------------------------------------- rules
# rule(row) -> (fill written, faired fill written if that is the λ-H fill and it fails)


def rule_before(row):
    """main 2a0a2d3: the λ-H fill against the bilaplacian fill (win the hidden rings, do
    not lose the siblings, or < 0.5× on the hidden rings); fair3 if it wins the same tests
    against fair2, else fair2."""
    h, s = row["hidden"], row["sibling"]
    hl, sl = _said(h), _said(s)
    faired = "fair3" if h and _wins(h, s, "fair3", "fair2") else "fair2"
    decisive = "conformal" in hl and hl["conformal"] < 0.5 * hl["fair2"]
    keep = decisive or _wins(hl, sl, "conformal", "fair2") or _crossed_keep(row, h, s)
    return ("conformal" if keep else faired), faired


def rule_library(row):
    """The library's own rule today (``choose``, siblings as ``sibling_test_plan`` runs
    them)."""
    h, s = row["hidden"], row["sibling"]
    run, with_lh = sibling_test_plan(h)
    sib = {} if not run else s if with_lh else {k: v for k, v in s.items()
                                                 if k != "conformal"}
    v = choose(h, sib, crossed=row["crossed"])
    return ("conformal" if v.keep else v.faired), v.faired


def _three_way(row, faired, decisive=0.5):
    h, s = row["hidden"], row["sibling"]
    hl, sl = _said(h), _said(s)
    win = "conformal" in hl and faired in hl and hl["conformal"] < decisive * hl[faired]
    keep = win or _wins(hl, sl, "conformal", faired) or _crossed_keep(row, h, s)
    return ("conformal" if keep else faired), faired


def rule_three_way(row):
    """The λ-H fill against the faired fill the tests pick (fair3 if it wins the tests
    against fair2, else fair2), by the same tests."""
    h, s = row["hidden"], row["sibling"]
    faired = "fair3" if h and _wins(h, s, "fair3", "fair2") else "fair2"
    return _three_way(row, faired)


def rule_three_way_no_decisive(row):
    """As above, without the decisive hidden-ring win (the siblings always heard)."""
    h, s = row["hidden"], row["sibling"]
    faired = "fair3" if h and _wins(h, s, "fair3", "fair2") else "fair2"
    return _three_way(row, faired, decisive=0.0)


def rule_three_way_hidden_faired(row):
    """The λ-H fill against the faired fill with the lower hidden-ring score (siblings
    where no hidden rings), by the same tests."""
    h, s = row["hidden"], row["sibling"]
    t = h if all(f in h for f in FAIRED) else s
    faired = min(FAIRED, key=lambda f: t.get(f, INF)) if t else "fair2"
    return _three_way(row, faired)


def rule_flipped_default(row):
    """As before, but fair2 only where it wins the tests against fair3 (fair3 when they
    are undecided)."""
    h, s = row["hidden"], row["sibling"]
    pick, _ = rule_before(row)
    faired = "fair2" if h and _wins(h, s, "fair2", "fair3") else "fair3"
    return (pick if pick == "conformal" else faired), faired


def rule_three_way_flipped(row):
    """Three-way, with fair3 the faired default when the tests are undecided."""
    h, s = row["hidden"], row["sibling"]
    faired = "fair2" if h and _wins(h, s, "fair2", "fair3") else "fair3"
    return _three_way(row, faired)


def rule_either_test(row):
    """As before, but the λ-H fill is kept when it wins either test against fair2."""
    h, s = row["hidden"], row["sibling"]
    pick, faired = rule_before(row)
    if _beats(_said(h), "conformal", "fair2") or _beats(_said(s), "conformal", "fair2"):
        pick = "conformal"
    return pick, faired


def rule_both_tests(row):
    """As before, but the λ-H fill must win every test that ran against fair2 (a sibling
    tie is a loss, no decisive skip)."""
    h, s = row["hidden"], row["sibling"]
    hl, sl = _said(h), _said(s)
    _, faired = rule_before(row)
    tests = [t for t in (hl, sl) if "conformal" in t]
    keep = (bool(tests) and all(_beats(t, "conformal", "fair2") for t in tests)) or \
        _crossed_keep(row, h, s)
    return ("conformal" if keep else faired), faired


def _argmin(t, names):
    names = [n for n in names if n in t and np.isfinite(t[n])]
    return min(names, key=t.get) if names else None


def _argmin_of(row, first, second):
    """The candidate with the lowest ``first``-test score (the ``second`` test's where the
    first did not run, or where the λ-H fill failed on its hole)."""
    one, other = _said(row[first]), _said(row[second])
    faired = _argmin(one, FAIRED) or _argmin(other, FAIRED) or "fair2"
    t = one if "conformal" in one or "conformal" not in other else other
    pick = _argmin(t, CANDIDATES) or faired
    if _crossed_keep(row, row["hidden"], row["sibling"]):
        pick = "conformal"
    return pick, faired


def rule_argmin_hidden(row):
    """The candidate with the lowest hidden-ring score (siblings where none, or where the
    λ-H fill failed on the hidden-ring hole)."""
    return _argmin_of(row, "hidden", "sibling")


def rule_argmin_hidden_checked(row):
    """The lowest hidden-ring score, unless it loses the siblings to the hidden runner-up
    (then the runner-up)."""
    h, s = _said(row["hidden"]), _said(row["sibling"])
    pick, faired = rule_argmin_hidden(row)
    ranked = sorted((n for n in CANDIDATES if n in h and np.isfinite(h[n])), key=h.get)
    if len(ranked) >= 2 and pick == ranked[0] and _beats(s, ranked[1], ranked[0]):
        pick = ranked[1]
    fr = [n for n in ranked if n in FAIRED]
    if len(fr) == 2 and _beats(s, fr[1], fr[0]):
        faired = fr[1]
    return pick, faired


def rule_argmin_siblings(row):
    """The candidate with the lowest sibling score (hidden rings where none, or where the
    λ-H fill failed on the sibling holes)."""
    return _argmin_of(row, "sibling", "hidden")


def rule_product(row):
    """The lowest product of the two tests' scores relative to each test's best (one test
    alone where the other did not run or the candidate failed there)."""
    h, s = _said(row["hidden"]), _said(row["sibling"])

    def combined(n):
        parts = [t[n] / max(min(t[m] for m in t if np.isfinite(t[m])), 1e-300)
                 for t in (h, s) if n in t and np.isfinite(t[n])]
        # geometric mean, so one test and two are on the same scale
        return float(np.prod(parts) ** (1 / len(parts))) if parts else INF

    faired = min(FAIRED, key=combined)
    pick = min(CANDIDATES, key=combined)
    if not np.isfinite(combined(pick)):
        pick = faired
    if _crossed_keep(row, row["hidden"], row["sibling"]):
        pick = "conformal"
    return pick, faired


def margin_rule(hidden_margin: float = 1.0, sibling_tolerance: float = 1.0,
                decisive: float = 0.5):
    """The old rule with its thresholds as knobs: the λ-H fill is kept below
    ``hidden_margin`` × fair2's hidden-ring score, unless its sibling score is above
    ``sibling_tolerance`` × fair2's; below ``decisive`` × on the hidden rings whatever the
    siblings say (1, 1, 0.5: the old rule, a sibling tie held)."""
    def rule(row):
        h, s = row["hidden"], row["sibling"]
        hl, sl = _said(h), _said(s)
        faired = "fair3" if h and _wins(h, s, "fair3", "fair2") else "fair2"
        if "conformal" in hl and "fair2" in hl:
            keep = hl["conformal"] < decisive * hl["fair2"] or (
                hl["conformal"] < hidden_margin * hl["fair2"] and (
                    "conformal" not in sl or
                    sl["conformal"] <= sibling_tolerance * sl["fair2"]))
        else:
            keep = "conformal" in sl and sl["conformal"] < hidden_margin * sl["fair2"]
        keep = keep or _crossed_keep(row, h, s)
        return ("conformal" if keep else faired), faired
    return rule


SCANS = {"hidden margin": [("hidden_margin", m) for m in (0.8, 0.9, 0.95, 1.0, 1.05)],
         "sibling tolerance": [("sibling_tolerance", t) for t in (0.9, 1.0, 1.1, 1.25, 1.5)],
         "decisive": [("decisive", d) for d in (0.3, 0.4, 0.5, 0.6, 0.7)]}


def _guarded(rule):
    def guarded(row):
        pick, faired = rule(row)
        return (faired if pick == "conformal" and row.get("grown") else pick), faired
    guarded.__doc__ = f"{rule.__doc__.splitlines()[0]} … and no λ-H fill on a grown patch."
    return guarded


def rule_always_lambda_h(row):
    """Always the λ-H fill (select=False)."""
    return "conformal", "fair2"


RULES = {
    "before (main 2a0a2d3)": rule_before,
    "three-way: λ-H vs the faired fill the tests pick": rule_three_way,
    "three-way, no decisive skip": rule_three_way_no_decisive,
    "three-way vs the lower hidden-ring faired fill": rule_three_way_hidden_faired,
    "before, fair3 when undecided": rule_flipped_default,
    "three-way, fair3 when undecided": rule_three_way_flipped,
    "before, λ-H kept when it wins either test": rule_either_test,
    "before, λ-H must win every test": rule_both_tests,
    "argmin hidden rings": rule_argmin_hidden,
    "argmin hidden rings, siblings check": rule_argmin_hidden_checked,
    "argmin siblings": rule_argmin_siblings,
    "argmin geometric mean of both tests (relative)": rule_product,
    "before + grown guard": _guarded(rule_before),
    "three-way + grown guard": _guarded(rule_three_way),
    "always λ-H (select=False)": rule_always_lambda_h,
    "library today (choose)": rule_library,
}


# --------------------------------------------------------------------------- measures


def chosen_errors(rows, rule) -> list[float]:
    out = []
    for r in rows:
        t = r["true"]
        if rule is None:
            out.append(min(v for v in t.values() if np.isfinite(v)))
            continue
        pick, faired = rule(r)
        out.append(t[pick] if np.isfinite(t[pick]) else t[faired])
    return out


def measures(rows, chosen) -> dict:
    chosen = np.asarray(chosen, float)
    fair2 = np.array([r["true"]["fair2"] for r in rows])
    better = np.array([min(r["true"]["fair2"], r["true"]["fair3"]) for r in rows])
    best = np.array([min(v for v in r["true"].values() if np.isfinite(v)) for r in rows])
    cgal = np.array([r.get("cgal", np.nan) for r in rows], float)
    ok = np.isfinite(cgal) & (cgal > 1e-6)
    meshes = list(dict.fromkeys(r["mesh"] for r in rows))
    per_mesh = {}
    for m in meshes:
        i = np.array([r["mesh"] == m for r in rows])
        if np.median(fair2[i]) > 1e-6:
            per_mesh[m] = np.median(chosen[i]) / np.median(fair2[i])
    worst_mesh = max(per_mesh, key=per_mesh.get)
    vs_faired = np.where(better > 1e-6, chosen / np.maximum(better, 1e-300), np.nan)
    wh = int(np.nanargmax(vs_faired))
    b = best > 1e-6
    regret = chosen[b] / best[b]
    return {"over_cgal": float(np.median(chosen[ok] / cgal[ok])) if ok.any() else np.nan,
            "worst_mesh": (worst_mesh, per_mesh[worst_mesh]),
            "meshes_above_1.1": sum(x > 1.1 for x in per_mesh.values()),
            "worst_hole": (f"{rows[wh]['mesh']} #{rows[wh]['hole']}", float(vs_faired[wh])),
            "above_1.5": [f"{rows[i]['mesh']} #{rows[i]['hole']}"
                          for i in np.flatnonzero(vs_faired > 1.5)],
            "pick_best": float(np.mean(regret <= 1.01)), "n": int(b.sum()),
            "regret": float(np.median(regret)), "mean_log_regret": float(np.mean(
                np.log(regret)))}


def replay(rows, rules=None) -> str:
    rules = RULES if rules is None else rules
    out = ["| rule | median / CGAL | worst mesh / fair2 | meshes > 1.1 | worst hole / "
           "better faired | holes > 1.5× | pick-best | median regret | mean log regret |",
           "|---|---|---|---|---|---|---|---|---|"]
    for label, rule in list(rules.items()) + [("best candidate (truth: ceiling)", None)]:
        m = measures(rows, chosen_errors(rows, rule))
        out.append(f"| {label} | {m['over_cgal']:.3f} | {m['worst_mesh'][1]:.3f} "
                   f"({m['worst_mesh'][0]}) | {m['meshes_above_1.1']} | "
                   f"{m['worst_hole'][1]:.2f} ({m['worst_hole'][0]}) | {len(m['above_1.5'])} "
                   f"| {100 * m['pick_best']:.0f} % | {m['regret']:.3f} | "
                   f"{m['mean_log_regret']:.3f} |")
    return "\n".join(out)


def holes_above(rows, rule, limit=1.5) -> str:
    out = []
    for r, c in zip(rows, chosen_errors(rows, rule), strict=True):
        t = r["true"]
        better = min(t["fair2"], t["fair3"])
        if better > 1e-6 and c / better > limit:
            out.append(f"{r['mesh']} #{r['hole']}: chose {c:.3g} = {c / better:.2f}× "
                       f"(fair2 {t['fair2']:.3g}, fair3 {t['fair3']:.3g}, λ-H "
                       f"{t['conformal']:.3g}; grown {r.get('grown')}, crossed "
                       f"{r['crossed']}; hidden {_fmt(r['hidden'])}; siblings "
                       f"{_fmt(r['sibling'])})")
    return "\n".join(out) or "none"


def _fmt(t):
    return ", ".join(f"{k} {v:.3g}" for k, v in t.items()) or "—"


def changed_holes(before, after, rule) -> str:
    """The holes where ``rule`` writes another fill on the ``after`` table than on the
    ``before`` table of the same holes (two builds of the tests, the same candidates): the
    error it writes on each, and both tests' scores on the after table."""
    old = {(r["mesh"], r["hole"]): r for r in before}
    out = ["| hole | fair2 | fair3 | λ-H | before | after | after / before | after / better "
           "faired | hidden (after) | siblings (after, found) |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    ratios = []
    for r in after:
        b = old.get((r["mesh"], r["hole"]))
        if b is None:
            continue
        t = r["true"]
        was, now = chosen_errors([b], rule)[0], chosen_errors([r], rule)[0]
        ratios.append(now / max(was, 1e-300))
        if rule(b)[0] == rule(r)[0] and was == now:
            continue
        better = min(t["fair2"], t["fair3"])
        out.append(f"| {r['mesh']} #{r['hole']} | {t['fair2']:.3g} | {t['fair3']:.3g} | "
                   f"{t['conformal']:.3g} | {rule(b)[0]} {was:.3g} | {rule(r)[0]} {now:.3g} | "
                   f"{now / was:.2f} | {now / better:.2f} | {_fmt(r['hidden'])} | "
                   f"{_fmt(r['sibling'])} ({r.get('siblings_found', '?')}) |")
    ratios = np.asarray(ratios)
    out.append(f"\n{len(ratios)} holes, {len(out) - 2} changed; after / before: geometric mean "
               f"{np.exp(np.log(ratios).mean()):.3f}, better by 10 % "
               f"{int((ratios < 1 / 1.1).sum())}, worse by 10 % {int((ratios > 1.1).sum())}")
    return "\n".join(out)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cache", required=True)
    parser.add_argument("--split", required=True, help="tuning, validation (or a probe set "
                        "of selfcheck_probes.py: random, thin)")
    parser.add_argument("--above", default=None, help="list the holes above 1.5× for "
                        "this rule (a label of the table)")
    parser.add_argument("--scan", action="store_true",
                        help="the old rule's thresholds scanned one at a time instead")
    parser.add_argument("--against", default=None, help="a cache of the same holes built "
                        "before a change of the tests: list the holes where the library's "
                        "rule writes another fill")
    args = parser.parse_args(argv)
    rows = [r for r in selfcheck_table.read_cache(Path(args.cache))
            if r["split"] == args.split]
    if args.against:
        before = [r for r in selfcheck_table.read_cache(Path(args.against))
                  if r["split"] == args.split]
        print(changed_holes(before, rows, rule_library))
        return
    print(f"{args.split}: {len(rows)} holes on {len({r['mesh'] for r in rows})} meshes\n")
    rules = None
    if args.scan:
        rules = {f"{knob} {value}": margin_rule(**{knob: value})
                 for scan in SCANS.values() for knob, value in scan}
    print(replay(rows, rules))
    if args.above:
        print("\n" + holes_above(rows, RULES[args.above]))


if __name__ == "__main__":
    main()
