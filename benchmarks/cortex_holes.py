"""Cortex holes: where the self-check keeps the λ-H fill and fair3 (or fair2) is closer, and
whether a truth-free signal of the known surface tells those holes (session 52, helper).

Rows: ``selfcheck_table.py --library``'s (each candidate's true error, both tests' scores
with every candidate, the candidates' distances, what the library wrote and why) with
``rim``: measures of the known surface around the hole, made here from the neighbourhood
``fill_holes`` hands the conformal method (:func:`rim_measures`; no truth):

- ``radius_edges``: the loop's mean distance from its centroid over the mean edge length;
- ``curvature_radius``: the RMS mean curvature H over the first ``RIM_RINGS`` rings, times
  that radius (how many folds of the surface the hole spans);
- ``rim_h_variation``: the total variation of H along the loop (H of each loop vertex taken
  from its first-ring neighbours) per loop vertex, over that RMS (how fast H changes along
  the rim: a rim crossing sulci and gyri against one along a fold);
- ``rim_h_spread``: the standard deviation of H along the loop over that RMS;
- ``rim_h_sign_changes``: how often H changes sign along the loop (convex to concave: a
  rim crossing sulci and gyri);
- ``normal_spread``: 1 − |mean unit normal of the loop vertices|.

Parts (fixed before any rule was tried): **A**, where thresholds are chosen: the tuning
half's fsaverage5 pial and white (left hemisphere) and holdouts 11–19's synthetic cortices;
**B**, where they are checked: holdouts 20–27's. No other set has a brain-kind mesh on the
tuning side.

    # the rows (one JSONL per set; brain meshes; the tuning half's, holdouts 11-27's)
    python benchmarks/cortex_holes.py table --manifest benchmarks/holdout27_manifest.json \
        --kind brain --cache /tmp/cortex/holdout27.jsonl
    python benchmarks/cortex_holes.py table --split tuning --meshes pial,white \
        --cache /tmp/cortex/tuning_brain.jsonl
    # off the cortex (the same rows for every hole of a tuning-side set)
    python benchmarks/cortex_holes.py table --manifest benchmarks/smooth_tuning_manifest.json \
        --cache /tmp/cortex/smooth_tuning.jsonl
    # per mesh, per hole, the screen and the rules
    python benchmarks/cortex_holes.py report /tmp/cortex
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import chooser_replay as replay  # noqa: E402
import holes_manifest  # noqa: E402
import selfcheck_table as table  # noqa: E402

from surfinpaint.fill.conformal import ConformalOptions  # noqa: E402
from surfinpaint.fill.conformal.selection import Verdict, fair3_over_lambda_h  # noqa: E402
from surfinpaint.geometry.mesh import (  # noqa: E402
    boundary_loops,
    laplacian_and_areas,
    mean_edge_length,
    vertex_adjacency,
    vertex_normals,
)

RIM_RINGS = 4  # rings of known surface the rim measures read
CLOSER = 1.2  # a candidate "closer" than another: by this factor


# ------------------------------------------------------------------ the rim measures


def mean_curvature(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Signed mean curvature per vertex (cotangent Laplacian over the Voronoi area, along the
    vertex normal; positive where the surface bends away from its normal, as on a sphere
    with outward normals) and the unit vertex normals."""
    lap, areas = laplacian_and_areas(vertices, faces)
    normals = vertex_normals(vertices, faces)
    h = -np.einsum("ij,ij->i", lap @ vertices, normals) / (2.0 * np.maximum(areas, 1e-300))
    return h, normals


