"""Holdout set 15's meshes (session 38): 12 fresh meshes, made and committed before any fill.

As holdouts 8 to 14's (``holdout8_meshes.py`` .. ``holdout14_meshes.py``): kept out of
:mod:`validation_meshes`, which imports :data:`HOLDOUT15_SOURCES` from here at its end and
adds them to its ``SOURCES``, so every benchmark reaches these meshes through it
(``validation_meshes.load("dolphin")``). The generators use its helpers (level sets,
manifold3d remeshing), holdouts 11 and 12's level-set and radial-surface helpers and holdout
14's smooth minimum; the four range scans are the portable scanner's
(``simulated_scan(..., portable=True)``: the same bits under every BLAS kernel). Import
:mod:`validation_meshes` first, not this module (an import cycle otherwise).

All six kinds, as holdouts 11 to 14: 4 simulated range scans of 4 of the others, 2 organic
shapes, 3 CAD parts, 1 tooth, 1 smooth level set and 1 brain-like surface (a synthetic
cortex whose sulci are separate branching curves ending blind, not a real brain)
(``benchmarks/holdout15_manifest.json``, docs/validation.md "Holdout set 15").

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
from holdout14_meshes import _flattened_underneath, _smooth_min
from validation_meshes import BenchMesh, Source


def _flat_capsule(x, y, z, a, b, r_a: float, r_b: float, squash, axis: int) -> float:
    """A tapered capsule (:func:`_capsule`) squashed by ``squash`` across coordinate
    ``axis`` (0, 1, 2 for x, y, z): a fin or a flipper, ``1 / squash`` as thick as wide."""
    p, a, b = [x, y, z], list(a), list(b)
    p[axis], a[axis], b[axis] = p[axis] * squash, a[axis] * squash, b[axis] * squash
    return _capsule(*p, a, b, r_a, r_b) / squash


# --------------------------------------------------------------------------- organic


def _dolphin() -> BenchMesh:
    """A dolphin (holdout 15): a spindle body along a gently arched spine (tapered capsules,
    narrowing into a tail stock flattened side to side), a bulging melon on the forehead, a
    short beak, a swept-back dorsal fin and two pectoral flippers (capsules flattened across
    their plane) and two horizontal tail flukes (flattened vertically) (smooth unions,
    manifold3d level set), isotropically remeshed with no feature kept. The fins and flukes
    are thin: 0.025-0.08 thick."""
    spine = [((-0.52, 0.0, 0.0), 0.1), ((-0.3, 0.0, 0.04), 0.15), ((0.0, 0.0, 0.05), 0.155),
             ((0.3, 0.0, 0.0), 0.1), ((0.52, 0.0, -0.05), 0.045)]

    def inside(x, y, z):
        body = [_capsule(x, y, z, a, b, r_a, r_b)
                for (a, r_a), (b, r_b) in zip(spine[:-1], spine[1:], strict=True)]
        stock = _flat_capsule(x, y, z, (0.3, 0.0, 0.0), (0.56, 0.0, -0.05), 0.1, 0.05, 1.7, 1)
        melon = _ellipsoid(x, y, z, (-0.47, 0.0, 0.04), (0.13, 0.095, 0.1))
        beak = _capsule(x, y, z, (-0.55, 0.0, -0.03), (-0.73, 0.0, -0.05), 0.045, 0.028)
        dorsal = _flat_capsule(x, y, z, (-0.02, 0.0, 0.15), (0.17, 0.0, 0.32), 0.08, 0.025,
                               2.0, 1)
        flippers = [_flat_capsule(x, y, z, (-0.3, s * 0.1, -0.08), (-0.17, s * 0.3, -0.19),
                                  0.055, 0.028, 1.8, 2) for s in (-1.0, 1.0)]
        flukes = [_flat_capsule(x, y, z, (0.54, 0.0, -0.05), (0.72, s * 0.2, -0.03), 0.06,
                                0.03, 2.0, 2) for s in (-1.0, 1.0)]
        return _smooth_max([*body, stock, melon, beak, dorsal, *flippers, *flukes], 0.02)

    return vm._level_set_mesh(inside, [-0.8, -0.36, -0.3, 0.82, 0.36, 0.38], 0.01, DOLPHIN_H)


def _songbird() -> BenchMesh:
    """A songbird on a perch (holdout 15): an egg-shaped body leaning forward, a round head
    with a short pointed beak and two small eyes, folded wings bulging on the sides, a long
    tail flattened top to bottom, and two thin legs gripping a branch (a tapered capsule)
    (smooth unions, manifold3d level set; genus 1, the loop through the legs and the
    branch), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        body = _ellipsoid(x, y, z, (0.0, 0.0, 0.0), (0.24, 0.16, 0.17))
        body = _smooth_max([body, _capsule(x, y, z, (-0.05, 0.0, 0.02), (0.16, 0.0, -0.1),
                                           0.13, 0.08)], 0.03)
        head = 0.12 - math.sqrt((x + 0.22) ** 2 + y * y + (z - 0.17) ** 2)
        beak = _capsule(x, y, z, (-0.3, 0.0, 0.16), (-0.42, 0.0, 0.14), 0.035, 0.006)
        eyes = [0.018 - math.sqrt((x + 0.29) ** 2 + (y - s * 0.08) ** 2 + (z - 0.2) ** 2)
                for s in (-1.0, 1.0)]
        wings = [_ellipsoid(x, y, z, (0.05, s * 0.13, 0.03), (0.2, 0.045, 0.11))
                 for s in (-1.0, 1.0)]
        tail = _flat_capsule(x, y, z, (0.18, 0.0, -0.06), (0.48, 0.0, -0.2), 0.07, 0.06, 2.6,
                             2)
        legs = [_capsule(x, y, z, (0.0, s * 0.06, -0.12), (0.02, s * 0.07, -0.3), 0.024,
                         0.018) for s in (-1.0, 1.0)]
        branch = _capsule(x, y, z, (0.0, -0.34, -0.33), (0.02, 0.34, -0.33), 0.045, 0.038)
        return _smooth_max([body, head, beak, *eyes, *wings, tail, *legs, branch], 0.018)

    return vm._level_set_mesh(inside, [-0.46, -0.4, -0.4, 0.54, 0.4, 0.32], 0.01,
                              SONGBIRD_H)


