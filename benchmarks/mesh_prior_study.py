"""A mesh-wide prior for the self-check (issue 14, tuning half): which candidate does best on
probe holes cut all over the known surface, away from the holes to fill?

The hidden-ring and sibling tests score the candidates on holes next to the hole, two or
three of them. This asks the same question of the whole mesh: ``--probes`` geodesic disks
as wide as the mesh's benchmark holes, at random vertices farther than both radii and
``GAP`` edge lengths from every benchmark hole of the mesh (so no probe sees a hole's
truth), are cut and filled by the three candidates (as ``selfcheck_table.py`` makes them),
and each candidate's true error on each probe is written. ``--replay`` then puts each
mesh's prior (the candidates' median errors over its probes, relative to the best) beside
the score table's rows of its holes (``selfcheck_table.py --cache``) and replays rules with
the measures of ``selfcheck_replay.py``. Rules are chosen on the tuning half only.

    python benchmarks/mesh_prior_study.py --split tuning --out /tmp/probes.jsonl
    python benchmarks/mesh_prior_study.py --split tuning --out /tmp/probes.jsonl \\
        --replay /tmp/scores.jsonl
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import holes_manifest  # noqa: E402
import selfcheck_replay as replay  # noqa: E402
import selfcheck_table  # noqa: E402
import validation  # noqa: E402
import validation_meshes as vm  # noqa: E402

from surfinpaint.fill.conformal import ConformalOptions  # noqa: E402
from surfinpaint.fill.neighbourhood import FilledMesh  # noqa: E402
from surfinpaint.geometry.mesh import mean_edge_length  # noqa: E402

GAP = 3.0  # edge lengths between a probe and a benchmark hole
NAMES = ("fair2", "fair3", "conformal")
SEED = 20261205


def probe_sites(mesh, entry, count: int, rng) -> list[dict]:
    """Up to ``count`` probe holes ``{"centre", "radius"}``: radii of the mesh's benchmark
    holes, centres at random vertices clear of every benchmark hole."""
    v = mesh.vertices
    h = mean_edge_length(v, mesh.faces)
    centres = np.array([hole["centre"] for hole in entry["holes"]])
    radii = np.array([hole["radius"] for hole in entry["holes"]])
    sites = []
    for vid in rng.permutation(len(v)):
        r = float(rng.choice(radii))
        clear = np.linalg.norm(centres - v[vid], axis=1) > radii + r + GAP * h
        if clear.all():
            sites.append({"centre": v[vid].tolist(), "radius": r, "vertex": int(vid)})
        if len(sites) == count:
            break
    return sites


def probe_errors(mesh, site, options) -> dict | None:
    """The candidates' true errors on one probe hole (None where it cannot be cut)."""
    try:
        cut = validation._cut(mesh, site)
    except ValueError:
        return None
    local = FilledMesh(cut.vertices, cut.faces).cut(
        cut.loop, options.neighbourhood_rings(len(cut.loop)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, fills, failure, _ = selfcheck_table.made_candidates(
            local.vertices, local.faces, local.local_loop, options)
        return {name: (float("inf") if isinstance(fills[name], Exception) else
                       selfcheck_table._true_error(local.vertices, local.faces, fills[name],
                                                   cut.truth_vertices, cut.truth_faces,
                                                   cut.diameter, 4000))
                for name in NAMES} | {"failure": failure, "n_edges": len(cut.loop)}


def measure(out: Path, split: str, probes: int) -> None:
    done = {r["mesh"] for r in selfcheck_table.read_cache(out)}
    options = ConformalOptions()
    for entry in holes_manifest.read()["meshes"]:
        if entry["split"] != split or entry["mesh"] in done:
            continue
        mesh = vm.load_entry(entry)
        rng = np.random.default_rng(SEED)
        rows = []
        for site in probe_sites(mesh, entry, probes, rng):
            errors = probe_errors(mesh, site, options)
            if errors is not None:
                rows.append({"mesh": entry["mesh"], "split": split, **site, **errors})
        with out.open("a") as fh:
            fh.writelines(json.dumps(r) + "\n" for r in rows)
        e = np.array([[r[k] for k in NAMES] for r in rows])
        print(f"{entry['mesh']}: {len(rows)} probes; median fair2 {np.median(e[:, 0]):.3g} "
              f"fair3 {np.median(e[:, 1]):.3g} λ-H {np.median(e[:, 2]):.3g}", flush=True)


def priors(probe_rows) -> dict:
    """{mesh: {candidate: median over the probes of its error / the probe's best}}."""
    by_mesh: dict[str, list] = {}
    for r in probe_rows:
        e = np.array([r[k] for k in NAMES], float)
        best = np.min(e)
        if np.isfinite(best) and best > 1e-9:
            by_mesh.setdefault(r["mesh"], []).append(e / best)
    return {m: dict(zip(NAMES, np.median(np.array(x), axis=0).tolist(), strict=True))
            for m, x in by_mesh.items()}


# --------------------------------------------------------------------------- rules


def prior_veto(limit: float, decisive: bool = True):
    """Today's rule, but a λ-H fill is not kept on a mesh whose probes' median λ-H error is
    above ``limit`` × the best (unless its hidden-ring score is decisive, ``decisive``)."""
    def rule(row, prior):
        pick, faired = replay.rule_library(row)
        if pick != "conformal" or prior["conformal"] <= limit:
            return pick, faired
        h = replay._said(row["hidden"])
        if decisive and "conformal" in h and h["conformal"] < 0.5 * h["fair2"]:
            return pick, faired
        return faired, faired
    return rule


def prior_faired(limit: float):
    """Today's rule, but where it writes a faired fill, the one the probes rank first when
    the other's median is above ``limit`` × it."""
    def rule(row, prior):
        pick, faired = replay.rule_library(row)
        if pick == "conformal":
            return pick, faired
        if prior["fair3"] * limit < prior["fair2"]:
            return "fair3", "fair3"
        if prior["fair2"] * limit < prior["fair3"]:
            return "fair2", "fair2"
        return pick, faired
    return rule


def prior_argmin(row, prior):
    """The candidate the probes rank first, whatever the hole's own tests say."""
    pick = min(NAMES, key=prior.get)
    return pick, ("fair3" if prior["fair3"] < prior["fair2"] else "fair2")


def rules() -> dict:
    out = {f"no λ-H where the probes' median λ-H is > {a}× the best": prior_veto(a)
           for a in (1.05, 1.1, 1.2)}
    out |= {f"same, without the decisive exception, > {a}×": prior_veto(a, decisive=False)
            for a in (1.1, 1.2)}
    out |= {f"faired fill: the probes' first where the other is > {a}×": prior_faired(a)
            for a in (1.1, 1.3)}
    out |= {"the probes' first candidate": prior_argmin}
    return out


def replay_table(probe_rows, score_rows) -> str:
    pri = priors(probe_rows)
    rows = [r for r in score_rows if r["mesh"] in pri]
    lines = ["| mesh | probes | fair2 | fair3 | λ-H (median / the probe's best) |",
             "|---|---|---|---|---|"]
    count = {m: sum(r["mesh"] == m for r in probe_rows) for m in pri}
    lines += [f"| {m} | {count[m]} | {p['fair2']:.3f} | {p['fair3']:.3f} | "
              f"{p['conformal']:.3f} |" for m, p in pri.items()]
    table = {"library today": replay.rule_library} | {
        label: (lambda r, f=f: f(r, pri[r["mesh"]])) for label, f in rules().items()}
    return "\n".join(lines) + "\n\n" + replay.replay(rows, table)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--split", choices=("tuning", "validation"), required=True)
    parser.add_argument("--out", required=True, help="JSONL of probe rows (appended)")
    parser.add_argument("--probes", type=int, default=24, help="probe holes per mesh")
    parser.add_argument("--replay", default=None, metavar="SCORES",
                        help="a selfcheck_table.py cache of the same half: replay rules")
    args = parser.parse_args(argv)
    out = Path(args.out)
    if args.replay:
        probe_rows = [r for r in selfcheck_table.read_cache(out) if r["split"] == args.split]
        score_rows = [r for r in selfcheck_table.read_cache(Path(args.replay))
                      if r["split"] == args.split]
        print(replay_table(probe_rows, score_rows))
        return
    measure(out, args.split, args.probes)


if __name__ == "__main__":
    main()
