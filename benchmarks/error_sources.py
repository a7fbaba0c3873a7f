"""Where the conformal fill's error comes from: the benchmark holes, filled with parts of the
pipeline replaced by the ground truth.

For each hole of ``accuracy.py`` (two-sided mean error to the removed surface, in % of the
hole diameter):

- ``fair``: the conventional fill (triangulate, refine, bilaplacian fairing): the baseline.
- ``fair3``: the same with trilaplacian fairing (the conformal method's self-check chooses
  between the two for its fallback).
- ``conformal``: the raw conformal fill of the paper's grid discretization (``select=False,
  discretization="grid"``): S0 is the ``fair`` fill. Every column below replaces a part of
  that grid pipeline (this study predates the mesh discretization, the default now).
- ``S0=truth``: the same λ-H pipeline with the removed surface itself as the initial fill
  (its map, grid and fill vertices), estimates still from the known part only.
- ``clean data``: S0 = truth, λ and H fitted on the whole true patch (no estimation noise at
  the hole's edge), then the biharmonic inpainting of the hole region as usual: what the
  inpainting model itself predicts from perfect data.
- ``true λ,H``: S0 = truth and no inpainting: the rebuild from the true (λ, H).

The column ``true λ,H`` isolates the rebuild, ``clean data`` the inpainting model,
``S0=truth`` the initial fill and estimation noise. The two ``grid`` columns measure the
rebuilt surface itself, before any vertex is placed on it: the mean distance from the
rebuilt hole grid nodes to the truth (one-sided), with S0 the ``fair`` fill (as
``conformal``) and with S0 the truth (as ``S0=truth``).

    python benchmarks/error_sources.py                      # all cases, ~3 min
    python benchmarks/error_sources.py --cases snowman,tooth
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

import accuracy  # noqa: E402  (the benchmark's cases and holes)

from surfinpaint import ConformalOptions, fill_holes  # noqa: E402
from surfinpaint.fill.conformal.grid_pass import patch_grid, reconstruct_patch  # noqa: E402
from surfinpaint.fill.conformal.patch import hole_patch  # noqa: E402
from surfinpaint.fill.liepa.baseline import faired_fill  # noqa: E402
from surfinpaint.geometry.metrics import (  # noqa: E402
    hole_patch_of,
    point_mesh_distance,
    surface_distance,
)
from surfinpaint.representation.estimation import robust_lambda_h  # noqa: E402
from surfinpaint.representation.grid import interpolate  # noqa: E402
from surfinpaint.representation.inpainting import inpaint  # noqa: E402
from surfinpaint.representation.reconstruction import dilate  # noqa: E402

COLUMNS = ("fair", "fair3", "conformal", "S0=truth", "clean data", "true λ,H",
           "grid, S0=fair", "grid, S0=truth")


def _error(patch_v, patch_f, cut) -> float:
    d = surface_distance(patch_v, patch_f, cut.truth_vertices, cut.truth_faces,
                         n_samples=4000)
    return 100.0 * d.mean / cut.diameter


def truth_as_fill(cut) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The cut mesh's vertices followed by the removed interior vertices, the removed faces
    over them, and the ids of those interior vertices (the truth as a fill, or as an
    initial fill)."""
    n = len(cut.vertices)
    hole = cut.holes[0]
    where = np.full(int(max(cut.kept.max(), hole.truth_ids.max())) + 1, -1)
    where[cut.kept] = np.arange(n)
    local = where[hole.truth_ids]
    new = np.flatnonzero(local < 0)
    local[new] = n + np.arange(len(new))
    vertices = np.vstack([cut.vertices, hole.truth_vertices[new]])
    return vertices, local[hole.truth_faces], n + np.arange(len(new))


