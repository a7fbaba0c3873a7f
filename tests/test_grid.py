"""Regular grids: placement, barycentric resampling and interpolation back at points."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_parameterization import grid_mesh

from surfinpaint.representation.grid import Grid, grid_over, interpolate, locate_nodes, resample


def test_grid_over_resolution_and_spacing():
    uv = np.array([[1.0, 2.0], [3.0, 3.0]])
    g = grid_over(uv, resolution=9)
    assert g.h == pytest.approx(0.25)
    assert g.shape == (9, 5)
    assert g.origin == (1.0, 2.0)
    assert g.u[-1] == pytest.approx(3.0) and g.v[-1] == pytest.approx(3.0)
    g2 = grid_over(uv, h=0.3, margin=0.1)
    assert g2.origin == pytest.approx((0.9, 1.9))
    assert g2.u[-1] >= 3.1 - 1e-12 and g2.v[-1] >= 3.1 - 1e-12
    U, V = g2.nodes()
    assert U.shape == g2.shape and V[0, 1] - V[0, 0] == pytest.approx(0.3)


@pytest.mark.parametrize("kw", [{}, {"h": 0.1, "resolution": 5}, {"resolution": 1},
                                {"h": -1.0}])
def test_grid_over_rejects_bad_parameters(kw):
    with pytest.raises(ValueError):
        grid_over(np.array([[0.0, 0.0], [1.0, 1.0]]), **kw)


def test_resample_reproduces_linear_functions_exactly():
    uv, f = grid_mesh(23, 17, extent=(0.0, 1.3, -0.2, 0.8), jitter=0.35)
    values = np.column_stack([2 * uv[:, 0] - 3 * uv[:, 1] + 1, uv[:, 1], np.ones(len(uv))])
    g = grid_over(uv, resolution=97, margin=0.05)
    sampled, inside, face_index = resample(uv, f, values, g)
    U, V = g.nodes()
    expect_inside = (U >= 0) & (U <= 1.3) & (V >= -0.2) & (V <= 0.8)
    # nodes within round-off of the border may go either way
    border = (np.abs(U) < 1e-9) | (np.abs(U - 1.3) < 1e-9) | (np.abs(V + 0.2) < 1e-9) \
        | (np.abs(V - 0.8) < 1e-9)
    assert np.array_equal(inside[~border], expect_inside[~border])
    assert np.allclose(sampled[inside, 0], (2 * U - 3 * V + 1)[inside], atol=1e-12)
    assert np.allclose(sampled[inside, 1], V[inside], atol=1e-12)
    assert np.all(np.isnan(sampled[~inside]))
    assert np.all(face_index[inside] >= 0) and np.all(face_index[~inside] == -1)
    # the node really lies in the triangle it reports
    i, j = np.argwhere(inside)[123]
    tri = uv[f[face_index[i, j]]]
    p = np.array([U[i, j], V[i, j]])
    lam = np.linalg.solve(np.vstack([tri.T, np.ones(3)]), np.append(p, 1.0))
    assert np.all(lam > -1e-9)


def test_resample_scalar_and_chunking(monkeypatch):
    import surfinpaint.representation.grid as grid_module

    uv, f = grid_mesh(11, jitter=0.3)
    g = grid_over(uv, resolution=41)
    full, inside, _ = resample(uv, f, uv[:, 0], g)
    monkeypatch.setattr(grid_module, "_CHUNK", 7)  # many tiny chunks
    chunked, inside2, _ = resample(uv, f, uv[:, 0], g)
    assert full.shape == g.shape
    assert np.array_equal(inside, inside2)
    assert np.allclose(full[inside], chunked[inside])


def test_interpolate_bilinear_is_exact_for_bilinear_functions():
    g = Grid((-1.0, 0.5), 0.1, (21, 13))
    U, V = g.nodes()
    f = lambda u, v: 1.0 + 2.0 * u - v + 3.0 * u * v  # noqa: E731
    rng = np.random.default_rng(1)
    pts = np.column_stack([rng.uniform(-1.0, 1.0, 500), rng.uniform(0.5, 1.7, 500)])
    for order in (1, 3):
        got = interpolate(f(U, V), g, pts, order=order)
        assert np.allclose(got, f(pts[:, 0], pts[:, 1]), atol=1e-12)


def test_interpolate_bicubic_is_exact_for_quadratics_and_falls_back_near_nan():
    g = Grid((0.0, 0.0), 0.25, (17, 17))
    U, V = g.nodes()
    q = lambda u, v: u * u - 2 * u * v + 0.5 * v * v + u  # noqa: E731
    vals = q(U, V)
    pts = np.array([[1.3, 2.2], [2.05, 0.6], [3.1, 3.3]])
    cubic = interpolate(vals, g, pts, order=3)
    assert np.allclose(cubic, q(pts[:, 0], pts[:, 1]), atol=1e-12)
    linear = interpolate(vals, g, pts, order=1)
    assert not np.allclose(linear, q(pts[:, 0], pts[:, 1]), atol=1e-6)
    holed = vals.copy()
    holed[4, 10] = np.nan  # inside the 4×4 stencil of the first point, not its cell
    near = interpolate(holed, g, pts[:1], order=3)
    assert near[0] == pytest.approx(linear[0])
    holed[5, 8] = np.nan  # a corner of the first point's cell
    assert np.isnan(interpolate(holed, g, pts[:1], order=1)[0])


def test_interpolate_vector_values_and_off_grid_points():
    g = Grid((0.0, 0.0), 1.0, (3, 3))
    U, V = g.nodes()
    vals = np.stack([U, V, U + V], axis=-1)
    out = interpolate(vals, g, np.array([[0.5, 1.5], [2.0, 2.0], [2.5, 0.0], [np.nan, 0]]))
    assert out.shape == (4, 3)
    assert np.allclose(out[0], [0.5, 1.5, 2.0]) and np.allclose(out[1], [2.0, 2.0, 4.0])
    assert np.all(np.isnan(out[2:]))
    with pytest.raises(ValueError, match="order"):
        interpolate(vals, g, np.zeros((1, 2)), order=2)


# ------------------------------------------------------------------- C1 (Clough–Tocher)


def _quadratic(uv):
    u, v = uv[:, 0], uv[:, 1]
    value = 1 + 2 * u - 3 * v + u * u - 2 * u * v + 0.7 * v * v
    grad = np.stack([2 + 2 * u - 2 * v, -3 - 2 * u + 1.4 * v], axis=1)
    return value, grad


def _locate(uv, f, points):
    """Brute-force containing triangle of each point (small meshes only)."""
    tri = uv[f]
    out = np.full(len(points), -1)
    for k, p in enumerate(points):
        t1, t2, r = tri[:, 0] - tri[:, 2], tri[:, 1] - tri[:, 2], p - tri[:, 2]
        det = t1[:, 0] * t2[:, 1] - t2[:, 0] * t1[:, 1]
        b1 = (r[:, 0] * t2[:, 1] - r[:, 1] * t2[:, 0]) / det
        b2 = (t1[:, 0] * r[:, 1] - t1[:, 1] * r[:, 0]) / det
        inside = (b1 >= -1e-12) & (b2 >= -1e-12) & (1 - b1 - b2 >= -1e-12)
        out[k] = np.flatnonzero(inside)[0]
    return out


def test_vertex_gradients_and_clough_tocher_reproduce_quadratics():
    from surfinpaint.representation.clough_tocher import clough_tocher, vertex_gradients

    uv, f = grid_mesh(12, extent=(0.0, 1.0, 0.0, 1.0), jitter=0.3)
    value, grad = _quadratic(uv)
    est = vertex_gradients(uv, f, value)
    assert est.shape == (len(uv), 2, 1)
    assert np.abs(est[:, :, 0] - grad).max() < 1e-5  # border vertices included
    g = grid_over(uv, resolution=61)
    _, inside, face_index = resample(uv, f, value, g)
    U, V = g.nodes()
    pts = np.column_stack([U[inside], V[inside]])
    exact = _quadratic(pts)[0]
    got = clough_tocher(uv, f, value, grad[:, :, None], face_index[inside], pts)[:, 0]
    assert np.abs(got - exact).max() < 1e-12
    # through the vertex values
    at_vertices = clough_tocher(uv, f, value, est, _locate(uv, f, uv), uv)[:, 0]
    assert np.abs(at_vertices - value).max() < 1e-12
    smooth, inside2, _ = resample(uv, f, value, g, interpolant="clough-tocher")
    linear, _, _ = resample(uv, f, value, g)
    assert np.array_equal(inside, inside2)
    assert np.abs(smooth[inside] - exact).max() < 1e-5
    assert np.abs(linear[inside] - exact).max() > 1e-3
    with pytest.raises(ValueError, match="interpolant"):
        resample(uv, f, value, g, interpolant="cubic")


def test_clough_tocher_is_c1_across_edges_and_converges_as_h_cubed():
    from surfinpaint.representation.clough_tocher import clough_tocher, vertex_gradients

    fun = lambda p: np.sin(3 * p[:, 0]) * np.cos(2 * p[:, 1])  # noqa: E731
    uv, f = grid_mesh(9, extent=(0.0, 1.0, 0.0, 1.0), jitter=0.3)
    grads = vertex_gradients(uv, f, fun(uv))
    # derivative across interior edges, one-sided on both sides of the edge's midpoint
    from surfinpaint.representation.clough_tocher import face_neighbours

    interior = np.flatnonzero(face_neighbours(f)[:, 2] >= 0)  # edge (f[t, 0], f[t, 1])
    assert len(interior) > 50
    jumps = {}
    for kind in ("clough-tocher", "linear"):
        worst = 0.0
        for a, b in f[interior[::10], :2]:
            m = (uv[a] + uv[b]) / 2
            e = uv[b] - uv[a]
            normal = np.array([-e[1], e[0]]) / np.linalg.norm(e)
            eps = 1e-5
            pts = np.array([m - eps * normal, m, m + eps * normal])
            if kind == "linear":
                tri = _locate(uv, f, pts)
                vals = []
                for p, t in zip(pts, tri, strict=True):
                    A = np.vstack([uv[f[t]].T, np.ones(3)])
                    vals.append(np.linalg.solve(A, np.append(p, 1.0)) @ fun(uv[f[t]]))
                vals = np.array(vals)
            else:
                vals = clough_tocher(uv, f, fun(uv), grads, _locate(uv, f, pts), pts)[:, 0]
            worst = max(worst, abs((vals[2] - vals[1]) - (vals[1] - vals[0])) / eps)
        jumps[kind] = worst
    assert jumps["clough-tocher"] < 1e-3 and jumps["linear"] > 1e-2
    errors = []
    for n in (9, 17, 33):
        uv, f = grid_mesh(n, extent=(0.0, 1.0, 0.0, 1.0), jitter=0.3)
        g = grid_over(uv, resolution=121)
        U, V = g.nodes()
        exact = fun(np.column_stack([U.ravel(), V.ravel()])).reshape(U.shape)
        smooth, inside, _ = resample(uv, f, fun(uv), g, interpolant="clough-tocher")
        linear, _, _ = resample(uv, f, fun(uv), g)
        errors.append(np.abs(smooth - exact)[inside].max())
        assert errors[-1] < np.abs(linear - exact)[inside].max() / 5
    assert errors[0] / errors[1] > 5 and errors[1] / errors[2] > 5  # ~8: O(h³)


def test_located_nodes_are_the_barycentric_combinations_of_their_triangles():
    # random triangles in node units, some overlapping, some off the grid, one degenerate
    rng = np.random.default_rng(3)
    t = rng.uniform(-3, 14, size=(30, 2))
    faces = rng.integers(0, 30, size=(25, 3))
    faces[0] = [0, 0, 1]
    t[2:5] = [[0.0, 0.0], [8.0, 4.0], [4.0, 2.0]]  # exactly on a line: weights ±inf off it
    faces[1] = [2, 3, 4]
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # read as outside, not warned about
        index, weights = locate_nodes(t, faces, (12, 10))
    ii, jj = np.divmod(np.arange(120), 10)
    nodes = np.column_stack([ii, jj]).astype(float)
    hit = index >= 0
    # inside: weights sum to one, are non-negative and give back the node
    tri = t[faces[index[hit]]]
    np.testing.assert_allclose(weights[hit].sum(1), 1.0, atol=1e-12)
    assert (weights[hit] >= -1e-10).all()
    np.testing.assert_allclose(np.einsum("ij,ijk->ik", weights[hit], tri), nodes[hit],
                               atol=1e-9)
    assert np.isnan(weights[~hit]).all()
    # a node is missed exactly when no non-degenerate triangle contains it (brute force)
    a, b, c = (t[faces[:, k]][None] for k in range(3))
    p = nodes[:, None]

    def cross(u, v):
        return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

    area = cross(b - a, c - a)
    s1, s2, s3 = cross(b - a, p - a), cross(c - b, p - b), cross(a - c, p - c)
    inside = (area != 0) & (((s1 >= 0) & (s2 >= 0) & (s3 >= 0))
                            | ((s1 <= 0) & (s2 <= 0) & (s3 <= 0)))
    np.testing.assert_array_equal(hit, inside.any(1))
    assert 0 < hit.sum() < 120