# --------------------------------------------------------------------------- CAD


def _drive_socket() -> BenchMesh:
    """A socket for a ratchet wrench (holdout 15): a turned body (both ends chamfered, a
    step down to a narrower drive end) with a knurled band of 24 V-grooves, a hexagonal bore
    with a chamfered mouth in its front, a square drive hole in its back, joined by a round
    through bore, and a detent hole through the wall into the square hole (manifold3d
    revolve, prisms and booleans; genus 2)."""
    import manifold3d as m3

    profile = [(0.0, 0.0), (0.19, 0.0), (0.21, 0.02), (0.21, 0.36), (0.19, 0.38),
               (0.175, 0.4), (0.175, 0.6), (0.16, 0.615), (0.0, 0.615)]
    body = m3.Manifold.revolve(m3.CrossSection([[(r, z) for r, z in profile]]), 96)
    groove = m3.CrossSection([[(0.225, -0.014), (0.225, 0.014), (0.199, 0.0)]])
    grooves = [m3.Manifold.extrude(groove, 0.18).translate((0.0, 0.0, 0.12)).rotate(
        (0.0, 0.0, 15.0 * k)) for k in range(24)]
    hexagon = m3.Manifold.cylinder(0.33, 0.135, -1, 6).translate((0.0, 0.0, -0.01))
    mouth = m3.Manifold.cylinder(0.04, 0.165, 0.125, 6).translate((0.0, 0.0, -0.01))
    through = m3.Manifold.cylinder(0.7, 0.06, -1, 48).translate((0.0, 0.0, -0.05))
    square = m3.Manifold.cube((0.19, 0.19, 0.2), True).translate((0.0, 0.0, 0.62))
    detent = m3.Manifold.cylinder(0.3, 0.022, -1, 32).rotate((0.0, 90.0, 0.0)).translate(
        (0.0, 0.0, 0.54))
    part = body - m3.Manifold.batch_boolean(
        [*grooves, hexagon, mouth, through, square, detent], m3.OpType.Add)
    return vm._manifold_mesh(part, DRIVE_SOCKET_H, refine=0.03)


