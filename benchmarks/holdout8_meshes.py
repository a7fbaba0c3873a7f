"""Holdout set 8's meshes (session 32): 12 fresh meshes, made and committed before any fill.

Kept out of :mod:`validation_meshes` (it had grown to about 1700 lines); that module imports
:data:`HOLDOUT8_SOURCES` from here at its end and adds them to its ``SOURCES``, so every
benchmark reaches these meshes through it (``validation_meshes.load("mushroom")``). The
generators use its helpers (level sets, manifold3d remeshing, simulated scans, ``_blob``,
``_crown``), as holdout 7's did. Import :mod:`validation_meshes` first, not this module: this
one imported first would be only half made when ``validation_meshes`` asks it for its
sources (an import cycle).

Of the six kinds, all but brain surfaces (none is fresh): 4 simulated range scans of 4 of
the others, 2 organic shapes, 3 CAD parts, 1 crown and 2 smooth level sets
(``benchmarks/holdout8_manifest.json``, docs/validation.md "Holdout set 8").
"""

from __future__ import annotations

import numpy as np
import validation_meshes as vm
from validation_meshes import BenchMesh, Source


def _smooth_max(values, k: float) -> float:
    """A smooth maximum (log-sum-exp) of ``values`` with blending width ``k``."""
    values = np.asarray(values, float)
    top = values.max()
    return float(top + k * np.log(np.exp((values - top) / k).sum()))


def _mushroom() -> BenchMesh:
    """A mushroom (holdout 8): a domed cap with a thin rim over a thick stem that
    leans and swells into a bulbous base, blended with a smooth maximum, shallow dents on
    the cap (manifold3d level set), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        cap = 0.42 * (1.0 - np.hypot(np.hypot(x - 0.05, y) / 0.82, (z - 0.82) / 0.42))
        cap = -_smooth_max([-cap, 0.74 - z + 0.12 * (x * x + y * y)], 0.03)
        lean = 0.09 * z * z
        r = 0.15 + 0.035 * np.cos(2.2 * z)
        stem = r - np.hypot(x - lean, y)
        stem = -_smooth_max([-stem, z - 0.95, -z - 0.05], 0.02)
        base = 0.27 * (1.0 - np.hypot(np.hypot(x, y) / 0.27, (z - 0.12) / 0.2))
        upper = 1.0 / (1.0 + np.exp(-(z - 0.95) / 0.03))
        dents = 0.012 * np.sin(9.0 * x + 2.0) * np.sin(8.0 * y - 1.0) * upper
        return _smooth_max([cap + dents, stem, base], 0.05)

    return vm._level_set_mesh(inside, [-1.0, -1.0, -0.2, 1.1, 1.0, 1.4], 0.025, MUSHROOM_H)


def _piston() -> BenchMesh:
    """A piston (holdout 8): a revolved outline (three ring grooves below a chamfered crown
    edge), hollowed from below to a skirt, two wrist pin bosses inside the skirt with the
    pin bore through them and both walls, and a shallow spherical bowl in the crown."""
    import manifold3d as m3

    grooves = [(0.47, 0.92), (0.47, 0.88), (0.5, 0.88), (0.5, 0.84), (0.47, 0.84),
               (0.47, 0.8), (0.5, 0.8), (0.5, 0.76), (0.47, 0.76), (0.47, 0.72), (0.5, 0.72)]
    outline = [(0.0, 0.0), (0.5, 0.0), *grooves[::-1], (0.5, 0.96), (0.46, 1.0), (0.0, 1.0)]
    body = m3.Manifold.revolve(m3.CrossSection([outline]), 128)
    skirt = m3.Manifold.cylinder(0.72, 0.42, -1, 112).translate((0.0, 0.0, -0.1))
    bosses = (m3.Manifold.cylinder(1.0, 0.14, -1, 48).rotate((0.0, 90.0, 0.0)).translate(
        (-0.5, 0.0, 0.4)) - m3.Manifold.cube((0.36, 0.6, 0.6)).translate((-0.18, -0.3, 0.1)))
    bosses = bosses ^ m3.Manifold.cylinder(1.0, 0.45, -1, 112)
    pin = m3.Manifold.cylinder(1.2, 0.07, -1, 32).rotate((0.0, 90.0, 0.0)).translate(
        (-0.6, 0.0, 0.4))
    bowl = m3.Manifold.sphere(0.6, 96).translate((0.0, 0.0, 1.55))
    return vm._manifold_mesh(body - skirt + bosses - pin - bowl, PISTON_H, refine=0.1)


def _tray() -> BenchMesh:
    """A project box tray (holdout 8): a rounded-rectangle box (its vertical edges rounded,
    a chamfer round its bottom) hollowed to a pocket with rounded corners and a flat floor,
    four screw bosses in the pocket's corners with holes through the floor."""
    import manifold3d as m3

    def rounded(w: float, d: float, r: float):
        return m3.CrossSection.square((w - 2 * r, d - 2 * r)).translate(
            (-w / 2 + r, -d / 2 + r)).offset(r, m3.JoinType.Round, circular_segments=64)

    outer = m3.Manifold.batch_hull([m3.Manifold.extrude(rounded(1.32, 0.82, 0.08), 0.01),
                                    m3.Manifold.extrude(rounded(1.4, 0.9, 0.12), 0.32)
                                    .translate((0.0, 0.0, 0.04))])
    pocket = m3.Manifold.extrude(rounded(1.24, 0.74, 0.06), 0.4).translate((0.0, 0.0, 0.08))
    tray = outer - pocket
    for sx in (-1, 1):
        for sy in (-1, 1):
            c = (sx * 0.47, sy * 0.22)
            boss = m3.Manifold.cylinder(0.24, 0.075, -1, 40).translate((*c, 0.06))
            hole = m3.Manifold.cylinder(0.5, 0.032, -1, 24).translate((*c, -0.1))
            tray = tray + boss - hole
    return vm._manifold_mesh(tray, TRAY_H, refine=0.1)


