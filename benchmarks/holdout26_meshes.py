"""Holdout set 26's meshes (session 49): 12 fresh meshes, made and committed before any fill.

As holdouts 8 to 25's (``holdout8_meshes.py`` .. ``holdout25_meshes.py``): kept out of
:mod:`validation_meshes`, which imports :data:`HOLDOUT26_SOURCES` from here after holdout
25's and adds them to its ``SOURCES``, so every benchmark reaches these meshes through it
(``validation_meshes.load("tulip")``). The generators use its helpers (level sets,
manifold3d remeshing), holdout 11's level-set and radial-surface helpers, holdout 12's
ellipsoid, holdout 14's smooth minimum and flattened underside, holdout 17's midline
fissure, holdout 18's side chart and holdout 25's flat wing and rounded rectangle; the four
range scans are the portable scanner's (``simulated_scan(..., portable=True)``: the same
bits under every BLAS kernel). Import :mod:`validation_meshes` first, not this module (an
import cycle otherwise).

All six kinds, as holdouts 11 to 25: 4 simulated range scans of 4 of the others, 2 organic
shapes, 3 CAD parts, 1 tooth, 1 smooth surface and 1 brain-like surface (a synthetic
cortex whose sulci are separate three-armed stars, between two halves split by a deep
midline fissure; not a real brain) (``benchmarks/holdout26_manifest.json``,
docs/validation.md "Holdout set 26"). Their thickness is mixed on purpose: the tulip's
petals and leaves, the pallet's boards, the ladder's rails and the chain link's side
plates are about 2 edges thick; the others are solid.

The level sets' insides and the radial heights are written with Python floats and
:mod:`math` (no numpy transcendental on arrays, whose SIMD loops differ between CPUs: the
AVX-512 ``exp`` and ``log`` of docs/validation.md "Session 43 (helper): cscan_snowman's
bytes"), so a mesh's bits do not depend on the CPU's vector units. Every remeshing passes
PyMeshLab's surface-distance check explicitly (:data:`SURFACE_CHECK`).
"""

from __future__ import annotations

import math

import validation_meshes as vm
from holdout11_meshes import _capsule, _radial_surface, _smooth_max
from holdout12_meshes import _ellipsoid
from holdout14_meshes import _flattened_underneath, _smooth_min
from holdout17_meshes import _with_midline_fissure
from holdout18_meshes import _feather_chart
from holdout25_meshes import _rounded_rectangle, _wing
from validation_meshes import BenchMesh, Source

# --------------------------------------------------------------------------- organic


def _banana(x, y, z, heading: float) -> float:
    """Inside of one banana of the hand: a tube along a circular arc of radius
    :data:`BANANA_BEND` in the vertical plane of ``heading`` (radians about z), starting
    at the crown and curving up, its radius swelling to :data:`BANANA_RADIUS` in the middle
    and tapering to both ends, its cross-section five-sided (five low ridges)."""
    dx, dy = math.cos(heading), math.sin(heading)
    sx, sy = BANANA_START * dx, BANANA_START * dy
    # the arc's centre lies BANANA_BEND above its start: the banana curves up
    px, py, pz = x - sx, y - sy, z - BANANA_BEND
    along, off = px * dx + py * dy, -px * dy + py * dx
    theta = math.atan2(along, -pz)
    end = BANANA_ARC
    if 0.0 <= theta <= end:
        bend = math.hypot(along, pz) - BANANA_BEND
        u = theta / end
    else:
        u = 0.0 if theta < 0.0 else 1.0
        a = u * end
        bend = math.hypot(along - BANANA_BEND * math.sin(a), pz + BANANA_BEND * math.cos(a))
    distance = math.hypot(bend, off)
    ridges = 1.0 + 0.05 * math.cos(5.0 * math.atan2(off, bend))
    radius = BANANA_RADIUS * math.sqrt(math.sin(math.pi * (0.1 + 0.8 * u)))
    return radius * ridges - distance


