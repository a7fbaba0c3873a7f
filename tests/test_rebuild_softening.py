"""The softened unit vectors of the mesh rebuild (mesh_lambda_h.soft_unit): the rebuild's
equations stay continuous where an intermediate surface folds a vertex's one-ring (its
area vector N vanishes) or is locally anti-conformal (the frame's w vanishes). With unit
vectors the residual jumps there and the continuation's curve ended at such points (the
cow's hoof cap at t = 0.584, docs/representation.md; PyMeshLab's cow is a validation mesh
and no longer benchmarked: the tests here are built cases)."""

from __future__ import annotations

import numpy as np
import pytest

from surfinpaint.data import bumpy_disk
from surfinpaint.representation.mesh_lambda_h import (
    SOFTENING,
    RebuildSystem,
    soft_unit,
    softening,
)
from surfinpaint.representation.represent import represent


def test_soft_unit_is_the_unit_vector_above_eps_and_smooth_through_zero():
    rng = np.random.default_rng(0)
    x = rng.normal(size=(200, 3))
    eps = np.linalg.norm(x, axis=1) * rng.uniform(0.2, 1.8, size=200)
    y, k, k1 = soft_unit(x, eps)
    outside = np.linalg.norm(x, axis=1) >= eps
    assert outside.any() and (~outside).any()
    unit = x / np.linalg.norm(x, axis=1, keepdims=True)
    assert np.abs(y[outside] - unit[outside]).max() < 1e-15
    assert np.all(np.linalg.norm(y, axis=1) <= 1 + 1e-15)
    # continuous through zero and at |x| = eps
    tiny, _, _ = soft_unit(1e-12 * unit, np.ones(200))
    assert np.abs(tiny).max() < 3e-12
    at_eps, _, _ = soft_unit(unit * (1 - 1e-9), np.ones(200))
    assert np.abs(at_eps - unit).max() < 1e-8
    # its derivative, k I + k1 x̂ x̂ᵀ, inside and outside the softened ball
    d = rng.normal(size=x.shape)
    h = 1e-7
    fd = (soft_unit(x + h * d, eps)[0] - soft_unit(x - h * d, eps)[0]) / (2 * h)
    exact = k[:, None] * d + k1[:, None] * unit * np.einsum("ij,ij->i", unit, d)[:, None]
    assert np.abs(fd - exact).max() < 1e-6 * np.abs(exact).max()


@pytest.fixture(scope="module")
def disk():
    v, f = bumpy_disk(8)
    rep = represent(v, f, check=False)
    system = RebuildSystem(f, rep.uv, rep.lam, rep.H, rep.defect, ~rep.known)
    centre = int(np.argmin(np.linalg.norm(v[:, :2], axis=1)))
    ring_faces = f[(f == centre).any(axis=1)]
    return v, f, rep, system, centre, ring_faces


def _area_vector(x, faces, i):
    faces = faces[(faces == i).any(axis=1)]
    c = np.cross(x[faces[:, 1]] - x[faces[:, 0]], x[faces[:, 2]] - x[faces[:, 0]])
    return c.sum(axis=0)


def _place_zero(fn, x, movers, damping=0.0, steps=40):
    """x with the vertices ``movers`` moved (damped Gauss–Newton) so that the vector
    ``fn(x)`` vanishes; and the direction of the movers that moves fn along its first
    axis."""
    x = x.copy()
    for _ in range(steps):
        base = fn(x)
        cols = []
        for j in movers:
            for c in range(3):
                y = x.copy()
                y[j, c] += 1e-7
                cols.append((fn(y) - base) / 1e-7)
        A = np.column_stack(cols)
        if damping:  # Levenberg–Marquardt: w ⊥ n, so one singular value is 0
            step = np.linalg.solve(A.T @ A + damping * np.eye(A.shape[1]), -A.T @ base)
        else:
            step = np.linalg.lstsq(A, -base, rcond=None)[0]
        step = step.reshape(-1, 3)
        x[movers] += step * min(1.0, 0.05 / np.abs(step).max())  # at most 0.05 a step
    d = np.zeros_like(x)
    d[movers] = np.linalg.lstsq(A, np.eye(len(base))[0], rcond=None)[0].reshape(-1, 3)
    return x, d / np.abs(d).max()


def _jumps(system, x, d):
    """max |R(x + δd) − R(x − δd)| at t = 1 for δ = 1e-8 and 1e-10: they fall with δ
    where R is continuous, and stay where it jumps."""
    return [np.abs(system.residual(x + h * d, 1.0) - system.residual(x - h * d, 1.0)).max()
            for h in (1e-8, 1e-10)]


