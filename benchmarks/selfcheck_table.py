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
    python benchmarks/selfcheck_table.py --manifest benchmarks/holdout24_manifest.json \
        --baseline /work/s48/holdout24.json --library --cache /tmp/h24.jsonl

Any tuning-side manifest or spent holdout manifest (9-27) can be read (``--manifest``; the
guard is ``cgal_s0._studied``: never the validation half nor a fresh holdout). With
``--library`` each row also says what the library wrote and why (``library``: the
``HoleReport``'s method, fairing order, note, the verdict's keep / faired / reference / lost
and the scores it saw, the plane test, the noise gate's smoothing and estimate, the crease)
and that fill's true error (session 49).

Rows already in the cache are not computed again: a replay of rules is instant.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import cgal_s0  # noqa: E402 - its guard: the sets a study may look at
import holes_manifest  # noqa: E402
import validation  # noqa: E402
import validation_meshes as vm  # noqa: E402
from variant_rows import read_rows  # noqa: E402

from surfinpaint import fill_holes  # noqa: E402
from surfinpaint.errors import FillError  # noqa: E402
from surfinpaint.fill.conformal import ConformalOptions  # noqa: E402
from surfinpaint.fill.conformal.candidates import Candidates  # noqa: E402
from surfinpaint.fill.conformal.patch import hole_patch, is_disk  # noqa: E402
from surfinpaint.fill.neighbourhood import FilledMesh  # noqa: E402 - fill_holes' neighbourhood
from surfinpaint.fill.selfcheck import (  # noqa: E402
    advantages_over,
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
    hidden_detail: dict = {}
    sibling_detail: list = []
    hidden = hidden_ring_scores(vertices, faces, loop, tests, hide_rings=o.hide_rings,
                                patch_rings=o.rings_in_patch, detail=hidden_detail)
    each = sibling_scores(vertices, faces, loop, tests, siblings=o.siblings,
                          gap_rings=o.gap_rings, patch_rings=o.rings_in_patch, each=True,
                          detail=sibling_detail)
    seconds_tests = time.perf_counter() - started
    # each candidate's paired advantage over fair2 and its standard error, per test: what
    # the significance cut (``selection.demoted``) weighs (session 49)
    advantages = advantages_over(hidden_detail, sibling_detail, "fair2")
    between = _between(vertices, faces, fills, diameter, n_samples)
    return {"true": true, "hidden": hidden, "sibling": mean_scores(each), "between": between,
            "advantages": advantages,
            "siblings_found": len(each),
            "crossed": candidates.crossed, "failure": failure, **shape,
            "seconds_lambda_h": seconds_lh, "seconds_tests": seconds_tests,
            **(extra(vertices, faces, fills, truth_vertices, truth_faces, diameter,
                     n_samples) if extra else {})}


def baseline_errors(path: Path | None) -> dict:
    """{(method, mesh, hole): mean %} of a saved validation run (``.json`` or ``.jsonl``);
    empty without one."""
    return validation._errors(read_rows([str(path)])) if path else {}


def _manifest_holes(split: str | None, meshes: list[str] | None, manifest: Path | None = None):
    """The selected entries of ``manifest`` (the tuning/validation halves' by default);
    refuses an entry a study must not look at where ``manifest`` is given."""
    for entry in holes_manifest.read(manifest or holes_manifest.MANIFEST)["meshes"]:
        if (split and entry["split"] != split) or (meshes and entry["mesh"] not in meshes):
            continue
        if manifest is not None and not cgal_s0._studied(entry):
            raise SystemExit(f"{entry['mesh']} is in {entry['split']}: study the tuning side "
                             f"and the spent holdouts 9-{cgal_s0.NEWEST_SPENT_HOLDOUT} only")
        yield entry


def _plain(value):
    """``value`` as JSON can hold it (dataclasses as dicts, arrays as lists)."""
    if dataclasses.is_dataclass(value):
        return {f.name: _plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (np.floating, np.integer, np.bool_)):
        return value.item()
    return value


def library_row(cut, n_samples: int = 10000) -> dict:
    """What ``fill_holes`` (the default conformal method) wrote for the hole and why, as
    ``validation.py``'s ``conformal`` column fills it (the whole cut mesh), and the true
    error of what it wrote (% of the hole diameter; inf where nothing was written)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fill_holes(cut.vertices, cut.faces, holes=[cut.loop], method="conformal")
    r = res.reports[0]
    v = r.verdict
    written = len(res.faces) > len(cut.faces)
    true = (100.0 * surface_distance(*hole_patch_of(np.asarray(res.vertices),
                                                    np.asarray(res.faces), len(cut.vertices),
                                                    cut.faces),
                                     cut.truth_vertices, cut.truth_faces,
                                     n_samples=n_samples).mean / cut.diameter
            if written else INF)
    smoothing = r.smoothing
    return {"method": r.method, "fair_order": r.fair_order, "note": r.note,
            "fallback": r.fallback, "plane": r.plane is not None, "ear_cut": r.ear_cut,
            "crease": r.crease,
            "crease_failure": r.crease_failure, "smoothed": r.smoothed,
            "smoothing": None if smoothing is None else {
                "length": smoothing.length, "why": smoothing.why,
                "noise": _plain(smoothing.noise)},
            "verdict": None if v is None else {
                "keep": v.keep, "make": v.make, "faired": v.faired, "reference": v.reference,
                "hidden": _plain(v.hidden), "sibling": _plain(v.sibling), "lost": list(v.lost)},
            "blended_with": (r.diagnostics.blended_with if r.diagnostics is not None
                             else None),
            "true": true}


def read_cache(path: Path) -> list[dict]:
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def build(cache: Path, split: str | None, meshes: list[str] | None,
          baseline: Path | list[Path] | None = None, options: ConformalOptions | None = None,
          extra=None, manifest: Path | None = None, library: bool = False) -> list[dict]:
    """The rows of the selected holes: from the cache, the missing ones computed and
    appended to it (a cache holds the rows of one set of ``options`` and ``extra``, see
    :func:`hole_scores`; ``library``: with :func:`library_row` as ``row["library"]``)."""
    base = {}
    for path in (baseline if isinstance(baseline, list) else [baseline] if baseline else []):
        base.update(baseline_errors(path))
    options = ConformalOptions() if options is None else options

    def compute(entry, k, hole, cut, local):
        row = hole_scores(local.vertices, local.faces, local.local_loop, cut.truth_vertices,
                          cut.truth_faces, cut.diameter, options=options, extra=extra)
        row = {"mesh": entry["mesh"], "hole": k, "split": entry["split"],
               "kind": entry["kind"], "n_edges": len(cut.loop),
               "near_border": hole["near_border"], "on_feature": hole["on_feature"],
               **row, "cgal": base.get(("cgal", entry["mesh"], k), float("nan")),
               "default_before": base.get(("conformal", entry["mesh"], k), float("nan"))}
        if library:
            row["library"] = library_row(cut)
        t = row["true"]
        print(f"{entry['mesh']} #{k}: fair2 {t['fair2']:.3g} fair3 {t['fair3']:.3g} "
              f"λ-H {t['conformal']:.3g} grown {row.get('grown')} "
              f"({row['seconds_tests']:.1f} s)", file=sys.stderr, flush=True)
        return row

    return cached_rows(cache, split, meshes, options, compute, manifest)


def cached_rows(cache: Path, split: str | None, meshes: list[str] | None,
                options: ConformalOptions, compute, manifest: Path | None = None
                ) -> list[dict]:
    """The rows of the selected holes of the manifest: those in ``cache`` read, the others
    made by ``compute(entry, k, hole, cut, local)`` (``local``: the hole's neighbourhood as
    :func:`surfinpaint.fill_holes` cuts it with ``options``' rings; warnings silenced) and
    appended to the cache."""
    have = {(r["mesh"], r["hole"]): r for r in read_cache(cache)}
    out = []
    for entry in _manifest_holes(split, meshes, manifest):
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
    parser.add_argument("--split", default=None,
                        help="the manifest's split to read (tuning, or a set's own name)")
    parser.add_argument("--manifest", default=None,
                        help="a tuning-side or spent holdout (9-27) manifest (default: the "
                        "halves' benchmarks/holes_manifest.json, unguarded as before)")
    parser.add_argument("--library", action="store_true",
                        help="also what the library wrote for each hole and why (library_row)")
    parser.add_argument("--meshes", default=None, help="comma-separated mesh ids")
    parser.add_argument("--cache", required=True, help="JSONL file of rows (appended)")
    parser.add_argument("--baseline", default=None,
                        help="validation.py runs (their --out .json or .jsonl, comma-separated) "
                        "for CGAL's and the default's errors (else NaN)")
    parser.add_argument("--option", action="append", default=[], metavar="NAME=INT",
                        help="a ConformalOptions field of the self-check's tests, e.g. "
                        "siblings=4 (use a cache of its own)")
    args = parser.parse_args(argv)
    meshes = args.meshes.split(",") if args.meshes else None
    options = ConformalOptions(**{k: int(v) for k, v in (o.split("=", 1)
                                                          for o in args.option)})
    return build(Path(args.cache), args.split, meshes,
                 [Path(b) for b in args.baseline.split(",")] if args.baseline else None,
                 options, manifest=Path(args.manifest) if args.manifest else None,
                 library=args.library)


if __name__ == "__main__":
    main()
