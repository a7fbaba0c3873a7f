"""Holdout set 16's meshes (session 39): 12 fresh meshes, made and committed before any fill.

As holdouts 8 to 15's (``holdout8_meshes.py`` .. ``holdout15_meshes.py``): kept out of
:mod:`validation_meshes`, which imports :data:`HOLDOUT16_SOURCES` from here at its end and
adds them to its ``SOURCES``, so every benchmark reaches these meshes through it
(``validation_meshes.load("crab")``). The generators use its helpers (level sets,
manifold3d remeshing), holdouts 11 and 12's level-set and radial-surface helpers, holdout
14's smooth minimum and holdout 15's flattened capsule; the four range scans are the
portable scanner's (``simulated_scan(..., portable=True)``: the same bits under every BLAS
kernel). Import :mod:`validation_meshes` first, not this module (an import cycle otherwise).

All six kinds, as holdouts 11 to 15: 4 simulated range scans of 4 of the others (one of
them the first scan of a brain-kind surface), 2 organic shapes, 3 CAD parts, 1 tooth, 1
smooth level set and 1 brain-like surface (a synthetic cortex whose sulci are open arcs
nested round a lateral fissure on each side, not a real brain)
(``benchmarks/holdout16_manifest.json``, docs/validation.md "Holdout set 16").

The level sets' insides and the radial heights are written with Python floats and
:mod:`math` (no numpy transcendental on arrays, whose SIMD loops differ between CPUs), so a
mesh's bits do not depend on the CPU's vector units.
"""

from __future__ import annotations

import math

import validation_meshes as vm
from holdout11_meshes import _capsule, _radial_surface, _smooth_max
from holdout12_meshes import _ellipsoid
from holdout14_meshes import _flattened_underneath, _smooth_min
from holdout15_meshes import _flat_capsule
from validation_meshes import BenchMesh, Source

# --------------------------------------------------------------------------- organic


def _crab_leg(side: float, k: int) -> list[tuple]:
    """The two segments of walking leg ``k`` (0 at the front) on ``side`` (-1, 1), as
    ``(start, end, start radius, end radius)``: from the shell's edge out and up to a knee,
    then out and down to a pointed tip on the ground."""
    y0 = 0.1 - 0.1 * k  # where it leaves the shell, front to back
    sweep = math.radians(-20.0 + 22.0 * k)  # the legs fan backwards
    hip = (side * 0.27, y0, -0.02)
    knee = (side * (0.27 + 0.22 * math.cos(sweep)), y0 - 0.22 * math.sin(sweep), 0.1)
    tip = (side * (0.27 + 0.42 * math.cos(sweep)), y0 - 0.42 * math.sin(sweep), -0.18)
    return [(hip, knee, 0.034, 0.028), (knee, tip, 0.028, 0.014)]


