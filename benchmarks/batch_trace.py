"""Where the time of a ``surfinpaint batch`` run goes, by CPU accounting (issue 17): a
measurement that holds on a shared machine, where wall-clock speed-ups do not.

Runs ``surfinpaint batch FOLDER -o OUT --overwrite -q --jobs N`` through the command line's
own ``main`` in this process, with :func:`surfinpaint.app.batch.fill_file` wrapped so that
every file's fill records its process, start and end (wall clock) and its CPU seconds, and
every process the CPU seconds it spent before its first file (imports, kernel loading comes
with the first file). Spawned workers import this script as their main module, so the
wrapper is theirs too. Prints

- the parent's CPU seconds before the files start (imports, listing the inputs, checking
  the options and the up-to-date outputs), while they run (progress, scheduling) and after
  (the summary);
- per worker: its start-up CPU (imports, before its first file), its files' CPU, and the
  CPU of its first file against the median of its files (the kernels loaded then);
- the *CPU makespan*: the parent's serial CPU plus the largest worker's start-up and files'
  CPU, which is the wall time of the run on two free cores if nothing else waits; the work
  over the makespan is the speed-up those CPU seconds allow, the idle tail the CPU seconds
  the first worker to finish waits for the last.

    python benchmarks/batch_trace.py FOLDER [--jobs 2] [--out DIR] [--json FILE]

FOLDER: input meshes (e.g. the ``scans`` folder ``benchmarks/batch.py --folder`` made).
"""

from __future__ import annotations

import argparse
import json
import logging
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import surfinpaint.app.batch as _batch

_TRACE = os.environ.get("SURFINPAINT_TRACE_DIR")
# the file may be executed twice in one namespace (a Dask preload is): wrap the original
_original_fill_file = getattr(_batch.fill_file, "__wrapped__", _batch.fill_file)


def _cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def _faults() -> int:
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt


def fill_file(job, options, *args, **kwargs):  # noqa: ANN001, ANN002, ANN003, ANN201
    """:func:`surfinpaint.app.batch.fill_file`, recording its times in the trace folder."""
    cpu, wall, faults = _cpu(), time.time(), _faults()
    row = _original_fill_file(job, options, *args, **kwargs)
    if _TRACE:
        record = {"pid": os.getpid(), "file": job.name, "start": wall, "end": time.time(),
                  "cpu_before": cpu, "cpu": _cpu() - cpu, "status": row.status,
                  "minor_faults": _faults() - faults}
        with open(Path(_TRACE) / f"{os.getpid()}.jsonl", "a", encoding="utf-8") as handle:
            handle.write(json.dumps(record) + "\n")
    return row


# spawned workers pickle the function by its module and name: they find this wrapper
fill_file.__module__, fill_file.__qualname__ = "surfinpaint.app.batch", "fill_file"
fill_file.__wrapped__ = _original_fill_file
_batch.fill_file = fill_file


def dask_setup(worker=None) -> None:  # noqa: ANN001
    """As a Dask worker preload (``--dask``): the wrapper above is installed on the worker
    by importing this file; the kernels are loaded as ``surfinpaint.app.dask_worker`` does,
    unless the trace is of cold workers."""
    if not os.environ.get("SURFINPAINT_TRACE_COLD"):
        from surfinpaint.app.dask_worker import dask_setup as setup

        setup(worker)


def _report(trace: Path, parent: dict, jobs: int) -> dict:
    records = [json.loads(line) for path in trace.glob("*.jsonl")
               for line in path.read_text().splitlines()]
    by_pid: dict[int, list[dict]] = {}
    for record in sorted(records, key=lambda r: r["start"]):
        by_pid.setdefault(record["pid"], []).append(record)
    workers = []
    for pid, files in by_pid.items():
        cpus = sorted(f["cpu"] for f in files)
        gaps = [b["start"] - a["end"] for a, b in zip(files, files[1:], strict=False)]
        workers.append({
            "pid": pid, "files": len(files),
            # a Dask worker started before the command: its start-up is not the run's
            "startup_cpu": 0.0 if parent.get("dask") else files[0]["cpu_before"],
            "gaps_wall": sum(gaps), "minor_faults": sum(f["minor_faults"] for f in files),
            "files_cpu": sum(cpus), "first_file_cpu": files[0]["cpu"],
            "median_file_cpu": cpus[len(cpus) // 2],
            "first_start": files[0]["start"] - parent["t0"],
            "last_end": files[-1]["end"] - parent["t0"],
            "busy_wall": sum(f["end"] - f["start"] for f in files)})
    serial = parent["cpu_before"] + parent["cpu_after"]
    spans = [w["startup_cpu"] + w["files_cpu"] for w in workers if w["pid"] != parent["pid"]]
    if not spans:  # --jobs 1: the parent fills
        spans = [parent["cpu_during"]]
        serial = parent["cpu_before"] + parent["cpu_after"]
    makespan = serial + max(spans)
    one_process = (parent["cpu_before"] + parent["cpu_after"]
                   + sum(w["files_cpu"] for w in workers))
    return {"jobs": jobs, "files": len(records), "parent": parent, "workers": workers,
            "cpu_makespan": makespan, "idle_tail_cpu": max(spans) - min(spans),
            "work_over_makespan": one_process / makespan,
            "children_cpu": parent["children_cpu"], "records": records}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("folder")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--out", help="output folder (default: a temporary one)")
    parser.add_argument("--json", help="also write the report here")
    parser.add_argument("--dask", action="store_true",
                        help="on a local Dask cluster of --jobs single-thread workers with "
                        "this file as their preload, started before the command (which is "
                        "then a fresh process, as a real run is)")
    parser.add_argument("--cold", action="store_true",
                        help="with --dask: the workers do not load the kernels at start")
    parser.add_argument("--dask-scheduler", help=argparse.SUPPRESS)  # the command's side
    parser.add_argument("batch_options", nargs="*", help="more options of the command")
    args = parser.parse_args(argv)
    global _TRACE
    if args.dask_scheduler:  # the command of a --dask trace: the trace folder is given
        _TRACE = os.environ["SURFINPAINT_TRACE_DIR"]
        report = _trace(args, ["--dask-scheduler", args.dask_scheduler], args.out,
                        Path(_TRACE), dask=True)
        Path(args.json).write_text(json.dumps(report, indent=1) + "\n")
        return
    trace = Path(tempfile.mkdtemp(prefix="surfinpaint-trace-"))
    os.environ["SURFINPAINT_TRACE_DIR"] = _TRACE = str(trace)
    if args.cold:
        os.environ["SURFINPAINT_TRACE_COLD"] = "1"
    out = args.out or tempfile.mkdtemp(prefix="surfinpaint-trace-out-")
    report = _trace_dask(args, out) if args.dask else \
        _trace(args, ["--jobs", str(args.jobs)], out, trace)
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=1) + "\n")
    _print(report)


