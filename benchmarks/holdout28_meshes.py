"""Holdout set 28's meshes (session 51): 12 fresh meshes, made and committed before any fill.

As holdouts 8 to 27's (``holdout8_meshes.py`` .. ``holdout27_meshes.py``): kept out of
:mod:`validation_meshes`, which imports :data:`HOLDOUT28_SOURCES` from here after holdout
27's and adds them to its ``SOURCES``, so every benchmark reaches these meshes through it
(``validation_meshes.load("walnut")``). The generators use its helpers (level sets,
manifold3d remeshing), holdout 11's level-set and radial-surface helpers, holdout 12's
ellipsoid, holdout 14's smooth minimum and flattened underside, holdout 17's midline
fissure and holdout 18's side chart and straight-sulcus depth; the four range scans are the
portable scanner's (``simulated_scan(..., portable=True)``: the same bits under every BLAS
kernel). Import :mod:`validation_meshes` first, not this module (an import cycle
otherwise).

All six kinds, as holdouts 11 to 27: 4 simulated range scans of 4 of the others, 2 organic
shapes, 3 CAD parts, 1 tooth, 1 smooth surface and 1 brain-like surface (a synthetic
cortex whose sulci are separate chevrons, between two halves split by a deep midline
fissure; not a real brain) (``benchmarks/holdout28_manifest.json``, docs/validation.md
"Holdout set 28"). Their thickness is mixed on purpose: the ginkgo leaf's blade and the
propeller's blades are about 2 to 3 edges thick; the others are solid.

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
from holdout18_meshes import _feather_chart, _feather_depth
from validation_meshes import BenchMesh, Source

# --------------------------------------------------------------------------- organic


def _walnut() -> BenchMesh:
    """A walnut in its shell (holdout 28): an ovoid a little pointed at its top, a raised
    seam round it where the two halves of the shell meet, and shallow irregular wrinkles
    over both halves (manifold3d level set), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        taper = 1.0 - 0.12 * max(z, 0.0) / 0.11  # narrower towards the pointed top
        body = _ellipsoid(x / taper, y / taper, z, (0.0, 0.0, 0.0), (0.095, 0.085, 0.11))
        seam = WALNUT_SEAM / math.cosh(x / 0.005)
        wrinkles = WALNUT_WRINKLE * (math.sin(93.0 * y + 37.0 * z) * math.sin(81.0 * z - 26.0 * x)
                                     + 0.6 * math.sin(120.0 * z + 58.0 * y - 34.0 * x))
        return body + seam + wrinkles * (1.0 - 1.0 / math.cosh(x / 0.012))

    return vm._level_set_mesh(inside, [-0.12, -0.11, -0.13, 0.12, 0.11, 0.13], 0.003,
                              WALNUT_H, SURFACE_CHECK)


