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


def annulus(n: int, seed: int) -> np.ndarray:
    """``n`` points (u, v) in the annulus 0.5 <= r <= 1 (a ring of known surface)."""
    rng = np.random.default_rng(seed)
    r = np.sqrt(rng.uniform(0.25, 1.0, n))
    t = rng.uniform(0, 2 * np.pi, n)
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


def tilted(uvw: np.ndarray) -> np.ndarray:
    """The points in a rotated and shifted frame: the test must not depend on the axes."""
    a = np.radians(35.0)
    rot = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    return uvw @ rot.T + np.array([3.0, -1.0, 2.0])


@pytest.mark.parametrize("seed", range(5))
def test_a_noisy_plane_is_flat(seed):
    uv = annulus(300, seed)
    w = 0.2 * uv[:, 0] - 0.1 * uv[:, 1] + np.random.default_rng(seed + 50).normal(0, 0.01, 300)
    t = study.flatness_test(tilted(np.column_stack([uv, w])))
    assert t["flat"] and t["p"] >= study.ALPHA
    assert t["sigma"] == pytest.approx(0.01, rel=0.3)  # the noise, from the residual


@pytest.mark.parametrize("seed", range(5))
def test_a_noisy_sphere_patch_is_curved(seed):
    uv = annulus(300, seed)
    radius = 4.0  # sagitta at the rim 1/8 of a unit: 12 noise levels
    w = radius - np.sqrt(radius ** 2 - (uv ** 2).sum(axis=1))
    w = w + np.random.default_rng(seed + 50).normal(0, 0.01, 300)
    t = study.flatness_test(tilted(np.column_stack([uv, w])))
    assert not t["flat"] and t["p"] < 1e-6


def test_an_exact_plane_is_flat():
    uv = annulus(50, 0)
    t = study.flatness_test(tilted(np.column_stack([uv, np.zeros(50)])))
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
