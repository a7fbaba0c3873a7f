"""Scale (issue 15): whole-process fills of large meshes against MeshLib, peak memory, and the
cost of one hole against the size of the mesh around it. Prints markdown tables.

1. The 651k-vertex case: ``icosphere(subdivisions=8)`` with vertices scaled by
   ``1 + 0.05 sin(6x) cos(5y)``, 10 geodesic-disk holes of radius 12 mean edge lengths,
   written as binary PLY. ``surfinpaint fill`` (default and ``--method fair``) and a MeshLib
   script (``loadMesh``, ``findHoleRepresentiveEdges``, ``fillHoleNicely`` with
   ``smoothCurvature=True`` and ``maxEdgeLen`` the mesh's mean edge length, ``saveMesh``) run
   as whole processes, interleaved in one paired run; wall time and the child's peak resident
   memory (``ru_maxrss`` from ``wait4``, i.e. VmHWM).
2. ``--big``: ``icosphere(subdivisions=9)`` (5.2M faces) bumped the same way with 100 small
   holes (radius 4 mean edge lengths, at most 30 edges), the same paired runs.
3. ``--scan``: a real range scan with many small holes, PyMeshFix's scanned Stanford bunny
   (its sample file) with the faces at its non-manifold edges removed first
   (``remove_nonmanifold_faces``, as ``fill --repair`` does), so every tool gets the same
   manifold mesh with 64 holes; the same paired runs.
4. The same hole in a small and a large mesh: a bumped ``icosphere(6)`` (41k vertices) with one
   hole, alone and next to a disjoint bumped ``icosphere(8)`` (1.4M faces in all): the hole
   and its neighbourhood are identical, so the per-hole seconds should be too.

    python benchmarks/scale.py [--big] [--scan] [--no-sphere] [--repeat 3]
                               [--workdir /tmp/surfinpaint-scale]

Meshes are generated once into ``--workdir`` and reused. MeshLib needs the ``peers`` extra.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from surfinpaint import fill_holes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.io import read_mesh, write_mesh

MESHLIB_SCRIPT = """
import sys
import meshlib.mrmeshpy as mm
mesh = mm.loadMesh(sys.argv[1])
settings = mm.FillHoleNicelySettings()
settings.smoothCurvature = True
settings.subdivideSettings.maxEdgeLen = mesh.averageEdgeLength()
settings.subdivideSettings.maxEdgeSplits = 10_000_000
for edge in mesh.topology.findHoleRepresentiveEdges():
    mm.fillHoleNicely(mesh, edge, settings)
mm.saveMesh(mesh, sys.argv[2])
"""


def bumpy_sphere(subdivisions: int) -> tuple[np.ndarray, np.ndarray]:
    """The issue's surface: an icosphere scaled by ``1 + 0.05 sin(6x) cos(5y)``."""
    import trimesh

    m = trimesh.creation.icosphere(subdivisions=subdivisions)
    v = np.asarray(m.vertices, dtype=float)
    v = v * (1 + 0.05 * np.sin(6 * v[:, 0]) * np.cos(5 * v[:, 1]))[:, None]
    return v, np.asarray(m.faces, dtype=np.int64)


def sphere_points(n: int) -> np.ndarray:
    """``n`` evenly spread unit vectors (a Fibonacci spiral): the hole centres."""
    k = np.arange(n) + 0.5
    polar = np.arccos(1 - 2 * k / n)
    azimuth = np.pi * (1 + 5**0.5) * k
    return np.column_stack([np.cos(azimuth) * np.sin(polar), np.sin(azimuth) * np.sin(polar),
                            np.cos(polar)])


@dataclass(frozen=True)
class Case:
    name: str
    path: Path
    n_vertices: int
    n_faces: int
    hole_edges: list[int]


def make_case(workdir: Path, name: str, subdivisions: int, n_holes: int,
              radius_edges: float) -> Case:
    """Generate (or reuse) a bumped sphere with ``n_holes`` geodesic-disk holes as binary PLY."""
    path = workdir / f"{name}.ply"
    meta = workdir / f"{name}.holes.npy"
    if not (path.exists() and meta.exists()):
        v, f = bumpy_sphere(subdivisions)
        h = mean_edge_length(v, f)
        cut = cut_holes(v, f, list(sphere_points(n_holes)), radius_edges * h)
        write_mesh(path, cut.vertices, cut.faces)
        np.save(meta, np.array([len(hole.loop) for hole in cut.holes]))
    v, f = read_mesh(path)[:2]
    return Case(name, path, len(v), len(f), np.load(meta).tolist())


