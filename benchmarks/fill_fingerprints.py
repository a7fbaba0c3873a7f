"""Fingerprints of the default fill on every tuning-side hole: did a change move anything?

A change on the fill path that should not move a written position (a refactor, a speed-up,
a rule that should not fire on the tuning side) is proven by filling every tuning-side hole
before and after it and comparing, hole by hole, two digests:

- ``geometry``: the written fill's new vertex positions (float64) and all its faces (int64),
  byte for byte;
- ``report``: the hole's report as text (method kept, fallback, notes, crease, crossings, the
  self-check's scores), so a change of a decision or of a score that did not change the fill
  is seen too.

The default sets are the 196 holes every rule is chosen on first: the benchmark's tuning half
(``holes_manifest.json``, split ``tuning``: 112 holes) and the tuning-side CAD parts
(``cad_tuning_manifest.json``: 84); ``--sets`` adds the other tuning-side sets (smooth_tuning,
curved_scans, thin_shells). Holdout sets and the validation half are refused: they are not
filled to choose anything.

Digests depend on the machine's floating point (CPU, BLAS): compare two runs made on one
machine. ``fill_fingerprints_reference.json`` is main's on all five tuning-side sets (409
holes; a check of fewer sets compares the holes both have), with the machine it was made on;
on another machine make a reference from main first::

    python benchmarks/fill_fingerprints.py --out before.json              # on main
    python benchmarks/fill_fingerprints.py --check before.json            # on the change
    python benchmarks/fill_fingerprints.py --check benchmarks/fill_fingerprints_reference.json

``--numpy-kernels`` fills with every numba kernel's numpy version instead (slower): checked
against a reference it shows that they give the compiled kernels' bits (session 43: all 196).
``--check`` prints how many holes kept both digests and each hole that did not, and exits 1
when a written position changed.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import platform
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np

# the compiled kernels on every fill, also on a cold numba cache: the digests are those of
# what a warm install writes (each numpy version should give the same bits; session 43 found
# one that did not, in the self-check's distances)
os.environ.setdefault("SURFINPAINT_COMPILE", "foreground")
sys.path.insert(0, str(Path(__file__).parent))
import holes_manifest  # noqa: E402
import validation  # noqa: E402

from surfinpaint import fill_holes  # noqa: E402

HERE = Path(__file__).parent
REFERENCE = HERE / "fill_fingerprints_reference.json"
SET_MANIFESTS = {
    "tuning": holes_manifest.MANIFEST,
    "cad_tuning": HERE / "cad_tuning_manifest.json",
    "smooth_tuning": HERE / "smooth_tuning_manifest.json",
    "curved_scans": HERE / "curved_scans_manifest.json",
    "thin_shells": HERE / "thin_shells_manifest.json",
}
DEFAULT_SETS = ("tuning", "cad_tuning")


def _digest(*parts: bytes) -> str:
    h = hashlib.sha256()
    for p in parts:
        h.update(p)
    return h.hexdigest()[:16]


def report_text(report) -> str:
    """The parts of a hole's report that say what was decided and why, as one line of text
    (the self-check's scores in full: a score that moved is a change even where the same
    fill was kept)."""
    d = report.diagnostics
    lambda_h = None if d is None else (d.rings, d.damping, d.blended_with, d.note)
    return repr((report.requested, report.method, report.fallback, report.note, report.skipped,
                 report.fair_order, report.crease, report.crease_failure, report.crossings,
                 report.failed, report.islands, report.verdict, report.plane, lambda_h))


def fingerprint(cut) -> dict:
    """The two digests of the default fill of one cut hole."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = fill_holes(cut.vertices, cut.faces, holes=[cut.loop])
    new = np.ascontiguousarray(np.asarray(res.vertices)[len(cut.vertices):], dtype=np.float64)
    faces = np.ascontiguousarray(res.faces, dtype=np.int64)
    text = "\n".join(report_text(r) for r in res.reports)
    return {"geometry": _digest(new.tobytes(), faces.tobytes()),
            "report": _digest(text.encode()), "written": res.reports[0].method}


