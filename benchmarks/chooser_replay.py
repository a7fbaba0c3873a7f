"""The self-check's rule against choosers learned from the spent holdouts and the tuning
side, scored leave-one-set-out (docs/selfcheck.md, session 49).

Reads the score tables of ``selfcheck_table.py --library`` (one JSONL per set, in one
directory): per hole each candidate's true error (fair2: the bilaplacian candidate, smoothed
where the noise gate opens; fair3; the raw λ-H fill), both tests' scores with every
candidate, the candidates' distances from each other, and what the library wrote and why.

1. The library's rule replayed on the table (``selection.sibling_test_plan`` and
   ``selection.choose`` on the table's scores) against what the library wrote, and the
   reasons where they differ.
2. Per set: the chooser rate (the written fill within 1 % of the best of the three, where
   the self-check chose: not where the plane test laid the fill), the median regret, the
   holes above 1.5× the better faired fill, the per-hole median / CGAL, the worst mesh / fair2
   (per-mesh medians) and the meshes above 1.1× fair2.
3. Learned choosers (features: what the library sees, no truth, no kind) and vetoes of the
   library's choice, each scored with every spent holdout a fold of its own and the tuning
   half and the tuning-side sets folded by mesh: the per-fold table, and the adoption bar.

    python benchmarks/chooser_replay.py /work/s49/chooser
    python benchmarks/chooser_replay.py /work/s49/chooser --models veto_lh_logistic --folds

scikit-learn is needed here (the study), never at runtime.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import cgal_s0  # noqa: E402 - its guard: the sets a study may look at

from surfinpaint.fill.conformal.options import SIGNIFICANCE  # noqa: E402
from surfinpaint.fill.conformal.selection import (  # noqa: E402
    choose,
    demoted,
    sibling_test_plan,
)

CANDIDATES = ("fair2", "fair3", "conformal")
TINY = 1e-6


def load(directory: Path) -> list[dict]:
    """The rows with the library's choice of every ``*.jsonl`` in ``directory`` (a set a
    study must not look at is refused)."""
    rows, seen = [], set()
    for path in sorted(directory.glob("*.jsonl")):
        for line in path.read_text().splitlines():
            if not line.strip():
                continue
            r = json.loads(line)
            if not cgal_s0._studied(r):
                raise SystemExit(f"{path}: {r['mesh']} is in {r['split']}: not study data")
            key = (r["split"], r["mesh"], r["hole"])
            if "library" in r and key not in seen:  # a hole computed twice: the first row
                seen.add(key)
                rows.append(r)
    return rows


def fold_of(row: dict) -> str:
    """A spent holdout is one fold; the tuning half and the tuning-side sets, one per mesh."""
    return row["split"] if row["split"].startswith("holdout") else f"{row['split']}:{row['mesh']}"


# ----------------------------------------------------------------- what the library wrote


def written(row: dict) -> str:
    """The candidate the library wrote ("fair2", "fair3", "conformal"), or "plane" (the
    plane test laid it: no choice), "ear_cut" (an ear-cut rule wrote it: no choice either),
    or "blend" (a blend of a failed λ-H fill)."""
    lib = row["library"]
    if lib["plane"]:
        return "plane"
    # an ear-cut rule wrote it, no self-check chose (session 51's default); rows made
    # before library_row recorded ``ear_cut`` say so in the note
    if lib.get("ear_cut") or (lib.get("note") or "").startswith("ear cutting:"):
        return "ear_cut"
    if lib["blended_with"]:
        return "blend"
    if lib["method"] == "conformal":
        return "conformal"
    return "fair3" if lib["fair_order"] == 3 else "fair2"


def choosable(row: dict) -> bool:
    """The self-check chose among all three candidates (no plane, the λ-H fill made)."""
    return written(row) in CANDIDATES and not row["failure"]


def replayed(row: dict) -> str:
    """The library's rule on the table's scores (both tests always run there; the
    sibling test's scores used as the library's plan would have run it)."""
    hidden = row["hidden"]
    run, with_lh = sibling_test_plan(hidden)
    sibling = ({} if not run else row["sibling"] if with_lh else
               {k: v for k, v in row["sibling"].items() if k != "conformal"})
    v = choose(hidden, sibling, crossed=row["crossed"])
    if "advantages" in row:  # the significance cut, as the default runs it
        v = demoted(v, row["advantages"], SIGNIFICANCE, crossed=row["crossed"])
    return "conformal" if v.keep and not row["failure"] else v.faired


def replay_check(rows: list[dict]) -> None:
    """The replay against what the library wrote, and why they differ where they do."""
    agree, differ = 0, []
    for r in rows:
        w = written(r)
        if w not in CANDIDATES:
            continue
        if replayed(r) == w:
            agree += 1
        else:
            differ.append(r)
    print(f"replay of the library's rule on the table: {agree} of {agree + len(differ)} "
          "holes agree (plane and blend holes left out)")
    reasons: dict[str, int] = {}
    for r in differ:
        v = r["library"]["verdict"] or {}
        same_hidden = _same(v.get("hidden", {}), r["hidden"])
        shallower = "one ring shallower" in (r["library"]["note"] or "")
        why = ("the library's hidden rings one ring shallower (a crease met beside the hole)"
               if shallower and not same_hidden
               else "the library's hidden-ring scores differ (other)" if not same_hidden
               else "the λ-H fill failed on the hole" if r["failure"]
               else "other")
        reasons[why] = reasons.get(why, 0) + 1
        if why == "other":
            print(f"  {r['split']} {r['mesh']} #{r['hole']}: wrote {written(r)}, replay "
                  f"{replayed(r)}; verdict {v}; table hidden {r['hidden']} sibling "
                  f"{r['sibling']}")
    for why, n in sorted(reasons.items(), key=lambda t: -t[1]):
        print(f"  {n}: {why}")
    # and the written fill's measured error against the table's candidate's
    off = [r for r in rows if written(r) in CANDIDATES and not _close(
        r["library"]["true"], r["true"][written(r)])]
    print(f"written fill's true error = the table's candidate's (1 %): "
          f"{sum(written(r) in CANDIDATES for r in rows) - len(off)} of "
          f"{sum(written(r) in CANDIDATES for r in rows)}")
    for r in off[:10]:
        print(f"  {r['split']} {r['mesh']} #{r['hole']}: library {r['library']['true']:.4g}, "
              f"table {written(r)} {r['true'][written(r)]:.4g}")


def _same(a: dict, b: dict) -> bool:
    return set(a) == set(b) and all(_close(a[k], b[k], 1e-9) for k in a)


def _close(a: float, b: float, rel: float = 0.01) -> bool:
    if not (math.isfinite(a) and math.isfinite(b)):
        return a == b
    return abs(a - b) <= rel * max(abs(a), abs(b), 1e-12)


# ---------------------------------------------------------------------- the measures


def error_of(row: dict, choice: str) -> float:
    """The true error of ``choice`` (a candidate; the library's own where it is "library"
    or no candidate)."""
    return row["true"][choice] if choice in CANDIDATES else row["library"]["true"]


def measures(rows: list[dict], choices: list[str]) -> dict:
    """The chooser rate, median regret, holes above 1.5× the better faired fill, per-hole
    median / CGAL, worst mesh / fair2 and meshes above 1.1× fair2 of ``choices``."""
    err = np.array([error_of(r, c) for r, c in zip(rows, choices, strict=True)])
    best = np.array([min(r["true"][k] for k in CANDIDATES) for r in rows])
    faired = np.array([min(r["true"]["fair2"], r["true"]["fair3"]) for r in rows])
    chose = np.array([written(r) != "plane" for r in rows]) & (best > TINY)
    regret = err[chose] / best[chose]
    cgal = np.array([r.get("cgal", float("nan")) for r in rows], dtype=float)
    has = np.isfinite(cgal) & (cgal > TINY) & np.isfinite(err)
    meshes: dict[str, list[int]] = {}
    for i, r in enumerate(rows):
        meshes.setdefault(f"{r['split']}:{r['mesh']}", []).append(i)
    vs_fair = {m: float(np.median(err[ix]) / np.median([rows[i]["true"]["fair2"] for i in ix]))
               for m, ix in meshes.items()
               if np.median([rows[i]["true"]["fair2"] for i in ix]) > TINY}
    worst = max(vs_fair, key=vs_fair.get) if vs_fair else None
    return {"holes": len(rows), "rate": float(np.mean(regret <= 1.01)) if len(regret) else
            float("nan"), "chose": int(chose.sum()),
            "regret": float(np.median(regret)) if len(regret) else float("nan"),
            "above": int(np.sum(err[faired > TINY] / faired[faired > TINY] > 1.5)),
            "cgal": float(np.median(err[has] / cgal[has])) if has.any() else float("nan"),
            "worst": (worst, vs_fair.get(worst, float("nan"))),
            "over": sorted(m for m, x in vs_fair.items() if x > 1.1)}


# ------------------------------------------------------------------------ the features


def _log_ratio(scores: dict, name: str, ref: str = "fair2") -> float:
    a, b = scores.get(name), scores.get(ref)
    if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)) or b <= 0:
        return 0.0
    return float(np.clip(math.log(max(a, 1e-300) / b), -4, 4))


def features(row: dict) -> list[float]:
    """What the library sees for the hole (no truth, no kind): both tests' log ratios to
    fair2 and whether each spoke, the candidates' distances from each other, the hole's size,
    crease and patch evidence, the noise gate's estimate."""
    h, s, b = row["hidden"], row["sibling"], row["between"]
    said_h = bool(h) and math.isfinite(h.get("conformal", 0.0))
    said_s = bool(s) and math.isfinite(s.get("conformal", 0.0))

    def dist(key):
        return math.log(b.get(key, 0.0) + 1e-3)

    noise = ((row["library"]["smoothing"] or {}).get("noise") or {})
    sigma, edge = noise.get("sigma", float("nan")), noise.get("edge", float("nan"))
    wide = noise.get("wide_sigma", float("nan"))
    adv = row.get("advantages", {})

    def z(test, name):
        a, se = adv.get(test, {}).get(name, (0.0, math.inf))
        return float(np.clip(a / se, -10, 10)) if se > 0 and math.isfinite(a) else 0.0

    return [
        z("hidden", "conformal"), z("hidden", "fair3"), z("sibling", "conformal"),
        z("sibling", "fair3"),
        _log_ratio(h, "conformal") if said_h else 0.0, _log_ratio(h, "fair3"), float(bool(h)),
        float(said_h),
        _log_ratio(s, "conformal") if said_s else 0.0, _log_ratio(s, "fair3"), float(bool(s)),
        float(said_s), float(row["siblings_found"]),
        dist("conformal|fair2"), dist("conformal|fair3"), dist("fair2|fair3"),
        dist("conformal|fair3") - dist("fair2|fair3"),
        math.log(row["n_edges"]), float(row["crossed"]), float(bool(row.get("grown"))),
        float(bool(row.get("crease"))), float(row.get("disk_rings") or 0),
        float(bool(row["library"]["smoothed"])),
        math.log(sigma / edge) if sigma > 0 and edge > 0 else -8.0,
        noise.get("correlation", 0.0) if math.isfinite(noise.get("correlation", 0.0)) else 0.0,
        math.log(wide / sigma) if sigma > 0 and math.isfinite(wide) and wide > 0 else 0.0,
    ]