def _ball_valve() -> BenchMesh:
    """A ball valve's body (holdout 15): a chamfered round body along the pipe's axis, a
    neck each side ending in a hexagonal end with chamfered corners (a hexagonal prism cut
    by a double cone, as on a nut), a bore through with a counterbored socket at each end,
    and a stem boss on top (chamfered) whose stem hole goes down into the bore (manifold3d
    revolve, prisms and booleans; genus 2)."""
    import manifold3d as m3

    def along_x(solid):  # a solid made along z, turned so that z runs along x
        return solid.rotate((0.0, 90.0, 0.0))

    body = along_x(m3.Manifold.revolve(m3.CrossSection([[
        (0.0, -0.25), (0.17, -0.25), (0.2, -0.21), (0.2, 0.21), (0.17, 0.25), (0.0, 0.25)]]),
        96))
    neck = along_x(m3.Manifold.cylinder(0.9, 0.11, -1, 96, True))
    cone = m3.Manifold.revolve(m3.CrossSection([[(0.0, -0.09), (0.12, -0.09), (0.18, -0.03),
                                                 (0.18, 0.03), (0.12, 0.09), (0.0, 0.09)]]),
                               96)
    nut = m3.Manifold.cylinder(0.18, 0.16, -1, 6, True).rotate((0.0, 0.0, 30.0)) ^ cone
    ends = [along_x(nut).translate((s * 0.5, 0.0, 0.0)) for s in (-1.0, 1.0)]
    boss = m3.Manifold.revolve(m3.CrossSection([[(0.0, 0.0), (0.08, 0.0), (0.08, 0.3),
                                                 (0.065, 0.315), (0.0, 0.315)]]), 64)
    bore = along_x(m3.Manifold.cylinder(1.4, 0.06, -1, 48, True))
    sockets = [along_x(m3.Manifold.cylinder(0.24, 0.085, -1, 64, True)).translate(
        (s * 0.59, 0.0, 0.0)) for s in (-1.0, 1.0)]
    stem = m3.Manifold.cylinder(0.4, 0.032, -1, 32)
    part = (body + neck + m3.Manifold.batch_boolean(ends, m3.OpType.Add) + boss
            - m3.Manifold.batch_boolean([bore, *sockets, stem], m3.OpType.Add))
    return vm._manifold_mesh(part, BALL_VALVE_H, refine=0.03)


def _reel_profile() -> list[tuple[float, float]]:
    """The cable reel's half section (radius, height), revolved about the axis: a drum
    between two thin flanges, a fillet of radius 0.04 where the drum meets each flange (a
    quarter circle, 4 steps), each flange's rim a full round (a half circle, 8 steps), a
    hub standing proud of each flange's outer face."""
    drum, flange, t, hub = 0.15, 0.44, 0.05, 0.1

    def arc(cx: float, cz: float, radius: float, start_deg: float,
            turn_deg: float = 90.0) -> list[tuple[float, float]]:
        # an arc about (cx, cz), counterclockwise from ``start_deg`` by ``turn_deg``, in
        # steps of 22.5 degrees (under the remeshing's 30-degree feature angle); with steps
        # of a third of an edge, 1 of 8 fresh processes made the reel one vertex different
        n = round(turn_deg / 22.5)
        steps = [math.radians(start_deg + turn_deg * k / n) for k in range(n + 1)]
        return [(cx + radius * math.cos(a), cz + radius * math.sin(a)) for a in steps]

    low, high = -0.2, 0.2  # the flanges' inner faces
    points = [(0.0, low - t - 0.03), (hub, low - t - 0.03), (hub, low - t)]
    points += arc(flange - 0.5 * t, low - 0.5 * t, 0.5 * t, 270.0, 180.0)  # the lower rim
    points += arc(drum + 0.04, low + 0.04, 0.04, 180.0)[::-1]  # the lower fillet
    points += arc(drum + 0.04, high - 0.04, 0.04, 90.0)[::-1]  # the upper fillet
    points += arc(flange - 0.5 * t, high + 0.5 * t, 0.5 * t, 270.0, 180.0)  # the upper rim
    points += [(hub, high + t), (hub, high + t + 0.03), (0.0, high + t + 0.03)]
    return points


