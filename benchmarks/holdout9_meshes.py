"""Holdout set 9's meshes (session 33): 12 fresh meshes, made and committed before any fill.

As holdout 8's (``holdout8_meshes.py``): kept out of :mod:`validation_meshes`, which imports
:data:`HOLDOUT9_SOURCES` from here at its end and adds them to its ``SOURCES``, so every
benchmark reaches these meshes through it (``validation_meshes.load("kidney_bean")``). The
generators use its helpers (level sets, manifold3d remeshing, simulated scans, ``_blob``).
Import :mod:`validation_meshes` first, not this module (an import cycle otherwise).

Of the six kinds, all but brain surfaces (none is fresh): 4 simulated range scans of 4 of
the others, 2 organic shapes, 3 CAD parts, 1 tooth and 2 smooth level sets
(``benchmarks/holdout9_manifest.json``, docs/validation.md "Holdout set 9").
"""

from __future__ import annotations

import numpy as np
import validation_meshes as vm
from holdout8_meshes import _smooth_max
from validation_meshes import BenchMesh, Source


def _kidney_bean() -> BenchMesh:
    """A kidney bean (holdout 9): a thick tube about a circular arc of 110°, flattened
    across, swelling towards its two rounded ends, a shallow dimple (the hilum) in the
    middle of its concave side, faint wrinkles (manifold3d level set), isotropically
    remeshed with no feature kept."""
    half = np.radians(55.0)

    def inside(x, y, z):
        a = np.arctan2(x, y + 0.75)  # angle about the arc's centre (0, -0.75), 0 at the top
        t = np.clip(a, -half, half)
        px, py = 0.75 * np.sin(t), 0.75 * np.cos(t) - 0.75
        r = 0.34 + 0.06 * (t / half) ** 2
        d = np.sqrt((x - px) ** 2 + (y - py) ** 2 + (z / 0.78) ** 2)
        hilum = 0.05 * np.exp(-(x * x + (y + 0.37) ** 2 + 2.0 * z * z) / (2 * 0.12**2))
        wrinkles = 0.006 * np.sin(11.0 * x + 1.0) * np.sin(9.0 * y - 0.5 * z)
        return r - d - hilum + wrinkles

    return vm._level_set_mesh(inside, [-1.3, -1.1, -0.5, 1.3, 0.5, 0.5], 0.025, BEAN_H)


def _lever_handle() -> BenchMesh:
    """A door lever handle (holdout 9): a revolved rose (a disc with a chamfered top edge, a
    concave fillet up into a neck, a chamfered neck top), a flat lever arm tapering from the
    neck to a rounded end with sharp top and bottom edges, a blind square spindle hole from
    below and two screw holes through the rose."""
    import manifold3d as m3

    fillet = [(0.16 + 0.06 * (1.0 - np.sin(a)), 0.1 + 0.06 * (1.0 - np.cos(a)))
              for a in np.linspace(0.0, 0.5 * np.pi, 9)]
    rose = m3.Manifold.revolve(m3.CrossSection([[
        (0.0, 0.0), (0.5, 0.0), (0.5, 0.06), (0.46, 0.1), *fillet, (0.16, 0.54),
        (0.13, 0.57), (0.0, 0.57)]]), 128)
    plan = m3.CrossSection.batch_hull([m3.CrossSection.circle(0.2, 64),
                                       m3.CrossSection.circle(0.11, 48).translate((1.15, 0.0))])
    arm = m3.Manifold.extrude(plan, 0.13).translate((0.0, 0.0, 0.34))
    spindle = m3.Manifold.cube((0.1, 0.1, 0.4)).translate((-0.05, -0.05, -0.1))
    part = rose + arm - spindle
    for y in (-0.33, 0.33):
        part = part - m3.Manifold.cylinder(0.4, 0.035, -1, 24).translate((0.0, y, -0.1))
    return vm._manifold_mesh(part, LEVER_H, refine=0.05)


