"""Candidate fills and the self-check's scores of each, per hole of the validation benchmark
(issue 14 item 3): what a chooser among more candidates could reach, measured on the
tuning half only.

Per hole: every candidate of :data:`CANDIDATES` is made on the hole (its truth error, % of
the hole diameter, as ``benchmarks/validation.py`` scores it) and on the self-check's test
holes (hidden rings and sibling holes, both always run), so any selection rule can be
replayed offline (``--replay``) without filling again.

Run::

    .venv/bin/python benchmarks/candidates_study.py --meshes <tuning ids> --out study.json
    .venv/bin/python benchmarks/candidates_study.py --replay study.json
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import holes_manifest  # noqa: E402
import validation  # noqa: E402
import validation_meshes as vm  # noqa: E402

from surfinpaint.errors import NUMERICAL_ERRORS, FillError  # noqa: E402
from surfinpaint.fill.conformal.candidates import Candidates  # noqa: E402
from surfinpaint.fill.conformal.options import ConformalOptions  # noqa: E402
from surfinpaint.fill.liepa.baseline import faired_fills  # noqa: E402
from surfinpaint.fill.results import Fill  # noqa: E402
from surfinpaint.fill.selfcheck import hidden_ring_scores, sibling_scores  # noqa: E402
from surfinpaint.geometry.metrics import hole_patch_of, surface_distance  # noqa: E402

TUNING = ("face000,scan_bunny,scan_bracket,bunny,bone,blob_a,cube40,bracket,airplane,pial,"
          "white,tooth,premolar,sphere,torus,snowman")
# faired families: name prefix -> (triangulation search, fairing operator)
FAMILIES = {"fair": ("delaunay", "cotan"), "ifair": ("delaunay", "intrinsic"),
            "afair": ("all", "cotan"), "cfair": ("delaunay", "clamped"),
            "tfair": ("cdt", "cotan")}
# λ-H candidates: name -> the faired fill it starts from
# (measured on bone #0-#4 and airplane #1: the λ-H fill from fair2 or ifair3 is the one from
# fair3 within 3 %, so only the default start and the planar CDT's are studied)
LAMBDA_H = {"conformal": "fair3", "lh_tfair3": "tfair3"}


def make(vertices, faces, loop, *, test: bool, families=FAMILIES, lambda_h=LAMBDA_H):
    """name -> Fill or the exception of a candidate that failed."""
    cands = Candidates.for_hole(vertices, faces, loop, ConformalOptions())
    out: dict = {}
    for prefix, (search, operator) in families.items():
        try:
            made = faired_fills(vertices, faces, loop, (2, 3), search=search,
                                operator=operator)
            for k, (nv, nf, used) in made.items():
                out[f"{prefix}{k}"] = Fill(nv, nf, "fair", fair_order=used)
        except (FillError, *NUMERICAL_ERRORS) as exc:
            out[f"{prefix}2"] = out[f"{prefix}3"] = exc
    for name, start in lambda_h.items():
        s0 = out.get(start)
        if not isinstance(s0, Fill):
            out[name] = FillError(f"no start {start}")
            continue
        try:
            out[name] = cands.lambda_h(vertices, faces, loop, (s0.vertices, s0.faces),
                                       test=test)
        except FillError as exc:
            out[name] = exc
    return out


def truth_errors(cut, fills, samples: int) -> dict[str, float]:
    out = {}
    for name, c in fills.items():
        if isinstance(c, Exception):
            out[name] = float("inf")
            continue
        v = np.concatenate([cut.vertices, c.vertices])
        f = np.concatenate([cut.faces, c.faces])
        pv, pf = hole_patch_of(v, f, len(cut.vertices), cut.faces)
        d = surface_distance(pv, pf, cut.truth_vertices, cut.truth_faces, n_samples=samples)
        out[name] = float(d.mean * 100.0 / cut.diameter)
    return out


def deviations(cut, fills, samples: int = 2000) -> dict[str, dict[str, float]]:
    """Truth-free: mean distance from each candidate's patch to each faired one's, % of the
    hole diameter (how far a candidate strays from the faired fills)."""
    from surfinpaint.geometry.metrics import point_mesh_distance, sample_surface

    made = {k: c for k, c in fills.items() if not isinstance(c, Exception) and len(c.faces)}
    allv = {k: np.concatenate([cut.vertices, c.vertices]) for k, c in made.items()}
    out: dict = {}
    for a, c in made.items():
        pts = sample_surface(allv[a], c.faces, samples, seed=0)
        out[a] = {b: float(point_mesh_distance(pts, allv[b], made[b].faces).mean()
                           * 100.0 / cut.diameter)
                  for b in ("fair2", "fair3") if b in made}
    return out


def study_hole(cut, samples: int, families=FAMILIES, lambda_h=LAMBDA_H) -> dict:
    o = ConformalOptions()
    v, f, loop = cut.vertices, cut.faces, cut.loop
    t0 = time.perf_counter()
    fills = make(v, f, loop, test=False, families=families, lambda_h=lambda_h)
    t1 = time.perf_counter()

    def tests(tv, tf, tl):
        return make(tv, tf, tl, test=True, families=families, lambda_h=lambda_h)

    hidden = hidden_ring_scores(v, f, loop, tests, hide_rings=o.hide_rings,
                                patch_rings=o.rings_in_patch)
    t2 = time.perf_counter()
    sibling = sibling_scores(v, f, loop, tests, siblings=o.siblings, gap_rings=o.gap_rings,
                             patch_rings=o.rings_in_patch)
    t3 = time.perf_counter()
    return {"truth": truth_errors(cut, fills, samples), "hidden": hidden, "sibling": sibling,
            "deviation": deviations(cut, fills),
            "edges": len(loop), "seconds": {"fills": t1 - t0, "hidden": t2 - t1,
                                            "sibling": t3 - t2}}


def run(meshes: list[str], samples: int, out: Path, families=FAMILIES, lambda_h=LAMBDA_H
        ) -> list[dict]:
    manifest = holes_manifest.read(holes_manifest.MANIFEST)
    rows = []
    partial = out.with_suffix(".partial.jsonl")
    partial.unlink(missing_ok=True)
    for entry in manifest["meshes"]:
        if entry["mesh"] not in meshes:
            continue
        mesh = vm.load_entry(entry)
        for k, hole in enumerate(entry["holes"]):
            cut = validation._cut(mesh, hole)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                row = {"mesh": entry["mesh"], "hole": k, "split": entry["split"],
                       **study_hole(cut, samples, families, lambda_h)}
            rows.append(row)
            with partial.open("a") as fh:
                fh.write(json.dumps(row, default=float) + "\n")
            t = row["truth"]
            print(f"{entry['mesh']} #{k}: " + " ".join(f"{n} {x:.3f}" for n, x in t.items()),
                  file=sys.stderr, flush=True)
    out.write_text(json.dumps(rows, default=float))
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--meshes", default=TUNING)
    parser.add_argument("--samples", type=int, default=10000)
    parser.add_argument("--out", default="candidates_study.json")
    parser.add_argument("--families", default=",".join(FAMILIES))
    parser.add_argument("--lambda-h", default=",".join(LAMBDA_H))
    parser.add_argument("--replay", default=None, help="replay the rules on a saved study")
    parser.add_argument("--baseline", default="/work/bench_baseline/final_combined.jsonl",
                        help="validation.py rows with CGAL's (for the / cgal column)")
    args = parser.parse_args(argv)
    if args.replay:
        rows = json.loads(Path(args.replay).read_text()) if args.replay.endswith(".json") \
            else [json.loads(x) for x in Path(args.replay).read_text().splitlines() if x]
        base = [json.loads(x) for x in Path(args.baseline).read_text().splitlines() if x]
        cgal = {(b["case"], b["hole"]): b["mean_pct"] for b in base if b["method"] == "cgal"}
        print(replay(rows, RULES, cgal))
        return
    families = {k: FAMILIES[k] for k in args.families.split(",")}
    lambda_h = {k: LAMBDA_H[k] for k in args.lambda_h.split(",") if k}
    run([m.strip() for m in args.meshes.split(",")], args.samples, Path(args.out), families,
        lambda_h)


# --------------------------------------------------------------------------- replay


def _plan_rule(hidden, sibling):
    """Today's rule (selection.choose) on fair2 / fair3 / conformal, siblings only where its
    plan runs them."""
    from surfinpaint.fill.conformal.selection import choose, sibling_test_plan

    h = {k: hidden[k] for k in ("fair2", "fair3", "conformal") if k in hidden}
    run_s, with_lh = sibling_test_plan(h)
    s = {}
    if run_s:
        s = {k: sibling[k] for k in ("fair2", "fair3") + (("conformal",) if with_lh else ())
             if k in sibling}
    v = choose(h, s)
    return ["conformal", v.faired] if v.keep else [v.faired]


def replay(rows: list[dict], rules: dict, reference: dict[tuple, float]) -> str:
    """Per rule: per-hole median chosen / CGAL, worst and count above 1.5 of chosen / better
    cotan faired fill, median regret to the best candidate of all."""
    lines = ["| rule | median / cgal | geo-mean / cgal | worst / better faired | holes > 1.5 "
             "| > 1.2 | median regret | best share | changed holes: better / worse than today "
             "(>2 %) |", "|---|---|---|---|---|---|---|---|---|"]
    today = {}
    for name, rule in rules.items():
        if not set(getattr(rule, "needs", ())) <= set(rows[0]["truth"]):
            continue  # a candidate the study did not make
        ratios, faired, regret, best, better, worse = [], [], [], 0, 0, 0
        for r in rows:
            t = r["truth"]
            # the rule's preference order: a candidate that failed on the hole is passed over
            e = next((t[p] for p in rule(r["hidden"], r["sibling"]) if np.isfinite(t[p])),
                     t["fair2"])
            key = (r["mesh"], r["hole"])
            today.setdefault(key, e)
            if e < 0.98 * today[key]:
                better += 1
            elif e > 1.02 * today[key]:
                worse += 1
            bf = min(t["fair2"], t["fair3"])
            c = reference.get((r["mesh"], r["hole"]))
            if c and c > 1e-6:
                ratios.append(e / c)
            if bf > 1e-6:
                faired.append((e / bf, r["mesh"], r["hole"]))
            lo = min(x for x in t.values() if np.isfinite(x))
            if lo > 1e-6:
                regret.append(e / lo)
                best += e <= 1.01 * lo
        worst = max(faired)
        lines.append(f"| {name} | {np.median(ratios):.3f} | "
                     f"{np.exp(np.mean(np.log(ratios))):.3f} | {worst[0]:.2f} ({worst[1]} "
                     f"#{worst[2]}) | {sum(x > 1.5 for x, *_ in faired)} | "
                     f"{sum(x > 1.2 for x, *_ in faired)} | {np.median(regret):.3f} | "
                     f"{best}/{len(regret)} | {better} / {worse} |")
    return "\n".join(lines)


def _argmin(keys, scores):
    """The keys by score, best first (then the others in order)."""
    present = sorted((k for k in keys if k in scores), key=scores.get)
    return present + [k for k in keys if k not in present]


def _today_with(alternates, order_by="hidden"):
    """Today's rule, with the faired fill chosen among fair2 and ``alternates``: each
    alternate that passes today's fair3-vs-fair2 test (wins the hidden rings, does not lose
    the siblings), the best of those by ``order_by``; the λ-H fill against fair2 as today."""
    from surfinpaint.fill.conformal.selection import _wins, choose, sibling_test_plan

    def rule(hidden, sibling):
        h = {k: hidden[k] for k in ("fair2", "fair3", "conformal") if k in hidden}
        run_s, with_lh = sibling_test_plan(h)
        faired_racing = any(k in hidden and hidden[k] < hidden["fair2"] for k in alternates)
        s = {}
        if run_s or faired_racing:
            s = {k: sibling[k] for k in sibling if k != "conformal" or with_lh}
        v = choose(h, {k: s[k] for k in ("fair2", "fair3", "conformal") if k in s})
        passing = [k for k in alternates if k in hidden and _wins(hidden, s, k, "fair2")]
        score = hidden if order_by == "hidden" else s
        faired = min(passing, key=lambda k: score.get(k, np.inf)) if passing else "fair2"
        return ["conformal", faired] if v.keep else [faired]
    rule.needs = alternates
    return rule


def _renamed(two: str, three: str):
    """Today's rule with ``two`` and ``three`` as the faired candidates (in the tests and
    as the fill written)."""
    def rule(hidden, sibling):
        def sub(d):
            out = {k: d[k] for k in ("conformal",) if k in d}
            out.update({new: d[old] for new, old in (("fair2", two), ("fair3", three))
                        if old in d})
            return out
        back = {"fair2": two, "fair3": three, "conformal": "conformal"}
        return [back[k] for k in _plan_rule(sub(hidden), sub(sibling))]
    rule.needs = (two, three)
    return rule


def _two_lambda_h(alternate: str, faired=("fair3",)):
    """Today's rule where the λ-H candidate is ``alternate`` instead of "conformal" when
    it passes the fair3-vs-fair2 test against it (wins the hidden rings, does not lose the
    siblings); faired fill among fair2 and ``faired``."""
    from surfinpaint.fill.conformal.selection import _wins

    base = _today_with(faired)

    def rule(hidden, sibling):
        lh = "conformal"
        if alternate in hidden and "conformal" in hidden and _wins(
                hidden, {k: sibling[k] for k in (alternate, "conformal") if k in sibling},
                alternate, "conformal"):
            lh = alternate
        h = dict(hidden)
        s = dict(sibling)
        if lh != "conformal":
            h["conformal"] = hidden[lh]
            if lh in sibling:
                s["conformal"] = sibling[lh]
        return [lh if k == "conformal" else k for k in base(h, s)]
    rule.needs = (alternate, *faired)
    return rule


RULES = {
    "today (choose)": _plan_rule,
    "fair2": lambda h, s: ["fair2"],
    "today, faired among fair3/tfair2/tfair3": _today_with(("fair3", "tfair2", "tfair3")),
    "today, λ-H from tfair3 when it wins": _two_lambda_h("lh_tfair3"),
    "both of the above": _two_lambda_h("lh_tfair3", ("fair3", "tfair2", "tfair3")),
    "today with ifair2 for fair2": _renamed("ifair2", "fair3"),
    "today with ifair3 for fair3": _renamed("fair2", "ifair3"),
    "today with ifair2, ifair3": _renamed("ifair2", "ifair3"),
    "today, faired among fair3": _today_with(("fair3",)),
    "today, faired among fair3/afair3": _today_with(("fair3", "afair3")),
    "today, faired among fair3/ifair3": _today_with(("fair3", "ifair3")),
    "today, faired among fair3/ifair2/ifair3": _today_with(("fair3", "ifair2", "ifair3")),
    "today, faired among all": _today_with(("fair3", "ifair2", "ifair3", "afair2",
                                            "afair3")),
    "today, faired among all, by sibling": _today_with(("fair3", "ifair2", "ifair3",
                                                        "afair2", "afair3"), "sibling"),
    "min hidden fair2/fair3/conformal": lambda h, s: _argmin(("fair2", "fair3", "conformal"), h),
    "min sibling fair2/fair3/conformal": lambda h, s: _argmin(("fair2", "fair3", "conformal"),
                                                              s),
}


if __name__ == "__main__":
    main()
