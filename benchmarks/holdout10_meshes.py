"""Holdout set 10's meshes (session 34): 12 fresh meshes, made and committed before any fill.

As holdouts 8 and 9's (``holdout8_meshes.py``, ``holdout9_meshes.py``): kept out of
:mod:`validation_meshes`, which imports :data:`HOLDOUT10_SOURCES` from here at its end and
adds them to its ``SOURCES``, so every benchmark reaches these meshes through it
(``validation_meshes.load("pear")``). The generators use its helpers (level sets, manifold3d
remeshing, ``_blob``); the four range scans are the first made with the portable scanner
(``simulated_scan(..., portable=True)``: the same bits under every BLAS kernel). Import
:mod:`validation_meshes` first, not this module (an import cycle otherwise).

Of the six kinds, all but brain surfaces (none is fresh): 4 simulated range scans of 4 of
the others, 2 organic shapes, 3 CAD parts, 1 tooth and 2 smooth level sets
(``benchmarks/holdout10_manifest.json``, docs/validation.md "Holdout set 10").
"""

from __future__ import annotations

import math

import numpy as np
import validation_meshes as vm
from holdout8_meshes import _smooth_max
from validation_meshes import BenchMesh, Source


def _segment_distance(x, y, z, a, b) -> float:
    """Distance of the point (x, y, z) from the segment from ``a`` to ``b`` (Python floats:
    no BLAS dot, whose rounding depends on the CPU's kernel)."""
    dx, dy, dz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    px, py, pz = x - a[0], y - a[1], z - a[2]
    t = min(max((px * dx + py * dy + pz * dz) / (dx * dx + dy * dy + dz * dz), 0.0), 1.0)
    return math.sqrt((px - t * dx) ** 2 + (py - t * dy) ** 2 + (pz - t * dz) ** 2)


def _pear() -> BenchMesh:
    """A pear (holdout 10): a round lower body and a smaller upper bulb set off to one side,
    blended into a smooth neck (log-sum-exp, width 0.12), a dimple where the flower was at
    the bottom and a slanted stalk blended in at the top (manifold3d level set), isotropically
    remeshed with no feature kept."""

    def inside(x, y, z):
        body = 0.5 - np.sqrt(x * x + y * y + (z / 0.92) ** 2)
        bulb = 0.29 - np.sqrt((x - 0.07) ** 2 + y * y + (z - 0.56) ** 2)
        fruit = _smooth_max([body, bulb], 0.12)
        stalk = 0.045 - _segment_distance(x, y, z, (0.08, 0.0, 0.78), (0.17, 0.03, 1.02))
        dimple = 0.06 * np.exp(-(x * x + y * y + (z + 0.47) ** 2) / (2 * 0.07**2))
        return _smooth_max([fruit, stalk], 0.03) - dimple

    return vm._level_set_mesh(inside, [-0.6, -0.6, -0.55, 0.6, 0.6, 1.1], 0.02, PEAR_H)


def _spanner() -> BenchMesh:
    """An open-end spanner (holdout 10): a flat handle with a shallow recess along its top,
    an open jaw head at one end (a disc with a slot at 15° to the handle, its mouth rounded)
    and a ring head at the other with a hexagonal hole: sharp edges everywhere (manifold3d
    extrusions)."""
    import manifold3d as m3

    handle = m3.CrossSection.batch_hull([m3.CrossSection.circle(0.11, 48).translate((0.0, 0.0)),
                                         m3.CrossSection.circle(0.13, 48).translate((1.5, 0.0))])
    jaw = m3.CrossSection.circle(0.3, 96).translate((1.72, 0.0))
    mouth = (m3.CrossSection.square((0.6, 0.21)).translate((0.0, -0.105))
             + m3.CrossSection.circle(0.105, 48)).rotate(15.0).translate((1.72, 0.0))
    ring = m3.CrossSection.circle(0.24, 96).translate((-0.2, 0.0))
    hexagon = m3.CrossSection.circle(0.13, 6).rotate(15.0).translate((-0.2, 0.0))
    plan = handle + jaw + ring - mouth - hexagon
    part = m3.Manifold.extrude(plan, 0.12)
    recess = m3.Manifold.extrude(m3.CrossSection.batch_hull([
        m3.CrossSection.circle(0.05, 32).translate((0.25, 0.0)),
        m3.CrossSection.circle(0.06, 32).translate((1.25, 0.0))]), 0.1).translate(
        (0.0, 0.0, 0.095))
    return vm._manifold_mesh(part - recess, SPANNER_H, refine=0.03)