def _wing_nut() -> BenchMesh:
    """A wing nut (holdout 9): a revolved hub tapering upwards with chamfered top and bottom
    edges, two wings (flat plates rising outwards to rounded tops, sharp-edged faces) on
    opposite sides, a bore through the hub with a chamfer at each end."""
    import manifold3d as m3

    hub = m3.Manifold.revolve(m3.CrossSection([[
        (0.0, 0.0), (0.2, 0.0), (0.24, 0.04), (0.2, 0.36), (0.17, 0.39), (0.0, 0.39)]]), 96)
    wing = m3.CrossSection.batch_hull([
        m3.CrossSection.square((0.1, 0.32)).translate((0.12, 0.02)),
        m3.CrossSection.circle(0.15, 48).translate((0.52, 0.4))])
    wing = m3.Manifold.extrude(wing, 0.1).translate((0.0, 0.0, -0.05)).rotate((90.0, 0.0, 0.0))
    part = hub + wing + wing.rotate((0.0, 0.0, 180.0))
    bore = m3.Manifold.revolve(m3.CrossSection([[
        (0.0, -0.1), (0.14, -0.1), (0.1, 0.03), (0.1, 0.36), (0.14, 0.49), (0.0, 0.49)]]), 48)
    # edges split to 0.03, not 0.05 as the others': at 0.05 PyMeshLab found 2 crossing faces
    # on a wing's curved underside after the remeshing (4 at 0.1, 2 at 0.02), at 0.03 none
    return vm._manifold_mesh(part - bore, WING_H, refine=0.03)


def _tslot() -> BenchMesh:
    """A T-slot extrusion section (holdout 9): a square profile with rounded corners, a
    T-slot in each side (a narrow opening between two lips, a wider cavity behind them with
    a sloping floor), a round bore along the middle, extruded and cut square at both ends."""
    import manifold3d as m3

    slot = m3.CrossSection([[(0.6, -0.13), (0.6, 0.13), (0.4, 0.13), (0.4, 0.24),
                             (0.32, 0.24), (0.25, 0.1), (0.25, -0.1), (0.32, -0.24),
                             (0.4, -0.24), (0.4, -0.13)]])
    profile = m3.CrossSection.square((0.88, 0.88)).translate((-0.44, -0.44)).offset(
        0.06, m3.JoinType.Round, circular_segments=48)
    for k in range(4):
        profile = profile - slot.rotate(90.0 * k)
    profile = profile - m3.CrossSection.circle(0.12, 64)
    return vm._manifold_mesh(m3.Manifold.extrude(profile, 0.7), TSLOT_H, refine=0.05)


def _fissured_molar() -> BenchMesh:
    """A molar with fissures (holdout 9): :func:`surfinpaint.data.tooth` (its four cusps)
    with a central fissure along the long axis and a cross fissure square to it carved
    into the top between the cusps along the normals (narrow Gaussian grooves fading out
    at their ends and down the sides), scaled long front to back and low."""
    from surfinpaint import data
    from surfinpaint.geometry.mesh import vertex_normals

    v, f = data.tooth(MOLAR_H)
    n = vertex_normals(v, f)
    top = np.clip((v[:, 2] - 0.7) / 0.25, 0.0, 1.0)
    top = top * top * (3 - 2 * top)
    x, y = v[:, 0], v[:, 1]

    def fissure(across, along, half):
        return np.exp(-across**2 / (2 * 0.045**2) - (np.maximum(np.abs(along) - half, 0.0)
                                                     / 0.1) ** 2)

    groove = 0.065 * np.maximum(fissure(y, x, 0.45), fissure(x, y, 0.35))
    v = (v - n * (groove * top)[:, None]) * np.array([1.2, 0.9, 0.85])
    return BenchMesh(v, f)


def _pretzel() -> BenchMesh:
    """A three-holed pretzel (holdout 9): the smooth union (log-sum-exp, width 0.06) of three
    tori of round section lying flat, their centres 120° apart on a circle, each one's tube
    overlapping the other two's: smooth, genus 3 (manifold3d level set), isotropically
    remeshed."""
    ang = np.radians([90.0, 210.0, 330.0])
    centres = 0.6 * np.column_stack([np.cos(ang), np.sin(ang)])

    def inside(x, y, z):
        ring = np.hypot(x - centres[:, 0], y - centres[:, 1])
        return _smooth_max(0.19 - np.hypot(ring - 0.5, z), 0.06)

    return vm._level_set_mesh(inside, [-1.4, -1.4, -0.4, 1.4, 1.4, 0.4], 0.02, PRETZEL_H)


