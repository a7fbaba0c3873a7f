"""Hedging where the self-check is unsure (issue 14, tuning half): a convex combination of
the three candidates, weighted by the tests' scores, instead of one candidate.

The bilaplacian, trilaplacian and λ-H fills of a hole share their triangles (one
triangulation and refinement; the λ-H fill moves S0's new vertices) unless the λ-H fill
was made on a grown patch or a lattice, so ``w2 fair2 + w3 fair3 + wL λ-H`` of their new
vertices is a fill too. Per hole this writes the self-check's score table row
(``selfcheck_table.py``: true errors, both tests, the candidates' distances) and the true
error of every combination on a simplex grid of step 1/``STEPS`` (``blends``, keyed
``"i2,i3,iL"`` in grid steps), then replays weighting rules with the measures of
``selfcheck_replay.py``. Rules are chosen on the tuning half only.

    python benchmarks/hedge_study.py --split tuning --cache /tmp/hedge.jsonl
    python benchmarks/hedge_study.py --split tuning --cache /tmp/hedge.jsonl --replay
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import selfcheck_replay as replay  # noqa: E402
import selfcheck_table  # noqa: E402

from surfinpaint.geometry.metrics import surface_distance  # noqa: E402

STEPS = 8
NAMES = ("fair2", "fair3", "conformal")


def simplex(steps: int = STEPS) -> list[tuple[int, int, int]]:
    """The grid points (i2, i3, iL), i2 + i3 + iL = steps."""
    return [(a, b, steps - a - b) for a in range(steps + 1) for b in range(steps + 1 - a)]


def blend_errors(vertices, faces, fills, truth_vertices, truth_faces, diameter, n_samples):
    """{"blends": {"i2,i3,iL": true error}} where the three candidates share their
    triangles, else {"blends": None}."""
    made = [fills.get(k) for k in NAMES]
    if any(f is None or isinstance(f, Exception) for f in made) or not all(
            np.array_equal(made[0].faces, f.faces) and len(made[0].vertices) == len(f.vertices)
            for f in made[1:]):
        return {"blends": None}
    new = np.stack([np.asarray(f.vertices, float) for f in made])
    pf = made[0].faces
    out = {}
    for w in simplex():
        moved = np.tensordot(np.asarray(w, float) / STEPS, new, axes=1)
        d = surface_distance(*selfcheck_table._patch(vertices, faces, moved, pf),
                             truth_vertices, truth_faces, n_samples=n_samples)
        out[",".join(map(str, w))] = 100.0 * d.mean / diameter
    return {"blends": out}


# --------------------------------------------------------------------------- rules
# rule(row) -> weights (w2, w3, wL) summing to 1, or None: write today's choice


def _grid(w) -> str:
    """The grid point nearest to weights ``w`` (largest remainders)."""
    w = np.asarray(w, float) / np.sum(w) * STEPS
    i = np.floor(w).astype(int)
    for k in np.argsort(-(w - i))[:STEPS - i.sum()]:
        i[k] += 1
    return ",".join(map(str, i))


def _relative(t: dict) -> dict:
    """A test's scores over the best score of the test (1 for the best), the λ-H fill's
    dropped where it failed on the test hole."""
    t = replay._said(t)
    lo = min(t.values()) if t else 0.0
    return {k: v / lo for k, v in t.items()} if lo > 0 else {}


def evidence(row) -> dict:
    """Each candidate's relative score: the geometric mean of its scores relative to each
    test's best (a candidate missing from a test gets that test's worst)."""
    tests = [_relative(row["hidden"]), _relative(row["sibling"])]
    tests = [t for t in tests if t]
    out = {}
    for k in NAMES:
        r = [t.get(k, max(t.values())) for t in tests]
        out[k] = float(np.exp(np.mean(np.log(r)))) if r else 1.0
    return out


def softmax_rule(beta: float):
    """Weights ∝ relative score^-β (β → ∞: the argmin of the geometric mean)."""
    def rule(row):
        e = evidence(row)
        if not np.isfinite(row["true"]["conformal"]):
            e.pop("conformal")
        w = {k: e[k] ** -beta if k in e else 0.0 for k in NAMES}
        return [w[k] for k in NAMES]
    return rule


def hedged_choice(margin: float, share: float = 0.5):
    """Today's choice, unless the written fill's relative score is within ``margin`` of
    the runner-up's: then ``share`` of the runner-up blended in."""
    def rule(row):
        pick, _ = replay.rule_library(row)
        e = evidence(row)
        if not np.isfinite(row["true"]["conformal"]):
            e.pop("conformal")
        others = {k: v for k, v in e.items() if k != pick}
        if pick not in e or not others:
            return None
        runner = min(others, key=others.get)
        if others[runner] > margin * e[pick]:
            return None
        w = dict.fromkeys(NAMES, 0.0)
        w[pick], w[runner] = 1 - share, share
        return [w[k] for k in NAMES]
    return rule


