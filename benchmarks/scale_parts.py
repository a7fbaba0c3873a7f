"""Where the CPU of the 651k case goes, part by part (issue 15; docs/scale.md, third pass).

1. The conformal holes: each of the ten holes' neighbourhoods is cut from the mesh (as
   ``fill_holes`` cuts it) and filled by ``conformal_fill`` in this process, after one
   untimed fill (kernels loaded); the CPU seconds of the whole loop and of its parts
   (the hidden-ring and sibling tests, the faired fills, the λ-H passes, the point-to-mesh
   distances of the tests' scores with their sampling; each part includes what runs
   inside it).
2. The whole-mesh work of ``fill_holes`` before the holes: validation with the edge table
   (``_prepared``) and ``find_holes``, three calls.
3. ``--phases``: instead, one whole ``surfinpaint fill`` run in this process (default and
   ``--method fair``), wall and CPU seconds of each phase: the imports, reading, the array
   checks, the edge table, the topology checks, ``find_holes``, the holes, assembling the
   result, the attributes, writing. CPU is the process's (``time.process_time``, every
   thread's: a phase's CPU counts what ran beside it). A large mesh's ``find_holes`` and
   ``triangle_incidence`` (``vertex_faces``) run on a thread beside the topology checks
   (session 24): their wall overlaps the checks'; the kernels load on another from before
   the read. This process imported numpy before the program's settings (huge pages
   ``madvise``d, the BLAS threads): ``benchmarks/scale_timeline.py`` times the command as
   the program runs it, per thread, with page faults.

The mesh is the one ``benchmarks/scale.py`` makes (generated here when missing). Run the
same command on two checkouts, alternated, to compare them:

    PYTHONPATH=src python benchmarks/scale_parts.py [--workdir /tmp/surfinpaint-scale] [--phases]
"""

from __future__ import annotations

import time

STARTED = time.perf_counter(), time.process_time()  # before the imports, for --phases

import argparse  # noqa: E402
import functools  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent))
from scale import make_case  # noqa: E402

import surfinpaint.fill.conformal.candidates as candidates  # noqa: E402
import surfinpaint.fill.conformal.method as method  # noqa: E402
from surfinpaint.fill import neighbourhood, pipeline, selfcheck  # noqa: E402
from surfinpaint.fill.conformal.options import ConformalOptions  # noqa: E402
from surfinpaint.fill.holes import find_holes  # noqa: E402
from surfinpaint.fill.warmup import Beside, warm_kernels  # noqa: E402
from surfinpaint.io.formats import read_mesh  # noqa: E402


def _timed(owner, name: str, label: str, spent: dict, wall: dict | None = None) -> None:
    """Wrap ``owner.name`` to add its CPU seconds to ``spent[label]`` (and its wall seconds
    to ``wall[label]``)."""
    inner = getattr(owner, name)

    @functools.wraps(inner)
    def wrapper(*args, **kwargs):
        started, clock = time.process_time(), time.perf_counter()
        try:
            return inner(*args, **kwargs)
        finally:
            spent[label] = spent.get(label, 0.0) + time.process_time() - started
            if wall is not None:
                wall[label] = wall.get(label, 0.0) + time.perf_counter() - clock

    setattr(owner, name, wrapper)


