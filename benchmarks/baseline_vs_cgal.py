"""Conventional fill (Liepa 2003, ours) against CGAL's triangulate_refine_and_fair_hole.

Cuts geodesic disks out of an icosphere, a torus and PyMeshLab's bunny, fills each hole with
:func:`surfinpaint.fill.liepa.baseline.conventional_fill` and with CGAL (Python bindings, package
``cgal``), and prints a markdown table of the two-sided distance to the removed truth (mean
and Hausdorff over area-uniform samples of both surfaces, in % of the hole diameter) and the
fill time (CGAL's includes writing and reading the mesh as OFF, its bindings' only way in).

Run: ``.venv/bin/python benchmarks/baseline_vs_cgal.py [--samples N]``
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import trimesh
from peers import cgal_fill  # benchmarks/peers.py: CGAL through its SWIG bindings

from surfinpaint.data import pymeshlab_sample, torus
from surfinpaint.fill.liepa.baseline import conventional_fill
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.metrics import surface_distance


def _icosphere(subdivisions: int):
    m = trimesh.creation.icosphere(subdivisions)
    return np.asarray(m.vertices), np.asarray(m.faces)


def cases():
    """(name, vertices, faces, centre vertex, radius) of each benchmark hole."""
    ico = trimesh.creation.icosphere(5)
    sv, sf = np.asarray(ico.vertices), np.asarray(ico.faces)
    tv, tf = torus()
    bv, bf = pymeshlab_sample("bunny.obj")
    diag = float(np.linalg.norm(bv.max(0) - bv.min(0)))
    # bunny centres: vertices nearest to a few fixed directions from the centroid
    c = bv.mean(0)
    dirs = np.array([[0, 1, 0.3], [1, 0, 0], [0, 0, 1], [-1, 0.5, 0]], float)
    bunny_centres = [int(np.argmax((bv - c) @ d)) for d in dirs]
    out = [
        ("sphere r=0.2", sv, sf, 0, 0.2),
        ("sphere r=0.5", sv, sf, 100, 0.5),
        ("sphere r=1.0", sv, sf, 200, 1.0),
        ("sphere(6) r=1.0", *_icosphere(6), 0, 1.0),
        ("torus outer r=0.3", tv, tf, int(np.argmax(tv[:, 0])), 0.3),
        ("torus inner r=0.3", tv, tf, int(np.argmin(np.linalg.norm(tv[:, :2], axis=1))), 0.3),
        ("torus top r=0.5", tv, tf, int(np.argmax(tv[:, 2])), 0.5),
    ]
    for k, (cid, frac) in enumerate(zip(bunny_centres, [0.06, 0.1, 0.08, 0.12], strict=True)):
        out.append((f"bunny {k} r={frac:g}·diag", bv, bf, cid, frac * diag))
    return out


def patch_mesh(vertices, new_v, new_f):
    """The fill patch alone, reindexed, for the distance computation."""
    allv = np.vstack([vertices, new_v])
    used = np.unique(new_f)
    remap = np.full(len(allv), -1)
    remap[used] = np.arange(len(used))
    return allv[used], remap[new_f]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--samples", type=int, default=20000)
    args = parser.parse_args()
    # compile the numba kernel before timing
    small = trimesh.creation.icosphere(2)
    cut = cut_geodesic_disk(small.vertices, small.faces, 0, 0.3)
    conventional_fill(cut.vertices, cut.faces, cut.loop)

    rows = []
    for name, v, f, centre, radius in cases():
        cut = cut_geodesic_disk(v, f, centre, radius)
        diam = cut.diameter
        res = {}
        for method in ("ours", "cgal"):
            t0 = time.perf_counter()
            if method == "ours":
                nv, nf = conventional_fill(cut.vertices, cut.faces, cut.loop)
            else:
                nv, nf = cgal_fill(cut.vertices, cut.faces, cut.loop)
            dt = time.perf_counter() - t0
            pv, pf = patch_mesh(cut.vertices, nv, nf)
            d = surface_distance(pv, pf, cut.truth_vertices, cut.truth_faces,
                                 n_samples=args.samples)
            res[method] = (100 * d.mean / diam, 100 * d.hausdorff / diam, dt, len(nf))
        rows.append((name, len(cut.loop), res))

    print("| hole | loop edges | ours mean % | CGAL mean % | ours/CGAL | ours Hausdorff % "
          "| CGAL Hausdorff % | ours faces | CGAL faces | ours s | CGAL s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    ratios = []
    for name, k, res in rows:
        o, c = res["ours"], res["cgal"]
        ratios.append(o[0] / c[0])
        print(f"| {name} | {k} | {o[0]:.3f} | {c[0]:.3f} | {o[0] / c[0]:.2f} | {o[1]:.3f} "
              f"| {c[1]:.3f} | {o[3]} | {c[3]} | {o[2]:.3f} | {c[2]:.3f} |")
    print(f"\nmean ours/CGAL ratio of mean error: {np.mean(ratios):.3f}; "
          f"geometric mean {np.exp(np.mean(np.log(ratios))):.3f}; worst {max(ratios):.3f}")


if __name__ == "__main__":
    main()