FEATURE_NAMES = ("hidden z λ-H", "hidden z fair3", "sibling z λ-H", "sibling z fair3",
                 "hidden λ-H/fair2", "hidden fair3/fair2", "hidden ran", "hidden λ-H said",
                 "sibling λ-H/fair2", "sibling fair3/fair2", "sibling ran", "sibling λ-H said",
                 "siblings found", "d(λ-H, fair2)", "d(λ-H, fair3)", "d(fair2, fair3)",
                 "d(λ-H, fair3) / d(fair2, fair3)", "log edges", "crossed", "grown", "crease",
                 "disk rings", "smoothed", "log noise / edge", "noise correlation",
                 "log wide / narrow noise")


def _targets(row: dict) -> np.ndarray:
    t = row["true"]
    f2 = max(t["fair2"], TINY)
    return np.array([math.log(max(t[k], TINY) / f2) for k in ("fair3", "conformal")])


# ----------------------------------------------------------------------------- models


def _scaled(model):
    from sklearn.pipeline import make_pipeline
    from sklearn.preprocessing import StandardScaler

    return make_pipeline(StandardScaler(), model)


def _regression_choice(make):
    """A chooser from two regressions of log(error / fair2's) (fair3, λ-H): the lowest."""
    def fit(train):
        x = np.array([features(r) for r in train])
        y = np.array([_targets(r) for r in train])
        ok = np.all(np.isfinite(y), axis=1)
        model = make().fit(x[ok], y[ok])

        def pick(row):
            p = model.predict(np.array([features(row)]))[0]
            return ("fair2", "fair3", "conformal")[int(np.argmin([0.0, *p]))]
        return pick
    return fit


