"""Timings of mesh I/O and validation on a ~1M-face torus (prints a table).

    .venv/bin/python benchmarks/bench_io.py [n_faces]
"""

from __future__ import annotations

import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

from surfinpaint.geometry.validation import nonmanifold_vertices, validate_mesh
from surfinpaint.io.formats import MeshWarning, read_mesh, write_mesh


def torus(n_faces: int) -> tuple[np.ndarray, np.ndarray]:
    n2 = max(3, int(np.sqrt(n_faces / 4)))
    n1 = max(3, n_faces // (2 * n2))
    i, j = np.meshgrid(np.arange(n1), np.arange(n2), indexing="ij")
    u, w = 2 * np.pi * i / n1, 2 * np.pi * j / n2
    v = np.stack([(2 + np.cos(w)) * np.cos(u), (2 + np.cos(w)) * np.sin(u), np.sin(w)], -1)

    def idx(a, b):
        return (a % n1) * n2 + (b % n2)

    a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
    f = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                        np.stack([a, c, d], -1).reshape(-1, 3)])
    return v.reshape(-1, 3), f


def main() -> None:
    n_faces = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    v, f = torus(n_faces)
    print(f"torus: {len(v)} vertices, {len(f)} faces\n")
    t = time.perf_counter()
    validate_mesh(v, f)
    t_val = time.perf_counter() - t
    t = time.perf_counter()
    nonmanifold_vertices(f)
    t_nm = time.perf_counter() - t
    print(f"validate_mesh        {t_val:6.2f} s")
    print(f"nonmanifold_vertices {t_nm:6.2f} s\n")
    print(f"{'format':10s} {'write s':>8s} {'read s':>8s} {'MB':>7s} {'max |dv|':>10s} same order")
    with tempfile.TemporaryDirectory() as tmp:
        for name in ["m.ply", "ascii.ply", "m.obj", "m.off", "m.stl", "m.gii", "m.gii.gz",
                     "lh.pial"]:
            path = Path(tmp) / name
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", MeshWarning)
                t = time.perf_counter()
                write_mesh(path, v, f, ascii=name.startswith("ascii"))
                tw = time.perf_counter() - t
            t = time.perf_counter()
            v2, f2 = read_mesh(path)
            tr = time.perf_counter() - t
            same = v2.shape == v.shape and np.array_equal(f2, f)
            dv = np.abs(v2 - v).max() if v2.shape == v.shape else float("nan")
            mb = path.stat().st_size / 1e6
            print(f"{name:10s} {tw:8.2f} {tr:8.2f} {mb:7.1f} {dv:10.2e} {same}")


if __name__ == "__main__":
    main()
