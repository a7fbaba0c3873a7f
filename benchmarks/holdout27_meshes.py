"""Holdout set 27's meshes (session 50): 12 fresh meshes, made and committed before any fill.

As holdouts 8 to 26's (``holdout8_meshes.py`` .. ``holdout26_meshes.py``): kept out of
:mod:`validation_meshes`, which imports :data:`HOLDOUT27_SOURCES` from here after holdout
26's and adds them to its ``SOURCES``, so every benchmark reaches these meshes through it
(``validation_meshes.load("samara")``). The generators use its helpers (level sets,
manifold3d remeshing), holdout 11's level-set and radial-surface helpers, holdout 12's
ellipsoid, holdout 14's smooth minimum and flattened underside, holdout 17's midline
fissure, holdout 18's side chart and holdout 25's flat wing; the four range scans are the
portable scanner's (``simulated_scan(..., portable=True)``: the same bits under every BLAS
kernel). Import :mod:`validation_meshes` first, not this module (an import cycle
otherwise).

All six kinds, as holdouts 11 to 26: 4 simulated range scans of 4 of the others, 2 organic
shapes, 3 CAD parts, 1 tooth, 1 smooth surface and 1 brain-like surface (a synthetic
cortex whose sulci are separate three-petalled roses, between two halves split by a deep
midline fissure; not a real brain) (``benchmarks/holdout27_manifest.json``,
docs/validation.md "Holdout set 27"). Their thickness is mixed on purpose: the samara's
wings, the truss's bars and the saw blade's disc are about 2 to 3 edges thick; the others
are solid.

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
from holdout25_meshes import _wing
from validation_meshes import BenchMesh, Source

# --------------------------------------------------------------------------- organic


def _coral_branches() -> list:
    """The staghorn coral's branches as tapered capsules (start, end, radius at the start,
    radius at the end): a short trunk, three limbs leaning out from its top, each forking
    twice more into blunt tips, every fork turned its own way."""
    branches = [((0.0, 0.0, -0.01), (0.0, 0.0, 0.1), 0.042, 0.036)]
    for k in range(3):
        heading = math.radians(120.0 * k + 15.0)
        tip = _coral_fork(branches, (0.0, 0.0, 0.1), heading, 38.0, 0.13, 0.033, 0.026)
        for side, length in ((-1.0, 0.12), (1.0, 0.1)):
            end = _coral_fork(branches, tip, heading + side * math.radians(32.0),
                              38.0 + 12.0 * side, length, 0.024, 0.02)
            if side > 0.0:  # the shorter fork splits once more
                for turn in (-1.0, 1.0):
                    _coral_fork(branches, end, heading + math.radians(32.0 + 30.0 * turn),
                                26.0, 0.07, 0.018, 0.014)
    return branches


def _coral_fork(branches: list, start, heading: float, lean_deg: float, length: float,
                r_start: float, r_end: float):
    """Append a branch from ``start`` leaning ``lean_deg`` from the vertical towards ``heading``
    and return its end."""
    lean = math.radians(lean_deg)
    end = (start[0] + length * math.sin(lean) * math.cos(heading),
           start[1] + length * math.sin(lean) * math.sin(heading),
           start[2] + length * math.cos(lean))
    branches.append((start, end, r_start, r_end))
    return end


def _staghorn_coral() -> BenchMesh:
    """A staghorn coral colony (holdout 27): a trunk cut flat at its foot, forking into
    tapered round branches with blunt tips, each ringed by low bumps (the corallites)
    (smooth unions, manifold3d level set), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        parts = []
        for a, b, r_a, r_b in CORAL_BRANCHES:
            parts.append(_capsule(x, y, z, a, b, r_a, r_b))
        body = _smooth_max(parts, 0.012)
        bumps = 0.003 * math.sin(80.0 * x) * math.sin(80.0 * y) * math.sin(80.0 * z)
        return _smooth_min([body + bumps, z], 0.004)

    return vm._level_set_mesh(inside, [-0.3, -0.3, -0.02, 0.3, 0.3, 0.42], 0.004,
                              CORAL_H, SURFACE_CHECK)


