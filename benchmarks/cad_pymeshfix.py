"""CAD holes PyMeshFix fills closer (session 49): from saved ``validation.py`` rows of
tuning-side CAD meshes, each hole's default and PyMeshFix errors, the holes where PyMeshFix
is at least 1.2× closer, what the default wrote there and the hole's features, and the meshes
lost to PyMeshFix (docs/candidates.md "Session 49 (helper): CAD holes PyMeshFix fills
closer").

    python benchmarks/cad_pymeshfix.py --rows run.json [more.json ...] [--instead triangulation]

Only rows of ``kind == "cad"`` meshes of a tuning-side set are read (the tuning half, the
tuning-side sets, spent holdouts 9-27); every other row is dropped unread. ``--instead M``
also scores a rule: column ``M`` written wherever ``--flag`` (a JSON list of
``[split, case, hole]``) names the hole, the default elsewhere.
"""

from __future__ import annotations

import argparse
import collections
import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import cgal_s0  # noqa: E402
import ear_cut_flatness  # noqa: E402
import peers  # noqa: E402
import thin_holes  # noqa: E402
import validation  # noqa: E402

from surfinpaint.fill.conformal.candidates import Candidates  # noqa: E402
from surfinpaint.fill.conformal.options import ConformalOptions  # noqa: E402
from surfinpaint.fill.liepa.baseline import conventional_fill, smoothing_decision  # noqa: E402
from surfinpaint.fill.selfcheck import hidden_ring_scores  # noqa: E402

FILLED, PEERS, written = thin_holes.FILLED, thin_holes.PEERS, thin_holes.written
_better_faired, _by_mesh, _jsonl = thin_holes._better_faired, thin_holes._by_mesh, thin_holes._jsonl
_med = thin_holes._med
HERE = Path(__file__).parent
SPENT = cgal_s0.NEWEST_SPENT_HOLDOUT
TUNING_SIDE = ("tuning", "cad_tuning", *(f"holdout{i}" for i in range(9, SPENT + 1)))
CLOSER = 1.2  # PyMeshFix "wins" a hole when the default's error is at least this × its own


def cad_entries(name: str) -> list[dict]:
    """The CAD manifest entries of a tuning-side set (``tuning``: the tuning half only)."""
    if name not in TUNING_SIDE:
        raise SystemExit(f"{name} is not tuning-side study data")
    return ear_cut_flatness.entries(name, {"cad"})


class _Patch:
    """A peer's fill as the self-check's tests take a candidate: new vertices, and faces
    over the mesh's vertices then the new ones."""

    def __init__(self, made):
        self.vertices, self.faces = np.asarray(made[0], float), np.asarray(made[1], np.int64)


def _compacted(fill):
    """``fill`` run on the vertices the faces use only (a test hole's hidden vertices stay in
    the array, and MeshFix drops unused vertices); its new faces mapped back."""
    def run(vertices, faces, loop):
        used = np.unique(faces)
        index = np.full(len(vertices), -1, np.int64)
        index[used] = np.arange(len(used))
        new_v, new_f = fill(vertices[used], index[faces], index[loop])
        back = np.concatenate([used, len(vertices) + np.arange(len(new_v))])
        return new_v, back[new_f]
    return run


def _with_others(fills):
    """The self-check's candidates of a test hole, and PyMeshFix's and the bare
    triangulation's fills of it."""
    def fill(vertices, faces, loop):
        out = dict(fills(vertices, faces, loop))
        for name, make in (("pymeshfix", _compacted(peers.pymeshfix_fill)),
                           ("pymeshfix_bare", _compacted(peers.pymeshfix_bare_fill)),
                           ("triangulation", lambda v, f, lp: conventional_fill(
                               v, f, lp, refine=False, fair=False))):
            try:
                out[name] = _Patch(make(vertices, faces, loop))
            except Exception as exc:  # noqa: BLE001 - a peer's failure scores infinite
                out[name] = exc
        return out
    return fill


def hidden_scores(entry: dict, mesh) -> list[dict]:
    """Each hole's hidden-ring test scores (the default's options) of the self-check's
    candidates, PyMeshFix's fill and the bare triangulation: truth-free."""
    out = []
    for k, hole in enumerate(entry["holes"]):
        cut = validation._cut(mesh, hole)
        v, f, loop = cut.vertices, cut.faces, cut.loop
        options = ConformalOptions()
        smoothing = smoothing_decision(v, f, loop, options.fair_smoothing)
        if smoothing is not None:
            options = replace(options, fair_smoothing=smoothing.length)
        candidates = Candidates.for_hole(v, f, loop, options)
        scores = hidden_ring_scores(v, f, loop, _with_others(candidates.for_tests()),
                                    hide_rings=options.hide_rings,
                                    patch_rings=options.rings_in_patch)
        out.append({"split": entry["split"], "case": entry["mesh"], "hole": k,
                    "crossed": candidates.crossed, "scores": scores})
    return out