def _crab() -> BenchMesh:
    """A crab (holdout 16): a broad shell (an ellipsoid flattened top to bottom, its front
    edge straighter), two eyes on short stalks, two claws (an arm of two segments, a
    swollen palm flattened side to side and two tapering fingers with a gap between them)
    and four walking legs a side (two segments each, bent up at the knee, down to pointed
    tips) (smooth unions, manifold3d level set), isotropically remeshed with no feature
    kept."""
    legs = [segment for side in (-1.0, 1.0) for k in range(4) for segment in _crab_leg(side, k)]

    def inside(x, y, z):
        shell = _ellipsoid(x, y, z, (0.0, -0.02, 0.0), (0.3, 0.22, 0.1))
        front = _ellipsoid(x, y, z, (0.0, 0.06, 0.01), (0.26, 0.16, 0.085))
        parts = [shell, front]
        parts += [_capsule(x, y, z, *segment) for segment in legs]
        for side in (-1.0, 1.0):
            parts.append(_capsule(x, y, z, (side * 0.07, 0.18, 0.04), (side * 0.09, 0.25, 0.1),
                                  0.022, 0.018))  # an eye stalk
            parts.append(0.03 - math.sqrt((x - side * 0.09) ** 2 + (y - 0.255) ** 2
                                          + (z - 0.105) ** 2))  # the eye
            parts.append(_capsule(x, y, z, (side * 0.2, 0.12, 0.0), (side * 0.33, 0.24, 0.04),
                                  0.045, 0.04))  # the arm
            parts.append(_capsule(x, y, z, (side * 0.33, 0.24, 0.04), (side * 0.3, 0.36, 0.05),
                                  0.04, 0.045))
            parts.append(_flat_capsule(x, y, z, (side * 0.29, 0.4, 0.05),
                                       (side * 0.25, 0.5, 0.05), 0.075, 0.06, 1.5, 0))
            parts.append(_capsule(x, y, z, (side * 0.24, 0.53, 0.08), (side * 0.18, 0.68, 0.06),
                                  0.032, 0.01))  # the fixed finger
            parts.append(_capsule(x, y, z, (side * 0.24, 0.53, 0.01), (side * 0.17, 0.66, -0.03),
                                  0.03, 0.01))  # the movable finger, below it
        return _smooth_max(parts, 0.015)

    return vm._level_set_mesh(inside, [-0.78, -0.52, -0.24, 0.78, 0.74, 0.18], 0.01, CRAB_H)


def _heart() -> BenchMesh:
    """A heart (holdout 16; the organ's outer shape): two ventricles making a blunt cone
    that ends in an apex pointing down, forwards and to one side, two atria bulging at the
    top behind them with an ear-like flap each, a shallow groove between atria and
    ventricles, and its great vessels: the aorta rising from the middle and arching back
    over the top to a stub going down, three branches rising from the arch, the pulmonary
    trunk in front of it forking in two, and a vena cava standing at the side (smooth
    unions, manifold3d level set), isotropically remeshed with no feature kept."""
    arch = [(0.02, 0.02, 0.18), (0.03, 0.0, 0.36), (-0.04, -0.1, 0.46), (-0.12, -0.22, 0.44),
            (-0.16, -0.3, 0.34), (-0.17, -0.33, 0.26)]  # its stub clear of the atria
    branches = [((-0.02, -0.08, 0.47), (0.03, -0.04, 0.62)),
                ((-0.07, -0.15, 0.47), (-0.07, -0.12, 0.62)),
                ((-0.12, -0.22, 0.46), (-0.17, -0.2, 0.6))]

    def inside(x, y, z):
        # the ventricles: along an axis tilted from the apex (lower, front, to -x) upwards
        lv = _capsule(x, y, z, (-0.14, 0.12, -0.42), (0.0, -0.02, 0.02), 0.05, 0.25)
        rv = _ellipsoid(x, y, z, (0.09, 0.1, -0.08), (0.2, 0.15, 0.24))
        atria = [_ellipsoid(x, y, z, (sx, -0.14, 0.1), (0.15, 0.12, 0.12))
                 for sx in (-0.12, 0.14)]
        flaps = [_flat_capsule(x, y, z, (sx, -0.02, 0.16), (sx + dx, 0.08, 0.12), 0.05, 0.03,
                               1.8, 2) for sx, dx in ((-0.2, -0.05), (0.22, 0.06))]
        aorta = [_capsule(x, y, z, a, b, 0.065, 0.062) for a, b in zip(arch[:-1], arch[1:],
                                                                       strict=True)]
        vessels = [_capsule(x, y, z, a, b, 0.026, 0.022) for a, b in branches]
        trunk = _capsule(x, y, z, (0.1, 0.08, 0.15), (0.1, 0.08, 0.28), 0.06, 0.055)
        forks = [_capsule(x, y, z, (0.1, 0.08, 0.28), (0.1 + dx, 0.14, 0.3), 0.045, 0.04)
                 for dx in (-0.2, 0.17)]  # in front of the aorta, not round it
        cava = _capsule(x, y, z, (0.24, -0.1, 0.12), (0.26, -0.1, 0.42), 0.05, 0.048)
        body = _smooth_max([lv, rv, *atria, *flaps], 0.05)
        groove = 0.015 * math.exp(-((z - 0.02 + 0.3 * y) / 0.03) ** 2)  # atria | ventricles
        return _smooth_max([body - groove, *aorta, *vessels, trunk, *forks, cava], 0.02)

    return vm._level_set_mesh(inside, [-0.42, -0.44, -0.52, 0.46, 0.4, 0.68], 0.01, HEART_H)


