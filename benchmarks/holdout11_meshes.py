"""Holdout set 11's meshes (session 35): 12 fresh meshes, made and committed before any fill.

As holdouts 8 to 10's (``holdout8_meshes.py`` .. ``holdout10_meshes.py``): kept out of
:mod:`validation_meshes`, which imports :data:`HOLDOUT11_SOURCES` from here at its end and
adds them to its ``SOURCES``, so every benchmark reaches these meshes through it
(``validation_meshes.load("acorn")``). The generators use its helpers (level sets,
manifold3d remeshing); the four range scans are the portable scanner's
(``simulated_scan(..., portable=True)``: the same bits under every BLAS kernel). Import
:mod:`validation_meshes` first, not this module (an import cycle otherwise).

All six kinds, the first later set with a brain-like surface (a synthetic folded
hemisphere, not a real brain): 4 simulated range scans of 4 of the others, 2 organic
shapes, 3 CAD parts, 1 tooth, 1 smooth level set and 1 folded surface
(``benchmarks/holdout11_manifest.json``, docs/validation.md "Holdout set 11").

The level sets' insides are written with Python floats and :mod:`math` (no numpy
transcendental on arrays, whose SIMD loops differ between CPUs), so a mesh's bits do not
depend on the CPU's vector units.
"""

from __future__ import annotations

import math

import numpy as np
import validation_meshes as vm
from validation_meshes import BenchMesh, Source


def _smooth_max2(a: float, b: float, k: float) -> float:
    """A smooth maximum (log-sum-exp) of two numbers with blending width ``k``, in Python
    floats."""
    top = max(a, b)
    return top + k * math.log(math.exp((a - top) / k) + math.exp((b - top) / k))


def _smooth_max(values, k: float) -> float:
    """A smooth maximum (log-sum-exp) of ``values`` (Python floats) with blending width
    ``k``."""
    top = max(values)
    return top + k * math.log(math.fsum(math.exp((v - top) / k) for v in values))


def _capsule(x, y, z, a, b, r_a: float, r_b: float) -> float:
    """Inside of a tapered capsule from ``a`` (radius ``r_a``) to ``b`` (radius ``r_b``)
    at (x, y, z): the radius at the nearest point of the segment minus the distance."""
    dx, dy, dz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    px, py, pz = x - a[0], y - a[1], z - a[2]
    t = min(max((px * dx + py * dy + pz * dz) / (dx * dx + dy * dy + dz * dz), 0.0), 1.0)
    d = math.sqrt((px - t * dx) ** 2 + (py - t * dy) ** 2 + (pz - t * dz) ** 2)
    return r_a + t * (r_b - r_a) - d


# --------------------------------------------------------------------------- organic


def _acorn() -> BenchMesh:
    """An acorn (holdout 11): an ovoid nut drawn out into a blunt point at the bottom, a
    scaly cup over its top third whose rim stands proud of the nut, and a short bent stalk
    on the cup (smooth unions, manifold3d level set), isotropically remeshed with no
    feature kept."""

    def inside(x, y, z):
        nut = 0.4 - math.sqrt(x * x + y * y + ((z + 0.08) / 1.3) ** 2)
        point = _capsule(x, y, z, (0.0, 0.0, -0.3), (0.0, 0.0, -0.66), 0.2, 0.035)
        nut = _smooth_max2(nut, point, 0.06)
        a = math.atan2(y, x)
        scales = 0.012 * math.sin(14.0 * a + 40.0 * z) * math.sin(14.0 * a - 40.0 * z)
        cup = 0.46 - math.sqrt(x * x + y * y + ((z - 0.2) / 0.8) ** 2) + scales
        cup = -_smooth_max2(-cup, 0.03 - z, 0.02)  # cut off below z = 0.03
        stalk = _capsule(x, y, z, (0.0, 0.0, 0.5), (0.07, 0.03, 0.66), 0.045, 0.035)
        return _smooth_max([nut, cup, stalk], 0.025)

    return vm._level_set_mesh(inside, [-0.6, -0.6, -0.75, 0.6, 0.6, 0.75], 0.02, ACORN_H)


