"""The smooth tuning set's meshes (session 38): smooth tubes and organic bodies, on the tuning side.

Issue 14's two recurring chooser mistakes on fresh sets are on smooth tubes and smooth organic
shapes: a λ-H fill kept over a much better trilaplacian fill, and the bilaplacian fill kept
where the trilaplacian and λ-H fills are about twice as close. The tuning side had few such
shapes, so rules for them could only be judged on holdouts. This set is for choosing rules:
rules may be chosen on it (``benchmarks/smooth_tuning_manifest.json``, split
``smooth_tuning``; docs/validation.md "Smooth tuning set").

Eight closed meshes, none a shape of holdouts 1-15, of the two halves or of the other
tuning-side sets: four smooth tubes (a figure-eight knot of varying radius, a theta-shaped
tube of genus 2, a ball with a handle, a wavy torus whose tube swells and narrows) and four
organic bodies with small features (a piglet, a cowrie shell, an octopus, a ram's horn).

Each shape's inside is a smooth union of tubes round sampled curves (the distance to the
nearest of a dense sampling of the curve, from a k-d tree, minus the radius there) and
ellipsoids, evaluated with numpy on a grid of the level set's spacing, read back trilinearly
by manifold3d's level set and isotropically remeshed (:func:`validation_meshes.
_level_set_mesh`'s steps). Only arithmetic and square roots touch the grid (the smooth union
is the polynomial one, no exp or log), and the curves are sampled with :mod:`math`, so a
mesh's bits do not depend on the CPU's vector units. :mod:`validation_meshes` imports
:data:`SMOOTH_TUNING_SOURCES` from here at its end (import it first, not this module).
"""

from __future__ import annotations

import math

import numpy as np
import validation_meshes as vm
from validation_meshes import BenchMesh, Source

# the grid spacing of every level set, relative to the mesh's edge length
STEP_OF_H = 0.7


def _curve(point, n: int, closed: bool) -> np.ndarray:
    """``n`` samples of the curve ``point(t)``, t in [0, 1) (closed) or [0, 1]."""
    ts = [k / n if closed else k / (n - 1) for k in range(n)]
    return np.array([point(t) for t in ts], float)


def _tube(samples: np.ndarray, radii: np.ndarray):
    """The inside of a tube round a densely sampled curve: (points) -> radius at the nearest
    sample minus the distance to it (a capsule's rounded ends at an open curve's ends)."""
    from scipy.spatial import cKDTree

    tree = cKDTree(samples)

    def inside(points: np.ndarray) -> np.ndarray:
        distance, nearest = tree.query(points)
        return radii[nearest] - distance
    return inside


def _ellipsoid(centre, axes):
    """The inside of an ellipsoid, roughly as a distance (the benchmark animals' form)."""
    c, a = np.asarray(centre, float), np.asarray(axes, float)

    def inside(points: np.ndarray) -> np.ndarray:
        q = (points - c) / a
        return (1.0 - np.sqrt((q * q).sum(1))) * a.min()
    return inside


def _smooth_union(values: list[np.ndarray], k: float) -> np.ndarray:
    """The polynomial smooth maximum of insides (blend width ``k``), pairwise in order."""
    out = values[0]
    for v in values[1:]:
        blend = np.maximum(k - np.abs(out - v), 0.0) / k
        out = np.maximum(out, v) + blend * blend * k * 0.25
    return out


def _smooth_cut(a: np.ndarray, b: np.ndarray, k: float) -> np.ndarray:
    """``a`` with ``b`` carved out, the edge rounded over ``k``."""
    return -_smooth_union([-a, b], k)


