"""Speed and memory of fill_holes (issue 4's targets), printed as markdown tables.

1. Seconds per hole against the hole's boundary edges, for the conformal method (with and
   without its self-check) and the faired baseline, on holes cut from a torus.
2. Peak memory and time for a mesh of about 1M vertices with 10 holes of about 100 edges,
   filled in a fresh process per method that only reads the mesh (an .npz) and fills it, so
   the peak is reading plus filling; the peak after reading is reported separately.

    python benchmarks/speed.py [--quick]
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time
import warnings

import numpy as np

from surfinpaint import ConformalOptions, fill_holes
from surfinpaint.data import torus
from surfinpaint.geometry.cutting import cut_geodesic_disk, cut_holes
from surfinpaint.geometry.mesh import mean_edge_length


def per_hole_times(quick: bool) -> list[dict]:
    v, f = torus(R=1.0, r=0.4, n_major=192, n_minor=80)
    h = mean_edge_length(v, f)
    rows = []
    radii = (3, 6, 10, 14) if quick else (3, 5, 8, 11, 14, 16)
    methods = (("fair", {}), ("conformal", {"options": ConformalOptions(select=False)}),
               ("conformal", {}))
    # warm up compiled kernels
    warm = cut_geodesic_disk(v, f, 0, 3 * h)
    for m, o in methods:
        fill_holes(warm.vertices, warm.faces, holes=[warm.loop], method=m, **o)
    for k, r in enumerate(radii):
        cut = cut_geodesic_disk(v, f, 1000 * k + 17, r * h)
        row = {"edges": len(cut.loop)}
        for m, o in methods:
            name = m if o.get("options", ConformalOptions()).select else \
                m + " (no self-check)"
            times = []
            for _ in range(1 if quick else 3):
                t = time.perf_counter()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    fill_holes(cut.vertices, cut.faces, holes=[cut.loop], method=m, **o)
                times.append(time.perf_counter() - t)
            row[name] = min(times)
        rows.append(row)
    return rows


def _make_large(path: str, n_major: int, n_minor: int) -> None:
    v, f = torus(R=1.0, r=0.4, n_major=n_major, n_minor=n_minor)
    h = mean_edge_length(v, f)
    rng = np.random.default_rng(0)
    centres = rng.choice(len(v), 10, replace=False)
    cut = cut_holes(v, f, centres, [10 * h] * 10)
    np.savez(path, vertices=cut.vertices, faces=cut.faces)


def _peak_mb() -> float:
    """Peak resident memory of this process (VmHWM). Not ru_maxrss: on Linux that survives
    execve, so a child would report its parent's peak."""
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def _child(method: str, path: str) -> None:
    with np.load(path) as data:  # "reading the mesh"
        vertices, faces = data["vertices"], data["faces"]
    before = _peak_mb()
    t = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = fill_holes(vertices, faces, method=method)
    seconds = time.perf_counter() - t
    peak = _peak_mb()
    print(json.dumps({"method": method, "vertices": len(vertices),
                      "holes": len(result.reports),
                      "max_edges": max(r.n_edges for r in result.reports),
                      "seconds": seconds, "peak_mb_before": before, "peak_mb": peak,
                      "kept": [r.method for r in result.reports]}))


def large_mesh(quick: bool) -> list[dict]:
    import os
    import tempfile

    n_major, n_minor = (1000, 250) if quick else (2000, 500)
    out = []
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "large.npz")
        _make_large(path, n_major, n_minor)
        for method in ("fair", "conformal"):
            proc = subprocess.run([sys.executable, __file__, "--child", method, path],
                                  capture_output=True, text=True, check=True)
            out.append(json.loads(proc.stdout.strip().splitlines()[-1]))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--child", nargs=2, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        _child(args.child[0], args.child[1])
        return
    rows = per_hole_times(args.quick)
    names = [k for k in rows[0] if k != "edges"]
    print("### Seconds per hole (torus, best of runs)\n")
    print("| boundary edges | " + " | ".join(names) + " |")
    print("|---|" + "---|" * len(names))
    for r in rows:
        print(f"| {r['edges']} | " + " | ".join(f"{r[n]:.3f}" for n in names) + " |")
    print("\n### A large mesh with 10 holes\n")
    print("| method | vertices | holes (max edges) | seconds | peak MB after reading | "
          "peak MB |")
    print("|---|---|---|---|---|---|")
    for r in large_mesh(args.quick):
        print(f"| {r['method']} | {r['vertices']} | {r['holes']} ({r['max_edges']}) "
              f"| {r['seconds']:.2f} | {r['peak_mb_before']:.0f} | {r['peak_mb']:.0f} |")


if __name__ == "__main__":
    main()
