"""Graded rectilinear grids: node placement, sampling and interpolation on unequal spacing,
the sampling floor they buy, and the Newton rebuild on their triangles."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from surfinpaint.data import bumpy_disk
from surfinpaint.representation.exports import grid_export, sampling_floor
from surfinpaint.representation.grid import Grid, graded_grid_over, grid_over, interpolate, resample
from surfinpaint.representation.grid_represent import LambdaH, rebuild_grid
from surfinpaint.representation.represent import CoarseGridWarning, load_representation, represent


def tall_bump(rings: int = 10):
    """The finger of test_representation.py: a Gaussian bump of height 1 on the bumpy disk."""
    v, f = bumpy_disk(rings)
    v[:, 2] = np.exp(-(v[:, 0] ** 2 + v[:, 1] ** 2) / 0.3**2)
    return v, f


def test_graded_grid_indices_are_linear_between_nodes_and_extended_past_the_ends():
    g = Grid((0.0, 1.0), 2.0, (3, 2), ((0.0, 1.0, 3.0), (1.0, 3.0)))
    assert g.graded and np.array_equal(g.u, [0.0, 1.0, 3.0]) and np.array_equal(g.v, [1, 3])
    t = g.to_index(np.array([[0.5, 2.0], [2.0, 1.0], [3.0, 3.0], [-1.0, 5.0], [np.nan, 1]]))
    np.testing.assert_allclose(t[:4], [[0.5, 0.5], [1.5, 0.0], [2.0, 1.0], [-1.0, 2.0]])
    assert np.isnan(t[4, 0]) and t[4, 1] == 0.0
    U, V = g.nodes()
    assert U.shape == (3, 2) and U[2, 0] == 3.0 and V[0, 1] == 3.0


def test_resampling_and_interpolation_on_a_graded_grid_are_exact_for_linear_data():
    # a triangulated square with a linear function: barycentric sampling at the graded nodes
    # (tested in uv, not in node indices) and bilinear interpolation back are exact
    n = 9
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n) ** 2, indexing="ij")
    uv = np.column_stack([x.ravel(), y.ravel()])
    k = np.arange(n * n).reshape(n, n)
    a, b, c, d = k[:-1, :-1].ravel(), k[1:, :-1].ravel(), k[1:, 1:].ravel(), k[:-1, 1:].ravel()
    faces = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    values = 2.0 * uv[:, 0] - 3.0 * uv[:, 1] + 0.5
    g = graded_grid_over(uv, faces, 40)
    assert g.graded and g.shape == grid_over(uv, resolution=40).shape
    sampled, inside, _ = resample(uv, faces, values, g)
    U, V = g.nodes()
    assert inside.all()
    np.testing.assert_allclose(sampled, 2.0 * U - 3.0 * V + 0.5, atol=1e-12)
    points = np.random.default_rng(0).random((200, 2))
    np.testing.assert_allclose(interpolate(sampled, g, points),
                               2.0 * points[:, 0] - 3.0 * points[:, 1] + 0.5, atol=1e-12)


def test_graded_nodes_crowd_where_the_parameter_triangles_are_small():
    # a triangulated square of equal triangles: the graded grid is (nearly) uniform
    n = 17
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    uv = np.column_stack([x.ravel(), y.ravel()])
    k = np.arange(n * n).reshape(n, n)
    a, b, c, d = k[:-1, :-1].ravel(), k[1:, :-1].ravel(), k[1:, 1:].ravel(), k[:-1, 1:].ravel()
    faces = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    g = graded_grid_over(uv, faces, 64)
    for spacing in (np.diff(g.u), np.diff(g.v)):
        assert (spacing > 0).all() and spacing.max() / spacing.min() < 1.2
    assert (g.u[0], g.u[-1], g.v[0], g.v[-1]) == (0.0, 1.0, 0.0, 1.0)
    assert g.h == max(np.diff(g.u).max(), np.diff(g.v).max())
    # the tall bump's map squeezes its top into the middle: both axes are finest there
    rep = represent(*tall_bump(), map="rectangular", check=False)
    g = graded_grid_over(rep.uv, rep.faces, 64)
    for axis in (g.u, g.v):
        spacing = np.diff(axis)
        middle = np.abs(0.5 * (axis[1:] + axis[:-1]) - 0.5 * (axis[0] + axis[-1]))
        assert spacing[np.argmin(middle)] < 0.5 * spacing[[0, -1]].min()
    with pytest.raises(ValueError, match="grading"):
        graded_grid_over(uv, faces, 64, grading=1.0)


def test_a_graded_grid_holds_a_tall_bump_that_the_square_grid_of_its_size_misses():
    # measured: at 64 nodes the square grid's samples miss the bump's top by 4.2 % of the
    # diagonal (Hausdorff; mean 0.044 %), the graded grid's by 0.97 % (mean 0.0048 %)
    rep = represent(*tall_bump(), check=False)
    floors = {}
    for spacing in ("uniform", "graded"):
        grid = grid_export(rep, 64, check=False, spacing=spacing)
        floors[spacing] = sampling_floor(grid)
    assert floors["uniform"].floor_hausdorff > 3 * floors["graded"].floor_hausdorff
    assert floors["uniform"].floor_mean > 5 * floors["graded"].floor_mean


def test_a_graded_export_rebuilds_to_its_floor_and_keeps_its_axes_in_the_file(tmp_path):
    rep = represent(*tall_bump(), check=False)
    with warnings.catch_warnings():  # its floor sits at the warning's 1 % (1.03 %, measured)
        warnings.simplefilter("ignore", CoarseGridWarning)
        grid = grid_export(rep, 64, spacing="graded")
    c = grid.check
    assert grid.grid.graded and c.converged
    assert abs(c.mean - c.floor_mean) < 1e-9 * c.diagonal
    grid.save(tmp_path / "graded.npz")
    back = load_representation(tmp_path / "graded.npz")
    assert isinstance(back, LambdaH) and back.grid == grid.grid and back.check == c
    v1, _, _ = rebuild_grid(back)
    v0, _, _ = rebuild_grid(grid)
    np.testing.assert_allclose(v1, v0, atol=1e-12 * c.diagonal)
    # no finite differences on unequal spacing: the paper's rebuilds are refused
    with pytest.raises(ValueError, match="graded"):
        rebuild_grid(grid, "laplacian")
    with pytest.raises(ValueError, match="resolution, not a spacing"):
        represent(*bumpy_disk(6), discretization="grid", spacing="graded", h=0.1)


def test_a_graded_grid_is_drawn_with_its_cells_where_they_are(tmp_path):
    from surfinpaint.app.lambda_h_figures import plot_representation

    rep = represent(*tall_bump(6), discretization="grid", resolution=24, spacing="graded",
                    check=False)
    path = tmp_path / "graded.png"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # headless, and pcolormesh takes the node axes as given
        plot_representation(rep, path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_grading_reaches_the_grid_and_is_refused_without_a_graded_one():
    v, f = tall_bump(6)
    ratios = []
    for grading in (0.0, 0.3, 0.8):
        rep = represent(v, f, discretization="grid", resolution=32, spacing="graded",
                        grading=grading, check=False)
        step = np.diff(rep.grid.u)
        ratios.append(step.max() / step.min())
    # measured: spacing ratios 1, 3.1 and 8.9 (0: equal spacing on the graded code path)
    assert ratios[0] < 1 + 1e-9 and 2 < ratios[1] < ratios[2] - 3
    with pytest.raises(ValueError, match="grading is for spacing='graded'"):
        represent(v, f, discretization="grid", resolution=32, grading=0.3, check=False)
    with pytest.raises(ValueError, match="grading must be in"):
        represent(v, f, discretization="grid", resolution=32, spacing="graded", grading=1.0,
                  check=False)
