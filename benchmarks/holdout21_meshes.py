"""Holdout set 21's meshes (session 44): 12 fresh meshes, made and committed before any fill.

As holdouts 8 to 20's (``holdout8_meshes.py`` .. ``holdout20_meshes.py``): kept out of
:mod:`validation_meshes`, which imports :data:`HOLDOUT21_SOURCES` from here at its end and
adds them to its ``SOURCES``, so every benchmark reaches these meshes through it
(``validation_meshes.load("saguaro")``). The generators use its helpers (level sets,
manifold3d remeshing), holdouts 11 and 12's level-set and radial-surface helpers, holdout
14's smooth minimum and holdout 18's side chart and segment sulci; the four range scans are
the portable scanner's (``simulated_scan(..., portable=True)``: the same bits under every
BLAS kernel). Import :mod:`validation_meshes` first, not this module (an import cycle
otherwise).

All six kinds, as holdouts 11 to 20: 4 simulated range scans of 4 of the others, 2 organic
shapes, 3 CAD parts, 1 tooth, 1 smooth surface and 1 brain-like surface (a synthetic cortex
whose sulci are short oblique dashes in staggered rows, en echelon, between two halves
split by a deep midline fissure; not a real brain) (``benchmarks/holdout21_manifest.json``,
docs/validation.md "Holdout set 21"). Their thickness is mixed on purpose: the mains
plug's blades are 3 edges thick, the hydraulic block's walls beside its mounting holes 2 to
3, the pea pod's stalk and the tooth's root tips 2 to 4; the others are solid.

The level sets' insides and the radial heights are written with Python floats and
:mod:`math` (no numpy transcendental on arrays, whose SIMD loops differ between CPUs: the
AVX-512 ``exp`` and ``log`` of docs/validation.md "Session 43 (helper): cscan_snowman's
bytes"), so a mesh's bits do not depend on the CPU's vector units. Every remeshing passes
PyMeshLab's surface-distance check explicitly (:data:`SURFACE_CHECK`), and no remeshed arc
is so fine that its edges turn by about the remesher's feature angle (30°).
"""

from __future__ import annotations

import math

import validation_meshes as vm
from holdout11_meshes import _capsule, _radial_surface, _smooth_max
from holdout12_meshes import _ellipsoid
from holdout14_meshes import _smooth_min
from holdout17_meshes import _with_midline_fissure
from holdout18_meshes import _feather_chart, _feather_depth
from validation_meshes import BenchMesh, Source

# --------------------------------------------------------------------------- organic


def _ribbed_column(x, y, z, a, b, r_a: float, r_b: float, ribs: int, amplitude: float):
    """Inside of a near-vertical tapered capsule from ``a`` to ``b`` with ``ribs``
    lengthwise ribs of height ``amplitude``, converging on its rounded top (the rib term
    fades as the distance to the axis, about a vertical axis through the nearest axis
    point, shrinks)."""
    inside = _capsule(x, y, z, a, b, r_a, r_b)
    s = min(max((z - a[2]) / (b[2] - a[2]), 0.0), 1.0)
    dx = x - (a[0] + s * (b[0] - a[0]))
    dy = y - (a[1] + s * (b[1] - a[1]))
    rho = math.sqrt(dx * dx + dy * dy)
    fade = min(1.0, rho / (r_a + s * (r_b - r_a))) ** 2
    return inside + amplitude * fade * math.cos(ribs * math.atan2(dy, dx))