def _banana_hand() -> BenchMesh:
    """A hand of three bananas (holdout 26): three curved five-ridged fruits fanning out
    from a common crown, each tapering to a small blunt tip, and a short thick stalk
    (smooth unions, manifold3d level set), isotropically remeshed with no feature kept."""
    reach = BANANA_START + BANANA_BEND * math.sin(BANANA_ARC)  # the tips' place
    lift = BANANA_BEND * (1.0 - math.cos(BANANA_ARC))

    def inside(x, y, z):
        parts = [_ellipsoid(x, y, z, (0.0, 0.0, 0.0), (0.04, 0.06, 0.035)),
                 _capsule(x, y, z, (-0.01, 0.0, 0.005), (-0.09, 0.0, 0.05), 0.022, 0.016)]
        for heading in BANANA_HEADINGS:
            parts.append(_banana(x, y, z, heading))
            parts.append(_capsule(x, y, z, (reach * math.cos(heading),
                                            reach * math.sin(heading), lift),
                                  ((reach + 0.012) * math.cos(heading),
                                   (reach + 0.012) * math.sin(heading), lift + 0.012),
                                  0.008, 0.007))  # the blunt tip
        return _smooth_max(parts, 0.01)

    return vm._level_set_mesh(inside, [-0.13, -0.21, -0.07, 0.34, 0.21, 0.2], 0.005,
                              BANANA_H, SURFACE_CHECK)


def _tulip() -> BenchMesh:
    """A tulip (holdout 26): a cup of six petals, a thin shell open at the top whose rim
    rises to six pointed petal tips with notches between them, on a long slightly curved
    stem, and two long flat leaves rising from the stem's foot (smooth unions, manifold3d
    level set), isotropically remeshed with no feature kept. The petals and leaves are
    thin: :data:`TULIP_PETAL` and holdout 25's wing thick."""
    cup_centre, cup_axes = (0.0, 0.0, 0.33), (0.085, 0.085, 0.11)

    def inside(x, y, z):
        shell = 0.5 * TULIP_PETAL - abs(_ellipsoid(x, y, z, cup_centre, cup_axes))
        phi = math.atan2(y, x)
        rim = 0.39 - 0.045 * (1.0 - abs(math.cos(3.0 * phi))) - z
        parts = [_smooth_min([shell, rim], 0.003),
                 _capsule(x, y, z, (0.0, 0.0, 0.215), (0.015, 0.0, 0.08), 0.011, 0.011),
                 _capsule(x, y, z, (0.015, 0.0, 0.08), (0.0, 0.0, -0.04), 0.011, 0.012)]
        for side in (-1.0, 1.0):  # the leaves, flat in the xz plane: the wing's xy
            parts.append(_wing(x, z, y, (side * 0.01, -0.02, side * 0.015),
                               (side * 0.13, 0.2, side * 0.03), 0.03, 0.012))
        return _smooth_max(parts, 0.004)

    return vm._level_set_mesh(inside, [-0.16, -0.11, -0.07, 0.16, 0.11, 0.42], 0.0035,
                              TULIP_H, SURFACE_CHECK)


# --------------------------------------------------------------------------- CAD


def _pallet() -> BenchMesh:
    """A block pallet (holdout 26): five top deck boards across three stringer boards on
    nine blocks, over three bottom deck boards, thin boards with gaps between them
    (manifold3d boxes and booleans)."""
    import manifold3d as m3

    def board(size, centre):
        return m3.Manifold.cube(size, True).translate(centre)

    t = PALLET_BOARD
    # each layer reaches halfway into the boards above and below it (boards meeting face to
    # face stay apart in manifold3d's union) and no two side faces are flush (a flush seam
    # in a flat face left edges of the remeshing in more than two faces): each layer steps
    # 0.01 or more past the one below or above it
    parts = [board((0.42, 0.065, t), (0.0, (k - 2) * 0.08, 0.09 - 0.5 * t)) for k in range(5)]
    for i in (-1, 0, 1):
        x = i * 0.16
        parts.append(board((0.07, 0.36, 1.5 * t), (x, 0.0, 0.09 - 1.25 * t)))
        for j in (-1, 0, 1):
            parts.append(board((0.09, 0.08, 0.09 - 2.0 * t), (x, j * 0.13, 0.045 - 0.5 * t)))
        parts.append(board((0.44, 0.1, t), (0.0, i * 0.13, 0.5 * t)))
    part = m3.Manifold.batch_boolean(parts, m3.OpType.Add)
    return vm._manifold_mesh(part, PALLET_H, refine=0.03, surface_check=SURFACE_CHECK)


