"""Holdout set 12's meshes (session 35): 12 fresh meshes, made and committed before any fill.

As holdouts 8 to 11's (``holdout8_meshes.py`` .. ``holdout11_meshes.py``): kept out of
:mod:`validation_meshes`, which imports :data:`HOLDOUT12_SOURCES` from here at its end and
adds them to its ``SOURCES``, so every benchmark reaches these meshes through it
(``validation_meshes.load("teddy")``). The generators use its helpers (level sets,
manifold3d remeshing) and holdout 11's level-set helpers; the four range scans are the
portable scanner's (``simulated_scan(..., portable=True)``: the same bits under every BLAS
kernel). Import :mod:`validation_meshes` first, not this module (an import cycle otherwise).

All six kinds, as holdout 11: 4 simulated range scans of 4 of the others, 2 organic shapes,
3 CAD parts, 1 tooth, 1 smooth level set and 1 brain-like surface (a synthetic cerebellum
with parallel folia, not a real brain) (``benchmarks/holdout12_manifest.json``,
docs/validation.md "Holdout set 12").

The level sets' insides are written with Python floats and :mod:`math` (no numpy
transcendental on arrays, whose SIMD loops differ between CPUs), so a mesh's bits do not
depend on the CPU's vector units.
"""

from __future__ import annotations

import math

import validation_meshes as vm
from holdout11_meshes import _capsule, _radial_surface, _smooth_max
from validation_meshes import BenchMesh, Source


def _ellipsoid(x, y, z, centre, axes) -> float:
    """Inside of an ellipsoid (scaled: ``1 - |(p - centre) / axes|`` times its smallest
    half-axis, roughly a distance near the surface), in Python floats."""
    u = (x - centre[0]) / axes[0]
    v = (y - centre[1]) / axes[1]
    w = (z - centre[2]) / axes[2]
    return min(axes) * (1.0 - math.sqrt(u * u + v * v + w * w))


# --------------------------------------------------------------------------- organic


