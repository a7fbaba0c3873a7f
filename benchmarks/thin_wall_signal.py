"""How close the surface's far side comes to a hole, truth-free, for the holes of a tuning-side
set (session 41: the λ-H fill kept where it loses on thin walls; docs/selfcheck.md "Session 41
(helper)").

For a hole (its loop on the cut mesh), the *far side* is every vertex of the mesh whose
geodesic distance from the loop (Dijkstra along edges) exceeds ``FAR`` × the hole's diameter,
or that cannot be reached (another component): on a wall a few edges thick, the wall's other
face is close in space but far along the surface. Signals, each over the hole's diameter (the
largest distance between two loop vertices):

- ``gap loop``: the nearest far-side vertex to any loop vertex;
- ``gap centre``: the nearest far-side vertex to the loop's centroid;
- ``wrap``: session 12's measure of how far the ring wraps round the part
  (:func:`thin_parts.wrap`, not over the diameter).

Optionally (``--patches``), for holes of the study's rows where the λ-H fill was written, the
λ-H fill is made again (``conformal_raw``) and its new vertices' nearest far-side distance is
recorded over the diameter (``patch gap``): whether the patch approaches the opposite wall.

    python benchmarks/thin_wall_signal.py --set thin_shells --out signals.jsonl
    python benchmarks/thin_wall_signal.py --table signals.jsonl --rows study.jsonl
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import smooth_selfcheck_study as study  # noqa: E402
import thin_parts  # noqa: E402

# the far side: geodesically farther from the loop than this many hole diameters
FAR = 2.0


def far_side(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
             far: float = FAR) -> tuple[np.ndarray, float]:
    """(far-side vertex ids, the hole's diameter): vertices used by ``faces`` whose geodesic
    distance along edges from ``loop`` exceeds ``far`` × the diameter (or unreachable)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    pts = vertices[loop]
    diameter = float(np.sqrt(((pts[:, None] - pts[None]) ** 2).sum(-1)).max())
    # each edge once: a sparse matrix sums duplicate entries, which would double the
    # lengths of edges shared by two faces
    e = np.unique(np.sort(np.vstack([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]),
                          axis=1), axis=0)
    w = np.linalg.norm(vertices[e[:, 0]] - vertices[e[:, 1]], axis=1)
    n = len(vertices)
    graph = coo_matrix((np.r_[w, w], (np.r_[e[:, 0], e[:, 1]], np.r_[e[:, 1], e[:, 0]])),
                       shape=(n, n)).tocsr()
    geo = dijkstra(graph, directed=False, indices=loop, min_only=True,
                   limit=far * diameter * 1.0001)
    used = np.zeros(n, bool)
    used[faces.ravel()] = True
    return np.flatnonzero(used & ~(geo <= far * diameter)), diameter


def wall_signals(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                 far: float = FAR) -> dict:
    """The hole's truth-free thin-wall signals (module docstring); inf where nothing is far."""
    from scipy.spatial import cKDTree

    ids, diameter = far_side(vertices, faces, loop, far)
    wrapped = thin_parts.wrap(vertices, faces, loop)
    if len(ids) == 0:
        return {"diameter": diameter, "wrap": wrapped, "gap loop": np.inf,
                "gap centre": np.inf}
    tree = cKDTree(vertices[ids])
    pts = vertices[loop]
    return {"diameter": diameter, "wrap": wrapped,
            "gap loop": float(tree.query(pts)[0].min()) / diameter,
            "gap centre": float(tree.query(pts.mean(0))[0]) / diameter}


def patch_gap(vertices, faces, loop, far: float = FAR) -> float:
    """The λ-H fill's (``conformal_raw``) new vertices' nearest far-side vertex, over the
    hole's diameter (nan where the fill fell back)."""
    import warnings

    import accuracy
    from scipy.spatial import cKDTree

    ids, diameter = far_side(vertices, faces, loop, far)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        v, _, _, note = accuracy.run_method("conformal_raw", vertices, faces, loop)
    new = v[len(vertices):]
    if note or not len(new) or not len(ids):
        return float("nan")
    return float(cKDTree(vertices[ids]).query(new)[0].min()) / diameter


def run(which: str, out: Path, meshes=None, patches: set | None = None) -> None:
    with out.open("a") as fh:
        for mesh_id, _, k, _, cut in study.holes_of(which, meshes):
            row = {"set": which, "mesh": mesh_id, "hole": k,
                   **wall_signals(cut.vertices, cut.faces, np.asarray(cut.loop))}
            if patches is not None and (mesh_id, k) in patches:
                row["patch gap"] = patch_gap(cut.vertices, cut.faces, np.asarray(cut.loop))
            fh.write(json.dumps(row) + "\n")
            fh.flush()
            print(which, mesh_id, k, {a: round(b, 4) for a, b in row.items()
                                      if isinstance(b, float)}, file=sys.stderr, flush=True)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--set", choices=(*study.SETS, "animals"))
    parser.add_argument("--out", type=Path)
    parser.add_argument("--meshes", default=None)
    parser.add_argument("--patches", type=Path, default=None,
                        help="study rows: remake the λ-H fill where it was written")
    parser.add_argument("--table", nargs="+", default=None, help="signal rows to screen")
    parser.add_argument("--rows", nargs="+", default=None, help="the study's rows")
    parser.add_argument("--instead", choices=("fair2", "fair3"), default=None,
                        help="screen writing this fill instead of a kept λ-H fill")
    args = parser.parse_args(argv)
    if args.table:
        print(screen(study.read(*args.table), study.read(*args.rows), args.instead))
        return
    patches = None
    if args.patches:
        patches = {(r["mesh"], r["hole"]) for r in study.read(args.patches)
                   if r["evidence"] is not None
                   and study.library_rule(r["evidence"]) == "conformal"}
    run(args.set, args.out, args.meshes.split(",") if args.meshes else None, patches)



def screen(signal_rows: list[dict], study_rows: list[dict], instead: str | None = None) -> str:
    """Each signal's best one-sided threshold over the holes where the library keeps the λ-H
    fill: the faired fill the self-check would write without it (``study._faired``; or
    ``instead``, "fair2" or "fair3", when given) instead, catching holes where the λ-H fill
    is 1.5× farther than that fill, less those where it is 1.5× closer
    (:func:`smooth_selfcheck_study.best_threshold`)."""
    by = {(r["set"], r["mesh"], r["hole"]): r for r in signal_rows}
    kept = [r for r in study_rows if r["evidence"] is not None
            and study.library_rule(r["evidence"]) == "conformal"
            and (r["set"], r["mesh"], r["hole"]) in by]
    lh = np.array([study.outcome(r, "conformal") for r in kept])
    other = np.array([study.outcome(r, instead or study._faired(r["evidence"])) for r in kept])
    ratio = lh / other
    names = [k for k in ("gap loop", "gap centre", "wrap", "patch gap")
             if any(k in by[(r["set"], r["mesh"], r["hole"])] for r in kept)]
    lines = [f"{len(kept)} holes where the λ-H fill is kept: 1.5× farther than "
             f"{instead or 'the faired fill written without it'} on "
             f"{int((ratio >= 1.5).sum())}, 1.5× closer on "
             f"{int((ratio <= 1 / 1.5).sum())}", "",
             "| signal | best threshold | holes switched | λ-H 1.5× farther among them | "
             "λ-H 1.5× closer among them |", "|---|---|---|---|---|"]
    for name in names:
        values = np.array([by[(r["set"], r["mesh"], r["hole"])].get(name, np.nan)
                           for r in kept], float)
        best = study.best_threshold(values, ratio)
        lines.append(f"| {name} | — | 0 | 0 | 0 |" if best is None else
                     f"| {name} | {best['side']} {best['threshold']:.3g} | {best['switched']} | "
                     f"{best['caught']} | {best['broken']} |")
    lines += ["", "| hole | λ-H / faired instead | " + " | ".join(names) + " |",
              "|---" * (len(names) + 2) + "|"]
    for x, r in sorted(zip(ratio, kept, strict=True), key=lambda p: -p[0]):
        s = by[(r["set"], r["mesh"], r["hole"])]
        lines.append(f"| {r['set']} {r['mesh']} #{r['hole']} | {x:.2f} | "
                     + " | ".join(f"{s.get(n, np.nan):.3f}" for n in names) + " |")
    return "\n".join(lines)


if __name__ == "__main__":
    main()
