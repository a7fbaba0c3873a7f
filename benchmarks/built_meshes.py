"""The λ-H fill on meshes built as real ones are (issue 20): a coarse quadruped and a
genus-6 plate, boolean unions from manifold3d (a CAD tessellation: slivers with corners
down to 0.02°, sharp junctions); also a leg with a hoof (:func:`foot`, for the λ-H
representation's benchmark, benchmarks/represent_speed.py). Cuts geodesic disks of
radius 2h and 3.5h at 40 seeded random vertices (holes the cutter refuses are skipped),
fills each with the λ-H fill (``select=False``) and prints every fallback with its reason,
then the count.

    PYTHONPATH=src .venv/bin/python benchmarks/built_meshes.py [quadruped|plate] [--refine L]

``--refine L`` first splits every edge longer than L (manifold3d's ``refine_to_length``).
The tests (tests/test_built_meshes.py) use these meshes.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from surfinpaint import ConformalOptions
from surfinpaint.fill.conformal import conformal_fill
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import mean_edge_length


def _mesh(solid) -> tuple[np.ndarray, np.ndarray]:
    mesh = solid.to_mesh()
    return (np.asarray(mesh.vert_properties, dtype=float)[:, :3],
            np.asarray(mesh.tri_verts, dtype=np.int64))


def quadruped(refine: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A low-poly animal: an ellipsoid body, head, neck, four legs, a tail and two ears
    (520 vertices; the limbs 12 edges around and one edge long)."""
    import manifold3d as m3

    shape = m3.Manifold
    parts = [shape.sphere(1.0, 24).scale([1.6, 0.7, 0.7]),
             shape.sphere(0.45, 24).translate([2.0, 0, 0.7]),
             shape.cylinder(1.1, 0.28, 0.25, 12).rotate([0, 55, 0]).translate([1.2, 0, 0.2]),
             shape.cylinder(1.2, 0.08, 0.03, 8).rotate([0, -60, 0]).translate([-1.5, 0, 0.2])]
    parts += [shape.cylinder(1.4, 0.18, 0.14, 12).translate([x, y, -1.6])
              for x in (-1.0, 1.0) for y in (-0.35, 0.35)]
    parts += [shape.cylinder(0.35, 0.1, 0.0, 6).translate([2.0, s * 0.2, 1.05])
              for s in (-1, 1)]
    solid = shape.batch_boolean(parts, m3.OpType.Add)
    return _mesh(solid.refine_to_length(refine) if refine else solid)


def plate(refine: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A 6 × 2 × 0.5 plate with six round through-holes: genus 6 (200 vertices)."""
    import manifold3d as m3

    holes = [m3.Manifold.cylinder(1.0, 0.35, 0.35, 16, True).translate([x, 0, 0])
             for x in np.linspace(-2.4, 2.4, 6)]
    solid = (m3.Manifold.cube([6.0, 2.0, 0.5], True)
             - m3.Manifold.batch_boolean(holes, m3.OpType.Add))
    return _mesh(solid.refine_to_length(refine) if refine else solid)


def foot(refine: float = 0.03, segments: int = 32) -> tuple[np.ndarray, np.ndarray]:
    """A leg ending in a hoof: a cylinder of radius 0.1 and length 1 (z from 0 to 1)
    united with a sphere of radius 0.13 flattened to half its height at its foot, edges
    split to at most ``refine`` (a CAD tessellation: slivers along the leg, a sharp
    junction). A geodesic cap around its lowest vertex is a long sack behind a small
    opening: cut at 0.85 (2589 vertices at the defaults) its LSCM map's λ varies 1712×,
    docs/representation.md session 13."""
    import manifold3d as m3

    leg = m3.Manifold.cylinder(1.0, 0.1, 0.1, segments)
    hoof = m3.Manifold.sphere(0.13, segments).scale([1.0, 1.0, 0.5])
    solid = m3.Manifold.batch_boolean([leg, hoof], m3.OpType.Add)
    return _mesh(solid.refine_to_length(refine))


def holes(v: np.ndarray, f: np.ndarray):
    """The benchmark's holes of a built mesh: 40 random centres (seed 0), geodesic disks of
    2 and 3.5 mean edge lengths, those that can be cut: (centre, radius in h, cut)."""
    h = mean_edge_length(v, f)
    for centre in np.random.default_rng(0).choice(len(v), 40, replace=False):
        for radius in (2.0, 3.5):
            try:
                yield int(centre), radius, cut_geodesic_disk(v, f, int(centre), radius * h)
            except ValueError:
                continue


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("mesh", choices=("quadruped", "plate"))
    parser.add_argument("--refine", type=float, default=None)
    args = parser.parse_args()
    v, f = {"quadruped": quadruped, "plate": plate}[args.mesh](args.refine)
    raw = ConformalOptions(select=False)
    count, failed, start = 0, 0, time.perf_counter()
    for centre, radius, cut in holes(v, f):
        count += 1
        result = conformal_fill(cut.vertices, cut.faces, cut.loop, raw)
        if result.kind != "conformal":
            failed += 1
            print(f"vertex {centre} r={radius}h ({len(cut.loop)} edges): {result.failure}",
                  flush=True)
    print(f"{args.mesh} ({len(v)} vertices): fell back on {failed} / {count} holes "
          f"in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
