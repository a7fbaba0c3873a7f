"""Liepa refinement of hole patches and batch Delaunay flips."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from scipy.spatial import Delaunay

from surfinpaint.errors import MeshError
from surfinpaint.fill.liepa.refinement import boundary_scales, delaunay_flip, refine_patch
from surfinpaint.fill.liepa.triangulation import minimum_weight_triangulation
from surfinpaint.geometry.mesh import boundary_loops, face_areas, mean_edge_length, unique_edges


def _edge_set(faces):
    e, _, _ = unique_edges(faces)
    return {tuple(x) for x in e.tolist()}


def _min_angles(p, f):
    t = p[f]
    out = []
    for k in range(3):
        u = t[:, (k + 1) % 3] - t[:, k]
        w = t[:, (k + 2) % 3] - t[:, k]
        c = np.einsum("ij,ij->i", u, w) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1)
        out.append(np.degrees(np.arccos(np.clip(c, -1, 1))))
    return np.min(out, axis=0)


def test_flips_turn_a_fan_into_the_delaunay_triangulation():
    # points in convex position on an ellipse (random angles: no four co-circular, so the
    # Delaunay triangulation is unique)
    rng = np.random.default_rng(3)
    k = 24
    t = np.sort(rng.uniform(0, 2 * np.pi, k))
    p = np.column_stack([1.5 * np.cos(t), np.sin(t), np.zeros(k)])
    assert len(Delaunay(p[:, :2]).convex_hull) == k  # all on the hull
    fan = np.column_stack([np.zeros(k - 2, int), np.arange(1, k - 1), np.arange(2, k)])
    hull = np.column_stack([np.arange(k), np.roll(np.arange(k), -1)])
    flipped = delaunay_flip(p, fan, fixed_edges=hull)
    assert _edge_set(flipped) == _edge_set(Delaunay(p[:, :2]).simplices)
    assert face_areas(p, flipped).sum() == pytest.approx(face_areas(p, fan).sum())
    # orientation kept: all normals still +z
    n = np.cross(p[flipped[:, 1]] - p[flipped[:, 0]], p[flipped[:, 2]] - p[flipped[:, 0]])
    assert (n[:, 2] > 0).all()


def test_planar_patch_matches_boundary_scale():
    k = 60
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    p = np.column_stack([np.cos(t), np.sin(t), np.zeros(k)])
    h = np.linalg.norm(p[1] - p[0])
    loop = np.arange(k)
    tri = minimum_weight_triangulation(p, loop)
    new_v, patch = refine_patch(p, tri, loop)
    allv = np.vstack([p, new_v])
    # stays planar, inside the disk, and covers it exactly
    assert np.abs(new_v[:, 2]).max() == 0
    assert np.linalg.norm(new_v[:, :2], axis=1).max() < 1
    assert face_areas(allv, patch).sum() == pytest.approx(face_areas(p, tri).sum(), rel=1e-12)
    e, _, count = unique_edges(patch)
    assert (count <= 2).all()
    loop_edges = np.sort(np.column_stack([loop, np.roll(loop, -1)]), axis=1)
    assert {tuple(x) for x in e[count == 1].tolist()} == {tuple(x) for x in loop_edges.tolist()}
    # the density follows σ = h: interior edges near h, none long
    length = np.linalg.norm(allv[e[count == 2, 0]] - allv[e[count == 2, 1]], axis=1)
    assert 0.8 * h < length.mean() < 1.25 * h
    assert length.max() < 2.0 * h
    # Delaunay relaxation keeps the triangles reasonable (measured: smallest angle 18°)
    assert _min_angles(allv, patch).min() > 12


def test_patch_on_sphere_hole_matches_mesh_density():
    m = trimesh.creation.icosphere(4)
    v, f = np.asarray(m.vertices), np.asarray(m.faces)
    d = np.linalg.norm(v - v[0], axis=1)
    faces = f[~(d[f] < 0.6).all(axis=1)]
    loop = boundary_loops(faces)[0]
    tri = minimum_weight_triangulation(v, loop, faces)
    new_v, patch = refine_patch(v, tri, loop, faces=faces)
    allv = np.vstack([v, new_v])
    target = mean_edge_length(v, f)
    assert mean_edge_length(allv, patch) == pytest.approx(target, rel=0.15)
    closed = np.vstack([faces, patch])
    _, _, count = unique_edges(closed)
    assert (count == 2).all()  # closes the hole, edge-manifold
    # Liepa's refinement only inserts centroids: new vertices stay on the flat patch
    assert np.linalg.norm(new_v, axis=1).max() < 1
    # boundary scale is the mean edge length at the loop
    assert boundary_scales(v, faces, loop).mean() == pytest.approx(target, rel=0.1)


def test_scales_argument_controls_density():
    k = 30
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    p = np.column_stack([np.cos(t), np.sin(t), np.zeros(k)])
    loop = np.arange(k)
    tri = minimum_weight_triangulation(p, loop)
    coarse, _ = refine_patch(p, tri, loop, scales=np.full(k, 0.4))
    fine, _ = refine_patch(p, tri, loop, scales=np.full(k, 0.1))
    assert len(fine) > 4 * len(coarse)


def test_bad_input():
    p = np.eye(3)
    tri = np.array([[2, 1, 0]])
    with pytest.raises(MeshError, match="outside"):
        refine_patch(p, np.array([[0, 1, 5]]), np.array([0, 1, 2]))
    with pytest.raises(ValueError, match="density"):
        refine_patch(p, tri, np.array([0, 1, 2]), density=0)
    with pytest.raises(ValueError, match="scales"):
        refine_patch(p, tri, np.array([0, 1, 2]), scales=np.ones(2))
    # a single triangle within scale: nothing to do
    new_v, patch = refine_patch(p, tri, np.array([0, 1, 2]), scales=np.full(3, 10.0))
    assert new_v.shape == (0, 3) and patch.tolist() == tri.tolist()


def test_compiled_flips_match_the_numpy_rounds(monkeypatch):
    # a refined patch on a regular sphere: many co-circular quads and equal scores, where the
    # ranks and tie-breaks of the two implementations must agree exactly
    import surfinpaint.fill.liepa.refinement as refinement

    m = trimesh.creation.icosphere(3)
    faces = m.faces[np.linalg.norm(m.triangles_center - m.vertices[0], axis=1) > 0.5]
    loop = max(boundary_loops(faces), key=len)
    patch = minimum_weight_triangulation(m.vertices, loop, faces)
    calls = []
    original = refinement.delaunay_flip

    def record(*args, **kwargs):
        calls.append((args, kwargs))
        return original(*args, **kwargs)

    monkeypatch.setattr(refinement, "delaunay_flip", record)
    refine_patch(m.vertices, patch, loop, faces=faces)
    monkeypatch.undo()
    assert calls
    for args, kwargs in calls:
        compiled = delaunay_flip(*args, **kwargs)
        monkeypatch.setattr(refinement, "_FLIP_KERNEL", [None])  # the numpy rounds
        plain = delaunay_flip(*args, **kwargs)
        monkeypatch.undo()
        assert np.array_equal(compiled, plain)


def _regular_triangulation(seed: int):
    """A random regular (weighted Delaunay) triangulation of jittered points, lifted off the
    plane: far from Delaunay in 3D, with co-circular quads when the points sit on a grid."""
    from scipy.spatial import ConvexHull

    rng = np.random.default_rng(seed)
    n = int(rng.integers(5, 40))
    xy = rng.random((n, 2))
    if seed % 3 == 0:  # near a grid: ties between equal scores
        xy = np.round(xy * 4) / 4 + 1e-3 * rng.random((n, 2))
    hull = ConvexHull(np.column_stack([xy, (xy**2).sum(1) + rng.random(n) * (seed % 4)]))
    low = hull.simplices[hull.equations[:, 2] < 0]
    a, b, c = (xy[low[:, k]] for k in range(3))
    ccw = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    faces = np.where(ccw[:, None] > 0, low, low[:, [0, 2, 1]]).astype(np.int64)
    z = rng.normal(0, [0.0, 0.05, 0.3, 1.0][seed % 4], n)
    return np.column_stack([xy, z]), faces, rng


@pytest.mark.parametrize("seed", range(60))
def test_compiled_flips_match_the_numpy_rounds_on_random_triangulations(monkeypatch, seed):
    # the compiled kernel pairs half-edges and picks winners without the numpy rounds' sorts:
    # random cases with fixed and forbidden edges, round caps, equal scores and winners that
    # would make the same new edge (about one case in six) must give the same faces
    import surfinpaint.fill.liepa.refinement as refinement

    p, faces, rng = _regular_triangulation(seed)
    edges = unique_edges(faces)[0]
    forbidden = rng.integers(0, len(p), (5, 2))
    options = {"fixed_edges": edges[rng.random(len(edges)) < 0.2],
               "forbidden_edges": forbidden[forbidden[:, 0] != forbidden[:, 1]],
               "max_rounds": [1, 2, 1000][seed % 3]}
    compiled = delaunay_flip(p, faces, **options)
    monkeypatch.setattr(refinement, "_FLIP_KERNEL", [None])  # the numpy rounds
    plain = delaunay_flip(p, faces, **options)
    assert np.array_equal(compiled, plain)