def _best_class(row) -> int:
    return int(np.argmin([row["true"][k] for k in CANDIDATES]))


def _class_weight(row) -> float:
    e = sorted(row["true"][k] for k in CANDIDATES)
    return float(min(math.log(max(e[1], TINY) / max(e[0], TINY)), 3.0)) + 0.01


def _classifier_choice(make):
    """A chooser from a classifier of the best candidate, weighted by how much it wins."""
    def fit(train):
        x = np.array([features(r) for r in train])
        y = np.array([_best_class(r) for r in train])
        w = np.array([_class_weight(r) for r in train])
        model = make()
        model.fit(x, y, **{f"{model.steps[-1][0]}__sample_weight": w}
                  if hasattr(model, "steps") else {"sample_weight": w})

        def pick(row):
            return CANDIDATES[int(model.predict(np.array([features(row)]))[0])]
        return pick
    return fit


def _veto(kept: str, instead: str, where, make, p: float = 0.5):
    """The library's rule, with ``kept`` written instead as ``instead`` where a classifier
    (trained on the holes ``where`` says, the library having written ``kept``; weighted by
    how much closer) gives ``instead`` being closer a probability above ``p``."""
    other = instead if callable(instead) else (lambda row: instead)

    def fit(train):
        mine = [r for r in train if written(r) == kept and where(r)]
        x = np.array([features(r) for r in mine])
        y = np.array([r["true"][other(r)] < r["true"][kept] for r in mine], dtype=int)
        w = np.array([min(abs(math.log(max(r["true"][other(r)], TINY) /
                                       max(r["true"][kept], TINY))), 3.0) + 0.01
                      for r in mine])
        model = make()
        model.fit(x, y, **{f"{model.steps[-1][0]}__sample_weight": w}
                  if hasattr(model, "steps") else {"sample_weight": w})

        def pick(row):
            w_ = written(row)
            if w_ == kept and where(row) and model.predict_proba(
                    np.array([features(row)]))[0, -1] > p:
                return other(row)
            return w_
        return pick
    return fit


