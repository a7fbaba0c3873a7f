"""Large holes in a strongly folded brain surface: does the λ-H fill run there, and how well?

Random geodesic-disk holes on nilearn's fsaverage5 LEFT hemisphere (the right one is reserved
for the independent evaluation and is never loaded here), at a radius that spans gyri and
sulci (8 mean edge lengths by default, larger than most of the benchmark's brain holes).
Every hole is filled by the default method, both faired fills and CGAL's (the ``peers``
extra), scored against the removed surface as ``benchmarks/accuracy.py`` does; the table
gives each hole's outcome and the λ-H fill's failure reason where it fell back.

This is tuning-side data (the pial and white surfaces are tuning meshes of
``benchmarks/validation.py``): rules may be chosen on it, and the numbers say how far issue
20's "a strongly folded brain patch" is from its target.

    python benchmarks/brain_probes.py [--surfaces pial,white] [--holes 25] [--radius 8]
                                      [--seed 1] [--methods conformal,fair,fair3,cgal]
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import accuracy  # noqa: E402

from surfinpaint.data import fsaverage5  # noqa: E402
from surfinpaint.geometry.cutting import cut_geodesic_disk  # noqa: E402
from surfinpaint.geometry.mesh import mean_edge_length  # noqa: E402

DEFAULT_METHODS = ("conformal", "fair", "fair3", "cgal")


def probe_cuts(surface: str, holes: int, radius_h: float, seed: int):
    """``(centre, cut)`` for ``holes`` random centres on the left ``surface``; centres whose
    disk cannot be cut into one clean hole are skipped (the count is printed)."""
    v, f = fsaverage5(surface, "left")
    h = mean_edge_length(v, f)
    rng = np.random.default_rng(seed)
    for centre in rng.integers(len(v), size=holes):
        try:
            yield int(centre), cut_geodesic_disk(v, f, int(centre), radius_h * h)
        except Exception as exc:  # noqa: BLE001 - a centre the cutter refuses is skipped
            print(f"note: {surface} centre {centre} skipped: {exc}", file=sys.stderr)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--surfaces", default="pial,white")
    parser.add_argument("--holes", type=int, default=25, help="holes per surface")
    parser.add_argument("--radius", type=float, default=8.0, help="in mean edge lengths")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--methods", default=",".join(DEFAULT_METHODS))
    parser.add_argument("--samples", type=int, default=10000)
    args = parser.parse_args(argv)
    methods = args.methods.split(",")
    accuracy.warm_up(methods)
    rows = []
    for surface in args.surfaces.split(","):
        for k, (centre, cut) in enumerate(probe_cuts(surface, args.holes, args.radius,
                                                     args.seed)):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                scored = {m: accuracy.score(cut, m, surface, k, args.radius, args.samples)
                          for m in methods}
            rows.append((surface, k, centre, len(cut.loop), scored))
            d = scored.get("conformal")
            print(f"{surface} #{k} (centre {centre}, {len(cut.loop)} edges): "
                  + ", ".join(f"{m} {accuracy._fmt(r.mean_pct)}" for m, r in scored.items())
                  + (f" [{d.status}: {d.note[:160]}]" if d is not None and d.note else ""),
                  file=sys.stderr, flush=True)
    print(table(rows, methods))


def table(rows, methods) -> str:
    """The per-hole table and the summary lines (README-ready markdown)."""
    lines = ["| surface | hole | centre | edges | " + " | ".join(methods)
             + " | λ-H outcome |", "|---|---|---|---|" + "---|" * (len(methods) + 1)]
    fell, ratios_cgal, above = 0, [], 0
    for surface, k, centre, edges, scored in rows:
        default = scored.get("conformal")
        outcome = "—"
        if default is not None:
            outcome = default.status if default.status != "fallback" else \
                "fell back: " + default.note.split(": ", 1)[-1][:90]
            fell += default.status == "fallback"
            if "cgal" in scored and scored["cgal"].mean_pct > 0:
                ratios_cgal.append(default.mean_pct / scored["cgal"].mean_pct)
            faired = min(scored[m].mean_pct for m in ("fair", "fair3") if m in scored) \
                if any(m in scored for m in ("fair", "fair3")) else np.nan
            above += bool(default.mean_pct > 1.5 * faired)
        lines.append(f"| {surface} | {k} | {centre} | {edges} | "
                     + " | ".join(accuracy._fmt(scored[m].mean_pct) for m in methods)
                     + f" | {outcome} |")
    n = len(rows)
    lines += ["", f"λ-H fallbacks: {fell} / {n} ({100 * fell / max(n, 1):.0f} %); "
              f"default / CGAL per-hole median: "
              f"{accuracy._fmt(float(np.median(ratios_cgal))) if ratios_cgal else '—'}; "
              f"holes above 1.5× the better faired fill: {above}"]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
