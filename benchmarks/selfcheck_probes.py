"""Holes beyond the manifest, on tuning-side data only, where the λ-H fill's patch is thin:
does a grown patch (``fill/conformal/patch.grown_patch``) warn that the λ-H fill is worse?

Two sets (rows in the format of ``selfcheck_table.py``, appended to a JSONL cache):

- ``random``: holes of 4, 6, 8, 10 edge lengths at random vertices of every tuning mesh (a
  seed of their own, not the manifest's), scored in full only where the fill's disk patch
  keeps fewer than 3 rings (``MIN_RINGS`` of the mesh pass);
- ``thin``: holes of 3–11 edge lengths on thin tori (``data.torus``, tube radius 0.1–0.2,
  16–32 edges around the tube), every hole scored.

    python benchmarks/selfcheck_probes.py --set thin --cache /tmp/probes.jsonl
    python benchmarks/selfcheck_replay.py --cache /tmp/probes.jsonl --split thin
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
import selfcheck_table  # noqa: E402
import validation  # noqa: E402
import validation_meshes as vm  # noqa: E402

from surfinpaint import data  # noqa: E402
from surfinpaint.fill.conformal import ConformalOptions  # noqa: E402
from surfinpaint.fill.conformal.candidates import Candidates  # noqa: E402
from surfinpaint.fill.conformal.patch import is_disk  # noqa: E402
from surfinpaint.fill.neighbourhood import FilledMesh  # noqa: E402 - fill_holes' neighbourhood
from surfinpaint.geometry.cutting import cut_geodesic_disk  # noqa: E402
from surfinpaint.geometry.mesh import faces_near, mean_edge_length  # noqa: E402

THIN_TORI = {"torus_r10_16": (0.10, 16), "torus_r15_24": (0.15, 24),
             "torus_r20_32": (0.20, 32)}


def _disk_rings(faces, loop, fill_faces, rings) -> int:
    n = int(max(faces.max(), fill_faces.max())) + 1
    return next((k for k in range(rings, 0, -1) if is_disk(np.concatenate(
        [fill_faces, faces_near(faces, loop, k - 1, n)]))), 0)


def _scored(cut, options, name, hole, r_h, split, only_thin: bool) -> dict | None:
    local = FilledMesh(cut.vertices, cut.faces).cut(
        cut.loop, options.neighbourhood_rings(len(cut.loop)))
    v, f, loop = local.vertices, local.faces, local.local_loop
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if only_thin:
            fair3 = Candidates.for_hole(v, f, loop, options).faired(v, f, loop)["fair3"]
            if _disk_rings(f, loop, fair3.faces, options.rings_in_patch) >= 3:
                return None
        row = selfcheck_table.hole_scores(v, f, loop, cut.truth_vertices, cut.truth_faces,
                                          cut.diameter, options=options)
    return {"mesh": name, "hole": hole, "split": split, "radius_h": r_h,
            "n_edges": len(cut.loop), **row}


def random_cuts(per_mesh: int, checked: list):
    """``per_mesh`` random holes per tuning mesh, those that can be cut: (mesh id, centre
    vertex, radius in h, cut); ``checked`` gets the number cut on each mesh."""
    tuning = [e["mesh"] for e in holes_manifest.read()["meshes"] if e["split"] == "tuning"]
    for mesh_id in tuning:
        checked.append(0)
        mesh = vm.load(mesh_id)
        h = mean_edge_length(mesh.vertices, mesh.faces)
        rng = np.random.default_rng(4242)
        for i, c in enumerate(rng.permutation(len(mesh.vertices))[:per_mesh]):
            r_h = (4, 6, 8, 10)[i % 4]
            try:
                cut = validation._cut(mesh, {"centre": mesh.vertices[c], "radius": r_h * h})
            except ValueError:
                continue
            checked[-1] += 1
            yield mesh_id, int(c), r_h, cut


def random_holes(per_mesh: int, options: ConformalOptions, checked: list,
                 keys: set[str] | None = None):
    """The thin holes among ``per_mesh`` random ones per tuning mesh (with ``keys``, the
    holes named "mesh vCENTRE rRADIUS" instead, thin or not); ``checked`` gets the number
    of holes cut and checked on each mesh."""
    for mesh_id, c, r_h, cut in random_cuts(per_mesh, checked):
        if keys is not None and f"{mesh_id} v{c} r{r_h}" not in keys:
            continue
        row = _scored(cut, options, mesh_id, c, r_h, "random", only_thin=keys is None)
        if row is not None:
            yield row


def thin_cuts():
    """The holes on the thin tori that can be cut: (torus name, hole number, radius in h,
    cut)."""
    for name, (r, n_minor) in THIN_TORI.items():
        v, f = data.torus(R=1.0, r=r, n_major=160, n_minor=n_minor)
        h = mean_edge_length(v, f)
        rng = np.random.default_rng(7)
        centres = rng.permutation(len(v))
        for i, r_h in enumerate((3, 4, 5, 6, 3, 4, 5, 6, 8, 9, 10, 11, 8, 9)):
            try:
                cut = cut_geodesic_disk(v, f, int(centres[i]), r_h * h)
            except ValueError:
                continue
            yield name, i, r_h, cut


def thin_holes(options: ConformalOptions):
    for name, i, r_h, cut in thin_cuts():
        yield _scored(cut, options, name, i, r_h, "thin", only_thin=False)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--set", choices=("random", "thin"), required=True)
    parser.add_argument("--per-mesh", type=int, default=40)
    parser.add_argument("--cache", required=True)
    parser.add_argument("--keys", default=None, help="random set: score only these holes "
                        "(a file of keys 'mesh vCENTRE rRADIUS', one a line, as "
                        "selfcheck_coverage.py names them)")
    args = parser.parse_args(argv)
    options = ConformalOptions()
    checked: list[int] = []
    keys = set(Path(args.keys).read_text().splitlines()) if args.keys else None
    rows = (random_holes(args.per_mesh, options, checked, keys) if args.set == "random"
            else thin_holes(options))
    n = 0
    with Path(args.cache).open("a") as fh:
        for row in rows:
            fh.write(json.dumps(row) + "\n")
            fh.flush()
            n += 1
            t = row["true"]
            print(f"{row['mesh']} #{row['hole']} r={row['radius_h']}h: grown {row.get('grown')}"
                  f" fair2 {t['fair2']:.3g} fair3 {t['fair3']:.3g} λ-H {t['conformal']:.3g}",
                  file=sys.stderr, flush=True)
    print(f"{args.set}: {n} holes scored" + (f" of {sum(checked)} cut and checked"
                                             if checked else ""), file=sys.stderr)


if __name__ == "__main__":
    main()
