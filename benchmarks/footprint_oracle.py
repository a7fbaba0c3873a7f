"""Oracle experiment: does the λ-H fill on the brain improve when the initial fill S0 has
the removed surface's area?

For each brain hole of ``accuracy.py`` the faired cap S0 is inflated along its vertex
normals (displacement ∝ ring distance from the loop, 0 on the loop) until its area equals
the removed surface's (the only use of the truth), outward (``+``) or inward (``-``), and
the λ-H fill is run from it (:func:`error_sources._variant`: estimates from the known part
only). Errors are given as ratios to the baseline's (bilaplacian fill); ``grid`` is the
rebuilt grid nodes' mean distance to the truth (one-sided, % of the hole diameter).

    python benchmarks/footprint_oracle.py [--cases pial,white]
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.sparse.csgraph import dijkstra

sys.path.insert(0, str(Path(__file__).parent))

import accuracy  # noqa: E402
import error_sources as es  # noqa: E402

from surfinpaint.fill.liepa.baseline import conventional_fill  # noqa: E402
from surfinpaint.geometry.mesh import face_areas, vertex_adjacency, vertex_normals  # noqa: E402


def inflated(vertices, fill, moving, loop, target_area, sign):
    """``vertices`` with ``moving`` pushed along the fill's normals (times ``sign``) until
    the fill's area is ``target_area`` (bisection)."""
    normals = vertex_normals(vertices, fill)[moving]
    graph = vertex_adjacency(fill, len(vertices)).astype(float)
    rings = dijkstra(graph, directed=False, indices=loop, min_only=True, unweighted=True)
    bump = (rings[moving] / rings[moving].max())[:, None]
    lo, hi = 0.0, float(np.ptp(vertices[loop], axis=0).max())
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        out = vertices.copy()
        out[moving] += sign * mid * bump * normals
        lo, hi = (mid, hi) if face_areas(out, fill).sum() < target_area else (lo, mid)
    out = vertices.copy()
    out[moving] += sign * lo * bump * normals
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cases", default="pial,white")
    args = parser.parse_args()
    print("| case | hole | truth area / cap area | S0 = cap | inflated + | inflated − | "
          "S0 = truth | grid: cap | grid: inflated + | grid: truth |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    ratios = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name, k, cut in accuracy.benchmark_cuts(args.cases.split(",")):
            n = len(cut.vertices)
            new_v, new_f = conventional_fill(cut.vertices, cut.faces, cut.loop)
            fill = np.asarray(new_f, np.int64)
            cap = np.vstack([cut.vertices, new_v])
            moving = n + np.arange(len(new_v))
            truth_area = face_areas(cut.truth_vertices, cut.truth_faces).sum()
            fair = es._error(*es.hole_patch_of(cap, np.vstack([cut.faces, fill]), n,
                                               cut.faces), cut)
            up = inflated(cap, fill, moving, cut.loop, truth_area, 1.0)
            down = inflated(cap, fill, moving, cut.loop, truth_area, -1.0)
            try:
                row = [es._variant(s0, fill, moving, cut, estimate_on="known",
                                   inpainting=True) / fair for s0 in (cap, up, down)]
                row.append(es._variant(*es.truth_as_fill(cut), cut, estimate_on="known",
                                       inpainting=True) / fair)
                row += [es._variant(s0, fill, moving, cut, estimate_on="known",
                                    inpainting=True, grid_points=True) for s0 in (cap, up)]
                row.append(es._variant(*es.truth_as_fill(cut), cut, estimate_on="known",
                                       inpainting=True, grid_points=True))
            except Exception as exc:  # noqa: BLE001 - a failed hole is a row, not a crash
                print(f"| {name} | {k} | failed: {exc} |")
                continue
            ratios.append(row[:4])
            area = truth_area / face_areas(cap, fill).sum()
            print(f"| {name} | {k} | {area:.2f} | " + " | ".join(f"{x:.2f}" for x in row)
                  + " |", flush=True)
    r = np.array(ratios)
    print(f"\nmedian ratio to the baseline over {len(r)} holes: S0 = cap "
          f"{np.median(r[:, 0]):.2f}, inflated + {np.median(r[:, 1]):.2f}, inflated − "
          f"{np.median(r[:, 2]):.2f}, S0 = truth {np.median(r[:, 3]):.2f}")


if __name__ == "__main__":
    main()
