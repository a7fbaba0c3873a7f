"""Holdout set 13's meshes (session 36): 12 fresh meshes, made and committed before any fill.

As holdouts 8 to 12's (``holdout8_meshes.py`` .. ``holdout12_meshes.py``): kept out of
:mod:`validation_meshes`, which imports :data:`HOLDOUT13_SOURCES` from here at its end and
adds them to its ``SOURCES``, so every benchmark reaches these meshes through it
(``validation_meshes.load("seahorse")``). The generators use its helpers (level sets,
manifold3d remeshing) and holdout 11's level-set and radial-surface helpers; the four range
scans are the portable scanner's (``simulated_scan(..., portable=True)``: the same bits
under every BLAS kernel). Import :mod:`validation_meshes` first, not this module (an import
cycle otherwise).

All six kinds, as holdouts 11 and 12: 4 simulated range scans of 4 of the others, 2
organic shapes, 3 CAD parts, 1 tooth, 1 smooth level set and 1 brain-like surface (a
synthetic forebrain with whorled gyri, not a real brain)
(``benchmarks/holdout13_manifest.json``, docs/validation.md "Holdout set 13").

The level sets' insides and the radial heights are written with Python floats and
:mod:`math` (no numpy transcendental on arrays, whose SIMD loops differ between CPUs); the
seahorse's tail takes a maximum over numpy arrays of squares and square roots, each
correctly rounded. So a mesh's bits do not depend on the CPU's vector units.
"""

from __future__ import annotations

import math

import numpy as np
import validation_meshes as vm
from holdout11_meshes import _capsule, _radial_surface, _smooth_max
from validation_meshes import BenchMesh, Source

GOLDEN_ANGLE = math.pi * (3.0 - math.sqrt(5.0))


# --------------------------------------------------------------------------- organic


def _seahorse_spine() -> tuple[np.ndarray, np.ndarray]:
    """Centres and radii of the balls whose union is the seahorse's trunk and tail: an arc
    bulging forward (the belly), a short drop, then a spiral of 1.1 turns curling forward
    whose radius shrinks from 0.215 to 0.06, the tube from 0.055 to 0.03, faint bony rings
    along it (by :mod:`math`: the same bits on every CPU)."""
    points = []  # (x, z, tube radius)
    for k in range(161):  # the trunk: an arc about (-0.25, 0.05) of radius 0.3, 60° to -60°
        a = math.radians(60.0 - 120.0 * k / 160)
        t = k / 160
        tube = (0.09 + 0.06 * math.sin(0.5 * math.pi * t / 0.55) if t < 0.55
                else 0.15 - 0.075 * (t - 0.55) / 0.45)
        points.append((-0.25 + 0.3 * math.cos(a), 0.05 + 0.3 * math.sin(a), tube))
    for k in range(1, 61):  # the drop into the tail
        t = k / 60
        points.append((-0.1 - 0.02 * t, -0.21 - 0.27 * t, 0.075 - 0.02 * t))
    start, end = math.radians(158.0), math.radians(158.0 + 1.1 * 360.0)
    for k in range(1, 501):  # the curl about (0.08, -0.56)
        t = k / 500
        a = start + (end - start) * t
        r = 0.215 - 0.155 * t
        points.append((0.08 + r * math.cos(a), -0.56 + r * math.sin(a), 0.055 - 0.025 * t))
    length = [0.0]  # arc length along the spine, for the rings
    for p, q in zip(points[:-1], points[1:], strict=True):
        length.append(length[-1] + math.hypot(q[0] - p[0], q[1] - p[1]))
    centres = np.array([(x, 0.0, z) for x, z, _ in points])
    radii = np.array([tube + 0.006 * math.cos(2.0 * math.pi * s / SEAHORSE_RING)
                      for (_, _, tube), s in zip(points, length, strict=True)])
    return centres, radii


SEAHORSE_RING = 0.08  # the spacing of the bony rings along the trunk and tail