def _teddy() -> BenchMesh:
    """A sitting teddy bear (holdout 12): an egg-shaped body, a round head with a snout and
    a ball of a nose, two round ears flattened front to back, two arms reaching forward
    and two stubby legs stretched out in front (tapered capsules), blended by smooth unions
    (manifold3d level set), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        body = _ellipsoid(x, y, z, (0.0, 0.0, 0.0), (0.32, 0.27, 0.4))
        head = 0.27 - math.sqrt(x * x + (y + 0.03) ** 2 + (z - 0.58) ** 2)
        snout = _ellipsoid(x, y, z, (0.0, -0.25, 0.52), (0.12, 0.1, 0.09))
        nose = 0.04 - math.sqrt(x * x + (y + 0.35) ** 2 + (z - 0.55) ** 2)
        ears = [_ellipsoid(x, y, z, (s * 0.2, 0.0, 0.8), (0.1, 0.05, 0.1)) for s in (-1, 1)]
        arms = [_capsule(x, y, z, (s * 0.22, -0.05, 0.2), (s * 0.36, -0.3, 0.0), 0.1, 0.08)
                for s in (-1.0, 1.0)]
        legs = [_capsule(x, y, z, (s * 0.16, -0.05, -0.28), (s * 0.22, -0.48, -0.36), 0.12,
                         0.1) for s in (-1.0, 1.0)]
        return _smooth_max([body, head, snout, nose, *ears, *arms, *legs], 0.03)

    return vm._level_set_mesh(inside, [-0.55, -0.65, -0.55, 0.55, 0.4, 0.95], 0.02, TEDDY_H)


def _fish() -> BenchMesh:
    """A fish (holdout 12): a laterally flattened spindle body, a narrow tail stalk and a
    forked tail fin of two flattened lobes, a dorsal and a belly fin (flattened tapered
    capsules), and two bulging eyes (manifold3d level set), isotropically remeshed with no
    feature kept."""

    def flat(x, y, z, a, b, r_a, r_b, squash):  # a capsule squashed across y
        return _capsule(x, y * squash, z, a, b, r_a, r_b) / squash

    def inside(x, y, z):
        body = _ellipsoid(x, y, z, (0.0, 0.0, 0.0), (0.62, 0.14, 0.26))
        stalk = flat(x, y, z, (0.4, 0.0, 0.0), (0.78, 0.0, 0.0), 0.12, 0.05, 1.6)
        lobes = [flat(x, y, z, (0.74, 0.0, 0.0), (0.98, 0.0, s * 0.26), 0.08, 0.05, 1.6)
                 for s in (-1.0, 1.0)]
        dorsal = flat(x, y, z, (-0.1, 0.0, 0.18), (0.22, 0.0, 0.36), 0.1, 0.045, 1.8)
        belly = flat(x, y, z, (0.12, 0.0, -0.16), (0.3, 0.0, -0.3), 0.08, 0.04, 1.8)
        eyes = [0.045 - math.sqrt((x + 0.42) ** 2 + (y - s * 0.085) ** 2 + (z - 0.06) ** 2)
                for s in (-1.0, 1.0)]
        return _smooth_max([body, stalk, *lobes, dorsal, belly, *eyes], 0.025)

    return vm._level_set_mesh(inside, [-0.75, -0.25, -0.45, 1.1, 0.25, 0.5], 0.015, FISH_H)


# --------------------------------------------------------------------------- CAD


def _brick() -> BenchMesh:
    """A toy building brick (holdout 12): a 4 by 2 block with eight round studs on top,
    hollow from below (thin walls and top) with three hollow tubes standing inside between
    the studs' rows (manifold3d booleans)."""
    import manifold3d as m3

    pitch, height = 0.32, 0.38
    block = m3.Manifold.cube((4 * pitch, 2 * pitch, height), True).translate(
        (0.0, 0.0, 0.5 * height))
    hollow = m3.Manifold.cube((4 * pitch - 0.14, 2 * pitch - 0.14, height), True).translate(
        (0.0, 0.0, 0.5 * height - 0.07))
    studs = [m3.Manifold.cylinder(0.07, 0.1, -1, 48).translate(
        ((i - 1.5) * pitch, (j - 0.5) * pitch, height)) for i in range(4) for j in range(2)]
    tubes = [(m3.Manifold.cylinder(height - 0.05, 0.13, -1, 48)
              - m3.Manifold.cylinder(height, 0.08, -1, 48).translate((0.0, 0.0, -0.1))
              ).translate(((i - 1.0) * pitch, 0.0, 0.0)) for i in range(3)]
    part = block - hollow + m3.Manifold.batch_boolean(studs + tubes, m3.OpType.Add)
    return vm._manifold_mesh(part, BRICK_H, refine=0.03)


def _hex_key() -> BenchMesh:
    """A hex key (holdout 12): a bar of regular hexagonal section (0.16 across the flats)
    bent through a quarter turn round a radius of 0.12, a long arm ending in a chamfer and a
    short arm ending in a narrower neck and a ball (manifold3d revolve, extrusions and
    booleans)."""
    import manifold3d as m3

    across = 0.16
    corner = across / math.sqrt(3.0)  # the hexagon's circumradius
    hexagon = [(corner * math.cos(math.pi / 3 * k), corner * math.sin(math.pi / 3 * k))
               for k in range(6)]
    bend_r = 0.12
    section = m3.CrossSection([[(bend_r + px, py) for px, py in hexagon]])
    # the bend: the section revolved a quarter turn about z (in the xy-plane's first quadrant)
    bend = m3.Manifold.revolve(section, 48, 90.0)
    # the long arm along -y from the bend's start (the section in the xz-plane at y = 0),
    # its end chamfered: cut by a cylinder of the corners' radius ending in a cone
    long_arm = m3.Manifold.extrude(m3.CrossSection([hexagon]), 1.1).rotate(
        (90.0, 0.0, 0.0)).translate((bend_r, 0.0, 0.0))
    rod = m3.Manifold.batch_hull([
        m3.Manifold.cylinder(1.06, corner, -1, 48).rotate((90.0, 0.0, 0.0)),
        m3.Manifold.cylinder(0.01, 0.06, -1, 48).rotate((90.0, 0.0, 0.0)).translate(
            (0.0, -1.1, 0.0))]).translate((bend_r, 0.0, 0.0))
    # the short arm along -x from the bend's end (the section in the yz-plane at x = 0),
    # a neck and a ball at its end
    short_arm = m3.Manifold.extrude(m3.CrossSection([hexagon]), 0.34).rotate(
        (0.0, -90.0, 0.0)).rotate((90.0, 0.0, 0.0)).translate((0.0, bend_r, 0.0))
    neck = m3.Manifold.cylinder(0.14, 0.055, -1, 48).rotate((0.0, -90.0, 0.0)).translate(
        (-0.32, bend_r, 0.0))
    ball = m3.Manifold.sphere(0.09, 64).translate((-0.5, bend_r, 0.0))
    part = bend + (long_arm ^ rod) + short_arm + neck + ball
    return vm._manifold_mesh(part, HEX_KEY_H, refine=0.03)


