"""The timeline of one whole ``surfinpaint fill`` process (issue 15; docs/scale.md, session 43):
each stage's start and end (ms from the launcher's start of the process), its thread, its
thread CPU and its page faults, then the process's and its workers' CPU, system time and
page faults.

The command runs as the program runs it (``app.program.command_line``: the settings made
before numpy is imported, the imports without collections, ``gc.freeze``), in a child
process of this script, with ``PYTHONPYCACHEPREFIX`` set as ``benchmarks/scale.py`` sets
it. The stages are the functions the fill calls, wrapped where the caller looks them up; a
stage on another thread (the kernels' loading, the passes beside the checks) is named with
that thread. The forked workers' holes are not broken down (``benchmarks/scale_parts.py``:
the holes by part).

    PYTHONPATH=src python benchmarks/scale_timeline.py [--workdir /tmp/surfinpaint-scale]
        [--runs 3] [--method conformal]

A near-quiet timeline on a machine shared with other work: run it under ``chrt -f 10`` (a
real-time policy, inherited by the workers: the other processes wait while it runs).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

# the child's driver: wraps the stages, runs the program's command, prints one row a stage
DRIVER = r"""
import gc, os, resource, sys, threading, time
T0 = float(sys.argv.pop(1))
rows = []
def faults():
    return resource.getrusage(resource.RUSAGE_THREAD).ru_minflt
def timed(name, f):
    def wrapper(*args, **kwargs):
        start, cpu, flt = time.perf_counter(), time.thread_time(), faults()
        try:
            return f(*args, **kwargs)
        finally:
            rows.append((name, threading.current_thread().name, start - T0,
                         time.perf_counter() - T0, time.thread_time() - cpu, faults() - flt))
    return wrapper
from surfinpaint.app import program
start, cpu, flt = time.perf_counter(), time.thread_time(), faults()
if hasattr(program, "command_line"):  # the program's start (session 45)
    program.command_line()
else:
    program.process_settings()
    gc.disable()
    from surfinpaint.app import cli
    gc.freeze()
    gc.enable()
from surfinpaint.app import cli
rows.append(("import the command line", "MainThread", start - T0, time.perf_counter() - T0,
             time.thread_time() - cpu, faults() - flt))
from surfinpaint.fill import neighbourhood, pipeline, warmup
for owner, names in ((cli, ("read_mesh_data", "fill_mesh_data", "write_with_materials")),
                     (warmup, ("warm_kernels",)),
                     (pipeline, ("check_arrays", "triangle_rows", "check_topology",
                                 "find_holes", "triangle_incidence", "fill_in_parallel",
                                 "fill_hole", "far_crossing_triangles", "crossing_fill_pairs",
                                 "topology_changes"))):
    for name in names:
        setattr(owner, name, timed(name, getattr(owner, name)))
build = pipeline.EdgeTable.build
pipeline.EdgeTable.build = classmethod(
    lambda cls, *a, **k: timed("EdgeTable.build", build)(*a, **k))
result = neighbourhood.FilledMesh.result
neighbourhood.FilledMesh.result = lambda self, *a: timed("FilledMesh.result", result)(self, *a)
start, cpu, flt = time.perf_counter(), time.thread_time(), faults()
code = cli.main(sys.argv[1:])
rows.append(("cli.main", "MainThread", start - T0, time.perf_counter() - T0,
             time.thread_time() - cpu, faults() - flt))
gc.freeze()
me, workers = (resource.getrusage(who) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
for row in sorted(rows, key=lambda row: row[2]):
    print("stage", repr(row), file=sys.stderr)
print("usage", repr((me.ru_utime, me.ru_stime, me.ru_minflt, workers.ru_utime, workers.ru_stime,
                     workers.ru_minflt)), file=sys.stderr)
sys.exit(code)
"""


def run_once(case: Path, out: Path, method: str, workdir: Path) -> tuple[list, tuple, float]:
    """One process: its stage rows, its usage (self user, system, faults; workers' the
    same) and its wall seconds."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPYCACHEPREFIX"] = str(workdir / "pycache")
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, "-c", DRIVER, repr(start), "fill", str(case), "-o",
                           str(out), "-q", "--method", method], env=env, capture_output=True,
                          text=True)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr[-2000:])
    rows, usage = [], ()
    for line in proc.stderr.splitlines():
        kind, _, text = line.partition(" ")
        if kind == "stage":
            rows.append(eval(text))  # noqa: S307 (our own child's repr of a tuple)
        elif kind == "usage":
            usage = eval(text)  # noqa: S307
    return rows, usage, wall


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/surfinpaint-scale"))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--method", default="conformal", choices=("conformal", "fair"))
    args = parser.parse_args(argv)
    sys.path.insert(0, str(Path(__file__).parent))
    from scale import make_case

    args.workdir.mkdir(parents=True, exist_ok=True)
    case = make_case(args.workdir, "bumpy-sphere-651k", 8, 10, 12.0)
    out = args.workdir / f"{case.name}.timeline.ply"
    run_once(case.path, out, args.method, args.workdir)  # untimed: bytecode and caches
    for k in range(args.runs):
        rows, usage, wall = run_once(case.path, out, args.method, args.workdir)
        print(f"run {k + 1}: {wall:.3f} s wall, load {os.getloadavg()[0]:.1f}")
        print("| stage | thread | start ms | end ms | wall ms | CPU ms | page faults |")
        print("|---|---|---|---|---|---|---|")
        for name, thread, start, end, cpu, faults in rows:
            print(f"| {name} | {thread} | {1e3 * start:.0f} | {1e3 * end:.0f} | "
                  f"{1e3 * (end - start):.1f} | {1e3 * cpu:.1f} | {faults} |")
        user, system, faults, w_user, w_system, w_faults = usage
        print(f"\nthis process: CPU {user + system:.3f} s (system {system:.3f}), {faults} page "
              f"faults; its workers: CPU {w_user + w_system:.3f} s (system {w_system:.3f}), "
              f"{w_faults} page faults\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