def _seahorse() -> BenchMesh:
    """A seahorse (holdout 13): standing, a trunk bulging forward into a belly and
    flattened from side to side, a tail curling forward into a spiral of 1.1 turns, faint
    bony rings along trunk and tail, a head bent forward with a long tubular muzzle ending
    in a flared tip, a coronet on the head (a short stump), two eyes and a small flat back fin
    (smooth unions, manifold3d level set), isotropically remeshed with no feature kept."""
    centres, radii = _seahorse_spine()

    def inside(x, y, z):
        y_flat = y * 1.25  # the trunk and tail flattened from side to side
        d2 = (centres[:, 0] - x) ** 2 + y_flat * y_flat + (centres[:, 2] - z) ** 2
        spine = float((radii - np.sqrt(d2)).max()) / 1.25
        head = _capsule(x, y, z, (-0.1, 0.0, 0.36), (-0.04, 0.0, 0.44), 0.085, 0.08)
        muzzle = _capsule(x, y, z, (0.0, 0.0, 0.44), (0.26, 0.0, 0.37), 0.05, 0.032)
        tip = 0.042 - math.sqrt((x - 0.27) ** 2 + y * y + (z - 0.37) ** 2)
        coronet = _capsule(x, y, z, (-0.09, 0.0, 0.48), (-0.13, 0.0, 0.58), 0.045, 0.035)
        eyes = [0.028 - math.sqrt((x + 0.02) ** 2 + (y - s * 0.07) ** 2 + (z - 0.455) ** 2)
                for s in (-1.0, 1.0)]
        fin = _capsule(x, y * 2.2, z, (-0.11, 0.0, 0.06), (-0.2, 0.0, -0.07), 0.05,
                       0.035) / 2.2
        return _smooth_max([spine, head, muzzle, tip, coronet, *eyes, fin], 0.025)

    return vm._level_set_mesh(inside, [-0.4, -0.2, -0.85, 0.4, 0.2, 0.7], 0.015, SEAHORSE_H)


def _pinecone() -> BenchMesh:
    """A pinecone (holdout 13): an egg-shaped cone, widest low down and tapering to its
    top, covered by 150 woody scales set on a golden-angle spiral (each a bump rising to a
    rim on its lower side where it drops onto the scale below: the higher of neighbouring
    scales wins, so they overlap like shingles), smaller towards both ends. Made as a radial
    height field over an icosphere (so it cannot cross itself), then isotropically remeshed
    with no feature kept."""
    count = PINECONE_SCALES
    scales = []  # (polar angle, azimuth) of each scale's centre, from the top down
    for k in range(count):
        polar = math.acos(1.0 - 2.0 * (k + 0.5) / count)
        scales.append((polar, math.fmod(k * GOLDEN_ANGLE, 2.0 * math.pi)))

    def radius(ux, uy, uz):
        lateral = 0.3 * (1.0 - 0.3 * uz)  # wider low down
        r = 1.0 / math.sqrt((ux * ux + uy * uy) / (lateral * lateral) + (uz / 0.5) ** 2)
        polar, azimuth = math.acos(max(-1.0, min(1.0, uz))), math.atan2(uy, ux)
        top = 0.0
        for p, a in scales:
            d_polar = polar - p
            if abs(d_polar) > 0.4:
                continue
            d_azimuth = math.remainder(azimuth - a, 2.0 * math.pi) * math.sin(polar)
            # rising slowly towards the lower rim (past the centre), dropping off below it
            down = d_polar - 0.08
            across = (d_azimuth / 0.15) ** 2 + (down / (0.07 if down > 0.0 else 0.2)) ** 2
            if across < 4.0:  # cut off where exp(-across) = exp(-4), continuously
                top = max(top, (math.exp(-across) - SCALE_FLOOR) / (1.0 - SCALE_FLOOR))
        ends = 1.0 - math.exp(-(ux * ux + uy * uy) / 0.06)  # smaller scales at the ends
        return r + PINECONE_RELIEF * ends * top

    return _radial_surface(radius, PINECONE_H)