def _snail() -> BenchMesh:
    """A snail (holdout 11): a slug body tapering to its tail, a raised head with two eye
    stalks ending in balls, and a coiled shell on its back (a tube about a logarithmic
    spiral of 1.9 turns whose whorls overlap: the union of balls along it; the umbilicus
    goes through the coil, genus 1), blended by smooth unions (manifold3d level set),
    isotropically remeshed with no feature kept."""
    turns = np.linspace(0.7 * 2.0 * np.pi, 2.6 * 2.0 * np.pi, 600)  # from radius 0.04 out
    # the spiral's radius and centres by math (libm), not numpy's SIMD loops
    radius = np.array([0.38 * math.exp(-0.19 * (2.6 * 2.0 * math.pi - t)) for t in turns])
    centres = np.array([(-0.12 + r * math.cos(t), 0.0, 0.25 + r * math.sin(t))
                        for r, t in zip(radius, turns, strict=True)])
    tube = 0.58 * radius + 0.012  # each whorl overlaps the one inside it

    def inside(x, y, z):
        d2 = (centres[:, 0] - x) ** 2 + (centres[:, 1] - y) ** 2 + (centres[:, 2] - z) ** 2
        shell = float((tube - np.sqrt(d2)).max())
        foot = _capsule(x, y / 1.3, z / 0.7, (-0.85, 0.0, -0.2 / 0.7), (0.55, 0.0, -0.2 / 0.7),
                        0.04, 0.17) * 0.7
        head = _capsule(x, y, z, (0.5, 0.0, -0.16), (0.72, 0.0, -0.05), 0.14, 0.11)
        stalks = [max(_capsule(x, y, z, (0.7, s * 0.05, 0.0), (0.86, s * 0.14, 0.3), 0.045,
                               0.032),
                      0.06 - math.sqrt((x - 0.87) ** 2 + (y - s * 0.145) ** 2
                                       + (z - 0.32) ** 2)) for s in (-1.0, 1.0)]
        body = _smooth_max([foot, head, *stalks], 0.03)
        return _smooth_max2(body, shell, 0.03)

    return vm._level_set_mesh(inside, [-1.0, -0.35, -0.4, 1.0, 0.35, 0.95], 0.02, SNAIL_H)


# --------------------------------------------------------------------------- CAD


def _keycap() -> BenchMesh:
    """A keyboard keycap (holdout 11): a hollow tapered shell of rounded-square plan, its
    top dished by a cylinder, open underneath, a round stem hanging from the inside of the
    top with a cross-shaped socket in it (manifold3d hulls and booleans)."""
    import manifold3d as m3

    def slab(side: float, corner: float, z: float, height: float):
        plan = m3.CrossSection.square((side - 2 * corner, side - 2 * corner), True).offset(
            corner, m3.JoinType.Round, circular_segments=32)
        return m3.Manifold.extrude(plan, height).translate((0.0, 0.0, z))

    outer = m3.Manifold.batch_hull([slab(0.9, 0.08, 0.0, 0.01), slab(0.66, 0.1, 0.44, 0.01)])
    inner = m3.Manifold.batch_hull([slab(0.76, 0.05, -0.1, 0.01), slab(0.56, 0.06, 0.31, 0.01)])
    dish = m3.Manifold.cylinder(2.0, 1.4, -1, 192, True).rotate((0.0, 90.0, 0.0)).translate(
        (0.0, 0.0, 0.45 - 0.035 + 1.4))
    stem = m3.Manifold.cylinder(0.3, 0.13, -1, 64).translate((0.0, 0.0, 0.03))
    socket = (m3.Manifold.cube((0.17, 0.05, 0.5), True) + m3.Manifold.cube((0.05, 0.17, 0.5),
                                                                          True))
    part = outer - inner - dish + (stem - socket.translate((0.0, 0.0, 0.03)))
    return vm._manifold_mesh(part, KEYCAP_H, refine=0.03)


