"""Thin parts (issue 14, session 12): a truth-free measure of how far a hole's ring wraps
around the part it sits on, against the λ-H fill's loss to the bilaplacian fill.

The measure, ``wrap``: over the faces within two rings of the hole's loop, one minus the
length of the area-weighted mean unit normal (0 on a flat ring; about 0.36 on a ring that
reaches half-way around a cylinder; 1 where the ring's normals cancel, a ring all around a
limb). It is computed before any fill, from the surface around the hole only.

    PYTHONPATH=src .venv/bin/python benchmarks/thin_parts.py quad OUT.jsonl      # 80 holes
    PYTHONPATH=src .venv/bin/python benchmarks/thin_parts.py tuning OUT.jsonl    # tuning half
    PYTHONPATH=src .venv/bin/python benchmarks/thin_parts.py --table OUT.jsonl [--base ROWS.jsonl]

``quad`` fills each hole of ``built_meshes.holes(quadruped)`` with the default fill
(self-check on) and with both faired fills, and records the errors (% of the hole's
diameter, ``eggcrate.error``); ``tuning`` records only ``wrap`` for the manifest's tuning
holes (cut as ``validation.py`` cuts them, on the neighbourhood ``fill_holes`` hands the
method), whose errors are in a saved validation run (``--base``).
"""
import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from surfinpaint.geometry.mesh import faces_near  # noqa: E402


def wrap(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, rings: int = 2) -> float:
    """One minus the length of the area-weighted mean unit normal of the faces within
    ``rings`` rings of ``loop`` (truth-free; 0 on a flat ring)."""
    near = faces_near(faces, np.asarray(loop), rings - 1, len(vertices))
    p = vertices[near]
    cross = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])  # 2 × area × unit normal
    return float(1.0 - np.linalg.norm(cross.sum(axis=0)) / np.linalg.norm(cross, axis=1).sum())


def quad_rows(out: Path) -> None:
    import built_meshes
    import eggcrate

    from surfinpaint.fill.conformal import conformal_fill
    from surfinpaint.fill.liepa.baseline import faired_fills
    v, f = built_meshes.quadruped()
    with out.open("w") as fh:
        for centre, radius, cut in built_meshes.holes(v, f):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                result = conformal_fill(cut.vertices, cut.faces, cut.loop)
                faired = faired_fills(cut.vertices, cut.faces, cut.loop, (2, 3))
            row = {"key": f"quad v{centre} r{radius}", "edges": len(cut.loop),
                   "wrap": wrap(cut.vertices, cut.faces, cut.loop), "kind": result.kind,
                   "fair_order": result.fair_order,
                   "default": eggcrate.error(cut, result.vertices, result.faces)}
            for k, (nv, nf, _) in faired.items():
                row[f"fair{k}"] = eggcrate.error(cut, nv, nf)
            fh.write(json.dumps(row) + "\n")
            fh.flush()
            print(json.dumps(row), flush=True)


def tuning_rows(out: Path) -> None:
    import holes_manifest
    import validation
    import validation_meshes as vm

    from surfinpaint.fill.conformal import ConformalOptions
    from surfinpaint.fill.neighbourhood import FilledMesh
    options = ConformalOptions()
    with out.open("w") as fh:
        for entry in holes_manifest.read()["meshes"]:
            if entry["split"] != "tuning":
                continue
            mesh = vm.load_entry(entry)
            for k, hole in enumerate(entry["holes"]):
                cut = validation._cut(mesh, hole)
                local = FilledMesh(cut.vertices, cut.faces).cut(
                    cut.loop, options.neighbourhood_rings(len(cut.loop)))
                row = {"key": f"{entry['mesh']} #{k}", "mesh": entry["mesh"], "hole": k,
                       "wrap": wrap(local.vertices, local.faces, local.local_loop)}
                fh.write(json.dumps(row) + "\n")
                print(json.dumps(row), flush=True)


def table(path: Path, base: Path | None) -> None:
    rows = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    if base is not None:
        err = {}
        for r in map(json.loads, base.read_text().splitlines()):
            if r.get("status") in ("ok", "fallback", "selected") and r.get("mean_pct") is not None:
                err[(r["method"], r["case"], r["hole"])] = r["mean_pct"]
        for r in rows:
            for m, name in (("fair", "fair2"), ("fair3", "fair3"), ("conformal", "default"),
                            ("conformal_raw", "raw")):
                r[name] = err.get((m, r["mesh"], r["hole"]), float("nan"))
    rows.sort(key=lambda r: -r["wrap"])
    print("| hole | wrap | fair2 | fair3 | default | default / fair2 |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['key']} | {r['wrap']:.3f} | {r['fair2']:.3g} | {r['fair3']:.3g} | "
              f"{r['default']:.3g} | {r['default'] / r['fair2']:.2f} |")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("family", nargs="?", choices=("quad", "tuning"))
    p.add_argument("out", nargs="?")
    p.add_argument("--table")
    p.add_argument("--base")
    a = p.parse_args()
    if a.table:
        table(Path(a.table), Path(a.base) if a.base else None)
        return
    {"quad": quad_rows, "tuning": tuning_rows}[a.family](Path(a.out))


if __name__ == "__main__":
    main()
