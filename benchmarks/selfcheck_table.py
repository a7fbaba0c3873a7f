"""The self-check's score table on the validation benchmark's holes, cached, for replaying
selection rules (``benchmarks/selfcheck_rules.py --manifest``).

For every hole of ``benchmarks/holes_manifest.json`` (cut as ``benchmarks/validation.py``
cuts it, on the neighbourhood ``fill_holes`` hands the conformal method), each candidate
(``fair2``: bilaplacian fairing; ``fair3``: trilaplacian; ``conformal``: the raw λ-H fill)
is made as ``conformal_fill`` makes it with the default options, and scored three ways: its
true error (two-sided mean distance to the removed truth, % of the hole diameter, as
``accuracy.score`` measures it), the hidden-ring test and the sibling-hole test (both always
run, with every candidate). Each row also says whether a crease crosses the hole, whether the
λ-H fill's patch had to be grown unevenly (``fill/conformal/patch.grown_patch``), and CGAL's
error and the default fill's error from a saved ``validation.py`` run, and how many sibling
holes could be cut and filled (``siblings_found``, of ``siblings`` asked for). ``between``
holds the candidates' distances from each other (the same two-sided mean distance, between
their patches, % of the hole diameter): evidence that needs no truth and no test hole.

    python benchmarks/selfcheck_table.py --split tuning --cache /tmp/scores.jsonl
    python benchmarks/selfcheck_table.py --split tuning --option siblings=4 --cache /tmp/s4.jsonl

Rows already in the cache are not computed again: a replay of rules is instant.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import holes_manifest  # noqa: E402
import validation  # noqa: E402
import validation_meshes as vm  # noqa: E402
from variant_rows import read_rows  # noqa: E402

from surfinpaint.errors import FillError  # noqa: E402
from surfinpaint.fill.conformal import ConformalOptions  # noqa: E402
from surfinpaint.fill.conformal.candidates import Candidates  # noqa: E402
from surfinpaint.fill.conformal.patch import hole_patch, is_disk  # noqa: E402
from surfinpaint.fill.neighbourhood import FilledMesh  # noqa: E402 - fill_holes' neighbourhood
from surfinpaint.fill.selfcheck import (  # noqa: E402
    hidden_ring_scores,
    mean_scores,
    sibling_scores,
)
from surfinpaint.geometry.mesh import faces_near  # noqa: E402
from surfinpaint.geometry.metrics import hole_patch_of, surface_distance  # noqa: E402

INF = float("inf")


def _patch(vertices, faces, new_vertices, new_faces):
    """The fill's patch (its faces and the mesh's faces around the hole), as the true
    error measures it."""
    return hole_patch_of(np.concatenate([vertices, new_vertices]),
                         np.concatenate([faces, new_faces]), len(vertices), faces)


def _true_error(vertices, faces, fill, truth_vertices, truth_faces, diameter, n_samples):
    d = surface_distance(*_patch(vertices, faces, fill.vertices, fill.faces),
                         truth_vertices, truth_faces, n_samples=n_samples)
    return 100.0 * d.mean / diameter


def _between(vertices, faces, fills, diameter, n_samples) -> dict:
    """{"a|b": distance between candidates a and b (% of the hole diameter)}, the pairs
    of candidates that were made."""
    made = {k: _patch(vertices, faces, f.vertices, f.faces) for k, f in fills.items()
            if not isinstance(f, Exception)}
    names = sorted(made)
    return {f"{a}|{b}": 100.0 * surface_distance(*made[a], *made[b],
                                                 n_samples=n_samples).mean / diameter
            for i, a in enumerate(names) for b in names[i + 1:]}


def _patch_shape(faces, loop, fill, rings) -> dict:
    """How the λ-H fill's patch came out: the rings ``hole_patch`` keeps as a disk, whether
    none does (then it is grown unevenly), and what the mesh pass used."""
    n = int(max(faces.max(), fill.faces.max(), np.max(loop))) + 1
    disk_rings = next((k for k in range(rings, 0, -1) if is_disk(np.concatenate(
        [fill.faces, faces_near(faces, loop, k - 1, n)]))), 0)
    d = fill.diagnostics
    out = {"disk_rings": disk_rings, "used_rings": d.rings if d else None,
           "map": d.mesh.map if d is not None and d.mesh is not None else None,
           "damping": d.damping if d else None, "crease": fill.crease is not None}
    grown = disk_rings == 0
    if d is not None and d.mesh is not None and not out["crease"] and d.rings:
        try:
            shrunk, _ = hole_patch(faces, loop, fill.faces, d.rings)
            # the mesh pass grew its patch unevenly (a thin patch) when it is not the disk
            grown |= len(shrunk) != len(d.mesh.faces)
        except FillError:
            grown = True
    out["grown"] = bool(grown)
    return out


def made_candidates(vertices, faces, loop, options: ConformalOptions):
    """The candidates as ``conformal_fill`` makes them: ``(candidates, fills, failure,
    seconds of the λ-H fill)``; ``fills["conformal"]`` is the FillError where it failed."""
    candidates = Candidates.for_hole(vertices, faces, loop, options)
    fills = candidates.faired(vertices, faces, loop)
    s0 = candidates.initial(vertices, faces, loop, fills)
    failure = None
    started = time.perf_counter()
    try:
        fills["conformal"] = candidates.lambda_h(vertices, faces, loop, s0)
    except FillError as exc:
        fills["conformal"], failure = exc, str(exc)
    return candidates, fills, failure, time.perf_counter() - started


def hole_scores(vertices, faces, loop, truth_vertices, truth_faces, diameter,
                n_samples: int = 10000, options: ConformalOptions | None = None,
                extra=None) -> dict:
    """The candidates as ``conformal_fill`` makes them (its test holes too), their true
    errors and both tests' scores, every candidate in every test. ``extra``, if given,
    adds its dict to the row: a study's measures of the same candidates, called as
    ``extra(vertices, faces, fills, truth_vertices, truth_faces, diameter, n_samples)``."""
    o = ConformalOptions() if options is None else options
    candidates, fills, failure, seconds_lh = made_candidates(vertices, faces, loop, o)
    true = {name: INF if isinstance(fill, Exception) else
            _true_error(vertices, faces, fill, truth_vertices, truth_faces, diameter,
                        n_samples) for name, fill in fills.items()}
    shape = ({} if failure else
             _patch_shape(faces, loop, fills["conformal"], o.rings_in_patch))
    tests = candidates.for_tests()
    started = time.perf_counter()
    hidden = hidden_ring_scores(vertices, faces, loop, tests, hide_rings=o.hide_rings,
                                patch_rings=o.rings_in_patch)
    each = sibling_scores(vertices, faces, loop, tests, siblings=o.siblings,
                          gap_rings=o.gap_rings, patch_rings=o.rings_in_patch, each=True)
    seconds_tests = time.perf_counter() - started
    between = _between(vertices, faces, fills, diameter, n_samples)
    return {"true": true, "hidden": hidden, "sibling": mean_scores(each), "between": between,
            "siblings_found": len(each),
            "crossed": candidates.crossed, "failure": failure, **shape,
            "seconds_lambda_h": seconds_lh, "seconds_tests": seconds_tests,
            **(extra(vertices, faces, fills, truth_vertices, truth_faces, diameter,
                     n_samples) if extra else {})}


def baseline_errors(path: Path | None) -> dict:
    """{(method, mesh, hole): mean %} of a saved validation run (``.json`` or ``.jsonl``);
    empty without one."""
    return validation._errors(read_rows([str(path)])) if path else {}


def _manifest_holes(split: str | None, meshes: list[str] | None):
    manifest = holes_manifest.read()
    for entry in manifest["meshes"]:
        if (split and entry["split"] != split) or (meshes and entry["mesh"] not in meshes):
            continue
        yield entry


def read_cache(path: Path) -> list[dict]:
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def build(cache: Path, split: str | None, meshes: list[str] | None,
          baseline: Path | None = None, options: ConformalOptions | None = None,
          extra=None) -> list[dict]:
    """The rows of the selected holes: from the cache, the missing ones computed and
    appended to it (a cache holds the rows of one set of ``options`` and ``extra``, see
    :func:`hole_scores`)."""
    base = baseline_errors(baseline)
    options = ConformalOptions() if options is None else options

    def compute(entry, k, hole, cut, local):
        row = hole_scores(local.vertices, local.faces, local.local_loop, cut.truth_vertices,
                          cut.truth_faces, cut.diameter, options=options, extra=extra)
        row = {"mesh": entry["mesh"], "hole": k, "split": entry["split"],
               "kind": entry["kind"], "n_edges": len(cut.loop),
               "near_border": hole["near_border"], "on_feature": hole["on_feature"],
               **row, "cgal": base.get(("cgal", entry["mesh"], k), float("nan")),
               "default_before": base.get(("conformal", entry["mesh"], k), float("nan"))}
        t = row["true"]
        print(f"{entry['mesh']} #{k}: fair2 {t['fair2']:.3g} fair3 {t['fair3']:.3g} "
              f"λ-H {t['conformal']:.3g} grown {row.get('grown')} "
              f"({row['seconds_tests']:.1f} s)", file=sys.stderr, flush=True)
        return row

    return cached_rows(cache, split, meshes, options, compute)


def cached_rows(cache: Path, split: str | None, meshes: list[str] | None,
                options: ConformalOptions, compute) -> list[dict]:
    """The rows of the selected holes of the manifest: those in ``cache`` read, the others
    made by ``compute(entry, k, hole, cut, local)`` (``local``: the hole's neighbourhood as
    :func:`surfinpaint.fill_holes` cuts it with ``options``' rings; warnings silenced) and
    appended to the cache."""
    have = {(r["mesh"], r["hole"]): r for r in read_cache(cache)}
    out = []
    for entry in _manifest_holes(split, meshes):
        todo = [k for k in range(len(entry["holes"])) if (entry["mesh"], k) not in have]
        mesh = vm.load_entry(entry) if todo else None
        for k, hole in enumerate(entry["holes"]):
            if (entry["mesh"], k) in have:
                out.append(have[(entry["mesh"], k)])
                continue
            cut = validation._cut(mesh, hole)
            local = FilledMesh(cut.vertices, cut.faces).cut(
                cut.loop, options.neighbourhood_rings(len(cut.loop)))
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                row = compute(entry, k, hole, cut, local)
            with cache.open("a") as fh:
                fh.write(json.dumps(row) + "\n")
            out.append(row)
    return out


def main(argv: list[str] | None = None) -> list[dict]:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--split", choices=("tuning", "validation"), default=None)
    parser.add_argument("--meshes", default=None, help="comma-separated mesh ids")
    parser.add_argument("--cache", required=True, help="JSONL file of rows (appended)")
    parser.add_argument("--baseline", default=None,
                        help="a validation.py run (its --out .json or .jsonl) for CGAL's and "
                        "the default's errors (else NaN)")
    parser.add_argument("--option", action="append", default=[], metavar="NAME=INT",
                        help="a ConformalOptions field of the self-check's tests, e.g. "
                        "siblings=4 (use a cache of its own)")
    args = parser.parse_args(argv)
    meshes = args.meshes.split(",") if args.meshes else None
    options = ConformalOptions(**{k: int(v) for k, v in (o.split("=", 1)
                                                          for o in args.option)})
    return build(Path(args.cache), args.split, meshes,
                 Path(args.baseline) if args.baseline else None, options)


if __name__ == "__main__":
    main()
