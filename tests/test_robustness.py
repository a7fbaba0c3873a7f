"""Awkward but valid meshes are filled without losing anything, by both methods; a failing
conformal fill falls back to the baseline with a warning, never silently.

The corpus is generated here: several components, unreferenced vertices, a one-triangle
hole, a loop pinched at a vertex, a third of a sphere missing, a hole next to the outer
border of an open disk, a closed mesh, and holes one edge apart.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from conftest import grid_mesh

import surfinpaint.fill.conformal.candidates
import surfinpaint.fill.conformal.checks
from surfinpaint import ConformalOptions, GridOptions
from surfinpaint.data import sphere
from surfinpaint.errors import FillError
from surfinpaint.fill.conformal.checks import FOLD_ANGLE
from surfinpaint.fill.holes import find_holes
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.intersection import patch_intersects_surroundings
from surfinpaint.geometry.mesh import (
    edge_faces,
    face_normals,
    k_ring,
    mean_edge_length,
    vertex_normals,
)
from surfinpaint.geometry.validation import nonmanifold_vertices, validate_mesh

METHODS = ["conformal", "fair"]


def _loops(vertices, faces) -> set[frozenset]:
    return {frozenset(h.loop.tolist()) for h in find_holes(vertices, faces)}


def check_filled(vertices, faces, result, *, left_open=None, intersections=True):
    """The invariants every fill keeps.

    Original vertices and faces unchanged and first; finite coordinates; an edge-manifold,
    consistently oriented result without duplicate or degenerate faces; unreferenced
    vertices still unreferenced; reports that add up; no fill triangle crossing the surface;
    and exactly the loops ``left_open`` (default: the outer borders and the skipped holes)
    still open. ``intersections=False`` skips the crossing check (a fill of a bumpy sheet's
    outer border must cross the sheet).
    """
    n, m = len(vertices), len(faces)
    np.testing.assert_array_equal(result.vertices[:n], vertices)
    np.testing.assert_array_equal(result.faces[:m], faces)
    assert result.vertices.shape[1] == 3 and np.isfinite(result.vertices).all()
    before = validate_mesh(vertices, faces)
    after = validate_mesh(result.vertices, result.faces)
    np.testing.assert_array_equal(after.unreferenced_vertices, before.unreferenced_vertices)
    reports = result.reports
    assert sum(r.new_faces for r in reports) == len(result.faces) - m
    assert sum(r.new_vertices for r in reports) == len(result.vertices) - n
    for r in reports:
        if r.skipped:
            assert r.new_faces == 0 and r.method == "none"
        else:
            assert r.new_faces > 0 and r.method in ("conformal", "fair")
            assert r.n_edges == len(r.loop)
    if left_open is None:
        left_open = {frozenset(h.loop.tolist()) for h in find_holes(vertices, faces)
                     if h.is_border}
        left_open |= {frozenset(r.loop.tolist()) for r in reports if r.skipped}
    assert _loops(result.vertices, result.faces) == left_open
    new = result.faces[m:]
    if intersections:
        assert patch_intersects_surroundings(result.vertices, new, faces).shape == (0, 2)
    return after


def _fill(vertices, faces, method, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(vertices, faces, method=method, **kwargs)
    return result, [str(w.message) for w in caught]


def _holey_sphere(subdivisions=2, radius_edges=2.5, centres=(0,)):
    v, f = sphere(subdivisions)
    h = mean_edge_length(v, f)
    cut = cut_holes(v, f, list(centres), [radius_edges * h] * len(centres))
    return cut.vertices, cut.faces


# ----------------------------------------------------------------------------------- corpus


@pytest.mark.parametrize("method", METHODS)
def test_several_components(method):
    a_v, a_f = _holey_sphere()
    b_v, b_f = _holey_sphere(centres=(40,))
    c_v, c_f = sphere(1)  # a closed third component
    v = np.vstack([a_v, b_v + [3, 0, 0], c_v + [0, 3, 0]])
    f = np.vstack([a_f, b_f + len(a_v), c_f + len(a_v) + len(b_v)])
    holes = find_holes(v, f)
    assert len(holes) == 2 and len({h.component for h in holes}) == 2
    result, _ = _fill(v, f, method)
    assert len(result.reports) == 2
    after = check_filled(v, f, result)
    assert after.is_closed and after.n_components == 3


@pytest.mark.parametrize("method", METHODS)
def test_unreferenced_vertices(method):
    v, f = _holey_sphere()
    # three stray vertices: at the front, in the middle and at the end
    strays = np.array([[9.0, 9, 9], [np.pi, -1e6, 0.0], [-0.0, 1e-300, 2.5]])
    at = [0, len(v) // 2 + 1, len(v) + 2]
    keep = np.setdiff1d(np.arange(len(v) + 3), at)
    w = np.empty((len(v) + 3, 3))
    w[keep] = v
    w[at] = strays
    g = keep[f]
    result, _ = _fill(w, g, method)
    after = check_filled(w, g, result)
    assert after.unreferenced_vertices.tolist() == at
    assert after.is_closed


@pytest.mark.parametrize("method", METHODS)
def test_one_triangle_hole(method):
    v, f = sphere(2)
    g = np.delete(f, 17, axis=0)
    result, _ = _fill(v, g, method)
    assert [(r.n_edges, r.new_vertices, r.new_faces) for r in result.reports] == [(3, 0, 1)]
    check_filled(v, g, result)
    # the one new face is the removed one, same orientation (any rotation of its corners)
    new = result.faces[-1]
    assert any(np.array_equal(np.roll(new, k), f[17]) for k in range(3))


def _pinched(v, f, centre):
    around = np.flatnonzero((f == centre).any(axis=1))
    first = around[0]
    opposite = [t for t in around[1:] if len(np.intersect1d(f[t], f[first])) == 1][0]
    return np.delete(f, [first, opposite], axis=0)


@pytest.mark.parametrize("method", METHODS)
def test_pinched_loop(method):
    # two triangles that share only a corner are missing: one loop touching itself there
    v, f = sphere(2)
    centre = 20
    g = _pinched(v, f, centre)
    assert nonmanifold_vertices(g).tolist() == [centre]
    assert sorted(len(h.loop) for h in find_holes(v, g)) == [3, 3]  # split at the corner
    result, messages = _fill(v, g, method)
    after = check_filled(v, g, result)
    for r in result.reports:
        if r.skipped:
            # skipped, with the bow-tie named in a warning
            assert any(str(centre) in m and "bow-tie" in m for m in messages)
    if all(r.skipped is None for r in result.reports):
        assert after.is_closed and after.nonmanifold_vertices.size == 0


@pytest.mark.parametrize("method", METHODS)
def test_a_third_of_a_sphere_missing(method):
    v, f = sphere(3)
    g = f[~(v[f][:, :, 2].mean(axis=1) > 1 / 3)]
    holes = find_holes(v, g)
    assert len(holes) == 1 and not holes[0].is_border
    result, _ = _fill(v, g, method)
    after = check_filled(v, g, result)
    assert after.is_closed
    # the fill is a cap: every new vertex above the cut
    assert (result.vertices[len(v):, 2] > 1 / 3 - 0.05).all()


def _bumpy_grid(nx=14):
    v, f = grid_mesh(nx, nx)
    v = v.copy()
    v[:, 2] = 0.15 * np.sin(2.5 * v[:, 0]) * np.cos(2 * v[:, 1])
    return v, f


@pytest.mark.parametrize("method", METHODS)
def test_hole_next_to_the_outer_border(method):
    v, f = _bumpy_grid(14)
    # the 2-ring of the vertex at grid position (3, 7): its loop is one edge from the border
    centre = 3 * 15 + 7
    near = k_ring(f, [centre], 1, len(v))
    g = f[~near[f].all(axis=1)]
    holes = find_holes(v, g)
    assert [h.is_border for h in holes] == [True, False]
    border_vertices = set(holes[0].loop.tolist())
    assert not border_vertices & set(holes[1].loop.tolist())
    result, _ = _fill(v, g, method)
    assert len(result.reports) == 1
    check_filled(v, g, result)
    # and with include_border the outer border is closed as well (by a sheet that crosses
    # the bumpy one: both span the same loop)
    result, _ = _fill(v, g, "fair", include_border=True)
    assert check_filled(v, g, result, left_open=set(), intersections=False).is_closed


@pytest.mark.parametrize("method", METHODS)
def test_no_holes(method):
    v, f = sphere(2)
    result, messages = _fill(v, f, method)
    assert result.reports == [] and messages == []
    np.testing.assert_array_equal(result.vertices, v)
    np.testing.assert_array_equal(result.faces, f)
    # the result does not share memory with the input
    assert not np.shares_memory(result.vertices, v)


@pytest.mark.parametrize("method", METHODS)
def test_holes_one_edge_apart(method):
    v, f = sphere(3)
    # two 2-ring holes whose centres are 5 edges apart: one edge between their loops
    from scipy.sparse.csgraph import shortest_path

    from surfinpaint.geometry.mesh import vertex_adjacency

    hops = shortest_path(vertex_adjacency(f, len(v)), unweighted=True, indices=[0])[0]
    other = int(np.flatnonzero(hops == 5)[0])
    holes_mask = k_ring(f, [0], 1, len(v)) | k_ring(f, [other], 1, len(v))
    g = f[~holes_mask[f].all(axis=1)]
    loops = find_holes(v, g)
    assert len(loops) == 2
    gap = hops[loops[1].loop].min() - hops[loops[0].loop].max()
    assert gap <= 2
    result, _ = _fill(v, g, method)
    assert check_filled(v, g, result).is_closed


def test_include_border_does_not_double_a_lone_triangle():
    # a loose triangle next to a sphere with a hole: its border loop is the triangle itself,
    # and "filling" it would only add the same face reversed (a duplicate face)
    v, f = _holey_sphere()
    v = np.vstack([v, [[3.0, 0, 0], [4, 0, 0], [3, 1, 0]]])
    f = np.vstack([f, [len(v) - 3, len(v) - 2, len(v) - 1]])
    result, _ = _fill(v, f, "fair", include_border=True)
    lone = frozenset(range(len(v) - 3, len(v)))
    check_filled(v, f, result, left_open={lone})


def _t_junction(n_split=1):
    """A bent grid where one interior edge (a, b) is split into ``n_split + 1`` pieces on one
    side only, as in CAD meshes: a zero-width slit whose loop is a, the split points, b."""
    v, f = _bumpy_grid(6)
    a, b = 3 * 7 + 3, 3 * 7 + 4  # grid positions (3, 3) and (3, 4): an interior edge
    (t,) = [i for i in range(len(f)) if {a, b} <= set(f[i].tolist())][:1]
    row = f[t].tolist()
    k = row.index(a)
    if row[(k + 1) % 3] != b:  # walk the face so that it reads (a, b, apex)
        a, b = b, a
        k = row.index(a)
    apex = row[(k + 2) % 3]
    t_split = np.linspace(0, 1, n_split + 2)[1:-1]
    points = v[a] + t_split[:, None] * (v[b] - v[a])
    ids = [a, *range(len(v), len(v) + n_split), b]
    fan = [[ids[i], ids[i + 1], apex] for i in range(n_split + 1)]
    return np.vstack([v, points]), np.vstack([np.delete(f, t, axis=0), fan]), ids


@pytest.mark.parametrize("n_split", [1, 2])
@pytest.mark.parametrize("method", METHODS)
def test_t_junction_slit(method, n_split):
    # the slit spans no area: a fill could only add zero-area triangles, which the result
    # must not contain (left open with a warning is fine)
    v, f, ids = _t_junction(n_split)
    holes = find_holes(v, f)
    assert sorted(len(h.loop) for h in holes) == [n_split + 2, 24]
    result, messages = _fill(v, f, method)
    check_filled(v, f, result)
    if any(r.skipped for r in result.reports):
        assert messages


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"method": "magic"}, "unknown method"),
        ({"neighbourhood_rings": 0}, "neighbourhood_rings"),
        ({"max_hole_edges": -1}, "max_hole_edges"),
        ({"holes": [0.5]}, "0.5"),
        ({"holes": [3]}, "out of range"),
    ],
)
def test_bad_parameters(kwargs, match):
    v, f = _holey_sphere()
    with pytest.raises(ValueError, match=match):
        fill_holes(v, f, **({"method": "fair"} | kwargs))


def test_explicit_loops_in_any_direction():
    v, f = _holey_sphere(centres=(0, int(np.argmin(sphere(2)[0] @ sphere(2)[0][0]))))
    loops = [h.loop for h in find_holes(v, f)]
    result, _ = _fill(v, f, "fair", holes=[loops[1][::-1], np.roll(loops[0], 3)])
    assert check_filled(v, f, result).is_closed


# ------------------------------------------------------------------------- conformal fallback


def _force(monkeypatch, fake):
    """Replace the λ-H pass of both discretizations by ``fake`` (the grid pass's
    signature: vertices, patch_faces, n_fill_faces, moving, options -> positions, λ-H
    grids, reconstruction used); the selection rule is left alone."""
    candidates = surfinpaint.fill.conformal.candidates
    monkeypatch.setattr(candidates, "inpaint_patch", fake)

    def on_mesh(vertices, faces, loop, fill_faces, moving, *, rings=4, **kwargs):
        patch, used = candidates.hole_patch(faces, loop, fill_faces, rings)
        positions, _, _ = fake(vertices, patch, len(fill_faces), moving, None)
        return positions, patch, used, None

    monkeypatch.setattr(candidates, "inpaint_patch_on_mesh", on_mesh)


def _fallback_case():
    return _holey_sphere(subdivisions=3, radius_edges=4)


def test_fallback_when_the_conformal_fill_raises(monkeypatch):
    def fake(*args, **kwargs):
        raise FillError("forced failure")

    _force(monkeypatch, fake)
    v, f = _fallback_case()
    with pytest.warns(UserWarning, match="forced failure"):
        result = fill_holes(v, f, method="conformal")
    (r,) = result.reports
    assert r.requested == "conformal" and r.method == "fair"
    assert "forced failure" in r.fallback
    assert check_filled(v, f, result).is_closed
    # the same fill as asking for the faired fill the self-check chose directly
    direct = fill_holes(v, f, method="fair", fair_order=r.fair_order)
    np.testing.assert_allclose(result.vertices, direct.vertices, atol=1e-12)


def test_fallback_when_the_grid_is_too_large():
    # the grid discretization's own failure
    v, f = _fallback_case()
    with pytest.warns(UserWarning, match="max_nodes"):
        result = fill_holes(v, f, method="conformal", options=ConformalOptions(
            discretization="grid", grid=GridOptions(max_nodes=10)))
    (r,) = result.reports
    assert r.method == "fair" and "max_nodes" in r.fallback
    check_filled(v, f, result)


def _moving_fake(transform):
    def fake(vertices, patch_faces, n_fill_faces, moving, options):
        return transform(vertices, patch_faces, n_fill_faces, moving), None, "fake"
    return fake


def _assert_falls_back(monkeypatch, transform):
    """The λ-H pass replaced by ``transform``: the hole gets the faired fill, with a
    warning and the reason in the report, and the result is a valid closed mesh."""
    _force(monkeypatch, _moving_fake(transform))
    v, f = _fallback_case()
    with pytest.warns(UserWarning):
        result = fill_holes(v, f, method="conformal")
    (r,) = result.reports
    assert r.method == "fair" and r.fallback
    check_filled(v, f, result)


def test_fallback_on_non_finite_positions(monkeypatch):
    def nan(vertices, patch_faces, n_fill_faces, moving):
        out = vertices[moving].copy()
        out[len(out) // 2] = np.nan
        return out

    _assert_falls_back(monkeypatch, nan)


def _assert_damped_or_falls_back(monkeypatch, transform, fold_angle=FOLD_ANGLE):
    """The λ-H pass replaced by ``transform``, whose fill fails the checks: what is written
    is either the faired fill (with the reason) or the λ-H fill damped toward its start
    until it passes them (``damping`` < 1), never the failing fill itself."""
    _force(monkeypatch, _moving_fake(transform))
    v, f = _fallback_case()
    result = fill_holes(v, f, method="conformal", options=ConformalOptions(select=False))
    (r,) = result.reports
    if r.method == "fair":
        assert r.fallback
    else:
        assert r.method == "conformal" and 0 < r.diagnostics.damping < 1
    check_filled(v, f, result)
    assert patch_intersects_surroundings(result.vertices, result.new_faces, f).shape == (0, 2)
    # no fold-over at any edge of the fill (the λ-H check's own definition, FOLD_ANGLE)
    normals = face_normals(result.vertices, result.faces)
    _, owner, count = edge_faces(result.faces)
    pairs = owner[(count == 2) & (owner.max(axis=1) >= len(f))]
    cos = np.einsum("ij,ij->i", normals[pairs[:, 0]], normals[pairs[:, 1]])
    assert (cos > np.cos(np.radians(fold_angle)) - 1e-12).all()
    return r


def test_folded_positions_are_damped_not_written(monkeypatch):
    # the fill mirrored across the plane z = 0, which holds the hole's axis: every fill
    # triangle is flipped against the surface around it
    def fold(vertices, patch_faces, n_fill_faces, moving):
        return vertices[moving] * np.array([1.0, 1.0, -1.0])

    r = _assert_damped_or_falls_back(monkeypatch, fold)
    assert r.method == "conformal"  # 15 % of the way to the mirror image folds nothing


def test_patch_through_the_surroundings_is_damped_or_falls_back(monkeypatch):
    _assert_damped_or_falls_back(monkeypatch, _spread)


def _spread(vertices, patch_faces, n_fill_faces, moving):
    # the fill spread out over the surface around the hole, corrugated through it: no fold
    # between neighbouring triangles is needed for it to cross the ring
    p = vertices[moving]
    loop_ids = np.setdiff1d(np.unique(patch_faces[:n_fill_faces]), moving)
    c = vertices[loop_ids].mean(axis=0)
    normal = c / np.linalg.norm(c)
    tangent = (p - c) - np.outer((p - c) @ normal, normal)
    sign = np.where(np.arange(len(p)) % 2 == 0, 1.0, -1.0)[:, None]
    return c + 2.2 * tangent + 0.06 * sign * normal


def test_crossing_patch_is_caught_without_the_fold_check(monkeypatch):
    # the same crossing patch, with the fold test switched off: the intersection test of the
    # patch against its surrounding rings has to catch it by itself
    monkeypatch.setattr(surfinpaint.fill.conformal.checks, "FOLD_ANGLE", 180.0)
    _assert_damped_or_falls_back(monkeypatch, _spread, fold_angle=180.0)


def test_conformal_fill_faces_the_same_way_as_the_surface():
    # normals of the fill agree with the surface around it (no hidden inside-out patch)
    v, f = _holey_sphere(subdivisions=3, radius_edges=5)
    result, _ = _fill(v, f, "conformal")
    check_filled(v, f, result)
    normals = vertex_normals(result.vertices, result.faces)
    new = np.arange(len(v), len(result.vertices))
    outward = result.vertices[new] / np.linalg.norm(result.vertices[new], axis=1)[:, None]
    assert (np.einsum("ij,ij->i", normals[new], outward) > 0.5).all()
