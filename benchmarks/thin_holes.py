"""Holes across thin parts (session 48): label each planned hole of tuning-side manifests by
the truth-based test and record the truth-free loop measure (docs/selfcheck.md "Session 48
(helper): holes across thin parts").

Each hole is cut as ``validation.py`` cuts it (no fill). Truth-based (it looks at the removed
patch): the hole reaches across a thin part when some removed vertex has a normal opposed to
the centre's (dot < −0.5) and lies behind the centre's tangent plane (docs/validation.md
"Holdout set 24 (session 47)"). The centre's normal is the mean of the vertex normals of the
centre and its one-ring. Recorded per hole: ``thin`` (that test), ``far_depth_h`` (the
nearest such removed vertex's depth behind the centre's plane, in mean edge lengths h: the
part's thickness where the hole crosses it), ``through_h`` (the same over every vertex of the
mesh within 1.5 h of the centre's normal line: the part's thickness at the centre, ``null``
where nothing faces back), and the truth-free measures of
:func:`loop_sheets.loop_sheets` (``opposed``, ``gap``) and session 12's
ring ``wrap`` (:func:`thin_parts.wrap`).

    PYTHONPATH=src python benchmarks/thin_holes.py --sets tuning,cad_tuning --out labels.jsonl

``tuning`` is the tuning half of ``holes_manifest.json`` (never its validation half); other
names are ``benchmarks/<name>_manifest.json``. Holdouts 24 and later are refused.

    python benchmarks/thin_holes.py --table labels.jsonl [more.jsonl ...] \
        --rows run.json [run2.jsonl ...] [--opposed 0.5 --gap 0.3]

joins the labels with saved ``validation.py`` rows (only rows of labelled holes, or of range
scans of a tuning-side set, are read: a scan is one view and has no far side) and prints, per
class, the default against CGAL and the better faired fill, the closest tool, what was
written, the meshes lost; the truth-free test's confusion table; and, for each fill written
instead where the test fires, the rule's count of holes better / worse by 10 %, holes above
1.5× the better faired fill and meshes won (the default most accurate of all peers).
"""

from __future__ import annotations

import argparse
import collections
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import accuracy  # noqa: E402
import holes_manifest  # noqa: E402
import thin_parts  # noqa: E402
import validation  # noqa: E402
from loop_sheets import OPPOSED_DOT, facing_away, loop_sheets  # noqa: E402

from surfinpaint.geometry.mesh import faces_near, vertex_normals  # noqa: E402

HERE = Path(__file__).parent
# the through-thickness probe: vertices within this many h of the centre's normal line
THROUGH_H = 1.5
SPENT = 23  # the newest spent holdout: later ones are not study data
TUNING_SIDE = ("tuning", "cad_tuning", "smooth_tuning", "curved_scans", "thin_shells",
               *(f"holdout{i}" for i in range(9, SPENT + 1)))
PEERS = ("cgal", "cgal3", "meshlib", "pymeshlab", "pymeshfix")
FILLED = ("ok", "selected", "fallback")
# fills a rule could write instead where the truth-free test fires (triangulation: the
# loop's alone; conformal_rings3: the λ-H fill of a 3-ring patch; pymeshfix: a peer's,
# for reference only)
INSTEAD = ("fair_sfauto", "fair3", "fair1", "triangulation", "conformal_raw", "conformal_rings3",
           "pymeshfix")


def entries(name: str) -> list[dict]:
    """The manifest entries of a tuning-side set (``tuning``: the tuning half only)."""
    if name.startswith("holdout") and int(name[7:] or 1) > SPENT:
        raise SystemExit(f"{name} is not spent: not study data")
    if name == "tuning":
        manifest = json.loads(Path(holes_manifest.MANIFEST).read_text())
        return [e for e in manifest["meshes"] if e["split"] == "tuning"
                and e["mesh"] in holes_manifest.SPLIT["tuning"]]
    return json.loads((HERE / f"{name}_manifest.json").read_text())["meshes"]