def _ginkgo_leaf() -> BenchMesh:
    """A ginkgo leaf (holdout 28): a thin fan-shaped blade, its outer edge wavy and notched
    in the middle (two lobes), a little cupped, on a thin stalk (smooth union, manifold3d
    level set), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        r = math.hypot(x, y)
        phi = math.atan2(x, y)  # 0 straight up the stalk's line, the fan spreading to ±65°
        edge = 0.16 + 0.005 * math.cos(14.0 * phi) - 0.045 / math.cosh(phi / 0.07)
        sides = r * math.sin(min(GINKGO_SPREAD - abs(phi), 0.5 * math.pi))
        outline = _smooth_min([edge - r, sides], 0.006)
        middle = 0.4 * r * r  # cupped
        blade = _smooth_min([outline, 0.5 * GINKGO_BLADE - abs(z - middle)], 0.003)
        stalk = _capsule(x, y, z, (0.0, -0.11, 0.0), (0.0, 0.015, 0.0), 0.0045, 0.004)
        return _smooth_max([blade, stalk], 0.004)

    return vm._level_set_mesh(inside, [-0.17, -0.125, -0.02, 0.17, 0.18, 0.035], 0.002,
                              GINKGO_H, SURFACE_CHECK)


# --------------------------------------------------------------------------- CAD


def _propeller() -> BenchMesh:
    """A three-bladed boat propeller (holdout 28): a hub with a bore and a keyway, its
    front end chamfered, three thin flat blades of rounded outline set at a pitch
    (manifold3d outlines, extrusion and booleans)."""
    import manifold3d as m3

    profile = [(0.0, -0.04), (0.04, -0.04), (0.04, 0.03), (0.028, 0.05), (0.0, 0.05)]
    hub = m3.Manifold.revolve(m3.CrossSection([profile]), 64)  # the nose chamfered
    outline = []
    for k in range(80):  # the blade's outline, root (x = 0.03) to tip (x = 0.2), skewed
        a = 2.0 * math.pi * k / 80
        outline.append((0.115 - 0.085 * math.cos(a),
                        -0.04 * math.sin(a) + 0.008 * (1.0 - math.cos(a))))  # anticlockwise
    blade = m3.Manifold.extrude(m3.CrossSection([outline]), PROPELLER_BLADE)
    blade = blade.translate((0.0, 0.0, -0.5 * PROPELLER_BLADE))
    blade = blade.rotate((PROPELLER_PITCH, 0.0, 0.0))  # the chord tilted about the radius
    blades = [blade.rotate((0.0, 0.0, 120.0 * k)) for k in range(3)]
    part = m3.Manifold.batch_boolean([hub] + blades, m3.OpType.Add)
    bore = m3.Manifold.cylinder(0.2, 0.011, 0.011, 48, True)
    key = m3.Manifold.cube((0.008, 0.01, 0.2), True).translate((0.0, 0.013, 0.0))
    part = part - bore - key
    return vm._manifold_mesh(part, PROPELLER_H, refine=0.03, surface_check=SURFACE_CHECK)


def _tensile_specimen() -> BenchMesh:
    """A flat dog-bone tensile specimen (holdout 28): two wide grips joined by a narrower
    gauge length, the shoulders filleted, a pin hole through each grip (manifold3d outline,
    extrusion and booleans)."""
    import manifold3d as m3

    gauge = m3.CrossSection.square((0.24, 0.04), True)
    grips = [m3.CrossSection.square((0.1, 0.08), True).translate((side * 0.15, 0.0))
             for side in (-1.0, 1.0)]
    outline = m3.CrossSection.batch_boolean([gauge] + grips, m3.OpType.Add)
    outline = outline.offset(0.03, m3.JoinType.Round, 2.0, 64).offset(
        -0.03, m3.JoinType.Round, 2.0, 64)  # a closing: the shoulders filleted
    for side in (-1.0, 1.0):
        outline = outline - m3.CrossSection.circle(0.012, 40).translate((side * 0.16, 0.0))
    part = m3.Manifold.extrude(outline, SPECIMEN_THICKNESS)
    return vm._manifold_mesh(part, SPECIMEN_H, refine=0.03, surface_check=SURFACE_CHECK)


def _splined_shaft() -> BenchMesh:
    """A splined shaft (holdout 28): eight straight splines along its middle, a plain
    journal at each end, chamfered, a cross hole through one journal (manifold3d outlines,
    extrusion and booleans)."""
    import manifold3d as m3

    section = m3.CrossSection.circle(0.068, 96)
    for k in range(8):
        tooth = m3.CrossSection.square((0.028, 0.02), True).translate((0.074, 0.0))
        section = section + tooth.rotate(45.0 * k)
    splines = m3.Manifold.extrude(section, 0.24).translate((0.0, 0.0, 0.12))
    profile = [(0.0, -0.008), (0.042, -0.008), (0.05, 0.0), (0.05, 0.5), (0.042, 0.508),
               (0.0, 0.508)]
    core = m3.Manifold.revolve(m3.CrossSection([profile]), 96)  # both journals, chamfered
    hole = m3.Manifold.cylinder(0.2, 0.009, 0.009, 40, True).rotate((90.0, 0.0, 0.0))
    part = splines + core - hole.translate((0.0, 0.0, 0.44))
    return vm._manifold_mesh(part, SHAFT_H, refine=0.03, surface_check=SURFACE_CHECK)


# --------------------------------------------------------------------------- teeth


def _labyrinthodont_tooth() -> BenchMesh:
    """A labyrinthodont's tooth (holdout 28): a tall cone bent a little backwards, its
    lower part fluted by many shallow folds that fade towards the blunt tip, on a short
    root (smooth unions, manifold3d level set), isotropically remeshed with no feature
    kept."""

    def inside(x, y, z):
        u = min(max(z / TOOTH_HEIGHT, 0.0), 1.0)
        bx = x + 0.06 * u * u  # bent backwards (towards -x) as it rises
        radius = TOOTH_RADIUS * (1.0 - 0.92 * u)
        folds = 1.0 + TOOTH_FOLD * (1.0 - u) * math.cos(TOOTH_FOLDS * math.atan2(y, bx))
        crown = _smooth_min([radius * folds - math.hypot(bx, y), TOOTH_HEIGHT - z, z + 0.01],
                            0.008)
        root = _capsule(x, y, z, (0.0, 0.0, 0.02), (0.0, 0.0, -0.1), 0.07, 0.035)
        return _smooth_max([crown, root], 0.01)

    return vm._level_set_mesh(inside, [-0.11, -0.1, -0.15, 0.1, 0.1, 0.38], 0.003,
                              TOOTH_H, SURFACE_CHECK)


# --------------------------------------------------------------------------- smooth


def _hourglass() -> BenchMesh:
    """An hourglass solid (holdout 28): a solid of revolution whose radius grows with the
    square of the height from a narrow waist, its two ends flat with rounded rims (smooth
    intersection, manifold3d level set), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        radius = HOURGLASS_WAIST + 1.6 * z * z
        return _smooth_min([radius - math.hypot(x, y), HOURGLASS_HALF - abs(z)], 0.03)

    return vm._level_set_mesh(inside, [-0.17, -0.17, -0.27, 0.17, 0.17, 0.27], 0.004,
                              HOURGLASS_H, SURFACE_CHECK)