PINECONE_SCALES, PINECONE_RELIEF = 150, 0.06
SCALE_FLOOR = math.exp(-4.0)


# --------------------------------------------------------------------------- CAD


def _elbow() -> BenchMesh:
    """A pipe elbow (holdout 13): a tube bent through a quarter turn (bend radius 0.4, outer
    radius 0.14, wall 0.045), a short straight stub at each end flaring out where it meets a
    square end plate with a bore and four bolt holes (manifold3d revolve and
    booleans; genus 9)."""
    import manifold3d as m3

    bend_r, outer, inner, stub = 0.4, 0.14, 0.095, 0.15
    disc = m3.CrossSection.circle(outer, 96).translate((bend_r, 0.0))
    bend = m3.Manifold.revolve(disc, 192, 90.0)
    bend_bore = m3.Manifold.revolve(m3.CrossSection.circle(inner, 96).translate((bend_r, 0.0)),
                                    192, 90.0)

    def end(length: float, radius: float, cone: float | None = None):
        # a solid along +z from 0, its section a circle (a cone if ``cone``)
        return m3.Manifold.cylinder(length, radius, radius if cone is None else cone, 96)

    def plate():
        square = m3.Manifold.cube((0.6, 0.6, 0.06), True).translate((0.0, 0.0, 0.03))
        bolts = [m3.Manifold.cylinder(0.2, 0.03, -1, 32).translate((sx * 0.2, sy * 0.2, -0.05))
                 for sx in (-1.0, 1.0) for sy in (-1.0, 1.0)]
        return square - m3.Manifold.batch_boolean(bolts, m3.OpType.Add)

    def fitting():  # stub, flare and plate along +z from the bend's end at z = 0
        flare = end(0.06, outer, outer + 0.036).translate((0.0, 0.0, stub - 0.05))
        body = end(stub, outer) + flare + plate().translate((0.0, 0.0, stub))
        return body - end(stub + 0.3, inner).translate((0.0, 0.0, -0.1))

    # at the bend's start (section in the xz-plane at y = 0) the pipe runs along -y, at its
    # end (section in the yz-plane at x = 0) along -x
    first = fitting().rotate((90.0, 0.0, 0.0)).translate((bend_r, 0.0, 0.0))
    second = fitting().rotate((0.0, -90.0, 0.0)).translate((0.0, bend_r, 0.0))
    part = (bend - bend_bore) + first + second
    return vm._manifold_mesh(part, ELBOW_H, refine=0.03)


def _padlock() -> BenchMesh:
    """A padlock (holdout 13): a body of rounded-rectangle plan (vertical edges rounded,
    its top edge chamfered) with a keyhole pocket on its front, and a round U-shaped
    shackle whose legs go into the top (manifold3d extrusions, hulls, revolve and
    booleans; genus 1)."""
    import manifold3d as m3

    width, depth, height, corner = 0.7, 0.28, 0.6, 0.06

    def slab(inset: float, z: float, thickness: float):
        plan = m3.CrossSection.square((width - 2 * corner - 2 * inset,
                                       depth - 2 * corner - 2 * inset), True).offset(
            corner, m3.JoinType.Round, circular_segments=48)
        return m3.Manifold.extrude(plan, thickness).translate((0.0, 0.0, z))

    body = m3.Manifold.batch_hull([slab(0.0, 0.0, height - 0.04),
                                   slab(0.04, height - 0.001, 0.001)])
    keyhole = (m3.CrossSection.circle(0.06, 48).translate((0.0, 0.3))
               + m3.CrossSection.square((0.05, 0.16)).translate((-0.025, 0.13)))
    # the outline in the xz-plane, extruded into the front face (y = -depth / 2) 0.06 deep
    pocket = m3.Manifold.extrude(keyhole, 0.2).rotate((90.0, 0.0, 0.0)).translate(
        (0.0, -0.5 * depth + 0.06, 0.0))
    spread, bar, top = 0.2, 0.055, 0.85
    arc = m3.Manifold.revolve(m3.CrossSection.circle(bar, 48).translate((spread, 0.0)),
                              96, 180.0).rotate((90.0, 0.0, 0.0)).translate((0.0, 0.0, top))
    legs = [m3.Manifold.cylinder(top - height + 0.15, bar, -1, 48).translate(
        (s * spread, 0.0, height - 0.15)) for s in (-1.0, 1.0)]
    part = body - pocket + m3.Manifold.batch_boolean([arc, *legs], m3.OpType.Add)
    return vm._manifold_mesh(part, PADLOCK_H, refine=0.03)


