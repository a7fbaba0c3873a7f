"""Session 26: a noise-aware self-check on scans (issue 14), on the tuning side only.

On simulated range scans the default fill sometimes writes a candidate much worse than the
better faired fill. This study asks whether the self-check keeps a candidate other than the
reference fair2 (the λ-H fill, or fair3) on score differences that the noise of the test
itself explains, and measures a rule with no tuned distance threshold:

- each test's per-sample distances are kept (``detail`` of
  :func:`surfinpaint.fill.selfcheck.hidden_ring_scores` / ``sibling_scores``); a
  candidate's **advantage** over fair2 is the mean of the paired per-sample differences and
  its standard error the cluster-robust one, the faces the samples lie on as clusters
  (:func:`surfinpaint.fill.selfcheck.paired_advantage`; over two siblings: the mean of the
  advantages, the errors added in quadrature);
- the **rule** ``z``: where today's self-check keeps the λ-H fill or writes fair3, it is
  kept only when its advantage over fair2 in the test that decides (the hidden rings; the
  sibling holes where no hidden-ring test speaks for the λ-H fill) exceeds ``z`` standard
  errors; else the next choice down (λ-H → the verdict's faired fill, which passes the same
  test → fair2). ``z = 2.326`` (one-sided 1 %, the plane test's level), fixed before any
  run; 1.645 (5 %) is shown as a sensitivity only.

Holes where the plane test lays fair2 on the plane do not run the self-check and are left
as they are. The rule only ever moves a hole towards fair2, so each hole's outcome is the
error of fair2, fair3 or today's default, all measured. The self-check is replayed with
the default options on the cut mesh (the verdict's scores are those of ``fill_holes``'s
own run: the replay's pick is checked against the default's error, column ``agree``).

Holes: the manifest's tuning half (split "tuning" only; never validation or holdout rows)
and the extra scans of ``scan_flatness_study.EXTRA`` (tuning-half sources, three noise
levels). Errors as ``benchmarks/accuracy.py`` scores them (two-sided mean distance to the
removed truth, % of hole diameter; on scans the truth is the noise-free scan).

    taskset -c 1 .venv/bin/python benchmarks/scan_noise_selfcheck.py --set extra \\
        --out /tmp/s26noise_extra.jsonl
    taskset -c 1 .venv/bin/python benchmarks/scan_noise_selfcheck.py --set tuning \\
        --out /tmp/s26noise_tuning.jsonl
    .venv/bin/python benchmarks/scan_noise_selfcheck.py --tables /tmp/s26noise_extra.jsonl \\
        /tmp/s26noise_tuning.jsonl

Rows already in ``--out`` are not computed again. Results: docs/selfcheck.md, "Session 26:
a noise-aware self-check on scans".
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
import accuracy  # noqa: E402
import scan_flatness_study as sfs  # noqa: E402
import validation  # noqa: E402

from surfinpaint import ConformalOptions  # noqa: E402
from surfinpaint.fill.conformal.candidates import Candidates  # noqa: E402
from surfinpaint.fill.conformal.method import known_plane  # noqa: E402
from surfinpaint.fill.conformal.selection import _said, choose, sibling_test_plan  # noqa: E402
from surfinpaint.fill.selfcheck import (  # noqa: E402
    advantages_over,
    hidden_ring_scores,
    sibling_scores,
)
from surfinpaint.geometry.cutting import edge_graph  # noqa: E402

Z_RULE = 2.326  # one-sided 1 %: the plane test's level, fixed before any run
Z_SHOWN = (1.645, Z_RULE)
METHODS = ("fair", "fair3", "conformal")


# --------------------------------------------------------------------------- the replay


def replay(cut) -> dict:
    """The default's plane test and self-check on the cut hole, with the tests' spreads."""
    options = ConformalOptions()
    v, f, loop = cut.vertices, cut.faces, cut.loop
    candidates = Candidates.for_hole(v, f, loop, options)
    plane = known_plane(v, f, loop)
    wide = known_plane(v, f, loop, rings=4)
    rec = {"flat": bool(plane.flat), "sigma": float(plane.noise),
           "sigma4": float(wide.noise), "crossed": bool(candidates.crossed)}
    if plane.flat:
        return rec
    graph = edge_graph(f, len(v))
    hd: dict = {}
    hidden = hidden_ring_scores(v, f, loop, candidates.for_tests(),
                                hide_rings=options.hide_rings,
                                patch_rings=options.rings_in_patch, graph=graph, detail=hd)
    run, with_lh = sibling_test_plan(hidden, reference="fair2", choose_faired=True)
    sd: list = []
    sibling = {}
    if run:
        sibling = sibling_scores(v, f, loop, candidates.for_tests(with_lambda_h=with_lh),
                                 siblings=options.siblings, gap_rings=options.gap_rings,
                                 patch_rings=options.rings_in_patch, graph=graph, detail=sd)
    verdict = choose(hidden, sibling, reference="fair2", choose_faired=True,
                     crossed=candidates.crossed)
    rec.update(hidden=hidden, sibling=sibling, keep=bool(verdict.keep),
               faired=verdict.faired, hidden_said=bool(_said(hidden)),
               **{"adv_" + k: v for k, v in advantages_over(hd, sd).items()})
    return rec


def hole_row(cut, n_samples: int, also=()) -> dict:
    row = {"errors": {}, "status": {}, "note": {}}
    for m in (*METHODS, *also):
        r = accuracy.score(cut, m, "x", 0, 0.0, n_samples)
        row["errors"][m] = r.mean_pct if r.status in validation.FILLED else float("nan")
        row["status"][m], row["note"][m] = r.status, r.note
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        row["replay"] = replay(cut)
    return row


def run(which: str, out: Path, n_samples: int, only=None, also=()) -> None:
    for set_name, mesh_id, kind, h, k, hole, cut in sfs.pending_holes(which, out, only):
        t0 = time.perf_counter()
        row = {"set": set_name, "mesh": mesh_id, "hole": k, "kind": kind,
               "radius_h": hole["radius"] / h, **hole_row(cut, n_samples, also)}
        row["seconds"] = time.perf_counter() - t0
        with out.open("a") as fh:
            fh.write(json.dumps(row, default=float) + "\n")
        e, rp = row["errors"], row["replay"]
        print(f"{mesh_id} #{k}: " + " ".join(f"{a} {b:.3f}" for a, b in e.items())
              + f" flat {rp['flat']} kept {_pick(rp)}", file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- the rule


def _pick(rp: dict) -> str:
    """Today's pick: "plane", "lambda_h", "fair3" or "fair2"."""
    if rp["flat"]:
        return "plane"
    if rp["keep"]:
        return "lambda_h"
    return rp["faired"]