def _rook() -> BenchMesh:
    """A chess rook (holdout 11): a turned body (a chamfered base with a rounded bead, a
    concave cove up into a tapering waist, a collar, a cylindrical head) whose top is
    hollowed into a bowl and cut by four square crenel slots (manifold3d revolve and
    booleans)."""
    import manifold3d as m3

    bead = [(0.44 + 0.06 * math.cos(a), 0.16 + 0.06 * math.sin(a))
            for a in np.linspace(-0.5 * math.pi, 0.5 * math.pi, 13)]
    cove = [(0.3 + 0.12 * (1.0 - math.sin(a)), 0.22 + 0.12 * (1.0 - math.cos(a)))
            for a in np.linspace(0.5 * math.pi, 0.0, 11)]
    profile = [(0.0, 0.0), (0.46, 0.0), (0.5, 0.04), (0.5, 0.1), *bead, (0.42, 0.22), *cove,
               (0.26, 0.8), (0.36, 0.84), (0.36, 0.9), (0.32, 0.93), (0.32, 1.2),
               (0.0, 1.2)]
    body = m3.Manifold.revolve(m3.CrossSection([profile]), 128)
    bowl = m3.Manifold.cylinder(0.3, 0.22, -1, 96).translate((0.0, 0.0, 1.06))
    part = body - bowl
    for angle in (0.0, 90.0):
        part = part - m3.Manifold.cube((0.9, 0.12, 0.2), True).rotate(
            (0.0, 0.0, angle + 45.0)).translate((0.0, 0.0, 1.2))
    return vm._manifold_mesh(part, ROOK_H, refine=0.03)