def _heat_sink() -> BenchMesh:
    """A heat sink (holdout 10): a base plate with six straight fins standing on it, their
    tops chamfered on both sides, two mounting holes with counterbores through the base in
    its fin-free margins (manifold3d booleans)."""
    import manifold3d as m3

    part = m3.Manifold.cube((1.0, 0.8, 0.12)).translate((-0.5, -0.4, 0.0))
    fin = m3.Manifold.extrude(m3.CrossSection([[(-0.035, 0.0), (0.035, 0.0), (0.035, 0.4),
                                                 (0.0, 0.44), (-0.035, 0.4)]]), 0.8)
    fin = fin.rotate((90.0, 0.0, 0.0)).translate((0.0, 0.4, 0.11))
    for x in np.linspace(-0.3, 0.3, 6):
        part = part + fin.translate((float(x), 0.0, 0.0))
    for x in (-0.43, 0.43):
        hole = (m3.Manifold.cylinder(0.4, 0.035, -1, 32).translate((x, 0.0, -0.1))
                + m3.Manifold.cylinder(0.1, 0.055, -1, 32).translate((x, 0.0, 0.07)))
        part = part - hole
    return vm._manifold_mesh(part, SINK_H, refine=0.05)


def _bell_crank() -> BenchMesh:
    """A bell crank (holdout 10): two flat arms at 100° from a pivot boss, each ending in a
    boss, the bosses standing proud of the arms on both faces, a bore through each (the
    pivot's with a keyway), a triangular lightening hole with rounded corners in the web
    between the arms (manifold3d extrusions and booleans)."""
    import manifold3d as m3

    angle = np.radians(100.0)
    end_a, end_b = (0.9, 0.0), (0.7 * np.cos(angle), 0.7 * np.sin(angle))
    arms = (m3.CrossSection.batch_hull([m3.CrossSection.circle(0.2, 64),
                                        m3.CrossSection.circle(0.12, 48).translate(end_a)])
            + m3.CrossSection.batch_hull([m3.CrossSection.circle(0.2, 64),
                                          m3.CrossSection.circle(0.11, 48).translate(end_b)])
            + m3.CrossSection.hull(m3.CrossSection([[(0.0, 0.0), (0.45, 0.0),
                                                     (0.3 * np.cos(angle), 0.3 * np.sin(angle))
                                                     ]])).offset(0.08, m3.JoinType.Round,
                                                                 circular_segments=32))
    window = m3.CrossSection([[(0.16, 0.08), (0.36, 0.08), (0.04, 0.28)]]).offset(
        0.02, m3.JoinType.Round, circular_segments=16)
    part = m3.Manifold.extrude(arms - window, 0.1)
    bosses = [((0.0, 0.0), 0.2, 0.11), (end_a, 0.12, 0.05), (end_b, 0.11, 0.045)]
    for (x, y), r, _ in bosses:
        part = part + m3.Manifold.cylinder(0.22, r, -1, 64).translate((x, y, -0.06))
    for (x, y), _, bore in bosses:
        part = part - m3.Manifold.cylinder(0.4, bore, -1, 48).translate((x, y, -0.15))
    key = m3.Manifold.cube((0.05, 0.04, 0.4)).translate((0.09, -0.02, -0.15))
    return vm._manifold_mesh(part - key, CRANK_H, refine=0.03)


def _rooted_molar() -> BenchMesh:
    """A molar with its roots (holdout 10): a crown (a rounded, flattened box) with four
    cusps on its top and a groove between them, narrowing at the neck into two tapering
    roots that spread apart downwards, their tips rounded (smooth union, manifold3d level
    set), isotropically remeshed with no feature kept."""
    cusps = [(sx * 0.2, sy * 0.16, 0.36) for sx in (-1, 1) for sy in (-1, 1)]

    def inside(x, y, z):
        crown = 0.36 - np.sqrt((x / 1.15) ** 2 + (y / 0.95) ** 2 + ((z - 0.12) / 0.7) ** 2)
        bumps = [0.13 - np.sqrt((x - cx) ** 2 + (y - cy) ** 2 + ((z - cz) / 0.9) ** 2)
                 for cx, cy, cz in cusps]
        tooth = _smooth_max([crown, *bumps], 0.05)
        roots = [(0.13 - 0.07 * min(max(-z, 0.0) / 0.7, 1.0))
                 - _segment_distance(x, y, z, (sx * 0.14, 0.0, -0.05), (sx * 0.3, 0.0, -0.72))
                 for sx in (-1, 1)]
        return _smooth_max([tooth, *roots], 0.04)

    return vm._level_set_mesh(inside, [-0.6, -0.45, -0.85, 0.6, 0.45, 0.6], 0.02, MOLAR_H)