def _lh_said(scores) -> bool:
    """The test ran and the λ-H fill did not fail on its hole (``selection._said``)."""
    return bool(scores) and bool(np.isfinite(scores.get("conformal", 0.0)))


def _deciding(rp: dict, pick: str) -> tuple[str, str]:
    """The candidate and the test that decided a non-fair2 pick."""
    if pick == "lambda_h":
        return "conformal", ("hidden" if rp["hidden_said"] else "sibling")
    return "fair3", "hidden"


def _significant(rp: dict, name: str, test: str, z: float) -> bool:
    adv, se = rp.get("adv_" + test, {}).get(name, (np.nan, np.inf))
    return bool(adv > z * se)


def rule_pick(rp: dict, z: float) -> str:
    """The noise-aware pick: today's, unless its advantage over fair2 in the test that
    decided it is within ``z`` standard errors (then the next choice down)."""
    pick = _pick(rp)
    if pick == "lambda_h":
        if rp["crossed"] and not rp["hidden_said"] and not _lh_said(rp.get("sibling")):
            return pick  # a crease fill kept where no test spoke: nothing to weigh
        if _significant(rp, *_deciding(rp, pick), z):
            return pick
        pick = rp["faired"]
    if pick == "fair3":
        return pick if _significant(rp, "fair3", "hidden", z) else "fair2"
    return pick