# --------------------------------------------------------------------------- brain-like


def _chevron_segments() -> list:
    """The chevron sulci as chart segments ((t0, p0), (t1, p1), free start, free end) of
    :func:`_feather_chart`: at each corner of :data:`CHEVRONS` two straight arms
    :data:`CHEVRON_ARM` long meeting at the corner (no fade there) and spreading
    :data:`CHEVRON_SPREAD` to either side of the way the chevron points, each ending
    blind."""
    segments = []
    for t, p, heading in CHEVRONS:
        for side in (-1.0, 1.0):
            angle = heading + math.pi + side * CHEVRON_SPREAD  # the arms trail behind
            end = (t + CHEVRON_ARM * math.cos(angle), p + CHEVRON_ARM * math.sin(angle))
            segments.append(((t, p), end, False, True))
    return segments


def _chevron_cortex() -> BenchMesh:
    """A synthetic cortex with chevron sulci (holdout 28; brain-like, not a brain): an
    ovoid long front to back, fuller at the front and flattened underneath, split over the
    top by a deep midline fissure into two halves; on each side separate V-shaped sulci in
    staggered rows, each two straight arms meeting at a sharp corner and ending blind, the
    rows pointing front and back in turn, none joined. Made as a radial height field over an
    icosphere (so it cannot cross itself), then isotropically remeshed with no feature
    kept."""

    def radius(ux, uy, uz):
        lateral = 0.47 * (1.0 + 0.05 * uy)  # fuller at the front (+y)
        r = 1.0 / math.sqrt((ux / lateral) ** 2 + (uy / 0.76) ** 2 + (uz / 0.54) ** 2)
        r = _flattened_underneath(r, uz, 0.37)  # flattened underneath, blended
        t, p, scale = _feather_chart(ux, uy, uz)
        depth = _feather_depth(t, p, scale, CHEVRON_SEGMENTS)
        depth = _with_midline_fissure(depth, ux, uz, CHEVRON_FISSURE_WIDTH)
        return r - CHEVRON_DEPTH * depth

    return _radial_surface(radius, CHEVRON_H, SURFACE_CHECK)


WALNUT_SEAM, WALNUT_WRINKLE = 0.006, 0.0035
GINKGO_BLADE, GINKGO_SPREAD = 0.01, math.radians(65.0)
PROPELLER_BLADE, PROPELLER_PITCH = 0.01, 35.0
SPECIMEN_THICKNESS = 0.02
TOOTH_HEIGHT, TOOTH_RADIUS, TOOTH_FOLD, TOOTH_FOLDS = 0.34, 0.07, 0.07, 20
HOURGLASS_WAIST, HOURGLASS_HALF = 0.05, 0.25
# the chevrons' corners in holdout 18's side chart (t, p, the way each points) in three
# staggered rows, pointing front (0) and back (π) in turn
CHEVRONS = ((-0.55, -0.4, 0.0), (0.25, -0.4, 0.0), (0.95, -0.4, 0.0),
            (-0.75, 0.18, math.pi), (0.05, 0.18, math.pi), (0.85, 0.18, math.pi),
            (-0.4, 0.76, 0.0), (0.4, 0.76, 0.0))