def cad_rows(row_files: list[str]):
    """({(method, split, case, hole): error %}, {hole: the default's row},
    {(method, hole): row}); a later file's row of the same hole and method replaces an
    earlier one (a rerun)."""
    err, default, rows = {}, {}, {}
    for path in row_files:
        for r in _jsonl(path):
            key = (r["extra"]["split"], r["case"], r["hole"])
            if key[0] not in TUNING_SIDE or r["extra"]["kind"] != "cad":
                continue  # not study data, or not a CAD part: dropped unread
            rows[(r["method"], *key)] = r
            err.pop((r["method"], *key), None)
            if r["status"] in FILLED and np.isfinite(r["mean_pct"]):
                err[(r["method"], *key)] = r["mean_pct"]
            if r["method"] == "conformal":
                default[key] = r
    default = {k: v for k, v in default.items()
               if ("conformal", *k) in err and ("pymeshfix", *k) in err}
    return err, default, rows


def features(row: dict) -> str:
    """The planner's labels of a hole: on a sharp edge or corner, near a border."""
    x = row["extra"]
    return ", ".join(n for n, on in (("feature", x.get("on_feature")),
                                     ("border", x.get("near_border"))) if on) or "—"


def hole_table(err: dict, default: dict, rows: dict, keys: list,
               ears: dict | None = None) -> list[str]:
    """One row per hole PyMeshFix fills at least CLOSER× closer; with ``ears`` (the
    features of ``ear_cut_flatness.py --offplane`` by hole) the ear cut's columns instead of
    the new vertex counts: its flat share (2°), and its error bare, refined within its planes
    and with its vertices off the planes faired."""
    if ears is not None:
        return _ear_table(err, default, keys, ears)
    lines = ["| hole | r (h) | loop edges | features | written | default % | PyMeshFix % | "
             "ratio | its triangulation alone % | best faired % | new vertices (default, "
             "PyMeshFix) |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for k in keys:
        d, p = default[k], rows[("pymeshfix", *k)]
        lines.append(
            f"| {k[0]} {k[1]} #{k[2]} | {d['radius_h']:g} | {d['boundary_edges']} | "
            f"{features(d)} | {written(k, err, d)} | {err[('conformal', *k)]:.3g} | "
            f"{err[('pymeshfix', *k)]:.3g} | "
            f"{err[('conformal', *k)] / max(err[('pymeshfix', *k)], 1e-9):.2f} | "
            f"{err.get(('pymeshfix_bare', *k), np.nan):.3g} | {_better_faired(err, k):.3g} | "
            f"{d['new_vertices']}, {p['new_vertices']} |")
    return lines


def _ear_table(err: dict, default: dict, keys: list, ears: dict) -> list[str]:
    """:func:`hole_table` with the ear cut's columns (session 52)."""
    def cell(x):
        return "—" if x is None else f"{x:.3g}"
    lines = ["| hole | loop edges | written | default % | PyMeshFix % | ratio | flat share | "
             "crease ° | ear cut alone % | refined in planes % | faired off planes % | best "
             "faired % |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for k in keys:
        d, f = default[k], ears.get(k, {})
        lines.append(
            f"| {k[0]} {k[1]} #{k[2]} | {d['boundary_edges']} | {written(k, err, d)} | "
            f"{err[('conformal', *k)]:.3g} | {err[('pymeshfix', *k)]:.3g} | "
            f"{err[('conformal', *k)] / max(err[('pymeshfix', *k)], 1e-9):.2f} | "
            f"{cell(f.get('flat2'))} | {cell(f.get('crease2'))} | {cell(f.get('ear_error'))} | "
            f"{cell(f.get('ear_inplanes_error'))} | {cell(f.get('ear_offplane_error'))} | "
            f"{_better_faired(err, k):.3g} |")
    return lines


def counts(name: str, keys: list, err: dict, default: dict) -> str:
    """How often a class of holes is written each way and has each feature."""
    what = collections.Counter(written(k, err, default[k]) for k in keys)
    feat = collections.Counter(features(default[k]) for k in keys)
    return (f"- {name}: {len(keys)} holes; written " +
            ", ".join(f"{w} {n}" for w, n in what.most_common()) + "; features " +
            ", ".join(f"{w} {n}" for w, n in feat.most_common()) +
            f"; loop edges median {_med([default[k]['boundary_edges'] for k in keys]):.0f}")


def lost_meshes(err: dict, keys: list) -> list[str]:
    """Meshes whose default median is above PyMeshFix's (and whether the default is still
    the most accurate of all peers: it cannot be)."""
    lines = []
    for mesh, ks in sorted(_by_mesh(keys).items()):
        mine = _med([err[("conformal", *k)] for k in ks])
        theirs = _med([err[("pymeshfix", *k)] for k in ks])
        best = min(PEERS, key=lambda p: _med([err[(p, *k)] for k in ks if (p, *k) in err]))
        if mine > theirs:
            lines.append(f"- {mesh[0]} {mesh[1]}: default {mine:.3g} %, PyMeshFix "
                         f"{theirs:.3g} % (best peer {best})")
    return lines


def rule(err: dict, keys: list, alt: str, flagged: set) -> list[str]:
    """``alt`` written on the flagged holes, the default elsewhere, per set."""
    c = thin_holes.rule_counts(err, keys, alt, flagged)
    return [f"- {alt} on {c['changed']} holes: better by 10 % {c['better']}, worse by 10 % "
            f"{c['worse']}, median ratio {c['median']:.3f}; holes above 1.5× the better "
            f"faired fill {c['above'][0]} → {c['above'][1]}; meshes most accurate of all "
            f"peers {c['won'][0]} → {c['won'][1]} / {c['won'][2]}",
            "- sets that change (won before → after / meshes): " + ("; ".join(
                f"{s} {a} → {b} / {n}" for s, (a, b, n) in sorted(c["sets"].items())
                if a != b) or "none")]


def flagged_by_scores(score_files: list[str], fill: str, ratio: float) -> set:
    """Holes whose hidden-ring score of ``fill`` is below ``ratio`` × the best of the
    self-check's candidates' (fair2, fair3, the λ-H fill): a truth-free rule."""
    out = set()
    for path in score_files:
        for r in _jsonl(path):
            s = r["scores"]
            ours = min(s.get(m, np.inf) for m in ("fair2", "fair3", "conformal"))
            if s.get(fill, np.inf) < ratio * ours:
                out.add((r["split"], r["case"], r["hole"]))
    return out


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rows", nargs="+", default=[])
    ap.add_argument("--instead", nargs="*", default=[])
    ap.add_argument("--flag", help="JSON list of [split, case, hole] the rule fires on")
    ap.add_argument("--hidden", help="comma-separated sets: write each CAD hole's hidden-ring "
                    "scores to --out (jsonl) instead of the tables")
    ap.add_argument("--out")
    ap.add_argument("--scores", nargs="*", default=[],
                    help="--hidden's files: --instead fires where the fill's hidden-ring "
                    "score is below --ratio × the best of fair2, fair3 and the λ-H fill")
    ap.add_argument("--ratio", type=float, nargs="*", default=[1.0])
    ap.add_argument("--ears", nargs="*", default=[],
                    help="ear_cut_flatness.py --offplane feature files: the table's ear-cut "
                    "columns (session 52)")
    args = ap.parse_args(argv)
    if args.hidden:
        with open(args.out, "a") as fh:
            for name in args.hidden.split(","):
                for entry in cad_entries(name):
                    mesh = validation.loaded_or_none(entry)
                    if mesh is None:
                        continue
                    for r in hidden_scores(entry, mesh):
                        fh.write(json.dumps(r) + "\n")
                        fh.flush()
                    print(f"{name} {entry['mesh']}: done", file=sys.stderr, flush=True)
        return
    err, default, rows = cad_rows(args.rows)
    keys = sorted(default)
    won = [k for k in keys
           if err[("conformal", *k)] >= CLOSER * max(err[("pymeshfix", *k)], 1e-9)]
    ratio = [err[("conformal", *k)] / max(err[("pymeshfix", *k)], 1e-9) for k in keys]
    print(f"{len(keys)} CAD holes on {len(_by_mesh(keys))} meshes; default / PyMeshFix "
          f"median {_med(ratio):.3f}; PyMeshFix {CLOSER}× closer on {len(won)}, the default "
          f"{CLOSER}× closer on {sum(x <= 1 / CLOSER for x in ratio)}")
    print(counts("PyMeshFix closer", won, err, default))
    print(counts("the others", [k for k in keys if k not in won], err, default))
    ears = None
    if args.ears:
        ears = {(f["split"], f["case"], f["hole"]): f for path in args.ears
                for f in _jsonl(path)}
    print("\n".join(hole_table(err, default, rows, won, ears)))
    print("\nMeshes where the default's median is above PyMeshFix's:")
    print("\n".join(lost_meshes(err, keys)))
    for alt in args.instead:
        print(f"\nceiling: {alt} written wherever it is closer to the truth than the default")
        print("\n".join(rule(err, keys, alt, {k for k in keys if err.get((alt, *k), np.inf)
                                              < err[("conformal", *k)]})))
        if args.scores:
            for ratio in args.ratio:
                flagged = flagged_by_scores(args.scores, alt, ratio)
                print(f"\nhidden-ring score of {alt} below {ratio} × ours "
                      f"(fires on {len(flagged & set(keys))} holes):")
                print("\n".join(rule(err, keys, alt, flagged)))
        else:
            flagged = {tuple(x) for x in json.loads(Path(args.flag).read_text())} \
                if args.flag else set(keys)
            print("\n".join(rule(err, keys, alt, flagged)))


if __name__ == "__main__":
    main()