def _ladder() -> BenchMesh:
    """A short ladder (holdout 26): two thin flat rails joined by five round rungs whose
    ends are set into the rails (manifold3d boxes, cylinders and booleans; genus 4)."""
    import manifold3d as m3

    parts = []
    for side in (-1.0, 1.0):
        rail = m3.Manifold.cube((LADDER_RAIL, 0.045, 0.55), True)
        parts.append(rail.translate((side * 0.11, 0.0, 0.275)))
    for k in range(5):
        rung = m3.Manifold.cylinder(0.22, 0.014, 0.014, 48, True).rotate((0.0, 90.0, 0.0))
        parts.append(rung.translate((0.0, 0.0, 0.075 + 0.1 * k)))
    part = m3.Manifold.batch_boolean(parts, m3.OpType.Add)
    return vm._manifold_mesh(part, LADDER_H, refine=0.03, surface_check=SURFACE_CHECK)


def _chain_link() -> BenchMesh:
    """A cable drag chain's link (holdout 26): two thin side plates with rounded ends, a
    round pivot hole at each end, joined by a crossbar along the top and one along the
    bottom (manifold3d outlines, extrusions and booleans; genus 5)."""
    import manifold3d as m3

    outline = _rounded_rectangle(0.16, 0.07, 0.034)
    hole = m3.CrossSection.circle(0.014, 48)
    plate = m3.Manifold.extrude(outline - hole.translate((-0.046, 0.0))
                                - hole.translate((0.046, 0.0)), CHAIN_PLATE)
    plate = plate.translate((0.0, 0.0, -0.5 * CHAIN_PLATE)).rotate((90.0, 0.0, 0.0))
    parts = [plate.translate((0.0, side * 0.05, 0.0)) for side in (-1.0, 1.0)]
    for side in (-1.0, 1.0):
        bar = m3.Manifold.cube((0.05, 0.1, 0.012), True)
        parts.append(bar.translate((0.0, 0.0, side * 0.029)))  # flush with the plates' edges
    part = m3.Manifold.batch_boolean(parts, m3.OpType.Add)
    return vm._manifold_mesh(part, CHAIN_H, refine=0.03, surface_check=SURFACE_CHECK)


# --------------------------------------------------------------------------- teeth


def _triangle(x, y, corners) -> float:
    """Inside of the triangle ``corners`` (counter-clockwise) at (x, y): a smooth minimum
    of the signed distances to its three edges' lines (positive inside), so its corners
    are rounded (a sharp salient angle is a knife edge the remeshing cannot follow)."""
    edges = []
    for k in range(3):
        (ax, ay), (bx, by) = corners[k], corners[(k + 1) % 3]
        length = math.hypot(bx - ax, by - ay)
        edges.append(((bx - ax) * (y - ay) - (by - ay) * (x - ax)) / length)
    return _smooth_min(edges, VOLE_ROUND)


def _vole_outline(x, y) -> float:
    """Inside of the vole molar's outline at (x, y): a band along x with a rounded loop at
    each end and :data:`VOLE_PRISMS` triangles pointing alternately to +y and -y, so the
    outline zigzags (salient angles) down both sides."""
    parts = [min(0.02 - abs(y), 0.13 - abs(x)),
             0.034 - math.hypot(x + 0.13, y), 0.03 - math.hypot(x - 0.13, y)]
    for k in range(VOLE_PRISMS):
        cx, sign = -0.1 + 0.05 * k, 1.0 if k % 2 == 0 else -1.0
        corners = [(cx - 0.035, -0.015 * sign), (cx + 0.035, -0.015 * sign), (cx, 0.06 * sign)]
        parts.append(_triangle(x, y, corners if sign > 0 else corners[::-1]))
    return _smooth_max(parts, 0.005)