def _die() -> BenchMesh:
    """A six-sided die (holdout 11): a cube with rounded edges and corners (the hull of
    eight balls) whose faces carry 1 to 6 spherical pips, 21 in all, each with a sharp
    rim (manifold3d hull and booleans)."""
    import manifold3d as m3

    r, half = 0.12, 0.5
    balls = [m3.Manifold.sphere(r, 48).translate((sx * (half - r), sy * (half - r),
                                                  sz * (half - r)))
             for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    part = m3.Manifold.batch_hull(balls)
    layouts = {1: [(0, 0)], 2: [(-1, -1), (1, 1)], 3: [(-1, -1), (0, 0), (1, 1)],
               4: [(-1, -1), (-1, 1), (1, -1), (1, 1)],
               5: [(-1, -1), (-1, 1), (0, 0), (1, -1), (1, 1)],
               6: [(-1, -1), (-1, 0), (-1, 1), (1, -1), (1, 0), (1, 1)]}
    # face (number) -> axis and side: opposite faces add up to 7
    faces = {1: (2, 1), 6: (2, -1), 2: (0, 1), 5: (0, -1), 3: (1, 1), 4: (1, -1)}
    pip_radius, depth, pitch = 0.085, 0.05, 0.24
    sphere_radius = (pip_radius**2 + depth**2) / (2 * depth)
    pips = []
    for number, (axis, side) in faces.items():
        for a, b in layouts[number]:
            centre = [0.0, 0.0, 0.0]
            others = [k for k in range(3) if k != axis]
            centre[others[0]], centre[others[1]] = a * pitch, b * pitch
            centre[axis] = side * (half + sphere_radius - depth)
            pips.append(m3.Manifold.sphere(sphere_radius, 48).translate(tuple(centre)))
    return vm._manifold_mesh(part - m3.Manifold.batch_boolean(pips, m3.OpType.Add), DIE_H)


# --------------------------------------------------------------------------- teeth


def _shark_tooth() -> BenchMesh:
    """A shark's tooth (holdout 11): a flat triangular blade, lens-shaped in section, its
    tip bent back and rounded, both cutting edges serrated (scallops along the edges only), on a
    thicker root with two lobes and a notch between them (manifold3d level set),
    isotropically remeshed with no feature kept."""
    corners = ((-0.5, 0.0), (0.5, 0.0), (0.12, 1.05))
    normals = []
    for (ax, az), (bx, bz) in zip(corners, corners[1:] + corners[:1], strict=True):
        length = math.hypot(bz - az, ax - bx)  # outward: the outline is counter-clockwise
        normals.append(((ax, az), ((bz - az) / length, (ax - bx) / length)))

    def outline(x, z):  # signed distance to the blade's outline in the xz-plane (< 0 in)
        x = x - 0.12 * z * z  # the tip bent back
        plain = max((x - ax) * nx + (z - az) * nz for (ax, az), (nx, nz) in normals)
        ramp = min(max((z - 0.08) / 0.1, 0.0), 1.0)  # no scallops on the base
        scallops = 0.012 * math.sin(2.0 * math.pi * z / 0.09) * ramp
        return plain + scallops * math.exp(-(plain / 0.04) ** 2)

    def inside(x, y, z):
        edge = outline(x, z)
        s = min(max(-edge / 0.3, 0.0), 1.0)
        blade = 0.085 * math.sqrt(s * (2.0 - s)) - abs(y) if s > 0.0 else -edge - abs(y)
        tip = 0.035 - math.sqrt((x - 0.12 - 0.12 * 0.99**2) ** 2 + y * y + (z - 0.99) ** 2)
        blade = _smooth_max2(blade, tip, 0.015)  # a rounded tip, not a point
        lobes = [0.2 - math.sqrt(((x - sx * 0.34) / 1.6) ** 2 + (y / 0.9) ** 2
                                 + ((z + 0.02) / 0.85) ** 2) for sx in (-1.0, 1.0)]
        notch = 0.1 - math.sqrt(x * x + (z + 0.2) ** 2)
        root = -_smooth_max2(-_smooth_max2(*lobes, 0.06), notch, 0.03)
        return _smooth_max2(blade, root, 0.04)

    return vm._level_set_mesh(inside, [-0.85, -0.3, -0.3, 0.85, 0.3, 1.15], 0.015, SHARK_H)


# --------------------------------------------------------------------------- smooth


def _gyroid_ball() -> BenchMesh:
    """A ball of gyroid network (holdout 11): one of the two labyrinths of a gyroid of
    period 0.9 (``(sin kx cos ky + sin ky cos kz + sin kz cos kx) / k > 0``) made solid
    towards the centre and bounded by adding ``0.6 (0.62 - r)``: one smooth function, so the
    labyrinth opens to the outside near the radius 0.62 without a crease; saddles
    everywhere, genus 6 (manifold3d level set), isotropically remeshed."""
    k = 2.0 * math.pi / 0.9

    def inside(x, y, z):
        g = (math.sin(k * x) * math.cos(k * y) + math.sin(k * y) * math.cos(k * z)
             + math.sin(k * z) * math.cos(k * x)) / k
        return g + 0.6 * (0.62 - math.sqrt(x * x + y * y + z * z))

    return vm._level_set_mesh(inside, [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0], 0.02, GYROID_H)


# --------------------------------------------------------------------------- brain-like


def _folded_hemisphere() -> BenchMesh:
    """A folded hemisphere (holdout 11; brain-like, not a brain): an egg-shaped half of a
    brain, long front to back, its inner (medial) side flattened, a temporal lobe bulging
    low at the side, its whole surface folded by sulci (grooves along the zero set of a
    random field of 14 plane waves) between broad rounded gyri. Made as a radial height
    field over an icosphere (so it cannot cross itself), then isotropically remeshed with
    no feature kept."""
    rng = np.random.default_rng(1135)
    waves = rng.normal(size=(14, 3))
    waves = [tuple(float(c) / math.sqrt(float((w * w).sum())) for c in w) for w in waves]
    phases = [float(p) for p in rng.uniform(0.0, 2.0 * math.pi, 14)]
    temporal = (-0.6 / 1.1, 0.3 / 1.1, -0.75 / 1.1)  # roughly unit: lateral, front, low

    def radius(ux, uy, uz):
        r = 1.0 / math.sqrt((ux / 0.5) ** 2 + (uy / 0.78) ** 2 + (uz / 0.56) ** 2)
        r += 0.1 * math.exp(-((ux - temporal[0]) ** 2 + (uy - temporal[1]) ** 2
                              + (uz - temporal[2]) ** 2) / (2.0 * 0.3**2))
        if ux > 0.0:  # the flat medial side at x = 0.3, blended (smooth minimum, 0.03)
            medial = 0.3 / ux
            low = min(r, medial)
            r = low - 0.03 * math.log(math.exp((low - r) / 0.03)
                                      + math.exp((low - medial) / 0.03))
        field = math.fsum(math.sin(FOLD_FREQUENCY * r * (w[0] * ux + w[1] * uy + w[2] * uz)
                                   + p) for w, p in zip(waves, phases, strict=True))
        return r - FOLD_DEPTH * math.exp(-(field / math.sqrt(7.0) / FOLD_WIDTH) ** 2)

    return _radial_surface(radius, FOLDED_H)


def _radial_surface(radius, h: float, surface_check: bool | None = None) -> BenchMesh:
    """The closed surface ``r = radius(ux, uy, uz)`` over the unit directions (Python
    floats in, a float out: the same bits on every CPU), sampled at an icosphere's vertices
    and remeshed to edge length ``h``: a radial height field, for folded brain-like shapes
    that level sets make non-manifold (``surface_check``: ``validation_meshes._remesh``'s)."""
    from surfinpaint import data

    v, f = data.sphere(6)
    v = v / np.sqrt((v * v).sum(axis=1))[:, None]  # unit directions
    r = np.array([radius(float(a), float(b), float(c)) for a, b, c in v])
    return vm._mesh(*vm._remesh(v * r[:, None], f, h, feature_deg=180.0,
                                surface_check=surface_check))


FOLD_FREQUENCY, FOLD_DEPTH, FOLD_WIDTH = 16.0, 0.08, 0.6


ACORN_H, SNAIL_H, KEYCAP_H, ROOK_H, DIE_H, SHARK_H, GYROID_H, FOLDED_H = (
    0.02, 0.018, 0.02, 0.02, 0.025, 0.018, 0.032, 0.02)


# A thirteenth set, made in session 35 after holdout 10 had been made: all six kinds, the
# brain kind by a synthetic folded hemisphere. No source is shared with the two halves, the
# first ten holdouts, the tuning-side CAD parts, scan_flatness_study.py's extra scans,
# animals.py, built_meshes.py, eggcrate.py, brain_probes.py, the λ-H families or session
# 32's tuning-side study parts; every parameter was fixed and the manifest committed before
# any fill was run on them. The scans are portable (the same bits on every CPU's BLAS).
HOLDOUT11_SOURCES: dict[str, Source] = {
    "scan_snail": Source("range_scan", "simulated scan of the snail (portable scanner)",
                         vm._scan(_snail, (0.3, -1.0, 0.5), 155, portable=True)),
    "scan_gyroid_ball": Source("range_scan", "simulated scan of the gyroid ball (portable "
                               "scanner)", vm._scan(_gyroid_ball, (0.4, 0.6, 0.8), 156,
                                                    portable=True)),
    "scan_keycap": Source("range_scan", "simulated scan of the keycap CAD part (portable "
                          "scanner)", vm._scan(_keycap, (0.6, -0.5, 0.7), 157, portable=True)),
    "scan_die": Source("range_scan", "simulated scan of the die CAD part (portable scanner)",
                       vm._scan(_die, (0.6, -0.5, 0.7), 158, portable=True)),
    "acorn": Source("organic", "acorn, pointed nut, scaly cup with a proud rim, bent stalk "
                    "(level set), remeshed", _acorn),
    "snail": Source("organic", "snail, tapering foot, head with two eye stalks, coiled shell "
                    "of overlapping whorls (level set), remeshed", _snail),
    "keycap": Source("cad", "manifold3d: keycap, tapered hollow shell, rounded corners, "
                     "cylindrical dish, stem with a cross socket", _keycap),
    "rook": Source("cad", "manifold3d: chess rook, turned body, bead, cove, collar, bowl "
                   "top, four crenel slots", _rook),
    "die": Source("cad", "manifold3d: six-sided die, rounded edges and corners, 21 "
                  "spherical pips", _die),
    "shark_tooth": Source("teeth", "shark tooth, flat lens-section blade, serrated edges, "
                          "bent tip, two-lobed root (level set)", _shark_tooth),
    "gyroid_ball": Source("smooth", "ball of gyroid network, period 0.9, opening to the "
                          "outside (level set, genus 6), remeshed", _gyroid_ball),
    "folded_hemisphere": Source("brain", "synthetic folded hemisphere, flat medial side, "
                                "temporal lobe, random sulci (radial height field), "
                                "remeshed", _folded_hemisphere),
}