def _cable_reel() -> BenchMesh:
    """A cable reel (holdout 15): a turned drum between two thin flanges (filleted where
    they meet it, their rims rounded), a hub proud of each flange, a bore through with
    chamfered mouths, six round lightening holes through one flange and four oblong ones
    through the other, and a radial slot in the first flange's rim for the cable's end
    (manifold3d revolve and booleans; genus 11)."""
    import manifold3d as m3

    reel = m3.Manifold.revolve(m3.CrossSection([_reel_profile()]), 128)
    bore = m3.Manifold.cylinder(0.6, 0.05, -1, 48, True)
    mouths = [m3.Manifold.cylinder(0.03, 0.05, 0.08, 48).rotate((s * 90.0 - 90.0, 0.0, 0.0))
              .translate((0.0, 0.0, s * 0.255)) for s in (-1.0, 1.0)]
    rounds = [m3.Manifold.cylinder(0.1, 0.045, -1, 48).translate(
        (0.3 * math.cos(a), 0.3 * math.sin(a), 0.18))
        for a in (math.radians(60.0 * k) for k in range(6))]
    oblong = m3.CrossSection.square((0.1, 0.001), True).offset(0.032, m3.JoinType.Round,
                                                                circular_segments=32)
    oblongs = [m3.Manifold.extrude(oblong.rotate(90.0 * k + 45.0).translate(
        (0.3 * math.cos(math.radians(90.0 * k + 45.0)),
         0.3 * math.sin(math.radians(90.0 * k + 45.0)))), 0.12).translate((0.0, 0.0, -0.3))
        for k in range(4)]
    slot = m3.Manifold.cube((0.2, 0.03, 0.12), True).translate((0.4, 0.0, 0.23)).rotate(
        (0.0, 0.0, 30.0))  # between two round holes
    part = reel - m3.Manifold.batch_boolean([bore, *mouths, *rounds, *oblongs, slot],
                                            m3.OpType.Add)
    return vm._manifold_mesh(part, CABLE_REEL_H, refine=0.03)


# --------------------------------------------------------------------------- teeth


def _crescent(x, y, z, centre, radius: float, start_deg: float, end_deg: float,
              height: float) -> float:
    """Inside of a crescent-shaped ridge: tapered capsules along an arc of ``radius`` about
    ``centre`` (x, y) from ``start_deg`` to ``end_deg``, its crest at ``height`` in the
    middle, its horns lower and thinner (six segments, smooth union)."""
    points = []
    for k in range(7):
        t = k / 6
        a = math.radians(start_deg + (end_deg - start_deg) * t)
        mid = math.sin(math.pi * t)  # 0 at the horns, 1 in the middle
        points.append(((centre[0] + radius * math.cos(a), centre[1] + radius * math.sin(a),
                        height - 0.09 * (1.0 - mid)), 0.028 + 0.02 * mid))
    return _smooth_max([_capsule(x, y, z, a, b, r_a, r_b)
                        for (a, r_a), (b, r_b) in zip(points[:-1], points[1:], strict=True)],
                       0.012)