def outcome(row: dict, pick: str) -> float:
    e = row["errors"]
    return {"fair2": e["fair"], "fair3": e["fair3"]}.get(pick, e["conformal"])


def agree(row: dict) -> bool:
    """The replay's pick gives the default's error (faired picks: the same fill)."""
    pick = _pick(row["replay"])
    e = row["errors"]
    if pick in ("fair2", "fair3"):
        return bool(np.isclose(outcome(row, pick), e["conformal"]))
    return True


# --------------------------------------------------------------------------- tables


GROUPS = [("extra scans (benchmark noise)", lambda r: r["set"] == "extra"),
          ("extra scans, 3x noise", lambda r: r["set"] == "extra_noisy"),
          ("extra scans, 6x noise", lambda r: r["set"] == "extra_noisy6"),
          ("tuning half, scans", lambda r: r["set"] == "tuning" and r["kind"] == "range_scan"),
          ("tuning half, not scans",
           lambda r: r["set"] == "tuning" and r["kind"] != "range_scan")]


def summary(rows: list[dict], label: str) -> str:
    dflt = np.array([r["errors"]["conformal"] for r in rows])
    best = np.array([min(r["errors"]["fair"], r["errors"]["fair3"]) for r in rows])
    picks = [_pick(r["replay"]) for r in rows]
    lines = [f"### {label}: {len(rows)} holes (today's picks: "
             + ", ".join(f"{p} {picks.count(p)}" for p in ("plane", "lambda_h", "fair3",
                                                            "fair2"))
             + f"; replay agrees on {sum(agree(r) for r in rows)})", "",
             "| rule | changed | median % | / default (median) | worse > 10 % | better > 10 % "
             "| > 1.5x best faired | > 1.2x best faired |",
             "|---|---|---|---|---|---|---|---|"]
    lines.append(f"| today's default | 0 | {np.nanmedian(dflt):.3f} | 1 | 0 | 0 | "
                 f"{(dflt > 1.5 * best).sum()} | {(dflt > 1.2 * best).sum()} |")
    for z in Z_SHOWN:
        new = [rule_pick(r["replay"], z) for r in rows]
        err = np.array([outcome(r, p) for r, p in zip(rows, new, strict=True)])
        ratio = err / dflt
        lines.append(f"| z = {z} | {sum(a != b for a, b in zip(new, picks, strict=True))} | "
                     f"{np.nanmedian(err):.3f} | {np.nanmedian(ratio):.3f} | "
                     f"{(ratio > 1.1).sum()} | {(ratio < 1 / 1.1).sum()} | "
                     f"{(err > 1.5 * best).sum()} | {(err > 1.2 * best).sum()} |")
    return "\n".join(lines)


def _fmt_test(rp: dict, test: str) -> str:
    s = rp.get("adv_" + test) or {}
    return ", ".join(f"{k} {a:.2g}±{e:.2g}" for k, (a, e) in s.items()) or "—"