def _vole_molar() -> BenchMesh:
    """A vole's molar (holdout 26; an arvicoline rodent's, ever-growing): a tall prism,
    curved back along its length, whose outline zigzags down both sides in alternating
    triangles (salient angles) between a rounded loop at each end, its flat occlusal
    surface's dentine basins framed by raised enamel rims along the outline (smooth
    intersections, manifold3d level set), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        shifted = x - 0.06 * (z / 0.22) ** 2  # the column curves back as it rises
        outline = _vole_outline(shifted, y)
        top = 0.22 - 0.012 * math.tanh(max(outline, 0.0) / 0.008)  # the enamel rims
        return _smooth_min([outline, top - z, z], 0.006)

    return vm._level_set_mesh(inside, [-0.19, -0.085, -0.02, 0.24, 0.085, 0.24], 0.004,
                              VOLE_H, SURFACE_CHECK)


# --------------------------------------------------------------------------- smooth


def _superformula(angle: float, m: float, n1: float, n2: float, n3: float) -> float:
    """Gielis's superformula with a = b = 1: ``(|cos(m a / 4)|^n2 + |sin(m a / 4)|^n3)
    ^(-1 / n1)``."""
    return (abs(math.cos(0.25 * m * angle)) ** n2
            + abs(math.sin(0.25 * m * angle)) ** n3) ** (-1.0 / n1)


def _supershape() -> BenchMesh:
    """A smooth supershape (holdout 26): a body whose radius is the product of two
    superformulas, one round the z axis (six rounded lobes round its waist, fading towards
    the poles, so it stays smooth there) and one from pole to pole (a broad shoulder above
    and below the waist), a radial height field remeshed with no feature kept."""

    def radius(ux, uy, uz):
        around = _superformula(math.atan2(uy, ux), 6.0, 1.0, 2.0, 6.0)
        up = _superformula(math.asin(max(-1.0, min(1.0, uz))), 4.0, 1.5, 2.0, 8.0)
        fade = (1.0 - uz * uz) ** 2
        return SUPERSHAPE_SIZE * (1.0 + fade * (around - 1.0)) * up

    return _radial_surface(radius, SUPERSHAPE_H, SURFACE_CHECK)


# --------------------------------------------------------------------------- brain-like


def _star_depth(t, p, _scale) -> float:
    """The triradiate sulci's depth (0 to 1) at chart point (t, p): ``1 / cosh`` of the
    distance in the chart (unscaled) to the nearest arm of the nearest star over
    :data:`STAR_WIDTH`; each star three straight arms of :data:`STAR_ARM` 120° apart from
    its centre, turned by its own angle, the arms' ends blind."""
    nearest = 10.0
    for (ct, cp), turn in STARS:
        if abs(t - ct) > STAR_ARM + 0.15 or abs(p - cp) > STAR_ARM + 0.15:
            continue
        for k in range(3):
            a = turn + 2.0 * math.pi * k / 3.0
            dt, dp = STAR_ARM * math.cos(a), STAR_ARM * math.sin(a)
            u = min(max(((t - ct) * dt + (p - cp) * dp) / (STAR_ARM * STAR_ARM), 0.0), 1.0)
            nearest = min(nearest, math.hypot(t - ct - u * dt, p - cp - u * dp))
    return 1.0 / math.cosh(nearest / STAR_WIDTH)


def _triradiate_cortex() -> BenchMesh:
    """A synthetic cortex with triradiate sulci (holdout 26; brain-like, not a brain): an
    ovoid long front to back, fuller at the back and flattened underneath, split over the
    top by a deep midline fissure into two halves; on each side separate three-armed
    star-shaped sulci in staggered rows, each turned its own way, no two joined. Made as a
    radial height field over an icosphere (so it cannot cross itself), then isotropically
    remeshed with no feature kept."""

    def radius(ux, uy, uz):
        lateral = 0.45 * (1.0 - 0.05 * uy)  # fuller at the back (-y)
        r = 1.0 / math.sqrt((ux / lateral) ** 2 + (uy / 0.75) ** 2 + (uz / 0.54) ** 2)
        r = _flattened_underneath(r, uz, 0.35)  # flattened underneath, blended
        depth = _star_depth(*_feather_chart(ux, uy, uz))
        depth = _with_midline_fissure(depth, ux, uz, STAR_FISSURE_WIDTH)
        return r - STAR_DEPTH * depth

    return _radial_surface(radius, STAR_H, SURFACE_CHECK)


def _stars() -> list:
    """The stars' centres in holdout 18's side chart (staggered rows, every other row half
    a step along) and their turns (the golden angle times their number, so no two alike)."""
    stars = []
    for row, p in enumerate((-0.3, 0.15, 0.6)):
        shift = 0.5 * STAR_STEP * (row % 2)
        for column in range(-2, 3):
            t = column * STAR_STEP + shift - 0.25 * STAR_STEP
            if abs(t) < 0.95:
                stars.append(((t, p), 2.39996 * len(stars)))
    return stars


