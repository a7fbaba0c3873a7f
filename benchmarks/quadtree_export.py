"""The quadtree export of the λ-H representation, measured (issue 18).

Per disk, :func:`~surfinpaint.representation.quadtree_represent.represent_quadtree` (the
library's ``represent --export-quadtree``): the parameter domain (LSCM by default, as the
default representation; or the paper's rectangle) covered by 2:1-balanced quadtrees, one
per target, whose cells are split while a cell's side on the surface, (side in the plane) ×
σ, exceeds TARGET × the diagonal (σ = √(surface area / parameter area) of the mesh's
triangles, the median at each vertex, the largest at the cell's 9 probe points); with
LSCM's free border, the triangles with a corner outside the mesh's parameter triangles are
dropped. φ is sampled at the nodes from the mesh itself (piecewise linear, ``--sampling
pl``, the default) or from its Clough–Tocher interpolant (``smooth``: on the tall finger that
interpolant folds, 279 folded edges of the sampled 0.1 tree; docs/representation.md,
session 19); λ, H and the defect are those of the tree's own triangles, so the sampled φ
solves the mesh-form equations exactly. The rebuild
(:func:`~surfinpaint.representation.quadtree_represent.level_solves`):

- ``--direct``: each tree alone, from the harmonic surface (Newton, then the continuation,
  as :func:`~surfinpaint.representation.represent.rebuild` of a mesh representation);
- default: coarse to fine (the library's rebuild): the coarsest as ``--direct``, each finer
  one from the coarser solution interpolated at its nodes, the nodes the two share held
  while Newton solves for the others, then released; a finer tree that does not converge
  so, alone as ``--direct``. As in the library, the trees after one that fails are not
  tried (their floors are still measured).

The round trip is measured as the library's self-check: the rebuilt nodes interpolated
(Clough–Tocher over the tree's triangles) at the mesh's vertices, against the mesh,
two-sided surface distance in % of the diagonal (targets of the 512² export: mean < 0.1 %,
Hausdorff < 1 %); the *floor* is the same with the sampled φ (an exact rebuild).

Run: ``PYTHONPATH=src python benchmarks/quadtree_export.py [--meshes foot,legcap,finger2]
[--targets 0.4,0.2,0.1,0.05,0.02] [--depth 14] [--map lscm|rectangular] [--floor-only] [--direct]
[--sampling pl|smooth]``
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
from represent_speed import MAKERS, pymeshlab_sample

from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.representation.quadtree_represent import (
    DEFAULT_TARGETS,
    level_solves,
    represent_quadtree,
    tree_vertices,
)
from surfinpaint.representation.roundtrip import measure_round_trip

# held out: nothing here was chosen on them (session 18's check of the graded grid);
# name: (PyMeshLab sample, axis, its lowest or highest vertex, geodesic radius)
HELD_OUT = {"cow_hoof25": ("cow.obj", 1, "min", 0.25), "cow_hoof40": ("cow.obj", 1, "min", 0.4),
            "cow_z_max": ("cow.obj", 2, "max", 0.3), "cow_z_min": ("cow.obj", 2, "min", 0.3),
            "bone_x_min": ("bone.ply", 0, "min", 0.3)}


def held_out_cap(name: str):
    sample, axis, end, radius = HELD_OUT[name]
    v, f = pymeshlab_sample(sample)
    seed = int(np.argmin(v[:, axis]) if end == "min" else np.argmax(v[:, axis]))
    cut = cut_geodesic_disk(v, f, seed, radius)
    return f"held out: {sample} cap at its {end} {'xyz'[axis]}, r = {radius}", \
        cut.truth_vertices, cut.truth_faces


def folded_edges(points: np.ndarray, faces: np.ndarray) -> int:
    """Interior edges whose two triangles' normals differ by more than 90°."""
    p = points[faces]
    normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    table = EdgeTable.build(faces, len(points))
    a, b = table.owners[table.count == 2].T
    return int(((normal[a] * normal[b]).sum(axis=1) < 0).sum())


def run(name: str, targets: tuple[float, ...], depth: int, map: str, floor_only: bool,
        direct: bool, sampling: str = "pl") -> None:
    if name in HELD_OUT:
        title, v, f = held_out_cap(name)
    else:
        title, (v, f) = MAKERS[name][0], MAKERS[name][1]()
    started = time.perf_counter()
    rep = represent_quadtree(v, f, targets=targets, map=map, max_depth=depth,
                             sampling=sampling)
    print(f"\n**{title}** ({len(v)} vertices, map {rep.map}, depth ≤ {depth}, sampling "
          f"{sampling}; trees sampled in {time.perf_counter() - started:.1f} s)\n")
    print("| target × diag | nodes | folded edges | floor mean / Hausdorff % "
          "| rebuild mean / Hausdorff % | converged | factorizations | s | how |")
    print("|---|---|---|---|---|---|---|---|---|")
    solves = iter(()) if floor_only else level_solves(rep, direct=direct)
    failed = False
    for level in rep.levels:
        started = time.perf_counter()
        solve = None if failed else next(solves, None)
        x, ok, steps, how = (level.phi, False, 0, "not tried" if failed else "not rebuilt") \
            if solve is None else (solve.points, solve.converged, solve.iterations,
                                   solve.message)
        failed |= solve is not None and not solve.converged
        c = measure_round_trip(v, tree_vertices(rep, level, x), f, converged=ok,
                               iterations=steps, message=how, seconds=0.0,
                               floor=tree_vertices(rep, level, level.phi))
        d = c.diagonal / 100
        rebuilt = "–" if solve is None else f"{c.mean / d:.3g} / {c.hausdorff / d:.3g}"
        print(f"| {level.target:g} | {len(level.uv)} | {folded_edges(level.phi, level.faces)} "
              f"| {c.floor_mean / d:.3g} / {c.floor_hausdorff / d:.3g} | {rebuilt} | {ok} "
              f"| {steps} | {time.perf_counter() - started:.1f} | {how} |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--meshes", default="foot,legcap,finger2",
                        help=f"of {', '.join(MAKERS)}, or held out: {', '.join(HELD_OUT)}")
    parser.add_argument("--targets", default=",".join(map(str, DEFAULT_TARGETS)),
                        help="the trees' cell sides × the diagonal, coarse to fine")
    parser.add_argument("--depth", type=int, default=14)
    parser.add_argument("--map", choices=("lscm", "rectangular"), default="lscm")
    parser.add_argument("--floor-only", action="store_true")
    parser.add_argument("--sampling", choices=("pl", "smooth"), default="pl",
                        help="φ at the nodes from the mesh itself (default) or from its "
                             "Clough–Tocher interpolant")
    parser.add_argument("--direct", action="store_true",
                        help="rebuild each tree alone from the harmonic surface")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    targets = tuple(float(t) for t in args.targets.split(","))
    for name in args.meshes.split(","):
        run(name, targets, args.depth, args.map, args.floor_only, args.direct, args.sampling)


if __name__ == "__main__":
    main()
