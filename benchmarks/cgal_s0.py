"""Where CGAL's faired fills beat ours: its triangulation, its refinement or its fairing
weights? (issue 14 item 3, on tuning holes; docs/candidates.md)

Per hole, the mean error (% of the hole diameter, as ``benchmarks/validation.py`` scores)
of fills that mix CGAL's steps (through the ``cgal`` package's ``triangulate_hole``,
``triangulate_and_refine_hole`` and ``triangulate_refine_and_fair_hole``) with ours:

- ``cgal`` / ``cgal3``: CGAL's whole pipeline (bi- / trilaplacian);
- ``fair{k}``: ours (3D-Delaunay-restricted DP, our default refinement, cotangent fairing);
- ``ctri+fair{k}``: CGAL's triangulation, our Liepa-style refinement
  (``refine_patch(style="liepa")``) and fairing;
- ``ctri+cstyle+fair{k}``: CGAL's triangulation, our CGAL-style refinement
  (``style="cgal"``, session 9) and fairing;
- ``cref+fair{k}``: CGAL's triangulation and refinement, our fairing;
- ``cref+clamped{k}``: the same with CGAL's non-negative clamped cotangents
  (``operator="clamped"``);
- ``cdt+fair{k}``: our planar constrained Delaunay triangulation (``search="cdt"``);
- ``clamped{k}``: ours with CGAL's clamped weights (session 43: is it the weights?);
- ``cstyle+fair{k}`` / ``cstyle+clamped{k}``: ours with the CGAL-style refinement, with
  our cotangent or CGAL's clamped weights (session 44);
- ``n:<column>``: the new vertices of a column's patch (refinement density).

Run::

    .venv/bin/python benchmarks/cgal_s0.py --holes bunny#1,cube40#1,pial#0,white#2
    .venv/bin/python benchmarks/cgal_s0.py --holes tuning --ratios \
        cref+fair3/ctri+fair3,ctri+cstyle+fair3/ctri+fair3 --out s0.json

(``--holes tuning``: every hole of the tuning meshes; ``--ratios a/b,...``: per-hole ratios
of two columns over the holes, as a table; ``--out``: the rows as JSON.)

Session 43: ``--manifest`` takes a spent holdout set (9–18) instead of the tuning half, and
``--holes brain`` every hole of a manifest's brain-kind meshes (tuning split only in
``holes_manifest.json``), ``--triangulation-only`` the two triangulations unrefined.
Session 44: any tuning-side set and the spent holdouts (9-27 from session 52);
``--holes scan`` every hole of a manifest's range scans, ``--orders 2`` the bilaplacian
columns only::

    .venv/bin/python benchmarks/cgal_s0.py --manifest benchmarks/curved_scans_manifest.json \
        --holes scan --orders 2 --out s0_cscan.json

Session 43::

    .venv/bin/python benchmarks/cgal_s0.py --manifest benchmarks/holdout17_manifest.json \
        --holes brain --out h17.json
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import accuracy  # noqa: E402
import holes_manifest  # noqa: E402
import peers  # noqa: E402
import validation  # noqa: E402
import validation_meshes as vm  # noqa: E402

from surfinpaint.fill.liepa.baseline import faired_fills  # noqa: E402
from surfinpaint.fill.liepa.fairing import fair  # noqa: E402
from surfinpaint.fill.liepa.refinement import refine_patch  # noqa: E402
from surfinpaint.fill.liepa.triangulation import minimum_weight_triangulation  # noqa: E402
from surfinpaint.geometry.mesh import faces_near  # noqa: E402
from surfinpaint.geometry.metrics import hole_patch_of, surface_distance  # noqa: E402

HOLES = ("bunny#1,airplane#5,cube40#1,pial#0,white#2,white#3,face000#3,bunny#0,white#1,"
         "white#4")


def _cgal_step(step: str):
    """peers.cgal_fill with CGAL's ``step`` in place of triangulate_refine_and_fair_hole."""
    import CGAL.CGAL_Polygon_mesh_processing as pmp

    def run(v, f, loop):
        whole = pmp.triangulate_refine_and_fair_hole

        def call(poly, border, out_faces, out_vertices, density, _continuity):
            if step == "triangulate_hole":
                return getattr(pmp, step)(poly, border, out_faces)
            return getattr(pmp, step)(poly, border, out_faces, out_vertices, density)
        pmp.triangulate_refine_and_fair_hole = call
        try:
            return peers.cgal_fill(v, f, loop)
        finally:
            pmp.triangulate_refine_and_fair_hole = whole
    return run


