"""Fairing Δᵏx = 0 with the cotangent Laplacian."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from surfinpaint.errors import MeshError
from surfinpaint.fill.liepa.fairing import fair, fair_smoothed
from surfinpaint.fill.liepa.refinement import refine_patch
from surfinpaint.fill.liepa.triangulation import minimum_weight_triangulation
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import k_ring


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


def _sliver_hole(jitter: float, seed: int):
    """A hole (4 edge lengths) in a smooth height field over a grid jittered by ``jitter`` of
    its spacing (normal noise: slivers with negative cotangent weights), its triangulated
    and refined flat patch, and the height function."""
    def height(x, y):
        return 0.3 * np.sin(2 * x) * np.cos(2 * y)

    n = 31
    x, y = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n), indexing="ij")
    rng = np.random.default_rng(seed)
    x = x + jitter * rng.standard_normal(x.shape) * (2 / n)
    y = y + jitter * rng.standard_normal(y.shape) * (2 / n)
    v = np.column_stack([x.ravel(), y.ravel(), height(x, y).ravel()])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    f = np.vstack([np.column_stack([a, a + n, a + n + 1]),
                   np.column_stack([a, a + n + 1, a + 1])])
    h = np.linalg.norm(v[f[:, 0]] - v[f[:, 1]], axis=1).mean()
    cut = cut_geodesic_disk(v, f, np.zeros(3), 4 * h)
    tri = minimum_weight_triangulation(cut.vertices, cut.loop, cut.faces)
    new_v, patch = refine_patch(cut.vertices, tri, cut.loop, faces=cut.faces)
    return (np.vstack([cut.vertices, new_v]), np.vstack([cut.faces, patch]),
            np.arange(len(cut.vertices), len(cut.vertices) + len(new_v)), height)


def _height_error(v, free, height):
    return float(np.abs(v[free, 2] - height(v[free, 0], v[free, 1])).mean())


@pytest.mark.parametrize("seed", [3, 4])
def test_intrinsic_operator_fairs_sliver_patches(seed):
    # measured: trilaplacian error 4.3e-2 / 8.3e-2 with cotangent weights, 1.0e-3 / 9.2e-4
    # with the intrinsic Delaunay ones; bilaplacian 2.4e-3 / 8.9e-4 vs 2.2e-4 / 3.0e-4
    v, f, free, height = _sliver_hole(0.45, seed)
    err = {(order, op): _height_error(fair(v, f, free, order=order, operator=op), free, height)
           for order in (2, 3) for op in ("cotan", "intrinsic")}
    assert err[3, "intrinsic"] < 0.05 * err[3, "cotan"]
    assert err[2, "intrinsic"] < 0.5 * err[2, "cotan"]


def test_intrinsic_operator_on_a_regular_grid_fairs_well_too():
    # no slivers (right triangles, flipped where the surface curves): the cotangent
    # operator is a little better here (measured 2.8e-5 vs 5.8e-5 bilaplacian, 3.0e-5 vs
    # 1.2e-4 trilaplacian, on a height field of amplitude 0.3); both follow the surface
    v, f, free, height = _sliver_hole(0.0, 3)
    for order in (2, 3):
        cot = _height_error(fair(v, f, free, order=order), free, height)
        intr = _height_error(fair(v, f, free, order=order, operator="intrinsic"), free,
                             height)
        assert cot < 5e-5 and intr < 2e-4


@pytest.mark.parametrize("order", [2, 3])
def test_intrinsic_operator_keeps_a_plane(order):
    v, f = _grid(seed=5)
    free = _central(v, 0.25)
    # at their place already: a planar triangulation's Laplacian reproduces linear
    # functions (measured 3e-15; 1.6 % of an edge off without the margin of faces that
    # keeps the tufted cover's flips at its border away from the operator's rows)
    out = fair(v, f, free, order=order, operator="intrinsic")
    assert np.abs(out - v).max() < 1e-10
    lifted = v.copy()
    lifted[free, 2] = 0.2
    out = fair(lifted, f, free, order=order, operator="intrinsic")
    assert np.abs(out[:, 2]).max() < 1e-12  # rows sum to zero: z = 0 is the solution


def test_unknown_operator():
    v, f = _grid(6)
    with pytest.raises(ValueError, match="operator"):
        fair(v, f, [7], operator="robust")


def test_clamped_cotangent_laplacian():
    from surfinpaint.geometry.mesh import cotangent_laplacian

    # an acute mesh (equilateral-ish icosphere): clamping changes nothing
    m = trimesh.creation.icosphere(2)
    plain = cotangent_laplacian(m.vertices, m.faces)
    assert abs(cotangent_laplacian(m.vertices, m.faces, nonnegative=True) - plain).max() \
        < 1e-12
    # obtuse corners of the jittered grid: negative weights become zero, and the rows
    # still sum to zero (a lifted plane comes back to z = 0)
    v, f = _grid(jitter=0.45, seed=1)
    lap = cotangent_laplacian(v, f).tocoo()
    clamped = cotangent_laplacian(v, f, nonnegative=True).tocoo()
    off = lap.row != lap.col
    assert (lap.data[off] < 0).any()
    assert (clamped.data[clamped.row != clamped.col] >= 0).all()
    assert np.abs(np.asarray(clamped.sum(axis=1))).max() < 1e-12
    free = _central(v, 0.25)
    lifted = v.copy()
    lifted[free, 2] = 0.2
    assert np.abs(fair(lifted, f, free, order=3, operator="clamped")[:, 2]).max() < 1e-12


@pytest.mark.parametrize("order", [2, 3])
def test_an_exactly_singular_fairing_system_is_a_mesh_error(order, monkeypatch):
    # SuperLU raises on an exactly singular system (no pivoting: geometry.linalg.definite_lu);
    # the caller gets the MeshError a singular system always gave, naming free vertices
    import surfinpaint.fill.liepa.fairing as fairing

    def singular(a):
        raise RuntimeError("Factor is exactly singular")

    monkeypatch.setattr(fairing, "factorized_definite", singular)
    v, f = _grid(6)
    with pytest.raises(MeshError, match="fairing system is singular") as info:
        fair(v, f, [7, 8], order=order)
    assert info.value.vertices == [7, 8]


@pytest.mark.parametrize("order", [1, 2, 3])
def test_fairing_without_pivoting_is_the_pivoted_solve_to_round_off(order, monkeypatch):
    # the systems are definite (the stiffness matrix, and L M⁻¹ L, L M⁻¹ L M⁻¹ L with the
    # fixed vertices out), so SuperLU without pivoting gives what partial pivoting gives
    import scipy.sparse.linalg as spla

    import surfinpaint.fill.liepa.fairing as fairing

    v, f = _grid(12, jitter=0.3)  # slivers: negative cotangent weights
    v[:, 2] = 0.2 * np.sin(3 * v[:, 0]) * np.cos(2 * v[:, 1])  # curved: fairing moves it
    free = np.flatnonzero(np.linalg.norm(v[:, :2] - 0.5, axis=1) < 0.3)
    v[free, 2] = 0.0
    plain = fair(v, f, free, order=order)
    monkeypatch.setattr(fairing, "factorized_definite",
                        lambda a: lambda b: spla.spsolve(a.tocsc(), b))
    pivoted = fair(v, f, free, order=order)
    assert np.abs(plain[free] - v[free]).max() > 1e-3  # the free vertices did move
    np.testing.assert_allclose(plain, pivoted, rtol=0, atol=1e-12)


def _noisy_plane_hole(seed: int, noise: float = 0.05):
    """A jittered grid in z = 0 whose vertices have normal noise of ``noise`` edges, its
    central vertices (free, put back on the plane) and the 3 rings of known vertices around
    them (soft); the grid's spacing h."""
    n = 24
    v, f = _grid(n, 0.2, seed)
    h = 1.0 / (n - 1)
    v[:, 2] = noise * h * np.random.default_rng(seed + 10).standard_normal(len(v))
    free = _central(v, 0.2)
    v[free, 2] = 0.0
    soft = np.setdiff1d(np.flatnonzero(k_ring(f, free, 3, len(v))), free)
    return v, f, free, soft, h


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_smoothing_fill_follows_a_noisy_plane_closer_than_the_bilaplacian(seed):
    # the bilaplacian fill takes the noisy ring's slopes into the hole; the smoothing fill
    # (smoothing length one edge) follows the ring within its noise: measured 0.16-0.62 of
    # the bilaplacian's mean height error on these four seeds
    v, f, free, soft, h = _noisy_plane_hole(seed)
    bilaplacian = np.abs(fair(v, f, free, order=2)[free, 2]).mean()
    smoothed = fair_smoothed(v, f, free, soft, h ** 4)
    assert np.abs(smoothed[free, 2]).mean() < 0.7 * bilaplacian
    outside = np.setdiff1d(np.arange(len(v)), free)
    assert np.array_equal(smoothed[outside], v[outside])  # known vertices never move


def test_smoothing_fill_without_stiffness_is_the_bilaplacian_fill():
    v, f, free, soft, h = _noisy_plane_hole(0)
    # the data terms dominate: the soft vertices are held, the free ones bilaplacian
    np.testing.assert_allclose(fair_smoothed(v, f, free, soft, 1e-12 * h ** 4),
                               fair(v, f, free, order=2), atol=1e-10)


def test_smoothing_fill_keeps_a_plane():
    v, f, free, soft, h = _noisy_plane_hole(0, noise=0.0)
    tilted = v.copy()
    tilted[:, 2] = 0.3 * v[:, 0] - 0.2 * v[:, 1]
    # cotangent weights reproduce linear functions: a plane is its own smoothing
    np.testing.assert_allclose(fair_smoothed(tilted, f, free, soft, (2 * h) ** 4), tilted,
                               atol=1e-12)