def truth_label(vertices, faces, normals, cut, h: float) -> dict:
    """The truth-based label of one cut hole (it reads the removed vertices)."""
    hole = cut.holes[0]
    c = hole.center
    ring = np.unique(faces_near(faces, np.array([c]), 0, len(vertices)))
    nc = normals[ring].sum(axis=0)
    nc /= np.linalg.norm(nc)
    removed = np.setdiff1d(np.arange(len(vertices)), cut.kept)
    depth = (vertices - vertices[c]) @ nc  # < 0: behind the centre's plane
    back = (normals @ nc < OPPOSED_DOT) & (depth < 0)
    far = removed[back[removed]]
    lateral = np.linalg.norm(vertices - vertices[c] - depth[:, None] * nc, axis=1)
    through = back & (lateral <= THROUGH_H * h)
    return {"thin": bool(len(far)), "far": int(len(far)), "removed": int(len(removed)),
            "far_depth_h": float(-depth[far].max() / h) if len(far) else None,
            "through_h": float(-depth[through].max() / h) if through.any() else None}


def loop_geometry(cut, normals) -> dict:
    """The loop's points and its normals on the known faces, and the removed patch's points
    and normals (to try other tests on a saved file)."""
    near = faces_near(cut.faces, cut.loop, 0, len(cut.vertices))
    hole = cut.holes[0]
    return {"points": cut.vertices[cut.loop].round(7).tolist(),
            "normals": vertex_normals(cut.vertices, near)[cut.loop].round(5).tolist(),
            "patch": hole.truth_vertices.round(7).tolist(),
            "patch_normals": normals[hole.truth_ids].round(5).tolist()}


def label_set(name: str, out, loops=None) -> None:
    for entry in entries(name):
        mesh = validation.loaded_or_none(entry)
        if mesh is not None:
            label_set_entry(entry, mesh, out, loops)
            print(f"{name} {entry['mesh']}: done", file=sys.stderr, flush=True)


def label_set_entry(entry: dict, mesh, out, loops=None) -> None:
    """Label the holes of one manifest entry, its mesh loaded."""
    v, f = mesh.vertices, mesh.faces
    normals = vertex_normals(v, f)
    h = entry["h"]
    for k, hole in enumerate(entry["holes"]):
        cut = validation._cut(mesh, hole)
        sheets = loop_sheets(cut.vertices, cut.faces, cut.loop)
        row = {"split": entry["split"], "case": entry["mesh"], "hole": k,
               "kind": entry["kind"], "radius_h": hole["radius_h"],
               "edges": len(cut.loop), "diameter_h": cut.diameter / h,
               **truth_label(v, f, normals, cut, h),
               "opposed": sheets.opposed, "gap": sheets.gap,
               "wrap": thin_parts.wrap(cut.vertices, cut.faces, cut.loop)}
        out.write(json.dumps(row) + "\n")
        out.flush()
        if loops is not None:
            loops.write(json.dumps({**{k: row[k] for k in ("split", "case", "hole")},
                                    "h": h, **loop_geometry(cut, normals)}) + "\n")


# --------------------------------------------------------------------------- tables


def _jsonl(path: str) -> list[dict]:
    text = Path(path).read_text()
    return json.loads(text)["rows"] if path.endswith(".json") else \
        [json.loads(line) for line in text.splitlines() if line.strip()]


def _med(x) -> float:
    return float(np.median(x)) if len(x) else float("nan")


def joined(label_files: list[str], row_files: list[str]):
    """({hole: label}, {(method, *hole): error %}, {hole: the default's row}); scans of a
    tuning-side set that were not labelled are labelled not thin and not flagged."""
    labels = {}
    for path in label_files:
        for r in _jsonl(path):
            labels[(r["split"], r["case"], r["hole"])] = r
    err, default = {}, {}
    for path in row_files:
        for r in _jsonl(path):
            key = (r["extra"]["split"], r["case"], r["hole"])
            if key[0] not in TUNING_SIDE:
                continue  # another half's rows are dropped unread
            if key not in labels and r["extra"]["kind"] == "range_scan":
                labels[key] = {"thin": False, "opposed": 0.0, "gap": float("inf"),
                               "kind": "range_scan", "far_depth_h": None, "scan": True}
            if key not in labels:
                continue
            if r["status"] in FILLED and np.isfinite(r["mean_pct"]):
                err[(r["method"], *key)] = r["mean_pct"]
            if r["method"] == "conformal":
                default[key] = r
    labels = {k: v for k, v in labels.items() if ("conformal", *k) in err}
    return labels, err, default


