"""Holdout set 14's meshes (session 37): 12 fresh meshes, made and committed before any fill.

As holdouts 8 to 13's (``holdout8_meshes.py`` .. ``holdout13_meshes.py``): kept out of
:mod:`validation_meshes`, which imports :data:`HOLDOUT14_SOURCES` from here at its end and
adds them to its ``SOURCES``, so every benchmark reaches these meshes through it
(``validation_meshes.load("hand")``). The generators use its helpers (level sets,
manifold3d remeshing) and holdouts 11 and 12's level-set and radial-surface helpers; the
four range scans are the portable scanner's (``simulated_scan(..., portable=True)``: the
same bits under every BLAS kernel). Import :mod:`validation_meshes` first, not this module
(an import cycle otherwise).

All six kinds, as holdouts 11 to 13: 4 simulated range scans of 4 of the others, 2 organic
shapes, 3 CAD parts, 1 tooth, 1 smooth level set and 1 brain-like surface (a synthetic
cortex with polygonal gyri, not a real brain) (``benchmarks/holdout14_manifest.json``,
docs/validation.md "Holdout set 14").

The level sets' insides and the radial heights are written with Python floats and
:mod:`math` (no numpy transcendental on arrays, whose SIMD loops differ between CPUs), so a
mesh's bits do not depend on the CPU's vector units.
"""

from __future__ import annotations

import math

import numpy as np
import validation_meshes as vm
from holdout11_meshes import _capsule, _radial_surface, _smooth_max
from holdout12_meshes import _ellipsoid
from validation_meshes import BenchMesh, Source


def _flattened_underneath(r: float, uz: float, floor: float) -> float:
    """The radius ``r`` of an ovoid in the unit direction whose z component is ``uz``,
    flattened underneath at ``z = -floor`` and blended (log-sum-exp, width 0.03): the
    synthetic cortices of holdouts 14 to 23 (Python floats)."""
    cut = -floor / uz if uz < 0.0 else 10.0
    low = min(r, cut)
    return low - 0.03 * math.log(math.exp((low - r) / 0.03) + math.exp((low - cut) / 0.03))


def _smooth_min(values, k: float) -> float:
    """A smooth minimum (log-sum-exp) of ``values`` with blending width ``k``: a rounded
    intersection of insides."""
    return -_smooth_max([-v for v in values], k)


# --------------------------------------------------------------------------- organic


def _finger(base, spread_deg: float, lengths, radius: float, curls_deg):
    """The segments (start, end, start radius, end radius) of a finger from ``base``: it
    points up (+z) turned by ``spread_deg`` about y, each joint bending it further towards
    the palm side (-y) by ``curls_deg``; its radius tapers to 0.8 of ``radius``."""
    spread = math.radians(spread_deg)
    segments, point, bend = [], base, 0.0
    taper = [radius * (1.0 - 0.2 * k / len(lengths)) for k in range(len(lengths) + 1)]
    for k, (length, curl) in enumerate(zip(lengths, curls_deg, strict=True)):
        bend += math.radians(curl)
        step = (length * math.cos(bend) * math.sin(spread), -length * math.sin(bend),
                length * math.cos(bend) * math.cos(spread))
        end = (point[0] + step[0], point[1] + step[1], point[2] + step[2])
        segments.append((point, end, taper[k], taper[k + 1]))
        point = end
    return segments


