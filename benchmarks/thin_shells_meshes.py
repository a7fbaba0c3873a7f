"""The thin shells set's meshes (session 41): smooth closed walls 2-6 edges thick, with
saddle-shaped parts, on the tuning side.

Holdout set 17's first run kept the λ-H fill on thin smooth walls of negative curvature (a
cooling-tower shell and others) where a faired fill was 2-5× closer. The tuning side had no
such walls, so a rule for them could only be judged on a holdout. This set is for choosing
rules: rules may be chosen on it (``benchmarks/thin_shells_manifest.json``, split
``thin_shells``; docs/validation.md "Session 41 (helper): the thin shells set").

Nine closed meshes, none a shape of a holdout, of the two halves or of the other tuning-side
sets: six shells of revolution (a catenoid neck open at both ends, a vase with a closed
foot, a waist and a flared lip, a flaring trumpet bell, a ring-shaped gutter: half a torus
shell, a hollow torus whose cavity is a second surface, a bottle with a long neck) and
three thickened sheets (a saddle-bent disc, a helicoid band of one full twist, a plate bent
into an S).
Each is the set of points within half the wall's thickness of a densely sampled surface
(so every rim comes out rounded: the wall's end is a half-round), the distance read from a
k-d tree of the samples (of the profile curve in the (ρ, z) half-plane for the shells of
revolution), evaluated on a grid and meshed as :mod:`smooth_tuning_meshes` meshes its
shapes. The samples are made with :mod:`math` only.
:mod:`validation_meshes` imports :data:`THIN_SHELL_SOURCES` from here at its end.
"""

from __future__ import annotations

import math

import numpy as np
from smooth_tuning_meshes import _level_set
from validation_meshes import BenchMesh, Source


def _revolved_shell(profile: np.ndarray, thickness: float):
    """The inside of a wall of ``thickness`` about the surface of revolution (about z) of the
    densely sampled ``profile`` ((ρ, z) rows): half the thickness minus the distance, in the
    (ρ, z) half-plane, to the nearest sample."""
    from scipy.spatial import cKDTree

    tree = cKDTree(profile)

    def inside(points: np.ndarray) -> np.ndarray:
        rho = np.sqrt(points[:, 0] * points[:, 0] + points[:, 1] * points[:, 1])
        distance, _ = tree.query(np.column_stack([rho, points[:, 2]]))
        return 0.5 * thickness - distance
    return inside


def _sheet(samples: np.ndarray, thickness: float):
    """The inside of a wall of ``thickness`` about a densely sampled sheet (3-D rows)."""
    from scipy.spatial import cKDTree

    tree = cKDTree(samples)

    def inside(points: np.ndarray) -> np.ndarray:
        distance, _ = tree.query(points)
        return 0.5 * thickness - distance
    return inside


def _profile(point, n: int) -> np.ndarray:
    return np.array([point(k / (n - 1)) for k in range(n)], float)


def _catenoid() -> BenchMesh:
    """A catenoid neck ρ = 0.45 cosh(z / 0.45), z in [-0.7, 0.7], open at both ends, wall
    4 edges thick (negative curvature everywhere; not holdout 17's hyperboloid tower)."""
    def point(t):
        z = -0.7 + 1.4 * t
        return (0.45 * math.cosh(z / 0.45), z)
    return _level_set(_revolved_shell(_profile(point, 6000), 4 * CATENOID_H),
                      [-1.25, -1.25, -0.85, 1.25, 1.25, 0.85], CATENOID_H)