def scan_case(workdir: Path) -> Case:
    """PyMeshFix's scanned bunny, its non-manifold faces removed, written (once) as binary
    PLY: a scan's many small holes (most of them a few edges)."""
    from pymeshfix import examples

    from surfinpaint import find_holes
    from surfinpaint.geometry.repair import remove_nonmanifold_faces

    path = workdir / "scanned-bunny.ply"
    if not path.exists():
        v, f = read_mesh(examples.bunny_scan)[:2]
        write_mesh(path, v, remove_nonmanifold_faces(v, f)[0])
    v, f = read_mesh(path)[:2]
    return Case("scanned-bunny (PyMeshFix's sample)", path, len(v), len(f),
                [h.n_edges for h in find_holes(v, f) if not h.is_border])


@dataclass(frozen=True)
class Run:
    wall: float
    peak_mb: float
    load: float
    cpu: float  # user + system seconds of the child and its workers


# Linux counts a process's peak memory from before its exec, so a child forked from this
# (large) process would report at least this process's size: a small launcher forks it
# instead, times it and reports its ru_maxrss (= VmHWM) on the last line of stderr.
LAUNCHER = """
import os, resource, subprocess, sys, time
start = time.perf_counter()
code = subprocess.call(sys.argv[1:], stdout=subprocess.DEVNULL)
wall = time.perf_counter() - start
usage = resource.getrusage(resource.RUSAGE_CHILDREN)
cpu = usage.ru_utime + usage.ru_stime
print(f"\\nscale-run {wall} {usage.ru_maxrss} {cpu}", file=sys.stderr)
sys.exit(code)
"""


def child_environment(workdir: Path) -> dict[str, str]:
    """The children's environment: this one, with Python's compiled bytecode cached under
    ``workdir`` (``PYTHONPYCACHEPREFIX``) even where ``PYTHONDONTWRITEBYTECODE`` is set, so
    every tool's imports read ``.pyc`` files as an installed package's do (these sessions'
    environment sets that variable: surfinpaint's own modules were compiled from source in
    every run, about 0.07 s; docs/scale.md, session 22)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPYCACHEPREFIX"] = str(workdir / "pycache")
    return env


def run_child(cmd: list[str], env: dict[str, str] | None = None) -> Run:
    """Run ``cmd`` to completion; its wall time, peak resident memory (the child's
    ``ru_maxrss``, i.e. VmHWM; a worker process's own peak when larger), CPU seconds (user +
    system, the child's workers included) and the 1-minute load average when it ended."""
    proc = subprocess.run([sys.executable, "-c", LAUNCHER, *cmd], capture_output=True,
                          text=True, env=env)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({proc.returncode}):\n"
                           f"{proc.stderr[-2000:]}")
    _, wall, peak_kb, cpu = proc.stderr.strip().splitlines()[-1].split()
    return Run(float(wall), float(peak_kb) / 1024.0, os.getloadavg()[0], float(cpu))


def tools(case: Case, workdir: Path, with_meshlib: bool) -> dict[str, list[str]]:
    out = str(workdir / f"{case.name}.out.ply")
    me = [sys.executable, "-m", "surfinpaint", "fill", str(case.path), "-o", out, "-q"]
    commands = {"surfinpaint (default)": me, "surfinpaint --method fair": me + ["--method", "fair"]}
    if with_meshlib:
        commands["MeshLib fillHoleNicely"] = [sys.executable, "-c", MESHLIB_SCRIPT,
                                              str(case.path), str(workdir / "meshlib.out.ply")]
    return commands


def paired(case: Case, workdir: Path, repeat: int, with_meshlib: bool) -> dict[str, list[Run]]:
    """Every tool once per round, rounds interleaved so load changes hit all alike, after
    one untimed round (bytecode written, files and kernels in the caches for every tool)."""
    commands = tools(case, workdir, with_meshlib)
    env = child_environment(workdir)
    for cmd in commands.values():
        run_child(cmd, env)
    runs: dict[str, list[Run]] = {name: [] for name in commands}
    for _ in range(repeat):
        for name, cmd in commands.items():
            runs[name].append(run_child(cmd, env))
    return runs