def _samara() -> BenchMesh:
    """A maple's double samara (holdout 27): two plump seeds joined at their base under a
    thin stalk, each with a long flat wing (holdout 25's thin wing) spreading from it in a
    V, wider towards its rounded tip, with a thickened vein along its leading edge (smooth
    unions, manifold3d level set), isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        parts = [_capsule(x, y, z, (0.0, 0.012, 0.0), (0.0, 0.075, 0.004), 0.008, 0.007)]
        for side in (-1.0, 1.0):
            parts.append(_ellipsoid(x, y, z, (side * 0.033, -0.01, 0.0), (0.04, 0.032, 0.026)))
            parts.append(_wing(x, y, z, (side * 0.05, -0.02, 0.0),
                               (side * 0.2, -0.17, 0.0), 0.022, 0.045))
            parts.append(_capsule(x, y, z, (side * 0.05, -0.005, 0.0),
                                  (side * 0.235, -0.15, 0.0), 0.011, 0.007))  # the vein
        return _smooth_max(parts, 0.005)

    return vm._level_set_mesh(inside, [-0.27, -0.24, -0.04, 0.27, 0.09, 0.04], 0.003,
                              SAMARA_H, SURFACE_CHECK)


# --------------------------------------------------------------------------- CAD


def _gear_rack() -> BenchMesh:
    """A straight gear rack (holdout 27): a bar with straight-sided teeth (20° flanks, flat
    tops and roots) along its top, its bottom edges chamfered, two counterbored mounting
    holes through its side (manifold3d outline, extrusion and booleans)."""
    import manifold3d as m3

    pitch, tan20 = math.pi * RACK_MODULE, math.tan(math.radians(20.0))
    root, top = 0.06, 0.06 + 2.25 * RACK_MODULE
    outline = [(-0.25, 0.012), (-0.238, 0.0), (0.238, 0.0), (0.25, 0.012), (0.25, root)]
    for k in range(RACK_TEETH - 1, -1, -1):  # from +x to -x, so the outline turns anticlockwise
        centre = -0.5 * (RACK_TEETH - 1) * pitch + k * pitch
        half_top = 0.25 * pitch - RACK_MODULE * tan20
        half_root = 0.25 * pitch + 1.25 * RACK_MODULE * tan20
        outline += [(centre + half_root, root), (centre + half_top, top),
                    (centre - half_top, top), (centre - half_root, root)]
    outline.append((-0.25, root))
    bar = m3.Manifold.extrude(m3.CrossSection([outline]), 0.06).rotate((90.0, 0.0, 0.0))
    bar = bar.translate((0.0, 0.03, 0.0))  # the face width along y, centred
    for x in (-0.15, 0.15):
        bore = m3.Manifold.cylinder(0.1, 0.009, 0.009, 48, True)
        counterbore = m3.Manifold.cylinder(0.024, 0.016, 0.016, 48, True)
        for tool in (bore, counterbore.translate((0.0, 0.0, 0.03))):
            bar = bar - tool.rotate((90.0, 0.0, 0.0)).translate((x, 0.0, 0.03))
    return vm._manifold_mesh(bar, RACK_H, refine=0.03, surface_check=SURFACE_CHECK)


def _warren_truss() -> BenchMesh:
    """A flat Warren truss (holdout 27): top and bottom chords and end posts joined by
    diagonals in a zigzag, thin bars round triangular openings whose corners are filleted,
    a pin hole through each bottom corner (manifold3d outlines, extrusion and booleans)."""
    import manifold3d as m3

    def bar(a, b, width):
        length = math.hypot(b[0] - a[0], b[1] - a[1])
        angle = math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]))
        piece = m3.CrossSection.square((length + width, width), True).rotate(angle)
        return piece.translate((0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])))

    span, height, panels = 0.6, 0.15, 5
    frame = [bar((-0.5 * span, 0.0), (0.5 * span, 0.0), 0.034),
             bar((-0.5 * span, height), (0.5 * span, height), 0.026)]
    frame += [bar((s * 0.5 * span, 0.0), (s * 0.5 * span, height), 0.026) for s in (-1, 1)]
    for k in range(panels):
        x0, x1 = -0.5 * span + k * span / panels, -0.5 * span + (k + 1) * span / panels
        low, high = ((x0, 0.0), (x1, height)) if k % 2 == 0 else ((x1, 0.0), (x0, height))
        frame.append(bar(low, high, 0.02))
    outline = m3.CrossSection.batch_boolean(frame, m3.OpType.Add)
    outline = outline.offset(0.012, m3.JoinType.Round, 2.0, 48).offset(
        -0.012, m3.JoinType.Round, 2.0, 48)  # a closing: the openings' corners filleted
    pin = m3.CrossSection.circle(0.006, 40)
    outline = outline - pin.translate((-0.5 * span, 0.0)) - pin.translate((0.5 * span, 0.0))
    truss = m3.Manifold.extrude(outline, TRUSS_BAR).translate((0.0, 0.0, -0.5 * TRUSS_BAR))
    truss = truss.rotate((90.0, 0.0, 0.0))
    return vm._manifold_mesh(truss, TRUSS_H, refine=0.03, surface_check=SURFACE_CHECK)


def _saw_blade() -> BenchMesh:
    """A circular saw blade (holdout 27): a thin flat disc whose rim is cut into hooked
    teeth with sharp tips, an arbor hole, four expansion slots in from the gullets ending
    in round holes, and two pin holes (manifold3d outline, extrusion and booleans)."""
    import manifold3d as m3

    pitch = 2.0 * math.pi / SAW_TEETH
    outline = []
    for k in range(SAW_TEETH):
        a = k * pitch
        for radius, turn in ((0.178, 0.0), (0.2, 0.1), (0.183, 0.82)):
            outline.append((radius * math.cos(a + turn * pitch),
                            radius * math.sin(a + turn * pitch)))
    disc = m3.CrossSection([outline]) - m3.CrossSection.circle(0.025, 64)
    for k in range(4):
        a = 6 * k * pitch  # at a gullet's bottom, so the slot opens into it
        slot = m3.CrossSection.square((0.055, 0.008), True).translate((0.1575, 0.0))
        end = m3.CrossSection.circle(0.009, 32).translate((0.13, 0.0))
        disc = disc - (slot + end).rotate(math.degrees(a))
    for a in (math.radians(45.0), math.radians(225.0)):
        disc = disc - m3.CrossSection.circle(0.006, 32).translate((0.045 * math.cos(a),
                                                                   0.045 * math.sin(a)))
    blade = m3.Manifold.extrude(disc, SAW_DISC).translate((0.0, 0.0, -0.5 * SAW_DISC))
    return vm._manifold_mesh(blade, SAW_H, refine=0.03, surface_check=SURFACE_CHECK)


# --------------------------------------------------------------------------- teeth


def _desmostylian_molar() -> BenchMesh:
    """A desmostylian's molar (holdout 27; Desmostylus's, a bundle of columns): eight tall
    round columns in two rows of four, pressed together along their length (grooves
    between them), each worn flat on top to an enamel ring round a dentine pit, unevenly
    high, on a neck and two short roots (smooth unions, manifold3d level set), isotropically
    remeshed with no feature kept."""

    def inside(x, y, z):
        parts = [_capsule(x, y, z, (side * 0.075, 0.0, 0.0), (side * 0.095, 0.0, -0.12),
                          0.036, 0.012) for side in (-1.0, 1.0)]  # the roots
        parts.append(_ellipsoid(x, y, z, (0.0, 0.0, 0.0), (0.15, 0.075, 0.03)))  # the neck
        for k, (cx, cy) in enumerate(DESMO_COLUMNS):
            d = DESMO_RADIUS * (1.0 - 0.15 * z / 0.2) - math.hypot(x - cx, y - cy)
            worn = DESMO_TOP[k] - 0.01 * math.tanh(max(d, 0.0) / 0.01)  # rim round a pit
            parts.append(_smooth_min([d, worn - z, z + 0.01], 0.006))
        return _smooth_max(parts, 0.008)

    return vm._level_set_mesh(inside, [-0.17, -0.1, -0.15, 0.17, 0.1, 0.22], 0.004,
                              DESMO_H, SURFACE_CHECK)


# --------------------------------------------------------------------------- smooth


def _twisted_prism() -> BenchMesh:
    """A twisted prism (holdout 27): a straight column whose section is a smooth
    five-pointed star (radius ``R (1 + 0.3 cos 5φ)``), turning half a turn about its axis
    from bottom to top, its ends rounded (smooth intersection, manifold3d level set),
    isotropically remeshed with no feature kept."""

    def inside(x, y, z):
        turn = math.pi * z / PRISM_HEIGHT  # half a turn over the height
        phi = math.atan2(y, x) - turn
        section = PRISM_RADIUS * (1.0 + 0.3 * math.cos(5.0 * phi)) - math.hypot(x, y)
        return _smooth_min([section, 0.5 * PRISM_HEIGHT - abs(z)], 0.02)

    return vm._level_set_mesh(inside, [-0.22, -0.22, -0.3, 0.22, 0.22, 0.3], 0.004,
                              PRISM_H, SURFACE_CHECK)


# --------------------------------------------------------------------------- brain-like


def _rose_points(centre, turn: float) -> list:
    """Points along one three-petalled rose (``r = ROSE_PETAL cos 3θ``) in the side chart,
    turned by ``turn``, as a closed polyline."""
    points = []
    for k in range(ROSE_SAMPLES + 1):
        theta = math.pi * k / ROSE_SAMPLES  # r = cos 3θ closes after half a turn
        r = ROSE_PETAL * math.cos(3.0 * theta)
        points.append((centre[0] + r * math.cos(theta + turn),
                       centre[1] + r * math.sin(theta + turn)))
    return points


def _rose_depth(t, p, _scale) -> float:
    """The rose sulci's depth (0 to 1) at chart point (t, p): ``1 / cosh`` of the distance
    in the chart (unscaled) to the nearest rose's curve over :data:`ROSE_WIDTH`."""
    nearest = 10.0
    for (ct, cp), points in ROSES:
        if abs(t - ct) > ROSE_PETAL + 0.15 or abs(p - cp) > ROSE_PETAL + 0.15:
            continue
        for (at, ap), (bt, bp) in zip(points[:-1], points[1:], strict=True):
            dt, dp = bt - at, bp - ap
            length2 = dt * dt + dp * dp
            u = 0.0 if length2 == 0.0 else min(max(((t - at) * dt + (p - ap) * dp) / length2,
                                                   0.0), 1.0)
            nearest = min(nearest, math.hypot(t - at - u * dt, p - ap - u * dp))
    return 1.0 / math.cosh(nearest / ROSE_WIDTH)


