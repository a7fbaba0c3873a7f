"""Validation benchmark: the holes of ``benchmarks/holes_manifest.json`` (32 meshes of 6 kinds,
split by mesh into a tuning and a validation half), every method, both halves reported,
validation first.

Each hole is cut (:func:`surfinpaint.geometry.cutting.cut_geodesic_disk`), filled and scored
exactly as in ``benchmarks/accuracy.py`` (its :func:`accuracy.score`: two-sided mean
distance between the fill and the removed truth, in % of the hole diameter); on simulated
range scans the truth is the removed patch without the scanner noise. Methods: ours (fair,
fair3, conformal = the default, conformal_raw = λ-H without the self-check) and the peers of
``benchmarks/peers.py`` (cgal, cgal3, meshlib, pymeshlab, pymeshfix).

Run (one hole at a time, nothing parallel)::

    .venv/bin/python benchmarks/validation.py --out validation.json      # all 224 holes
    .venv/bin/python benchmarks/validation.py --quick                     # 6 holes, smoke
    .venv/bin/python benchmarks/validation.py --tables validation.json    # tables again
    .venv/bin/python benchmarks/validation.py --manifest benchmarks/holdout_manifest.json \
        --out holdout.json        # a holdout set: holdout_manifest.json, holdout2_ ... holdout29_

Every row is also appended to ``<out>.partial.jsonl`` as it is made, so the tables of a run
that was stopped can be printed with ``--tables <out>.partial.jsonl``.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
import traceback
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import accuracy  # noqa: E402
import holes_manifest  # noqa: E402
import peers  # noqa: E402
import validation_meshes as vm  # noqa: E402

from surfinpaint.geometry.cutting import cut_geodesic_disk  # noqa: E402
from surfinpaint.geometry.mesh import mean_edge_length  # noqa: E402

OURS = ("fair", "fair3", "fair_sfauto", "conformal", "conformal_raw")
PEERS = ("cgal", "cgal3", "meshlib", "pymeshlab", "pymeshfix")
METHODS = OURS + PEERS
DEFAULT = "conformal"
# what the self-check chooses among: its bilaplacian candidate is smoothed where the noise
# gate opens (session 45), the `fair_sfauto` column; runs made before that column existed
# score the plain `fair` column in its place
CANDIDATES = ("fair_sfauto", "fair3", "conformal_raw")
OLD_FAIR2 = "fair"
FILLED = ("ok", "selected", "fallback")
# reported in this order: the validation half first, then the holdout sets (fresh meshes,
# benchmarks/holdout_manifest.json, holdout2_manifest.json to holdout29_manifest.json), then
# the tuning half every rule was chosen on
SPLITS = ("validation", "holdout", "holdout2", "holdout3", "holdout4", "holdout5", "holdout6",
          "holdout7", "holdout8", "holdout9", "holdout10", "holdout11", "holdout12", "holdout13",
          "holdout14", "holdout15", "holdout16", "holdout17", "holdout18", "holdout19",
          "holdout20", "holdout21", "holdout22", "holdout23", "holdout24", "holdout25",
          "holdout26", "holdout27", "holdout28", "holdout29", "tuning", "cad_tuning",
          "smooth_tuning", "curved_scans", "thin_shells")
SPLIT_NAMES = {"holdout": "Holdout set", "holdout2": "Holdout set 2",
               "holdout3": "Holdout set 3", "holdout4": "Holdout set 4",
               "holdout5": "Holdout set 5", "holdout6": "Holdout set 6",
               "holdout7": "Holdout set 7", "holdout8": "Holdout set 8",
               "holdout9": "Holdout set 9", "holdout10": "Holdout set 10",
               "holdout11": "Holdout set 11", "holdout12": "Holdout set 12",
               "holdout13": "Holdout set 13", "holdout14": "Holdout set 14",
               "holdout15": "Holdout set 15", "holdout16": "Holdout set 16",
               "holdout17": "Holdout set 17", "holdout18": "Holdout set 18",
               "holdout19": "Holdout set 19", "holdout20": "Holdout set 20",
               "holdout21": "Holdout set 21", "holdout22": "Holdout set 22",
               "holdout23": "Holdout set 23", "holdout24": "Holdout set 24",
               "holdout25": "Holdout set 25", "holdout26": "Holdout set 26",
               "holdout27": "Holdout set 27", "holdout28": "Holdout set 28",
               "holdout29": "Holdout set 29",
               "cad_tuning": "Tuning-side CAD parts",
               "smooth_tuning": "Tuning-side smooth tubes and organic bodies",
               "curved_scans": "Tuning-side range scans of curved shapes",
               "thin_shells": "Tuning-side thin smooth walls with saddle-shaped parts"}


def _cut(mesh: vm.BenchMesh, hole: dict):
    cut = cut_geodesic_disk(mesh.vertices, mesh.faces, np.asarray(hole["centre"]),
                            hole["radius"])
    if mesh.truth is None:
        return cut
    h = cut.holes[0]  # range scan: compare with the noise-free surface
    return replace(cut, holes=[replace(h, truth_vertices=mesh.truth[h.truth_ids])])


def loaded_or_none(entry: dict, label: str | None = None) -> vm.BenchMesh | None:
    """The mesh of a manifest entry, checked against it (:func:`validation_meshes.load_entry`),
    or None with a note on stderr where this machine cannot make it (a source that is not
    installed, or a mesh made with other bytes than the manifest's): its holes are skipped,
    and said so."""
    try:
        return vm.load_entry(entry)
    except (FileNotFoundError, ModuleNotFoundError, RuntimeError) as exc:
        print(f"note: skipping {label or entry['mesh']}: {exc}", file=sys.stderr)
        return None


def run(manifest: dict, methods: list[str], samples: int, partial: Path | None,
        meshes: list[str] | None = None, max_holes: int | None = None) -> list[dict]:
    rows = []
    # the validation half first: the numbers that count are there even if a run is cut short
    order = sorted(manifest["meshes"], key=lambda e: e["split"] != "validation")
    for entry in order:
        if meshes and entry["mesh"] not in meshes:
            continue
        mesh = loaded_or_none(entry)
        if mesh is None:
            continue
        h = mean_edge_length(mesh.vertices, mesh.faces)
        for k, hole in enumerate(entry["holes"][:max_holes]):
            cut = _cut(mesh, hole)
            for m in methods:
                try:
                    row = accuracy.score(cut, m, entry["mesh"], k, hole["radius"] / h, samples)
                except Exception as exc:  # noqa: BLE001 - a scoring bug must not end a long
                    # run: the row says so (status "error") and the traceback is printed
                    traceback.print_exc(limit=4, file=sys.stderr)
                    row = accuracy.Row(case=entry["mesh"], hole=k, radius_h=hole["radius"] / h,
                                       boundary_edges=len(cut.loop), diameter=cut.diameter,
                                       method=m, status="error",
                                       note=f"scoring: {type(exc).__name__}: {exc}"[:200])
                row.extra = {"kind": entry["kind"], "split": entry["split"],
                             "near_border": hole["near_border"],
                             "on_feature": hole["on_feature"]}
                d = asdict(row)
                rows.append(d)
                if partial is not None:
                    with partial.open("a") as fh:
                        fh.write(json.dumps(d, default=float) + "\n")
                print(f"{entry['mesh']} #{k} r={hole['radius_h']}h {m}: {row.status} "
                      f"mean {accuracy._fmt(row.mean_pct)} % in {accuracy._fmt(row.seconds)} s"
                      f"{' ' + row.note if row.note else ''}", file=sys.stderr, flush=True)
    return rows


# --------------------------------------------------------------------------- tables


def _errors(rows: list[dict]) -> dict:
    """{(method, mesh, hole): mean %} of the filled rows."""
    return {(r["method"], r["case"], r["hole"]): r["mean_pct"] for r in rows
            if r["status"] in FILLED and np.isfinite(r["mean_pct"])}


def _med(x) -> float:
    return float(np.median(x)) if len(x) else float("nan")


def _f(x: float, d: int = 3) -> str:
    return accuracy._fmt(x, d)


def headline(rows: list[dict], methods: list[str]) -> dict:
    """The numbers of issue 14's targets for one half (see docs/validation.md)."""
    err = _errors(rows)
    holes = sorted({(r["case"], r["hole"]) for r in rows})
    meshes = list(dict.fromkeys(r["case"] for r in rows))
    out: dict = {"meshes": len(meshes), "holes": len(holes)}

    def ratio(a: str, b: str, keys) -> list[float]:
        return [err[(a, *k)] / err[(b, *k)] for k in keys
                if (a, *k) in err and (b, *k) in err and err[(b, *k)] > 1e-6]

    out["default_over_cgal_per_hole"] = _med(ratio(DEFAULT, "cgal", holes))
    for flag in ("near_border", "on_feature"):
        keys = sorted({(r["case"], r["hole"]) for r in rows if r["extra"][flag]})
        out[f"default_over_cgal_{flag}"] = (_med(ratio(DEFAULT, "cgal", keys)), len(keys))
    # every method the tables name, present or not: a file without the peers' rows (a run
    # of ours only) gets NaN in their columns instead of stopping the table
    named = list(dict.fromkeys([*methods, "cgal", "fair", DEFAULT]))
    per_mesh = {m: {meth: _med([err[(meth, c, k)] for c, k in holes
                                if c == m and (meth, c, k) in err]) for meth in named}
                for m in meshes}
    out["per_mesh"] = per_mesh
    out["default_over_cgal_median_mesh"] = _med(
        [per_mesh[m][DEFAULT] / per_mesh[m]["cgal"] for m in meshes
         if per_mesh[m]["cgal"] > 1e-6 or not np.isfinite(per_mesh[m]["cgal"])])
    present = [p for p in PEERS if p in methods]
    wins = [m for m in meshes if all(per_mesh[m][DEFAULT] <= per_mesh[m][p] or
                                     not np.isfinite(per_mesh[m][p]) for p in present)]
    out["default_best_of_peers"] = (len(wins), len(meshes)) if present else None
    # the same per hole: steadier than a median of seven, which one hole can tip
    scored = [k for k in holes if (DEFAULT, *k) in err]
    closest = [k for k in scored if all(err[(DEFAULT, *k)] <= err.get((p, *k), np.inf)
                                        for p in present)]
    out["default_best_of_peers_per_hole"] = (len(closest), len(scored)) if present else None
    vs_fair = {m: per_mesh[m][DEFAULT] / per_mesh[m]["fair"] for m in meshes
               if per_mesh[m]["fair"] > 1e-6}
    worst = max(vs_fair, key=vs_fair.get) if vs_fair else None
    out["worst_mesh_vs_fair"] = (worst, vs_fair.get(worst, float("nan")))
    out["meshes_above_1.1_fair"] = sorted(m for m, x in vs_fair.items() if x > 1.1)
    faired = {k: min(err[(m, *k)] for m in ("fair", "fair3") if (m, *k) in err)
              for k in holes if any((m, *k) in err for m in ("fair", "fair3"))}
    vs_faired = {k: err[(DEFAULT, *k)] / faired[k] for k in holes
                 if (DEFAULT, *k) in err and k in faired and faired[k] > 1e-6}
    wk = max(vs_faired, key=vs_faired.get) if vs_faired else None
    out["worst_hole_vs_better_faired"] = (wk, vs_faired.get(wk, float("nan")))
    out["holes_above_1.5_faired"] = sum(x > 1.5 for x in vs_faired.values())
    for meth in ("conformal", "conformal_raw"):
        mine = [r for r in rows if r["method"] == meth]
        fell = [r["note"].split(": ", 1)[-1] for r in mine if r["status"] == "fallback"]
        reasons: dict[str, int] = {}
        for note in fell:
            key = note[:100]
            reasons[key] = reasons.get(key, 0) + 1
        out[f"{meth}_fallback"] = (len(fell), len(mine), reasons)
    # the self-check as a chooser among its candidates, where it ran (not where the plane
    # test laid the faired fill on the plane)
    planar = {(r["case"], r["hole"]) for r in rows
              if r["method"] == DEFAULT and r["note"] == accuracy.PLANE_NOTE}
    out["plane_holes"] = len(planar)
    chosen_best, regret, oracle = 0, [], []
    old_fair2 = not any(r["method"] == CANDIDATES[0] for r in rows)
    names = (OLD_FAIR2, *CANDIDATES[1:]) if old_fair2 else CANDIDATES
    out["chooser_candidates"] = names
    for k in holes:
        if not all((m, *k) in err for m in names):
            continue
        cands = [err[(m, *k)] for m in names]
        if ("cgal", *k) in err and err[("cgal", *k)] > 1e-6:
            oracle.append(min(cands) / err[("cgal", *k)])
        best = min(cands)
        if k in planar or (DEFAULT, *k) not in err or best <= 1e-6:
            continue
        r = err[(DEFAULT, *k)] / best
        regret.append(r)
        chosen_best += r <= 1.01
    out["chooser_best"] = (chosen_best, len(regret))
    out["chooser_median_regret"] = _med(regret)
    out["oracle_over_cgal"] = _med(oracle)
    out["seconds"] = {meth: (_med([r["seconds"] for r in rows if r["method"] == meth
                                   and r["status"] in FILLED]),
                             _med([r["seconds"] for r in rows if r["method"] == meth
                                   and r["status"] in FILLED and r["boundary_edges"] <= 100]),
                             max([r["seconds"] for r in rows if r["method"] == meth
                                  and r["status"] in FILLED], default=float("nan")),
                             # the fill's CPU seconds (runs before session 48 have none)
                             _med([r["cpu_seconds"] for r in rows if r["method"] == meth
                                   and r["status"] in FILLED and "cpu_seconds" in r]))
                      for meth in methods}
    out["failed"] = {meth: sum(r["status"] in ("failed", "open", "error") for r in rows
                               if r["method"] == meth) for meth in methods}
    return out


def report(rows: list[dict], methods: list[str], split: str) -> str:
    part = [r for r in rows if r["extra"]["split"] == split]
    name = SPLIT_NAMES.get(split, f"{split.capitalize()} half")
    if not part:
        return f"## {name}: no rows\n"
    hl = headline(part, methods)
    kinds = {r["case"]: r["extra"]["kind"] for r in part}
    lines = [f"## {name}: {hl['meshes']} meshes, {hl['holes']} holes\n"]
    best_of_peers = hl["default_best_of_peers"]
    wins = (f"{best_of_peers[0]} / {best_of_peers[1]} "
            f"({100 * best_of_peers[0] / max(best_of_peers[1], 1):.0f} %)" if best_of_peers
            else "— (no peers' rows)")
    per_hole = hl["default_best_of_peers_per_hole"]
    hole_wins = (f"{per_hole[0]} / {per_hole[1]} ({100 * per_hole[0] / max(per_hole[1], 1):.0f} %)"
                 if per_hole else "—")
    wm, wmr = hl["worst_mesh_vs_fair"]
    wh, whr = hl["worst_hole_vs_better_faired"]
    cb, cn = hl["chooser_best"]
    lines += [
        "| measure (default = conformal) | value | target |",
        "|---|---|---|",
        f"| per-hole median error / CGAL | {_f(hl['default_over_cgal_per_hole'])} | ≤ 0.67 |",
        f"| same, holes near a border ({hl['default_over_cgal_near_border'][1]}) | "
        f"{_f(hl['default_over_cgal_near_border'][0])} | |",
        f"| same, holes on a sharp edge or corner ({hl['default_over_cgal_on_feature'][1]}) | "
        f"{_f(hl['default_over_cgal_on_feature'][0])} | |",
        f"| median over meshes of (mesh median / CGAL's) | "
        f"{_f(hl['default_over_cgal_median_mesh'])} | |",
        f"| meshes where the default is most accurate of all peers (per-mesh median) | "
        f"{wins} | ≥ 80 % |",
        f"| holes where the default is the closest of all peers | {hole_wins} | |",
        f"| worst mesh median / bilaplacian (fair) | {_f(wmr)} ({wm}) | ≤ 1.1 |",
        f"| meshes above 1.1 × fair | {', '.join(hl['meshes_above_1.1_fair']) or 'none'} | |",
        f"| worst hole / better faired fill (min fair, fair3) | {_f(whr)} "
        f"({wh[0]} #{wh[1]}) | ≤ 1.5 |" if wh else "| worst hole | — | |",
        f"| holes above 1.5 × the better faired fill | {hl['holes_above_1.5_faired']} | 0 |",
    ]
    for meth in ("conformal", "conformal_raw"):
        k, t, _ = hl[f"{meth}_fallback"]
        lines.append(f"| {meth}: λ-H failed, fell back | {k} / {t} "
                     f"({100 * k / max(t, 1):.1f} %) | ≤ 2 % |")
    lines += [
        f"| holes laid on their plane by the plane test (no self-check) | "
        f"{hl['plane_holes']} | |",
        f"| self-check picks the best of {'/'.join(hl['chooser_candidates'])} (within 1 %) | "
        f"{cb} / {cn} ({100 * cb / max(cn, 1):.0f} %) | ≥ 70 % |",
        f"| self-check median regret (chosen / best candidate) | "
        f"{_f(hl['chooser_median_regret'])} | ≤ 1.05 |",
        f"| perfect chooser among the candidates / CGAL (per-hole median) | "
        f"{_f(hl['oracle_over_cgal'])} | |",
        "",
        "λ-H fallback reasons (conformal): " + ("; ".join(
            f"{v}× {k}" for k, v in hl["conformal_fallback"][2].items()) or "none"),
        "",
        "| mesh | kind | " + " | ".join(methods) + " | default / cgal |",
        "|---|---|" + "---|" * (len(methods) + 1),
    ]
    for mesh, med in hl["per_mesh"].items():
        best = min((med[p] for p in methods if np.isfinite(med[p])), default=np.nan)
        cells = [f"**{_f(med[m])}**" if med[m] == best else _f(med[m]) for m in methods]
        ratio = med[DEFAULT] / med["cgal"] if med.get("cgal", 0) > 1e-6 else float("nan")
        lines.append(f"| {mesh} | {kinds[mesh]} | " + " | ".join(cells) + f" | {_f(ratio)} |")
    lines += ["", "| method | median s per hole | median CPU s per hole | median s, ≤ 100 "
              "edges | max s | failed/open/error |",
              "|---|---|---|---|---|---|"]
    for meth in methods:
        a, b2, c, cpu = hl["seconds"][meth]
        lines.append(f"| {meth} | {_f(a)} | {_f(cpu)} | {_f(b2)} | {_f(c)} "
                     f"| {hl['failed'][meth]} |")
    return "\n".join(lines) + "\n"


def tables(rows: list[dict], methods: list[str]) -> str:
    methods = [m for m in methods if any(r["method"] == m for r in rows)]
    head = ("Per-mesh cells: median over the mesh's holes of the two-sided mean distance, % of "
            "the hole diameter; bold: the best method of the row.\n")
    present = [s for s in SPLITS if any(r["extra"]["split"] == s for r in rows)]
    return head + "\n" + "\n".join(report(rows, methods, s)
                                    for s in present or ["validation", "tuning"])


def main(argv: list[str] | None = None) -> list[dict]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true",
                        help="smoke test: the first hole of one small mesh per kind")
    parser.add_argument("--methods", default=",".join(METHODS))
    parser.add_argument("--meshes", default=None, help="comma-separated mesh ids")
    parser.add_argument("--samples", type=int, default=10000)
    parser.add_argument("--manifest", default=str(holes_manifest.MANIFEST),
                        help="the holes (default: both halves; benchmarks/"
                        "holdout_manifest.json, holdout2_manifest.json, "
                        "holdout3_manifest.json, holdout4_manifest.json, "
                        "holdout5_manifest.json, holdout6_manifest.json, "
                        "holdout7_manifest.json, holdout8_manifest.json, "
                        "holdout9_manifest.json, holdout10_manifest.json, "
                        "holdout11_manifest.json, holdout12_manifest.json, "
                        "holdout13_manifest.json, holdout14_manifest.json, "
                        "holdout15_manifest.json, holdout16_manifest.json, "
                        "holdout17_manifest.json, holdout18_manifest.json, "
                        "holdout19_manifest.json, holdout20_manifest.json, "
                        "holdout21_manifest.json, holdout22_manifest.json, "
                        "holdout23_manifest.json, holdout24_manifest.json, "
                        "holdout25_manifest.json, holdout26_manifest.json, "
                        "holdout27_manifest.json, holdout28_manifest.json, "
                        "holdout29_manifest.json: the holdout sets)")
    parser.add_argument("--out", default=None, help="write all rows as JSON here")
    parser.add_argument("--tables", default=None,
                        help="print the tables of a saved run (.json or .partial.jsonl)")
    args = parser.parse_args(argv)
    methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    unknown = [m for m in methods if m not in accuracy.ALL_METHODS + PEERS]
    if unknown:
        parser.error(f"unknown methods {unknown}")
    if args.tables:
        text = Path(args.tables).read_text()
        rows = (json.loads(text)["rows"] if args.tables.endswith(".json")
                else [json.loads(line) for line in text.splitlines() if line.strip()])
        print(tables(rows, methods))
        return rows
    manifest = holes_manifest.read(Path(args.manifest))
    meshes = [m.strip() for m in args.meshes.split(",")] if args.meshes else None
    max_holes = None
    if args.quick:
        meshes = meshes or ["scan_wuson", "tooth", "blob_c", "nut", "inflated", "peanut"]
        max_holes = 1
    partial = Path(args.out + ".partial.jsonl") if args.out else None
    if partial is not None and partial.exists():
        partial.unlink()
    accuracy.warm_up(methods)
    started = time.perf_counter()
    rows = run(manifest, methods, args.samples, partial, meshes, max_holes)
    total = time.perf_counter() - started
    print(tables(rows, methods))
    print(f"\npeers: {peers.versions()}; python {platform.python_version()}; "
          f"total {total:.1f} s")
    if args.out:
        Path(args.out).write_text(json.dumps(
            {"rows": rows, "versions": peers.versions(), "quick": args.quick,
             "seconds": total}, indent=1, default=float))
    return rows


if __name__ == "__main__":
    main()