def _trace_dask(args: argparse.Namespace, out: str) -> dict:
    """The command run as a fresh process (this script, ``--dask-scheduler``) against a
    local cluster started here and settled before it; adds the CPU of this process
    meanwhile (the scheduler)."""
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=args.jobs, threads_per_worker=1, processes=True,
                      dashboard_address=":0", preload=[str(Path(__file__).resolve())],
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        client.wait_for_workers(args.jobs)
        time.sleep(1.0)
        report_file = Path(os.environ["SURFINPAINT_TRACE_DIR"]) / "command.json"
        before = _cpu()
        subprocess.run([sys.executable, __file__, args.folder, "--jobs", str(args.jobs),
                        "--out", out, "--json", str(report_file), "--dask-scheduler",
                        cluster.scheduler_address, *args.batch_options], check=True)
        report = json.loads(report_file.read_text())
        report["scheduler_cpu"] = _cpu() - before
    return report


def _trace(args: argparse.Namespace, how: list[str], out: str, trace: Path,
           dask: bool = False) -> dict:
    """Run the command in this process, marking the parent's phases."""
    from surfinpaint.app.cli import main as cli_main

    marks = {}
    name = "_run_dask" if dask else "_run_local"
    original = getattr(_batch, name)

    def run(*a, **k):  # noqa: ANN002, ANN003, ANN202
        marks["cpu_start"], marks["t_start"] = _cpu(), time.time()
        try:
            return original(*a, **k)
        finally:
            marks["cpu_end"], marks["t_end"] = _cpu(), time.time()

    setattr(_batch, name, run)
    code = cli_main(["batch", args.folder, "-o", out, "--overwrite", "-q", *how,
                     *args.batch_options])
    cpu_end, t_end = _cpu(), time.time()
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    parent = {"pid": os.getpid(), "t0": T0, "exit": code, "dask": dask,
              "cpu_before": marks["cpu_start"],
              "cpu_imports": CPU0_IMPORTED,
              "cpu_during": marks["cpu_end"] - marks["cpu_start"],
              "cpu_after": cpu_end - marks["cpu_end"],
              "wall_before": marks["t_start"] - T0, "wall_during": marks["t_end"]
              - marks["t_start"], "wall_after": t_end - marks["t_end"], "wall": t_end - T0,
              "children_cpu": children.ru_utime + children.ru_stime}
    return _report(trace, parent, args.jobs)


def _print(report: dict) -> None:
    p = report["parent"]
    how = f"Dask, {report['jobs']} workers" if p.get("dask") else f"--jobs {report['jobs']}"
    print(f"{how}: {report['files']} files; wall {p['wall']:.2f} s "
          f"(before the files {p['wall_before']:.2f}, files {p['wall_during']:.2f}, after "
          f"{p['wall_after']:.2f}); load {os.getloadavg()[0]:.1f}")
    print(f"parent CPU: before the files {p['cpu_before']:.2f} s (of which imports "
          f"{p['cpu_imports']:.2f}), during {p['cpu_during']:.2f}, after {p['cpu_after']:.2f};"
          f" workers' CPU (RUSAGE_CHILDREN) {report['children_cpu']:.2f}")
    for w in report["workers"]:
        print(f"  pid {w['pid']}: {w['files']} files, start-up CPU {w['startup_cpu']:.2f} s, "
              f"files CPU {w['files_cpu']:.2f} (first {w['first_file_cpu']:.2f}, median "
              f"{w['median_file_cpu']:.2f}); first file at {w['first_start']:.2f} s, last "
              f"done at {w['last_end']:.2f} s (wall), idle between files "
              f"{w['gaps_wall']:.2f} s; {w['minor_faults']} minor page faults")
    if "scheduler_cpu" in report:
        print(f"the scheduler's CPU (the tracing process) {report['scheduler_cpu']:.2f} s")
    print(f"CPU makespan {report['cpu_makespan']:.2f} s, idle tail {report['idle_tail_cpu']:.2f}"
          f" CPU s, one process's work / makespan {report['work_over_makespan']:.2f}x")


def _process_start() -> float:
    """This process's start (wall clock, from /proc: 10 ms steps), or now elsewhere."""
    try:
        ticks = int(Path("/proc/self/stat").read_text().rsplit(")", 1)[1].split()[19])
        boot = next(int(line.split()[1]) for line in Path("/proc/stat").read_text()
                    .splitlines() if line.startswith("btime"))
        return boot + ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError, StopIteration):
        return time.time()


T0 = _process_start()
CPU0_IMPORTED = _cpu()

if __name__ == "__main__":
    main(sys.argv[1:])