def _selenodont() -> BenchMesh:
    """A selenodont upper molar (holdout 15; a ruminant's): a tall crown of rounded-square
    section whose top carries four crescent-shaped ridges, two a lobe, all four concave
    towards the cheek side (+x) as in a ruminant's upper molar, with a deep pit (the
    infundibulum) between the two crescents of each lobe; a narrower neck and three
    tapering roots (manifold3d level set), isotropically remeshed with no feature kept."""
    crescents = [((cx, yc), 0.17, 125.0, 235.0, hc) for yc in (-0.18, 0.18)
                 for cx, hc in ((0.32, 0.36), (0.0, 0.33))]  # the outer, the inner one

    def section(x, y, half_x, half_y, depth):  # a rounded square (superellipse, power 4)
        return depth * (1.0 - math.sqrt(math.sqrt((x / half_x) ** 4 + (y / half_y) ** 4)))

    def inside(x, y, z):
        body = _smooth_min([section(x, y, 0.3, 0.4, 0.17), 0.26 - z, z + 0.1], 0.03)
        ridges = [_crescent(x, y, z, centre, r, a0, a1, hc)
                  for centre, r, a0, a1, hc in crescents]
        crown = _smooth_max([body, *ridges], 0.03)
        pits = [_ellipsoid(x, y, z, (0.05, yc, 0.3), (0.055, 0.1, 0.16)) for yc in (-0.18, 0.18)]
        crown = _smooth_min([crown, *[-p for p in pits]], 0.015)
        neck = _smooth_min([section(x, y, 0.25, 0.34, 0.15), -z, z + 0.3], 0.02)
        roots = [_capsule(x, y, z, (rx, ry, -0.15), (1.2 * rx, 1.15 * ry, -0.66), 0.1, 0.035)
                 for rx, ry in ((0.13, -0.2), (0.13, 0.2), (-0.14, 0.0))]
        return _smooth_max([crown, neck, *roots], 0.04)

    return vm._level_set_mesh(inside, [-0.42, -0.55, -0.72, 0.42, 0.55, 0.48], 0.012,
                              SELENODONT_H)


# --------------------------------------------------------------------------- smooth


def _tetra_frame() -> BenchMesh:
    """A tetrahedral frame (holdout 15): tubes along the six edges of a regular
    tetrahedron (radii 0.055 to 0.08, a different one on each edge), smoothly joined at the
    four corners, each corner a little swollen (a smooth union of capsules and balls,
    manifold3d level set; genus 3), isotropically remeshed."""
    corners = [(0.42, 0.42, 0.42), (0.42, -0.42, -0.42), (-0.42, 0.42, -0.42),
               (-0.42, -0.42, 0.42)]
    edges = [(0, 1, 0.055), (0, 2, 0.065), (0, 3, 0.08), (1, 2, 0.07), (1, 3, 0.06),
             (2, 3, 0.075)]

    def inside(x, y, z):
        tubes = [_capsule(x, y, z, corners[a], corners[b], r, r) for a, b, r in edges]
        balls = [0.1 - math.sqrt((x - c[0]) ** 2 + (y - c[1]) ** 2 + (z - c[2]) ** 2)
                 for c in corners]
        return _smooth_max([*tubes, *balls], 0.04)

    return vm._level_set_mesh(inside, [-0.58, -0.58, -0.58, 0.58, 0.58, 0.58], 0.01,
                              TETRA_FRAME_H)


# --------------------------------------------------------------------------- brain-like


def _arc_distance(ux, uy, uz, arc) -> float:
    """Angular distance from the unit direction (ux, uy, uz) to a great-circle arc given as
    (start, end, the unit normal of its plane); both ends unit directions."""
    (ax, ay, az), (bx, by, bz), (nx, ny, nz) = arc
    off = ux * nx + uy * ny + uz * nz
    px, py, pz = ux - off * nx, uy - off * ny, uz - off * nz  # onto the arc's plane
    # between the ends: (a x p) and (p x b) both point along the normal
    ax_p = (ay * pz - az * py) * nx + (az * px - ax * pz) * ny + (ax * py - ay * px) * nz
    p_xb = (py * bz - pz * by) * nx + (pz * bx - px * bz) * ny + (px * by - py * bx) * nz
    if ax_p >= 0.0 and p_xb >= 0.0:
        return math.asin(min(1.0, abs(off)))
    to_a = math.acos(max(-1.0, min(1.0, ux * ax + uy * ay + uz * az)))
    to_b = math.acos(max(-1.0, min(1.0, ux * bx + uy * by + uz * bz)))
    return min(to_a, to_b)