def paired_table(case: Case, runs: dict[str, list[Run]]) -> str:
    ref = runs.get("MeshLib fillHoleNicely")
    ref_wall = statistics.median(r.wall for r in ref) if ref else None
    lines = [f"**{case.name}**: {case.n_vertices:,} vertices, {case.n_faces:,} faces, "
             f"{len(case.hole_edges)} holes of {min(case.hole_edges)}–{max(case.hole_edges)} "
             "edges, binary PLY", "",
             "| tool | wall s (median) | runs | × MeshLib | CPU s (median) | peak MB | "
             "load (1 min) |", "|---|---|---|---|---|---|---|"]
    for name, rs in runs.items():
        wall = statistics.median(r.wall for r in rs)
        ratio = f"{wall / ref_wall:.2f}" if ref_wall else "–"
        lines.append(f"| {name} | {wall:.2f} | {', '.join(f'{r.wall:.2f}' for r in rs)} | "
                     f"{ratio} | {statistics.median(r.cpu for r in rs):.2f} | "
                     f"{max(r.peak_mb for r in rs):.0f} | "
                     f"{', '.join(f'{r.load:.1f}' for r in rs)} |")
    return "\n".join(lines)


def same_hole(repeat: int) -> str:
    """Per-hole seconds of one hole in a small mesh and in the same mesh next to a large
    disjoint component (identical hole and neighbourhood)."""
    v, f = bumpy_sphere(6)
    cut = cut_holes(v, f, [sphere_points(1)[0]], 12 * mean_edge_length(v, f))
    big_v, big_f = bumpy_sphere(8)
    big_v = big_v + np.array([10.0, 0, 0])
    meshes = {"small": (cut.vertices, cut.faces),
              "large": (np.vstack([cut.vertices, big_v]),
                        np.vstack([cut.faces, big_f + len(cut.vertices)]))}
    lines = ["| mesh | vertices | faces | hole edges | method | per-hole s (min of "
             f"{repeat}) | whole call s (min) |", "|---|---|---|---|---|---|---|"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fill_holes(cut.vertices, cut.faces, holes=[cut.loop])  # compile / warm up
        for method in ("conformal", "fair"):
            for name, (mv, mf) in meshes.items():
                per_hole, whole = [], []
                for _ in range(repeat):
                    start = time.perf_counter()
                    result = fill_holes(mv, mf, holes=[cut.loop], method=method)
                    whole.append(time.perf_counter() - start)
                    per_hole.append(result.reports[0].seconds)
                lines.append(f"| {name} | {len(mv):,} | {len(mf):,} | {len(cut.loop)} | "
                             f"{method} | {min(per_hole):.3f} | {min(whole):.2f} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--big", action="store_true", help="also the 5M-face, 100-hole case")
    parser.add_argument("--scan", action="store_true",
                        help="also PyMeshFix's scanned bunny (64 small holes)")
    parser.add_argument("--repeat", type=int, default=3, help="rounds of the paired runs")
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/surfinpaint-scale"))
    parser.add_argument("--no-meshlib", action="store_true", help="skip MeshLib")
    parser.add_argument("--no-sphere", action="store_true", help="skip the 651k case")
    parser.add_argument("--no-same-hole", action="store_true", help="skip table 3")
    args = parser.parse_args(argv)
    args.workdir.mkdir(parents=True, exist_ok=True)
    with_meshlib = not args.no_meshlib
    if with_meshlib:
        try:
            import meshlib.mrmeshpy  # noqa: F401
        except ImportError:
            print("meshlib is not installed (pip install surfinpaint[peers]): skipping it")
            with_meshlib = False
    print(f"machine: {os.cpu_count()} cores, load average at start "
          f"{', '.join(f'{x:.1f}' for x in os.getloadavg())}\n")
    cases = [] if args.no_sphere else [make_case(args.workdir, "bumpy-sphere-651k", 8, 10,
                                                 12.0)]
    if args.big:
        cases.append(make_case(args.workdir, "bumpy-sphere-5M-faces", 9, 100, 4.0))
    if args.scan:
        cases.append(scan_case(args.workdir))
    for case in cases:
        print(paired_table(case, paired(case, args.workdir, args.repeat, with_meshlib)), "\n")
    if not args.no_same_hole:
        print(same_hole(args.repeat))
    return 0


if __name__ == "__main__":
    sys.exit(main())