def _vase() -> BenchMesh:
    """A vase: a closed flat foot rounding up into a body that swells (ρ 0.3 to 0.6) and
    narrows to a waist (ρ 0.3), then flares to a lip; wall 3 edges thick (the waist and the
    flare are saddle-shaped)."""
    def point(t):
        if t < 0.1:  # the foot, from the axis out
            return (0.15 * t / 0.1, -0.9)
        if t < 0.2:  # a quarter circle up into the body
            a = -0.5 * math.pi + 0.5 * math.pi * (t - 0.1) / 0.1
            return (0.15 + 0.15 * math.cos(a), -0.75 + 0.15 * math.sin(a))
        u = (t - 0.2) / 0.8
        rho = 0.3 + 0.3 * math.sin(math.pi * u / 0.8) ** 2 if u <= 0.8 \
            else 0.3 + 3.0 * (u - 0.8) ** 2
        return (rho, -0.75 + 1.6 * u)
    return _level_set(_revolved_shell(_profile(point, 8000), 3 * VASE_H),
                      [-0.75, -0.75, -1.0, 0.75, 0.75, 0.95], VASE_H)


def _trumpet() -> BenchMesh:
    """A trumpet bell: ρ = 0.22 + 0.7 (z / 1.6)³, z in [0, 1.6], open at both ends, wall 3
    edges thick (ρ'' ≥ 0: saddle-shaped everywhere, flattest in the narrow pipe)."""
    def point(t):
        z = 1.6 * t
        return (0.22 + 0.7 * (z / 1.6) ** 3, z - 0.8)
    return _level_set(_revolved_shell(_profile(point, 6000), 3 * TRUMPET_H),
                      [-1.05, -1.05, -0.95, 1.05, 1.05, 0.95], TRUMPET_H)


def _gutter() -> BenchMesh:
    """A ring-shaped gutter: the lower part of a torus shell (tube radius 0.35 about a circle
    of radius 0.8, a 234° arc of the tube's section), wall 5 edges thick (saddle-shaped on
    the ring's inner side)."""
    def point(t):
        a = 0.85 * math.pi + 1.3 * math.pi * t
        return (0.8 + 0.35 * math.cos(a), 0.35 * math.sin(a))
    return _level_set(_revolved_shell(_profile(point, 6000), 5 * GUTTER_H),
                      [-1.3, -1.3, -0.5, 1.3, 1.3, 0.3], GUTTER_H)


def _saddle_plate() -> BenchMesh:
    """A disc of radius 1 bent to the saddle z = 0.35 (x² - y²), wall 2.5 edges thick."""
    rings, spokes = 300, 1200
    samples = [(0.0, 0.0, 0.0)]
    for i in range(1, rings + 1):
        r = i / rings
        for j in range(max(6, round(spokes * r))):
            a = 2 * math.pi * j / max(6, round(spokes * r))
            x, y = r * math.cos(a), r * math.sin(a)
            samples.append((x, y, 0.35 * (x * x - y * y)))
    return _level_set(_sheet(np.array(samples, float), 2.5 * SADDLE_H),
                      [-1.1, -1.1, -0.45, 1.1, 1.1, 0.45], SADDLE_H)


def _twisted_band() -> BenchMesh:
    """A helicoid band: width 0.9, length 2, one full twist (the section turns by 2π over the
    length), wall 6 edges thick (a minimal surface: saddle-shaped everywhere)."""
    across, along = 150, 800
    samples = []
    for j in range(along + 1):
        z = -1.0 + 2.0 * j / along
        a = math.pi * z
        for i in range(across + 1):
            u = -0.45 + 0.9 * i / across
            samples.append((u * math.cos(a), u * math.sin(a), z))
    return _level_set(_sheet(np.array(samples, float), 6 * BAND_H),
                      [-0.65, -0.65, -1.2, 0.65, 0.65, 1.2], BAND_H)


def _hollow_torus() -> BenchMesh:
    """A hollow torus: a torus shell (tube radius 0.38 about a circle of radius 0.85) closed
    all round, its cavity a second, inward-facing surface, wall 4 edges thick (the ring's
    inner side saddle-shaped, on both surfaces)."""
    def point(t):
        a = 2 * math.pi * t
        return (0.85 + 0.38 * math.cos(a), 0.38 * math.sin(a))
    return _level_set(_revolved_shell(_profile(point, 6000), 4 * HOLLOW_H),
                      [-1.35, -1.35, -0.5, 1.35, 1.35, 0.5], HOLLOW_H)