def tuning_entries(sets: list[str]) -> list[tuple[str, dict]]:
    """(set name, manifest entry) of every tuning-side mesh of ``sets``."""
    out = []
    for name in sets:
        if name not in SET_MANIFESTS:
            raise SystemExit(f"fill_fingerprints: {name!r} is not a tuning-side set; choose "
                             f"from {', '.join(SET_MANIFESTS)} (holdout sets and the "
                             "validation half are never filled to choose anything)")
        manifest = holes_manifest.read(SET_MANIFESTS[name])
        out += [(name, e) for e in manifest["meshes"] if e["split"] == name]
    return out


def run(sets: list[str], meshes: list[str] | None = None) -> dict[str, dict]:
    """Fingerprints of every hole, keyed ``set/mesh#k``."""
    holes = {}
    for name, entry in tuning_entries(sets):
        if meshes and entry["mesh"] not in meshes:
            continue
        # a mesh this machine cannot make as committed has no comparable fills: skipped, and
        # said so (its holes are then missing from both sides of a --check)
        mesh = validation.loaded_or_none(entry, f"{name}/{entry['mesh']}")
        if mesh is None:
            continue
        for k, hole in enumerate(entry["holes"]):
            key = f"{name}/{entry['mesh']}#{k}"
            holes[key] = fingerprint(validation._cut(mesh, hole))
            print(f"{key}: {holes[key]['written']} {holes[key]['geometry']} "
                  f"{holes[key]['report']}", file=sys.stderr, flush=True)
    return holes


def compare(now: dict[str, dict], reference: dict[str, dict]) -> tuple[list[str], list[str]]:
    """The holes whose geometry differs, and those whose report alone differs (holes in only
    one of the two are not compared)."""
    common = [k for k in now if k in reference]
    geometry = [k for k in common if now[k]["geometry"] != reference[k]["geometry"]]
    report = [k for k in common if k not in geometry
              and now[k]["report"] != reference[k]["report"]]
    return geometry, report


def _machine() -> dict:
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=HERE,
                                capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    import scipy
    cpu, flags = platform.machine(), ""
    try:  # Linux: the CPU's name and the vector units BLAS may choose its kernels by
        info = Path("/proc/cpuinfo").read_text().splitlines()
        cpu = next(ln.split(":", 1)[1].strip() for ln in info if ln.startswith("model name"))
        have = next(ln.split(":", 1)[1].split() for ln in info if ln.startswith("flags"))
        flags = " ".join(f for f in ("avx2", "avx512f", "fma") if f in have)
    except (OSError, StopIteration):
        pass
    return {"commit": commit, "machine": f"{cpu} ({flags})" if flags else cpu,
            "python": platform.python_version(), "numpy": np.__version__,
            "scipy": scipy.__version__}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sets", default=",".join(DEFAULT_SETS),
                        help=f"comma-separated, from {', '.join(SET_MANIFESTS)}")
    parser.add_argument("--meshes", default=None, help="comma-separated mesh ids (a subset)")
    parser.add_argument("--out", default=None, help="write the fingerprints as JSON here")
    parser.add_argument("--check", default=None, help="compare with this earlier --out")
    parser.add_argument("--numpy-kernels", action="store_true",
                        help="fill with every numba kernel's numpy version (each should give "
                        "the compiled kernel's digests)")
    args = parser.parse_args(argv)
    if args.numpy_kernels:
        from surfinpaint import compiled
        compiled.Kernel.get = lambda self: None  # run() then calls the numpy version
    sets = args.sets.split(",")
    holes = run(sets, args.meshes.split(",") if args.meshes else None)
    if args.out:
        Path(args.out).write_text(json.dumps({"made_with": _machine(), "sets": sets,
                                              "holes": holes}, indent=1) + "\n")
    if not args.check:
        return 0
    ref = json.loads(Path(args.check).read_text())
    geometry, report = compare(holes, ref["holes"])
    n = sum(k in ref["holes"] for k in holes)
    print(f"against {args.check} (made on {ref['made_with']['commit']}): geometry "
          f"{n - len(geometry)}/{n} the same, reports {n - len(geometry) - len(report)}/{n}")
    for k in geometry:
        print(f"  geometry differs: {k} (written {ref['holes'][k]['written']} -> "
              f"{holes[k]['written']})")
    for k in report:
        print(f"  report differs:   {k}")
    return 1 if geometry else 0


if __name__ == "__main__":
    raise SystemExit(main())
