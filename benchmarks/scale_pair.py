"""Paired whole-process runs of the 651k case's ``surfinpaint fill`` from several source trees
(issue 15; docs/scale.md, session 43): the trees' runs interleaved round by round (the order
rotated each round), after one untimed run of each; per run the wall and CPU seconds of the
process and its workers, the peak memory and the output's sha256 (first 12 hex); then each
tree's medians and its paired ratios to the first tree (median and geometric mean of the
rounds' ratios).

Each tree runs with its own ``PYTHONPYCACHEPREFIX`` (``benchmarks/scale.py``'s launcher and
child environment, ``PYTHONPATH`` the tree). numba keys its cache by the source's path: fill a
new tree's cache first (``SURFINPAINT_COMPILE=foreground``, one run), or its first runs use
the numpy kernels while the background compilation fills it (docs/scale.md, session 42).

    PYTHONPATH=src python benchmarks/scale_pair.py main=/tmp/main/src,branch=src [--rounds 8]
        [--workdir /tmp/surfinpaint-scale] [--fill-args="--method fair"]
"""

from __future__ import annotations

import argparse
import hashlib
import shlex
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
from scale import child_environment, make_case, run_child  # noqa: E402


def digest(path: Path) -> str:
    """The first 12 hex digits of the file's sha256 (as docs/scale.md gives outputs)."""
    return hashlib.sha256(path.read_bytes()).hexdigest()[:12]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("trees", help="NAME=SRC[,NAME=SRC...]: the first is the reference")
    parser.add_argument("--rounds", type=int, default=8)
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/surfinpaint-scale"))
    parser.add_argument("--fill-args", default="",
                        help='more arguments of the fill command, e.g. --fill-args="--method fair"')
    args = parser.parse_args(argv)
    if args.rounds < 1 or "=" not in args.trees:
        parser.error("give NAME=SRC trees and at least one round")
    trees = dict(item.split("=", 1) for item in args.trees.split(","))
    args.workdir.mkdir(parents=True, exist_ok=True)
    case = make_case(args.workdir, "bumpy-sphere-651k", 8, 10, 12.0)

    def run(name: str):
        env = child_environment(args.workdir / f"pair-{name}")
        env["PYTHONPATH"] = str(Path(trees[name]).resolve())
        out = args.workdir / f"pair-{name}.out.ply"
        result = run_child([sys.executable, "-m", "surfinpaint", "fill", str(case.path), "-o",
                            str(out), "-q", *shlex.split(args.fill_args)], env)
        return result, digest(out)

    names = list(trees)
    for name in names:
        run(name)
    runs: dict[str, list] = {name: [] for name in names}
    for k in range(args.rounds):
        for name in names[k % len(names):] + names[:k % len(names)]:
            result, out = run(name)
            runs[name].append(result)
            print(f"round {k + 1} {name}: {result.wall:.3f} s wall, {result.cpu:.3f} s CPU, "
                  f"{result.peak_mb:.0f} MB, output {out}, load {result.load:.1f}", flush=True)
    reference = runs[names[0]]
    for name in names:
        walls, cpus = [r.wall for r in runs[name]], [r.cpu for r in runs[name]]
        line = (f"{name}: median {statistics.median(walls):.3f} s wall, "
                f"{statistics.median(cpus):.3f} s CPU")
        if name != names[0]:
            wall_ratio = [a.wall / b.wall for a, b in zip(runs[name], reference, strict=True)]
            cpu_ratio = [a.cpu / b.cpu for a, b in zip(runs[name], reference, strict=True)]
            line += (f"; / {names[0]}: wall {statistics.median(wall_ratio):.3f} (geometric "
                     f"{statistics.geometric_mean(wall_ratio):.3f}), CPU "
                     f"{statistics.median(cpu_ratio):.3f} (geometric "
                     f"{statistics.geometric_mean(cpu_ratio):.3f})")
        print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
