"""The resampled export that holds, measured on every benchmark disk (issue 18).

Per disk, the library's :func:`~surfinpaint.representation.exports.resampled_export`
(``surfinpaint represent DISK -o rep.npz --export images.npz``): the quadtrees (default
targets 0.4 … 0.02 × the diagonal) where their rebuild gives the disk back within the
target (mean < 0.1 %, Hausdorff < 1 % of the bounding-box diagonal), else the square grid
at 512 nodes along its long side; a candidate whose samples alone miss the target is not
rebuilt. Printed per disk: the default representation (``represent(v, f)``: the mesh
form, or the quadtrees where its rebuild does not converge) and its round trip; the
export's form written, its size, its own round trip (two-sided
surface distance, % of the diagonal) and sampling floor, whether it meets the target, the
stages the export said (why a candidate was passed), and the seconds.

The disks are ``benchmarks/represent_speed.py``'s eleven (the tuning disks of the trees'
defaults: finger h = 2, foot, leg cap) and the held-out PyMeshLab caps of
``benchmarks/quadtree_export.py`` (nothing was chosen on them).

Run: ``PYTHONPATH=src python benchmarks/resampled_export.py [--meshes bumpy,pial70,...]``
"""

from __future__ import annotations

import argparse
import time
import warnings

from quadtree_export import HELD_OUT, held_out_cap
from represent_speed import MAKERS

from surfinpaint.representation.exports import form_size, resampled_export, within_target
from surfinpaint.representation.represent import represent


def run(name: str) -> None:
    if name in HELD_OUT:
        title, v, f = held_out_cap(name)
    else:
        title, (v, f) = MAKERS[name][0], MAKERS[name][1]()
    said = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rep = represent(v, f)  # the default, checked: the mesh form, or the trees
    c = rep.check
    default = (f"{rep.discretization}: {c.mean_percent:.2g} / {c.hausdorff_percent:.2g}"
               + ("" if c.converged else " (not converged)"))
    started = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        form = resampled_export(rep, progress=said.append)
    seconds = time.perf_counter() - started
    c = form.check
    d = c.diagonal / 100
    size = form_size(form)
    passed = [line for line in said if line.startswith("the ")]
    warned = sorted({w.category.__name__ for w in caught})
    print(f"| {title} | {len(v)} | {default} | {form.discretization} ({form.map}) | {size} | "
          f"{c.mean / d:.3g} / {c.hausdorff / d:.3g} | "
          f"{c.floor_mean / d:.3g} / {c.floor_hausdorff / d:.3g} | "
          f"{'**yes**' if within_target(c) else 'no'} | {seconds:.0f} | "
          f"{'; '.join(passed) or '–'} | {', '.join(warned) or '–'} |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--meshes", default=",".join([*MAKERS, *HELD_OUT]),
                        help=f"of {', '.join(MAKERS)}, or held out: {', '.join(HELD_OUT)}")
    args = parser.parse_args()
    print("| disk | vertices | default representation: round trip mean / Hausdorff % | "
          "export (map) | nodes per tree / grid | round trip mean / Hausdorff % | floor mean "
          "/ Hausdorff % | within 0.1 / 1 % | export s | candidates passed | warnings |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name in args.meshes.split(","):
        run(name)


if __name__ == "__main__":
    main()