def _sulcus_arcs() -> list[tuple]:
    """The sulci as great-circle arcs: :data:`PRIMARY_SULCI` primary arcs (a Fibonacci
    lattice of midpoints, each turned by a seeded generator's uniform angle, 0.6-1 rad
    long), each with two or three side branches leaving it perpendicularly at points along
    it, 0.2-0.35 rad long, to one side or the other (a seeded numpy generator's uniform
    numbers: the same bits on every CPU; the rest is :mod:`math` on Python floats)."""
    rng = np.random.default_rng(1538)
    draws = rng.uniform(0.0, 1.0, size=(PRIMARY_SULCI, 12)).tolist()
    golden = math.pi * (3.0 - math.sqrt(5.0))
    arcs = []

    def unit(v):
        n = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        return (v[0] / n, v[1] / n, v[2] / n)

    def cross(p, q):
        return (p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0])

    def rotate(p, axis, angle):  # p turned about the unit axis by angle (Rodrigues)
        c, s = math.cos(angle), math.sin(angle)
        k = cross(axis, p)
        d = axis[0] * p[0] + axis[1] * p[1] + axis[2] * p[2]
        return tuple(p[i] * c + k[i] * s + axis[i] * d * (1.0 - c) for i in range(3))

    def arc(start, tangent_axis, length):  # from ``start`` about the axis by ``length``
        end = rotate(start, tangent_axis, length)
        return (start, end, unit(cross(start, end)))

    for k, row in enumerate(draws):
        z = 1.0 - 2.0 * (k + 0.5) / PRIMARY_SULCI
        r = math.sqrt(1.0 - z * z)
        mid = (r * math.cos(k * golden), r * math.sin(k * golden), z)
        helper = (0.0, 0.0, 1.0) if abs(z) < 0.9 else (1.0, 0.0, 0.0)
        axis = unit(cross(mid, helper))
        axis = rotate(axis, mid, math.pi * row[0])  # the arc's direction, turned
        length = 0.6 + 0.4 * row[1]
        start = rotate(mid, axis, -0.5 * length)
        arcs.append(arc(start, axis, length))
        for j in range(2 + (row[2] > 0.5)):
            at = rotate(start, axis, length * (0.2 + 0.6 * row[3 + j]))
            side = 1.0 if row[6 + j] > 0.5 else -1.0
            branch_axis = unit(cross(at, axis))  # perpendicular to the primary arc
            arcs.append(arc(at, tuple(side * c for c in branch_axis),
                            0.2 + 0.15 * row[9 + j]))
    return arcs


def _branched_cortex() -> BenchMesh:
    """A synthetic cortex with branched sulci (holdout 15; brain-like, not a brain): an
    ovoid long front to back, narrower at the front, its underside flattened, its surface
    cut by separate sulci, each a great-circle arc with two or three short side branches
    leaving it perpendicularly (T-junctions), ending blind in the surrounding gyral
    surface, a few crossing one another; their depth a ``1 / cosh`` of the distance to the
    nearest arc, varying smoothly over the brain. Made as a radial height field over an
    icosphere (so it cannot cross itself), then isotropically remeshed with no feature
    kept."""
    arcs = _sulcus_arcs()

    def radius(ux, uy, uz):
        lateral = 0.55 * (1.0 - 0.12 * uy)  # narrower at the front (+y)
        r = 1.0 / math.sqrt((ux / lateral) ** 2 + (uy / 0.8) ** 2 + (uz / 0.55) ** 2)
        r = _flattened_underneath(r, uz, 0.36)  # flattened underneath, blended
        nearest = min(_arc_distance(ux, uy, uz, arc) for arc in arcs)
        depth = BRANCH_DEPTH * (1.0 + 0.3 * math.sin(2.0 * ux - 3.0 * uz + 1.0))
        return r - depth / math.cosh(nearest / BRANCH_WIDTH)

    return _radial_surface(radius, BRANCHED_H)


