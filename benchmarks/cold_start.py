"""Cold start (issue 15): a whole ``surfinpaint`` command in a fresh numba cache (cold) and
again in the same cache (warm), in pairs, with the CPU seconds, the wall and the load.

Between the cold and the warm run the script waits until the background compilation the
cold run started has released its lock (``surfinpaint.compiled.lock_path``), so "warm" is
the second run after an install. CPU is user + system of the command and the workers it
waited for (``RUSAGE_CHILDREN``), not of the detached background compilation; outputs are
compared byte for byte (cold against warm). Prints a markdown table.

    python benchmarks/cold_start.py [--pairs 3] [--workdir /tmp/surfinpaint-cold] [--big]

Runs ``demo``, ``fill`` of a small holed sphere (626 vertices, conformal), ``fill`` of the
bundled mesh (the demo's snowman, without the demo's drawing) and, with
``--big``, of ``benchmarks/scale.py``'s 163k case (default, ``--jobs 1``, ``--method fair``).
"""

from __future__ import annotations

import argparse
import fcntl
import filecmp
import os
import resource
import subprocess
import sys
import tempfile
import time
from importlib.resources import files
from pathlib import Path

from scale import make_case

from surfinpaint.data import sphere
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.io import write_mesh


def commands(workdir: Path, big: bool) -> dict[str, list[str]]:
    """Each run's arguments after ``python -m surfinpaint``; ``OUT`` is its output."""
    small = workdir / "small.ply"
    if not small.exists():
        v, f = sphere(3)
        cut = cut_geodesic_disk(v, f, 0, 0.5)
        write_mesh(small, cut.vertices, cut.faces)
    bundled = str(files("surfinpaint") / "meshes" / "snowman_holes.ply")
    runs = {"demo": ["demo", "-o", "OUT"],
            "fill small": ["fill", str(small), "-o", "OUT.ply", "-q"],
            "fill bundled": ["fill", bundled, "-o", "OUT.ply", "-q"]}
    if big:
        case = str(make_case(workdir, "bumpy-sphere-163k", 7, 10, 12).path)
        runs["163k"] = ["fill", case, "-o", "OUT.ply", "-q"]
        runs["163k --jobs 1"] = ["fill", case, "-o", "OUT.ply", "-q", "--jobs", "1"]
        runs["163k fair"] = ["fill", case, "-o", "OUT.ply", "-q", "--method", "fair"]
    return runs


def timed(args: list[str], env: dict) -> tuple[float, float, float]:
    """(CPU s, wall s, 1-minute load before) of ``python -m surfinpaint ARGS``."""
    load = os.getloadavg()[0]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "surfinpaint", *args], env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, wall, load


def wait_for_background(env: dict) -> None:
    """Until the background compilation started under ``env`` released its lock."""
    path = subprocess.run([sys.executable, "-c", "from surfinpaint.compiled import lock_path; "
                           "print(lock_path())"], env=env, capture_output=True, text=True,
                          check=True).stdout.strip()
    if os.path.exists(path):
        with open(path) as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)


def pair(args: list[str], workdir: Path) -> tuple[list[tuple[float, float, float]], bool]:
    """A cold and a warm run in one fresh cache; whether their outputs are identical."""
    cache = tempfile.mkdtemp(prefix="cache-", dir=workdir)
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    runs, outs = [], []
    for kind in ("cold", "warm"):
        out = str(workdir / f"out-{kind}")
        runs.append(timed([a.replace("OUT", out) for a in args], env))
        wait_for_background(env)
        outs.append(Path(out + ".ply") if args[0] == "fill" else Path(out) / "filled.ply")
    return runs, filecmp.cmp(*outs, shallow=False)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=3)
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/surfinpaint-cold"))
    parser.add_argument("--big", action="store_true")
    args = parser.parse_args(argv)
    args.workdir.mkdir(parents=True, exist_ok=True)
    print("| run | cold CPU s (wall s) | warm CPU s (wall s) | cold − warm CPU s (wall s) "
          "| load | same output |")
    print("|---|---|---|---|---|---|")
    for name, command in commands(args.workdir, args.big).items():
        for k in range(args.pairs):
            ((c, cw, cl), (w, ww, wl)), same = pair(command, args.workdir)
            print(f"| `{name}` {k + 1} | {c:.2f} ({cw:.1f}) | {w:.2f} ({ww:.1f}) | "
                  f"{c - w:.2f} ({cw - ww:.1f}) | {cl:.1f}–{wl:.1f} | {same} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
