"""Triangle-triangle intersection: known pairs, coplanar cases, shared neighbours, an
independent reference on random pairs, the prefilter against brute force, and a patch pushed
through the surface around it."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import grid_mesh

from surfinpaint.data import sphere, torus
from surfinpaint.geometry.intersection import (
    intersecting_pairs,
    patch_intersects_surroundings,
    self_intersections,
    triangles_intersect,
)


def _pair(a, b, shared=()):
    """Vertices and the two faces of triangles given by corner points; ``shared`` maps a
    corner of b to the corner of a it reuses."""
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    shared = dict(shared)
    vertices = list(a)
    fb = []
    for q in range(3):
        if q in shared:
            fb.append(shared[q])
        else:
            fb.append(len(vertices))
            vertices.append(b[q])
    return np.array(vertices), np.array([[0, 1, 2]]), np.array([fb])


def _hit(a, b, shared=()):
    v, fa, fb = _pair(a, b, shared)
    forward = bool(triangles_intersect(v, fa, fb)[0])
    backward = bool(triangles_intersect(v, fb, fa)[0])
    assert forward == backward, "the test must be symmetric"
    return forward


A = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]


@pytest.mark.parametrize(
    ("b", "expected"),
    [
        ([[0.2, 0.2, -1], [0.2, 0.2, 1], [1, 1, 0.5]], True),     # pierces the interior
        ([[2, 2, -1], [2, 2, 1], [3, 3, 0]], False),              # beside it
        ([[0, 0, 1], [1, 0, 1], [0, 1, 1]], False),               # parallel, above
        ([[0.1, 0.1, 0.5], [0.6, 0.1, 0.5], [0.1, 0.6, -0.5]], True),
        ([[0.5, 0.5, -1], [0.5, 0.5, 1], [2, 2, 0]], True),       # through the hypotenuse
        ([[0.2, 0.2, 0], [2, 0.2, 1], [2, 0.2, -1]], True),       # a corner inside A
        ([[0.7, 0.7, -1], [0.7, 0.7, 1], [2, 2, 0]], False),      # just past the hypotenuse
    ],
)
def test_general_position(b, expected):
    assert _hit(A, b) is expected


@pytest.mark.parametrize(
    ("b", "expected"),
    [
        ([[0.2, 0.2, 0], [1.2, 0.2, 0], [0.2, 1.2, 0]], True),    # overlapping
        ([[2, 0, 0], [3, 0, 0], [2, 1, 0]], False),               # apart
        ([[0.1, 0.1, 0], [0.3, 0.1, 0], [0.1, 0.3, 0]], True),    # inside: no edges cross
        ([[-1, -1, 0], [3, -1, 0], [-1, 3, 0]], True),            # contains A
        ([[1, 1, 0], [0.4, 0.4, 0], [2, 0.5, 0]], True),          # crosses the hypotenuse
        ([[1, 1, 0], [0.51, 0.51, 0], [2, 0.5, 0]], False),       # a hair past it
    ],
)
def test_coplanar(b, expected):
    assert _hit(A, b) is expected


def test_shared_edge():
    # B shares A's edge (1, 2): opposite sides in the plane, folded over, and bent up
    assert not _hit(A, [[1, 0, 0], [0, 1, 0], [1, 1, 0]], {0: 1, 1: 2})
    assert _hit(A, [[1, 0, 0], [0, 1, 0], [0.2, 0.2, 0]], {0: 1, 1: 2})
    assert not _hit(A, [[1, 0, 0], [0, 1, 0], [0.5, 0.5, 1]], {0: 1, 1: 2})
    assert not _hit(A, [[1, 0, 0], [0, 1, 0], [0.2, 0.2, 1e-3]], {0: 1, 1: 2})


def test_shared_vertex():
    p = {0: 0}
    # in the plane: cones apart, cones overlapping
    assert not _hit(A, [[0, 0, 0], [-1, 0, 0], [0, -1, 0]], p)
    assert not _hit(A, [[0, 0, 0], [0, 1, 0], [-1, 0, 0]], {0: 0, 1: 2})
    assert _hit(A, [[0, 0, 0], [1, 1, 0], [-1, 1, 0]], p)
    # out of the plane: above it, through A's interior, through the plane beside A
    assert not _hit(A, [[0, 0, 0], [1, 1, 1], [-1, 1, 1]], p)
    assert _hit(A, [[0, 0, 0], [0.3, 0.3, 1], [0.3, 0.3, -1]], p)
    assert not _hit(A, [[0, 0, 0], [-0.3, -0.3, 1], [-0.3, -0.3, -1]], p)
    # touching A's far edge from the shared corner counts: the overlap is a whole segment
    assert _hit(A, [[0, 0, 0], [0.5, 0.5, 1], [0.5, 0.5, -1]], p)


def test_same_triangle():
    v = np.array(A, float)
    assert triangles_intersect(v, [[0, 1, 2]], [[0, 1, 2]])[0]
    assert triangles_intersect(v, [[0, 1, 2]], [[0, 2, 1]])[0]


def test_degenerate_not_reported():
    v = np.array(A + [[2, 0, 0], [0.2, 0.2, -1], [0.2, 0.2, 1]], float)
    assert not triangles_intersect(v, [[0, 1, 3]], [[4, 5, 2]])[0]


def test_length_mismatch():
    with pytest.raises(ValueError, match="row by row"):
        triangles_intersect(np.eye(3), [[0, 1, 2]], np.zeros((2, 3), int))


def _segment_hits_triangle(p, q, tri, eps=1e-12):
    """Closed segment against closed triangle (Möller–Trumbore), non-coplanar only."""
    e1, e2 = tri[1] - tri[0], tri[2] - tri[0]
    d = q - p
    h = np.cross(d, e2)
    det = e1 @ h
    if abs(det) < eps:
        return False
    s = p - tri[0]
    u = (s @ h) / det
    qv = np.cross(s, e1)
    w = (d @ qv) / det
    t = (e2 @ qv) / det
    return bool(u >= 0 and w >= 0 and u + w <= 1 and 0 <= t <= 1)


def _reference(a, b):
    return any(_segment_hits_triangle(a[i], a[(i + 1) % 3], b) for i in range(3)) or any(
        _segment_hits_triangle(b[i], b[(i + 1) % 3], a) for i in range(3))


def test_random_pairs_match_segment_reference():
    rng = np.random.default_rng(1)
    k = 400
    a = rng.random((k, 3, 3))
    b = rng.random((k, 3, 3)) * 0.8 + 0.1
    v = np.concatenate([a.reshape(-1, 3), b.reshape(-1, 3)])
    fa = np.arange(3 * k).reshape(-1, 3)
    fb = 3 * k + np.arange(3 * k).reshape(-1, 3)
    got = triangles_intersect(v, fa, fb)
    expected = np.array([_reference(a[i], b[i]) for i in range(k)])
    assert 0.2 < expected.mean() < 0.8  # both outcomes are well represented
    np.testing.assert_array_equal(got, expected)


def test_prefilter_matches_brute_force():
    rng = np.random.default_rng(2)
    k = 150
    centres = rng.random((k, 1, 3))
    # mixed sizes so a large triangle has to be found from a small one's side
    sizes = np.where(rng.random(k) < 0.1, 1.5, 0.3)[:, None, None]
    tri = centres + sizes * (rng.random((k, 3, 3)) - 0.5)
    v = tri.reshape(-1, 3)
    f = np.arange(3 * k).reshape(-1, 3)
    fa, fb = f[:60], f[60:]
    i, j = np.meshgrid(np.arange(60), np.arange(k - 60), indexing="ij")
    brute = triangles_intersect(v, fa[i.ravel()], fb[j.ravel()])
    expected = {(int(x), int(y)) for x, y, hit in zip(i.ravel(), j.ravel(), brute,
                                                      strict=True) if hit}
    got = {tuple(map(int, row)) for row in intersecting_pairs(v, fa, fb)}
    assert len(expected) > 10
    assert got == expected
    # within one set: the i < j pairs of the brute force
    i, j = np.triu_indices(k, 1)
    brute = triangles_intersect(v, f[i], f[j])
    assert {tuple(map(int, r)) for r in self_intersections(v, f)} == {
        (int(x), int(y)) for x, y, hit in zip(i, j, brute, strict=True) if hit}


@pytest.mark.parametrize("mesh", ["sphere", "torus", "grid", "bumpy"])
def test_clean_meshes_have_no_self_intersections(mesh):
    if mesh == "sphere":
        v, f = sphere(3)
    elif mesh == "torus":
        v, f = torus(1.0, 0.3, 48, 16)
    else:
        v, f = grid_mesh(20, 20)
        if mesh == "bumpy":
            v = v.copy()
            v[:, 2] = 0.05 * np.sin(9 * v[:, 0]) * np.cos(7 * v[:, 1])
    assert self_intersections(v, f).shape == (0, 2)


def _grid_with_fill():
    """A flat grid; the faces in a disk around its centre play the fill, the rest the ring."""
    v, f = grid_mesh(24, 24)
    centre = np.array([0.5, 0.5, 0.0])
    inside = (np.linalg.norm(v[f].mean(axis=1) - centre, axis=1) < 0.2)
    fill, ring = f[inside], f[~inside]
    interior = np.setdiff1d(np.unique(fill), np.unique(ring))
    return v, fill, ring, interior, centre


def test_flat_fill_is_clean():
    v, fill, ring, _, _ = _grid_with_fill()
    assert patch_intersects_surroundings(v, fill, ring).shape == (0, 2)


def test_pushed_through_patch_is_flagged():
    v, fill, ring, interior, centre = _grid_with_fill()
    bad = v.copy()
    # spread the fill out over the ring and corrugate it through the ring's plane
    bad[interior, :2] = centre[:2] + 1.8 * (v[interior, :2] - centre[:2])
    bad[interior, 2] = np.where(np.arange(len(interior)) % 2 == 0, 0.05, -0.05)
    pairs = patch_intersects_surroundings(bad, fill, ring)
    assert len(pairs) > 0
    assert pairs[:, 0].max() < len(fill) and pairs[:, 1].max() < len(ring)
    # each reported pair really does intersect
    assert triangles_intersect(bad, fill[pairs[:, 0]], ring[pairs[:, 1]]).all()
    # lifting the fill straight up, off the plane, touches the ring only along the loop
    lifted = v.copy()
    lifted[interior, 2] = 0.1
    assert patch_intersects_surroundings(lifted, fill, ring).shape == (0, 2)


def test_fill_through_the_far_side_of_a_sphere():
    # a sphere's cap pushed through to the other side crosses the faces there
    v, f = sphere(3)
    centroid = v[f].mean(axis=1)
    cap = centroid[:, 2] > 0.8
    fill, ring = f[cap], f[~cap]
    interior = np.setdiff1d(np.unique(fill), np.unique(ring))
    bad = v.copy()
    bad[interior, 2] = -1.5
    assert len(patch_intersects_surroundings(bad, fill, ring)) > 0
    assert patch_intersects_surroundings(v, fill, ring).shape == (0, 2)


@pytest.mark.parametrize("amplitude", [0.0, 1e-12, 1e-7, 1e-3, 0.3])
def test_height_fields_never_self_intersect(amplitude):
    # any triangulation of the plane lifted as a graph z = h(x, y) is embedded, however
    # flat: neighbours that are (nearly) coplanar must not be reported
    from scipy.spatial import Delaunay

    rng = np.random.default_rng(3)
    xy = rng.random((400, 2))
    f = Delaunay(xy).simplices
    z = amplitude * (np.sin(7 * xy[:, 0]) * np.cos(5 * xy[:, 1]) + rng.random(len(xy)))
    v = np.column_stack([xy, z]) + [1e3, -2e3, 0]  # off the origin: round-off in play
    assert self_intersections(v, f).shape == (0, 2)


def test_flat_fold_is_flagged():
    # push one interior vertex of a flat triangulation across its neighbourhood: the
    # triangles around it now overlap others in the plane
    from scipy.spatial import Delaunay

    rng = np.random.default_rng(4)
    xy = rng.random((200, 2))
    f = Delaunay(xy).simplices
    v = np.column_stack([xy, np.zeros(len(xy))])
    centre = int(np.argmin(np.linalg.norm(xy - 0.5, axis=1)))
    v[centre, :2] += 0.15
    pairs = self_intersections(v, f)
    assert len(pairs) > 0
    assert np.isin(f[pairs].reshape(len(pairs), -1), centre).any(axis=1).all()
