"""Inpainted overlays of filled holes against the truth: fsaverage5 left pial surface with its
curvature, sulcal depth and cortical thickness maps (as nilearn ships them, offline).

Geodesic disks are cut out of the surface (:func:`surfinpaint.geometry.cutting.cut_holes`,
one hole a case, centres drawn at random with a fixed seed) and the maps' values at the new
vertices are compared with the truth, for four rules:

- ``biharmonic``: :mod:`surfinpaint.fill.attributes` (biharmonic on the patch's LSCM map);
- ``biharmonic-3d``: the same on the patch's 3D triangles (the surface metric);
- ``harmonic``: ``order=1`` on the LSCM map (the Dirichlet energy is conformally invariant,
  so this is also the harmonic fill on the surface);
- ``nearest``: each new vertex copies the nearest original vertex's value (3D distance).

Two settings. ``true surface``: the removed vertices are put back where they were, so only the
overlay is inpainted and the error is exact at each vertex. ``filled surface``: the hole is
filled by :func:`surfinpaint.fill_holes` (default method) and the truth at a new vertex is the
map interpolated (barycentrically) at its closest point on the removed patch.

Errors are mean absolute errors over all new vertices of all holes, in the map's units
(curv in 1/mm, sulc and thickness in mm), with the map's standard deviation for scale.

First, the sphere targets of ``tests/test_attributes.py`` (unit sphere, one hole of geodesic
radius 0.8, default fill): colour linear in position, z, normals and a two-label split.

    python benchmarks/attributes.py [--holes 12] [--radii 8,15,25] [--seed 0] [--no-fill]
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np
from scipy.spatial import cKDTree

from surfinpaint import fill_holes
from surfinpaint.data import fsaverage5, sphere
from surfinpaint.fill.attributes import (
    fill_hole_attributes,
    fill_result_attributes,
    hole_domain,
    inpaint_values,
)
from surfinpaint.geometry.closest_point import closest_point_on_triangles
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length, vertex_normals

MAPS = ("curv", "sulc", "thick")
RULES = ("biharmonic", "biharmonic-3d", "harmonic", "nearest")


def load_maps() -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """The LEFT pial surface and its maps (never the right hemisphere: it is reserved)."""
    import nibabel
    from nilearn import datasets

    bundle = datasets.fetch_surf_fsaverage("fsaverage5")
    v, f = fsaverage5("pial", "left")
    maps = {name: np.asarray(nibabel.load(bundle[f"{name}_left"]).agg_data(), dtype=float)
            for name in MAPS}
    return v, f, maps


def _stack(maps: dict[str, np.ndarray], ids: np.ndarray) -> np.ndarray:
    return np.column_stack([maps[name][ids] for name in MAPS])


def true_surface_case(v, f, maps, cut) -> dict[str, np.ndarray]:
    """(new, maps) errors of each rule with the removed vertices back in place."""
    hole = cut.holes[0]
    kept_faces = cut.kept[cut.faces]
    loop = cut.kept[hole.loop]
    fill_faces = hole.truth_ids[hole.truth_faces]
    new_ids = np.setdiff1d(hole.truth_ids, cut.kept)
    truth = _stack(maps, new_ids)
    attrs = {name: maps[name] for name in MAPS}
    kinds = dict.fromkeys(MAPS, "values")
    out = {}
    for rule, order in (("biharmonic", 2), ("harmonic", 1)):
        filled = fill_hole_attributes(v, kept_faces, loop, fill_faces, new_ids, attrs,
                                      kinds=kinds, order=order)
        out[rule] = np.column_stack([filled[name] for name in MAPS]) - truth
    dom = hole_domain(v, kept_faces, loop, fill_faces)
    known = ~np.isin(dom.ids, new_ids)
    flat = inpaint_values(v[dom.ids], dom.faces, known, _stack(maps, dom.ids))
    out["biharmonic-3d"] = flat[np.searchsorted(dom.ids, new_ids)] - truth
    _, nearest = cKDTree(v[cut.kept]).query(v[new_ids])
    out["nearest"] = _stack(maps, cut.kept[nearest]) - truth
    return out


def _truth_at(points, hole, maps) -> np.ndarray:
    """The maps interpolated at each point's closest point on the removed patch."""
    tv, tf = hole.truth_vertices, hole.truth_faces
    k = min(16, len(tf))
    _, cand = cKDTree(tv[tf].mean(axis=1)).query(points, k=k)
    cand = cand.reshape(len(points), k)
    rep = np.repeat(points, k, axis=0)
    tri = tv[tf[cand.ravel()]]
    q = closest_point_on_triangles(rep, tri[:, 0], tri[:, 1], tri[:, 2])
    best = np.argmin(((q - rep) ** 2).sum(axis=1).reshape(-1, k), axis=1)
    pick = np.arange(len(points)) * k + best
    a, b, c = tri[pick, 0], tri[pick, 1], tri[pick, 2]
    q = q[pick]
    # barycentric coordinates of q in its triangle
    v0, v1, v2 = b - a, c - a, q - a
    d00, d01, d11 = (v0 * v0).sum(1), (v0 * v1).sum(1), (v1 * v1).sum(1)
    d20, d21 = (v2 * v0).sum(1), (v2 * v1).sum(1)
    den = np.maximum(d00 * d11 - d01 * d01, 1e-300)
    wb = (d11 * d20 - d01 * d21) / den
    wc = (d00 * d21 - d01 * d20) / den
    weights = np.column_stack([1 - wb - wc, wb, wc])
    corner_ids = hole.truth_ids[tf[cand[np.arange(len(points)), best]]]
    values = np.stack([_stack(maps, corner_ids[:, j]) for j in range(3)], axis=1)
    return np.einsum("ij,ijk->ik", weights, values)


