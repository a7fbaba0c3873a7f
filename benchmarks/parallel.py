"""Holes filled in parallel (issue 15): ``fill_holes(..., jobs=1)`` against ``jobs=2`` on a
bumped ``icosphere(subdivisions)`` (``1 + 0.05 sin(6x) cos(5y)``, as benchmarks/scale.py) with
``--holes`` geodesic-disk holes of ``--radius`` mean edge lengths. Whole ``fill_holes`` calls,
interleaved (jobs=1, jobs=2, jobs=1, ...) in one run, best of ``--repeat``; after one untimed
warm-up call per method (the compiled kernels). The hole phase is the whole call less the
same call with every hole skipped (``max_hole_edges=1``: validation and hole finding). The
results of the two are checked bit-identical. Prints a markdown table and the load, then,
per method and jobs, the medians over the repeats of the parent's CPU in the call and, for
jobs=2, the workers' CPU (``os.times()``: the workers are reaped when the pool shuts down),
their busy time (wall inside each task, recorded in the worker) and their idle time: workers ×
the pool's life (created to shut down) less the busy time, and that idle time before each
worker's first task, between its tasks and after its last. CPU and idle time are less noisy
than the wall on a shared machine.

    python benchmarks/parallel.py [--subdivisions 6] [--holes 10] [--radius 11] [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from concurrent.futures import Future
from pathlib import Path

import numpy as np

from surfinpaint import fill_holes
from surfinpaint.fill import parallel
from surfinpaint.fill.conformal import ConformalOptions
from surfinpaint.fill.hole_steps import FAIR_NEIGHBOURHOOD_RINGS
from surfinpaint.fill.neighbourhood import FilledMesh
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length

sys.path.insert(0, str(Path(__file__).parent))
from scale import bumpy_sphere, sphere_points  # noqa: E402  (the same surface and centres)


def n_independent(vertices, faces, loops, method: str) -> int:
    """How many holes the parallel run can send to workers at once."""
    mesh = FilledMesh(vertices, faces)
    rings = [ConformalOptions().neighbourhood_rings(len(loop)) if method == "conformal"
             else FAIR_NEIGHBOURHOOD_RINGS for loop in loops]
    reach = [mesh.cut(loop, r).ids for loop, r in zip(loops, rings, strict=True)]
    return len(parallel.independent(reach, loops))


def _timed_task(fn, *args, **kwargs):
    """A worker's task with its wall seconds (run in the worker: forked, it sees this module)."""
    started = time.monotonic()
    result = fn(*args, **kwargs)
    return result, (os.getpid(), started, time.monotonic())


class _PoolLog:
    """Wraps ``parallel.pool``: each pool's life and its tasks' wall seconds."""

    def __init__(self) -> None:
        self.pool = parallel.pool
        self.lives: list[tuple[int, float, float]] = []  # (workers, created, shut down)
        self.tasks: list[tuple[int, float, float]] = []  # (worker's pid, started, ended)

    def __call__(self, workers, *args, **kwargs):
        executor = self.pool(workers, *args, **kwargs)
        created = time.monotonic()
        submit, shutdown = executor.submit, executor.shutdown

        def timed_submit(fn, *a, **kw):
            outer = Future()

            def done(inner):
                if inner.cancelled():
                    outer.cancel()
                elif inner.exception() is not None:
                    outer.set_exception(inner.exception())
                else:
                    result, task = inner.result()
                    self.tasks.append(task)
                    outer.set_result(result)

            submit(_timed_task, fn, *a, **kw).add_done_callback(done)
            return outer

        def timed_shutdown(*a, **kw):
            shutdown(*a, **kw)
            self.lives.append((workers, created, time.monotonic()))

        executor.submit, executor.shutdown = timed_submit, timed_shutdown
        return executor

    def take(self) -> dict[str, float]:
        """The workers' busy and idle seconds since the last call, the idle split into
        before a worker's first task (from the pool's creation: the forks included),
        between its tasks, and after its last (to the pool's shut-down)."""
        busy = sum(end - start for _, start, end in self.tasks)
        parts = {"busy": busy, "idle": sum(w * (end - start) for w, start, end in self.lives)
                 - busy, "first": 0.0, "between": 0.0, "last": 0.0}
        for _, created, shut in self.lives:
            for pid in {t[0] for t in self.tasks}:
                mine = sorted((s, e) for p, s, e in self.tasks
                              if p == pid and created <= s <= shut)
                if mine:
                    parts["first"] += mine[0][0] - created
                    parts["last"] += shut - mine[-1][1]
                    parts["between"] += sum(b[0] - a[1] for a, b in
                                            zip(mine[:-1], mine[1:], strict=True))
        self.lives, self.tasks = [], []
        return parts


