"""Two candidate families measured on the validation benchmark's tuning half (issue 14
item 3): blends between a faired fill and the raw λ-H fill, and the λ-H fill started from
the bilaplacian instead of the trilaplacian fill (S0).

The faired fills and the λ-H fill of a hole share their triangles (one triangulation and
refinement; the λ-H fill moves S0's new vertices), so a blend ``(1 - a) faired + a λ-H`` of
their new vertices is a fill too. Per hole it writes the truth error (% of the hole
diameter, as ``benchmarks/validation.py`` scores it) of ``fair``, ``fair3``, ``raw`` (the λ-H
fill from the trilaplacian S0, ``select=False``), ``raw2`` (from the bilaplacian S0) and of
the blends, then replays rules against the default's rows of a saved validation run
(``--baseline``: the default, CGAL's and the peers' rows).

Run::

    .venv/bin/python benchmarks/blend_study.py --out blends.jsonl
    .venv/bin/python benchmarks/blend_study.py --out blends.jsonl --replay --baseline RUN.jsonl
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import holes_manifest  # noqa: E402
import validation  # noqa: E402
import validation_meshes as vm  # noqa: E402
from variant_rows import read_rows  # noqa: E402

from surfinpaint.fill.conformal import ConformalOptions  # noqa: E402
from surfinpaint.fill.pipeline import fill_holes  # noqa: E402
from surfinpaint.geometry.metrics import hole_patch_of, surface_distance  # noqa: E402

ALPHAS = (0.25, 0.5, 0.75)
FILLS = {
    "fair": {"method": "fair"},
    "fair3": {"method": "fair", "fair_order": 3},
    "raw": {"method": "conformal", "options": ConformalOptions(select=False)},
    "raw2": {"method": "conformal", "fair_order": 2, "options": ConformalOptions(select=False)},
}
PEERS = ("cgal", "cgal3", "meshlib", "pymeshlab", "pymeshfix")


def hole_row(cut, samples: int) -> dict:
    """The truth errors of the fills of :data:`FILLS` and of their blends on one hole."""
    n = len(cut.vertices)
    made = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name, kwargs in FILLS.items():
            res = fill_holes(cut.vertices, cut.faces, holes=[cut.loop], **kwargs)
            made[name] = (np.asarray(res.vertices)[n:], np.asarray(res.faces),
                          any(r.fallback for r in res.reports))

    def error(new_vertices, faces):
        pv, pf = hole_patch_of(np.vstack([cut.vertices, new_vertices]), faces, n, cut.faces)
        d = surface_distance(pv, pf, cut.truth_vertices, cut.truth_faces, n_samples=samples)
        return 100.0 * d.mean / cut.diameter

    row = {name: error(v, f) for name, (v, f, _) in made.items()}
    row["raw_fallback"] = made["raw"][2]
    shared = all(np.array_equal(made["raw"][1], made[m][1]) for m in ("fair", "fair3"))
    if shared and not made["raw"][2]:
        for base in ("fair", "fair3"):
            for a in ALPHAS:
                row[f"{base}_{a}"] = error((1 - a) * made[base][0] + a * made["raw"][0],
                                           made["raw"][1])
    return row


def measure(out: Path, split: str, samples: int) -> None:
    manifest = holes_manifest.read(holes_manifest.MANIFEST)
    done = ({(r["case"], r["hole"]) for r in read_rows([str(out)])} if out.exists() else set())
    for entry in manifest["meshes"]:
        if entry["split"] != split:
            continue
        mesh = vm.load_entry(entry)
        for k, hole in enumerate(entry["holes"]):
            if (entry["mesh"], k) in done:
                continue
            cut = validation._cut(mesh, hole)
            row = {"case": entry["mesh"], "hole": k, "edges": len(cut.loop),
                   **hole_row(cut, samples)}
            with out.open("a") as fh:
                fh.write(json.dumps(row) + "\n")
            print(entry["mesh"], k, {m: round(row[m], 4) for m in FILLS}, flush=True)


def replay(rows: list[dict], baseline: list[dict]) -> None:
    """Per rule: per-hole median / CGAL, meshes where it beats every peer, worst mesh median
    / bilaplacian, worst hole / the better faired fill."""
    base = {(r["method"], r["case"], r["hole"]): r for r in baseline}

    def default_pick(r):
        e = base[("conformal", r["case"], r["hole"])]["mean_pct"]
        return next((k for k in ("raw", "fair3", "fair")
                     if abs(e - r[k]) <= 1e-9 * max(1.0, e)), "?"), e

    picks = [default_pick(r) for r in rows]
    rules = {
        "default": lambda r, c, e: e,
        "always raw (λ-H, no self-check)": lambda r, c, e: r["raw"],
        "always raw2 (bilaplacian S0)": lambda r, c, e: r["raw2"],
        "default, kept λ-H -> raw2": lambda r, c, e: r["raw2"] if c == "raw" else e,
        **{f"default, kept λ-H -> {b} blend {a}":
           (lambda r, c, e, a=a, b=b: r.get(f"{b}_{a}", e) if c == "raw" else e)
           for b in ("fair", "fair3") for a in ALPHAS},
        "oracle fair, fair3, raw": lambda r, c, e: min(r["fair"], r["fair3"], r["raw"]),
        "oracle with raw2 and the blends": lambda r, c, e: min(
            v for k, v in r.items() if k not in ("case", "hole", "edges", "raw_fallback")),
    }
    print("| rule | median / CGAL | most accurate | worst mesh / fair | worst hole (> 1.5) |")
    print("|---|---|---|---|---|")
    for name, rule in rules.items():
        err = {(r["case"], r["hole"]): rule(r, *p) for r, p in zip(rows, picks, strict=True)}
        faired = {(r["case"], r["hole"]): min(r["fair"], r["fair3"]) for r in rows}
        worst = np.array([err[k] / faired[k] for k in err if faired[k] > 1e-9])
        cgal = [err[k] / base[("cgal", *k)]["mean_pct"] for k in err
                if base[("cgal", *k)]["mean_pct"] > 1e-6]
        meshes, best = [], 0
        for mesh in sorted({k[0] for k in err}):
            keys = [k for k in err if k[0] == mesh]
            med = np.median([err[k] for k in keys])
            meshes.append((med / np.median([base[("fair", *k)]["mean_pct"] for k in keys]),
                           mesh))
            best += med <= min(np.median([base[(p, *k)]["mean_pct"] for k in keys
                                          if base[(p, *k)]["status"] in validation.FILLED])
                               for p in PEERS)
        ratio, mesh = max(meshes)
        print(f"| {name} | {np.median(cgal):.3f} | {best} / {len(meshes)} | {ratio:.3f} "
              f"({mesh}) | {worst.max():.2f} ({(worst > 1.5).sum()}) |")
    ratio = np.array([r["raw2"] / r["raw"] for r in rows])
    print(f"\nraw2 / raw per hole: median {np.median(ratio):.3f}, lower on "
          f"{(ratio < 1).sum()}, > 1.1 on {(ratio > 1.1).sum()} of {len(ratio)}")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default="blends.jsonl")
    parser.add_argument("--split", default="tuning", choices=("tuning",),
                        help="only the tuning half: rules are chosen there")
    parser.add_argument("--samples", type=int, default=10000)
    parser.add_argument("--replay", action="store_true", help="replay the rules on --out")
    parser.add_argument("--baseline", default=None,
                        help="a validation.py run with the default's and the peers' rows")
    args = parser.parse_args(argv)
    if not args.replay:
        measure(Path(args.out), args.split, args.samples)
    if args.baseline:
        replay(read_rows([args.out]), read_rows([args.baseline]))


if __name__ == "__main__":
    main()