def _rose_cortex() -> BenchMesh:
    """A synthetic cortex with rose-shaped sulci (holdout 27; brain-like, not a brain): an
    ovoid long front to back, fuller at the front and flattened underneath, split over the
    top by a deep midline fissure into two halves; on each side separate sulci each along a
    three-petalled rose (three closed loops through one centre, each round a small gyrus),
    in two staggered rows, each turned its own way, no two joined. Made as a radial height
    field over an icosphere (so it cannot cross itself), then isotropically remeshed with no
    feature kept."""

    def radius(ux, uy, uz):
        lateral = 0.46 * (1.0 + 0.04 * uy)  # fuller at the front (+y)
        r = 1.0 / math.sqrt((ux / lateral) ** 2 + (uy / 0.74) ** 2 + (uz / 0.55) ** 2)
        r = _flattened_underneath(r, uz, 0.36)  # flattened underneath, blended
        depth = _rose_depth(*_feather_chart(ux, uy, uz))
        depth = _with_midline_fissure(depth, ux, uz, ROSE_FISSURE_WIDTH)
        return r - ROSE_DEPTH * depth

    return _radial_surface(radius, ROSE_H, SURFACE_CHECK)


def _roses() -> list:
    """The roses' centres in holdout 18's side chart (two staggered rows) and their
    polylines, each turned by the golden angle times its number (so no two alike)."""
    roses = []
    for p, columns in ((-0.2, (-0.75, 0.0, 0.75)), (0.55, (-0.375, 0.375))):
        for t in columns:
            turn = 2.39996 * len(roses)
            roses.append(((t, p), _rose_points((t, p), turn)))
    return roses