def written(key, err: dict, row: dict) -> str:
    """What the default wrote: λ-H kept, fair2, fair3, plane, ear cut or fallback."""
    if row["status"] == "fallback":
        return "fallback"
    if row["note"].startswith("plane test"):
        return "plane"
    if row["note"].startswith(accuracy.EAR_CUT_NOTE):
        return "ear cut"
    if row["note"].startswith("self-check kept"):
        mine = err[("conformal", *key)]
        for method, name in (("fair_sfauto", "fair2"), ("fair", "fair2"), ("fair3", "fair3")):
            if abs(err.get((method, *key), np.inf) - mine) < 1e-9:
                return name
        return "faired"
    return "λ-H kept"


def _better_faired(err: dict, key) -> float:
    return min((err[(m, *key)] for m in ("fair", "fair3") if (m, *key) in err),
               default=float("nan"))


def _by_mesh(keys) -> dict:
    meshes = collections.defaultdict(list)
    for k in keys:
        meshes[k[:2]].append(k)
    return meshes


def meshes_won(err: dict, meshes: dict, method_of) -> set:
    """Meshes where the written fill's median over the mesh's holes is at most every peer's."""
    won = set()
    for mesh, keys in meshes.items():
        mine = _med([err[(method_of(k), *k)] for k in keys])
        if all(not mine > _med([err[(p, *k)] for k in keys if (p, *k) in err])
               for p in PEERS):
            won.add(mesh)
    return won


def class_lines(name: str, keys: list, err: dict, default: dict) -> list[str]:
    """The default on one class of holes."""
    over_cgal = [err[("conformal", *k)] / err[("cgal", *k)] for k in keys
                 if err.get(("cgal", *k), 0) > 1e-6]
    over_faired = [err[("conformal", *k)] / _better_faired(err, k) for k in keys
                   if _better_faired(err, k) > 1e-6]
    closest = collections.Counter(
        min(("conformal", *PEERS), key=lambda m: err.get((m, *k), np.inf)) for k in keys)
    each = {m: [err[(m, *k)] / err[("cgal", *k)] for k in keys
                if (m, *k) in err and err.get(("cgal", *k), 0) > 1e-6]
            for m in ("conformal", *INSTEAD[:-1], *PEERS)}
    what = collections.Counter(written(k, err, default[k]) for k in keys)
    return [f"### {name}: {len(keys)} holes",
            f"- default / CGAL, per-hole median: {_med(over_cgal):.3f}; default / better "
            f"faired fill: median {_med(over_faired):.3f}, above 1.5×: "
            f"{sum(x > 1.5 for x in over_faired)}; the default's median error "
            f"{_med([err[('conformal', *k)] for k in keys]):.3f} %",
            "- per-hole median / CGAL (over n holes where not all): " + ", ".join(
                f"{m} {_med(x):.3f}" + (f" (n {len(x)})" if len(x) < len(over_cgal) else "")
                for m, x in each.items() if x),
            "- closest of the default and the peers: " + ", ".join(
                f"{m} {n}" for m, n in closest.most_common()),
            "- written: " + ", ".join(f"{w} {n}" for w, n in what.most_common())]


