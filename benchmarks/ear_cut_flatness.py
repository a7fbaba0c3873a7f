"""The ear-cut triangulation's plane-continuing pieces as a truth-free rule (session 50):
for each hole of tuning-side sets, the loop's greedy ear-cut triangulation
(:func:`surfinpaint.fill.liepa.ear_cutting.ear_cut_triangulation`), how much of it continues
a known face's plane (:func:`surfinpaint.fill.conformal.ear_cut.plane_pieces`, at several
angles), the largest angle between the planes it continues (a crease inside the patch), and
its error against the truth (as ``validation.py`` scores a fill). docs/candidates.md
"Session 50 (helper): ear-cut triangulation where a crease crosses the hole".

    PYTHONPATH=src python benchmarks/ear_cut_flatness.py --sets cad_tuning,holdout9 \
        --kinds cad --out features.jsonl
    python benchmarks/ear_cut_flatness.py --table features.jsonl ... --rows run.json ... \
        [--flat 0.95 --crease 30 --angle 2]

Only tuning-side sets are read: the tuning half of ``holes_manifest.json``, the tuning-side
sets, and the spent holdouts 9 to ``cgal_s0.NEWEST_SPENT_HOLDOUT`` (later ones and the
validation half are refused). The
table joins the features with saved ``validation.py`` rows and scores the rule "write the
ear-cut triangulation where at least ``--flat`` of its area continues a known face's plane
(at ``--angle`` degrees) and two of those planes meet at more than ``--crease`` degrees".
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import cgal_s0  # noqa: E402
import holes_manifest  # noqa: E402
import thin_holes  # noqa: E402
import validation  # noqa: E402

from surfinpaint.errors import FillError  # noqa: E402
from surfinpaint.fill.conformal.ear_cut import (  # noqa: E402
    PIECE_CREASE,
    ear_cut_fill,
    ear_cut_flat,
    faired_off_planes,
    plane_pieces,
    refined_in_planes,
)
from surfinpaint.fill.liepa.fairing import fair as fair_patch  # noqa: E402
from surfinpaint.fill.liepa.refinement import refine_patch  # noqa: E402
from surfinpaint.geometry.metrics import surface_distance  # noqa: E402

HERE = Path(__file__).parent
TUNING_SIDE = (*cgal_s0.TUNING_SIDE_SETS,
               *(f"holdout{i}" for i in range(9, cgal_s0.NEWEST_SPENT_HOLDOUT + 1)))
ANGLES = (1.0, 2.0, 3.0, 5.0, 10.0)  # degrees
SAMPLES = 10000  # validation.py's default
FLAT = 0.9  # the rule's threshold (ConformalOptions.ear_cut_flat) for --refined


def entries(name: str, kinds: set[str] | None) -> list[dict]:
    """The manifest entries of a tuning-side set (``tuning``: the tuning half only), of
    the given kinds (all where None)."""
    if name not in TUNING_SIDE:
        raise SystemExit(f"{name} is not tuning-side study data")
    if name == "tuning":
        manifest = json.loads(Path(holes_manifest.MANIFEST).read_text())
        found = [e for e in manifest["meshes"] if e["split"] == "tuning"
                 and e["mesh"] in holes_manifest.SPLIT["tuning"]]
    else:
        found = json.loads((HERE / f"{name}_manifest.json").read_text())["meshes"]
    return [e for e in found if kinds is None or e["kind"] in kinds]


def _error(cut, new_vertices: np.ndarray, patch: np.ndarray) -> float:
    """A fill's error as ``validation.py`` scores it (% of the hole's diameter)."""
    v = np.vstack([cut.vertices, new_vertices])
    used, back = np.unique(patch, return_inverse=True)
    d = surface_distance(v[used], back.reshape(-1, 3), cut.truth_vertices, cut.truth_faces,
                         n_samples=SAMPLES)
    return d.mean * 100.0 / cut.diameter


def faired_from_ear_cut(cut, ears: np.ndarray) -> dict:
    """Step 2's study: the faired fills (orders 2 and 3) made on the ear-cut triangulation
    refined as the default refines its minimum-weight one (the faired candidates'
    connectivity and S0 then start from the kept corner); their errors."""
    new, patch = refine_patch(cut.vertices, ears, cut.loop, faces=cut.faces)
    out = {}
    n = len(cut.vertices)
    for order in (2, 3):
        placed = new
        if len(new):
            placed = fair_patch(np.vstack([cut.vertices, new]), np.vstack([cut.faces, patch]),
                                np.arange(n, n + len(new)), order=order)[n:]
        out[f"ear_fair{order}"] = _error(cut, placed, patch)
    return out


def refined_features(cut) -> dict:
    """Session 51's study: where the rule fires (``ear_cut_flat`` at :data:`FLAT`), the
    written fill, the ear cut refined within its planes: its error (``ear_refined_error``)
    and new vertex count (``ear_refined_vertices``); nothing elsewhere."""
    made = ear_cut_flat(cut.vertices, cut.faces, cut.loop, FLAT)
    if made is None:
        return {}
    return {"ear_refined_error": _error(cut, made.vertices, made.faces),
            "ear_refined_vertices": len(made.vertices)}


def offplane_features(cut, ears: np.ndarray) -> dict:
    """Session 52's study, on every hole (whatever its flat share): the ear cut refined
    within its planes (:func:`refined_in_planes`; ``ear_inplanes_error``) and the same with
    the vertices off its planes faired (:func:`faired_off_planes`; ``ear_offplane_error``,
    ``ear_offplane_free`` the vertices moved); None where either fails."""
    out = {"ear_inplanes_error": None, "ear_offplane_error": None, "ear_offplane_free": 0}
    try:
        new, patch = refined_in_planes(cut.vertices, cut.faces, cut.loop, ears)
        out["ear_inplanes_error"] = _error(cut, new, patch)
        placed = faired_off_planes(cut.vertices, cut.faces, new, patch)
    except FillError as exc:
        out["offplane_note"] = str(exc)
        return out
    out["ear_offplane_error"] = _error(cut, placed, patch)
    out["ear_offplane_free"] = int((np.abs(placed - new).max(axis=1) > 0).sum()) if len(new) \
        else 0
    return out


def hole_features(cut, faired: bool = False, refined: bool = False,
                  offplane: bool = False) -> dict:
    """The ear-cut patch's pieces at each angle of :data:`ANGLES`, and its error (% of the
    hole's diameter; None where the ear cut leaves a zero-area triangle); with ``faired``
    also :func:`faired_from_ear_cut`'s, with ``refined`` :func:`refined_features`, with
    ``offplane`` :func:`offplane_features`."""
    out = {"loop_edges": len(cut.loop)}
    try:
        fill = ear_cut_fill(cut.vertices, cut.faces, cut.loop)
    except FillError as exc:
        out["ear_error"] = None
        out["note"] = str(exc)
        return out
    tri = fill.faces
    out["ear_error"] = _error(cut, np.zeros((0, 3)), tri)
    if faired:
        out.update(faired_from_ear_cut(cut, tri))
    if refined:
        out.update(refined_features(cut))
    if offplane:
        out.update(offplane_features(cut, tri))
    for a in ANGLES:
        p = plane_pieces(cut.vertices, cut.faces, tri, np.radians(a))
        out[f"flat{a:g}"] = p.flat_fraction()
        out[f"count{a:g}"] = float((p.plane >= 0).mean())
        out[f"crease{a:g}"] = float(np.degrees(p.crease()))
        out[f"planes{a:g}"] = int(len(np.unique(p.plane[p.plane >= 0])))
    return out


def features(sets: list[str], kinds: set[str] | None, out: Path, faired: bool = False,
             refined: bool = False, offplane: bool = False) -> None:
    """Append one JSON line per hole of ``sets`` to ``out``."""
    for name in sets:
        for entry in entries(name, kinds):
            mesh = validation.loaded_or_none(entry)
            if mesh is None:
                continue
            for k, hole in enumerate(entry["holes"]):
                cut = validation._cut(mesh, hole)
                row = {"split": entry["split"] if name == "tuning" else name,
                       "case": entry["mesh"], "hole": k, "kind": entry["kind"],
                       **hole_features(cut, faired, refined, offplane)}
                with out.open("a") as fh:
                    fh.write(json.dumps(row) + "\n")
                print(f"{name} {entry['mesh']} #{k}: ear {row.get('ear_error')}",
                      file=sys.stderr, flush=True)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sets", help="comma-separated tuning-side set names")
    parser.add_argument("--kinds", help="comma-separated mesh kinds (default: all)")
    parser.add_argument("--out", type=Path)
    parser.add_argument("--faired", action="store_true",
                        help="also the faired fills on the ear-cut triangulation (step 2)")
    parser.add_argument("--refined", action="store_true",
                        help="also the written fill, the ear cut refined within its planes, "
                             "where the rule fires (session 51); with --table: score it as "
                             "the rule's fill, and compare it with the bare ear cut")
    parser.add_argument("--offplane", action="store_true",
                        help="also, on every hole, the ear cut refined within its planes and "
                             "with its vertices off the planes faired (session 52)")
    parser.add_argument("--table", nargs="+", help="feature files to join with --rows")
    parser.add_argument("--rows", nargs="+", default=[])
    parser.add_argument("--flat", type=float, nargs="+", default=[0.9, 0.95, 0.99, 1.0])
    parser.add_argument("--crease", type=float, nargs="+", default=[10.0, 20.0, 30.0, 45.0])
    parser.add_argument("--angle", type=float, nargs="+", default=[1.0, 2.0, 5.0])
    parser.add_argument("--between", type=float, nargs="*",
                        help="with --table: session 52's rules, the ear cut refined within its "
                             "planes / faired off them written where these lower bounds ≤ the "
                             "flat share < --high (needs --offplane features)")
    parser.add_argument("--high", type=float, default=FLAT)
    parser.add_argument("--halves", type=Path,
                        help="with --between: a JSON {half: [mesh names]} to score each on")
    parser.add_argument("--list", action="store_true",
                        help="also list the holes of the first thresholds")
    args = parser.parse_args(argv)
    if args.table:
        feats, err = joined(args.table, args.rows, args.refined)
        if args.refined:
            print("\n".join(refined_lines(feats, err)))
        if args.between:
            halves = ({k: set(v) for k, v in json.loads(args.halves.read_text()).items()}
                      if args.halves else None)
            print("\n".join(between_table(feats, err, args.between, args.high, halves)))
            return
        grid = [(f, c, a) for a in args.angle for c in args.crease for f in args.flat]
        print("\n".join(rule_table(feats, err, grid)))
        if args.list:
            print("\n".join(fired_lines(feats, err, *grid[0])))
        return
    kinds = set(args.kinds.split(",")) if args.kinds else None
    features(args.sets.split(","), kinds, args.out, args.faired, args.refined, args.offplane)



# --------------------------------------------------------------------------- the rule's table

EAR = "ear_cut"  # the ear-cut triangulation's column in the joined errors
BARE = "ear_cut_bare"  # the bare ear cut's, where EAR is the refined one (--refined)
# session 52 (--offplane): the ear cut refined within its planes on every hole, and with its
# vertices off the planes faired
INPLANES, OFFPLANE = "ear_inplanes", "ear_offplane"


def joined(feature_files: list[str], row_files: list[str], refined: bool = False
           ) -> tuple[dict, dict]:
    """``(features, err)``: each hole's features by ``(split, case, hole)``, and the errors
    of every method's rows of those holes by ``(method, split, case, hole)`` (later files
    replace earlier ones' rows), with the ear-cut triangulation's as method :data:`EAR`
    (with ``refined``: the refined one's where it was made, the bare one's as
    :data:`BARE`)."""
    feats = {}
    for path in feature_files:
        for line in Path(path).read_text().splitlines():
            f = json.loads(line)
            feats[(f["split"], f["case"], f["hole"])] = f
    err = {}
    for path in row_files:
        for r in thin_holes._jsonl(path):
            key = (r["method"], r["extra"]["split"], r["case"], r["hole"])
            if key[1:] not in feats:
                continue
            err.pop(key, None)
            if r["status"] in thin_holes.FILLED and np.isfinite(r["mean_pct"]):
                err[key] = r["mean_pct"]
    for key, f in feats.items():
        if f.get("ear_error") is not None:
            err[(EAR, *key)] = f["ear_error"]
            err[(BARE, *key)] = f["ear_error"]
        if refined and f.get("ear_refined_error") is not None:
            err[(EAR, *key)] = f["ear_refined_error"]
        for method in (INPLANES, OFFPLANE):
            if f.get(f"{method}_error") is not None:
                err[(method, *key)] = f[f"{method}_error"]
    return feats, err


def refined_lines(feats: dict, err: dict) -> list[str]:
    """The refined ear cut against the bare one on the holes where both were made (the
    rule fired at :data:`FLAT`): per hole ratio, better / worse by 10 %, summed error."""
    keys = sorted(k for k, f in feats.items() if f.get("ear_refined_error") is not None)
    ratio = np.array([max(err[(EAR, *k)], 1e-6) / max(err[(BARE, *k)], 1e-6) for k in keys])
    out = [f"refined against bare on the {len(keys)} holes the rule fires on: better / "
           f"worse by 10 % {(ratio < 1 / 1.1).sum()} / {(ratio > 1.1).sum()}, median ratio "
           f"{np.median(ratio) if len(keys) else float('nan'):.3f}, summed error bare "
           f"{sum(err[(BARE, *k)] for k in keys):.3f} → refined "
           f"{sum(err[(EAR, *k)] for k in keys):.3f} %, new vertices "
           f"{sum(feats[k]['ear_refined_vertices'] for k in keys)}"]
    out += [f"  {k[0]} {k[1]} #{k[2]}: bare {err[(BARE, *k)]:.3g} → refined "
            f"{err[(EAR, *k)]:.3g} %" for k, r in zip(keys, ratio, strict=True)
            if r < 1 / 1.1 or r > 1.1]
    return out


def fires(f: dict, flat: float, crease: float, angle: float) -> bool:
    """The rule: at least ``flat`` of the ear-cut patch's area continues known faces' planes
    (at ``angle`` degrees) and two of those planes meet at more than ``crease`` degrees."""
    return (f.get("ear_error") is not None and f[f"flat{angle:g}"] >= flat
            and f[f"crease{angle:g}"] > crease)


def rule_table(feats: dict, err: dict, grid: list[tuple[float, float, float]]) -> list[str]:
    """Per set of thresholds ``(flat, crease, angle)``: thin_holes' rule counts."""
    keys = sorted(k for k in feats if ("conformal", *k) in err)
    out = [f"{len(keys)} holes on {len(thin_holes._by_mesh(keys))} meshes with the "
           "default's row",
           "| flat ≥ | crease > ° | angle ° | fires | written | better / worse by 10 % | "
           "summed error there % (default → rule) | above 1.5× better faired (default → "
           "rule) | meshes won |",
           "|---|---|---|---|---|---|---|---|---|"]
    for flat, crease, angle in grid:
        flagged = {k for k in keys if fires(feats[k], flat, crease, angle)}
        out.append(f"| {flat:g} | {crease:g} | {angle:g} | {len(flagged)} | "
                   + _rule_cells(err, keys, EAR, flagged))
    return out