def filled_surface_case(maps, cut) -> dict[str, np.ndarray] | None:
    """(new, maps) errors of each rule on the default fill of the hole."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = fill_holes(cut.vertices, cut.faces)
    n = len(cut.vertices)
    if len(result.vertices) == n:
        return None
    new = result.vertices[n:]
    truth = _truth_at(new, cut.holes[0], maps)
    attrs = {name: maps[name][cut.kept] for name in MAPS}
    kinds = dict.fromkeys(MAPS, "values")
    out = {}
    for rule, order in (("biharmonic", 2), ("harmonic", 1)):
        filled = fill_result_attributes(result, attrs, kinds=kinds, order=order)
        out[rule] = np.column_stack([filled[name][n:] for name in MAPS]) - truth
    _, nearest = cKDTree(cut.vertices).query(new)
    out["nearest"] = _stack(maps, cut.kept[nearest]) - truth
    return out


def sphere_targets() -> str:
    """The sphere case of the tests, measured: a markdown list."""
    direction = np.array([0.6, 0.3, 0.7]) / np.linalg.norm([0.6, 0.3, 0.7])

    def colour(p):
        return 127.5 + 127.5 * p @ direction

    v, f = sphere(4)
    cut = cut_holes(v, f, [0], [0.8])
    cv, cf, n = cut.vertices, cut.faces, len(cut.vertices)
    normal = np.cross(v[0], [0.0, 0.0, 1.0])
    normal /= np.linalg.norm(normal)
    result = fill_holes(cv, cf)
    out = fill_result_attributes(result, {
        "color": np.rint(colour(cv)).astype(np.uint8), "z": cv[:, 2],
        "normal": vertex_normals(cv, cf), "side": np.where(cv @ normal > 0, 7, 2)})
    new = result.vertices[n:]
    _, nearest = cKDTree(cv).query(new)
    unit = new / np.linalg.norm(new, axis=1, keepdims=True)
    angle = np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", out["normal"][n:], unit),
                                         -1, 1)))
    side = new @ normal
    far = np.abs(side) > mean_edge_length(cv, cf)
    wrong = out["side"][n:] != np.where(side > 0, 7, 2)
    return "\n".join([
        f"sphere(4), one {len(cut.loop)}-edge hole, {len(new)} new vertices:",
        f"- colour: mean error {np.abs(out['color'][n:] - colour(new)).mean():.2f}/255 "
        f"(nearest colour copied: {np.abs(np.rint(colour(cv))[nearest] - colour(new)).mean():.1f})",
        f"- z: max error {np.abs(out['z'][n:] - new[:, 2]).max():.4f}",
        f"- normals: max {angle.max():.1f} degrees from the sphere's",
        f"- labels: {int(wrong[far].sum())} of {int(far.sum())} new vertices farther than an "
        f"edge from the plane on the wrong side ({int(wrong[~far].sum())} of "
        f"{int((~far).sum())} nearer)"])


def _table(errors: dict, maps, title: str, rules) -> str:
    lines = [f"**{title}**", "",
             "| map (sd) | hole radius | new vertices | " + " | ".join(rules) + " |",
             "|---|---|---|" + "---|" * len(rules)]
    for j, name in enumerate(MAPS):
        for radius, per_rule in errors.items():
            if not per_rule:
                continue
            mae = {rule: np.abs(np.concatenate(per_rule[rule])[:, j]).mean() for rule in rules}
            count = sum(len(e) for e in per_rule[rules[0]])
            cells = " | ".join(f"{mae[rule]:.4f}" for rule in rules)
            lines.append(f"| {name} ({maps[name].std():.3f}) | {radius:g} mm | {count} | "
                         f"{cells} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--holes", type=int, default=12, help="holes per radius")
    parser.add_argument("--radii", default="8,15,25", help="geodesic radii in mm")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--no-fill", action="store_true", help="true surface only")
    args = parser.parse_args(argv)
    print(sphere_targets() + "\n")
    v, f, maps = load_maps()
    rng = np.random.default_rng(args.seed)
    radii = [float(r) for r in args.radii.split(",")]
    true_err: dict = {r: {rule: [] for rule in RULES} for r in radii}
    fill_err: dict = {r: {rule: [] for rule in RULES if rule != "biharmonic-3d"}
                      for r in radii}
    started, skipped = time.perf_counter(), 0
    for radius in radii:
        made = 0
        for center in rng.permutation(len(v)):
            if made == args.holes:
                break
            try:
                cut = cut_holes(v, f, [int(center)], [radius])
            except ValueError:
                skipped += 1
                continue
            made += 1
            for rule, e in true_surface_case(v, f, maps, cut).items():
                true_err[radius][rule].append(e)
            if not args.no_fill:
                errors = filled_surface_case(maps, cut)
                for rule, e in (errors or {}).items():
                    fill_err[radius][rule].append(e)
    print(f"fsaverage5 left pial, {args.holes} holes per radius, seed {args.seed} "
          f"({skipped} centres skipped: no disk), {time.perf_counter() - started:.0f} s\n")
    print(_table(true_err, maps, "True surface: mean absolute error at the removed vertices",
                 RULES))
    if not args.no_fill:
        print()
        print(_table(fill_err, maps, "Filled surface (default fill): mean absolute error at "
                     "the new vertices", [r for r in RULES if r != "biharmonic-3d"]))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