def rule_counts(err: dict, keys: list, alt: str, flagged: set) -> dict:
    """What writing ``alt`` on the ``flagged`` holes (the default elsewhere, and where
    ``alt`` has no row) changes: holes changed, better / worse by 10 %, the median ratio,
    holes above 1.5× the better faired fill (default, rule), meshes won (default, rule, of
    all) and per set ``{set: [won before, after, meshes]}``."""
    def method_of(k):
        return alt if k in flagged and (alt, *k) in err else "conformal"
    meshes = _by_mesh(keys)
    changed = [k for k in keys if method_of(k) == alt]
    ratio = [max(err[(alt, *k)], 1e-6) / max(err[("conformal", *k)], 1e-6) for k in changed]
    above = [sum(err[(f(k), *k)] / _better_faired(err, k) > 1.5 for k in keys
                 if _better_faired(err, k) > 1e-6)
             for f in (lambda k: "conformal", method_of)]
    before = meshes_won(err, meshes, lambda k: "conformal")
    after = meshes_won(err, meshes, method_of)
    sets = collections.defaultdict(lambda: [0, 0, 0])
    for mesh in meshes:
        sets[mesh[0]][0] += mesh in before
        sets[mesh[0]][1] += mesh in after
        sets[mesh[0]][2] += 1
    return {"changed": len(changed), "better": sum(x < 1 / 1.1 for x in ratio),
            "worse": sum(x > 1.1 for x in ratio), "median": _med(ratio), "above": above,
            "won": (len(before), len(after), len(meshes)), "sets": dict(sets)}


def rule_lines(labels: dict, err: dict, flagged: set) -> list[str]:
    """Each fill of ``INSTEAD`` written where the test fires, against the default."""
    keys = sorted(labels)
    lines = ["| written instead where the test fires | holes changed | better by 10 % | "
             "worse by 10 % | median ratio | holes above 1.5× (default → rule) | meshes won "
             "(default → rule) | sets that change (won before → after / meshes) |",
             "|---|---|---|---|---|---|---|---|"]
    for alt in INSTEAD:
        c = rule_counts(err, keys, alt, flagged)
        moved = "; ".join(f"{s} {a} → {b} / {n}" for s, (a, b, n) in c["sets"].items()
                          if a != b)
        lines.append(f"| {alt} | {c['changed']} | {c['better']} | {c['worse']} | "
                     f"{c['median']:.3f} | {c['above'][0]} → {c['above'][1]} | "
                     f"{c['won'][0]} → {c['won'][1]} / {c['won'][2]} | {moved or 'none'} |")
    return lines


