"""Session 26: flat vs curved under scan noise (issue 14), on the tuning side only.

On simulated range scans whose holes lie on flat faces of CAD parts, flat fills (PyMeshLab,
PyMeshFix) beat the bilaplacian fill: fair2 takes its slopes from the noisy ring around the
loop and carries the noise into the fill. This study measures a rule that needs no tuned
distance threshold:

- the **flatness test** (``geometry.flatness.plane_test``, through the default fill's
  ``fill.conformal.method.known_plane``): in the principal frame of the known vertices
  within ``k`` rings of the loop, a plane and a quadric height field fitted by least
  squares and compared by an F-test (the noise level is the quadric's own residual), and
  Moran's I of the plane's residuals (noise is independent between neighbours, a shape is
  not). "Flat" when neither is significant at ``alpha`` (1 %, fixed a priori);
- the **flat candidate** (``fill.liepa.baseline.laid_on_plane``): the fair2 fill's vertices
  keep their positions along the fitted plane, and their heights above it were the
  harmonic extension of the loop's heights (the loop's noise averaged, not extrapolated as
  a slope); since session 29 they are zero (the vertices projected onto the plane). The
  loop and every original vertex stay where they are.
- the rule: flat verdict → flat candidate, else the default fill as it was before
  (``conformal_noplane``). Adopted in session 26 with k = 2: today's ``conformal``.

Holes: the manifest's tuning half (``benchmarks/holes_manifest.json``, split "tuning" only)
and extra simulated scans of tuning-half sources (:data:`EXTRA`: new views and seeds), their
holes planned by ``holes_manifest.plan_holes`` as the manifest's scans are. Validation and
holdout rows are never read. Every fill is scored as ``benchmarks/accuracy.py`` scores it
(two-sided mean distance to the removed truth, % of the hole diameter; on scans the truth is
the noise-free scan).

    taskset -c 1 .venv/bin/python benchmarks/scan_flatness_study.py --set extra \\
        --out /tmp/s26_extra.jsonl
    taskset -c 1 .venv/bin/python benchmarks/scan_flatness_study.py --set tuning \\
        --out /tmp/s26_tuning.jsonl
    .venv/bin/python benchmarks/scan_flatness_study.py --tables /tmp/s26_extra.jsonl \\
        /tmp/s26_tuning.jsonl --k 2

Rows already in ``--out`` are not computed again. k = 2 rings was chosen on these (tuning
side) holes; results in docs/candidates.md, "Session 26".
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
import holes_manifest  # noqa: E402
import validation  # noqa: E402
import validation_meshes as vm  # noqa: E402

from surfinpaint.fill.conformal.method import PLANE_ALPHA, known_plane  # noqa: E402
from surfinpaint.fill.liepa.baseline import faired_fills, laid_on_plane  # noqa: E402
from surfinpaint.geometry.mesh import mean_edge_length  # noqa: E402
from surfinpaint.geometry.metrics import hole_patch_of, surface_distance  # noqa: E402

ALPHA = PLANE_ALPHA  # the tests' significance level, fixed before any run
RINGS = (2, 3, 4, 6)  # the k compared on the tuning side
# "conformal_noplane" is the default before the plane test was adopted; "conformal" today's
OURS = ("fair", "fair3", "conformal_noplane", "conformal")
PEERS = ("pymeshlab", "pymeshfix", "meshlib")

# extra simulated scans of TUNING-half sources: (source id, view, seed[, noise in pixels,
# default 0.05 as the manifest's scans]); the noisier ones are their own sets
EXTRA = {
    "xscan_cube40_a": ("cube40", (0.5, 0.3, 1.0), 111),
    "xscan_cube40_b": ("cube40", (0.15, 0.1, 1.0), 112),
    "xscan_bracket_top": ("bracket", (0.1, 0.05, 1.0), 113),
    "xscan_bracket_side": ("bracket", (-0.6, 0.4, 0.8), 114),
    "xscan_airplane": ("airplane", (0.3, 0.5, 1.0), 115),
    "xscan_bunny_side": ("bunny", (-1.0, 0.2, 0.3), 116),
    "xscan_bone": ("bone", (0.2, 1.0, 0.3), 117),
    "xscan_blob_a": ("blob_a", (0.5, -0.4, 1.0), 118),
    "xscan_tooth": ("tooth", (0.1, 0.2, 1.0), 119),
    "xscan_torus": ("torus", (0.3, 0.4, 1.0), 120),
    # a second batch, made after the first was seen
    "xscan_cube40_c": ("cube40", (0.7, 0.6, 1.0), 121),
    "xscan_bracket_top2": ("bracket", (0.0, 0.3, 1.0), 122),
    "xscan_bracket_under": ("bracket", (0.3, -0.2, -1.0), 123),
    "xscan_snowman": ("snowman", (1.0, 0.2, 0.3), 124),
    "xscan_sphere": ("sphere", (0.2, 0.1, 1.0), 125),
    "xscan_premolar": ("premolar", (0.1, 0.1, 1.0), 126),
    # three times the noise: less power to see curvature, more harm from noisy slopes
    "nscan_cube40": ("cube40", (0.5, 0.3, 1.0), 131, 0.15),
    "nscan_bracket": ("bracket", (0.1, 0.05, 1.0), 132, 0.15),
    "nscan_sphere": ("sphere", (0.2, 0.1, 1.0), 133, 0.15),
    "nscan_torus": ("torus", (0.3, 0.4, 1.0), 134, 0.15),
    "nscan_blob_a": ("blob_a", (0.5, -0.4, 1.0), 135, 0.15),
    "nscan_bunny": ("bunny", (0.3, 0.2, 1.0), 136, 0.15),
    "nscan_bone": ("bone", (0.2, 1.0, 0.3), 137, 0.15),
    # six times the noise: where the test stops seeing curvature
    "n6scan_cube40": ("cube40", (0.5, 0.3, 1.0), 141, 0.3),
    "n6scan_sphere": ("sphere", (0.2, 0.1, 1.0), 143, 0.3),
    "n6scan_torus": ("torus", (0.3, 0.4, 1.0), 144, 0.3),
    "n6scan_blob_a": ("blob_a", (0.5, -0.4, 1.0), 145, 0.3),
    "n6scan_bunny": ("bunny", (0.3, 0.2, 1.0), 146, 0.3),
}


# --------------------------------------------------------------------------- the test


def plane_verdict(cut, k: int):
    """The plane test of the known vertices within ``k`` rings of the cut's loop (the
    default fill's own, :func:`surfinpaint.fill.conformal.method.known_plane`), as a row's
    record: ``flat`` both tests' verdict, ``flat_F`` the F-test's alone."""
    t = known_plane(cut.vertices, cut.faces, cut.loop, rings=k)
    return t, {"flat": t.flat, "flat_F": bool(t.p_curvature >= ALPHA), "p": t.p_curvature,
               "p_moran": t.p_pattern, "n": t.points, "sigma": t.noise}


# --------------------------------------------------------------------------- the holes


def extra_mesh(name: str) -> vm.BenchMesh:
    source, view, seed, *noise = EXTRA[name]
    m = vm.SOURCES[source].make()
    scan = vm.simulated_scan(m.vertices, m.faces, view, seed=seed, noise_h=(noise or [0.05])[0])
    return vm.split_bowties(scan)[0]


def holes(which: str):
    """(set, mesh id, kind, BenchMesh loader, holes) of the tuning half or the extra scans."""
    if which == "tuning":
        for e in holes_manifest.read()["meshes"]:
            if e["split"] != "tuning":  # never a validation row
                continue
            yield "tuning", e["mesh"], e["kind"], (lambda e=e: vm.load(e["mesh"])), e["holes"]
    else:
        for name in EXTRA:
            def load(name=name):
                return extra_mesh(name)
            noise = EXTRA[name][3] if len(EXTRA[name]) > 3 else 0.05
            set_name = {0.05: "extra", 0.15: "extra_noisy", 0.3: "extra_noisy6"}[noise]
            yield set_name, name, "range_scan", load, None


def _error(cut, new_vertices, patch, n_samples) -> float:
    v = np.vstack([cut.vertices, new_vertices])
    f = np.vstack([cut.faces, patch])
    pv, pf = hole_patch_of(v, f, len(cut.vertices), cut.faces)
    d = surface_distance(pv, pf, cut.truth_vertices, cut.truth_faces, n_samples=n_samples)
    return float(d.mean * 100.0 / cut.diameter)


def hole_row(cut, methods, n_samples: int) -> dict:
    row = {"errors": {}, "tests": {}}
    for m in methods:
        r = accuracy.score(cut, m, "x", 0, 0.0, n_samples)
        row["errors"][m] = (r.mean_pct if r.status in validation.FILLED else float("nan"))
        row.setdefault("status", {})[m] = r.status
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        nv, patch, _ = faired_fills(cut.vertices, cut.faces, cut.loop, (2,))[2]
    row["errors"]["fair2_ref"] = _error(cut, nv, patch, n_samples)
    for k in RINGS:
        t, row["tests"][str(k)] = plane_verdict(cut, k)
        flat_v = laid_on_plane(nv, t.centre, t.normal)
        row["errors"][f"plane{k}"] = _error(cut, flat_v, patch, n_samples)
    return row


def pending_holes(which: str, out: Path, only=None):
    """The holes of ``which`` (:func:`holes`) whose rows are not in ``out`` yet, as (set, mesh
    id, kind, mean edge length, hole number, planned hole, its cut)."""
    done = set()
    if out.exists():
        done = {(r["mesh"], r["hole"]) for r in map(json.loads, out.read_text().splitlines())}
    for set_name, mesh_id, kind, load, planned in holes(which):
        if only and mesh_id not in only:
            continue
        if planned is not None and all((mesh_id, k) in done for k in range(len(planned))):
            continue
        mesh = load()
        h = mean_edge_length(mesh.vertices, mesh.faces)
        if planned is None:
            planned = holes_manifest.plan_holes(mesh.vertices, mesh.faces, kind,
                                                2000 + list(EXTRA).index(mesh_id), mesh_id)
        print(f"{mesh_id}: {len(mesh.vertices)} vertices, {len(planned)} holes",
              file=sys.stderr, flush=True)
        for k, hole in enumerate(planned):
            if (mesh_id, k) not in done:
                yield set_name, mesh_id, kind, h, k, hole, validation._cut(mesh, hole)


def run(which: str, out: Path, methods, n_samples: int, only=None) -> None:
    for set_name, mesh_id, kind, h, k, hole, cut in pending_holes(which, out, only):
        t0 = time.perf_counter()
        row = {"set": set_name, "mesh": mesh_id, "hole": k, "kind": kind,
               "radius_h": hole["radius"] / h, "near_border": hole["near_border"],
               "on_feature": hole["on_feature"], **hole_row(cut, methods, n_samples)}
        row["seconds"] = time.perf_counter() - t0
        with out.open("a") as fh:
            fh.write(json.dumps(row, default=float) + "\n")
        e = row["errors"]
        print(f"{mesh_id} #{k}: " + " ".join(f"{a} {b:.3f}" for a, b in e.items())
              + " flat " + "".join("F" if row["tests"][str(r)]["flat"] else "c"
                                   for r in RINGS), file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- tables


VERDICTS = {"flat": "F-test and Moran's I", "flat_F": "F-test alone"}


def _default(row: dict) -> float:
    """The default fill without the plane test (rows made before it was adopted: their
    "conformal")."""
    e = row["errors"]
    return e["conformal_noplane"] if "conformal_noplane" in e else e["conformal"]


def _rule(row: dict, k: int, verdict: str = "flat") -> float:
    return row["errors"][f"plane{k}"] if row["tests"][str(k)][verdict] else _default(row)


def summary(rows: list[dict], label: str) -> str:
    lines = [f"### {label}: {len(rows)} holes", "",
             "| test | k | flat verdicts | rule / default (median) | worse > 10 % "
             "| better > 10 % | > 1.5x best faired: default, rule | median % default, rule |",
             "|---|---|---|---|---|---|---|---|"]
    dflt = np.array([_default(r) for r in rows])
    best = np.array([min(r["errors"]["fair"], r["errors"]["fair3"]) for r in rows])
    for verdict, k in [(a, k) for a in VERDICTS for k in RINGS]:
        rule = np.array([_rule(r, k, verdict) for r in rows])
        flat = sum(r["tests"][str(k)][verdict] for r in rows)
        ratio = rule / dflt
        lines.append(
            f"| {VERDICTS[verdict]} | {k} | {flat} | {np.nanmedian(ratio):.3f} | "
            f"{(ratio > 1.1).sum()} | "
            f"{(ratio < 1 / 1.1).sum()} | {(dflt > 1.5 * best).sum()}, "
            f"{(rule > 1.5 * best).sum()} | {np.nanmedian(dflt):.3f}, "
            f"{np.nanmedian(rule):.3f} |")
    return "\n".join(lines)


def per_mesh(rows: list[dict], k: int) -> str:
    methods = [m for m in ("fair", "fair3", "conformal_noplane", "conformal", *PEERS,
                           f"plane{k}")
               if m in rows[0]["errors"]]
    lines = [f"per mesh, median % (k = {k}; flat = holes with a flat verdict)", "",
             "| mesh | flat | " + " | ".join(methods) + " | rule |",
             "|---|---|" + "---|" * (len(methods) + 1)]
    for mesh in dict.fromkeys(r["mesh"] for r in rows):
        rs = [r for r in rows if r["mesh"] == mesh]
        flat = sum(r["tests"][str(k)]["flat"] for r in rs)
        cells = [f"{np.nanmedian([r['errors'][m] for r in rs]):.3f}" for m in methods]
        rule = np.nanmedian([_rule(r, k) for r in rs])
        lines.append(f"| {mesh} | {flat}/{len(rs)} | " + " | ".join(cells) + f" | {rule:.3f} |")
    return "\n".join(lines)


def flagged(rows: list[dict], k: int) -> str:
    lines = [f"holes with a flat verdict of the F-test (k = {k}; * = also of Moran's I): "
             "default, plane, fair, fair3 (%), p of F, p of Moran"]
    for r in rows:
        t = r["tests"][str(k)]
        if t["flat_F"]:
            e = r["errors"]
            lines.append(f"  {'*' if t['flat'] else ' '} {r['mesh']} #{r['hole']}: "
                         f"{_default(r):.3f} {e[f'plane{k}']:.3f} {e['fair']:.3f} "
                         f"{e['fair3']:.3f}  p={t['p']:.3g} p_moran={t['p_moran']:.3g}")
    return "\n".join(lines)


def tables(paths: list[Path], k_detail: int | None = None) -> str:
    rows = [json.loads(line) for p in paths for line in Path(p).read_text().splitlines()]
    rows = [r for r in rows if r["set"] in ("tuning", "extra", "extra_noisy", "extra_noisy6")]
    out = []
    groups = [("extra scans", [r for r in rows if r["set"] == "extra"]),
              ("extra scans, 3x noise", [r for r in rows if r["set"] == "extra_noisy"]),
              ("extra scans, 6x noise", [r for r in rows if r["set"] == "extra_noisy6"]),
              ("tuning half, scans", [r for r in rows if r["set"] == "tuning"
                                      and r["kind"] == "range_scan"]),
              ("tuning half, not scans", [r for r in rows if r["set"] == "tuning"
                                          and r["kind"] != "range_scan"])]
    for label, rs in groups:
        if rs:
            out.append(summary(rs, label))
            for k in ([k_detail] if k_detail else []):
                out.append(per_mesh(rs, k))
                out.append(flagged(rs, k))
    return "\n\n".join(out)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--set", choices=("tuning", "extra"), default="extra")
    parser.add_argument("--out", default="/tmp/s26.jsonl")
    parser.add_argument("--meshes", default=None)
    parser.add_argument("--peers", action="store_true", help="also PyMeshLab, PyMeshFix, "
                        "MeshLib")
    parser.add_argument("--samples", type=int, default=10000)
    parser.add_argument("--tables", nargs="+", default=None)
    parser.add_argument("--k", type=int, default=None, help="per-mesh tables for this k")
    args = parser.parse_args(argv)
    if args.tables:
        print(tables([Path(p) for p in args.tables], args.k))
        return
    methods = list(OURS) + (list(PEERS) if args.peers else [])
    run(args.set, Path(args.out), methods, args.samples,
        args.meshes.split(",") if args.meshes else None)


if __name__ == "__main__":
    main()