def _rule_cells(err: dict, keys: list, alt: str, flagged: set) -> str:
    """A rule's table cells: holes written, better / worse by 10 %, summed error there
    (default → rule), holes above 1.5× the better faired fill, meshes won."""
    c = thin_holes.rule_counts(err, keys, alt, flagged)
    written = [k for k in flagged if (alt, *k) in err]
    before, after = (sum(err[(m, *k)] for k in written) for m in ("conformal", alt))
    return (f"{c['changed']} | {c['better']} / {c['worse']} | {before:.2f} → {after:.2f} | "
            f"{c['above'][0]} → {c['above'][1]} | {c['won'][0]} → {c['won'][1]} of "
            f"{c['won'][2]} |")


def between_table(feats: dict, err: dict, lows: list[float], high: float,
                  halves: dict[str, set] | None = None) -> list[str]:
    """Session 52's rules: ``alt`` (the ear cut refined within its planes, or with its
    vertices off the planes faired) written where ``low`` ≤ the flat share (2°) < ``high``
    and a crease > 20° crosses the patch, the default elsewhere; per half of the meshes
    (``halves``: name → mesh names) and on all."""
    groups = {"all": None, **(halves or {})}
    out = ["| meshes | written | flat share | fires | better / worse by 10 % | summed error "
           "there % (default → rule) | above 1.5× better faired (default → rule) | "
           "meshes won |", "|---|---|---|---|---|---|---|---|"]
    for name, names in groups.items():
        keys = sorted(k for k in feats if ("conformal", *k) in err
                      and (names is None or k[1] in names))
        for alt in (INPLANES, OFFPLANE):
            for low in lows:
                flagged = {k for k in keys if fires(feats[k], low, PIECE_CREASE, 2.0)
                           and feats[k]["flat2"] < high}
                out.append(f"| {name} ({len(thin_holes._by_mesh(keys))}) | {alt} | [{low:g}, "
                           f"{high:g}) | " + _rule_cells(err, keys, alt, flagged))
    return out


def fired_lines(feats: dict, err: dict, flat: float, crease: float, angle: float
                ) -> list[str]:
    """The holes the rule fires on, with the default's and the ear cut's errors."""
    out = ["| hole | loop edges | flat | crease ° | default % | ear cut % | ratio |",
           "|---|---|---|---|---|---|---|"]
    for k in sorted(feats):
        f = feats[k]
        if ("conformal", *k) not in err or not fires(f, flat, crease, angle):
            continue
        d, e = err[("conformal", *k)], err[(EAR, *k)]
        out.append(f"| {k[0]} {k[1]} #{k[2]} | {f['loop_edges']} | {f[f'flat{angle:g}']:.3f} "
                   f"| {f[f'crease{angle:g}']:.1f} | {d:.3g} | {e:.3g} | "
                   f"{max(e, 1e-6) / max(d, 1e-6):.3g} |")
    return out


if __name__ == "__main__":
    main()