def shrunk_choice(alpha: float):
    """Today's choice moved ``alpha`` of the way to the mean of the candidates made."""
    def rule(row):
        pick, _ = replay.rule_library(row)
        made = [k for k in NAMES if np.isfinite(row["true"][k])]
        w = {k: alpha / len(made) if k in made else 0.0 for k in NAMES}
        w[pick] += 1 - alpha
        return [w[k] for k in NAMES]
    return rule


RULES = {
    **{f"softmax β={b}": softmax_rule(b) for b in (0.5, 1, 2, 4, 8)},
    **{f"hedge within {m}, share {s}": hedged_choice(m, s)
       for m in (1.1, 1.25, 1.5) for s in (0.25, 0.5)},
    **{f"today's choice shrunk {a} to the mean": shrunk_choice(a) for a in (0.25, 0.5)},
}


def written(row, rule) -> float:
    """The true error of what ``rule`` writes on ``row`` (today's choice where it gives no
    weights or the candidates do not share their triangles)."""
    w = rule(row) if rule is not None else None
    if w is None or row.get("blends") is None:
        return replay.chosen_errors([row], replay.rule_library)[0]
    return row["blends"][_grid(w)]


def table(rows) -> str:
    shared = sum(r.get("blends") is not None for r in rows)
    out = [f"{len(rows)} holes, {shared} with shared triangles (blends possible)\n",
           "| rule | median / CGAL | worst mesh / fair2 | meshes > 1.1 | worst hole / "
           "better faired | holes > 1.5× | median written / today's | holes better / "
           "worse by 10 % |", "|---|---|---|---|---|---|---|---|"]
    today = np.array([written(r, None) for r in rows])
    oracle = [min(r["blends"].values()) if r.get("blends") else
              min(v for v in r["true"].values() if np.isfinite(v)) for r in rows]
    for label, errors in [("today (library rule)", today)] + [
            (label, np.array([written(r, rule) for r in rows])) for label, rule in
            RULES.items()] + [("best grid blend (truth: ceiling)", np.array(oracle))]:
        m = replay.measures(rows, errors)
        ratio = errors / np.maximum(today, 1e-300)
        out.append(f"| {label} | {m['over_cgal']:.3f} | {m['worst_mesh'][1]:.3f} "
                   f"({m['worst_mesh'][0]}) | {m['meshes_above_1.1']} | "
                   f"{m['worst_hole'][1]:.2f} ({m['worst_hole'][0]}) | "
                   f"{len(m['above_1.5'])} | {np.median(ratio):.3f} | "
                   f"{int((ratio < 1 / 1.1).sum())} / {int((ratio > 1.1).sum())} |")
    return "\n".join(out)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--split", choices=("tuning", "validation"), required=True)
    parser.add_argument("--cache", required=True, help="JSONL rows (appended)")
    parser.add_argument("--baseline", default=None, help="a validation.py run for CGAL's "
                        "errors (its --out .json or .jsonl)")
    parser.add_argument("--replay", action="store_true", help="print the rule table only")
    args = parser.parse_args(argv)
    if args.replay:
        rows = [r for r in selfcheck_table.read_cache(Path(args.cache))
                if r["split"] == args.split]
    else:
        rows = selfcheck_table.build(Path(args.cache), args.split, None,
                                     Path(args.baseline) if args.baseline else None,
                                     extra=blend_errors)
    print(table(rows))


if __name__ == "__main__":
    main()
