"""Does the tube-ends warning (:mod:`surfinpaint.fill.topology`) fire where it should not?

For each mesh of ``benchmarks/holes_manifest.json`` in the chosen split, the manifest's holes
that can be cut together (greedily, skipping those that would overlap) are cut at once and
filled by the faired fill; the warnings of :func:`surfinpaint.fill.topology.topology_changes`
are printed with the time the check took. None of these holes is a tube cut across, so any
warning is a false alarm.

Run::

    .venv/bin/python benchmarks/topology_warning.py --split tuning
    .venv/bin/python benchmarks/topology_warning.py --split validation
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import validation_meshes as vm  # noqa: E402

from surfinpaint.fill.pipeline import fill_holes  # noqa: E402
from surfinpaint.fill.topology import topology_changes  # noqa: E402
from surfinpaint.geometry.cutting import cut_holes  # noqa: E402

MANIFEST = Path(__file__).parent / "holes_manifest.json"


def _cut_together(mesh: vm.BenchMesh, holes: list[dict]):
    """The mesh with as many of ``holes`` cut at once as do not overlap."""
    chosen: list[dict] = []
    for hole in holes:
        trial = [*chosen, hole]
        try:
            cut_holes(mesh.vertices, mesh.faces, [np.asarray(h["centre"]) for h in trial],
                      [h["radius"] for h in trial])
        except ValueError:
            continue
        chosen.append(hole)
    return cut_holes(mesh.vertices, mesh.faces, [np.asarray(h["centre"]) for h in chosen],
                     [h["radius"] for h in chosen]), len(chosen)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--split", choices=("tuning", "validation"), default="tuning")
    args = parser.parse_args(argv)
    meshes = json.loads(MANIFEST.read_text())["meshes"]
    alarms = 0
    for entry in meshes:
        if entry["split"] != args.split:
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cut, n_cut = _cut_together(vm.load_entry(entry), entry["holes"])
            result = fill_holes(cut.vertices, cut.faces, method="fair")
            started = time.perf_counter()
            changes = topology_changes(result)
            seconds = time.perf_counter() - started
        alarms += len(changes)
        print(f"{entry['mesh']}: {n_cut} holes cut, {len(result.reports)} filled, "
              f"{len(changes)} warnings, check {seconds:.3f} s", flush=True)
        for change in changes:
            print(f"  {change.message}")
    print(f"{alarms} warnings in all")
    return 0


if __name__ == "__main__":
    sys.exit(main())