PRIMARY_SULCI, BRANCH_DEPTH, BRANCH_WIDTH = 26, 0.07, 0.045


DOLPHIN_H, SONGBIRD_H, DRIVE_SOCKET_H, BALL_VALVE_H, CABLE_REEL_H, SELENODONT_H = (
    0.012, 0.012, 0.012, 0.012, 0.012, 0.014)
TETRA_FRAME_H, BRANCHED_H = 0.014, 0.016


# A seventeenth set, made in session 38 after holdout 14 had been made: all six kinds, the
# brain kind by a synthetic cortex with branched sulci. No source is shared with the two
# halves, the first fourteen holdouts, the tuning-side CAD parts, scan_flatness_study.py's
# extra scans, animals.py, built_meshes.py, eggcrate.py, brain_probes.py, the λ-H families
# or session 32's tuning-side study parts; every parameter was fixed and the manifest
# committed before any fill was run on them. The scans are portable (the same bits on every
# CPU's BLAS).
HOLDOUT15_SOURCES: dict[str, Source] = {
    "scan_dolphin": Source("range_scan", "simulated scan of the dolphin (portable scanner)",
                           vm._scan(_dolphin, (0.3, -1.0, 0.5), 171, portable=True)),
    "scan_tetra_frame": Source("range_scan", "simulated scan of the tetrahedral frame "
                               "(portable scanner)", vm._scan(_tetra_frame, (0.5, -0.8, 0.4),
                                                              172, portable=True)),
    "scan_ball_valve": Source("range_scan", "simulated scan of the ball valve body CAD part "
                              "(portable scanner)", vm._scan(_ball_valve, (0.6, -0.6, 0.5),
                                                             173, portable=True)),
    "scan_cable_reel": Source("range_scan", "simulated scan of the cable reel CAD part "
                              "(portable scanner)", vm._scan(_cable_reel, (0.5, -0.6, 0.7),
                                                             174, portable=True)),
    "dolphin": Source("organic", "dolphin, arched spindle body, melon, beak, swept dorsal fin, "
                      "pectoral flippers, tail flukes (level set), remeshed", _dolphin),
    "songbird": Source("organic", "songbird on a perch, egg-shaped body, head with a pointed "
                       "beak, folded wings, flat tail, two thin legs gripping a branch (level "
                       "set), remeshed", _songbird),
    "drive_socket": Source("cad", "manifold3d: ratchet drive socket, chamfered stepped body, "
                           "knurled band, hexagonal bore with a chamfered mouth, square drive "
                           "hole, detent hole", _drive_socket),
    "ball_valve": Source("cad", "manifold3d: ball valve body, chamfered round body, necks, "
                         "chamfered hexagonal ends, bore with counterbored sockets, stem boss "
                         "with a stem hole", _ball_valve),
    "cable_reel": Source("cad", "manifold3d: cable reel, drum filleted into two thin flanges "
                         "with rounded rims, hubs, chamfered bore, round and oblong "
                         "lightening holes, cable slot", _cable_reel),
    "selenodont": Source("teeth", "selenodont upper molar, four crescent ridges, two "
                         "infundibulum pits, waist, three roots (level set)", _selenodont),
    "tetra_frame": Source("smooth", "tetrahedral frame, six tubes of different radii smoothly "
                          "joined at swollen corners (level set, genus 3), remeshed",
                          _tetra_frame),
    "branched_cortex": Source("brain", "synthetic cortex, ovoid narrower at the front, "
                              "separate sulci along arcs with side branches in T-junctions, "
                              "ending blind (radial height field), remeshed",
                              _branched_cortex),
}
