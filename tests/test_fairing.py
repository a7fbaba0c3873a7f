"""Fairing Δᵏx = 0 with the cotangent Laplacian."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from surfinpaint.errors import MeshError
from surfinpaint.fill.liepa.fairing import fair
from surfinpaint.fill.liepa.refinement import refine_patch
from surfinpaint.fill.liepa.triangulation import minimum_weight_triangulation
from surfinpaint.geometry.cutting import cut_geodesic_disk


def _grid(n: int = 16, jitter: float = 0.2, seed: int = 0):
    """Irregular planar triangulation of the unit square in z = 0."""
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    v = np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)])
    inner = (x.ravel() > 0) & (x.ravel() < 1) & (y.ravel() > 0) & (y.ravel() < 1)
    v[inner, :2] += jitter / n * rng.uniform(-1, 1, (inner.sum(), 2))
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    f = np.concatenate([np.column_stack([a, a + n, a + n + 1]),
                        np.column_stack([a, a + n + 1, a + 1])])
    return v, f


def _central(v, radius):
    return np.flatnonzero(np.linalg.norm(v[:, :2] - 0.5, axis=1) < radius)


@pytest.mark.parametrize("order", [1, 2, 3])
def test_reproduces_a_plane(order):
    v, f = _grid()
    free = _central(v, 0.25)
    # free vertices at their true place: the planar mesh is already the solution
    # (cotangent weights reproduce linear functions), in all three coordinates
    out = fair(v, f, free, order=order)
    assert np.abs(out - v).max() < 1e-12
    # lifted off the plane: z comes back to 0 exactly, whatever the weights
    lifted = v.copy()
    lifted[free, 2] = np.random.default_rng(1).uniform(0.1, 0.3, len(free))
    out = fair(lifted, f, free, order=order, iterations=2)
    assert np.abs(out[:, 2]).max() < 1e-12
    assert np.array_equal(np.delete(out, free, axis=0), np.delete(lifted, free, axis=0))


def test_reproduces_a_tilted_plane_with_bool_mask():
    v, f = _grid(seed=2)
    free = np.zeros(len(v), bool)
    free[_central(v, 0.3)] = True
    tilted = v.copy()
    tilted[:, 2] = 0.3 * v[:, 0] - 0.7 * v[:, 1] + 0.1
    noisy = tilted.copy()
    noisy[free, 2] += 0.2
    out = fair(noisy, f, free)
    # rows of L sum to zero and the fixed vertices are on the plane, so the solution is on
    # it too, whatever the (noisy) weights
    assert np.abs(out[:, 2] - (0.3 * out[:, 0] - 0.7 * out[:, 1] + 0.1)).max() < 1e-12


def test_sphere_cap_fill_is_close_to_the_sphere():
    """A cap removed from a unit icosphere: the flat patch is off the sphere by about the
    cap's sagitta; the biharmonic fill must be much closer (measured 0.039 sagitta)."""
    m = trimesh.creation.icosphere(4)
    cut = cut_geodesic_disk(m.vertices, m.faces, 0, 0.5)
    v, faces, loop = cut.vertices, cut.faces, cut.loop
    axis = v[loop].mean(axis=0)
    axis /= np.linalg.norm(axis)
    sagitta = 1 - (v[loop] @ axis).min()
    tri = minimum_weight_triangulation(v, loop, faces)
    new_v, patch = refine_patch(v, tri, loop, faces=faces)
    n = len(v)
    flat_err = np.abs(np.linalg.norm(new_v, axis=1) - 1).max()
    out = fair(np.vstack([v, new_v]), np.vstack([faces, patch]), np.arange(n, n + len(new_v)))
    err = np.abs(np.linalg.norm(out[n:], axis=1) - 1).max()
    assert flat_err > 0.5 * sagitta
    assert err < 0.06 * sagitta
    assert np.array_equal(out[:n], v)


def test_is_local():
    """Vertices beyond the stencil's rings never enter the system: garbage there is fine."""
    v, f = _grid(20)
    free = _central(v, 0.15)
    bad = v.copy()
    bad[np.linalg.norm(v[:, :2] - 0.5, axis=1) > 0.45] = np.nan
    out = fair(bad, f, free)
    assert np.isfinite(out[free]).all()
    assert np.allclose(out[free], v[free], atol=1e-12)


def test_bad_input():
    v, f = _grid(6)
    with pytest.raises(ValueError, match="order"):
        fair(v, f, [7], order=0)
    with pytest.raises(ValueError, match="iterations"):
        fair(v, f, [7], iterations=0)
    with pytest.raises(MeshError, match="outside"):
        fair(v, f, [7, 99])
    with pytest.raises(ValueError, match="shape"):
        fair(v, f, np.ones(3, bool))
    with pytest.raises(MeshError, match="in no face"):
        fair(np.vstack([v, [[2, 2, 2]]]), f, [len(v)])
    # no fixed vertex anywhere: singular
    with pytest.raises(MeshError, match="not connected to any fixed"):
        fair(v, f, np.arange(len(v)))
    assert np.array_equal(fair(v, f, []), v)


@pytest.mark.parametrize("order", [2, 3])
def test_a_cut_border_does_not_pull_a_plane(order):
    # free vertices next to the left side, which a crease cut open: its one-sided Laplacians
    # are not zero on a plane; left out, the plane (and its triangles) stay as they are
    v, f = _grid(jitter=0.0)
    left = np.isclose(v[:, 0], 0)
    free = np.flatnonzero((v[:, 0] > 0) & (v[:, 0] < 0.3) & (np.abs(v[:, 1] - 0.5) < 0.25))
    pulled = fair(v, f, free, order=order)
    assert np.abs(pulled - v).max() > 1e-3
    kept = fair(v, f, free, order=order, cut=left)
    assert np.abs(kept - v).max() < 1e-12