def _level_set(inside, bounds, h: float) -> BenchMesh:
    """The surface where ``inside(points)`` (vectorized) is 0, meshed and remeshed to ``h``."""
    import manifold3d as m3

    step = STEP_OF_H * h
    lo = np.asarray(bounds[:3], float)
    counts = np.floor((np.asarray(bounds[3:], float) - lo) / step).astype(int) + 2
    axes = [lo[i] + step * np.arange(counts[i]) for i in range(3)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    values = inside(grid).reshape(counts).tolist()
    nx, ny, nz = (int(c) - 1 for c in counts)
    x0, y0, z0 = (float(x) for x in lo)

    def sample(x: float, y: float, z: float) -> float:  # trilinear, clamped to the grid
        u, v, w = (x - x0) / step, (y - y0) / step, (z - z0) / step
        i, j, k = (min(max(int(math.floor(s)), 0), n - 1) for s, n in
                   ((u, nx), (v, ny), (w, nz)))
        u, v, w = min(max(u - i, 0.0), 1.0), min(max(v - j, 0.0), 1.0), min(max(w - k, 0.0), 1.0)
        a, b = values[i], values[i + 1]
        c00 = a[j][k] * (1 - u) + b[j][k] * u
        c01 = a[j][k + 1] * (1 - u) + b[j][k + 1] * u
        c10 = a[j + 1][k] * (1 - u) + b[j + 1][k] * u
        c11 = a[j + 1][k + 1] * (1 - u) + b[j + 1][k + 1] * u
        return (c00 * (1 - v) + c10 * v) * (1 - w) + (c01 * (1 - v) + c11 * v) * w

    m = m3.Manifold.level_set(sample, [float(b) for b in bounds], step).to_mesh()
    v = np.asarray(m.vert_properties, float)[:, :3]
    f = np.asarray(m.tri_verts, np.int64)
    return vm._mesh(*vm._remesh(v, f, h, feature_deg=180.0))


# --------------------------------------------------------------------------- smooth tubes


def _knot() -> BenchMesh:
    """A tube round a figure-eight knot ``((2 + cos 2t) cos 3t, (2 + cos 2t) sin 3t,
    sin 4t) × 0.35``, its radius swelling and narrowing twice round (0.09 to 0.17):
    smooth, genus 1, knotted, its curvature varying along it (not holdout 4's trefoil)."""
    def point(t):
        s = 2 * math.pi * t
        return (0.35 * (2 + math.cos(2 * s)) * math.cos(3 * s),
                0.35 * (2 + math.cos(2 * s)) * math.sin(3 * s), 0.35 * math.sin(4 * s))
    n = 6000
    radii = np.array([0.13 + 0.04 * math.sin(2 * 2 * math.pi * k / n) for k in range(n)])
    return _level_set(_tube(_curve(point, n, True), radii), [-1.3, -1.3, -0.6, 1.3, 1.3, 0.6],
                      KNOT_H)


def _theta() -> BenchMesh:
    """A theta-shaped tube: a tube round an ellipse (semi-axes 1 and 0.65, rising and
    falling by 0.12 twice round) and a bowed bar along its long axis, blended (genus 2;
    not holdout 4's double torus or holdout 13's lemniscate)."""
    def ring(t):
        s = 2 * math.pi * t
        return (math.cos(s), 0.65 * math.sin(s), 0.12 * math.sin(2 * s))

    def bar(t):
        x = -1.0 + 2.0 * t
        return (x, 0.1 * math.sin(math.pi * x), 0.22 * (1.0 - x * x))
    n = 4000
    ring_r = np.array([0.15 + 0.03 * math.cos(2 * 2 * math.pi * k / n) for k in range(n)])
    bar_r = np.array([0.10 + 0.03 * (1.0 - (-1.0 + 2.0 * k / (n - 1)) ** 2) for k in range(n)])
    parts = [_tube(_curve(ring, n, True), ring_r), _tube(_curve(bar, n, False), bar_r)]
    return _level_set(lambda p: _smooth_union([part(p) for part in parts], 0.08),
                      [-1.25, -0.9, -0.35, 1.25, 0.9, 0.5], THETA_H)


def _handle_ball() -> BenchMesh:
    """A slightly squashed ball (semi-axes 0.75, 0.75, 0.68) with a mug's handle on its
    side: a tube (radius 0.075 to 0.1) round a C-shaped arc whose ends sink into the
    ball, blended (genus 1; not holdout 10's ball with a ring round its equator)."""
    def arc(t):
        a = math.radians(-125.0 + 250.0 * t)
        return (0.72 + 0.5 * math.cos(a), 0.08 * math.sin(a), 0.5 * math.sin(a))
    n = 3000
    radii = np.array([0.075 + 0.025 * abs(-1.0 + 2.0 * k / (n - 1)) for k in range(n)])
    parts = [_ellipsoid((0.0, 0.0, 0.0), (0.75, 0.75, 0.68)),
             _tube(_curve(arc, n, False), radii)]
    return _level_set(lambda p: _smooth_union([part(p) for part in parts], 0.08),
                      [-0.85, -0.85, -0.8, 1.4, 0.85, 0.8], HANDLE_H)


def _wavy_torus() -> BenchMesh:
    """A torus whose tube swells and narrows three times round (radius 0.16 to 0.4) about a
    circle of radius 1 rising and falling by 0.15 twice round (genus 1; not the tuning
    half's torus or holdout 2's thick one: its minor radius varies)."""
    def point(t):
        s = 2 * math.pi * t
        return (math.cos(s), math.sin(s), 0.15 * math.sin(2 * s))
    n = 5000
    radii = np.array([0.28 + 0.12 * math.cos(3 * 2 * math.pi * k / n) for k in range(n)])
    return _level_set(_tube(_curve(point, n, True), radii), [-1.45, -1.45, -0.6, 1.45, 1.45, 0.6],
                      WAVY_H)


# --------------------------------------------------------------------------- organic


def _piglet() -> BenchMesh:
    """A piglet: an ellipsoid body, a round head with a short snout, two small ears, four
    stubby legs and a curly tail (a helix of 1.5 turns), blended."""
    def tail(t):
        a = 3 * math.pi * t
        return (-0.9 - 0.25 * t, 0.09 * math.sin(a), 0.15 + 0.09 * math.cos(a))
    n = 1500
    parts = [_ellipsoid((0.0, 0.0, 0.0), (0.9, 0.55, 0.5)),
             _ellipsoid((0.95, 0.0, 0.22), (0.38, 0.34, 0.33)),
             _tube(_curve(lambda t: (1.25 + 0.18 * t, 0.0, 0.15 - 0.02 * t), n, False),
                   np.full(n, 0.13)),
             _ellipsoid((0.98, 0.2, 0.52), (0.07, 0.11, 0.15)),
             _ellipsoid((0.98, -0.2, 0.52), (0.07, 0.11, 0.15)),
             _tube(_curve(tail, n, False), np.full(n, 0.055))]
    for x in (-0.5, 0.5):
        for y in (-0.28, 0.28):
            parts.append(_tube(_curve(lambda t, x=x, y=y: (x, y, -0.25 - 0.5 * t), n, False),
                               np.full(n, 0.12)))
    return _level_set(lambda p: _smooth_union([part(p) for part in parts], 0.07),
                      [-1.35, -0.7, -0.95, 1.55, 0.7, 0.8], PIGLET_H)


def _cowrie() -> BenchMesh:
    """A cowrie shell: a domed ellipsoid flattened underneath, a long narrow aperture along
    its underside between two swollen lips, and a small bump at the spire end."""
    n = 2000

    def slit(t):
        x = -0.85 + 1.7 * t
        return (x, 0.06 * math.sin(math.pi * x), -0.36)
    body = _ellipsoid((0.0, 0.0, 0.0), (1.0, 0.62, 0.48))
    lips = [_tube(_curve(lambda t, y=y: (-0.8 + 1.6 * t, y, -0.28), n, False),
                  np.full(n, 0.08)) for y in (-0.14, 0.14)]
    spire = _ellipsoid((-0.92, 0.0, 0.05), (0.14, 0.12, 0.12))
    groove = _tube(_curve(slit, n, False), np.full(n, 0.07))

    def inside(p):
        shell = _smooth_union([body(p), spire(p)], 0.08)
        floor = _smooth_cut(shell, -0.3 - p[:, 2], 0.06)  # flattened underneath
        with_lips = _smooth_union([floor, *(lip(p) for lip in lips)], 0.05)
        return _smooth_cut(with_lips, groove(p), 0.04)
    return _level_set(inside, [-1.15, -0.75, -0.5, 1.1, 0.75, 0.55], COWRIE_H)


def _octopus() -> BenchMesh:
    """An octopus: a tall mantle over a head with two bulging eyes, and eight tapering arms
    (radius 0.14 to 0.065) reaching out and down, each curling sideways at its end."""
    n = 1500
    parts = [_ellipsoid((0.0, 0.0, 0.6), (0.42, 0.4, 0.55)),
             _ellipsoid((0.0, 0.0, 0.08), (0.45, 0.45, 0.33)),
             _ellipsoid((0.3, 0.22, 0.2), (0.1, 0.1, 0.1)),
             _ellipsoid((0.3, -0.22, 0.2), (0.1, 0.1, 0.1))]
    for arm in range(8):
        def point(t, a0=2 * math.pi * arm / 8 + 0.2):
            a = a0 + 0.7 * t * t
            rho = 0.22 + 1.1 * t
            return (rho * math.cos(a), rho * math.sin(a), -0.08 - 0.3 * math.sin(math.pi * t)
                    + 0.25 * t * t)
        parts.append(_tube(_curve(point, n, False),
                           np.array([0.14 * (1 - 0.55 * k / (n - 1)) for k in range(n)])))
    return _level_set(lambda p: _smooth_union([part(p) for part in parts], 0.07),
                      [-1.5, -1.5, -0.6, 1.5, 1.5, 1.25], OCTOPUS_H)


def _horn() -> BenchMesh:
    """A ram's horn: a tube round a rising conical spiral of 0.8 turn, its radius tapering
    from 0.33 at the rounded base to 0.07 at the tip, the spiral tightening as it goes."""
    n = 4000

    def point(t):
        a = 1.6 * math.pi * t
        rho = 0.95 * (1.0 - 0.62 * t)
        return (rho * math.cos(a), rho * math.sin(a), 0.6 * t - 0.1 * math.sin(math.pi * t))
    radii = np.array([0.07 + 0.26 * (1.0 - k / (n - 1)) ** 1.5 for k in range(n)])
    return _level_set(_tube(_curve(point, n, False), radii), [-1.05, -1.0, -0.45, 1.35, 1.1, 0.8],
                      HORN_H)


KNOT_H, THETA_H, HANDLE_H, WAVY_H = 0.028, 0.024, 0.026, 0.03
PIGLET_H, COWRIE_H, OCTOPUS_H, HORN_H = 0.028, 0.026, 0.03, 0.024

SMOOTH_TUNING_SOURCES: dict[str, Source] = {
    "knot8": Source("smooth", "tube round a figure-eight knot, radius 0.09-0.17 (level set), "
                    "remeshed", _knot),
    "theta_tube": Source("smooth", "theta-shaped tube: a wavy elliptic ring and a bowed bar "
                         "(smooth union, level set, genus 2), remeshed", _theta),
    "handle_ball": Source("smooth", "squashed ball with a mug handle on its side (smooth "
                          "union, level set, genus 1), remeshed", _handle_ball),
    "wavy_torus": Source("smooth", "torus whose tube swells and narrows three times round, "
                         "its circle rising and falling (level set), remeshed", _wavy_torus),
    "piglet": Source("organic", "piglet, body, head, snout, ears, four stubby legs, curly "
                     "tail (smooth union, level set), remeshed", _piglet),
    "cowrie": Source("organic", "cowrie shell, domed, flat underneath, aperture slit between "
                     "two lips, spire bump (level set), remeshed", _cowrie),
    "octopus": Source("organic", "octopus, mantle, head, two eyes, eight tapering arms curling "
                      "at their ends (smooth union, level set), remeshed", _octopus),
    "horn": Source("organic", "ram's horn, tube round a tightening conical spiral, radius "
                   "tapering 0.33 to 0.07 (level set), remeshed", _horn),
}