def _jack() -> BenchMesh:
    """A jack (holdout 9): the smooth union (log-sum-exp, width 0.08) of three rounded rods
    along the axes, of different lengths and thicknesses, the z rod's ends swollen into
    balls: convex ends, concave saddles where the rods meet, smooth, genus 0 (manifold3d
    level set), isotropically remeshed."""

    def rod(p, q, half, r):
        return r - np.hypot(max(abs(p) - half, 0.0), q)

    def inside(x, y, z):
        return _smooth_max([rod(x, np.hypot(y, z), 0.75, 0.2),
                            rod(y, np.hypot(x, z), 0.55, 0.24),
                            rod(z, np.hypot(x, y), 0.6, 0.16),
                            0.26 - np.sqrt(x * x + y * y + (abs(z) - 0.72) ** 2)], 0.08)

    return vm._level_set_mesh(inside, [-1.15, -1.0, -1.2, 1.15, 1.0, 1.2], 0.025, JACK_H)


BEAN_H, LEVER_H, WING_H, TSLOT_H, MOLAR_H, PRETZEL_H, JACK_H = (0.03, 0.025, 0.02, 0.025, 0.03,
                                                                0.035, 0.03)
_blob_j = vm._blob(1010, 5, 0.04, 0.025, 13.0)


# An eleventh set, made in session 33 after holdout 8 had been made: of the six kinds, all
# but brain surfaces (none is fresh). No source is shared with the two halves, the first
# eight holdouts, the tuning-side CAD parts, scan_flatness_study.py's extra scans,
# animals.py, built_meshes.py, eggcrate.py, brain_probes.py, the λ-H families or session
# 32's tuning-side study parts; every parameter was fixed and the manifest committed before
# any fill was run on them.
HOLDOUT9_SOURCES: dict[str, Source] = {
    "scan_kidney_bean": Source("range_scan", "simulated scan of the kidney bean",
                               vm._scan(_kidney_bean, (0.3, 0.8, 0.6), 95)),
    "scan_pretzel": Source("range_scan", "simulated scan of the three-holed pretzel",
                           vm._scan(_pretzel, (-0.4, 0.3, 1.0), 96)),
    "scan_lever_handle": Source("range_scan", "simulated scan of the door lever handle CAD "
                                "part", vm._scan(_lever_handle, (-0.8, 0.3, 0.5), 97)),
    "scan_tslot": Source("range_scan", "simulated scan of the T-slot extrusion section CAD "
                         "part", vm._scan(_tslot, (0.7, -0.3, 0.5), 98)),
    "kidney_bean": Source("organic", "kidney bean, arched and flattened, swollen ends, hilum "
                          "dimple (level set), remeshed", _kidney_bean),
    "blob_j": Source("organic", "union of 5 random ellipsoids with faint fine wrinkles (level "
                     "set)", _blob_j),
    "lever_handle": Source("cad", "manifold3d: door lever handle, chamfered rose, filleted "
                           "neck, tapered flat arm, square spindle hole, screw holes",
                           _lever_handle),
    "wing_nut": Source("cad", "manifold3d: wing nut, tapered hub, chamfers, two flat wings, "
                       "chamfered bore", _wing_nut),
    "tslot": Source("cad", "manifold3d: T-slot extrusion section, rounded corners, four "
                    "T-slots with lips, centre bore", _tslot),
    "fissured_molar": Source("teeth", "tooth body, its 4 cusps split by a carved central and "
                             "cross fissure, long front to back", _fissured_molar),
    "pretzel": Source("smooth", "three-holed pretzel (smooth union of 3 tori, level set, "
                      "genus 3), remeshed", _pretzel),
    "jack": Source("smooth", "jack, three rounded rods along the axes, ball ends (smooth "
                   "union, level set), remeshed", _jack),
}