def _bottle() -> BenchMesh:
    """A bottle: a closed flat foot rounding up into a cylindrical body (ρ 0.45), a shoulder
    narrowing in a smooth S to a long neck (ρ 0.14) and a slightly flared mouth, wall 3
    edges thick (the shoulder's upper half and the mouth's flare saddle-shaped)."""
    def point(t):
        if t < 0.12:  # the foot, from the axis out
            return (0.3 * t / 0.12, -0.95)
        if t < 0.22:  # a quarter circle up into the body
            a = -0.5 * math.pi + 0.5 * math.pi * (t - 0.12) / 0.1
            return (0.3 + 0.15 * math.cos(a), -0.8 + 0.15 * math.sin(a))
        u = (t - 0.22) / 0.78
        z = -0.8 + 1.7 * u
        if z < 0.0:
            return (0.45, z)
        if z < 0.45:  # the shoulder: a smooth step from 0.45 down to 0.14
            s = z / 0.45
            return (0.45 - 0.31 * s * s * (3.0 - 2.0 * s), z)
        return (0.14 + 0.6 * max(z - 0.75, 0.0) ** 2, z)
    return _level_set(_revolved_shell(_profile(point, 8000), 3 * BOTTLE_H),
                      [-0.6, -0.6, -1.05, 0.6, 0.6, 1.0], BOTTLE_H)


def _s_plate() -> BenchMesh:
    """A rectangular plate (2 by 1.1, corners rounded off by the wall) bent along its length
    into an S, z = 0.3 sin(π x), and twisted slightly across (z += 0.15 x y), wall 3 edges
    thick."""
    along, across = 800, 440
    samples = []
    for j in range(along + 1):
        x = -1.0 + 2.0 * j / along
        for i in range(across + 1):
            y = -0.55 + 1.1 * i / across
            samples.append((x, y, 0.3 * math.sin(math.pi * x) + 0.15 * x * y))
    return _level_set(_sheet(np.array(samples, float), 3 * SPLATE_H),
                      [-1.1, -0.65, -0.5, 1.1, 0.65, 0.5], SPLATE_H)


HOLLOW_H, BOTTLE_H, SPLATE_H = 0.035, 0.028, 0.03
CATENOID_H, VASE_H, TRUMPET_H, GUTTER_H, SADDLE_H, BAND_H = 0.04, 0.03, 0.03, 0.035, 0.04, 0.03

THIN_SHELL_SOURCES: dict[str, Source] = {
    "catenoid_shell": Source("smooth", "catenoid neck shell open at both ends, wall 4 edges, "
                             "rims rounded (level set), remeshed", _catenoid),
    "vase": Source("smooth", "vase, closed foot, swelling body, waist, flared lip, wall 3 "
                   "edges (level set), remeshed", _vase),
    "trumpet_bell": Source("smooth", "trumpet bell flaring from a narrow pipe, open at both "
                           "ends, wall 3 edges (level set), remeshed", _trumpet),
    "ring_gutter": Source("smooth", "ring-shaped gutter, the lower part of a torus shell, wall "
                          "5 edges (level set), remeshed", _gutter),
    "saddle_plate": Source("smooth", "disc bent to a saddle z = 0.35 (x^2 - y^2), wall 2.5 "
                           "edges (level set), remeshed", _saddle_plate),
    "twisted_band": Source("smooth", "helicoid band of one full twist, wall 6 edges (level "
                           "set), remeshed", _twisted_band),
    "hollow_torus": Source("smooth", "hollow torus, a closed torus shell with a torus-shaped "
                           "cavity, wall 4 edges (level set), remeshed", _hollow_torus),
    "bottle": Source("smooth", "bottle, closed foot, cylindrical body, S-shaped shoulder, long "
                     "neck, flared mouth, wall 3 edges (level set), remeshed", _bottle),
    "s_plate": Source("smooth", "rectangular plate bent into an S along its length and twisted "
                      "slightly, wall 3 edges (level set), remeshed", _s_plate),
}