def _impeller() -> BenchMesh:
    """A radial-vane impeller (holdout 8): a revolved disc (its outer top edge rounded by a
    fillet), a hub with a chamfered top, six straight radial vanes standing on the disc and
    joining the hub, a keyed bore through hub and disc."""
    import manifold3d as m3

    arc = [(0.74 + 0.06 * np.cos(a), 0.02 + 0.06 * np.sin(a))
           for a in np.linspace(0.0, 0.5 * np.pi, 10)]
    disc = m3.Manifold.revolve(m3.CrossSection([[(0.0, -0.04), (0.8, -0.04), *arc,
                                                 (0.0, 0.08)]]), 160)
    hub = m3.Manifold.revolve(m3.CrossSection([[(0.0, 0.0), (0.17, 0.0), (0.17, 0.3),
                                                (0.14, 0.33), (0.0, 0.33)]]), 80)
    part = disc + hub
    for k in range(6):
        part = part + m3.Manifold.cube((0.58, 0.08, 0.22)).translate(
            (0.12, -0.04, 0.04)).rotate((0.0, 0.0, 60.0 * k))
    bore = m3.Manifold.cylinder(0.6, 0.07, -1, 32).translate((0.0, 0.0, -0.2))
    key = m3.Manifold.cube((0.04, 0.04, 0.6)).translate((0.05, -0.02, -0.2))
    # edges split to 0.05, not 0.1 as the others': at 0.1 PyMeshLab found 20 crossing faces
    # where the vanes meet the hub and the disc's fillet after the remeshing, at 0.05 none
    return vm._manifold_mesh(part - bore - key, IMPELLER_H, refine=0.05)


