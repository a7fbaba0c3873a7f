"""A method variant's rows of ``benchmarks/validation.py`` against a saved run, per hole.

Two uses (docs/candidates.md, "CGAL-style refinement (session 9)"):

- ``--pairs variant:base,...``: per hole, variant error / base error over the holes both
  filled (median, geometric mean, holes better / worse by 10 %, the worst and best hole), the
  median of each over CGAL's error, and the variant's median seconds per hole;
- ``--as-default variant:base,... --out FILE``: the base run with each base method's rows
  replaced by the variant's rows under the base name (the variant as if it were the default),
  for ``validation.py --tables FILE``.

Run::

    python benchmarks/variant_rows.py --rows /tmp/run.json.partial.jsonl \\
        --base /work/bench_baseline/final3_combined.jsonl --split tuning \\
        --pairs fair_cgalref:fair,fair3_cgalref:fair3
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np


def read_rows(paths: list[str]) -> list[dict]:
    """Rows of ``.json`` (``{"rows": [...]}``) or ``.jsonl`` files, concatenated."""
    rows: list[dict] = []
    for path in paths:
        text = Path(path).read_text()
        rows += (json.loads(text)["rows"] if path.endswith(".json")
                 else [json.loads(line) for line in text.splitlines() if line.strip()])
    return rows


def _errors(rows: list[dict], split: str | None) -> dict:
    return {(r["method"], r["case"], r["hole"]): r for r in rows
            if r["status"] in ("ok", "selected", "fallback") and np.isfinite(r["mean_pct"])
            and (split is None or r["extra"]["split"] == split)}


def compare(rows: list[dict], base: list[dict], variant: str, method: str,
            split: str | None) -> dict:
    """Per-hole ratios of ``variant`` (in ``rows``) to ``method`` (in ``base``)."""
    mine, theirs = _errors(rows, split), _errors(base, split)
    keys = sorted(k[1:] for k in mine if k[0] == variant and (method, *k[1:]) in theirs)
    ratio = np.array([mine[(variant, *k)]["mean_pct"] / theirs[(method, *k)]["mean_pct"]
                      for k in keys if theirs[(method, *k)]["mean_pct"] > 1e-6])
    kept = [k for k in keys if theirs[(method, *k)]["mean_pct"] > 1e-6]
    cgal = [k for k in kept if ("cgal", *k) in theirs and theirs[("cgal", *k)]["mean_pct"] > 1e-6]

    def over_cgal(src, name):
        return float(np.median([src[(name, *k)]["mean_pct"] / theirs[("cgal", *k)]["mean_pct"]
                                for k in cgal])) if cgal else float("nan")

    worst, best = int(np.argmax(ratio)), int(np.argmin(ratio))
    return {"holes": len(ratio), "median": float(np.median(ratio)),
            "geomean": float(np.exp(np.log(ratio).mean())),
            "better": int((ratio < 1 / 1.1).sum()), "worse": int((ratio > 1.1).sum()),
            "worst": (kept[worst], float(ratio[worst])), "best": (kept[best], float(ratio[best])),
            "variant_over_cgal": over_cgal(mine, variant),
            "base_over_cgal": over_cgal(theirs, method),
            "seconds": float(np.median([mine[(variant, *k)]["seconds"] for k in kept]))}


def as_default(rows: list[dict], base: list[dict], renames: dict[str, str]) -> list[dict]:
    """``base`` with the rows of each renamed base method replaced by the variant's rows."""
    replaced = set(renames.values())
    out = [r for r in base if r["method"] not in replaced]
    for r in rows:
        if r["method"] in renames:
            out.append({**r, "method": renames[r["method"]], "note": r["note"]})
    return out


def _pairs(text: str) -> list[tuple[str, str]]:
    return [tuple(p.split(":", 1)) for p in text.split(",") if p]


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--rows", required=True, help="comma-separated row files (variants)")
    parser.add_argument("--base", required=True, help="row file of the base run")
    parser.add_argument("--split", default=None, choices=("tuning", "validation"))
    parser.add_argument("--pairs", default="", help="variant:base method pairs to compare")
    parser.add_argument("--as-default", default="", help="variant:base renames for --out")
    parser.add_argument("--out", default=None, help="merged .jsonl (with --as-default)")
    args = parser.parse_args(argv)
    rows, base = read_rows(args.rows.split(",")), read_rows([args.base])
    if args.pairs:
        print("| variant / base | holes | median ratio | geometric mean | better / worse by 10 % "
              "| worst | best | median / CGAL (variant, base) | variant s per hole |")
        print("|---|---|---|---|---|---|---|---|---|")
        for variant, method in _pairs(args.pairs):
            c = compare(rows, base, variant, method, args.split)
            (wc, wh), wr = c["worst"]
            (bc, bh), br = c["best"]
            print(f"| {variant} / {method} | {c['holes']} | {c['median']:.3f} | "
                  f"{c['geomean']:.3f} | {c['better']} / {c['worse']} | {wr:.2f} ({wc} #{wh}) | "
                  f"{br:.2f} ({bc} #{bh}) | {c['variant_over_cgal']:.3f}, "
                  f"{c['base_over_cgal']:.3f} | {c['seconds']:.3f} |")
    if args.as_default:
        if not args.out:
            parser.error("--as-default needs --out")
        merged = as_default(rows, base, dict(_pairs(args.as_default)))
        if args.split:
            merged = [r for r in merged if r["extra"]["split"] == args.split]
        Path(args.out).write_text("".join(json.dumps(r, default=float) + "\n" for r in merged))
        print(f"wrote {len(merged)} rows to {args.out}")


if __name__ == "__main__":
    main()