def listing(rows: list[dict], factor: float = 1.2) -> str:
    lines = [f"holes where today's default is > {factor}x the better faired fill: errors "
             "(% of diameter) default / fair2 / fair3; pick today -> rule (z = "
             f"{Z_RULE}); sigma (k = 2, k = 4 rings, mesh units); advantage over fair2 ± "
             "standard error (mesh units) in the hidden-ring and sibling tests", "",
             "| hole | ratio | default | fair2 | fair3 | pick | rule | sigma2 | sigma4 "
             "| hidden: adv ± se | sibling: adv ± se |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        e, rp = r["errors"], r["replay"]
        best = min(e["fair"], e["fair3"])
        if not e["conformal"] > factor * best:
            continue
        lines.append(f"| {r['mesh']} #{r['hole']} | {e['conformal'] / best:.2f} | "
                     f"{e['conformal']:.3f} | {e['fair']:.3f} | {e['fair3']:.3f} | "
                     f"{_pick(rp)} | {rule_pick(rp, Z_RULE)} | {rp['sigma']:.2g} | "
                     f"{rp['sigma4']:.2g} | {_fmt_test(rp, 'hidden')} | "
                     f"{_fmt_test(rp, 'sibling')} |")
    return "\n".join(lines)


def changed(rows: list[dict], z: float = Z_RULE) -> str:
    lines = [f"holes whose pick the rule (z = {z}) changes: default -> rule error (%)", ""]
    for r in rows:
        rp = r["replay"]
        a, b = _pick(rp), rule_pick(rp, z)
        if a != b:
            lines.append(f"- {r['mesh']} #{r['hole']}: {a} {outcome(r, a):.3f} -> {b} "
                         f"{outcome(r, b):.3f} (sigma {rp['sigma']:.2g}; hidden "
                         f"{_fmt_test(rp, 'hidden')}; sibling {_fmt_test(rp, 'sibling')})")
    return "\n".join(lines)


def ladder(rows: list[dict]) -> str:
    """Every hole where today's pick is the λ-H fill or fair3 (not a crease fill kept
    without tests), by its advantage over fair2 in the deciding test in standard errors
    (t): what writing fair2 instead would do. Shows where any z would cut, without
    choosing one from these holes."""
    items = []
    for r in rows:
        rp = r["replay"]
        pick = _pick(rp)
        if pick not in ("lambda_h", "fair3") or rule_pick(rp, np.inf) == pick:
            continue
        name, test = _deciding(rp, pick)
        adv, se = rp.get("adv_" + test, {}).get(name, (np.nan, np.inf))
        items.append((adv / se if se > 0 else np.inf, r, pick, test))
    items.sort(key=lambda x: x[0])
    lines = ["today's non-fair2 picks by t = advantage / standard error in the deciding test; "
             "error today -> with fair2 (%), ratio", "",
             "| hole | pick | test | t | today | fair2 | fair2 / today |",
             "|---|---|---|---|---|---|---|"]
    for t, r, pick, test in items:
        a, b = outcome(r, pick), r["errors"]["fair"]
        ratio = f"{b / a:.2f}" if a > 1e-9 else "—"  # a λ-H fill exact on a plane
        lines.append(f"| {r['mesh']} #{r['hole']} | {pick} | {test} | {t:.2f} | {a:.3f} | "
                     f"{b:.3f} | {ratio} |")
    return "\n".join(lines)


def tables(paths: list[Path]) -> str:
    rows = [json.loads(line) for p in paths for line in Path(p).read_text().splitlines()]
    out = []
    for label, keep in GROUPS:
        rs = [r for r in rows if keep(r)]
        if rs:
            out += [summary(rs, label), listing(rs), changed(rs), ladder(rs)]
    return "\n\n".join(out)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--set", choices=("tuning", "extra"), default="extra")
    parser.add_argument("--out", default="/tmp/s26noise.jsonl")
    parser.add_argument("--meshes", default=None)
    parser.add_argument("--samples", type=int, default=10000)
    parser.add_argument("--also", default="", help="more accuracy.py methods to score, "
                        "comma-separated (e.g. conformal_signif: the rule run for real)")
    parser.add_argument("--tables", nargs="+", default=None)
    args = parser.parse_args(argv)
    if args.tables:
        print(tables([Path(p) for p in args.tables]))
        return
    run(args.set, Path(args.out), args.samples,
        args.meshes.split(",") if args.meshes else None,
        tuple(m for m in args.also.split(",") if m))


if __name__ == "__main__":
    main()
