"""Timings of the robustness checks: patch-vs-surroundings intersection tests and the
non-manifold repair (prints a table).

    .venv/bin/python benchmarks/bench_robustness.py
"""

from __future__ import annotations

import time

import numpy as np

from surfinpaint.data import pymeshfix_bunny, pymeshlab_sample, sphere
from surfinpaint.geometry.intersection import patch_intersects_surroundings, self_intersections
from surfinpaint.geometry.repair import remove_nonmanifold_faces


def best_of(fn, repeat: int = 5) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def main() -> None:
    rows = []
    v, f = sphere(5)
    order = np.argsort(np.linalg.norm(v[f].mean(axis=1) - v[0], axis=1))
    for n_fill, n_ring in [(500, 1500), (2000, 5000), (8000, 12000)]:
        fill, ring = f[order[:n_fill]], f[order[n_fill:n_fill + n_ring]]
        rows.append((f"patch_intersects_surroundings {n_fill} x {n_ring}",
                     best_of(lambda fill=fill, ring=ring:
                             patch_intersects_surroundings(v, fill, ring))))
    rows.append((f"self_intersections, icosphere {len(f)} faces",
                 best_of(lambda: self_intersections(v, f), 2)))
    for name, load in [("PyMeshFix bunny", pymeshfix_bunny),
                       ("PyMeshLab face000", lambda: pymeshlab_sample("rangemaps/face000.ply"))]:
        bv, bf = load()
        rows.append((f"remove_nonmanifold_faces, {name} {len(bf)} faces",
                     best_of(lambda bv=bv, bf=bf: remove_nonmanifold_faces(bv, bf), 3)))
    width = max(len(r[0]) for r in rows)
    print(f"{'step':<{width}}  seconds")
    for name, seconds in rows:
        print(f"{name:<{width}}  {seconds:7.4f}")


if __name__ == "__main__":
    main()