def _anvil() -> BenchMesh:
    """An anvil (holdout 13): a flat-topped face block with a heel at one end, a horn (a
    cone with a rounded tip, below the face's level) at the other, a waist tapering down to
    a splayed foot, a square hole and a round hole through the heel (manifold3d hulls and
    booleans; genus 2)."""
    import manifold3d as m3

    def slab(half_x: float, half_y: float, z: float, thickness: float = 0.001):
        return m3.Manifold.cube((2 * half_x, 2 * half_y, thickness), True).translate(
            (0.0, 0.0, z + 0.5 * thickness))

    foot = m3.Manifold.batch_hull([slab(0.4, 0.22, 0.0, 0.04), slab(0.24, 0.11, 0.149)])
    waist = m3.Manifold.batch_hull([slab(0.22, 0.1, 0.14), slab(0.3, 0.13, 0.36)])
    face = m3.Manifold.cube((0.97, 0.28, 0.2)).translate((-0.62, -0.14, 0.35))
    horn = m3.Manifold.batch_hull([
        m3.Manifold.cylinder(0.01, 0.1, -1, 96).rotate((0.0, 90.0, 0.0)).translate(
            (0.3, 0.0, 0.4)),
        m3.Manifold.sphere(0.025, 32).translate((0.78, 0.0, 0.47))])
    square_hole = m3.Manifold.cube((0.08, 0.08, 0.4), True).translate((-0.52, 0.0, 0.45))
    round_hole = m3.Manifold.cylinder(0.4, 0.035, -1, 32).translate((-0.39, 0.0, 0.25))
    part = foot + waist + face + horn - square_hole - round_hole
    return vm._manifold_mesh(part, ANVIL_H, refine=0.03)


# --------------------------------------------------------------------------- teeth