def hole_lines(keys: list, labels: dict, err: dict, default: dict, flagged: set) -> list[str]:
    """One row per hole: its label, the test, what was written and the errors (%)."""
    lines = ["| hole | r (h) | thick (h) | opposed, gap | test | written | default | fair2 | "
             "fair3 | λ-H raw | best peer |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for k in keys:
        r = labels[k]
        peer = min(PEERS, key=lambda p: err.get((p, *k), np.inf))
        depth = "—" if r["far_depth_h"] is None else f"{r['far_depth_h']:.1f}"
        cells = [f"{err[(m, *k)]:.3g}" if (m, *k) in err else "—"
                 for m in ("conformal", "fair_sfauto", "fair3", "conformal_raw")]
        lines.append(f"| {k[0]} {k[1]} #{k[2]} | {r['radius_h']} | {depth} | "
                     f"{r['opposed']:.2f}, {r['gap']:.2f} | {'fires' if k in flagged else '—'} "
                     f"| {written(k, err, default[k])} | " + " | ".join(cells) +
                     f" | {peer} {err.get((peer, *k), np.nan):.3g} |")
    return lines


def wrapping(loop_files: list[str]) -> dict:
    """{hole: whether its removed patch (with its border ring) holds two vertices that face
    away from each other}: the symmetric truth label, not tied to the centre's normal."""
    out = {}
    for path in loop_files:
        for r in _jsonl(path):
            pairs = facing_away(np.asarray(r["patch"]), np.asarray(r["patch_normals"]))
            out[(r["split"], r["case"], r["hole"])] = bool(pairs.any())
    return out


# (opposed at least, gap at most): the truth-free test's variants in the confusion table
VARIANTS = ((1e-9, np.inf), (0.5, np.inf), (0.5, 0.3), (0.75, 0.2))


def firing(labels: dict, opposed: float, gap: float) -> set:
    """The holes where the truth-free test fires."""
    return {k for k, r in labels.items() if r["opposed"] >= opposed and r["gap"] <= gap}


def confusion(labels: dict, truths: dict) -> list[str]:
    """Each variant of the test against each truth label: fires / silent on the holes the
    label says yes, and on those it says no."""
    lines = ["| test (opposed ≥, gap ≤) | label | yes: fires | yes: silent | no: fires | "
             "no: silent |", "|---|---|---|---|---|---|"]
    for opposed, gap in VARIANTS:
        fires = firing(labels, opposed, gap)
        for name, truth in truths.items():
            yes = [k for k in labels if truth(k)]
            no = [k for k in labels if not truth(k)]
            lines.append(f"| {opposed:.2g}, {gap:.2g} | {name} | "
                         f"{sum(k in fires for k in yes)} | {sum(k not in fires for k in yes)} | "
                         f"{sum(k in fires for k in no)} | {sum(k not in fires for k in no)} |")
    return lines


def tables(label_files: list[str], row_files: list[str], opposed: float, gap: float,
           loop_files: list[str] = ()) -> str:
    labels, err, default = joined(label_files, row_files)
    thin = [k for k in sorted(labels) if labels[k]["thin"]]
    rest = [k for k in sorted(labels) if not labels[k]["thin"]]
    flagged = firing(labels, opposed, gap)
    depth = [labels[k]["far_depth_h"] for k in thin]
    lines = [f"{len(labels)} holes ({sum('scan' in r for r in labels.values())} range-scan "
             f"holes not cut, counted not thin), {len(thin)} across a thin part (the part "
             f"{_med(depth):.1f} h thick there, median; {min(depth, default=np.nan):.1f}–"
             f"{max(depth, default=np.nan):.1f} h)", ""]
    lines += class_lines("across a thin part", thin, err, default) + [""]
    lines += class_lines("not", rest, err, default) + [""]
    above = [k for k in labels if _better_faired(err, k) > 1e-6
             and err[("conformal", *k)] / _better_faired(err, k) > 1.5]
    meshes = _by_mesh(labels)
    lost = [m for m in meshes if m not in meshes_won(err, meshes, lambda k: "conformal")]
    lost_thin = sum(any(labels[k]["thin"] for k in meshes[m]) for m in lost)
    lines += [f"holes above 1.5× the better faired fill: {len(above)}, across a thin part "
              f"{sum(labels[k]['thin'] for k in above)}; meshes lost: {len(lost)}, with a "
              f"hole across a thin part {lost_thin}", ""]
    truths = {"across a thin part": lambda k: labels[k]["thin"]}
    if loop_files:
        wraps = wrapping(loop_files)
        truths["the patch wraps over a part"] = lambda k: wraps.get(k, False)
        lines += [f"(the symmetric label: {sum(k in wraps for k in labels)} holes cut; scans "
                  "not cut count as not wrapping)", ""]
    lines += confusion(labels, truths)
    lines += ["", f"rules below: the test with opposed ≥ {opposed}, gap ≤ {gap}", ""]
    listed = sorted(set(thin) | flagged)
    return "\n".join(lines + [""] + rule_lines(labels, err, flagged) + [""] +
                     hole_lines(listed, labels, err, default, flagged)) + "\n"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--table", nargs="+", default=None, help="label files to tabulate")
    parser.add_argument("--rows", nargs="+", default=[], help="validation.py rows")
    parser.add_argument("--loops", nargs="+", default=[], help="labelling: also write each "
                        "loop's and removed patch's points and normals to this file; with "
                        "--table: those files, for the symmetric label")
    parser.add_argument("--opposed", type=float, default=0.5)
    parser.add_argument("--gap", type=float, default=0.3)
    parser.add_argument("--sets", help="comma-separated set names")
    parser.add_argument("--out")

    args = parser.parse_args(argv)
    if args.table:
        print(tables(args.table, args.rows, args.opposed, args.gap, args.loops))
        return
    with open(args.out, "a") as out, open(args.loops[0] if args.loops else "/dev/null",
                                          "a") as loops:
        for name in args.sets.split(","):
            label_set(name, out, loops if args.loops else None)


if __name__ == "__main__":
    main()
