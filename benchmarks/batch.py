"""Batch throughput (issue 17): generated meshes filled by ``surfinpaint batch`` with
``--jobs 1``, ``--jobs 2`` and on a local Dask cluster of 2 worker processes; prints a
markdown table.

Each run is the whole command in a fresh process (imports and worker start-up included),
into its own output folder; the Dask cluster is started before its run and not timed (the
command is for an existing cluster): once with workers that start cold (surfinpaint is
imported, and its kernels loaded, by the first task), once with workers started with the
preload ``surfinpaint.app.dask_worker`` (docs/batch.md). The outputs of all runs are
checked to be identical file by file. On a shared
machine the table also says how much a second busy process gains there at the time (two
processes spinning against one): a speed-up cannot exceed it.

    python benchmarks/batch.py [--files 40] [--repeats 1] [--method conformal] [--folder DIR]
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from surfinpaint.data import snowman, sphere, tooth, torus
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.io.formats import read_mesh, write_mesh


def _spread_centres(vertices: np.ndarray, n: int, rng: np.random.Generator) -> list[int]:
    """``n`` vertices far apart: a random one, then each the farthest from those chosen."""
    chosen = [int(rng.integers(len(vertices)))]
    distance = np.linalg.norm(vertices - vertices[chosen[0]], axis=1)
    for _ in range(n - 1):
        chosen.append(int(np.argmax(distance)))
        distance = np.minimum(distance, np.linalg.norm(vertices - vertices[chosen[-1]], axis=1))
    return chosen


def make_meshes(folder: Path, count: int) -> list[Path]:
    """``count`` meshes of 10k-26k vertices with 2-3 holes each (snowmen, spheres, tori,
    teeth) in nested folders, as subjects of a study would be."""
    shapes = [snowman(0.03), sphere(5), torus(n_major=256, n_minor=100), tooth(0.02)]
    rng = np.random.default_rng(17)
    paths = []
    for i in range(count):
        v, f = shapes[i % len(shapes)]
        h = mean_edge_length(v, f)
        n_holes = 2 + i % 2
        cut = cut_holes(v, f, _spread_centres(v, n_holes, rng),
                        list(rng.uniform(2.0, 3.5, n_holes) * h))
        path = folder / f"subject{i // 2:02d}" / f"{'lh' if i % 2 == 0 else 'rh'}.ply"
        path.parent.mkdir(parents=True, exist_ok=True)
        write_mesh(path, cut.vertices, cut.faces)
        paths.append(path)
    return paths


def timed(command: list[str]) -> tuple[float, float]:
    """Wall seconds of ``command``, and the CPU seconds (user + system) of it and of the
    processes it waited for (its local workers; not a Dask cluster's)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    seconds = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed ({done.returncode}):\n{done.stderr}")
    return seconds, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def spare_cores(seconds: float = 2.0) -> float:
    """Work of two busy processes at once over that of one (2.0: two idle cores; 1.0: the
    machine gives a second process nothing): what any speed-up measured now is bounded by."""
    import multiprocessing

    counts = []
    for n in (1, 2):
        with multiprocessing.get_context("spawn").Pool(n) as pool:
            counts.append(sum(pool.map(_spin, [seconds] * n)))
    return counts[1] / counts[0]


def _spin(seconds: float) -> int:
    started, n = time.perf_counter(), 0
    while time.perf_counter() - started < seconds:
        n += 1
    return n


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--files", type=int, default=40)
    parser.add_argument("--method", default="conformal", choices=("conformal", "fair"))
    parser.add_argument("--folder", help="work folder (default: a temporary one)")
    parser.add_argument("--repeats", type=int, default=1,
                        help="rounds of the three runs; the best of each is tabled")
    args = parser.parse_args()
    work = Path(args.folder or tempfile.mkdtemp(prefix="surfinpaint-batch-"))
    inputs = work / "scans"
    paths = make_meshes(inputs, args.files)
    batch = [sys.executable, "-m", "surfinpaint", "batch", str(inputs), "--method",
             args.method, "--overwrite", "-q", "-o"]
    from distributed import LocalCluster

    load_before, spare = os.getloadavg()[0], spare_cores()
    runs: dict[str, list[tuple[float, float]]] = {
        "--jobs 1": [], "--jobs 2": [], "Dask, 2 workers": [], "Dask, preloaded workers": []}
    for _ in range(args.repeats):  # the modes alternate, so that a change of load hits all
        runs["--jobs 1"].append(timed([*batch, str(work / "jobs1"), "--jobs", "1"]))
        runs["--jobs 2"].append(timed([*batch, str(work / "jobs2"), "--jobs", "2"]))
        # a fresh cluster for each Dask run (not timed): workers that import surfinpaint and
        # load its kernels in their first task, or at their start with the documented preload
        for name, folder, preload in (
                ("Dask, 2 workers", "dask", []),
                ("Dask, preloaded workers", "dask_preloaded", ["surfinpaint.app.dask_worker"])):
            with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                              dashboard_address=":0", preload=preload) as cluster:
                runs[name].append(timed([*batch, str(work / folder), "--dask-scheduler",
                                         cluster.scheduler_address]))
    load_after = os.getloadavg()[0]
    for path in paths:
        relative = path.relative_to(inputs)
        first = read_mesh(work / "jobs1" / relative)
        for other in ("jobs2", "dask", "dask_preloaded"):
            again = read_mesh(work / other / relative)
            if not all(np.array_equal(a, b) for a, b in zip(first, again, strict=True)):
                raise SystemExit(f"{other}/{relative} differs from jobs1/{relative}")
    best = {name: min(times) for name, times in runs.items()}
    print(f"{args.files} meshes ({sum(len(read_mesh(p)[0]) for p in paths)} vertices in "
          f"all, 2-3 holes each), --method {args.method}, {os.cpu_count()} cores; load "
          f"average (1 min) {load_before:.1f} before, {load_after:.1f} after; two busy "
          f"processes got {spare:.2f}x the work of one; outputs of the three runs "
          f"identical; best of {args.repeats}\n")
    print("| run | wall (s) | all runs (s) | CPU (s) | speed-up over --jobs 1 | "
          "against --jobs 2 |")
    print("|---|---:|---|---:|---:|---:|")
    for name, (seconds, cpu) in best.items():
        print(f"| {name} | {seconds:.1f} | {', '.join(f'{t:.1f}' for t, _ in runs[name])} | "
              f"{cpu:.1f}{' (client only)' if 'Dask' in name else ''} | "
              f"{best['--jobs 1'][0] / seconds:.2f}x | "
              f"{seconds / best['--jobs 2'][0] - 1:+.0%} |")


if __name__ == "__main__":
    main()