def process_phases(path: Path, out: Path, method: str) -> list[tuple[str, float, float]]:
    """(phase, wall s, CPU s) of one ``surfinpaint fill path -o out --method method`` run in
    this process (the first call only: the second method's imports are already done)."""
    from surfinpaint.app import cli
    from surfinpaint.fill.objects import fill_mesh_data  # noqa: F401 (imported by the cli)

    spent: dict[str, float] = {}
    wall: dict[str, float] = {}
    for owner, name, label in (
            (cli, "read_mesh_data", "read"), (cli, "write_with_materials", "write"),
            (pipeline, "check_arrays", "array checks"),
            (pipeline.EdgeTable, "build", "edge table"),
            (pipeline, "check_topology", "topology checks"),
            (pipeline, "find_holes", "find_holes"),
            (pipeline, "triangle_incidence", "vertex_faces"),
            (pipeline, "fill_in_parallel", "holes"), (pipeline, "fill_hole", "holes"),
            (neighbourhood.FilledMesh, "result", "assembling the result"),
            (pipeline, "_with_attributes", "attributes"),
            (pipeline, "topology_changes", "topology changes")):
        _timed(owner, name, label, spent, wall)
    clock, started = time.perf_counter(), time.process_time()
    cli.main(["fill", str(path), "-o", str(out), "-q", "--method", method])
    rows = [(k, wall[k], spent[k]) for k in spent]
    return rows + [("whole run (after the imports)", time.perf_counter() - clock,
                    time.process_time() - started)]


def hole_parts(vertices: np.ndarray, faces: np.ndarray) -> dict[str, float]:
    """CPU seconds of the ten conformal holes, in all and by part."""
    options = ConformalOptions()
    mesh = neighbourhood.FilledMesh(vertices, faces)
    cuts = [mesh.cut(h.loop, options.neighbourhood_rings(h.n_edges))
            for h in find_holes(vertices, faces)]
    spent: dict[str, float] = {}
    for owner, name, label in (
            (method, "hidden_ring_scores", "hidden-ring test"),
            (method, "sibling_scores", "sibling test"),
            (candidates, "faired_fills", "faired fills"),
            (candidates, "inpaint_patch_on_mesh", "λ-H passes"),
            # the self-check's scores: every point-to-mesh search and its sampling
            (selfcheck, "point_mesh_distances", "distances")):
        _timed(owner, name, label, spent)
    warm_kernels()
    method.conformal_fill(cuts[-1].vertices, cuts[-1].faces, cuts[-1].local_loop)
    spent.clear()
    started = time.process_time()
    for cut in cuts:
        method.conformal_fill(cut.vertices, cut.faces, cut.local_loop)
    return {"all holes": time.process_time() - started, **spent}


def whole_mesh(vertices: np.ndarray, faces: np.ndarray, calls: int = 3) -> list[tuple]:
    """CPU seconds of ``fill_holes``' validation and of ``find_holes``, ``calls`` times."""
    out = []
    for _ in range(calls):
        started = time.process_time()
        prepared = pipeline._prepared(vertices, faces, False, True, Beside(False))
        middle = time.process_time()
        find_holes(prepared.vertices, prepared.triangles, prepared.table, validate=False)
        out.append((middle - started, time.process_time() - middle))
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/surfinpaint-scale"))
    parser.add_argument("--phases", choices=("conformal", "fair"),
                        help="one whole fill by this method, by phase (run once a process)")
    args = parser.parse_args(argv)
    args.workdir.mkdir(parents=True, exist_ok=True)
    case = make_case(args.workdir, "bumpy-sphere-651k", 8, 10, 12.0)
    if args.phases:
        imports = (time.perf_counter() - STARTED[0], time.process_time() - STARTED[1])
        rows = process_phases(case.path, args.workdir / f"{case.name}.phases.ply", args.phases)
        print(f"{args.phases} (load {open('/proc/loadavg').read().split()[0]}): imports of "
              f"the benchmark and the package {imports[0]:.2f} s wall, {imports[1]:.2f} s CPU")
        for name, wall, cpu in rows:
            print(f"  {name:32s} {wall:6.2f} s wall {cpu:6.2f} s CPU")
        return 0
    vertices, faces = read_mesh(case.path)[:2]
    load = lambda: open("/proc/loadavg").read().split()[0]  # noqa: E731
    parts = hole_parts(vertices, faces)
    print("holes (CPU s): " + ", ".join(f"{k} {v:.2f}" for k, v in parts.items())
          + f" (load {load()})")
    print("validation + find_holes (CPU s): " + ", ".join(
        f"{a:.2f} + {b:.2f}" for a, b in whole_mesh(vertices, faces)) + f" (load {load()})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