def _round_tetra() -> BenchMesh:
    """A rounded tetrahedron (holdout 8): the set where a smooth maximum (log-sum-exp,
    width 0.12) of the distances to a regular tetrahedron's four face planes is below 0.5:
    four nearly flat faces, rounded edges and corners, smooth, genus 0 (manifold3d level
    set), isotropically remeshed."""
    normals = np.array([[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0],
                        [-1.0, -1.0, 1.0]]) / np.sqrt(3.0)

    def inside(x, y, z):
        return -_smooth_max(normals @ np.array([x, y, z]) - 0.5, 0.12)

    return vm._level_set_mesh(inside, [-1.6, -1.6, -1.6, 1.6, 1.6, 1.6], 0.03, TETRA_H)


def _saddle_ball() -> BenchMesh:
    """A ball with a monkey-saddle top (holdout 8): the unit ball cut by the surface
    ``z = 0.3 + 0.45 (x³ - 3xy²)``, the two blended by a smooth minimum (width 0.08): a
    three-fold saddle for a top, a rounded rim, smooth, genus 0 (manifold3d level set),
    isotropically remeshed."""

    def inside(x, y, z):
        ball = 1.0 - np.sqrt(x * x + y * y + z * z)
        top = 0.3 + 0.45 * (x**3 - 3 * x * y * y) - z
        return -_smooth_max([-ball, -top], 0.08)

    return vm._level_set_mesh(inside, [-1.2, -1.2, -1.2, 1.2, 1.2, 1.2], 0.03, SADDLE_H)


MUSHROOM_H, PISTON_H, TRAY_H, IMPELLER_H, TETRA_H, SADDLE_H = (0.03, 0.028, 0.025, 0.03, 0.035,
                                                               0.045)
_blob_i = vm._blob(909, 6, 0.04, 0.035, 9.0)
_crown9 = vm._crown(9, 0.38, 0.12, (1.15, 0.9, 1.0), 18, 0.045)


# A tenth set, made in session 32 after holdout 7 had been run: of the six kinds, all but
# brain surfaces (none is fresh). No source is shared with the two halves, the first seven
# holdouts, the tuning-side CAD parts, scan_flatness_study.py's extra scans, animals.py,
# built_meshes.py, eggcrate.py, brain_probes.py, the λ-H families or session 32's
# tuning-side study parts; every parameter was fixed and the manifest committed before any
# fill was run on them.
HOLDOUT8_SOURCES: dict[str, Source] = {
    "scan_mushroom": Source("range_scan", "simulated scan of the mushroom",
                            vm._scan(_mushroom, (0.7, 0.5, -0.4), 91)),
    "scan_saddle_ball": Source("range_scan", "simulated scan of the monkey-saddle ball",
                               vm._scan(_saddle_ball, (-0.3, 0.4, 1.0), 92)),
    "scan_impeller": Source("range_scan", "simulated scan of the radial-vane impeller CAD "
                            "part", vm._scan(_impeller, (0.4, -0.5, 0.9), 93)),
    "scan_tray": Source("range_scan", "simulated scan of the project box tray CAD part",
                        vm._scan(_tray, (0.6, -0.7, 0.5), 94)),
    "mushroom": Source("organic", "mushroom, domed cap, leaning stem, bulbous base (level "
                       "set), remeshed", _mushroom),
    "blob_i": Source("organic", "union of 6 random ellipsoids with fine wrinkles (level set)",
                     _blob_i),
    "piston": Source("cad", "manifold3d: piston, ring grooves, chamfered crown with a bowl, "
                     "hollow skirt, pin bosses, pin bore", _piston),
    "tray": Source("cad", "manifold3d: project box tray, rounded walls, bottom chamfer, "
                   "flat-floored pocket, screw bosses", _tray),
    "impeller": Source("cad", "manifold3d: radial-vane impeller, filleted disc, six vanes, "
                       "chamfered hub, keyed bore", _impeller),
    "crown9": Source("teeth", "tooth body, 9 more low cusps in a ring round the top, wide side "
                     "to side", _crown9),
    "round_tetra": Source("smooth", "rounded tetrahedron (smooth maximum of 4 planes, level "
                          "set), remeshed", _round_tetra),
    "saddle_ball": Source("smooth", "ball with a monkey-saddle top (smooth minimum, level "
                          "set), remeshed", _saddle_ball),
}