def _variant(vertices, fill, moving, cut, *, estimate_on: str, inpainting: bool,
             grid_points: bool = False) -> float:
    patch, _ = hole_patch(cut.faces, cut.loop, fill, 10)
    pg = patch_grid(vertices, patch, len(fill))
    valid = pg.inside if estimate_on == "all" else pg.known
    lam0, H0 = robust_lambda_h(pg.phi, pg.h, valid=valid, radius=3, sigma=2.25)
    region = dilate(pg.hole, 1) & pg.inside
    domain = pg.inside & ((np.isfinite(lam0) & np.isfinite(H0)) | region)
    if inpainting:
        lam0, H0 = np.moveaxis(inpaint(np.stack([lam0, H0], -1), region, domain=domain,
                                       h=pg.h), -1, 0)
    rebuilt, _ = reconstruct_patch(pg, np.where(domain, lam0, np.nan),
                                   np.where(domain, H0, np.nan), region, domain)
    if grid_points:
        d = point_mesh_distance(rebuilt[pg.hole], cut.truth_vertices, cut.truth_faces)
        return 100.0 * float(d.mean()) / cut.diameter
    moved = vertices.copy()
    moved[moving] = interpolate(rebuilt, pg.grid, pg.uv_of(moving), order=3)
    return _error(moved, fill, cut)


def hole_row(cut) -> list[float]:
    n = len(cut.vertices)
    out = []
    for options in ({"method": "fair"}, {"method": "fair", "fair_order": 3},
                    {"options": ConformalOptions(select=False, discretization="grid")}):
        res = fill_holes(cut.vertices, cut.faces, [cut.loop], **options)
        out.append(_error(*hole_patch_of(res.vertices, res.faces, n, cut.faces), cut))
    truth = truth_as_fill(cut)
    fair_v, fair_f, _ = faired_fill(cut.vertices, cut.faces, cut.loop, 2)
    faired = (np.vstack([cut.vertices, fair_v]), fair_f, n + np.arange(len(fair_v)))
    for s0, estimate_on, inpainting, grid_points in (
            (truth, "known", True, False), (truth, "all", True, False),
            (truth, "all", False, False), (faired, "known", True, True),
            (truth, "known", True, True)):
        try:
            out.append(_variant(*s0, cut, estimate_on=estimate_on, inpainting=inpainting,
                                grid_points=grid_points))
        except Exception:  # a failed variant is a missing cell, not a crash
            out.append(float("nan"))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cases",
                        default="bunny,face,pial,white,sphere,torus,cube,snowman,tooth")
    args = parser.parse_args()
    rows, names = [], []
    print("| case | hole | edges | " + " | ".join(COLUMNS) + " |")
    print("|---|---|---|" + "---|" * len(COLUMNS))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name, k, cut in accuracy.benchmark_cuts(args.cases.split(",")):
            row = hole_row(cut)
            if row[0] < 1e-9:  # the fill is exact (a flat face): no ratio to take
                continue
            rows.append(row)
            names.append(name)
            print(f"| {name} | {k} | {len(cut.loop)} | "
                  + " | ".join(f"{x:.3f}" for x in row) + " |", flush=True)
    r = np.array(rows)
    # the first six columns are two-sided errors, compared with the baseline's; the two
    # grid columns are one-sided and only compared with each other
    ratio = np.column_stack([r[:, 1:6] / r[:, :1], r[:, 6] / r[:, 7]])
    heads = [*COLUMNS[1:6], "grid S0=fair / grid S0=truth"]
    print("\nMedian over holes (geometric mean) of the ratio to the baseline's error, and"
          " of the\nrebuilt grid's error with S0 = the faired fill to that with S0 = the"
          " truth:\n")
    print("| case | holes | " + " | ".join(heads) + " |")
    print("|---|---|" + "---|" * len(heads))
    names_arr = np.array(names)
    for name in [*dict.fromkeys(names), "all"]:
        sel = np.ones(len(rows), bool) if name == "all" else names_arr == name
        cells = []
        for c in range(len(heads)):
            x = ratio[sel, c]
            x = x[np.isfinite(x)]
            cells.append(f"{np.median(x):.2f} ({np.exp(np.log(x).mean()):.2f})"
                         if len(x) else "n/a")
        print(f"| {name} | {sel.sum()} | " + " | ".join(cells) + " |")

if __name__ == "__main__":
    main()