# --------------------------------------------------------------------------- CAD


def _hose_barb() -> BenchMesh:
    """A hose fitting (holdout 16): a hexagonal collar (its corners chamfered by a double
    cone, as a nut's) between a barbed nozzle (three conical barbs, each ending in a sharp
    step) and a plain spigot with an O-ring groove and a chamfered end, a bore through
    (manifold3d revolve, prisms and booleans; genus 1)."""
    import manifold3d as m3

    nozzle = [(0.0, 0.05), (0.065, 0.05)]
    for k in range(3):  # each barb a sharp step out facing the collar, then a cone to the tip
        z0 = 0.12 + 0.13 * k
        nozzle += [(0.065, z0), (0.09, z0), (0.065, z0 + 0.1)]
    nozzle += [(0.065, 0.49), (0.055, 0.5), (0.0, 0.5)]
    barbs = m3.Manifold.revolve(m3.CrossSection([nozzle]), 64)
    spigot = m3.Manifold.revolve(m3.CrossSection([[
        (0.0, -0.45), (0.055, -0.45), (0.07, -0.435), (0.07, -0.33), (0.05, -0.33),
        (0.05, -0.29), (0.07, -0.29), (0.07, -0.03), (0.0, -0.03)]]), 64)
    cone = m3.Manifold.revolve(m3.CrossSection([[(0.0, -0.09), (0.13, -0.09), (0.19, -0.03),
                                                 (0.19, 0.03), (0.13, 0.09), (0.0, 0.09)]]),
                               64)
    collar = m3.Manifold.cylinder(0.18, 0.17, -1, 6, True) ^ cone
    bore = m3.Manifold.cylinder(1.2, 0.032, -1, 32, True)
    part = (barbs + spigot + collar) - bore
    return vm._manifold_mesh(part, HOSE_BARB_H, refine=0.03)