def rim_measures(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                 rings: int = RIM_RINGS) -> dict[str, float]:
    """The known surface around a hole, measured (the module docstring's ``rim``).

    ``loop`` is the hole's boundary loop, in order. Vertices on any border (the hole's or
    the neighbourhood's outer one) get no curvature: their cotangent sums are partial.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    loop = np.asarray(loop, dtype=np.int64)
    n = len(vertices)
    h, normals = mean_curvature(vertices, faces)
    border = np.zeros(n, dtype=bool)
    for b in boundary_loops(faces):
        border[b] = True
    adjacency = vertex_adjacency(faces, n)
    reached = np.zeros(n, dtype=bool)
    reached[loop] = True
    band_rings = []
    for _ in range(rings):
        grown = np.asarray((adjacency @ reached.astype(np.float64)) > 0).ravel() | reached
        band_rings.append(np.flatnonzero(grown & ~reached & ~border))
        reached = grown
    band = np.concatenate(band_rings)
    radius = float(np.linalg.norm(vertices[loop] - vertices[loop].mean(axis=0), axis=1).mean())
    out = {"radius_edges": radius / mean_edge_length(vertices, faces)}
    if len(band) == 0 or len(band_rings[0]) == 0:
        return {**out, "curvature_radius": math.nan, "rim_h_variation": math.nan,
                "rim_h_spread": math.nan, "rim_h_sign_changes": math.nan,
                "normal_spread": math.nan}
    rms = float(np.sqrt(np.mean(h[band] ** 2)))
    first = np.zeros(n, dtype=bool)
    first[band_rings[0]] = True
    to_first = adjacency[loop].multiply(first[None, :]).tocsr()
    counts = np.asarray(to_first.sum(axis=1)).ravel()
    h_loop = np.asarray(to_first @ np.where(first, h, 0.0)).ravel() / np.maximum(counts, 1)
    h_loop = np.where(counts > 0, h_loop, np.median(h[band]))
    tiny = rms if rms > 0 else 1.0
    out.update({
        "curvature_radius": rms * radius,
        "rim_h_variation": float(np.abs(np.diff(np.r_[h_loop, h_loop[:1]])).sum()
                                 / (len(loop) * tiny)),
        "rim_h_spread": float(np.std(h_loop) / tiny),
        "rim_h_sign_changes": float(np.sum(np.sign(h_loop) != np.sign(np.roll(h_loop, 1)))),
        "normal_spread": float(1.0 - np.linalg.norm(normals[loop].mean(axis=0))),
    })
    return out


# ------------------------------------------------------------------ the rows


def build(cache: Path, manifest: Path | None, split: str | None, meshes: list[str] | None,
          kind: str | None) -> list[dict]:
    """``selfcheck_table``'s rows with the library's choice and ``rim``, of the selected
    holes (a kind: only that kind's meshes), cached in ``cache``."""
    options = ConformalOptions()
    if kind is not None:
        source = manifest or holes_manifest.MANIFEST
        picked = [e["mesh"] for e in holes_manifest.read(source)["meshes"]
                  if e.get("kind") == kind and (split is None or e["split"] == split)
                  and (meshes is None or e["mesh"] in meshes)]
        meshes = picked
        if not meshes:
            return []

    def compute(entry, k, hole, cut, local):
        row = table.hole_scores(local.vertices, local.faces, local.local_loop,
                                cut.truth_vertices, cut.truth_faces, cut.diameter,
                                options=options)
        row = {"mesh": entry["mesh"], "hole": k, "split": entry["split"],
               "kind": entry["kind"], "n_edges": len(cut.loop), **row,
               "library": table.library_row(cut),
               "rim": rim_measures(local.vertices, local.faces, local.local_loop)}
        print(f"{entry['split']} {entry['mesh']} #{k}: written {replay.written(row)}",
              file=sys.stderr, flush=True)
        return row

    manifest = manifest or holes_manifest.MANIFEST
    # the study guard on the whole selection before any mesh is made (never the validation
    # half nor a fresh holdout: cgal_s0._studied)
    list(table._manifest_holes(split, meshes, manifest))
    return table.cached_rows(cache, split, meshes, options, compute, manifest)


PART_A_LAST_HOLDOUT = 19  # part A: the tuning half and holdouts up to this; B: the later
RATIOS = (0.9, 0.95, 1.0, 1.05, 1.1, 1.2)  # lambda_h_over_fair3, the grid replayed on part A


def part(row: dict) -> str:
    """"A" (thresholds chosen here) or "B" (checked here): the module docstring's parts."""
    split = row["split"]
    return "A" if not split.startswith("holdout") or \
        int(split[7:]) <= PART_A_LAST_HOLDOUT else "B"


def written_with(row: dict, ratio: float | None) -> str:
    """What the library writes on the row's hole with ``lambda_h_over_fair3=ratio`` (None:
    the default), replayed: its written fill, given up for fair3 where
    :func:`~surfinpaint.fill.conformal.selection.fair3_over_lambda_h` says so on the
    table's hidden-ring scores. Holes without a three-way choice keep theirs."""
    wrote = replay.written(row)
    if ratio is None or wrote != "conformal" or row["failure"]:
        return wrote
    lib = row["library"]
    verdict = lib["verdict"] or {}
    shallower = "one ring shallower" in (lib["note"] or "")
    hidden = verdict.get("hidden") or row["hidden"]
    v = fair3_over_lambda_h(Verdict(keep=True, make=True, faired=verdict.get("faired", "fair2"),
                                    reference=verdict.get("reference", "fair2"),
                                    hidden=hidden),
                            ratio, shallower=shallower, crossed=row["crossed"])
    return "conformal" if v.keep else v.faired


def error_of(row: dict, which: str) -> float:
    """The true error of a candidate, or of what the library wrote where it is no candidate
    (a plane or ear-cut fill, a blend)."""
    return row["true"][which] if which in replay.CANDIDATES else row["library"]["true"]


def measures(rows: list[dict], ratio: float | None) -> dict:
    """Issue 14's measures of the fills written with ``ratio`` (see :func:`written_with`):
    the worst mesh median over fair2's (median over a mesh's holes, then their ratio, as
    ``validation.py``), the meshes above 1.1× fair2, the holes above 1.5× the better faired
    fill, the mean log regret (over the best candidate, where the self-check chose), and
    the holes changed against the
    default (closer / farther by 5 %, their geometric mean ratio)."""
    per_mesh: dict = {}
    above, regret, changed = 0, [], []
    for r in rows:
        t = r["true"]
        new, old = written_with(r, ratio), written_with(r, None)
        e = error_of(r, new)
        if new != old:
            changed.append(e / error_of(r, old))
        per_mesh.setdefault((r["split"], r["mesh"]), []).append((e, t["fair2"]))
        above += e / min(t["fair2"], t["fair3"]) > 1.5
        best = min(v for v in t.values() if np.isfinite(v))
        # as validation.py's chooser measures: where the self-check chose (no plane,
        # ear-cut or blended fill) and the best candidate is not exact
        if new in replay.CANDIDATES and not r["failure"] and best > 1e-6:
            regret.append(math.log(e / best))
    vs_fair = {m: np.median([a for a, _ in v]) / np.median([b for _, b in v])
               for m, v in per_mesh.items()}
    worst = max(vs_fair, key=vs_fair.get)
    c = np.array(changed)
    return {"worst": vs_fair[worst], "worst_mesh": worst[1], "vs_fair": vs_fair,
            "above_1.1": sum(x > 1.1 for x in vs_fair.values()), "above_1.5": above,
            "mean_log_regret": float(np.mean(regret)), "changed": len(c),
            "closer": int((c < 1 / 1.05).sum()), "farther": int((c > 1.05).sum()),
            "geomean": float(np.exp(np.mean(np.log(c)))) if len(c) else 1.0}


def _log_ratio(scores: dict, a: str, b: str) -> float:
    if not scores or a not in scores or b not in scores or not scores[b] > 0:
        return math.nan
    return math.log(scores[a] / scores[b]) if np.isfinite(scores[a]) else math.nan


def signals(row: dict) -> dict[str, float]:
    """The truth-free evidence screened: the tests' score ratios, the candidates' distances
    from each other, the hole's size and ``rim``."""
    h, s, b = row["hidden"], row["sibling"], row["between"]
    lh_f3, f2_f3 = b.get("conformal|fair3", math.nan), b.get("fair2|fair3", math.nan)
    return {"boundary edges": row["n_edges"],
            "hidden λ-H/fair3 (log)": _log_ratio(h, "conformal", "fair3"),
            "hidden λ-H/fair2 (log)": _log_ratio(h, "conformal", "fair2"),
            "hidden fair3/fair2 (log)": _log_ratio(h, "fair3", "fair2"),
            "siblings λ-H/fair3 (log)": _log_ratio(s, "conformal", "fair3"),
            "siblings fair3/fair2 (log)": _log_ratio(s, "fair3", "fair2"),
            "distance λ-H–fair3 / fair2–fair3": lh_f3 / f2_f3 if f2_f3 > 0 else math.nan,
            "distance fair2–fair3 (% diameter)": f2_f3,
            **row["rim"]}


def auc(high: list[float], low: list[float]) -> float:
    """P(a value of ``high`` > one of ``low``) (ties count half), NaNs left out."""
    a = np.array([x for x in high if np.isfinite(x)])
    b = np.array([x for x in low if np.isfinite(x)])
    if not len(a) or not len(b):
        return math.nan
    return float(((a[:, None] > b[None, :]) + 0.5 * (a[:, None] == b[None, :])).mean())


def _fmt(m: dict) -> str:
    return (f"{m['worst']:.3f} ({m['worst_mesh']}) | {m['above_1.1']} | {m['above_1.5']} | "
            f"{m['mean_log_regret']:.3f} | {m['changed']} ({m['closer']} / {m['farther']}, "
            f"{m['geomean']:.3f})")


def report(rows: list[dict], ratio: float | None = None) -> float:
    """The study's tables (markdown) from the rows; returns the ratio chosen on part A
    (lowest mean log regret with no mesh above 1.1× fair2 and no more holes above 1.5×
    than the default), or checks ``ratio`` if given."""
    brain = [r for r in rows if r["kind"] == "brain"]
    off = [r for r in rows if r["kind"] != "brain"]
    parts = {p: [r for r in brain if part(r) == p] for p in "AB"}
    print("## Per mesh (cortex): per-mesh median over fair2's\n")
    print("| part | set | mesh | default | fair3 | λ-H | best candidate | holes > 1.5× |")
    print("|---|---|---|---|---|---|---|---|")
    meshes: dict = {}
    for r in brain:
        meshes.setdefault((part(r), r["split"], r["mesh"]), []).append(r)
    for (p, split, mesh), rs in meshes.items():
        f2 = np.median([r["true"]["fair2"] for r in rs])
        cols = [np.median([error_of(r, replay.written(r)) for r in rs]),
                np.median([r["true"]["fair3"] for r in rs]),
                np.median([r["true"]["conformal"] for r in rs]),
                np.median([min(r["true"].values()) for r in rs])]
        n15 = sum(error_of(r, replay.written(r)) / min(r["true"]["fair2"], r["true"]["fair3"])
                  > 1.5 for r in rs)
        print(f"| {p} | {split} | {mesh} | " + " | ".join(f"{c / f2:.3f}" for c in cols)
              + f" | {n15} |")
    print("\n## Per hole (cortex): true errors (% of the hole diameter), what was written, "
          "the hidden rings' scores over fair2's\n")
    print("| part | mesh | hole | edges | fair2 | fair3 | λ-H | written | closest | "
          "written / better faired | hidden fair3, λ-H / fair2 |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in brain:
        t, h = r["true"], r["hidden"]
        w = replay.written(r)
        rel = (f"{h['fair3'] / h['fair2']:.2f}, {h.get('conformal', math.nan) / h['fair2']:.2f}"
               if h and h.get("fair2", 0) > 0 else "—")
        print(f"| {part(r)} | {r['mesh']} | {r['hole']} | {r['n_edges']} | {t['fair2']:.3g} | "
              f"{t['fair3']:.3g} | {t['conformal']:.3g} | {w} | {min(t, key=t.get)} | "
              f"{error_of(r, w) / min(t['fair2'], t['fair3']):.2f} | {rel} |")
    print("\n## Kept λ-H fills against fair3 (closer: by 1.2×)\n")
    print("| part | kept λ-H | fair3 closer | λ-H closer | λ-H / fair3 geometric mean |")
    print("|---|---|---|---|---|")
    for p, rs in parts.items():
        x = np.array([r["true"]["conformal"] / r["true"]["fair3"] for r in rs
                      if replay.written(r) == "conformal"])
        print(f"| {p} | {len(x)} | {(x >= CLOSER).sum()} | {(x <= 1 / CLOSER).sum()} | "
              f"{np.exp(np.mean(np.log(x))):.3f} |")
    print("\n## The screen: kept λ-H fills fair3 is 1.2× closer to (loss) against those "
          "1.2× closer than fair3 (win); AUC = P(signal higher on a loss)\n")
    print("| signal | AUC part A | AUC part B |")
    print("|---|---|---|")
    sig = {}
    for p, rs in parts.items():
        kept = [r for r in rs if replay.written(r) == "conformal"]
        loss = [signals(r) for r in kept if r["true"]["conformal"] >= CLOSER * r["true"]["fair3"]]
        win = [signals(r) for r in kept if CLOSER * r["true"]["conformal"] <= r["true"]["fair3"]]
        sig[p] = {k: auc([x[k] for x in loss], [x[k] for x in win]) for k in signals(kept[0])}
    for k in sig["A"]:
        print(f"| {k} | {sig['A'][k]:.2f} | {sig['B'][k]:.2f} |")
    print("\n## lambda_h_over_fair3 replayed (cortex): worst mesh / fair2 | meshes > 1.1 | "
          "holes > 1.5× better faired | mean log regret | changed (closer / farther, "
          "geometric mean)\n")
    print("| ratio | part A | part B |")
    print("|---|---|---|")
    table_a = {}
    for x in (None, *RATIOS):
        a, b = measures(parts["A"], x), measures(parts["B"], x)
        table_a[x] = a
        print(f"| {'default' if x is None else x} | {_fmt(a)} | {_fmt(b)} |")
    base = table_a[None]
    ok = [x for x in RATIOS if table_a[x]["above_1.1"] == 0
          and table_a[x]["above_1.5"] <= base["above_1.5"]]
    chosen = ratio if ratio is not None else min(ok, key=lambda x: table_a[x]["mean_log_regret"])
    print(f"\nchosen on part A: {chosen}" if ratio is None else f"\nchecked: {chosen}")
    print("\nThe cortex meshes and holes it changes (per-mesh median over fair2's; true "
          "errors):\n")
    before, after = measures(brain, None)["vs_fair"], measures(brain, chosen)["vs_fair"]
    for key in before:
        if abs(after[key] - before[key]) > 1e-9:
            print(f"- {key[0]} {key[1]}: {before[key]:.3f} → {after[key]:.3f}")
    for r in brain:
        new, old = written_with(r, chosen), replay.written(r)
        if new != old:
            print(f"- part {part(r)} {r['mesh']} #{r['hole']}: {old} {error_of(r, old):.3g} → "
                  f"{new} {error_of(r, new):.3g} ({error_of(r, new) / error_of(r, old):.2f}×)")
    if off:
        print(f"\n## Off the cortex, lambda_h_over_fair3 = {chosen} replayed per set\n")
        print("| set | holes | worst mesh / fair2 | meshes > 1.1 | holes > 1.5× | "
              "mean log regret | changed (closer / farther, geometric mean) |")
        print("|---|---|---|---|---|---|---|")
        for split in dict.fromkeys(r["split"] for r in off):
            rs = [r for r in off if r["split"] == split]
            a, b = measures(rs, None), measures(rs, chosen)
            print(f"| {split} | {len(rs)} | {a['worst']:.3f} → {b['worst']:.3f} "
                  f"({b['worst_mesh']}) | {a['above_1.1']} → {b['above_1.1']} | "
                  f"{a['above_1.5']} → {b['above_1.5']} | {a['mean_log_regret']:.3f} → "
                  f"{b['mean_log_regret']:.3f} | {b['changed']} ({b['closer']} / "
                  f"{b['farther']}, {b['geomean']:.3f}) |")
        print("\nThe holes it changes off the cortex (true errors):\n")
        for r in off:
            new, old = written_with(r, chosen), replay.written(r)
            if new != old:
                print(f"- {r['split']} {r['mesh']} #{r['hole']} ({r['kind']}): {old} "
                      f"{error_of(r, old):.3g} → {new} {error_of(r, new):.3g} "
                      f"({error_of(r, new) / error_of(r, old):.2f}×)")
    return chosen


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    make = sub.add_parser("table", help="the rows of a set's holes, cached")
    make.add_argument("--manifest", default=None, help="a tuning-side or spent holdout "
                      "manifest (default: the halves', where --split tuning is needed)")
    make.add_argument("--split", default=None)
    make.add_argument("--meshes", default=None, help="comma-separated mesh ids")
    make.add_argument("--kind", default=None, help="only meshes of this kind (brain)")
    make.add_argument("--cache", required=True, help="JSONL file of rows (appended)")
    show = sub.add_parser("report", help="the tables of the study, from the cached rows")
    show.add_argument("directory", help="the rows (*.jsonl: brain rows and others)")
    show.add_argument("--ratio", type=float, default=None,
                      help="check this lambda_h_over_fair3 instead of choosing one on part A")
    args = parser.parse_args(argv)
    if args.command == "table":
        build(Path(args.cache), Path(args.manifest) if args.manifest else None, args.split,
              args.meshes.split(",") if args.meshes else None, args.kind)
    else:
        report(replay.load(Path(args.directory)), args.ratio)


if __name__ == "__main__":
    main()
