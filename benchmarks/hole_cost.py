"""CPU seconds of the default method's per-hole fill, with digests to check two checkouts
give the same fills (issue 15; docs/scale.md, "The self-check's cost, session 10").

Two sets of holes, each filled in this process after one untimed fill (kernels loaded):

1. the ten holes of the 651k case (``benchmarks/scale.py``'s mesh, generated when missing),
   each cut with its neighbourhood as ``fill_holes`` cuts it and filled by
   ``conformal_fill``;
2. the six torus holes of ``benchmarks/speed.py`` (3-16 edge lengths), each filled by
   ``fill_holes`` (the default method).

Each run prints the CPU seconds of each set and the 1-minute load; the last two lines are a
digest per hole of the fill's arrays and its verdict (the scores of both tests and the
sentence; for ``fill_holes`` the whole report without its seconds). Run it on two checkouts,
alternated, and compare the digests:

    PYTHONPATH=src python benchmarks/hole_cost.py [--repeat 2] [--workdir /tmp/surfinpaint-scale]
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from scale import make_case  # noqa: E402

from surfinpaint import fill_holes  # noqa: E402
from surfinpaint.data import torus  # noqa: E402
from surfinpaint.fill.conformal.method import conformal_fill  # noqa: E402
from surfinpaint.fill.conformal.options import ConformalOptions  # noqa: E402
from surfinpaint.fill.holes import find_holes  # noqa: E402
from surfinpaint.fill.neighbourhood import FilledMesh  # noqa: E402
from surfinpaint.fill.warmup import warm_kernels  # noqa: E402
from surfinpaint.geometry.cutting import cut_geodesic_disk  # noqa: E402
from surfinpaint.geometry.mesh import mean_edge_length  # noqa: E402
from surfinpaint.io.formats import read_mesh  # noqa: E402


def _digest(*parts) -> str:
    h = hashlib.sha1()
    for part in parts:
        h.update(np.ascontiguousarray(part).tobytes() if isinstance(part, np.ndarray)
                 else repr(part).encode())
    return h.hexdigest()[:12]


def big_holes(workdir: Path) -> list:
    """The 651k case's holes, cut with their neighbourhoods."""
    case = make_case(workdir, "bumpy-sphere-651k", 8, 10, 12.0)
    vertices, faces = read_mesh(case.path)[:2]
    options = ConformalOptions()
    mesh = FilledMesh(vertices, faces)
    return [mesh.cut(h.loop, options.neighbourhood_rings(h.n_edges))
            for h in find_holes(vertices, faces)]


def speed_holes() -> list:
    """``benchmarks/speed.py``'s torus holes (its full set of radii)."""
    v, f = torus(R=1.0, r=0.4, n_major=192, n_minor=80)
    h = mean_edge_length(v, f)
    return [cut_geodesic_disk(v, f, 1000 * k + 17, r * h)
            for k, r in enumerate((3, 5, 8, 11, 14, 16))]


def fill_big(cuts) -> list[str]:
    out = []
    for cut in cuts:
        fill = conformal_fill(cut.vertices, cut.faces, cut.local_loop)
        v = fill.verdict
        tests = None if v is None else (sorted(v.hidden.items()), sorted(v.sibling.items()))
        out.append(_digest(tests, fill.selection, fill.vertices, fill.faces))
    return out


def fill_speed(cuts) -> list[str]:
    out = []
    for cut in cuts:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = fill_holes(cut.vertices, cut.faces, holes=[cut.loop])
        reports = [dataclasses.replace(r, seconds=0.0) for r in result.reports]
        out.append(_digest(result.vertices, result.faces, reports))
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/surfinpaint-scale"))
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args(argv)
    args.workdir.mkdir(parents=True, exist_ok=True)
    big, small = big_holes(args.workdir), speed_holes()
    warm_kernels()
    conformal_fill(big[-1].vertices, big[-1].faces, big[-1].local_loop)
    fill_speed(small[:1])
    for _ in range(args.repeat):
        started = time.process_time()
        big_digests = fill_big(big)
        middle = time.process_time()
        speed_digests = fill_speed(small)
        load = open("/proc/loadavg").read().split()[0]
        print(f"651k holes {middle - started:.2f} s CPU, speed.py holes "
              f"{time.process_time() - middle:.2f} s CPU (load {load})")
    print("651k holes:", " ".join(big_digests))
    print("speed.py holes:", " ".join(speed_digests))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