def _crankshaft() -> BenchMesh:
    """A crankshaft for two cylinders (holdout 16): three main journals on the axis, two
    crank pins half a turn apart, each between two webs (flat plates, rounded round the pin,
    with a half-disc counterweight on the far side of the axis), a nose with an open keyway
    at the front, a flange with six bolt holes at the back, and an oil hole slanting through
    each crank pin (manifold3d prisms and booleans; genus 8)."""
    import manifold3d as m3

    def along_x(solid, x0: float, y: float = 0.0):  # made along z, turned to run along x
        return solid.rotate((0.0, 90.0, 0.0)).translate((x0, y, 0.0))

    def web(x0: float, up: float):  # a web 0.06 thick from x0, its pin at y = 0.16 up
        outline = m3.CrossSection.batch_hull([
            m3.CrossSection.circle(0.1, 48),
            m3.CrossSection.circle(0.085, 48).translate((0.0, CRANK_THROW * up))])
        half = m3.CrossSection.square((0.4, 0.2)).translate((-0.2, -0.2 if up > 0 else 0.0))
        weight = m3.CrossSection.circle(0.19, 48) ^ half
        return along_x(m3.Manifold.extrude(outline + weight, 0.06), x0)

    def rod(x0: float, length: float, r: float, segments: int, y: float = 0.0):
        # reaching 0.01 into its neighbours each end, so that the union has no touching faces
        return along_x(m3.Manifold.cylinder(length + 0.02, r, -1, segments), x0 - 0.01, y)

    parts = [rod(-0.58, 0.12, 0.045, 32)]  # the nose
    webs, holes = [], []
    for k, x0 in enumerate((-0.46, -0.08, 0.3)):  # the main journals, 0.12 long
        parts.append(rod(x0, 0.12, 0.075, 48))
        if k == 2:
            break
        up = 1.0 if k == 0 else -1.0
        webs += [web(x0 + 0.12, up), web(x0 + 0.32, up)]
        parts.append(rod(x0 + 0.18, 0.14, 0.06, 48, CRANK_THROW * up))  # the crank pin
        holes.append(m3.Manifold.cylinder(0.2, 0.014, -1, 16, True).rotate(
            (45.0, 0.0, 0.0)).translate((x0 + 0.25, CRANK_THROW * up, 0.0)))  # oil hole
    flange = along_x(m3.Manifold.cylinder(0.05, 0.16, -1, 64), 0.42)
    holes += [along_x(m3.Manifold.cylinder(0.1, 0.018, -1, 24), 0.4, 0.11 * math.cos(a))
              .translate((0.0, 0.0, 0.11 * math.sin(a)))
              for a in (math.radians(60.0 * k + 30.0) for k in range(6))]
    holes.append(m3.Manifold.cube((0.09, 0.024, 0.03), True).translate((-0.54, 0.0, 0.04)))
    part = (m3.Manifold.batch_boolean([*parts, *webs, flange], m3.OpType.Add)
            - m3.Manifold.batch_boolean(holes, m3.OpType.Add))
    return vm._manifold_mesh(part, CRANKSHAFT_H, refine=0.03)


def _grille() -> BenchMesh:
    """A vent grille (holdout 16): a rectangular panel with rounded corners, a raised rim
    round it with a chamfered outer top edge, seven parallel slots with round ends through
    the panel, two stiffening bars across the slots' middle on the back, and four screw
    holes with countersinks in the corners (manifold3d prisms and booleans; genus 25)."""
    import manifold3d as m3

    def rounded(width: float, height: float, r: float):
        return m3.CrossSection.square((width - 2 * r, height - 2 * r), True).offset(
            r, m3.JoinType.Round, circular_segments=32)

    panel = m3.Manifold.extrude(rounded(0.9, 0.6, 0.06), 0.045)
    rim = (m3.Manifold.extrude(rounded(0.9, 0.6, 0.06), 0.075)
           - m3.Manifold.extrude(rounded(0.8, 0.5, 0.015), 0.2).translate((0.0, 0.0, -0.05)))
    bevel = m3.Manifold.hull(m3.Manifold.batch_boolean([
        m3.Manifold.extrude(rounded(0.9, 0.6, 0.06), 0.05),
        m3.Manifold.extrude(rounded(0.87, 0.57, 0.045), 0.075)], m3.OpType.Add))
    frame = rim ^ bevel
    slots = [m3.Manifold.extrude(m3.CrossSection.square((0.5, 0.001), True).offset(
        0.019, m3.JoinType.Round, circular_segments=32), 0.2).translate((0.0, y, -0.05))
        for y in (0.06 * k - 0.18 for k in range(7))]
    bars = [m3.Manifold.cube((0.04, 0.44, 0.045), True).translate((x, 0.0, -0.0075))
            for x in (-0.09, 0.09)]  # 0.03 below the panel, 0.015 into it
    screws = []
    for sx in (-1.0, 1.0):
        for sy in (-1.0, 1.0):
            at = (sx * 0.36, sy * 0.22, 0.0)
            screws.append(m3.Manifold.cylinder(0.2, 0.016, -1, 24, True).translate(at))
            screws.append(m3.Manifold.cylinder(0.03, 0.016, 0.04, 24).translate(
                (at[0], at[1], 0.02)))  # the countersink, at the panel's face
    part = (panel + frame - m3.Manifold.batch_boolean([*slots, *screws], m3.OpType.Add)
            + m3.Manifold.batch_boolean(bars, m3.OpType.Add))  # the bars bridge the slots
    return vm._manifold_mesh(part, GRILLE_H, refine=0.03)