def _saturn() -> BenchMesh:
    """A ringed ball (holdout 10): a sphere and a flat ring of rounded section about it,
    tilted by 20°, its inner edge blended into the sphere's equator (log-sum-exp, width
    0.06): smooth, genus 0, convex and concave (manifold3d level set), isotropically
    remeshed."""
    tilt = np.radians(20.0)
    c, s = np.cos(tilt), np.sin(tilt)

    def inside(x, y, z):
        y, z = c * y - s * z, s * y + c * z
        ball = 0.55 - np.sqrt(x * x + y * y + z * z)
        ring = 1.0 - np.sqrt(((np.hypot(x, y) - 0.78) / 0.27) ** 2 + (z / 0.09) ** 2)
        return _smooth_max([ball, 0.09 * ring], 0.06)

    return vm._level_set_mesh(inside, [-1.15, -1.15, -0.7, 1.15, 1.15, 0.7], 0.025, SATURN_H)


def _bead_ring() -> BenchMesh:
    """A ring of beads (holdout 10): seven balls, alternately larger and smaller, on a circle,
    threaded on a thin torus and blended into it (log-sum-exp, width 0.05): smooth, genus
    1, bulges and concave necks (manifold3d level set), isotropically remeshed."""
    ang = np.radians(np.arange(7) * 360.0 / 7)
    centres = 0.75 * np.column_stack([np.cos(ang), np.sin(ang)])
    radii = np.where(np.arange(7) % 2 == 0, 0.25, 0.2)

    def inside(x, y, z):
        beads = radii - np.sqrt((x - centres[:, 0]) ** 2 + (y - centres[:, 1]) ** 2 + z * z)
        thread = 0.09 - np.hypot(np.hypot(x, y) - 0.75, z)
        return _smooth_max([*beads, thread], 0.05)

    return vm._level_set_mesh(inside, [-1.1, -1.1, -0.35, 1.1, 1.1, 0.35], 0.025, BEADS_H)


PEAR_H, SPANNER_H, SINK_H, CRANK_H, MOLAR_H, SATURN_H, BEADS_H = (0.025, 0.02, 0.025, 0.02,
                                                                  0.025, 0.03, 0.03)
_blob_k = vm._blob(1111, 6, 0.04, 0.035, 10.5)


# A twelfth set, made in session 34 after holdout 9 had been made: of the six kinds, all but
# brain surfaces (none is fresh). No source is shared with the two halves, the first nine
# holdouts, the tuning-side CAD parts, scan_flatness_study.py's extra scans, animals.py,
# built_meshes.py, eggcrate.py, brain_probes.py, the λ-H families or session 32's
# tuning-side study parts; every parameter was fixed and the manifest committed before any
# fill was run on them. The scans are portable (the same bits on every CPU's BLAS).
HOLDOUT10_SOURCES: dict[str, Source] = {
    "scan_pear": Source("range_scan", "simulated scan of the pear (portable scanner)",
                        vm._scan(_pear, (0.5, -0.6, 0.4), 105, portable=True)),
    "scan_bead_ring": Source("range_scan", "simulated scan of the ring of beads (portable "
                             "scanner)", vm._scan(_bead_ring, (0.3, 0.4, 1.0), 106,
                                                  portable=True)),
    "scan_heat_sink": Source("range_scan", "simulated scan of the heat sink CAD part "
                             "(portable scanner)", vm._scan(_heat_sink, (0.5, -0.8, 0.6), 107,
                                                            portable=True)),
    "scan_bell_crank": Source("range_scan", "simulated scan of the bell crank CAD part "
                              "(portable scanner)", vm._scan(_bell_crank, (-0.4, 0.5, 0.9),
                                                             108, portable=True)),
    "pear": Source("organic", "pear, round body, offset upper bulb, flower dimple, slanted "
                   "stalk (level set), remeshed", _pear),
    "blob_k": Source("organic", "union of 6 random ellipsoids with medium wrinkles (level "
                     "set)", _blob_k),
    "spanner": Source("cad", "manifold3d: open-end spanner, jaw slot at 15°, ring head with a "
                      "hexagonal hole, recessed handle", _spanner),
    "heat_sink": Source("cad", "manifold3d: heat sink, base plate, six fins with chamfered "
                        "tops, counterbored mounting holes", _heat_sink),
    "bell_crank": Source("cad", "manifold3d: bell crank, two arms at 100°, proud bosses, bores, "
                         "keyway, rounded triangular window", _bell_crank),
    "rooted_molar": Source("teeth", "molar crown, 4 cusps, narrowing neck, two tapering "
                           "spreading roots (level set)", _rooted_molar),
    "saturn": Source("smooth", "sphere with a tilted flat ring blended into its equator (level "
                     "set, genus 0), remeshed", _saturn),
    "bead_ring": Source("smooth", "seven alternating beads threaded on a thin torus (smooth "
                        "union, level set, genus 1), remeshed", _bead_ring),
}