def _hypsodont() -> BenchMesh:
    """A hypsodont grinding tooth (holdout 13; a horse's): a tall column of
    rounded-square section bent slightly along its length, three vertical ribs down its
    outer face, a flat grinding surface crossed by enamel ridges (two oval loops round two
    pits and a ridge round the rim) and three short tapering roots (manifold3d level
    set), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        xb = x - 0.08 * ((0.45 - z) / 0.9) ** 2  # bent along x, more towards the roots
        section = 0.22 * (1.0 - math.sqrt(math.sqrt((xb / 0.26) ** 4 + (y / 0.22) ** 4)))
        if xb > 0.0:  # the ribs on the outer face
            section += (0.016 * math.fsum(math.exp(-((y - c) / 0.035) ** 2)
                                          for c in (-0.12, 0.0, 0.12)) * (xb / 0.26) ** 4)
        loops = 0.0
        for cx in (-0.11, 0.11):
            rho = math.sqrt(((xb - cx) / 0.085) ** 2 + (y / 0.13) ** 2)
            loops += 0.025 * math.exp(-((rho - 1.0) / 0.28) ** 2)  # an enamel loop
            loops -= 0.04 * math.exp(-(rho / 0.55) ** 2)  # the pit it encloses
        rim = 0.02 * math.exp(-(section / 0.03) ** 2)  # enamel round the edge
        top = 0.45 + loops + rim - z
        bottom = z + 0.4
        column = -_smooth_max([-section, -top, -bottom], 0.02)
        roots = [_capsule(x, y, z, (rx, ry, -0.3), (rx + 0.3 * (rx - 0.08), ry * 1.3, -0.62),
                          0.075, 0.03)
                 for rx, ry in ((-0.05, -0.1), (-0.05, 0.1), (0.2, 0.0))]
        return _smooth_max([column, *roots], 0.03)

    return vm._level_set_mesh(inside, [-0.4, -0.35, -0.75, 0.45, 0.35, 0.55], 0.015,
                              HYPSODONT_H)


# --------------------------------------------------------------------------- smooth


def _lemniscate() -> BenchMesh:
    """A sheared tube round a lemniscate of Gerono (holdout 13): the set
    ``(x^2 (1 - x^2) - y^2)^2 + (z - a x y)^2 < LEMNISCATE_LEVEL`` (scaled by 0.75), a smooth
    figure-of-eight tube whose four half-loops rise and fall in turn (the shear by ``a x y``
    lifts them out of the plane), thin at its two ends and widening into a saddle-shaped
    plate where its two loops cross (genus 2; the shear is a diffeomorphism and the level
    is below 1/16, the value at the loops' critical points, so the surface is smooth)
    (manifold3d level set), isotropically remeshed."""

    def inside(x, y, z):
        u, v = x / 0.75, y / 0.75
        g = u * u * (1.0 - u * u) - v * v
        w = z / 0.75 - LEMNISCATE_TWIST * u * v
        return 0.5 * (LEMNISCATE_LEVEL - g * g - w * w)

    return vm._level_set_mesh(inside, [-0.85, -0.55, -0.3, 0.85, 0.55, 0.3], 0.012,
                              LEMNISCATE_H)


LEMNISCATE_LEVEL, LEMNISCATE_TWIST = 0.012, 0.5


# --------------------------------------------------------------------------- brain-like


def _forebrain() -> BenchMesh:
    """A synthetic forebrain (holdout 13; brain-like, not a brain): two halves side by side,
    long front to back, split on top by a deep midline cleft, flattened underneath, a
    groove slanting up and back along each side, and gyri curled into whorls: grooves
    along the level sets of a smooth minimum of the distances to eight whorl centres (four
    a side), warped. Made as a radial height field over an icosphere (so it cannot
    cross itself), then isotropically remeshed with no feature kept."""
    centres = []  # whorl centres (unit directions), four a side
    for side in (-1.0, 1.0):
        for cy, cz in ((0.55, 0.35), (-0.1, 0.75), (-0.6, 0.25), (0.2, -0.3)):
            n = math.sqrt(0.35 + cy * cy + cz * cz)
            centres.append((side * math.sqrt(0.35) / n, cy / n, cz / n))

    def radius(ux, uy, uz):
        r = 1.0 / math.sqrt((ux / 0.55) ** 2 + (uy / 0.75) ** 2 + (uz / 0.5) ** 2)
        flat = -0.3 / uz if uz < 0.0 else 10.0  # the flat underside at z = -0.3, blended
        low = min(r, flat)
        r = low - 0.03 * math.log(math.exp((low - r) / 0.03) + math.exp((low - flat) / 0.03))
        upper = 0.5 + 0.5 * math.tanh((uz + 0.2) / 0.1)
        r -= 0.12 * upper * math.exp(-(ux / 0.07) ** 2)  # the midline cleft
        side = abs(ux) - 0.55 - 0.35 * uz + 0.25 * uy  # a slanting line on each side
        r -= 0.05 * math.exp(-(side / 0.06) ** 2) * (0.5 - 0.5 * math.tanh(uz / 0.15))
        near = [math.acos(max(-1.0, min(1.0, ux * cx + uy * cy + uz * cz)))
                for cx, cy, cz in centres]
        lowest = min(near)  # a smooth minimum of the angular distances
        whorl = lowest - 0.08 * math.log(math.fsum(math.exp(-(d - lowest) / 0.08)
                                                   for d in near))
        whorl += (0.05 * math.sin(5.0 * ux + 3.0 * uy) * math.sin(4.0 * uz - 2.0 * uy)
                  + 0.03 * math.sin(7.0 * uy - 4.0 * uz + 1.0))
        groove = math.exp((math.cos(GYRUS_FREQUENCY * whorl) - 1.0) / 0.7)
        return r - GYRUS_DEPTH * groove

    return _radial_surface(radius, FOREBRAIN_H)


GYRUS_FREQUENCY, GYRUS_DEPTH = 32.0, 0.035


SEAHORSE_H, PINECONE_H, ELBOW_H, PADLOCK_H, ANVIL_H, HYPSODONT_H, LEMNISCATE_H = (
    0.013, 0.016, 0.016, 0.016, 0.016, 0.016, 0.016)
FOREBRAIN_H = 0.019


# A fifteenth set, made in session 36 after holdout 12 had been made: all six kinds, the
# brain kind by a synthetic forebrain. No source is shared with the two halves, the first
# twelve holdouts, the tuning-side CAD parts, scan_flatness_study.py's extra scans,
# animals.py, built_meshes.py, eggcrate.py, brain_probes.py, the λ-H families or session
# 32's tuning-side study parts; every parameter was fixed and the manifest committed before
# any fill was run on them. The scans are portable (the same bits on every CPU's BLAS).
HOLDOUT13_SOURCES: dict[str, Source] = {
    "scan_seahorse": Source("range_scan", "simulated scan of the seahorse (portable "
                            "scanner)", vm._scan(_seahorse, (0.3, -1.0, 0.3), 163,
                                                 portable=True)),
    "scan_lemniscate": Source("range_scan", "simulated scan of the lemniscate tube (portable "
                              "scanner)", vm._scan(_lemniscate, (0.3, 0.5, 0.8), 164,
                                                   portable=True)),
    "scan_padlock": Source("range_scan", "simulated scan of the padlock CAD part (portable "
                           "scanner)", vm._scan(_padlock, (0.4, -1.0, 0.5), 165,
                                                portable=True)),
    "scan_anvil": Source("range_scan", "simulated scan of the anvil CAD part (portable "
                         "scanner)", vm._scan(_anvil, (0.5, -0.8, 0.5), 166, portable=True)),
    "seahorse": Source("organic", "seahorse, flattened trunk, spiral tail, bony rings, "
                       "tubular muzzle, head coronet, eyes, back fin (level set), remeshed",
                       _seahorse),
    "pinecone": Source("organic", "pinecone, egg-shaped, 150 overlapping woody scales on a "
                       "golden-angle spiral (radial height field), remeshed", _pinecone),
    "elbow": Source("cad", "manifold3d: pipe elbow, quarter bend, flared stubs, "
                    "square end plates with a bore and four bolt holes each", _elbow),
    "padlock": Source("cad", "manifold3d: padlock, rounded body, chamfered top, keyhole "
                      "pocket, U-shaped shackle", _padlock),
    "anvil": Source("cad", "manifold3d: anvil, face block with heel, cone horn, waist, "
                    "splayed foot, square and round heel holes", _anvil),
    "hypsodont": Source("teeth", "hypsodont grinding tooth, tall bent column, ribbed outer "
                        "face, enamel loops round two pits, three short roots (level set)",
                        _hypsodont),
    "lemniscate": Source("smooth", "sheared tube round a lemniscate of Gerono, "
                         "(x^2(1-x^2)-y^2)^2+(z-xy/2)^2 < 0.012 (level set, genus 2), "
                         "remeshed",
                         _lemniscate),
    "forebrain": Source("brain", "synthetic forebrain, two halves, midline cleft, slanting "
                        "side grooves, whorled gyri (radial height field), remeshed",
                        _forebrain),
}