# --------------------------------------------------------------------------- teeth


def _bilophodont() -> BenchMesh:
    """A bilophodont molar (holdout 16; a tapir's or a monkey's): a crown of rounded-
    rectangle section whose top carries two transverse crests (lophs), each joining a cusp
    on the cheek side to one on the tongue side, a deep valley between them and small
    shelves in front and behind; a bulging band (the cingulum) round the crown's foot, a
    narrower neck and two roots, one under each loph, flattened front to back (manifold3d
    level set), isotropically remeshed with no feature kept."""
    lophs = (0.15, -0.15)  # y of each crest

    def section(x, y, half_x, half_y, depth):  # a rounded rectangle (superellipse, power 4)
        return depth * (1.0 - math.sqrt(math.sqrt((x / half_x) ** 4 + (y / half_y) ** 4)))

    def inside(x, y, z):
        body = _smooth_min([section(x, y, 0.3, 0.36, 0.16), 0.26 - z, z + 0.05], 0.03)
        crests = []  # each loph a crest sunk into the body's top, a cusp at each end
        for yl in lophs:
            crests += [_capsule(x, y, z, (-0.19, yl, 0.3), (0.19, yl + 0.01, 0.31), 0.07, 0.07),
                       0.08 - math.sqrt((x + 0.19) ** 2 + (y - yl) ** 2 + (z - 0.33) ** 2),
                       0.08 - math.sqrt((x - 0.19) ** 2 + (y - yl) ** 2 + (z - 0.35) ** 2)]
        crown = _smooth_max([body, *crests], 0.025)
        valley = _capsule(x, y, z, (-0.4, 0.0, 0.33), (0.4, 0.0, 0.33), 0.07, 0.07)
        crown = _smooth_min([crown, -valley], 0.015)
        # the cingulum: a tube of radius 0.025 along the crown's wall (the section's value
        # with depth 0.3 is about the distance in from the wall)
        band = 0.025 - math.sqrt(section(x, y, 0.3, 0.36, 0.3) ** 2 + (z - 0.03) ** 2)
        neck = _smooth_min([section(x, y, 0.24, 0.3, 0.13), -z, z + 0.22], 0.02)
        roots = [_flat_capsule(x, y, z, (0.0, yl, -0.1), (0.02, 1.2 * yl, -0.6), 0.13,
                               0.05, 1.8, 1) for yl in lophs]
        return _smooth_max([crown, band, neck, *roots], 0.03)

    return vm._level_set_mesh(inside, [-0.4, -0.48, -0.7, 0.4, 0.48, 0.5], 0.012,
                              BILOPHODONT_H)


# --------------------------------------------------------------------------- smooth


def _footed_bowl() -> BenchMesh:
    """A footed bowl (holdout 16): a spherical shell 0.06 thick cut off above its middle,
    the rim rounded, standing on a ring-shaped foot (a torus) under its bottom (smooth
    minimum and maximum, manifold3d level set; genus 0), isotropically remeshed."""

    def inside(x, y, z):
        d = math.sqrt(x * x + y * y + (z - 0.5) ** 2)  # from the sphere's centre
        wall = _smooth_min([0.48 - d, d - 0.42, 0.66 - z], 0.02)
        rho = math.sqrt(x * x + y * y)
        foot = 0.035 - math.sqrt((rho - 0.2) ** 2 + (z - 0.045) ** 2)
        return _smooth_max([wall, foot], 0.025)

    return vm._level_set_mesh(inside, [-0.52, -0.52, -0.02, 0.52, 0.52, 0.7], 0.01,
                              FOOTED_BOWL_H)


# --------------------------------------------------------------------------- brain-like