def _saguaro() -> BenchMesh:
    """A saguaro cactus (holdout 21): a ribbed trunk standing on a flat cut, rounded on top,
    with two ribbed arms leaving it at different heights and bending up, on opposite sides
    (smooth unions, manifold3d level set), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        parts = [_ribbed_column(x, y, z, (0.0, 0.0, -0.1), (0.0, 0.0, 0.85), 0.09, 0.085,
                                14, SAGUARO_RIB),
                 _capsule(x, y, z, (0.0, 0.0, 0.3), (0.2, 0.0, 0.36), 0.055, 0.055),
                 _ribbed_column(x, y, z, (0.2, 0.0, 0.36), (0.22, 0.0, 0.62), 0.055, 0.052,
                                10, SAGUARO_RIB),
                 _capsule(x, y, z, (0.0, 0.0, 0.45), (-0.17, -0.04, 0.5), 0.05, 0.05),
                 _ribbed_column(x, y, z, (-0.17, -0.04, 0.5), (-0.18, -0.05, 0.72), 0.05,
                                0.047, 10, SAGUARO_RIB)]
        return _smooth_min([_smooth_max(parts, 0.015), z], 0.01)  # cut flat at z = 0

    return vm._level_set_mesh(inside, [-0.3, -0.17, -0.03, 0.34, 0.13, 0.97], 0.006,
                              SAGUARO_H, SURFACE_CHECK)


def _pea_pod() -> BenchMesh:
    """A pea pod (holdout 21): a pod curved along an arc, flattened across, pointed at both
    ends and swollen over six peas, with a ridge along its inner seam, a small calyx and a
    thin stalk at one end (smooth unions, manifold3d level set), isotropically remeshed with
    no feature kept. The stalk is thin: 0.028-0.022 across."""
    reach = POD_ARC * math.sin(POD_HALF_ANGLE)
    lift = POD_ARC * (1.0 - math.cos(POD_HALF_ANGLE))
    out = (-math.cos(POD_HALF_ANGLE), math.sin(POD_HALF_ANGLE))  # the stalk end's outward
    end = (-reach, 0.0, lift)

    def inside(x, y, z):
        phi = min(max(math.atan2(x, POD_ARC - z), -POD_HALF_ANGLE), POD_HALF_ANGLE)
        s, c = math.sin(phi), math.cos(phi)
        px, pz = x - POD_ARC * s, z - POD_ARC * (1.0 - c)  # from the nearest arc point
        along, w = px * c + pz * s, px * s - pz * c  # w > 0 away from the arc's centre
        t = phi / POD_HALF_ANGLE
        swell = math.sqrt(1.0 - t * t)
        peas = math.fsum(math.exp(-((t - k) / 0.09) ** 2) for k in PEAS)
        radius = 0.01 + 0.055 * swell ** 1.2 + 0.012 * swell * peas
        pod = radius - math.sqrt(along * along + w * w + (y / POD_FLAT) ** 2)
        pod += 0.006 * math.exp(-((y / 0.012) ** 2)) * (0.5 - 0.5 * math.tanh(w / 0.01))
        calyx = _ellipsoid(x, y, z, (end[0] + 0.015 * out[0], 0.0, end[2] + 0.015 * out[1]),
                           (0.028, 0.024, 0.028))
        stalk = _capsule(x, y, z, end, (end[0] + 0.07 * out[0] - 0.01, 0.0,
                                        end[2] + 0.07 * out[1] + 0.05), 0.014, 0.011)
        return _smooth_max([pod, calyx, stalk], 0.008)

    return vm._level_set_mesh(inside, [-0.56, -0.07, -0.09, 0.5, 0.07, 0.24], 0.006,
                              POD_H, SURFACE_CHECK)


# --------------------------------------------------------------------------- CAD


def _hex_bolt() -> BenchMesh:
    """A hex bolt (holdout 21): a hexagon head chamfered at its top corners, a washer face
    under it, a round shank with four turned grooves, a chamfered end and a cross hole for a
    split pin near it (manifold3d revolve, cone intersection and booleans; genus 1)."""
    import manifold3d as m3

    r = BOLT_RADIUS
    profile = [(0.0, -0.6), (0.055, -0.6), (r, -0.585)]  # (radius, z), the end chamfered
    for z0 in (-0.45, -0.39, -0.33, -0.27):  # the grooves, 0.025 wide, 0.014 deep
        profile += [(r, z0), (r - 0.014, z0), (r - 0.014, z0 + 0.025), (r, z0 + 0.025)]
    profile += [(r, -0.012), (0.13, -0.012), (0.13, 0.001), (0.0, 0.001)]  # washer face
    body = m3.Manifold.revolve(m3.CrossSection([profile]), 48)
    head = m3.Manifold.cylinder(0.1, 0.15, -1, 6) ^ m3.Manifold.cylinder(0.1, 0.23, 0.13, 64)
    pin = m3.Manifold.cylinder(0.3, 0.03, -1, 32, True).rotate((90.0, 0.0, 0.0)).translate(
        (0.0, 0.0, -0.545))
    return vm._manifold_mesh(body + head - pin, BOLT_H, refine=0.03,
                             surface_check=SURFACE_CHECK)


def _mains_plug() -> BenchMesh:
    """A mains plug (holdout 21): a body with rounded vertical edges and a shallow grip
    recess in each broad side, two flat blades and a round-ended earth pin standing from
    its front face, and a tapered cable boot with the cable's cut stub at its back
    (manifold3d rounded outline, extrusion and booleans; genus 0). The blades are thin:
    0.025 thick."""
    import manifold3d as m3

    outline = m3.CrossSection.square((0.26, 0.16), True).offset(0.04, m3.JoinType.Round,
                                                                 2.0, 32)
    body = m3.Manifold.extrude(outline, 0.2)
    grips = [m3.Manifold.cube((0.2, 0.03, 0.1), True).translate((0.0, side * 0.12, 0.1))
             for side in (-1.0, 1.0)]  # 0.015 deep into each broad side
    blades = [m3.Manifold.cube((0.08, PLUG_BLADE, 0.19)).translate(
        (x0 - 0.04, 0.025 - 0.5 * PLUG_BLADE, 0.19)) for x0 in (-0.07, 0.07)]
    pin = (m3.Manifold.cylinder(0.2, 0.028, -1, 40).translate((0.0, -0.07, 0.19))
           + m3.Manifold.sphere(0.028, 40).translate((0.0, -0.07, 0.39)))
    boot = m3.Manifold.cylinder(0.1, 0.04, 0.06, 48).translate((0.0, 0.0, -0.1))
    cable = m3.Manifold.cylinder(0.1, 0.03, -1, 40).translate((0.0, 0.0, -0.18))
    part = (m3.Manifold.batch_boolean([body, *blades, pin, boot, cable], m3.OpType.Add)
            - m3.Manifold.batch_boolean(grips, m3.OpType.Add))
    return vm._manifold_mesh(part, PLUG_H, refine=0.03, surface_check=SURFACE_CHECK)


def _hydraulic_block() -> BenchMesh:
    """A hydraulic manifold block (holdout 21): a block with rounded vertical edges, a main
    bore through it lengthwise, a counterbored port from the top and another from the side
    meeting it, and two mounting holes through it at opposite corners (manifold3d rounded
    outline, extrusion and booleans; genus 5). The walls beside the mounting holes are thin:
    0.03."""
    import manifold3d as m3

    outline = m3.CrossSection.square((0.42, 0.26), True).offset(0.04, m3.JoinType.Round,
                                                                 2.0, 32)
    block = m3.Manifold.extrude(outline, 0.3)
    z = 0.13  # the main bore's axis
    cuts = [m3.Manifold.cylinder(0.6, 0.05, -1, 48, True).rotate((0.0, 90.0, 0.0))
            .translate((0.0, 0.0, z)),
            m3.Manifold.cylinder(0.2, 0.035, -1, 32).translate((0.08, 0.0, z)),  # top port
            m3.Manifold.cylinder(0.05, 0.06, -1, 48).translate((0.08, 0.0, 0.26)),
            m3.Manifold.cylinder(0.2, 0.04, -1, 32).rotate((-90.0, 0.0, 0.0))  # side port
            .translate((-0.1, 0.0, z)),
            m3.Manifold.cylinder(0.04, 0.06, -1, 48).rotate((-90.0, 0.0, 0.0))
            .translate((-0.1, 0.14, z))]
    cuts += [m3.Manifold.cylinder(0.4, 0.035, -1, 32).translate((x0, y0, -0.05))
             for x0, y0 in ((0.185, 0.105), (-0.185, -0.105))]
    part = block - m3.Manifold.batch_boolean(cuts, m3.OpType.Add)
    return vm._manifold_mesh(part, BLOCK_H, refine=0.03, surface_check=SURFACE_CHECK)


# --------------------------------------------------------------------------- teeth


def _bunodont() -> BenchMesh:
    """A bunodont molar (holdout 21; a pig's): a low rounded crown with four bulbous main
    cusps at its corners and five smaller cusplets between and among them, a constricted
    neck, a root trunk and two tapering roots, front and back, spreading a little (smooth
    unions, manifold3d level set), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        parts = [_ellipsoid(x, y, z, (0.0, 0.0, 0.06), (0.19, 0.14, 0.065)),
                 _ellipsoid(x, y, z, (0.0, 0.0, -0.03), (0.15, 0.105, 0.06))]
        parts += [0.058 - math.sqrt((x - cx) ** 2 + (y - cy) ** 2 + (z - 0.1) ** 2)
                  for cx in (-0.095, 0.095) for cy in (-0.062, 0.062)]
        parts += [r - math.sqrt((x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2)
                  for cx, cy, cz, r in CUSPLETS]
        parts += [_capsule(x, y, z, (side * 0.085, 0.0, 0.0), (side * 0.12, 0.01, -0.23),
                           0.06, 0.018) for side in (-1.0, 1.0)]
        return _smooth_max(parts, 0.012)

    return vm._level_set_mesh(inside, [-0.27, -0.2, -0.28, 0.27, 0.2, 0.2], 0.008,
                              BUNODONT_H, SURFACE_CHECK)


# --------------------------------------------------------------------------- smooth


def _dimple_centres(count: int) -> list[tuple[float, float, float]]:
    """``count`` unit directions spread evenly over the sphere (a Fibonacci lattice:
    heights evenly spaced, each turned by the golden angle from the one before)."""
    golden = math.pi * (3.0 - math.sqrt(5.0))
    centres = []
    for k in range(count):
        z = 1.0 - (2.0 * k + 1.0) / count
        rho = math.sqrt(1.0 - z * z)
        centres.append((rho * math.cos(golden * k), rho * math.sin(golden * k), z))
    return centres


def _golf_ball() -> BenchMesh:
    """A golf ball (holdout 21): a ball covered by 120 round dimples, spread evenly (a
    Fibonacci lattice) with narrow lands between them, each a smooth bowl with a rounded rim
    (radial height field), isotropically remeshed with no feature kept."""
    centres = _dimple_centres(DIMPLES)
    near = math.cos(DIMPLE_ANGLE)

    def radius(ux, uy, uz):
        closest = max(ux * cx + uy * cy + uz * cz for cx, cy, cz in centres)
        if closest <= near:
            return GOLF_RADIUS
        s = math.acos(min(1.0, closest)) / DIMPLE_ANGLE
        return GOLF_RADIUS - DIMPLE_DEPTH * (1.0 - s * s) ** 2

    return _radial_surface(radius, GOLF_H, SURFACE_CHECK)


# --------------------------------------------------------------------------- brain-like


def _echelon_segments() -> list:
    """The en echelon sulci as chart segments ((t0, p0), (t1, p1), free start, free end) of
    :func:`_feather_chart`: in each row of :data:`ECHELON_ROWS` (its elevation, its first
    dash's centre t, how many dashes) short straight dashes :data:`ECHELON_STEP` apart front
    to back, each rising obliquely towards the front, overlapping its neighbours' extent
    without meeting them, free at both ends."""
    half_t, half_p = 0.5 * ECHELON_RUN, 0.5 * ECHELON_RISE
    return [((t - half_t, p - half_p), (t + half_t, p + half_p), True, True)
            for p, first, count in ECHELON_ROWS
            for t in (first + ECHELON_STEP * k for k in range(count))]


def _echelon_cortex() -> BenchMesh:
    """A synthetic cortex with en echelon sulci (holdout 21; brain-like, not a brain): an
    ovoid long front to back, fuller at the front, split over the top by a deep midline
    fissure into two halves; on each side three rows of short straight sulci, one row above
    another, each sulcus slanting up towards the front and overlapping the next one's
    extent, staggered like the dashes of en echelon faults, each ending blind at both ends.
    Made as a radial height field over an icosphere (so it cannot cross itself), then
    isotropically remeshed with no feature kept."""

    def radius(ux, uy, uz):
        lateral = 0.46 * (1.0 + 0.06 * uy)  # fuller at the front (+y)
        r = 1.0 / math.sqrt((ux / lateral) ** 2 + (uy / 0.8) ** 2 + (uz / 0.56) ** 2)
        t, p, scale = _feather_chart(ux, uy, uz)
        depth = _feather_depth(t, p, scale, ECHELON_SEGMENTS)
        depth = _with_midline_fissure(depth, ux, uz, ECHELON_FISSURE_WIDTH)
        return r - ECHELON_DEPTH * depth

    return _radial_surface(radius, ECHELON_H, SURFACE_CHECK)


SAGUARO_RIB = 0.008
POD_ARC, POD_HALF_ANGLE, POD_FLAT = 1.2, 0.35, 0.75  # the pod's arc radius, half-angle
PEAS = (-0.68, -0.41, -0.14, 0.14, 0.41, 0.68)  # the peas' places along the pod (-1 to 1)
BOLT_RADIUS = 0.07
PLUG_BLADE = 0.025  # 3.1 edges of 0.008
CUSPLETS = ((0.0, -0.075, 0.115, 0.035), (0.0, 0.075, 0.115, 0.035),
            (-0.125, 0.0, 0.105, 0.032), (0.125, 0.0, 0.105, 0.032), (0.0, 0.0, 0.1, 0.03))
DIMPLES, DIMPLE_ANGLE, DIMPLE_DEPTH, GOLF_RADIUS = 120, 0.12, 0.009, 0.25
# each row of dashes: its elevation (radians), its back dash's centre t, its number of dashes
ECHELON_ROWS = ((-0.3, -0.95, 7), (0.25, -1.1, 8), (0.8, -0.95, 7))
ECHELON_STEP, ECHELON_RUN, ECHELON_RISE = 0.3, 0.36, 0.3
ECHELON_SEGMENTS = _echelon_segments()
ECHELON_DEPTH, ECHELON_FISSURE_WIDTH = 0.065, 0.035
SAGUARO_H, POD_H, BOLT_H, PLUG_H, BLOCK_H, BUNODONT_H = (
    0.01, 0.008, 0.01, 0.008, 0.012, 0.01)
GOLF_H, ECHELON_H = 0.01, 0.016
# every remeshing passes PyMeshLab's surface-distance check (checksurfdist) explicitly: left
# to the filter, it is a leftover byte of the heap (validation_meshes._remesh; holdout 17)
SURFACE_CHECK = True


# A twenty-third set, made in session 44 after holdout 20 had been made: all six kinds, the
# brain kind by a synthetic cortex with en echelon sulci. No source is shared with the two
# halves, the first twenty holdouts, the tuning-side CAD parts, the smooth tuning set, the
# curved scans, the thin shells, scan_flatness_study.py's extra scans, animals.py,
# built_meshes.py, eggcrate.py, brain_probes.py, the λ-H families or session 32's
# tuning-side study parts; every parameter was fixed and the manifest committed before any
# fill was run on them. The scans are portable (the same bits on every CPU's BLAS).
HOLDOUT21_SOURCES: dict[str, Source] = {
    "scan_bunodont": Source("range_scan", "simulated scan of the bunodont molar (portable "
                            "scanner)", vm._scan(_bunodont, (0.3, -0.6, 0.75), 195,
                                                 portable=True)),
    "scan_golf_ball": Source("range_scan", "simulated scan of the golf ball (portable "
                             "scanner)", vm._scan(_golf_ball, (0.2, -0.6, 0.75), 196,
                                                  portable=True)),
    "scan_mains_plug": Source("range_scan", "simulated scan of the mains plug CAD part "
                              "(portable scanner)", vm._scan(_mains_plug, (0.4, -0.7, 0.6),
                                                             197, portable=True)),
    "scan_hydraulic_block": Source("range_scan", "simulated scan of the hydraulic manifold "
                                   "block CAD part (portable scanner)",
                                   vm._scan(_hydraulic_block, (-0.55, 0.5, 0.65), 198,
                                            portable=True)),
    "saguaro": Source("organic", "saguaro cactus, ribbed trunk cut flat at its foot, two "
                      "ribbed arms bending up at different heights (level set), remeshed",
                      _saguaro),
    "pea_pod": Source("organic", "pea pod, curved, flattened across, pointed ends, swollen "
                      "over six peas, seam ridge, calyx and thin stalk (level set), remeshed",
                      _pea_pod),
    "hex_bolt": Source("cad", "manifold3d: hex bolt, hexagon head chamfered at its corners, "
                       "washer face, shank with four turned grooves, chamfered end, cross "
                       "hole for a split pin", _hex_bolt),
    "mains_plug": Source("cad", "manifold3d: mains plug, body with rounded vertical edges "
                         "and two grip recesses, two thin flat blades, round-ended earth pin, "
                         "tapered cable boot, cut cable stub", _mains_plug),
    "hydraulic_block": Source("cad", "manifold3d: hydraulic manifold block, rounded vertical "
                              "edges, main bore, counterbored top and side ports meeting "
                              "it, two mounting holes", _hydraulic_block),
    "bunodont": Source("teeth", "bunodont molar, low crown with four bulbous cusps and five "
                       "cusplets, constricted neck, root trunk, two spreading roots (level "
                       "set)", _bunodont),
    "golf_ball": Source("smooth", "golf ball, 120 round dimples with rounded rims spread "
                        "evenly over a ball (radial height field), remeshed", _golf_ball),
    "echelon_cortex": Source("brain", "synthetic cortex, ovoid split by a deep midline "
                             "fissure, on each side three rows of short oblique sulci "
                             "staggered en echelon, ending blind (radial height field), "
                             "remeshed", _echelon_cortex),
}