def _veto_regression(kept: str, instead: str, where, make, margin: float = 0.0):
    """As :func:`_veto`, from a regression of log(error of ``kept`` / error of
    ``instead``): ``instead`` written where the prediction exceeds ``margin``."""
    def fit(train):
        mine = [r for r in train if written(r) == kept and where(r)]
        x = np.array([features(r) for r in mine])
        y = np.array([float(np.clip(math.log(max(r["true"][kept], TINY) /
                                             max(r["true"][instead], TINY)), -3, 3))
                      for r in mine])
        model = make().fit(x, y)

        def pick(row):
            w_ = written(row)
            if w_ == kept and where(row) and model.predict(
                    np.array([features(row)]))[0] > margin:
                return instead
            return w_
        return pick
    return fit


def _both(first, second):
    def fit(train):
        a, b = first(train), second(train)

        def pick(row):
            c = a(row)
            return c if c != written(row) else b(row)
        return pick
    return fit


def _faired_choice(row) -> str:
    """The faired fill the library would have written had it not kept the λ-H fill."""
    return (row["library"]["verdict"] or {}).get("faired", "fair2")


def _gated(row) -> bool:
    return bool(row["library"]["smoothed"])


def _any(row) -> bool:
    return True


def models() -> dict:
    from sklearn.linear_model import LogisticRegression, Ridge
    from sklearn.tree import DecisionTreeClassifier, DecisionTreeRegressor

    def logistic():
        return _scaled(LogisticRegression(C=1.0, max_iter=2000))

    def tree():
        return DecisionTreeClassifier(max_depth=3, min_samples_leaf=20, random_state=0)

    veto_lh = {"logistic": _veto("conformal", "fair3", _any, logistic),
               "tree": _veto("conformal", "fair3", _any, tree)}
    veto_lh["logistic_p70"] = _veto("conformal", "fair3", _any, logistic, 0.7)
    veto_lh["to_faired_logistic"] = _veto("conformal", _faired_choice, _any, logistic)
    veto_lh["to_faired_tree"] = _veto("conformal", _faired_choice, _any, tree)
    veto_scan = {"logistic": _veto("fair2", "conformal", _gated, logistic),
                 "tree": _veto("fair2", "conformal", _gated, tree)}
    def ridge():
        return _scaled(Ridge(alpha=10.0))

    return {
        "veto_lh_ridge": _veto_regression("conformal", "fair3", _any, ridge),
        "veto_scan_ridge": _veto_regression("fair2", "conformal", _gated, ridge),
        "ridge_a1": _regression_choice(lambda: _scaled(Ridge(alpha=1.0))),
        "ridge_a10": _regression_choice(lambda: _scaled(Ridge(alpha=10.0))),
        "tree_reg_d3": _regression_choice(
            lambda: DecisionTreeRegressor(max_depth=3, min_samples_leaf=20, random_state=0)),
        "logistic_best": _classifier_choice(logistic),
        "tree_best_d3": _classifier_choice(tree),
        "veto_lh_logistic": veto_lh["logistic"], "veto_lh_tree": veto_lh["tree"],
        "veto_lh_logistic_p70": veto_lh["logistic_p70"],
        "veto_lh_to_faired_logistic": veto_lh["to_faired_logistic"],
        "veto_lh_to_faired_tree": veto_lh["to_faired_tree"],
        "veto_scan_logistic": veto_scan["logistic"], "veto_scan_tree": veto_scan["tree"],
        "veto_both_logistic": _both(veto_lh["logistic"], veto_scan["logistic"]),
        "veto_both_tree": _both(veto_lh["tree"], veto_scan["tree"]),
    }


