"""Session 26's flatness test (``benchmarks/scan_flatness_study.py``): plane vs quadric
height field by an F-test, and the flat candidate fill, on analytic cases."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import grid_mesh

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
study = pytest.importorskip("scan_flatness_study")

from surfinpaint.fill.liepa.baseline import faired_fills  # noqa: E402
from surfinpaint.geometry.cutting import cut_geodesic_disk  # noqa: E402


def annulus(seed: int, height, noise: float = 0.01) -> tuple[np.ndarray, np.ndarray]:
    """The vertices of a 41 x 41 grid over [-1, 1]^2 in the annulus 0.5 <= r <= 1 (a ring of
    known surface around a hole), lifted to ``height(u, v)`` plus Gaussian noise, tilted and
    shifted (the test must not depend on the axes), and the grid edges between them."""
    v, f = grid_mesh(40, 40)
    uv = 2.0 * v[:, :2] - 1.0
    r = np.linalg.norm(uv, axis=1)
    keep = (r >= 0.5) & (r <= 1.0)
    local = np.full(len(v), -1)
    local[keep] = np.arange(keep.sum())
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    e = np.unique(np.sort(e[keep[e].all(axis=1)], axis=1), axis=0)
    w = height(uv[keep, 0], uv[keep, 1])
    w = w + np.random.default_rng(seed).normal(0, noise, len(w))
    a = np.radians(35.0)
    rot = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    points = np.column_stack([uv[keep], w]) @ rot.T + np.array([3.0, -1.0, 2.0])
    return points, local[e]


@pytest.mark.parametrize("seed", range(5))
def test_a_noisy_plane_is_flat(seed):
    t = study.flatness_test(*annulus(seed, lambda u, v: 0.2 * u - 0.1 * v))
    assert t["flat"] and t["flat_F"] and t["p"] >= study.ALPHA
    assert t["sigma"] == pytest.approx(0.01, rel=0.2)  # the noise, from the residual


@pytest.mark.parametrize("seed", range(5))
def test_a_noisy_sphere_patch_is_curved(seed):
    radius = 4.0  # sagitta at the rim 1/8 of a unit: 12 noise levels
    t = study.flatness_test(*annulus(seed, lambda u, v: radius - np.sqrt(
        radius ** 2 - u * u - v * v)))
    assert not t["flat"] and not t["flat_F"] and t["p"] < 1e-6


def test_folds_no_quadric_fits_are_not_flat():
    # ripples: the quadric fits no better than the plane (F-test alone: flat), but the
    # plane's residuals are alike between neighbours (Moran's I: not noise)
    t = study.flatness_test(*annulus(0, lambda u, v: 0.05 * np.sin(9 * u) * np.cos(9 * v),
                                     noise=0.0))
    assert t["flat_F"] and not t["flat"] and t["p_moran"] < 1e-6


def test_an_exact_plane_is_flat():
    t = study.flatness_test(*annulus(0, lambda u, v: 0.0 * u, noise=0.0))
    assert t["flat"] and t["F"] == 0.0


def test_the_flat_candidate_keeps_the_loop_and_follows_its_heights():
    v, f = grid_mesh(16, 16)
    cut = cut_geodesic_disk(v, f, np.array([0.5, 0.5, 0.0]), 0.3)
    w = cut.vertices.copy()
    w[cut.loop, 2] = 0.01  # the loop raised: the membrane is the plane z = 0.01
    nv, patch, _ = faired_fills(w, cut.faces, cut.loop, (2,))[2]
    out = study.plane_fill(w, cut.faces, nv, patch, np.zeros(3), np.array([0.0, 0.0, 1.0]))
    assert len(out) == len(nv) > 0
    np.testing.assert_allclose(out[:, 2], 0.01, atol=1e-12)
    np.testing.assert_allclose(out[:, :2], nv[:, :2], atol=1e-12)  # along the plane: fair2's
