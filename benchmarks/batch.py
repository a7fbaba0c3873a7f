"""Batch throughput (issue 17): generated meshes filled by ``surfinpaint batch`` with
``--jobs 1``, ``--jobs 2`` and on a local Dask cluster of 2 worker processes, in paired
rounds; prints the README table (medians, spreads, CPU beside wall, the load).

Each run is the whole command in a fresh process (imports and worker start-up included).
The runs of a round follow one another (their order rotates from round to round, so that
no run always comes first or last), and each round's speed-ups are taken within the round:
a change of load hits the runs it compares alike. Each run is a first run into an empty
output folder (no earlier summary: the files are ordered by the first-run rule), unless
``--rerun`` (the same folder every round, ``--overwrite``: ordered by the last round's
seconds). The Dask cluster is started before its run and not timed (the command is for an
existing cluster), fresh for every run: its workers started with the documented preload
``surfinpaint.app.dask_worker`` (imports and kernels at the worker's start, docs/batch.md)
and, with ``--cold``, also without it (surfinpaint imported, and its kernels loaded, by the
first task). CPU seconds: the command and its local workers; for Dask the command and the
cluster's workers (asked through the client), the scheduler apart. The outputs of all runs
are checked identical file by file, after every round. The table also says how much a
second busy process gains on this machine at the time (two processes spinning against one,
before and after): no speed-up can exceed it.

    python benchmarks/batch.py [--files 40] [--rounds 5] [--cold] [--rerun]
        [--method conformal] [--folder DIR] [--json FILE]
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from surfinpaint.data import snowman, sphere, tooth, torus
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.io.formats import read_mesh, write_mesh

JOBS1, JOBS2, DASK, COLD = "--jobs 1", "--jobs 2", "Dask, preloaded workers", "Dask, cold workers"
PRELOAD = "surfinpaint.app.dask_worker"
SPEEDUP_TARGET, DASK_TARGET = 1.7, 0.15
RERUN, FIRST_RUN = "a rerun (--overwrite; files ordered by the last round)", \
    "a first run into an empty folder"


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


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _self_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def _process_cpu() -> float:
    """This process's CPU seconds (run on each Dask worker through the client)."""
    return _self_cpu()


def timed(command: list[str]) -> tuple[float, float]:
    """Wall seconds of ``command``, and the CPU seconds (user + system) of it and of the
    processes it waited for (its local workers; not a Dask cluster's)."""
    before = _children_cpu()
    started = time.perf_counter()
    done = subprocess.run(command, capture_output=True, text=True)
    seconds = time.perf_counter() - started
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed ({done.returncode}):\n{done.stderr}")
    return seconds, _children_cpu() - before


def timed_on_cluster(command: list[str], preload: list[str]) -> tuple[float, float, float]:
    """:func:`timed` against a fresh local cluster of 2 single-thread worker processes
    (started, and settled, before the clock starts); the CPU adds that of the workers during
    the run. Also returns the CPU of this process meanwhile (the scheduler's thread)."""
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0", preload=preload,
                      silence_logs=logging.ERROR) as cluster, \
            Client(cluster) as client:
        client.wait_for_workers(2)
        time.sleep(1.0)  # the workers' start-up done before the clock starts
        workers_before = sum(client.run(_process_cpu).values())
        scheduler_before = _self_cpu()
        seconds, cpu = timed([*command, "--dask-scheduler", cluster.scheduler_address])
        scheduler = _self_cpu() - scheduler_before
        workers = sum(client.run(_process_cpu).values()) - workers_before
    return seconds, cpu + workers, scheduler


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


def _run_rounds(args: argparse.Namespace, work: Path, batch: list[str],
                check: Callable[[list[str]], None]) -> list[dict]:
    """The paired rounds: per round the load before it and each run's wall, CPU (and, for
    Dask, the scheduler's CPU); ``check(modes)`` after each round (not timed: the next
    round's runs replace the outputs)."""
    modes = [JOBS1, JOBS2, DASK] + ([COLD] if args.cold else [])
    folders = {JOBS1: "jobs1", JOBS2: "jobs2", DASK: "dask", COLD: "dask_cold"}
    rounds = []
    for r in range(args.rounds):
        record: dict = {"load": os.getloadavg()[0]}
        for mode in modes[r % len(modes):] + modes[:r % len(modes)]:
            out = work / folders[mode]
            if not args.rerun:
                shutil.rmtree(out, ignore_errors=True)  # a first run: no earlier summary
            command = [*batch, str(out)]
            if mode in (JOBS1, JOBS2):
                record[mode] = (*timed([*command, "--jobs", mode[-1]]), 0.0)
            else:
                record[mode] = timed_on_cluster(command, [PRELOAD] if mode == DASK else [])
        rounds.append(record)
        check(modes)
        print(f"round {r + 1}: load {record['load']:.1f}; " + ", ".join(
            f"{mode} {record[mode][0]:.1f} s" for mode in modes), file=sys.stderr)
    return rounds


def _check_identical(work: Path, inputs: Path, paths: list[Path], modes: list[str]) -> None:
    folders = {JOBS2: "jobs2", DASK: "dask", COLD: "dask_cold"}
    for path in paths:
        relative = path.relative_to(inputs)
        first = read_mesh(work / "jobs1" / relative)
        for mode in modes:
            if mode == JOBS1:
                continue
            again = read_mesh(work / folders[mode] / relative)
            if not all(np.array_equal(a, b) for a, b in zip(first, again, strict=True)):
                raise SystemExit(f"{folders[mode]}/{relative} differs from jobs1/{relative}")


def _range(values: list[float], form: str) -> str:
    low, high = form.format(min(values)), form.format(max(values))
    return low if low == high else f"{low} to {high}"