def left_out(rows: list[dict], fit) -> list[str]:
    """Each hole's choice by a model fitted without its fold (holes the self-check did not
    choose among three candidates keep the library's fill)."""
    folds = sorted({fold_of(r) for r in rows})
    out = [written(r) for r in rows]
    for fold in folds:
        train = [r for r in rows if fold_of(r) != fold and choosable(r)]
        pick = fit(train)
        for i, r in enumerate(rows):
            if fold_of(r) == fold and choosable(r):
                out[i] = pick(r)
    return out


# ------------------------------------------------------------------------------ tables


def _groups(rows: list[dict]) -> dict[str, list[int]]:
    """Row indices per spent holdout, and of the tuning side."""
    out: dict[str, list[int]] = {}
    for i, r in enumerate(rows):
        key = r["split"] if r["split"].startswith("holdout") else "tuning side"
        out.setdefault(key, []).append(i)
    return dict(sorted(out.items(), key=lambda kv: (kv[0] == "tuning side",
                                                     -int(kv[0][7:]) if kv[0][7:].isdigit()
                                                     else 0)))


def _fmt_worst(w) -> str:
    name, x = w
    return f"{x:.3f} ({name.split(':', 1)[1]})" if name else "–"


def per_set_table(rows: list[dict], library: list[str]) -> None:
    print("| set | holes | chose | chooser rate | median regret | holes > 1.5× faired | "
          "per-hole median / CGAL | worst mesh / fair2 | meshes > 1.1× fair2 |")
    print("|---|---|---|---|---|---|---|---|---|")
    for key, ix in _groups(rows).items():
        m = measures([rows[i] for i in ix], [library[i] for i in ix])
        print(f"| {key} | {m['holes']} | {m['chose']} | {m['rate']:.0%} | {m['regret']:.3f} | "
              f"{m['above']} | {m['cgal']:.3f} | {_fmt_worst(m['worst'])} | {len(m['over'])} |")