CORAL_BRANCHES = _coral_branches()
RACK_MODULE, RACK_TEETH = 0.016, 9
TRUSS_BAR, SAW_DISC, SAW_TEETH = 0.012, 0.012, 24
DESMO_RADIUS = 0.036
DESMO_COLUMNS = tuple((x, y) for y in (-0.03, 0.03) for x in (-0.099, -0.033, 0.033, 0.099))
DESMO_TOP = (0.19, 0.2, 0.205, 0.195, 0.185, 0.2, 0.198, 0.188)
PRISM_RADIUS, PRISM_HEIGHT = 0.15, 0.5
# the roses in holdout 18's side chart: petal length, samples along a rose, the sulci's
# width and depth
ROSE_PETAL, ROSE_SAMPLES = 0.3, 90
ROSES = _roses()
ROSE_WIDTH, ROSE_DEPTH, ROSE_FISSURE_WIDTH = 0.028, 0.06, 0.035
CORAL_H, SAMARA_H, RACK_H, TRUSS_H, SAW_H, DESMO_H = 0.006, 0.005, 0.006, 0.005, 0.005, 0.005
PRISM_H, ROSE_H = 0.008, 0.016
# every remeshing passes PyMeshLab's surface-distance check (checksurfdist) explicitly: left
# to the filter, it is a leftover byte of the heap (validation_meshes._remesh; holdout 17)
SURFACE_CHECK = True