def test_residual_is_continuous_where_a_one_ring_folds(disk):
    """N_i does not depend on p_i: two of its ring's vertices are moved so that the ring's
    area vector vanishes (a folded one-ring); crossing that point flips the unit normal."""
    v, f, rep, system, i, ring_faces = disk
    ring = np.setdiff1d(np.unique(ring_faces), [i])
    movers = [int(ring[0]), int(ring[len(ring) // 2])]  # not neighbours
    x, d = _place_zero(lambda y: _area_vector(y, f, i), v, movers)
    assert np.abs(x - v).max() < 0.5  # a local fold, not a far-away surface
    eps_n = softening(rep.lam, system.area)[1][i]
    assert np.linalg.norm(_area_vector(x, f, i)) < 1e-6 * eps_n
    big, small = _jumps(system, x, d)
    assert big > 50 * small  # continuous: the jump falls with δ (unit normals: it stays)


def test_residual_is_continuous_where_the_map_is_anti_conformal(disk):
    """The frame's w_i = P g_u − n × g_v vanishes where the vertex's map is locally a
    reflection; two ring vertices are moved there (g_u, g_v do not depend on p_i)."""
    v, f, rep, system, i, ring_faces = disk
    ring = np.setdiff1d(np.unique(ring_faces), [i])

    def w_at(x):
        n = _area_vector(x, f, i)
        n = n / np.linalg.norm(n)
        g_u, g_v = system.G_u[i] @ x, system.G_v[i] @ x
        return (g_u - (g_u @ n) * n - np.cross(n, g_v)).ravel()

    N0 = _area_vector(v, f, i)
    x, d = _place_zero(lambda y: np.concatenate([w_at(y), _area_vector(y, f, i) - N0]), v,
                       [int(j) for j in ring], damping=0.1)
    assert np.linalg.norm(_area_vector(x, f, i)) > 0.1 * softening(rep.lam, system.area)[1][i]
    assert np.linalg.norm(w_at(x)) < 1e-6 * 2 * rep.lam[i] * SOFTENING
    big, small = _jumps(system, x, d)
    assert big > 50 * small
def test_rebuild_jacobian_matches_finite_differences_where_softened(disk):
    v, f, rep, system, i, _ = disk
    rng = np.random.default_rng(1)
    x = v.copy()
    x[~rep.known] += 0.002 * rng.normal(size=x[~rep.known].shape)
    # shrink the surface around i so that |w| and |N| there fall inside the softened balls
    near = np.linalg.norm(v[:, :2] - v[i, :2], axis=1) < 0.25
    x[near & ~rep.known] = x[i] + 0.005 * (x[near & ~rep.known] - x[i])
    eps_n = softening(rep.lam, system.area)[1]
    N = np.array([_area_vector(x, f, j) for j in range(len(x))])
    assert (np.linalg.norm(N, axis=1) < eps_n)[~rep.known].any()
    d = np.where(rep.known[:, None], 0.0, rng.normal(size=v.shape))
    h = 1e-8
    fd = (system.residual(x + h * d, 0.7) - system.residual(x - h * d, 0.7)) / (2 * h)
    J, _ = system.jacobian(x, 0.7)
    assert np.linalg.norm(J @ d.ravel()[system.idx] - fd) < 1e-5 * np.linalg.norm(fd)


class _Dense:
    def __init__(self, M):
        self.M = np.asarray(M, dtype=float)

    def solve(self, b):
        return np.linalg.solve(self.M, b)


def test_corrector_refactors_where_the_chord_steps_stop_contracting():
    """On the unit circle x² + t² = 1, a chord matrix from a far point (slope 3× too small,
    so chord steps overshoot and grow) does not correct; the refactored one does."""
    from surfinpaint.representation import continuation

    def residual(z):
        return np.array([z[0] ** 2 + z[1] ** 2 - 1.0])

    def factor(z, row):
        return _Dense([[2 * z[0], 2 * z[1]], row])

    y = np.array([1.0, 0.0])
    tau = np.array([0.0, 1.0])
    stale = _Dense([[2 * y[0] / 3, 0.0], tau])  # the chord matrix of a wrong slope
    args = (residual, stale, y, tau, tau, 0.2)
    done, steps, refactored = continuation._correct(
        *args, lambda z: factor(z, tau), budget=10)
    assert done is not None and refactored >= 1 and done[1] == 0.2  # the first attempt
    # on the curve to the corrector's tolerance, at the arclength constraint t = Δs
    assert abs(residual(done[0])[0]) < continuation.CORRECTED
    assert abs(done[0][1] - done[1]) < 1e-12
    chord, _, none = continuation._correct(*args, lambda z: factor(z, tau), budget=0)
    # without refactoring the chord steps correct only where the predictor is already
    # within the tolerance: Δs halved six times or more
    assert none == 0 and (chord is None or chord[1] <= 0.2 / 64)
