"""The default fill's slowest holes, two source trees paired in fresh processes (issue 14).

The holes (cut once, kept in ``--workdir``): spent holdout 18's junction_box #6 and lathe_dog
#6, the CAD tuning part channel #5 and the built animal11 #5 (docs/convergence.md, sessions
41-44), and spent holdout 10's spanner #6 (a CAD hole whose candidate fills differ by more than
their size: docs/scale.md, session 52 helper). For each pair of runs, one fresh process per
tree (order alternated, pinned to one core with ``--cpu``) fills the hole once to warm up and
then ``--fills`` times; it reports the medians of the fills' user and system CPU seconds
(``os.times``: the system time is the page faults' share, which the allocator's thresholds
change, session 44 helper) and a hash of the written positions. Printed: each pair's totals and
ratio (second tree / first), then each hole's median ratio and whether the positions were the
same in every pair::

    python benchmarks/slow_holes.py /work/main/src src --pairs 5 --fills 5 --cpu 1
    python benchmarks/slow_holes.py A/src B/src --env MALLOC_TRIM_THRESHOLD_=268435456

Runs with ``SURFINPAINT_COMPILE=foreground`` (a fresh tree's numba cache is filled first, not
replaced by the kernels' numpy versions). A machine shared with other work gives noisy
seconds: read the ratios, not the times.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import pickle
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
HOLES = {"junction_box6": ("holdout18", "junction_box", 6),
         "lathe_dog6": ("holdout18", "lathe_dog", 6),
         "channel5": ("cad_tuning", "channel", 5),
         "animal11_5": ("animals", "animal11", 5),
         "spanner6": ("holdout10", "spanner", 6)}


def cut(name: str):
    """The hole ``name`` of :data:`HOLES`, cut as its benchmark cuts it."""
    sys.path.insert(0, str(HERE))
    import holes_manifest
    import validation
    import validation_meshes

    kind, mesh, k = HOLES[name]
    if kind == "animals":
        import animals

        from surfinpaint.geometry.cutting import cut_geodesic_disk
        seed = int(mesh[len("animal"):])
        m = animals.animal(seed)
        hole = holes_manifest.plan_holes(m.vertices, m.faces, "organic", 2000 + seed, mesh)[k]
        return cut_geodesic_disk(m.vertices, m.faces, np.asarray(hole["centre"]),
                                 hole["radius"])
    manifest = holes_manifest.read(HERE / f"{kind}_manifest.json")
    entry = next(e for e in manifest["meshes"] if e["mesh"] == mesh)
    return validation._cut(validation_meshes.load_entry(entry), entry["holes"][k])


def child(path: str, fills: int) -> None:
    """In the process under test: a warm fill, then ``fills`` fills of the pickled hole."""
    from surfinpaint import fill_holes

    hole = pickle.loads(Path(path).read_bytes())

    def fill():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return fill_holes(hole.vertices, hole.faces, holes=[hole.loop])

    fill()
    user, system = [], []
    for _ in range(fills):
        before = os.times()
        result = fill()
        after = os.times()
        user.append(after.user - before.user)
        system.append(after.system - before.system)
    new = np.ascontiguousarray(np.asarray(result.vertices)[len(hole.vertices):])
    print(json.dumps({"user": float(np.median(user)), "system": float(np.median(system)),
                      "total": float(np.median(np.add(user, system))),
                      "hash": hashlib.sha256(new.tobytes()).hexdigest()[:16]}))


def run(tree: str, path: Path, fills: int, cpu: int | None, env: dict) -> dict:
    """One fresh process of ``tree`` (a ``src`` directory) filling the hole at ``path``."""
    command = [sys.executable, __file__, "--child", str(path), "--fills", str(fills)]
    if cpu is not None:
        command = ["taskset", "-c", str(cpu), *command]
    environment = dict(os.environ, PYTHONPATH=tree, SURFINPAINT_COMPILE="foreground", **env)
    out = subprocess.run(command, env=environment, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("trees", nargs="*", help="two src directories: first, second")
    parser.add_argument("--holes", default=",".join(HOLES))
    parser.add_argument("--pairs", type=int, default=5)
    parser.add_argument("--fills", type=int, default=5)
    parser.add_argument("--cpu", type=int, default=None, help="pin each run to this core")
    parser.add_argument("--env", action="append", default=[], help="KEY=VALUE for the runs")
    parser.add_argument("--workdir", default="/tmp/surfinpaint_slow_holes")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        child(args.child, args.fills)
        return
    if len(args.trees) != 2:
        parser.error("give two src directories")
    env = dict(item.split("=", 1) for item in args.env)
    work = Path(args.workdir)
    work.mkdir(parents=True, exist_ok=True)
    for name in args.holes.split(","):
        path = work / f"{name}.pkl"
        if not path.exists():
            path.write_bytes(pickle.dumps(cut(name)))
        ratios, same = [], True
        for i in range(args.pairs):
            order = (0, 1) if i % 2 == 0 else (1, 0)
            runs = {k: run(args.trees[k], path, args.fills, args.cpu, env) for k in order}
            ratio = runs[1]["total"] / runs[0]["total"]
            ratios.append(ratio)
            same &= runs[0]["hash"] == runs[1]["hash"]
            print(f"{name} pair {i + 1}: " + "  ".join(
                f"{k}: {runs[k]['user']:.3f} + {runs[k]['system']:.3f} s" for k in (0, 1))
                + f"  ratio {ratio:.3f}", flush=True)
        print(f"{name}: median ratio {np.median(ratios):.3f} ({min(ratios):.3f}-"
              f"{max(ratios):.3f}), the same positions in every pair: {same}", flush=True)


if __name__ == "__main__":
    main()