def _arcuate_depth(ux, uy, uz, centre) -> float:
    """The sulci round one lateral fissure at ``centre`` (a unit direction): their depth
    (0 to 1) at the unit direction (ux, uy, uz). :data:`ARCS` gives each arc's angular
    radius about the centre and its half-span either side of straight up (the arcs open
    downwards and end blind); the fissure itself runs up from below into the centre."""
    cx, cy, cz = centre
    dot = ux * cx + uy * cy + uz * cz
    rho = math.acos(max(-1.0, min(1.0, dot)))
    # a frame at the centre: "up" is +z made tangent, "along" its cross with the centre
    upx, upy, upz = -cz * cx, -cz * cy, 1.0 - cz * cz
    n = math.sqrt(upx * upx + upy * upy + upz * upz)
    upx, upy, upz = upx / n, upy / n, upz / n
    alx, aly, alz = cy * upz - cz * upy, cz * upx - cx * upz, cx * upy - cy * upx
    px, py, pz = ux - dot * cx, uy - dot * cy, uz - dot * cz
    theta = math.atan2(px * alx + py * aly + pz * alz, px * upx + py * upy + pz * upz)
    wiggle = 0.03 * math.sin(5.0 * theta + 2.0 * rho)
    depth = 0.0
    for radius, half_span in ARCS:
        fade = 0.5 - 0.5 * math.tanh((abs(theta) - math.radians(half_span)) / 0.12)
        depth = max(depth, fade / math.cosh((rho + wiggle - radius) / ARC_WIDTH))
    # the lateral fissure: up from below (theta = pi) into the centre, deeper; the distance
    # to its ray is rho sin(angle off it) within a quarter turn of it, rho beyond
    off = math.pi - abs(theta)
    to_fissure = rho * math.sin(off) if off < 0.5 * math.pi else rho
    along = 0.5 - 0.5 * math.tanh((rho - 0.55) / 0.06)
    depth = max(depth, 1.4 * along / math.cosh(to_fissure / ARC_WIDTH))
    return depth


def _arcuate_cortex() -> BenchMesh:
    """A synthetic cortex with arcuate sulci (holdout 16; brain-like, not a brain): an ovoid
    long front to back, narrower at the front, its underside flattened, two small bulbs at
    the front below; on each side a short deep fissure runs up from below into a centre,
    and round it three sulci are nested open arcs (a small circle's upper part, each arc's
    span its own, wavy) ending blind below, a fourth runs front to back near the top, and a
    transverse sulcus crosses the top near the front: broad gyri bent round the fissure, as
    in a carnivore's brain. Made as a radial height field over an icosphere (so it cannot
    cross itself), then isotropically remeshed with no feature kept."""
    centres = []
    for side in (-1.0, 1.0):
        n = math.sqrt(0.85**2 + 0.15**2 + 0.2**2)
        centres.append((side * 0.85 / n, 0.15 / n, -0.2 / n))

    def radius(ux, uy, uz):
        lateral = 0.5 * (1.0 - 0.15 * uy)  # narrower at the front (+y)
        r = 1.0 / math.sqrt((ux / lateral) ** 2 + (uy / 0.75) ** 2 + (uz / 0.5) ** 2)
        r = _flattened_underneath(r, uz, 0.32)  # flattened underneath, blended
        for side in (-1.0, 1.0):  # the bulbs, front and below
            r += 0.05 * math.exp(-((ux - side * 0.12) ** 2 + (uy - 0.93) ** 2
                                   + (uz + 0.3) ** 2) / (2.0 * 0.08**2))
        depth = max(_arcuate_depth(ux, uy, uz, c) for c in centres)
        cross = ((0.5 - 0.5 * math.tanh((abs(ux) - 0.45) / 0.06))
                 * (0.5 + 0.5 * math.tanh(uz / 0.1)))  # across the top, near the front
        depth = max(depth, cross / math.cosh((uy - 0.42 - 0.1 * ux * ux) / ARC_WIDTH))
        return r - ARC_DEPTH * depth

    return _radial_surface(radius, ARCUATE_H)


