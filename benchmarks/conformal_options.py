"""How the conformal method's options change its accuracy: the measurements behind the
defaults, printed as markdown tables.

Every configuration fills the same benchmark holes (those of ``accuracy.py``) with the raw
conformal fill of the grid discretization (``select=False, discretization="grid"``, so the
self-check does not hide the option's effect; these options are the grid's); the score per
hole is its two-sided mean error divided by the faired fill's.

    python benchmarks/conformal_options.py
    python benchmarks/conformal_options.py --cases torus,bunny \\
        --configs '[{}, {"fit_radius": 2}, {"passes": 2}]'
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

import accuracy  # noqa: E402  (the benchmark's cases and holes)

from surfinpaint import ConformalOptions, GridOptions, fill_holes  # noqa: E402
from surfinpaint.geometry.metrics import hole_patch_of, surface_distance  # noqa: E402

DEFAULT_CONFIGS = [
    {},
    {"fit_radius": 2},
    {"fit_radius": 5},
    {"spacing": 0.35},
    {"reconstruct": "laplacian"},
    {"inpaint": "harmonic"},
    {"fidelity": 0.01},
    {"passes": 2},
]
# the names of ConformalOptions; the others are GridOptions'
CONFORMAL_NAMES = {"passes", "patch_rings", "start"}


def _options(config: dict) -> ConformalOptions:
    """The raw grid-discretization fill with ``config`` (names of either options class)."""
    outer = {k: v for k, v in config.items() if k in CONFORMAL_NAMES}
    grid = GridOptions(**{k: v for k, v in config.items() if k not in CONFORMAL_NAMES})
    return ConformalOptions(select=False, discretization="grid", grid=grid, **outer)


def _error(cut, result) -> float:
    pv, pf = hole_patch_of(result.vertices, result.faces, len(cut.vertices), cut.faces)
    d = surface_distance(pv, pf, cut.truth_vertices, cut.truth_faces, n_samples=4000)
    return d.mean / cut.diameter


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cases", default="torus,sphere,snowman,bunny,white")
    parser.add_argument("--configs", default=json.dumps(DEFAULT_CONFIGS),
                        help="JSON list of option dicts (names of GridOptions, or passes, "
                        "patch_rings, start)")
    args = parser.parse_args()
    configs = json.loads(args.configs)
    ratios: list[list[float]] = [[] for _ in configs]
    failed = [0] * len(configs)
    names = [json.dumps(c) if c else "defaults" for c in configs]
    print("| case | hole | edges | " + " | ".join(names) + " |")
    print("|---|---|---|" + "---|" * len(configs))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name, k, cut in accuracy.benchmark_cuts(args.cases.split(",")):
            fair = _error(cut, fill_holes(cut.vertices, cut.faces, method="fair"))
            if fair < 1e-9:
                continue
            cells = []
            for i, config in enumerate(configs):
                result = fill_holes(cut.vertices, cut.faces, options=_options(config))
                ratio = _error(cut, result) / fair
                if result.reports[0].fallback:
                    failed[i] += 1
                    cells.append(f"{ratio:.2f}*")
                else:
                    cells.append(f"{ratio:.2f}")
                ratios[i].append(ratio)
            print(f"| {name} | {k} | {len(cut.loop)} | " + " | ".join(cells) + " |",
                  flush=True)
    print("\n(* the conformal fill failed and the faired fill was used: ratio 1)\n")
    print("| options | median ratio | geometric mean | holes better than fair | worst | failed |")
    print("|---|---|---|---|---|---|")
    for name, r, nf in zip(names, ratios, failed, strict=True):
        r = np.array(r)
        print(f"| {name} | {np.median(r):.3f} | {np.exp(np.log(r).mean()):.3f} "
              f"| {(r < 0.99).sum()} of {len(r)} | {r.max():.2f} | {nf} |")


if __name__ == "__main__":
    main()