def fold_table(rows, library, chosen, name) -> dict:
    """Library against a model per fold; the adoption bar's counts."""
    print(f"\n#### {name}\n")
    print("| fold | holes | rate lib → model | > 1.5× lib → model | median / CGAL lib → model | "
          "worst mesh / fair2 lib → model |")
    print("|---|---|---|---|---|---|")
    tally = {"rate_better": 0, "rate_worse": 0, "above_better": 0, "above_worse": 0,
             "cgal_worse_2pct": [], "new_over": [], "folds": 0, "changed": 0,
             "closer": 0, "farther": 0}
    for key, ix in _groups(rows).items():
        sub = [rows[i] for i in ix]
        a = measures(sub, [library[i] for i in ix])
        b = measures(sub, [chosen[i] for i in ix])
        changed = sum(library[i] != chosen[i] for i in ix)
        print(f"| {key} | {a['holes']} ({changed} changed) | {a['rate']:.0%} → {b['rate']:.0%} | "
              f"{a['above']} → {b['above']} | {a['cgal']:.3f} → {b['cgal']:.3f} | "
              f"{_fmt_worst(a['worst'])} → {_fmt_worst(b['worst'])} |")
        if key == "tuning side":
            continue
        tally["folds"] += 1
        tally["changed"] += changed
        for i in ix:  # the changed holes: the model's fill closer or farther than the library's
            if library[i] != chosen[i]:
                new, old = error_of(rows[i], chosen[i]), error_of(rows[i], library[i])
                tally["closer"] += new < old
                tally["farther"] += new > old
        tally["rate_better"] += b["rate"] > a["rate"]
        tally["rate_worse"] += b["rate"] < a["rate"]
        tally["above_better"] += b["above"] < a["above"]
        tally["above_worse"] += b["above"] > a["above"]
        if math.isfinite(a["cgal"]) and b["cgal"] > 1.02 * a["cgal"]:
            tally["cgal_worse_2pct"].append(key)
        tally["new_over"] += sorted(set(b["over"]) - set(a["over"]))
    # the tuning side's meshes too
    ix = _groups(rows).get("tuning side", [])
    if ix:
        a = measures([rows[i] for i in ix], [library[i] for i in ix])
        b = measures([rows[i] for i in ix], [chosen[i] for i in ix])
        tally["new_over"] += sorted(set(b["over"]) - set(a["over"]))
    print(f"\nholdout folds: {tally['folds']}; chooser rate better / worse in "
          f"{tally['rate_better']} / {tally['rate_worse']}; holes > 1.5× fewer / more in "
          f"{tally['above_better']} / {tally['above_worse']}; per-hole median / CGAL worse by "
          f"> 2 % in {tally['cgal_worse_2pct'] or 'none'}; meshes newly > 1.1× fair2: "
          f"{tally['new_over'] or 'none'}")
    return tally


def passes(t: dict) -> bool:
    """The adoption bar: better on a clear majority (two thirds) of the holdout folds on
    both counts, no fold 2 % worse per hole against CGAL, no new mesh above 1.1× fair2."""
    clear = math.ceil(2 * t["folds"] / 3)
    return (t["rate_better"] >= clear and t["above_better"] >= clear
            and not t["cgal_worse_2pct"] and not t["new_over"])


def misses(rows: list[dict], library: list[str]) -> None:
    """The holes above 1.5× the better faired fill, by what was written and which candidate
    was closest; and the λ-H veto's class (a kept λ-H fill with fair3 closer) by size."""
    classes: dict[tuple, int] = {}
    for r, w in zip(rows, library, strict=True):
        faired = min(r["true"]["fair2"], r["true"]["fair3"])
        if faired > TINY and error_of(r, w) / faired > 1.5:
            best = min(CANDIDATES, key=lambda k: r["true"][k])
            key = (w, best, "scan" if r["kind"] == "range_scan" else "other")
            classes[key] = classes.get(key, 0) + 1
    print("\n| written | closest | kind | holes > 1.5× the better faired fill |")
    print("|---|---|---|---|")
    for (w, best, kind), n in sorted(classes.items(), key=lambda kv: -kv[1]):
        print(f"| {w} | {best} | {kind} | {n} |")
    kept = [r for r, w in zip(rows, library, strict=True) if w == "conformal"]
    worse = [r for r in kept if r["true"]["fair3"] < r["true"]["conformal"]]
    far = [r for r in kept if r["true"]["conformal"] > 1.5 * r["true"]["fair3"]]
    print(f"\nλ-H written: {len(kept)}; fair3 closer on {len(worse)}; by more than 1.5×: "
          f"{len(far)}")
    faired = [r for r, w in zip(rows, library, strict=True) if w in ("fair2", "fair3")
              and not r["failure"] and r["kind"] == "range_scan"]
    lh = [r for r in faired if r["true"]["conformal"] * 1.4 < r["true"][written(r)]]
    print(f"faired written on scans (λ-H made): {len(faired)}; λ-H 1.4× closer on {len(lh)}")