LOG = _PoolLog()
parallel.pool = LOG


def timed(vertices, faces, **kw) -> tuple[float, object, dict]:
    """Wall seconds, the result, and the CPU of the parent and of the workers."""
    before, started = os.times(), time.perf_counter()
    result = fill_holes(vertices, faces, **kw)
    seconds, after = time.perf_counter() - started, os.times()
    cpu = {"parent": after.user + after.system - before.user - before.system,
           "workers": (after.children_user + after.children_system
                       - before.children_user - before.children_system), **LOG.take()}
    return seconds, result, cpu


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--subdivisions", type=int, default=6)
    parser.add_argument("--holes", type=int, default=10)
    parser.add_argument("--radius", type=float, default=11.0)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--methods", default="fair,conformal")
    args = parser.parse_args()
    v, f = bumpy_sphere(args.subdivisions)
    cut = cut_holes(v, f, list(sphere_points(args.holes)), args.radius * mean_edge_length(v, f))
    V, F, loops = cut.vertices, cut.faces, [h.loop for h in cut.holes]
    edges = sorted(len(loop) for loop in loops)
    print(f"bumped icosphere({args.subdivisions}): {len(V)} vertices, {len(F)} faces, "
          f"{len(loops)} holes of {edges[0]}-{edges[-1]} edges; load before "
          f"{os.getloadavg()[0]:.1f}\n")
    print("| method | independent holes | jobs=1 call (s) | jobs=2 call (s) | prep (s) "
          "| hole phase jobs=1 (s) | jobs=2 (s) | speed-up (hole phase) | whole call |")
    print("|---|---|---|---|---|---|---|---|---|")
    all_runs, cpu_rows = [], []
    for method in args.methods.split(","):
        timed(V, F, method=method, jobs=1)  # warm-up: compiled kernels
        best = {1: np.inf, 2: np.inf, "prep": np.inf}
        results, runs = {}, {1: [], 2: []}
        cpus = {1: [], 2: [], "prep": []}
        for _ in range(args.repeat):
            seconds, _, cpu = timed(V, F, method=method, max_hole_edges=1)
            best["prep"] = min(best["prep"], seconds)
            cpus["prep"].append(cpu)
            for jobs in (1, 2):
                seconds, results[jobs], cpu = timed(V, F, method=method, jobs=jobs)
                runs[jobs].append(f"{seconds:.2f}")
                cpus[jobs].append(cpu)
                best[jobs] = min(best[jobs], seconds)
        cpu_rows.append((method, cpus))
        same = (np.array_equal(results[1].vertices, results[2].vertices)
                and np.array_equal(results[1].faces, results[2].faces))
        assert same, f"{method}: jobs=2 differs from jobs=1"
        holes1, holes2 = best[1] - best["prep"], best[2] - best["prep"]
        print(f"| {method} | {n_independent(V, F, loops, method)}/{len(loops)} "
              f"| {best[1]:.2f} | {best[2]:.2f} | {best['prep']:.2f} | {holes1:.2f} "
              f"| {holes2:.2f} | {holes1 / holes2:.2f}x | {best[1] / best[2]:.2f}x |")
        all_runs.append(f"{method}: jobs=1 {', '.join(runs[1])}; jobs=2 {', '.join(runs[2])}")
    print("\nevery call (s): " + " | ".join(all_runs))
    print(f"load after {os.getloadavg()[0]:.1f}; results bit-identical (np.array_equal)")
    print("\nCPU and idle seconds, medians over the repeats (every call in brackets):\n")
    print("| method | call | parent CPU | workers' CPU | workers busy | workers idle "
          "| idle before the first task | between tasks | after the last |")
    print("|---|---|---|---|---|---|---|---|---|")
    for method, cpus in cpu_rows:
        for key in ("prep", 1, 2):
            cells = []
            for part in ("parent", "workers", "busy", "idle", "first", "between", "last"):
                values = [c[part] for c in cpus[key]]
                cells.append(f"{statistics.median(values):.2f} "
                             f"[{', '.join(f'{x:.2f}' for x in values)}]"
                             if key == 2 or part == "parent" else "")
            name = "prep" if key == "prep" else f"jobs={key}"
            print(f"| {method} | {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