# (angular radius about the fissure's centre, half-span either side of up in degrees)
ARCS = ((0.36, 120.0), (0.62, 105.0), (0.88, 95.0), (1.18, 70.0))
ARC_DEPTH, ARC_WIDTH = 0.065, 0.05
CRANK_THROW = 0.16  # the crank pins' distance from the axis


CRAB_H, HEART_H, HOSE_BARB_H, CRANKSHAFT_H, GRILLE_H, BILOPHODONT_H = (
    0.012, 0.012, 0.012, 0.012, 0.012, 0.014)
FOOTED_BOWL_H, ARCUATE_H = 0.012, 0.016


# An eighteenth set, made in session 39 after holdout 15 had been made: all six kinds, the
# brain kind by a synthetic cortex with arcuate sulci. No source is shared with the two
# halves, the first fifteen holdouts, the tuning-side CAD parts, the smooth tuning set,
# scan_flatness_study.py's extra scans, animals.py, built_meshes.py, eggcrate.py,
# brain_probes.py, the λ-H families or session 32's tuning-side study parts; every parameter
# was fixed and the manifest committed before any fill was run on them. The scans are
# portable (the same bits on every CPU's BLAS).
HOLDOUT16_SOURCES: dict[str, Source] = {
    "scan_crab": Source("range_scan", "simulated scan of the crab (portable scanner)",
                        vm._scan(_crab, (0.3, -0.6, 0.8), 175, portable=True)),
    "scan_footed_bowl": Source("range_scan", "simulated scan of the footed bowl (portable "
                               "scanner)", vm._scan(_footed_bowl, (0.4, -0.7, 0.7), 176,
                                                    portable=True)),
    "scan_heart": Source("range_scan", "simulated scan of the heart (portable scanner)",
                         vm._scan(_heart, (0.5, 0.8, 0.3), 177, portable=True)),
    "scan_arcuate_cortex": Source("range_scan", "simulated scan of the synthetic cortex with "
                                  "arcuate sulci (portable scanner)",
                                  vm._scan(_arcuate_cortex, (0.9, -0.3, 0.3), 178,
                                           portable=True)),
    "crab": Source("organic", "crab, broad shell, eyes on stalks, two claws with a gap between "
                   "the fingers, eight bent walking legs (level set), remeshed", _crab),
    "heart": Source("organic", "heart, ventricles ending in an apex, atria with ear-like "
                    "flaps, aortic arch with three branches, forked pulmonary trunk, vena cava "
                    "(level set), remeshed", _heart),
    "hose_barb": Source("cad", "manifold3d: hose barb fitting, chamfered hexagonal collar, "
                        "three sharp barbs, spigot with an O-ring groove and a chamfered end, "
                        "bore", _hose_barb),
    "crankshaft": Source("cad", "manifold3d: two-throw crankshaft, three main journals, webs "
                         "with counterweights, crank pins with oil holes, keyed nose, flange "
                         "with six bolt holes", _crankshaft),
    "grille": Source("cad", "manifold3d: vent grille, rounded panel, raised rim with a "
                     "chamfered edge, seven round-ended slots, two back bars, countersunk "
                     "screw holes", _grille),
    "bilophodont": Source("teeth", "bilophodont molar, two transverse crests, deep valley, "
                          "cingulum band, neck, two flattened roots (level set)",
                          _bilophodont),
    "footed_bowl": Source("smooth", "footed bowl, spherical shell cut above its middle with a "
                          "rounded rim, ring foot (level set), remeshed", _footed_bowl),
    "arcuate_cortex": Source("brain", "synthetic cortex, ovoid with front bulbs, sulci in "
                             "nested open arcs round a lateral fissure on each side, transverse "
                             "sulcus (radial height field), remeshed", _arcuate_cortex),
}
