"""Coverage of the self-check's two tests (issue 14, session 24): on how many holes does each
test give a score, how many sibling holes it finds of those asked for, and why not.

For every hole of a set (on the neighbourhood ``fill_holes`` hands the conformal method),
both tests are run as ``conformal_fill`` runs them with the default options, with the faired
candidates only (coverage does not depend on which candidates are scored, only on whether a
test hole can be made and filled). A row records whether the hidden-ring test scored and,
for the default depth, why not (the enlarged hole's loops do not close, or not exactly one
loop runs along the hidden band); the number of sibling holes scored of ``siblings`` asked
for, and for the default centres the reason each one that could not be cut failed.

Sets (tuning-side only):

- ``tuning``: the manifest's tuning half (112 holes);
- ``thin``: the thin tori of ``selfcheck_probes.py`` (38 holes);
- ``random``: ``selfcheck_probes.py``'s random holes on the tuning meshes (all of them,
  not only the thin ones);
- ``quad``: the built quadruped's holes (``built_meshes.holes``, as ``thin_parts.py quad``).

    python benchmarks/selfcheck_coverage.py --set tuning --out /tmp/coverage_tuning.jsonl
    python benchmarks/selfcheck_coverage.py --set tuning --fallbacks --out /tmp/fb.jsonl
    python benchmarks/selfcheck_coverage.py --table /tmp/coverage_tuning.jsonl
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
import selfcheck_probes  # noqa: E402
import selfcheck_table  # noqa: E402
import validation  # noqa: E402
import validation_meshes as vm  # noqa: E402

from surfinpaint.fill.conformal import ConformalOptions  # noqa: E402
from surfinpaint.fill.conformal.candidates import Candidates  # noqa: E402
from surfinpaint.fill.neighbourhood import FilledMesh  # noqa: E402 - fill_holes' neighbourhood
from surfinpaint.fill.selfcheck import (  # noqa: E402
    _sibling_centres,
    hidden_band,
    hidden_ring_scores,
    sibling_reach,
    sibling_scores,
)
from surfinpaint.geometry.cutting import (  # noqa: E402
    cut_geodesic_disk,
    edge_graph,
    ring_distances,
)


def _hidden_why(vertices, faces, loop, hide_rings, graph) -> str:
    """Why the hidden-ring test at depth ``hide_rings`` makes no test hole ("" if it does)."""
    ring = ring_distances(faces, len(vertices), loop, hide_rings + 0.5, graph=graph)
    _, _, border, loops = hidden_band(faces, ring, hide_rings)
    if loops is None:
        return "loops do not close"
    enlarged = [l for l in loops if border[l].mean() > 0.5]
    return "" if len(enlarged) == 1 else f"{len(enlarged)} enlarged loops"


def _sibling_why(vertices, faces, loop, options, graph) -> list[str]:
    """The reason each default sibling centre could not be cut (none when all could)."""
    radius, gap = sibling_reach(vertices, loop, options.gap_rings)
    centres = _sibling_centres(vertices, faces, loop, gap, options.siblings, graph=graph)
    why = [f"{options.siblings - len(centres)} centres missing"] if len(centres) < \
        options.siblings else []
    for centre in centres:
        try:
            cut_geodesic_disk(vertices, faces, centre, radius)
        except ValueError as exc:
            text = str(exc)
            why.append("reaches the border" if "boundary:" in text else
                       "not a disk" if "not a disk" in text else
                       "several loops" if "loops instead" in text else
                       "no whole face" if "no whole face" in text else text[:40])
    return why


def coverage_row(vertices, faces, loop, options: ConformalOptions,
                 fallbacks: bool = False) -> dict:
    """Both tests' coverage of one hole, with the faired candidates (``fallbacks``: with
    the tests' fallbacks, ``min_hide_rings=1`` and ``tries=8``)."""
    tests = Candidates.for_hole(vertices, faces, loop, options).for_tests(
        with_lambda_h=False)
    graph = edge_graph(faces, len(vertices))
    started = time.process_time()
    hidden = hidden_ring_scores(vertices, faces, loop, tests, hide_rings=options.hide_rings,
                                patch_rings=options.rings_in_patch, graph=graph,
                                min_hide_rings=1 if fallbacks else None)
    seconds_hidden = time.process_time() - started
    started = time.process_time()
    found = sibling_scores(vertices, faces, loop, tests, siblings=options.siblings,
                           gap_rings=options.gap_rings, patch_rings=options.rings_in_patch,
                           each=True, graph=graph, tries=8 if fallbacks else None)
    seconds_sibling = time.process_time() - started
    return {"n_edges": len(loop), "hidden": bool(hidden),
            "hidden_why": _hidden_why(vertices, faces, loop, options.hide_rings, graph),
            "siblings": len(found),
            "sibling_why": _sibling_why(vertices, faces, loop, options, graph),
            "seconds_hidden": seconds_hidden, "seconds_sibling": seconds_sibling}