def explain(rows: list[dict]) -> None:
    """The λ-H veto's logistic model fitted on every row: its standardized coefficients."""
    from sklearn.linear_model import LogisticRegression

    mine = [r for r in rows if choosable(r) and written(r) == "conformal"]
    x = np.array([features(r) for r in mine])
    y = np.array([r["true"]["fair3"] < r["true"]["conformal"] for r in mine], dtype=int)
    w = np.array([min(abs(math.log(max(r["true"]["fair3"], TINY) /
                                   max(r["true"]["conformal"], TINY))), 3.0) + 0.01
                  for r in mine])
    sd = x.std(axis=0)
    sd[sd == 0] = 1.0
    model = LogisticRegression(C=1.0, max_iter=2000).fit((x - x.mean(axis=0)) / sd, y,
                                                         sample_weight=w)
    print(f"\nλ-H veto, logistic on all {len(mine)} kept λ-H fills (fair3 closer on "
          f"{int(y.sum())}); standardized coefficients, largest first:")
    for name, c in sorted(zip(FEATURE_NAMES, model.coef_[0], strict=True),
                          key=lambda t: -abs(t[1]))[:8]:
        print(f"  {name}: {c:+.2f}")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("directory", help="the selfcheck_table.py --library caches (*.jsonl)")
    parser.add_argument("--models", default="all", help="comma-separated, or 'all'")
    parser.add_argument("--folds", action="store_true", help="the per-fold table of each")
    parser.add_argument("--explain", action="store_true",
                        help="the λ-H veto's logistic coefficients, fitted on every row")
    args = parser.parse_args(argv)
    rows = load(Path(args.directory))
    sets = sorted({r["split"] for r in rows})
    print(f"{len(rows)} holes from {', '.join(sets)}\n")
    replay_check(rows)
    library = [written(r) for r in rows]
    print()
    per_set_table(rows, library)
    misses(rows, library)
    if args.explain:
        explain(rows)
    made = models()
    names = list(made) if args.models == "all" else args.models.split(",")
    summary = []
    for name in names:
        chosen = left_out(rows, made[name])
        if args.folds:
            tally = fold_table(rows, library, chosen, name)
        else:
            import contextlib
            import io
            with contextlib.redirect_stdout(io.StringIO()):
                tally = fold_table(rows, library, chosen, name)
        whole = measures(rows, chosen)
        summary.append((name, tally, whole))
    base = measures(rows, library)
    print("\n| rule (leave-one-set-out) | holdout holes changed (closer / farther) | "
          "chooser rate (all) | holes > 1.5× "
          "(all) | holdout folds: rate better / worse | > 1.5× fewer / more | folds "
          "> 2 % worse / CGAL | new meshes > 1.1× | passes |")
    print("|---|---|---|---|---|---|---|---|---|")
    print(f"| library | – | {base['rate']:.1%} | {base['above']} | – | – | – | – | – |")
    for name, t, whole in summary:
        print(f"| {name} | {t['changed']} ({t['closer']} / {t['farther']}) | "
              f"{whole['rate']:.1%} | {whole['above']} | "
              f"{t['rate_better']} / {t['rate_worse']} | {t['above_better']} / "
              f"{t['above_worse']} | {len(t['cgal_worse_2pct'])} | {len(t['new_over'])} | "
              f"{'yes' if passes(t) else 'no'} |")


if __name__ == "__main__":
    main()