def _hand() -> BenchMesh:
    """An open hand (holdout 14): a flat palm with rounded edges on a wrist stub, four
    fingers of three segments each, fanned out and curled a little towards the palm side
    (tapering, a knuckle bump at each joint), and a thumb of three segments standing out
    from the palm's side (smooth unions, manifold3d level set), isotropically remeshed with
    no feature kept. The fingers are thin: about 0.2-0.24 round."""
    fingers = []
    for x, spread, lengths, radius in ((-0.12, -14.0, (0.16, 0.1, 0.08), 0.037),
                                       (-0.04, -4.0, (0.18, 0.11, 0.085), 0.038),
                                       (0.04, 5.0, (0.17, 0.1, 0.08), 0.036),
                                       (0.12, 16.0, (0.13, 0.08, 0.07), 0.032)):
        fingers += _finger((x, -0.005, 0.12), spread, lengths, radius, (8.0, 18.0, 14.0))
    fingers += [((-0.13, -0.02, -0.07), (-0.25, -0.07, 0.03), 0.05, 0.04),
                ((-0.25, -0.07, 0.03), (-0.31, -0.1, 0.12), 0.04, 0.035),
                ((-0.31, -0.1, 0.12), (-0.345, -0.115, 0.19), 0.035, 0.03)]
    joints = [(end, 1.04 * r_end) for _, end, _, r_end in fingers[:-1]]  # knuckle bumps

    def inside(x, y, z):
        # the palm: a rounded slab, within 0.055 of a rectangle in the xz-plane, and the
        # ball of the thumb on its palm side
        dx = max(abs(x) - 0.14, 0.0)
        dz = max(abs(z - 0.02) - 0.12, 0.0)
        palm = 0.055 - math.sqrt(dx * dx + y * y + dz * dz)
        thenar = _ellipsoid(x, y, z, (-0.08, -0.035, -0.04), (0.09, 0.05, 0.11))
        wrist = _capsule(x, y * 1.5, z, (0.0, 0.0, -0.1), (0.0, 0.0, -0.42), 0.085,
                         0.08) / 1.5
        parts = [palm, thenar, wrist]
        parts += [_capsule(x, y, z, a, b, r_a, r_b) for a, b, r_a, r_b in fingers]
        parts += [r - math.sqrt((x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2)
                  for c, r in joints]
        return _smooth_max(parts, 0.015)

    return vm._level_set_mesh(inside, [-0.45, -0.26, -0.56, 0.3, 0.13, 0.62], 0.01, HAND_H)


def _tortoise() -> BenchMesh:
    """A tortoise (holdout 14): a domed carapace whose rounded rim overhangs a flat plastron,
    its dome divided by shallow grooves into scutes (five along the spine, four a side, a
    ring of twelve round the margin), each scute bulging a little; a head on a neck, four
    stubby legs with flattened feet and a short pointed tail (smooth unions, manifold3d
    level set), isotropically remeshed with no feature kept."""
    # the scutes' centres in the dome's plan coordinates (x / 0.42, y / 0.32: 1 at the rim)
    scutes = [(u, 0.0) for u in (-0.66, -0.33, 0.0, 0.33, 0.66)]
    scutes += [(u, s * 0.52) for u in (-0.5, -0.17, 0.17, 0.5) for s in (-1.0, 1.0)]
    scutes += [(0.93 * math.cos(a), 0.93 * math.sin(a))
               for a in (math.radians(15.0 + 30.0 * k) for k in range(12))]

    def inside(x, y, z):
        u, v = x / 0.42, y / 0.32
        near = sorted(math.hypot(u - cu, v - cv) for cu, cv in scutes)
        groove = 0.012 * math.exp(-((near[1] - near[0]) / 0.12) ** 2)
        bulge = 0.008 * math.exp(-(near[0] / 0.2) ** 2)
        dome = _ellipsoid(x, y, z, (0.0, 0.0, 0.0), (0.42, 0.32, 0.26)) - groove + bulge
        shell = _smooth_min([dome, z + 0.005], 0.012)
        plastron = _ellipsoid(x, y, z, (0.0, 0.0, 0.0), (0.37, 0.27, 0.075))
        neck = _capsule(x, y, z, (0.3, 0.0, 0.0), (0.5, 0.0, 0.06), 0.055, 0.045)
        head = _ellipsoid(x, y, z, (0.57, 0.0, 0.08), (0.085, 0.058, 0.052))
        legs = []
        for sx, sy in ((1.0, -1.0), (1.0, 1.0), (-1.0, -1.0), (-1.0, 1.0)):
            top, foot = (sx * 0.2, sy * 0.19, 0.0), (sx * 0.3, sy * 0.31, -0.13)
            legs.append(_capsule(x, y, z, top, foot, 0.062, 0.05))
            legs.append(_ellipsoid(x, y, z, (sx * 0.31, sy * 0.32, -0.155), (0.065, 0.06, 0.03)))
        tail = _capsule(x, y, z, (-0.36, 0.0, 0.0), (-0.48, 0.0, -0.05), 0.03, 0.012)
        return _smooth_max([shell, plastron, neck, head, *legs, tail], 0.02)

    return vm._level_set_mesh(inside, [-0.56, -0.44, -0.22, 0.7, 0.44, 0.32], 0.012,
                              TORTOISE_H)


# --------------------------------------------------------------------------- CAD


def _claw_hammer() -> BenchMesh:
    """A claw hammer's head (holdout 14): a turned striking face (chamfered rim) and neck
    along the head's axis, a cheek block with chamfered edges pierced by an oblong eye for
    the handle, and a claw curving down towards the handle side, tapering, split by a
    V notch with a rounded root (manifold3d revolve, hulls and booleans; genus 1)."""
    import manifold3d as m3

    # the face and neck: a profile (radius, position along the axis) revolved about the
    # axis, then turned so that the axis runs along x
    profile = [(0.0, -0.62), (0.1, -0.62), (0.122, -0.598), (0.122, -0.5), (0.085, -0.44),
               (0.085, -0.25), (0.0, -0.25)]
    face = m3.Manifold.revolve(m3.CrossSection([profile]), 96).rotate((0.0, 90.0, 0.0))
    plan = m3.CrossSection.square((0.42, 0.17), True).offset(-0.025, m3.JoinType.Miter)
    plan = plan.offset(0.025, m3.JoinType.Square)  # corners chamfered by 0.025

    def slab(inset: float, z: float, thickness: float):
        return m3.Manifold.extrude(plan.offset(-inset, m3.JoinType.Miter), thickness).translate(
            (-0.09, 0.0, z))

    cheek = m3.Manifold.batch_hull([slab(0.02, -0.16, 0.001), slab(0.0, -0.14, 0.28),
                                    slab(0.02, 0.159, 0.001)])
    eye = m3.Manifold.extrude(m3.CrossSection.square((0.08, 0.001), True).offset(
        0.035, m3.JoinType.Round, circular_segments=48), 0.6).translate((-0.1, 0.0, -0.3))
    # the claw: sections across an arc about (0.1, 0, -0.75) (radius 0.85 to its top),
    # each thinner and narrower than the last, hulled two by two
    sections = []
    for k in range(11):
        t = k / 10
        angle = math.radians(90.0 - 42.0 * t)
        thick, wide = 0.16 - 0.11 * t, 0.17 - 0.03 * t
        box = m3.Manifold.cube((0.001, wide, thick), True).translate(
            (0.0, 0.0, 0.85 - 0.5 * thick)).rotate((0.0, 90.0 - math.degrees(angle), 0.0))
        sections.append(box.translate((0.1, 0.0, -0.75)))
    claw = m3.Manifold.batch_boolean([m3.Manifold.batch_hull([a, b])
                                      for a, b in zip(sections[:-1], sections[1:], strict=True)],
                                     m3.OpType.Add)
    notch = (m3.CrossSection([[(0.36, -0.02), (0.95, -0.05), (0.95, 0.05), (0.36, 0.02)]])
             + m3.CrossSection.circle(0.024, 32).translate((0.36, 0.0)))
    notch = m3.Manifold.extrude(notch, 2.0).translate((0.0, 0.0, -1.2))
    part = face + cheek + claw - eye - notch
    return vm._manifold_mesh(part, CLAW_HAMMER_H, refine=0.03)


def _stool() -> BenchMesh:
    """A stool (holdout 14): a round seat with a chamfered top edge and an oblong hand hole,
    four splayed tapered legs cut flat at the floor and four rungs joining them in a ring
    (manifold3d hulls and booleans; genus 5)."""
    import manifold3d as m3

    height = 0.62
    seat = m3.Manifold.batch_hull([m3.Manifold.cylinder(0.04, 0.42, -1, 128).translate(
        (0.0, 0.0, height)), m3.Manifold.cylinder(0.001, 0.385, -1, 128).translate(
        (0.0, 0.0, height + 0.064))])
    hand_hole = m3.Manifold.extrude(m3.CrossSection.square((0.12, 0.001), True).offset(
        0.028, m3.JoinType.Round, circular_segments=32), 0.4).translate((0.0, 0.0, 0.4))

    def leg_at(sx: float, sy: float, z: float) -> tuple[float, float, float]:
        t = z / height  # from the foot (0) to the seat (1)
        return (sx * (0.33 - 0.09 * t), sy * (0.33 - 0.09 * t), z)

    corners = ((1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0))
    legs = [m3.Manifold.batch_hull([
        m3.Manifold.cylinder(0.001, 0.03, -1, 48).translate(leg_at(sx, sy, 0.0)),
        m3.Manifold.cylinder(0.001, 0.04, -1, 48).translate(leg_at(sx, sy, height + 0.01))])
        for sx, sy in corners]
    rungs = [m3.Manifold.batch_hull([m3.Manifold.sphere(0.022, 32).translate(leg_at(*a, 0.22)),
                                     m3.Manifold.sphere(0.022, 32).translate(leg_at(*b, 0.22))])
             for a, b in zip(corners, corners[1:] + corners[:1], strict=True)]
    part = seat - hand_hole + m3.Manifold.batch_boolean(legs + rungs, m3.OpType.Add)
    return vm._manifold_mesh(part, STOOL_H, refine=0.03)


def _camshaft() -> BenchMesh:
    """A camshaft (holdout 14): a turned shaft (chamfered ends, three bearing journals with
    chamfered edges, a flange at one end with four bolt holes, a blind bore in the other
    end) carrying four egg-shaped cam lobes a quarter turn apart (manifold3d revolve, hulls
    and booleans; genus 4)."""
    import manifold3d as m3

    profile = [(0.0, -0.8), (0.045, -0.8), (0.06, -0.785)]
    for centre in (-0.55, 0.0, 0.55):  # the journals, chamfered by 0.012
        a, b = centre - 0.05, centre + 0.05
        profile += [(0.06, a - 0.015), (0.088, a), (0.1, a + 0.012), (0.1, b - 0.012),
                    (0.088, b), (0.06, b + 0.015)]
    profile += [(0.06, 0.7), (0.075, 0.71), (0.16, 0.71), (0.16, 0.78), (0.145, 0.795),
                (0.0, 0.795)]
    shaft = m3.Manifold.revolve(m3.CrossSection([profile]), 96).rotate((0.0, 90.0, 0.0))
    bore = m3.Manifold.cylinder(0.12, 0.028, -1, 32).rotate((0.0, 90.0, 0.0)).translate(
        (-0.81, 0.0, 0.0))
    bolts = [m3.Manifold.cylinder(0.2, 0.022, -1, 32).rotate((0.0, 90.0, 0.0)).translate(
        (0.6, 0.11 * math.cos(a), 0.11 * math.sin(a)))
        for a in (math.radians(45.0 + 90.0 * k) for k in range(4))]
    lobe = m3.CrossSection.batch_hull([m3.CrossSection.circle(0.085, 96),
                                       m3.CrossSection.circle(0.04, 64).translate((0.095, 0.0))])
    lobes = [m3.Manifold.extrude(lobe, 0.08).rotate((0.0, 0.0, turn)).rotate(
        (0.0, 90.0, 0.0)).translate((x - 0.04, 0.0, 0.0))
        for x, turn in ((-0.4, 0.0), (-0.15, 180.0), (0.15, 90.0), (0.4, 270.0))]
    part = shaft + m3.Manifold.batch_boolean(lobes, m3.OpType.Add) - bore - m3.Manifold.\
        batch_boolean(bolts, m3.OpType.Add)
    return vm._manifold_mesh(part, CAMSHAFT_H, refine=0.03)


# --------------------------------------------------------------------------- teeth


def _tribosphenic() -> BenchMesh:
    """A tribosphenic lower molar (holdout 14; an early mammal's): a high trigonid of three
    tall pointed cusps in a triangle at the front, joined by shearing crests, and a low
    talonid behind it, a basin rimmed by three smaller cusps; a waist at the neck and two
    tapering roots flattened front to back (manifold3d level set), isotropically remeshed
    with no feature kept."""
    trigonid = ((0.12, 0.2), (-0.1, 0.33), (-0.12, 0.1))
    tips = ((0.12, 0.2, 0.5), (-0.1, 0.33, 0.42), (-0.12, 0.1, 0.47),  # the trigonid's
            (0.13, -0.2, 0.3), (-0.12, -0.22, 0.28), (0.0, -0.37, 0.26))  # the talonid's

    def inside(x, y, z):
        section = 0.19 * (1.0 - math.sqrt(math.sqrt((x / 0.21) ** 4 + (y / 0.44) ** 4)))
        step = 0.5 + 0.5 * math.tanh(y / 0.05)  # 1 under the trigonid, 0 under the talonid
        top = 0.04 + 0.08 * step - z
        body = _smooth_min([section, top, z + 0.12], 0.025)
        cusps = [_capsule(x, y, z, (tx * 0.6, ty, -0.05), (tx, ty, tz), 0.16 if tz > 0.4
                          else 0.12, 0.04) for tx, ty, tz in tips]
        crests = [_capsule(x, y, z, (ax, ay, 0.33), (bx, by, 0.33), 0.035, 0.035)
                  for (ax, ay), (bx, by) in zip(trigonid, trigonid[1:] + trigonid[:1],
                                                strict=True)]
        crown = _smooth_max([body, *cusps, *crests], 0.03)
        basin = _ellipsoid(x, y, z, (0.0, -0.2, 0.29), (0.12, 0.14, 0.1))
        crown = _smooth_min([crown, -basin], 0.02)
        roots = [_capsule(x, y * 1.6, z, (0.0, 1.6 * ry, -0.05),
                          (0.02 * side, 1.6 * (ry + 0.08 * side), -0.6), 0.16, 0.05) / 1.6
                 for ry, side in ((0.2, 1.0), (-0.2, -1.0))]
        return _smooth_max([crown, *roots], 0.03)

    return vm._level_set_mesh(inside, [-0.3, -0.55, -0.7, 0.3, 0.55, 0.6], 0.012,
                              TRIBOSPHENIC_H)


# --------------------------------------------------------------------------- smooth


def _blood_cell() -> BenchMesh:
    """A biconcave disc like a red blood cell (holdout 14): a Cassini oval with a waist,
    ``(p^2 + z^2)^2 - 2 c^2 (p^2 - z^2) + c^4 < a^4`` (``a`` a little above ``c``), revolved
    about the axis through its waist, its plan stretched to an ellipse (``p^2 = (x / 1.12)^2
    + y^2``) and the whole gently cupped (``z`` measured from ``0.12 p^2``): a fat convex
    rim, a band of saddles inside it and a shallow dimple in the middle of each side (a
    quartic level set; smooth, as ``a > c``), isotropically remeshed."""
    c, a = BLOOD_CELL_FOCI, BLOOD_CELL_A

    def inside(x, y, z):
        p2 = (x / 1.12) ** 2 + y * y
        w = z - 0.12 * p2
        q = (p2 + w * w) ** 2 - 2.0 * c * c * (p2 - w * w) + c ** 4
        return (a ** 4 - q) / (4.0 * a ** 3)  # roughly a distance near the surface

    return vm._level_set_mesh(inside, [-0.8, -0.72, -0.32, 0.8, 0.72, 0.38], 0.01,
                              BLOOD_CELL_H)


BLOOD_CELL_FOCI, BLOOD_CELL_A = 0.45, 0.4635


# --------------------------------------------------------------------------- brain-like


def _gyral_cells() -> list[tuple[float, float, float]]:
    """The centres of the polygonal gyri: a Fibonacci lattice of :data:`GYRAL_CELLS` unit
    directions, each moved by up to 0.25 of the lattice's spacing (a seeded numpy
    generator's uniform numbers: the same bits on every CPU)."""
    rng = np.random.default_rng(1437)
    shifts = rng.uniform(-1.0, 1.0, size=(GYRAL_CELLS, 3)).tolist()
    spacing = math.sqrt(4.0 * math.pi / GYRAL_CELLS)
    golden = math.pi * (3.0 - math.sqrt(5.0))
    centres = []
    for k, (sx, sy, sz) in enumerate(shifts):
        z = 1.0 - 2.0 * (k + 0.5) / GYRAL_CELLS
        r = math.sqrt(1.0 - z * z)
        px = r * math.cos(k * golden) + 0.25 * spacing * sx
        py = r * math.sin(k * golden) + 0.25 * spacing * sy
        pz = z + 0.25 * spacing * sz
        n = math.sqrt(px * px + py * py + pz * pz)
        centres.append((px / n, py / n, pz / n))
    return centres


def _polygyral_brain() -> BenchMesh:
    """A synthetic cortex with polygonal gyri (holdout 14; brain-like, not a brain): a whole
    brain's ovoid, widest towards the back, flattened underneath, a slight temporal bulge
    low on each side, its surface divided into polygonal gyri (the cells of a Voronoi diagram of
    90 jittered directions, measured on warped directions squeezed front to back, so the
    gyri are long and bent) by deep narrow sulci along the cells' borders, meeting three at a
    time in Y-junctions, their depth varying smoothly over the brain; the gyri are rounded
    over their whole width. Made as a radial
    height field over an icosphere (so it cannot cross itself), then isotropically remeshed
    with no feature kept."""
    centres = _gyral_cells()

    def radius(ux, uy, uz):
        lateral = 0.56 * (1.0 - 0.1 * uy)  # wider at the back (-y)
        r = 1.0 / math.sqrt((ux / lateral) ** 2 + (uy / 0.78) ** 2 + (uz / 0.52) ** 2)
        for side in (-1.0, 1.0):  # the temporal bulges
            r += 0.08 * math.exp(-((ux - side * 0.62) ** 2 + (uy - 0.2) ** 2
                                   + (uz + 0.45) ** 2) / 0.08)
        r = _flattened_underneath(r, uz, 0.34)  # flattened underneath, blended
        # the cells measured on warped, front-back stretched directions: long, bent gyri
        wx = ux + 0.15 * math.sin(3.0 * uy + 1.0)
        wy = 0.6 * (uy + 0.15 * math.sin(2.5 * uz + 2.0))
        wz = uz + 0.15 * math.sin(3.0 * ux)
        n = math.sqrt(wx * wx + wy * wy + wz * wz)
        near = sorted(math.acos(max(-1.0, min(1.0, (wx * cx + wy * cy + wz * cz) / n)))
                      for cx, cy, cz in centres)
        depth = SULCUS_DEPTH * (1.0 + 0.35 * math.sin(3.0 * ux + 2.0 * uy)
                                * math.cos(2.5 * uz - uy))
        # 1 / cosh: a narrow rounded fundus and gyri rounded over their whole width
        return r - depth / math.cosh((near[1] - near[0]) / SULCUS_WIDTH)

    return _radial_surface(radius, POLYGYRAL_H)


GYRAL_CELLS, SULCUS_DEPTH, SULCUS_WIDTH = 90, 0.07, 0.06


HAND_H, TORTOISE_H, CLAW_HAMMER_H, STOOL_H, CAMSHAFT_H, TRIBOSPHENIC_H = (
    0.012, 0.014, 0.014, 0.012, 0.012, 0.014)
BLOOD_CELL_H, POLYGYRAL_H = 0.016, 0.016


# A sixteenth set, made in session 37 after holdout 13 had been made: all six kinds, the
# brain kind by a synthetic cortex with polygonal gyri. No source is shared with the two
# halves, the first thirteen holdouts, the tuning-side CAD parts, scan_flatness_study.py's
# extra scans, animals.py, built_meshes.py, eggcrate.py, brain_probes.py, the λ-H families
# or session 32's tuning-side study parts; every parameter was fixed and the manifest
# committed before any fill was run on them. The scans are portable (the same bits on every
# CPU's BLAS).
HOLDOUT14_SOURCES: dict[str, Source] = {
    "scan_hand": Source("range_scan", "simulated scan of the open hand (portable scanner)",
                        vm._scan(_hand, (0.35, -1.0, 0.3), 167, portable=True)),
    "scan_blood_cell": Source("range_scan", "simulated scan of the biconcave disc (portable "
                              "scanner)", vm._scan(_blood_cell, (0.4, -0.5, 0.8), 168,
                                                   portable=True)),
    "scan_claw_hammer": Source("range_scan", "simulated scan of the claw hammer head CAD part "
                               "(portable scanner)", vm._scan(_claw_hammer, (0.4, -0.8, 0.6),
                                                              169, portable=True)),
    "scan_stool": Source("range_scan", "simulated scan of the stool CAD part (portable "
                         "scanner)", vm._scan(_stool, (0.4, -0.8, 0.5), 170, portable=True)),
    "hand": Source("organic", "open hand, flat palm, wrist stub, four fanned and slightly "
                   "curled three-segment fingers, thumb (level set), remeshed", _hand),
    "tortoise": Source("organic", "tortoise, domed carapace with grooved scutes over a flat "
                       "plastron, head on a neck, four stubby legs, tail (level set), "
                       "remeshed", _tortoise),
    "claw_hammer": Source("cad", "manifold3d: claw hammer head, chamfered striking face, neck, "
                          "chamfered cheek block with an oblong eye, curved tapering claw "
                          "with a V notch", _claw_hammer),
    "stool": Source("cad", "manifold3d: stool, round seat with a chamfered top edge and a "
                    "hand hole, four splayed tapered legs, four rungs", _stool),
    "camshaft": Source("cad", "manifold3d: camshaft, three chamfered journals, four cam "
                       "lobes a quarter turn apart, flange with four bolt holes, blind end "
                       "bore", _camshaft),
    "tribosphenic": Source("teeth", "tribosphenic lower molar, high trigonid of three cusps "
                           "with shearing crests, low talonid basin with three cusps, two "
                           "roots (level set)", _tribosphenic),
    "blood_cell": Source("smooth", "biconcave disc (revolved Cassini oval with a waist, "
                         "elliptic plan, gently cupped; quartic level set), remeshed",
                         _blood_cell),
    "polygyral_brain": Source("brain", "synthetic cortex, ovoid with temporal bulges, "
                              "polygonal gyri between deep sulci meeting in Y-junctions "
                              "(radial height field), remeshed", _polygyral_brain),
}