def _local(cut, options):
    local = FilledMesh(cut.vertices, cut.faces).cut(
        cut.loop, options.neighbourhood_rings(len(cut.loop)))
    return local.vertices, local.faces, local.local_loop


def holes(name: str, options: ConformalOptions, per_mesh: int):
    """(key, cut) of every hole of set ``name``."""
    if name == "tuning":
        for entry in selfcheck_table._manifest_holes("tuning", None):
            mesh = vm.load_entry(entry)
            for k, hole in enumerate(entry["holes"]):
                yield f"{entry['mesh']} #{k}", validation._cut(mesh, hole)
    elif name == "thin":
        for torus, i, r_h, cut in selfcheck_probes.thin_cuts():
            yield f"{torus} #{i} r{r_h}", cut
    elif name == "random":
        for mesh_id, c, r_h, cut in selfcheck_probes.random_cuts(per_mesh, []):
            yield f"{mesh_id} v{c} r{r_h}", cut
    elif name == "quad":
        import built_meshes
        v, f = built_meshes.quadruped()
        for centre, radius, cut in built_meshes.holes(v, f):
            yield f"quad v{centre} r{radius}", cut


def table(paths: list[Path]) -> str:
    """Coverage per file: holes, hidden-ring test with no score (and why), sibling holes
    found (0, 1, 2 of 2) and the reasons of the default centres that failed."""
    out = ["| rows | holes | no hidden-ring score | why (default depth) | siblings 0 / 1 / 2+ "
           "| why (default centres) | neither test |", "|---|---|---|---|---|---|---|"]
    for path in paths:
        rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
        no_hidden = [r for r in rows if not r["hidden"]]
        hw = Counter(r["hidden_why"] or "fill raised" for r in no_hidden)
        sw = Counter(w for r in rows for w in r["sibling_why"])
        found = Counter(min(r["siblings"], 2) for r in rows)
        neither = sum(not r["hidden"] and r["siblings"] == 0 for r in rows)
        out.append(f"| {path.name} | {len(rows)} | {len(no_hidden)} | "
                   f"{', '.join(f'{k} {v}' for k, v in hw.items()) or '—'} | "
                   f"{found[0]} / {found[1]} / {found[2]} | "
                   f"{', '.join(f'{k} {v}' for k, v in sw.items()) or '—'} | {neither} |")
    return "\n".join(out)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--set", choices=("tuning", "thin", "random", "quad"))
    parser.add_argument("--per-mesh", type=int, default=40)
    parser.add_argument("--out", help="JSONL file of rows (overwritten)")
    parser.add_argument("--table", nargs="+", help="coverage tables of JSONL files")
    parser.add_argument("--fallbacks", action="store_true", help="the tests with their "
                        "fallbacks (min_hide_rings=1, tries=8), not the default")
    args = parser.parse_args(argv)
    if args.table:
        print(table([Path(p) for p in args.table]))
        return
    options = ConformalOptions()
    with Path(args.out).open("w") as fh:
        for key, cut in holes(args.set, options, args.per_mesh):
            v, f, loop = _local(cut, options)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                row = {"set": args.set, "key": key,
                       **coverage_row(v, f, loop, options, args.fallbacks)}
            fh.write(json.dumps(row) + "\n")
            fh.flush()
            if not row["hidden"] or row["siblings"] < options.siblings:
                print(json.dumps(row), file=sys.stderr, flush=True)


if __name__ == "__main__":
    main()