CHEVRON_ARM, CHEVRON_SPREAD = 0.36, math.radians(28.0)
CHEVRON_SEGMENTS = _chevron_segments()
CHEVRON_DEPTH, CHEVRON_FISSURE_WIDTH = 0.06, 0.035
WALNUT_H, GINKGO_H, PROPELLER_H, SPECIMEN_H, SHAFT_H, TOOTH_H = (
    0.005, 0.004, 0.005, 0.005, 0.006, 0.005)
HOURGLASS_H, CHEVRON_H = 0.008, 0.016
# every remeshing passes PyMeshLab's surface-distance check (checksurfdist) explicitly: left
# to the filter, it is a leftover byte of the heap (validation_meshes._remesh; holdout 17)
SURFACE_CHECK = True


# A thirtieth set, made in session 51 after holdout 27 had been made: all six kinds, the
# brain kind by a synthetic cortex with chevron sulci. No source is shared with the two
# halves, the first twenty-seven holdouts, the tuning-side CAD parts, the smooth tuning
# set, the curved scans, the thin shells, scan_flatness_study.py's extra scans, animals.py,
# built_meshes.py, eggcrate.py, brain_probes.py, the λ-H families or session 32's
# tuning-side study parts; every parameter was fixed and the manifest committed before any
# fill was run on them. The scans are portable (the same bits on every CPU's BLAS).
HOLDOUT28_SOURCES: dict[str, Source] = {
    "scan_chevron_cortex": Source("range_scan", "simulated scan of the synthetic cortex with "
                                  "chevron sulci (portable scanner)", vm._scan(
                                      _chevron_cortex, (-0.8, 0.35, 0.5), 223, portable=True)),
    "scan_labyrinthodont_tooth": Source("range_scan", "simulated scan of the labyrinthodont "
                                        "tooth (portable scanner)", vm._scan(
                                            _labyrinthodont_tooth, (0.7, -0.6, 0.3), 224,
                                            portable=True)),
    "scan_walnut": Source("range_scan", "simulated scan of the walnut (portable scanner)",
                          vm._scan(_walnut, (0.5, 0.6, 0.6), 225, portable=True)),
    "scan_hourglass": Source("range_scan", "simulated scan of the hourglass solid (portable "
                             "scanner)", vm._scan(_hourglass, (0.7, 0.5, 0.4), 226,
                                                  portable=True)),
    "walnut": Source("organic", "walnut in its shell, ovoid pointed at the top, raised seam "
                     "between the two halves, shallow irregular wrinkles (level set), "
                     "remeshed", _walnut),
    "ginkgo_leaf": Source("organic", "ginkgo leaf, thin fan-shaped blade with a wavy outer "
                          "edge notched into two lobes, slightly cupped, on a thin stalk "
                          "(level set), remeshed", _ginkgo_leaf),
    "propeller": Source("cad", "manifold3d: three-bladed boat propeller, hub with a bore and "
                        "a keyway, chamfered nose, thin flat pitched blades", _propeller),
    "tensile_specimen": Source("cad", "manifold3d: flat dog-bone tensile specimen, two grips "
                               "and a narrower gauge length, filleted shoulders, a pin hole "
                               "in each grip", _tensile_specimen),
    "splined_shaft": Source("cad", "manifold3d: splined shaft, eight straight splines along "
                            "its middle, chamfered journals at both ends, a cross hole",
                            _splined_shaft),
    "labyrinthodont_tooth": Source("teeth", "labyrinthodont tooth, tall cone bent backwards, "
                                   "its lower part fluted by many folds fading towards the "
                                   "blunt tip, short root (level set)",
                                   _labyrinthodont_tooth),
    "hourglass": Source("smooth", "hourglass solid of revolution, narrow waist widening "
                        "with the square of the height, flat ends with rounded rims (level "
                        "set), remeshed", _hourglass),
    "chevron_cortex": Source("brain", "synthetic cortex, ovoid split by a deep midline "
                             "fissure, on each side separate V-shaped sulci in staggered rows "
                             "pointing front and back in turn, none joined (radial height "
                             "field), remeshed", _chevron_cortex),
}