def _error(cut, new_v, new_f) -> float:
    v = np.concatenate([cut.vertices, new_v])
    f = np.concatenate([cut.faces, new_f])
    pv, pf = hole_patch_of(v, f, len(cut.vertices), cut.faces)
    d = surface_distance(pv, pf, cut.truth_vertices, cut.truth_faces, n_samples=10000)
    return float(d.mean * 100.0 / cut.diameter)


def triangulation_row(cut) -> dict[str, float]:
    """The triangulations alone, unrefined and unfaired: CGAL's ``triangulate_hole``
    (``ctri``) and ours (``dp``: the 3D-Delaunay-restricted dynamic program), and whether
    they are the same set of faces (``same``: 1 or 0)."""
    v, f, loop = cut.vertices, cut.faces, cut.loop
    _, ctri, _, _ = accuracy._run_peer(_cgal_step("triangulate_hole"), v, f, loop)
    ours = minimum_weight_triangulation(v, loop, f)
    empty = np.zeros((0, 3))
    same = {tuple(sorted(t)) for t in ctri[len(f):].tolist()} == \
        {tuple(sorted(t)) for t in ours.tolist()}
    return {"tri:ctri": _error(cut, empty, ctri[len(f):]), "tri:dp": _error(cut, empty, ours),
            "same": float(same)}


def hole_row(cut, refinement_only: bool = False, orders=(2, 3)) -> dict[str, float]:
    """The columns of the module docstring for one hole; ``refinement_only``: only CGAL's
    triangulation refined three ways (ctri, cref, ctri+cstyle), each faired by ours;
    ``orders``: the fairing orders (2: bilaplacian, 3: trilaplacian) and CGAL's of each."""
    v, f, loop = cut.vertices, cut.faces, cut.loop
    n, m = len(v), len(f)

    def fair_on(new_v, patch, order, operator="cotan"):
        near = faces_near(f, loop, order - 2, n)  # what conventional_fill fairs on
        return fair(np.vstack([v, new_v]), np.vstack([near, patch]),
                    np.arange(n, n + len(new_v)), order=order, operator=operator)[n:]

    out = {}
    if not refinement_only:
        for peer in [("cgal", "cgal3")[order - 2] for order in orders]:
            cv, cf, _, _ = accuracy._run_peer(peers.PEERS[peer], v, f, loop)
            out[peer] = _error(cut, cv[n:], cf[m:])
        out["n:cgal"] = float(len(cv) - n)
    _, ctri, _, _ = accuracy._run_peer(_cgal_step("triangulate_hole"), v, f, loop)
    rv, rf, _, _ = accuracy._run_peer(_cgal_step("triangulate_and_refine_hole"), v, f, loop)
    tris = {"ctri": ctri[m:]}
    if not refinement_only:
        tris["cdt"] = minimum_weight_triangulation(v, loop, f, search="cdt")
    for order in orders:
        if not refinement_only:
            own = faired_fills(v, f, loop, (order,))[order]
            out[f"fair{order}"] = _error(cut, own[0], own[1])
            out["n:fair"] = float(len(own[0]))
            clamped = faired_fills(v, f, loop, (order,), operator="clamped")[order]
            out[f"clamped{order}"] = _error(cut, clamped[0], clamped[1])
            for operator, label in (("cotan", "fair"), ("clamped", "clamped")):
                cstyle = faired_fills(v, f, loop, (order,), operator=operator,
                                      refinement="cgal")[order]
                out[f"cstyle+{label}{order}"] = _error(cut, cstyle[0], cstyle[1])
        for name, tri in tris.items():
            new_v, patch = refine_patch(v, tri, loop, faces=f, style="liepa")
            out[f"{name}+fair{order}"] = _error(cut, fair_on(new_v, patch, order), patch)
            out[f"n:{name}"] = float(len(new_v))
        new_v, patch = refine_patch(v, ctri[m:], loop, faces=f, style="cgal")
        out[f"ctri+cstyle+fair{order}"] = _error(cut, fair_on(new_v, patch, order), patch)
        out[f"cref+fair{order}"] = _error(cut, fair_on(rv[n:], rf[m:], order), rf[m:])
        if not refinement_only:
            out[f"cref+clamped{order}"] = _error(
                cut, fair_on(rv[n:], rf[m:], order, "clamped"), rf[m:])
    return out


