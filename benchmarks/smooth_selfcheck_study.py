"""The self-check's choices on the tuning side, with every test's evidence, for replaying rules
(session 38: the λ-H fill kept over a much better trilaplacian fill on smooth tubes, and the
bilaplacian fill kept where the trilaplacian one is about twice as close on small holes of
smooth organic shapes; docs/selfcheck.md "Session 38 (helper)").

For every hole of a tuning-side set (the tuning half of ``holes_manifest.json``, the
tuning-side CAD parts, the smooth tuning set, the 12 animals of ``animals.py``), the hole is
cut as ``validation.py`` cuts it and filled by ``fair``, ``fair3``, ``conformal_raw``,
``conformal`` and ``cgal`` (``accuracy.score``). While ``conformal`` runs, the library's
self-check is wrapped: its verdict is kept as it is (the written fill is the library's), and
the hidden-ring test (the depth the library used) and the sibling test (every candidate,
always) are run again with their per-sample records, giving each candidate's paired advantage
over fair2 and over fair3 (:func:`surfinpaint.fill.selfcheck.advantages_over`). A rule is then
replayed from a row without any fill (:func:`library_rule` reproduces the library's choice).

    python benchmarks/smooth_selfcheck_study.py --set smooth_tuning --out /tmp/st/smooth.jsonl
    python benchmarks/smooth_selfcheck_study.py --replay /tmp/st/*.jsonl

Session 42: ``--manifest`` takes any holes manifest instead of ``--set`` (the spent holdout
sets, as tuning-side study data for the λ-H fills that lose), its rows' set named after the
file (``holdout17``); ``--holes`` limits a run to listed holes (``mesh#k``):

    python benchmarks/smooth_selfcheck_study.py --manifest benchmarks/holdout17_manifest.json \
        --holes penguin#3,penguin#4 --out /tmp/st/holdout17.jsonl
    python benchmarks/smooth_selfcheck_study.py --replay /tmp/st/*.jsonl --screen-kept
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from functools import partial
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import accuracy  # noqa: E402
import animals  # noqa: E402
import holes_manifest  # noqa: E402
import validation  # noqa: E402
import validation_meshes as vm  # noqa: E402

from surfinpaint.fill.conformal import method  # noqa: E402
from surfinpaint.fill.conformal.method import known_plane  # noqa: E402
from surfinpaint.fill.conformal.selection import (  # noqa: E402
    choose,
    demoted,
    sibling_test_plan,
)
from surfinpaint.fill.selfcheck import (  # noqa: E402
    advantages_over,
    hidden_ring_scores,
    sibling_scores,
)
from surfinpaint.geometry.cutting import cut_geodesic_disk, edge_graph  # noqa: E402

METHODS = ("fair", "fair3", "conformal_raw", "conformal", "cgal")
SHALLOWER = "hidden rings one ring shallower"
SETS = {"tuning": holes_manifest.MANIFEST, "cad_tuning": holes_manifest.CAD_TUNING_MANIFEST,
        "smooth_tuning": holes_manifest.SMOOTH_TUNING_MANIFEST,
        "curved_scans": holes_manifest.CURVED_SCANS_MANIFEST,
        "thin_shells": holes_manifest.THIN_SHELLS_MANIFEST}
N_ANIMALS = 12


# --------------------------------------------------------------------------- recording


def _evidence(vertices, faces, loop, candidates, verdict) -> dict:
    """Both tests again, every candidate, with per-sample records: the evidence of a row."""
    o = candidates.options
    shallower = SHALLOWER in verdict.scores
    graph = edge_graph(faces, len(vertices))
    hd: dict = {}
    hidden = hidden_ring_scores(vertices, faces, loop, candidates.for_tests(),
                                hide_rings=o.hide_rings - shallower,
                                patch_rings=o.rings_in_patch, graph=graph, detail=hd)
    sd: list = []
    sibling = sibling_scores(vertices, faces, loop, candidates.for_tests(),
                             siblings=o.siblings, gap_rings=o.gap_rings,
                             patch_rings=o.rings_in_patch, graph=graph, detail=sd)
    edge = float(np.linalg.norm(vertices[loop] - vertices[np.roll(loop, -1)], axis=1).mean())
    plane = known_plane(vertices, faces, loop)
    # session 40: how far apart the two faired fills are (one triangulation, so vertex by
    # vertex), to weigh against the noise: a truth-free signal for fair3 against fair2
    faired = candidates.faired(vertices, faces, loop)
    apart = np.linalg.norm(faired["fair2"].vertices - faired["fair3"].vertices, axis=1) \
        if {"fair2", "fair3"} <= set(faired) else np.zeros(0)
    return {"hidden": hidden, "sibling": sibling, "shallower": shallower,
            "p_curvature": float(plane.p_curvature),
            "fair23_rms": float(np.sqrt(np.mean(apart**2))) if len(apart) else 0.0,
            "fair23_max": float(apart.max()) if len(apart) else 0.0,
            "sigma": float(plane.noise),
            "sigma4": float(known_plane(vertices, faces, loop, rings=4).noise), "edge": edge,
            "crossed": bool(candidates.crossed), "n_edges": len(loop),
            "lib_hidden": dict(verdict.hidden), "lib_sibling": dict(verdict.sibling),
            "lib_keep": bool(verdict.keep), "lib_faired": verdict.faired,
            "adv2": advantages_over(hd, sd, "fair2"), "adv3": advantages_over(hd, sd, "fair3")}


def recording(records: list):
    """A wrapper of the library's self-check appending each hole's evidence to ``records``."""
    library = method.self_check

    def self_check(vertices, faces, loop, candidates):
        verdict = library(vertices, faces, loop, candidates)
        records.append(_evidence(vertices, faces, loop, candidates, verdict))
        return verdict
    return self_check


def holes_of(which: str, meshes=None):
    """(mesh id, kind, hole number, hole, cut) of a set (of its meshes ``meshes`` only, when
    given)."""
    if which == "animals":
        for seed in range(N_ANIMALS):
            name = f"animal{seed}"
            if meshes is not None and name not in meshes:
                continue
            mesh = animals.animal(seed)
            holes = holes_manifest.plan_holes(mesh.vertices, mesh.faces, "organic", 2000 + seed,
                                              name)
            for k, hole in enumerate(holes):
                yield name, "organic", k, hole, cut_geodesic_disk(
                    mesh.vertices, mesh.faces, np.asarray(hole["centre"]), hole["radius"])
        return
    for entry in holes_manifest.read(SETS[which])["meshes"]:
        if which == "tuning" and entry["split"] != "tuning":
            continue
        if meshes is not None and entry["mesh"] not in meshes:
            continue
        mesh = vm.load_entry(entry)
        for k, hole in enumerate(entry["holes"]):
            yield entry["mesh"], entry["kind"], k, hole, validation._cut(mesh, hole)


def run(which: str, out: Path, samples: int, meshes: list[str] | None = None,
        holes: set[str] | None = None) -> None:
    """Every hole of the set ``which`` (of ``meshes``, of ``holes`` as ``mesh#k``, when given)
    not yet in ``out``: the five methods' errors and the self-check's evidence, a row each."""
    done = {(r["mesh"], r["hole"]) for r in read(out)} if out.exists() else set()
    records: list = []
    method.self_check = recording(records)
    for mesh_id, kind, k, hole, cut in holes_of(which, meshes):
        if (mesh_id, k) in done or (holes is not None and f"{mesh_id}#{k}" not in holes):
            continue
        t0 = time.perf_counter()
        row = {"set": which, "mesh": mesh_id, "kind": kind, "hole": k,
               "radius_h": hole["radius_h"], "near_border": bool(hole["near_border"]),
               "errors": {}, "status": {}}
        records.clear()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for m in METHODS:
                r = accuracy.score(cut, m, mesh_id, k, hole["radius_h"], samples)
                row["errors"][m] = (r.mean_pct if r.status in validation.FILLED
                                    else float("nan"))
                row["status"][m] = r.status
                if m == "conformal":
                    row["note"] = r.note
        row["evidence"] = records[0] if records else None  # None: no self-check ran
        row["seconds"] = time.perf_counter() - t0
        with out.open("a") as fh:
            fh.write(json.dumps(row, default=float) + "\n")
        e = row["errors"]
        print(f"{which} {mesh_id} #{k}: " + " ".join(f"{m} {e[m]:.3f}" for m in METHODS)
              + f" ({row['seconds']:.1f} s)", file=sys.stderr, flush=True)


def read(*paths) -> list[dict]:
    rows = []
    for path in paths:
        rows += [json.loads(x) for x in Path(path).read_text().splitlines() if x.strip()]
    return rows


# --------------------------------------------------------------------------- rules
# rule(evidence) -> "conformal" (the λ-H fill), "fair2" or "fair3"


def _adv(ev: dict, ref: str, test: str, name: str) -> tuple[float, float]:
    return tuple(ev["adv" + ref[-1]].get(test, {}).get(name, (np.nan, np.inf)))


def library_rule(ev: dict) -> str:
    """The library's choice, replayed from the row's evidence (sibling test as planned)."""
    hidden = ev["hidden"]
    run_sib, with_lh = sibling_test_plan(hidden, shallower=ev["shallower"])
    sibling = {} if not run_sib else (ev["sibling"] if with_lh else
                                      {k: v for k, v in ev["sibling"].items()
                                       if k != "conformal"})
    verdict = choose(hidden, sibling, crossed=ev["crossed"], shallower=ev["shallower"])
    adv = {t: a for t, a in ev["adv2"].items() if t == "hidden" or run_sib}
    if "sibling" in adv and not with_lh:
        adv["sibling"] = {k: v for k, v in adv["sibling"].items() if k != "conformal"}
    verdict = demoted(verdict, adv, 2.326, crossed=ev["crossed"])
    return "conformal" if verdict.keep else verdict.faired


def _beats3_hidden(ev: dict, z: float) -> bool:
    """The λ-H fill's hidden-ring advantage over fair3 exceeds ``z`` standard errors."""
    a, se = _adv(ev, "fair3", "hidden", "conformal")
    return bool(a > z * se)


def rule_lh_beats_fair3(ev: dict) -> str:
    """(a) A kept λ-H fill must also beat fair3 on the hidden rings (by its mean); else fair3
    if fair3 beats fair2 there, else the library's faired fill."""
    pick = library_rule(ev)
    h = ev["hidden"]
    if pick == "conformal" and "fair3" in h and not h["conformal"] < h["fair3"]:
        return "fair3" if h["fair3"] < h["fair2"] else _faired(ev)
    return pick


def rule_lh_beats_fair3_significant(ev: dict, z: float = 2.326) -> str:
    """(a') as above, but where fair3 is significantly closer than the λ-H fill on the hidden
    rings (z standard errors)."""
    pick = library_rule(ev)
    a, se = _adv(ev, "fair3", "hidden", "conformal")
    if pick == "conformal" and -a > z * se:
        return "fair3"
    return pick


def _faired(ev: dict) -> str:
    e = dict(ev)
    e["hidden"] = {k: v for k, v in ev["hidden"].items() if k != "conformal"}
    e["sibling"] = {k: v for k, v in ev["sibling"].items() if k != "conformal"}
    return library_rule(e) if e["hidden"] or e["sibling"] else "fair2"


def rule_demoted_to_fair3(ev: dict) -> str:
    """(b) Where the λ-H fill beat fair2 on the hidden rings but is not kept (lost the
    siblings or not significant), write fair3 (its S0, nearer it) instead of fair2."""
    pick = library_rule(ev)
    h = ev["hidden"]
    if pick == "fair2" and "conformal" in h and np.isfinite(h["conformal"]) \
            and h["conformal"] < h["fair2"] and h.get("fair3", np.inf) < h["fair2"]:
        return "fair3"
    return pick


def rule_fair3_when_small(ev: dict, edges: int = 24) -> str:
    """(b') fair3 instead of fair2 on holes of at most ``edges`` boundary edges where the
    hidden rings rank fair3 first of the faired fills."""
    pick = library_rule(ev)
    h = ev["hidden"]
    if pick == "fair2" and ev["n_edges"] <= edges and h.get("fair3", np.inf) < h.get("fair2",
                                                                                      np.inf):
        return "fair3"
    return pick


def rule_faired_by_means(ev: dict) -> str:
    """(b'') the faired fill chosen by the hidden-ring means alone (no significance cut for
    fair3 against fair2)."""
    pick = library_rule(ev)
    h = ev["hidden"]
    if pick == "fair2" and not ev["shallower"] and h.get("fair3", np.inf) < h.get("fair2",
                                                                                  np.inf):
        s = ev["sibling"]
        if not s or s.get("fair3", np.inf) <= s.get("fair2", np.inf):
            return "fair3"
    return pick


def rule_demoted_by_the_cut_to_fair3(ev: dict) -> str:
    """(b-cut) fair3 where the scores alone keep the λ-H fill and only the significance cut
    drops it, and the hidden rings rank fair3 before fair2 (by their means)."""
    pick = library_rule(ev)
    h = ev["hidden"]
    if pick == "fair2" and _scores_keep(ev) and h.get("fair3", np.inf) < h.get("fair2", np.inf):
        return "fair3"
    return pick


def _scores_keep(ev: dict) -> bool:
    """The λ-H fill is kept by the scores alone (no significance cut)."""
    hidden = ev["hidden"]
    run_sib, with_lh = sibling_test_plan(hidden, shallower=ev["shallower"])
    sibling = {} if not run_sib else (ev["sibling"] if with_lh else
                                      {k: v for k, v in ev["sibling"].items()
                                       if k != "conformal"})
    return choose(hidden, sibling, crossed=ev["crossed"], shallower=ev["shallower"]).keep


def _failed_hidden(ev: dict) -> bool:
    """The hidden-ring test ran and the λ-H fill failed on its enlarged hole."""
    return not np.isfinite(ev["hidden"].get("conformal", 0.0))


def rule_failed_hidden_not_kept(ev: dict) -> str:
    """(c) A λ-H fill that failed on the hidden-ring test's hole is not kept on the sibling
    test alone: the faired fill is written (chosen as the library chooses it)."""
    pick = library_rule(ev)
    if pick == "conformal" and _failed_hidden(ev) and not ev["crossed"]:
        return _faired(ev)
    return pick


def rule_failed_hidden_beat_fair3(ev: dict) -> str:
    """(c') As (c), unless the λ-H fill also beats fair3 on the sibling holes by 2.326
    standard errors."""
    pick = library_rule(ev)
    if pick == "conformal" and _failed_hidden(ev) and not ev["crossed"]:
        a, se = _adv(ev, "fair3", "sibling", "conformal")
        return pick if a > 2.326 * se else _faired(ev)
    return pick


def rule_clean_ring_fair3(ev: dict, clean: float = 0.03) -> str:
    """(d) fair3 instead of fair2 where the ring is clean (the plane test's quadric residual
    below ``clean`` × the loop's mean edge: not a scan's noise) and the hidden rings rank
    fair3 before fair2 by their means, whatever the siblings or the significance cut."""
    pick = library_rule(ev)
    h = ev["hidden"]
    if pick == "fair2" and ev["sigma"] < clean * ev["edge"] \
            and h.get("fair3", np.inf) < h.get("fair2", np.inf):
        return "fair3"
    return pick


def rule_siblings_break_the_tie(ev: dict, z: float = 2.326) -> str:
    """(e) fair3 instead of fair2 where the hidden rings do not separate them (fair3's
    advantage within ``z`` standard errors either way) and the siblings find fair3 closer by
    more than ``z`` standard errors."""
    pick = library_rule(ev)
    if pick != "fair2" or ev["shallower"]:
        return pick
    a, se = _adv(ev, "fair2", "hidden", "fair3")
    b, sb = _adv(ev, "fair2", "sibling", "fair3")
    tied = not np.isfinite(a) or abs(a) <= z * se
    return "fair3" if tied and b > z * sb else pick


def rule_siblings_break_the_tie_clean(ev: dict, clean: float = 0.03) -> str:
    """(e-clean) (e) on a clean ring only (plane-test σ below ``clean`` × the loop's mean
    edge), as (d): written after (e) was seen to break a scan hole (scan_bunny #6)."""
    if ev["sigma"] >= clean * ev["edge"]:
        return library_rule(ev)
    return rule_siblings_break_the_tie(ev)


def rule_a_and_b(ev: dict) -> str:
    """(a') and (b) together."""
    pick = rule_lh_beats_fair3_significant(ev)
    return rule_demoted_to_fair3(ev) if pick == library_rule(ev) else pick


RULES = {"library (main 54b1d7a)": library_rule,
         "(a) λ-H must beat fair3 on the hidden rings": rule_lh_beats_fair3,
         "(a') fair3 where it beats a kept λ-H fill by 2.326 se": rule_lh_beats_fair3_significant,
         "(b) fair3 where the λ-H fill beat fair2 but was not kept": rule_demoted_to_fair3,
         "(b') fair3 on holes ≤ 24 edges where the hidden rings prefer it":
             rule_fair3_when_small,
         "(b'') fair3 by the hidden-ring means (no cut)": rule_faired_by_means,
         "(a') + (b)": rule_a_and_b,
         "(a') at z = 0 (fair3's hidden-ring mean below a kept λ-H fill's)":
             partial(rule_lh_beats_fair3_significant, z=0.0),
         "(a') at z = 1.645": partial(rule_lh_beats_fair3_significant, z=1.645),
         "(a') at z = 3.09": partial(rule_lh_beats_fair3_significant, z=3.09),
         "(b-cut) fair3 where only the significance cut dropped the λ-H fill":
             rule_demoted_by_the_cut_to_fair3,
         "(c) a λ-H fill that failed on the hidden-ring hole is not kept":
             rule_failed_hidden_not_kept,
         "(c') as (c) unless it beats fair3 on the siblings by 2.326 se":
             rule_failed_hidden_beat_fair3,
         "(d) fair3 on a clean ring (σ < 0.03 edge) where the hidden rings rank it first":
             rule_clean_ring_fair3,
         "(e) fair3 where the hidden rings tie fair2 and fair3 and the siblings prefer fair3":
             rule_siblings_break_the_tie,
         "(e-clean) (e) on a clean ring only (σ < 0.03 edge)": rule_siblings_break_the_tie_clean}


# --------------------------------------------------------------------------- replay


def outcome(row: dict, pick: str) -> float:
    """The error written by ``pick`` (a λ-H fill that fell back on the hole writes the
    library's fallback: the row's conformal error)."""
    e = row["errors"]
    if row["evidence"] is None:
        return e["conformal"]
    if pick == "conformal":
        return e["conformal"] if row["status"]["conformal_raw"] == "fallback" \
            else e["conformal_raw"]
    return e["fair" if pick == "fair2" else "fair3"]


def measures(rows: list[dict], rule) -> dict:
    """Issue 14's measures of ``rule`` over ``rows``."""
    written = np.array([outcome(r, rule(r["evidence"]) if r["evidence"] else "") for r in rows])
    e = {m: np.array([r["errors"][m] for r in rows]) for m in METHODS}
    lh = np.where([r["status"]["conformal_raw"] == "fallback" for r in rows], np.inf,
                  e["conformal_raw"])
    best = np.minimum(np.minimum(e["fair"], e["fair3"]), lh)
    faired = np.minimum(e["fair"], e["fair3"])
    chooser = np.array([r["evidence"] is not None for r in rows])
    meshes = sorted({(r["set"], r["mesh"]) for r in rows})
    per_mesh = []
    for s, m in meshes:
        idx = [i for i, r in enumerate(rows) if (r["set"], r["mesh"]) == (s, m)]
        per_mesh.append((np.median(written[idx]) / np.median(e["fair"][idx]), m))
    worst = max(per_mesh)
    ratio = written / faired
    return {"holes": len(rows), "median_cgal": float(np.nanmedian(written / e["cgal"])),
            "worst_mesh": worst, "above15": int(np.sum(ratio > 1.5)),
            "best_pick": int(np.sum(written[chooser] <= 1.01 * best[chooser])),
            "chooser": int(chooser.sum()),
            "log_regret": float(np.mean(np.log(written[chooser] / best[chooser]))),
            "above": sorted(((float(x), r["mesh"], r["hole"]) for x, r in zip(ratio, rows,
                                                                             strict=True)
                             if x > 1.5), reverse=True)}


def table(rows: list[dict]) -> str:
    # every set of the rows, in their order (session 42: holdout sets too)
    groups = [("union", rows)] + [(s, [r for r in rows if r["set"] == s])
                                  for s in dict.fromkeys(r["set"] for r in rows)]
    lines = ["| rule | set | holes | median / CGAL | worst mesh / fair2 | holes > 1.5× | "
             "best pick | mean log regret |", "|---|---|---|---|---|---|---|---|"]
    for name, rule in RULES.items():
        for g, rs in groups:
            if not rs:
                continue
            m = measures(rs, rule)
            lines.append(f"| {name} | {g} | {m['holes']} | {m['median_cgal']:.3f} | "
                         f"{m['worst_mesh'][0]:.3f} ({m['worst_mesh'][1]}) | {m['above15']} | "
                         f"{m['best_pick']}/{m['chooser']} "
                         f"({100 * m['best_pick'] / max(m['chooser'], 1):.0f} %) | "
                         f"{m['log_regret']:.4f} |")
    return "\n".join(lines)


def changed(rows: list[dict], rule) -> list[str]:
    """The holes whose written fill ``rule`` changes from the library's."""
    out = []
    for r in rows:
        if r["evidence"] is None:
            continue
        a, b = library_rule(r["evidence"]), rule(r["evidence"])
        if a != b:
            before, after = outcome(r, a), outcome(r, b)
            out.append(f"{r['set']} {r['mesh']} #{r['hole']} ({r['evidence']['n_edges']} "
                       f"edges): {a} {before:.3f} → {b} {after:.3f} ({after / before:.2f}×)")
    return out


def _t(ev: dict, ref: str, test: str, name: str) -> str:
    a, se = _adv(ev, ref, test, name)
    return "—" if not np.isfinite(a) or not se > 0 else f"{a / se:+.1f}"


def misses(rows: list[dict], above: float = 1.1) -> str:
    """The holes where the library's written fill is above ``above`` × the best candidate,
    with both tests' scores (relative to fair2's) and the advantages in standard errors."""
    lines = ["| hole | edges | fair2 | fair3 | λ-H | written | / best | / better faired | "
             "hidden f3/f2, λ-H/f2 | siblings f3/f2, λ-H/f2 | t hidden: f3, λ-H over f2 | "
             "t hidden: λ-H over f3 | t siblings: f3, λ-H over f2 |", "|---" * 13 + "|"]
    out = []
    for r in rows:
        ev = r["evidence"]
        if ev is None:
            continue
        e = r["errors"]
        lh = np.inf if r["status"]["conformal_raw"] == "fallback" else e["conformal_raw"]
        best = min(e["fair"], e["fair3"], lh)
        pick = library_rule(ev)
        w = outcome(r, pick)
        if not w > above * best:
            continue

        def rel(t, ev=ev):
            d = ev[t]
            if "fair2" not in d or not d["fair2"] > 0:
                return "—"
            return (f"{d.get('fair3', np.nan) / d['fair2']:.2f}, "
                    f"{d.get('conformal', np.nan) / d['fair2']:.2f}")
        out.append((w / min(e["fair"], e["fair3"]), f"| {r['set']} {r['mesh']} #{r['hole']} | "
                    f"{ev['n_edges']} | {e['fair']:.3f} | {e['fair3']:.3f} | {lh:.3f} | {pick} | "
                    f"{w / best:.2f} | {w / min(e['fair'], e['fair3']):.2f} | {rel('hidden')} | "
                    f"{rel('sibling')} | {_t(ev, 'fair2', 'hidden', 'fair3')}, "
                    f"{_t(ev, 'fair2', 'hidden', 'conformal')} | "
                    f"{_t(ev, 'fair3', 'hidden', 'conformal')} | "
                    f"{_t(ev, 'fair2', 'sibling', 'fair3')}, "
                    f"{_t(ev, 'fair2', 'sibling', 'conformal')} |"))
    return "\n".join(lines + [x for _, x in sorted(out, reverse=True)])


# --------------------------------------------------------------------------- signals
# session 40: on scans, where the library writes fair2, which truth-free number tells the
# holes where fair3 is 1.5x closer ("missed") from those where fair2 is 1.5x closer


def signals(row: dict) -> dict[str, float]:
    """A row's truth-free signals (nan where a test did not run): the two tests' fair3 / fair2
    scores and fair3's advantages in standard errors, the plane test's curvature p-value
    (log10) and noise σ per loop edge, the two faired fills' distance (rms, max) in σ and
    per edge, the hole's radius in σ, its boundary edges, and whether it is near the border."""
    ev = row["evidence"]
    hidden, sibling = ev["hidden"], ev["sibling"]
    sigma, edge = np.float64(ev["sigma"]), np.float64(ev["edge"])  # σ 0: inf, not an error

    def ratio(scores: dict) -> float:
        return scores["fair3"] / scores["fair2"] if {"fair2", "fair3"} <= set(scores) \
            else np.nan

    def t(test: str) -> float:
        a, se = _adv(ev, "fair2", test, "fair3")
        return a / se if np.isfinite(a) and se > 0 else np.nan

    with np.errstate(divide="ignore", invalid="ignore"):
        return {"hidden f3/f2": ratio(hidden), "sibling f3/f2": ratio(sibling),
                "t hidden f3": t("hidden"), "t sibling f3": t("sibling"),
                "log10 p curvature": float(np.log10(max(ev.get("p_curvature", np.nan),
                                                        1e-300))),
                "sigma / edge": sigma / edge,
                "fair2-fair3 rms / sigma": ev.get("fair23_rms", np.nan) / sigma,
                "fair2-fair3 max / sigma": ev.get("fair23_max", np.nan) / sigma,
                "fair2-fair3 rms / edge": ev.get("fair23_rms", np.nan) / edge,
                "radius / sigma": row["radius_h"] * edge / sigma,
                "boundary edges": float(ev["n_edges"]),
                "near border": float(row.get("near_border", np.nan))}


def best_threshold(values: np.ndarray, ratio: np.ndarray) -> dict | None:
    """The one-sided threshold on ``values`` that, writing fair3 instead of fair2 on its
    side, catches the most holes where fair3 is 1.5x closer (``ratio`` = fair2 / fair3 error
    >= 1.5) less those where fair2 is 1.5x closer (ratio <= 1/1.5), fewest switched on a tie;
    None where no threshold catches one."""
    best = None
    for threshold in np.unique(values[np.isfinite(values)]):
        for side in (">=", "<="):
            switched = values >= threshold if side == ">=" else values <= threshold
            caught = int((switched & (ratio >= 1.5)).sum())
            broken = int((switched & (ratio <= 1 / 1.5)).sum())
            key = (caught - broken, -int(switched.sum()))
            if caught and (best is None or key > best["key"]):
                best = {"key": key, "side": side, "threshold": float(threshold),
                        "switched": int(switched.sum()), "caught": caught, "broken": broken}
    return best


def screen(rows: list[dict]) -> str:
    """Each signal's best threshold over the scan holes where the library writes fair2."""
    picked = [r for r in rows if r["kind"] == "range_scan" and r["evidence"] is not None
              and library_rule(r["evidence"]) == "fair2"]
    ratio = np.array([r["errors"]["fair"] / r["errors"]["fair3"] for r in picked])
    table = [signals(r) for r in picked]
    lines = [f"{len(picked)} scan holes where fair2 is written: fair3 1.5x closer on "
             f"{int((ratio >= 1.5).sum())}, fair2 1.5x closer on "
             f"{int((ratio <= 1 / 1.5).sum())}", "",
             "| signal | best threshold | holes switched to fair3 | fair3 1.5× closer among "
             "them | fair2 1.5× closer among them |", "|---|---|---|---|---|"]
    for name in table[0] if table else []:
        best = best_threshold(np.array([s[name] for s in table], float), ratio)
        if best is None:
            lines.append(f"| {name} | — | 0 | 0 | 0 |")
            continue
        lines.append(f"| {name} | {best['side']} {best['threshold']:.3g} | {best['switched']} "
                     f"| {best['caught']} | {best['broken']} |")
    return "\n".join(lines)


# session 42: where the library keeps the λ-H fill, which truth-free number tells the holes
# where it is 1.5x farther than the faired fill a veto would write from those where it is
# 1.5x closer


def kept_signals(row: dict) -> dict[str, float]:
    """A kept λ-H fill's truth-free signals from its row's evidence (nan where a test did not
    score it): its advantage in standard errors over fair2 and over fair3 on each test, its
    score over the better faired fill's on each test, the two tests' disagreement (the log of
    the hidden-ring ratio over the siblings' ratio), whether it failed on the hidden-ring hole,
    the hole's boundary edges, the plane test's curvature p-value (log10), its noise σ per
    loop edge, and the two faired fills' rms distance per edge."""
    ev = row["evidence"]

    def t(ref: str, test: str) -> float:
        a, se = _adv(ev, ref, test, "conformal")
        return a / se if np.isfinite(a) and se > 0 else np.nan

    def over_faired(scores: dict) -> float:
        faired = min(scores.get("fair2", np.nan), scores.get("fair3", np.nan))
        lh = scores.get("conformal", np.nan)
        return lh / faired if faired > 0 and np.isfinite(lh) else np.nan

    hidden, sibling = over_faired(ev["hidden"]), over_faired(ev["sibling"])
    with np.errstate(divide="ignore", invalid="ignore"):
        return {"t hidden λ-H over fair2": t("fair2", "hidden"),
                "t hidden λ-H over fair3": t("fair3", "hidden"),
                "t siblings λ-H over fair2": t("fair2", "sibling"),
                "t siblings λ-H over fair3": t("fair3", "sibling"),
                "hidden λ-H / better faired": hidden, "siblings λ-H / better faired": sibling,
                "log hidden / siblings ratio": float(np.log(hidden / sibling)),
                "failed on the hidden rings": float(_failed_hidden(ev)),
                "boundary edges": float(ev["n_edges"]),
                "log10 p curvature": float(np.log10(max(ev.get("p_curvature", np.nan),
                                                        1e-300))),
                "sigma / edge": ev["sigma"] / ev["edge"],
                "fair2-fair3 rms / edge": ev.get("fair23_rms", np.nan) / ev["edge"]}


def screen_kept(rows: list[dict]) -> str:
    """Each :func:`kept_signals` signal's best one-sided threshold (:func:`best_threshold`)
    over the holes where the library keeps the λ-H fill: vetoing it writes the faired fill
    the library would choose without it (:func:`_faired`), catching holes where the λ-H fill
    is 1.5x farther than that fill ("losses caught") less those where it is 1.5x closer
    ("wins lost")."""
    kept = [r for r in rows if r["evidence"] is not None
            and library_rule(r["evidence"]) == "conformal"]
    ratio = np.array([outcome(r, "conformal") / outcome(r, _faired(r["evidence"]))
                      for r in kept])
    table = [kept_signals(r) for r in kept]
    lines = [f"{len(kept)} holes where the λ-H fill is kept: 1.5x farther than the faired "
             f"fill a veto writes on {int((ratio >= 1.5).sum())}, 1.5x closer on "
             f"{int((ratio <= 1 / 1.5).sum())}", "",
             "| signal | threshold (veto side) | vetoed | losses caught | wins lost |",
             "|---|---|---|---|---|"]
    for name in table[0] if table else []:
        best = best_threshold(np.array([s[name] for s in table], float), ratio)
        lines.append(f"| {name} | — | 0 | 0 | 0 |" if best is None else
                     f"| {name} | {best['side']} {best['threshold']:.3g} | "
                     f"{best['switched']} | {best['caught']} | {best['broken']} |")
    return "\n".join(lines)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--set", choices=(*SETS, "animals"))
    parser.add_argument("--manifest", type=Path, default=None,
                        help="a holes manifest instead of --set (its rows' set: the file's "
                        "name before _manifest)")
    parser.add_argument("--holes", default=None, help="comma-separated holes, mesh#k")
    parser.add_argument("--out", type=Path)
    parser.add_argument("--samples", type=int, default=10000)
    parser.add_argument("--meshes", default=None, help="comma-separated mesh ids of the set")
    parser.add_argument("--replay", nargs="+", default=None)
    parser.add_argument("--changes", action="store_true")
    parser.add_argument("--misses", action="store_true")
    parser.add_argument("--screen", action="store_true",
                        help="with --replay: each truth-free signal's best threshold (scans)")
    parser.add_argument("--screen-kept", action="store_true",
                        help="with --replay: each signal's best threshold for vetoing a kept "
                        "λ-H fill")
    args = parser.parse_args(argv)
    if args.replay:
        rows = read(*args.replay)
        bad = [r for r in rows if r["evidence"] is not None and not np.isclose(
            outcome(r, library_rule(r["evidence"])), r["errors"]["conformal"], rtol=1e-9)]
        print(f"{len(rows)} holes; the library's choice replayed differs from its written "
              f"fill on {len(bad)}: " + ", ".join(f"{r['mesh']} #{r['hole']}" for r in bad))
        print(table(rows))
        if args.misses:
            print("\n" + misses(rows))
        if args.screen:
            print("\n" + screen(rows))
        if args.screen_kept:
            print("\n" + screen_kept(rows))
        if args.changes:
            for name, rule in list(RULES.items())[1:]:
                print(f"\n{name}:")
                print("\n".join(changed(rows, rule)) or "(none)")
        return
    which = args.set
    if args.manifest is not None:
        which = args.manifest.name.removesuffix(".json").removesuffix("_manifest")
        SETS[which] = args.manifest
    holes = set(args.holes.split(",")) if args.holes else None
    # only the listed holes' meshes are loaded (a holdout set's scans take minutes to make)
    meshes = args.meshes.split(",") if args.meshes else \
        sorted({h.rsplit("#", 1)[0] for h in holes}) if holes else None
    run(which, args.out, args.samples, meshes, holes)


if __name__ == "__main__":
    main()