# A twenty-ninth set, made in session 50 after holdout 26 had been made: all six kinds,
# the brain kind by a synthetic cortex with rose-shaped sulci. No source is shared with the
# two halves, the first twenty-six holdouts, the tuning-side CAD parts, the smooth tuning
# set, the curved scans, the thin shells, scan_flatness_study.py's extra scans, animals.py,
# built_meshes.py, eggcrate.py, brain_probes.py, the λ-H families or session 32's
# tuning-side study parts; every parameter was fixed and the manifest committed before any
# fill was run on them. The scans are portable (the same bits on every CPU's BLAS).
HOLDOUT27_SOURCES: dict[str, Source] = {
    "scan_rose_cortex": Source("range_scan", "simulated scan of the synthetic cortex with "
                               "rose-shaped sulci (portable scanner)", vm._scan(
                                   _rose_cortex, (0.85, -0.3, 0.45), 219, portable=True)),
    "scan_desmostylian_molar": Source("range_scan", "simulated scan of the desmostylian "
                                      "molar (portable scanner)", vm._scan(
                                          _desmostylian_molar, (-0.4, 0.5, 0.8), 220,
                                          portable=True)),
    "scan_staghorn_coral": Source("range_scan", "simulated scan of the staghorn coral "
                                  "(portable scanner)", vm._scan(
                                      _staghorn_coral, (0.6, -0.7, 0.4), 221, portable=True)),
    "scan_saw_blade": Source("range_scan", "simulated scan of the saw blade CAD part "
                             "(portable scanner)", vm._scan(_saw_blade, (0.25, -0.35, 0.9),
                                                            222, portable=True)),
    "staghorn_coral": Source("organic", "staghorn coral, flat-footed trunk forking into "
                             "tapered round branches with blunt tips, low corallite bumps "
                             "(level set), remeshed", _staghorn_coral),
    "samara": Source("organic", "maple double samara, two plump seeds under a thin stalk, "
                     "two long thin flat wings spreading in a V, a vein along each leading "
                     "edge (level set), remeshed", _samara),
    "gear_rack": Source("cad", "manifold3d: gear rack, bar with straight-sided teeth along "
                        "its top, chamfered bottom edges, two counterbored side holes",
                        _gear_rack),
    "warren_truss": Source("cad", "manifold3d: flat Warren truss, thin chords, end posts and "
                           "zigzag diagonals round filleted triangular openings, two pin "
                           "holes", _warren_truss),
    "saw_blade": Source("cad", "manifold3d: circular saw blade, thin disc, 24 hooked teeth "
                        "with sharp tips, arbor hole, four expansion slots ending in round "
                        "holes, two pin holes", _saw_blade),
    "desmostylian_molar": Source("teeth", "desmostylian molar, eight tall columns pressed "
                                 "together in two rows, each worn to an enamel ring round a "
                                 "dentine pit, neck, two short roots (level set)",
                                 _desmostylian_molar),
    "twisted_prism": Source("smooth", "twisted prism, straight column of smooth five-pointed "
                            "star section turning half a turn from bottom to top, rounded "
                            "ends (level set), remeshed", _twisted_prism),
    "rose_cortex": Source("brain", "synthetic cortex, ovoid split by a deep midline fissure, "
                          "on each side separate sulci along three-petalled roses in two "
                          "staggered rows, none joined (radial height field), remeshed",
                          _rose_cortex),
}