def _funnel() -> BenchMesh:
    """A funnel (holdout 12): a conical bowl of wall 0.07 with a flat rim flange, narrowing
    into a straight spout cut off at a slant, and a flat tab on the flange with a hanging
    hole (manifold3d revolve and booleans; genus 2)."""
    import manifold3d as m3

    profile = [(0.09, -0.1), (0.15, -0.1), (0.15, 0.38), (0.6, 0.9), (0.7, 0.9), (0.7, 0.96),
               (0.56, 0.96), (0.09, 0.44)]
    bowl = m3.Manifold.revolve(m3.CrossSection([profile]), 160)
    slant = m3.Manifold.cube((1.0, 1.0, 0.4), True).rotate((0.0, 25.0, 0.0)).translate(
        (0.0, 0.0, -0.2))
    tab = (m3.Manifold.cube((0.26, 0.22, 0.06)).translate((0.62, -0.11, 0.9))
           - m3.Manifold.cylinder(0.2, 0.05, -1, 48).translate((0.8, 0.0, 0.85)))
    return vm._manifold_mesh(bowl - slant + tab, FUNNEL_H, refine=0.03)


# --------------------------------------------------------------------------- teeth


def _carnassial() -> BenchMesh:
    """A carnassial (holdout 12; a cat's upper shearing premolar): a long crown, narrow
    from cheek to tongue, rising into three pointed cusps in a row (the middle one the
    tallest) joined by a sharp-crested blade, a bulge on the tongue side and two
    diverging roots (manifold3d level set), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        crown = _ellipsoid(x, y, z, (0.0, 0.0, 0.18), (0.5, 0.15, 0.16))
        cusps = [_capsule(x, y * 1.6, z, (cx, 0.0, 0.18), (cx, 0.0, 0.18 + ch), 0.13, 0.035)
                 / 1.6 for cx, ch in ((-0.3, 0.2), (0.0, 0.38), (0.3, 0.26))]
        blade = _smooth_max(cusps, 0.025)
        bulge = _ellipsoid(x, y, z, (-0.22, 0.12, 0.15), (0.12, 0.1, 0.1))
        roots = [_capsule(x, y, z, (s * 0.24, 0.0, 0.12), (s * 0.34, 0.0, -0.45), 0.11, 0.035)
                 for s in (-1.0, 1.0)]
        return _smooth_max([crown, blade, bulge, *roots], 0.035)

    return vm._level_set_mesh(inside, [-0.65, -0.3, -0.6, 0.65, 0.35, 0.7], 0.015,
                              CARNASSIAL_H)


# --------------------------------------------------------------------------- smooth


def _chmutov() -> BenchMesh:
    """A Chmutov-type quartic (holdout 12): the set ``T4(x) + T4(y) + T4(z) < c`` of the
    Chebyshev polynomial ``T4(u) = 8u^4 - 8u^2 + 1`` at ``c = CHMUTOV_LEVEL`` (a regular
    value, away from the polynomial's critical values): a cube-like cage of bulges joined by
    tubes, saddles between them (manifold3d level set), isotropically remeshed. Scaled by
    0.6."""

    def t4(u):
        u2 = u * u
        return 8.0 * u2 * u2 - 8.0 * u2 + 1.0

    def inside(x, y, z):
        return 0.1 * (CHMUTOV_LEVEL - t4(x / 0.6) - t4(y / 0.6) - t4(z / 0.6))

    return vm._level_set_mesh(inside, [-0.75, -0.75, -0.75, 0.75, 0.75, 0.75], 0.015,
                              CHMUTOV_H)


CHMUTOV_LEVEL = 0.5


# --------------------------------------------------------------------------- brain-like


def _cerebellum() -> BenchMesh:
    """A synthetic cerebellum (holdout 12; brain-like, not a brain): two broad lateral
    hemispheres joined by a narrower middle (a notch at the front and one at the back), its
    whole surface folded into thin parallel folia (grooves running side to side, a function
    of the angle about the lateral axis, slightly wavy). Made as a radial height field
    over an icosphere (so it cannot cross itself), then isotropically remeshed with no
    feature kept."""
    def radius(ux, uy, uz):
        r = 1.0 / math.sqrt((ux / 0.62) ** 2 + (uy / 0.4) ** 2 + (uz / 0.32) ** 2)
        for side in (-1.0, 1.0):  # the notches: the middle lower front and back
            r -= 0.07 * math.exp(-(ux * ux) / (2.0 * 0.1**2)
                                 - (uy - side * 0.9) ** 2 / (2.0 * 0.35**2))
        angle = math.atan2(uz, uy) + 0.06 * math.sin(7.0 * ux)  # about the x axis
        groove = math.exp((math.cos(FOLIA * angle) - 1.0) / FOLIUM_WIDTH)
        # shallower towards the sides, where the grooves (about the x axis) crowd together
        fade = 1.0 - math.exp(-(uy * uy + uz * uz) / 0.08)
        return r - FOLIUM_DEPTH * fade * groove

    return _radial_surface(radius, CEREBELLUM_H)


FOLIA, FOLIUM_DEPTH, FOLIUM_WIDTH = 22.0, 0.04, 0.8


TEDDY_H, FISH_H, BRICK_H, HEX_KEY_H, FUNNEL_H, CARNASSIAL_H, CHMUTOV_H, CEREBELLUM_H = (
    0.02, 0.015, 0.02, 0.012, 0.02, 0.016, 0.025, 0.015)


# A fourteenth set, made in session 35 after holdout 11 had been made: all six kinds, the
# brain kind by a synthetic cerebellum. No source is shared with the two halves, the first
# eleven holdouts, the tuning-side CAD parts, scan_flatness_study.py's extra scans,
# animals.py, built_meshes.py, eggcrate.py, brain_probes.py, the λ-H families or session
# 32's tuning-side study parts; every parameter was fixed and the manifest committed before
# any fill was run on them. The scans are portable (the same bits on every CPU's BLAS).
HOLDOUT12_SOURCES: dict[str, Source] = {
    "scan_teddy": Source("range_scan", "simulated scan of the teddy bear (portable scanner)",
                         vm._scan(_teddy, (0.5, -1.0, 0.4), 159, portable=True)),
    "scan_chmutov": Source("range_scan", "simulated scan of the Chmutov quartic (portable "
                           "scanner)", vm._scan(_chmutov, (0.7, 0.3, 0.6), 160,
                                                portable=True)),
    "scan_brick": Source("range_scan", "simulated scan of the toy brick CAD part (portable "
                         "scanner)", vm._scan(_brick, (-0.5, -0.7, 0.6), 161, portable=True)),
    "scan_funnel": Source("range_scan", "simulated scan of the funnel CAD part (portable "
                          "scanner)", vm._scan(_funnel, (0.3, -0.4, 0.9), 162, portable=True)),
    "teddy": Source("organic", "sitting teddy bear, snout and nose, round ears, arms, legs "
                    "(level set), remeshed", _teddy),
    "fish": Source("organic", "fish, flattened spindle body, forked tail fin, dorsal and "
                   "belly fins, bulging eyes (level set), remeshed", _fish),
    "brick": Source("cad", "manifold3d: toy building brick 4 by 2, eight studs, hollow "
                    "underneath with three tubes", _brick),
    "hex_key": Source("cad", "manifold3d: hex key, hexagonal bar bent through a quarter "
                      "turn, chamfered long arm, ball-end short arm", _hex_key),
    "funnel": Source("cad", "manifold3d: funnel, conical bowl, rim flange with a holed tab, "
                     "spout cut at a slant", _funnel),
    "carnassial": Source("teeth", "carnassial tooth, narrow crown, three cusps in a row on "
                         "a blade, lingual bulge, two roots (level set)", _carnassial),
    "chmutov": Source("smooth", "Chmutov-type quartic T4(x)+T4(y)+T4(z) < 0.5 (level set), "
                      "remeshed", _chmutov),
    "cerebellum": Source("brain", "synthetic cerebellum, two hemispheres, front and back "
                         "notches, parallel folia (radial height field), remeshed",
                         _cerebellum),
}