def print_table(args: argparse.Namespace, rounds: list[dict], info: dict) -> None:
    """The README table: per run the median wall and its range, the median CPU, and the
    median (and range) of the per-round ratios against ``--jobs 1`` and ``--jobs 2``."""
    modes = [m for m in (JOBS1, JOBS2, DASK, COLD) if m in rounds[0]]
    loads = [r["load"] for r in rounds] + [info["load_after"]]
    print(f"`python benchmarks/batch.py --files {args.files} --rounds {args.rounds}"
          f"{' --cold' if args.cold else ''}{' --rerun' if args.rerun else ''}`: "
          f"{args.files} meshes ({info['vertices']:,} vertices in all, 2-3 holes each), "
          f"--method {args.method}, {os.cpu_count()} cores; {args.rounds} paired rounds, "
          f"each {RERUN if args.rerun else FIRST_RUN}; "
          f"load average (1 min) {_range(loads, '{:.1f}')} over the rounds; two busy "
          f"processes got {info['spare_before']:.2f}x (before) and {info['spare_after']:.2f}x "
          f"(after) the work of one; outputs of all runs identical.\n")
    spare = min(info["spare_before"], info["spare_after"])
    if spare < SPEEDUP_TARGET:
        print(f"**Not a check of the targets**: a second busy process got {spare:.2f}x the "
              f"work of one at some point (the {SPEEDUP_TARGET}x target needs two free "
              "cores); the machine was shared.\n")
    print("| run | wall (s), median | wall, range | CPU (s), median | speed-up over "
          "--jobs 1, median (range) | against --jobs 2, median (range) |")
    print("|---|---:|---:|---:|---:|---:|")
    for mode in modes:
        walls = [r[mode][0] for r in rounds]
        cpus = [r[mode][1] for r in rounds]
        speedups = [r[JOBS1][0] / r[mode][0] for r in rounds]
        against = [r[mode][0] / r[JOBS2][0] - 1 for r in rounds]
        cpu_note = " (command + workers)" if mode in (DASK, COLD) else ""
        ratio = "1.00×" if mode == JOBS1 else \
            f"{statistics.median(speedups):.2f}× ({_range(speedups, '{:.2f}')})"
        versus = "—" if mode == JOBS2 else \
            f"{statistics.median(against):+.0%} ({_range(against, '{:+.0%}')})"
        print(f"| {mode} | {statistics.median(walls):.1f} | {_range(walls, '{:.1f}')} | "
              f"{statistics.median(cpus):.1f}{cpu_note} | {ratio} | {versus} |")
    speedups = [r[JOBS1][0] / r[JOBS2][0] for r in rounds]
    against = [r[DASK][0] / r[JOBS2][0] - 1 for r in rounds]
    print(f"\nTargets: `--jobs 2` at least {SPEEDUP_TARGET}× faster than `--jobs 1`: median "
          f"{statistics.median(speedups):.2f}×, met in "
          f"{sum(s >= SPEEDUP_TARGET for s in speedups)} of {len(rounds)} rounds; Dask "
          f"(preloaded workers) within {DASK_TARGET:.0%} of `--jobs 2`: median "
          f"{statistics.median(against):+.0%}, met in "
          f"{sum(a <= DASK_TARGET for a in against)} of {len(rounds)} rounds. The Dask "
          f"scheduler's own CPU (in the benchmark's process): median "
          f"{statistics.median(r[DASK][2] for r in rounds):.1f} s a run.")
    print("\n| round | load | " + " | ".join(modes) + " | speed-up | Dask against --jobs 2 |")
    print("|---:|---:|" + "---:|" * (len(modes) + 2))
    for i, r in enumerate(rounds, 1):
        print(f"| {i} | {r['load']:.1f} | " + " | ".join(f"{r[m][0]:.1f}" for m in modes)
              + f" | {r[JOBS1][0] / r[JOBS2][0]:.2f}× | {r[DASK][0] / r[JOBS2][0] - 1:+.0%} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--files", type=int, default=40)
    parser.add_argument("--method", default="conformal", choices=("conformal", "fair"))
    parser.add_argument("--folder", help="work folder (default: a temporary one)")
    parser.add_argument("--rounds", type=int, default=5, help="paired rounds of the runs")
    parser.add_argument("--cold", action="store_true",
                        help="also a cluster whose workers start without the preload")
    parser.add_argument("--rerun", action="store_true",
                        help="rerun into the same folders (--overwrite) instead of first runs")
    parser.add_argument("--json", help="also write every run's numbers here")
    args = parser.parse_args()
    work = Path(args.folder or tempfile.mkdtemp(prefix="surfinpaint-batch-"))
    inputs = work / "scans"
    paths = make_meshes(inputs, args.files)
    command = [sys.executable, "-m", "surfinpaint", "batch"]
    options = ["--method", args.method, "--overwrite", "-q", "-o"]
    # not timed: numba's cache (compiled after a code change), the files in the OS cache
    timed([*command, str(inputs / "subject0[01]" / "*.ply"), *options, str(work / "warmup"),
           "--jobs", "1"])
    batch = [*command, str(inputs), *options]
    info = {"spare_before": spare_cores()}
    rounds = _run_rounds(args, work, batch,
                         lambda modes: _check_identical(work, inputs, paths, modes))
    info.update(spare_after=spare_cores(), load_after=os.getloadavg()[0],
                vertices=sum(len(read_mesh(p)[0]) for p in paths))
    if args.json:
        Path(args.json).write_text(json.dumps({"info": info, "rounds": rounds}, indent=1))
    print_table(args, rounds, info)


if __name__ == "__main__":
    main()