TUNING_SIDE_SETS = ("tuning", "cad_tuning", "smooth_tuning", "curved_scans", "thin_shells")
# the newest holdout set spent as study data: each session's fresh set is run once and stays
# out (the README's newest column) until the next session runs the next one
NEWEST_SPENT_HOLDOUT = 27
SELECTIONS = {"tuning": None, "brain": "brain", "scan": "range_scan"}  # --holes: kind


def _studied(entry: dict) -> bool:
    """A manifest entry this study may look at: the tuning half or a tuning-side set, or a
    spent holdout set 9-27 (never the validation half, nor holdout 28 and later)."""
    split = entry["split"]
    return split in TUNING_SIDE_SETS or (split.startswith("holdout") and split[7:].isdigit()
                                         and 9 <= int(split[7:]) <= NEWEST_SPENT_HOLDOUT)


def _print_ratios(rows, pairs) -> None:
    """Per-hole ratios of two columns over the holes: median, geometric mean, holes better
    / worse by 10 %, worst."""
    print("| ratio | holes | median | geometric mean | better / worse by 10 % | worst |")
    print("|---|---|---|---|---|---|")
    for pair in pairs:
        a, b = pair.split("/")
        r = np.array([row[a] / row[b] for _, row in rows if row[b] > 1e-9])
        specs = [spec for spec, row in rows if row[b] > 1e-9]
        w = int(np.argmax(r))
        print(f"| {a} / {b} | {len(r)} | {np.median(r):.3f} | {np.exp(np.log(r).mean()):.3f} | "
              f"{(r < 1 / 1.1).sum()} / {(r > 1.1).sum()} | {r[w]:.2f} ({specs[w]}) |")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--holes", default=HOLES,
                        help="mesh#hole, comma-separated, or 'tuning' (every tuning hole)")
    parser.add_argument("--ratios", default="", help="column/column pairs, comma-separated")
    parser.add_argument("--out", default=None, help="write the rows as JSON here")
    parser.add_argument("--manifest", default=str(holes_manifest.MANIFEST),
                        help="the tuning half's manifest (default) or a spent holdout set's")
    parser.add_argument("--triangulation-only", action="store_true",
                        help="only the two triangulations, unrefined (ctri, ours)")
    parser.add_argument("--orders", default="2,3",
                        help="fairing orders, comma-separated (2: bilaplacian, 3: trilaplacian)")
    parser.add_argument("--refinement-only", action="store_true",
                        help="only CGAL's triangulation refined three ways (ctri, cref, "
                             "ctri+cstyle), each faired by ours")
    args = parser.parse_args(argv)
    manifest = {e["mesh"]: e for e in holes_manifest.read(Path(args.manifest))["meshes"]}
    specs = args.holes.split(",")
    if args.holes in SELECTIONS:
        kind = SELECTIONS[args.holes]
        specs = [f"{e['mesh']}#{k}" for e in manifest.values() if _studied(e)
                 and kind in (None, e.get("kind")) for k in range(len(e["holes"]))]
    meshes: dict = {}
    rows = []
    for spec in specs:
        name, k = spec.split("#")
        if not _studied(manifest[name]):
            raise SystemExit(f"{name} is in {manifest[name]['split']}: study the tuning side "
                             f"and the spent holdouts 9-{NEWEST_SPENT_HOLDOUT} only")
        mesh = meshes.setdefault(name, vm.load_entry(manifest[name]))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cut = validation._cut(mesh, manifest[name]["holes"][int(k)])
            row = triangulation_row(cut) if args.triangulation_only else \
                hole_row(cut, args.refinement_only,
                                     tuple(int(o) for o in args.orders.split(",")))
        rows.append((spec, row))
        print(spec, " ".join(f"{a} {b:.3f}" for a, b in row.items()), file=sys.stderr,
              flush=True)
    if args.out:
        Path(args.out).write_text(json.dumps(dict(rows), indent=1))
    if args.ratios:
        _print_ratios(rows, args.ratios.split(","))
        return
    cols = [c for c in rows[0][1] if not c.startswith("n:")]
    print("| hole | " + " | ".join(cols) + " |")
    print("|---|" + "---|" * len(cols))
    for spec, row in rows:
        print(f"| {spec} | " + " | ".join(f"{row[c]:.3f}" for c in cols) + " |")


if __name__ == "__main__":
    main()