BANANA_HEADINGS = (math.radians(-28.0), 0.0, math.radians(28.0))
BANANA_START, BANANA_BEND, BANANA_ARC, BANANA_RADIUS = 0.03, 0.3, 1.0, 0.034
TULIP_PETAL = 0.014
PALLET_BOARD, LADDER_RAIL, CHAIN_PLATE = 0.015, 0.012, 0.012
VOLE_PRISMS, VOLE_ROUND = 5, 0.006
SUPERSHAPE_SIZE = 0.24
# the stars in holdout 18's side chart: their step along a row, arm length, the sulci's
# width and depth
STAR_STEP, STAR_ARM = 0.55, 0.2
STARS = _stars()
STAR_WIDTH, STAR_DEPTH, STAR_FISSURE_WIDTH = 0.03, 0.06, 0.035
BANANA_H, TULIP_H, PALLET_H, LADDER_H, CHAIN_H, VOLE_H = 0.007, 0.005, 0.007, 0.005, 0.005, 0.005
SUPERSHAPE_H, STAR_H = 0.01, 0.016
# every remeshing passes PyMeshLab's surface-distance check (checksurfdist) explicitly: left
# to the filter, it is a leftover byte of the heap (validation_meshes._remesh; holdout 17)
SURFACE_CHECK = True


# A twenty-eighth set, made in session 49 after holdout 25 had been made: all six kinds,
# the brain kind by a synthetic cortex with triradiate sulci. No source is shared with the
# two halves, the first twenty-five holdouts, the tuning-side CAD parts, the smooth tuning
# set, the curved scans, the thin shells, scan_flatness_study.py's extra scans, animals.py,
# built_meshes.py, eggcrate.py, brain_probes.py, the λ-H families or session 32's
# tuning-side study parts; every parameter was fixed and the manifest committed before any
# fill was run on them. The scans are portable (the same bits on every CPU's BLAS).
HOLDOUT26_SOURCES: dict[str, Source] = {
    "scan_triradiate_cortex": Source("range_scan", "simulated scan of the synthetic cortex "
                                     "with triradiate sulci (portable scanner)", vm._scan(
                                         _triradiate_cortex, (-0.85, 0.35, 0.4), 215,
                                         portable=True)),
    "scan_vole_molar": Source("range_scan", "simulated scan of the vole molar (portable "
                              "scanner)", vm._scan(_vole_molar, (0.35, -0.5, 0.8), 216,
                                                   portable=True)),
    "scan_supershape": Source("range_scan", "simulated scan of the supershape (portable "
                              "scanner)", vm._scan(_supershape, (0.5, 0.6, 0.6), 217,
                                                   portable=True)),
    "scan_chain_link": Source("range_scan", "simulated scan of the drag chain link CAD part "
                              "(portable scanner)", vm._scan(_chain_link, (0.3, -0.9, 0.3),
                                                             218, portable=True)),
    "banana_hand": Source("organic", "hand of three bananas, curved five-ridged fruits "
                          "fanning out from a common crown, blunt tips, short thick stalk "
                          "(level set), remeshed", _banana_hand),
    "tulip": Source("organic", "tulip, cup of six thin petals open at the top with pointed "
                    "tips, long curved stem, two long flat leaves (level set), remeshed",
                    _tulip),
    "pallet": Source("cad", "manifold3d: block pallet, five thin top deck boards on three "
                     "stringer boards, nine blocks, three bottom deck boards", _pallet),
    "ladder": Source("cad", "manifold3d: short ladder, two thin flat rails joined by five "
                     "round rungs", _ladder),
    "chain_link": Source("cad", "manifold3d: cable drag chain link, two thin side plates "
                         "with rounded ends and pivot holes, crossbars top and bottom",
                         _chain_link),
    "vole_molar": Source("teeth", "vole molar, tall curved prism, outline zigzagging in "
                         "alternating triangles, end loops, enamel rims round dentine "
                         "basins (level set)", _vole_molar),
    "supershape": Source("smooth", "supershape, radius the product of two superformulas, six "
                         "rounded lobes round its waist fading towards the poles, a broad "
                         "shoulder above and below the waist (radial height field), "
                         "remeshed", _supershape),
    "triradiate_cortex": Source("brain", "synthetic cortex, ovoid split by a deep midline "
                                "fissure, on each side separate three-armed star-shaped "
                                "sulci in staggered rows, none joined (radial height "
                                "field), remeshed", _triradiate_cortex),
}
