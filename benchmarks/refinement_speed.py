"""Seconds per hole of ``refine_patch`` in both styles ("liepa", "cgal") on the tuning holes
of ``benchmarks/holes_manifest.json`` (the triangulation made once per hole, best of three
runs; docs/candidates.md, "CGAL-style refinement (session 9)").

Run::

    python benchmarks/refinement_speed.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import holes_manifest  # noqa: E402
import validation  # noqa: E402
import validation_meshes as vm  # noqa: E402

from surfinpaint.fill.liepa.refinement import REFINEMENTS, refine_patch  # noqa: E402
from surfinpaint.fill.liepa.triangulation import minimum_weight_triangulation  # noqa: E402
from surfinpaint.geometry.mesh import faces_near, orient_loop  # noqa: E402


def main() -> None:
    seconds: dict[str, list[float]] = {style: [] for style in REFINEMENTS}
    edges = []
    refine_patch(np.eye(3), np.array([[0, 1, 2]]), np.arange(3))  # compile the flip kernel
    for entry in holes_manifest.read(holes_manifest.MANIFEST)["meshes"]:
        if entry["split"] != "tuning":
            continue
        mesh = vm.load_entry(entry)
        for hole in entry["holes"]:
            cut = validation._cut(mesh, hole)
            f = faces_near(cut.faces, cut.loop, 1, len(cut.vertices))
            loop = orient_loop(f, cut.loop, boundary=False)
            tri = minimum_weight_triangulation(cut.vertices, loop, f)
            edges.append(len(loop))
            for style in REFINEMENTS:
                best = np.inf
                for _ in range(3):
                    t0 = time.perf_counter()
                    refine_patch(cut.vertices, tri, loop, faces=f, style=style)
                    best = min(best, time.perf_counter() - t0)
                seconds[style].append(best)
    small = np.array(edges) <= 100
    print("| style | holes | median s | median s, ≤ 100 edges | max s |")
    print("|---|---|---|---|---|")
    for style, x in seconds.items():
        x = np.array(x)
        print(f"| {style} | {len(x)} | {np.median(x):.4f} | {np.median(x[small]):.4f} | "
              f"{x.max():.4f} |")


if __name__ == "__main__":
    main()
