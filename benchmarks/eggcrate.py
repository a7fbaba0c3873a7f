"""The egg-crate family of docs/convergence.md: holes in strongly curved, irregular height
fields where the lagged λ-H iteration diverges (issue 20). Prints one row per hole (the λ-H
fill's outcome, its failure reason, its error and the faired fills') and the fallback count.

    PYTHONPATH=src .venv/bin/python benchmarks/eggcrate.py [--out rows.jsonl] [--errors]

The family: 20² and 30² grids on the unit square, each vertex jittered by 0.3-0.4 of the
spacing h (6 seeds), z = a h cos(2πx / (p h)) cos(2πy / (p h)) for five (period p,
amplitude a, jitter) triples, a geodesic disk of radius 4h, 5h or 6h cut at the centre:
180 holes. Curvature radius ~1-2 edge lengths, as on a white-matter sulcus.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from surfinpaint import ConformalOptions
from surfinpaint.fill.conformal import conformal_fill
from surfinpaint.fill.liepa.baseline import faired_fill
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.metrics import hole_patch_of, surface_distance

FAMILY = ((5, 1.5, 0.4), (6, 2.0, 0.4), (7, 2.5, 0.4), (8, 3.0, 0.4), (6, 2.5, 0.3))
SIZES = (20, 30)
SEEDS = range(6)
RADII = (4, 5, 6)


def grid(n: int) -> tuple[np.ndarray, np.ndarray]:
    """A flat (n+1)² vertex grid on the unit square, two triangles per cell."""
    i, j = np.meshgrid(np.arange(n + 1), np.arange(n + 1), indexing="ij")
    vertices = np.column_stack([i.ravel() / n, j.ravel() / n, np.zeros(i.size)])
    a = (i[:-1, :-1] * (n + 1) + j[:-1, :-1]).ravel()
    b, c, d = a + (n + 1), a + (n + 1) + 1, a + 1
    return vertices, np.concatenate([np.column_stack([a, b, c]),
                                     np.column_stack([a, c, d])]).astype(np.int64)


def egg_crate(n: int, seed: int, period: float, amplitude: float, jitter: float,
              radius: int):
    """One hole of the family (a :class:`~surfinpaint.geometry.cutting.CutDisk`)."""
    flat, faces = grid(n)
    h = 1.0 / n
    shift = np.random.default_rng(seed).uniform(-1, 1, size=(len(flat), 2))
    v = flat.copy()
    v[:, :2] += jitter * shift * h
    wave = 2 * np.pi / (period * h)
    v[:, 2] = amplitude * h * np.cos(wave * v[:, 0]) * np.cos(wave * v[:, 1])
    centre = np.argmin(np.linalg.norm(flat[:, :2] - 0.5, axis=1))
    return cut_geodesic_disk(v, faces, centre, radius * h)


def error(cut, new_v, new_f) -> float:
    """Two-sided mean distance to the removed truth, % of the hole's diameter."""
    vertices = np.vstack([cut.vertices, new_v])
    pv, pf = hole_patch_of(vertices, np.vstack([cut.faces, new_f]), len(cut.vertices),
                           cut.faces)
    d = surface_distance(pv, pf, cut.truth_vertices, cut.truth_faces, n_samples=4000)
    return 100.0 * d.mean / cut.diameter


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", help="write the rows here (JSON lines)")
    parser.add_argument("--errors", action="store_true",
                        help="also measure the errors of the λ-H and faired fills")
    parser.add_argument("--sizes", default=",".join(map(str, SIZES)))
    args = parser.parse_args()
    raw = ConformalOptions(select=False)
    rows = []
    for n in map(int, args.sizes.split(",")):
        for seed in SEEDS:
            for period, amplitude, jitter in FAMILY:
                for radius in RADII:
                    cut = egg_crate(n, seed, period, amplitude, jitter, radius)
                    start = time.perf_counter()
                    result = conformal_fill(cut.vertices, cut.faces, cut.loop, raw)
                    row = dict(n=n, seed=seed, period=period, amplitude=amplitude,
                               jitter=jitter, radius=radius, kind=result.kind,
                               failure=result.failure,
                               seconds=round(time.perf_counter() - start, 3))
                    if args.errors:
                        row["error"] = error(cut, result.vertices, result.faces)
                        for order in (2, 3):
                            fv, ff, _ = faired_fill(cut.vertices, cut.faces, cut.loop, order)
                            row[f"fair{order}"] = error(cut, fv, ff)
                    rows.append(row)
                    print(json.dumps(row), flush=True)
    failed = [r for r in rows if r["kind"] != "conformal"]
    print(f"fell back on {len(failed)} / {len(rows)} holes")
    if args.out:
        with open(args.out, "w") as fh:
            fh.writelines(json.dumps(r) + "\n" for r in rows)


if __name__ == "__main__":
    main()
