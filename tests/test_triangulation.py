"""Liepa's minimum-weight triangulation of hole loops."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from surfinpaint.errors import MeshError
from surfinpaint.fill.liepa.triangulation import _planar_cdt, minimum_weight_triangulation
from surfinpaint.geometry.mesh import boundary_loops, face_areas, face_normals, unique_edges


def _convex_polygon(k: int, seed: int = 0) -> np.ndarray:
    """Counter-clockwise convex polygon in the z = 0 plane, irregular angles and radii."""
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0, 2 * np.pi, k))
    # an ellipse keeps it convex for any angles
    return np.column_stack([2.0 * np.cos(t), np.sin(t), np.zeros(k)])


def _shoelace(p: np.ndarray) -> float:
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _directed(faces: np.ndarray) -> set[tuple[int, int]]:
    return {(int(a), int(b)) for f in faces for a, b in ((f[0], f[1]), (f[1], f[2]),
                                                          (f[2], f[0]))}


@pytest.mark.parametrize("k", [3, 4, 7, 40])
def test_convex_polygon_covers_area_with_consistent_orientation(k):
    p = _convex_polygon(k, seed=k)
    loop = np.arange(k)
    tri = minimum_weight_triangulation(p, loop)
    assert tri.shape == (k - 2, 3)
    # exact cover: the triangle areas add up to the polygon's area
    assert face_areas(p, tri).sum() == pytest.approx(_shoelace(p), rel=1e-12)
    # the loop runs counter-clockwise along "existing" faces, so the patch faces clockwise
    assert np.allclose(face_normals(p, tri), [0, 0, -1])
    halves = _directed(tri)
    assert len(halves) == 3 * (k - 2)  # no half-edge twice: consistently oriented
    for i in range(k):
        a, b = int(loop[i]), int(loop[(i + 1) % k])
        assert (b, a) in halves and (a, b) not in halves
    _, _, count = unique_edges(tri)
    assert (count == 1).sum() == k  # only the loop edges are on the boundary


def test_three_edge_hole_gives_one_face():
    m = trimesh.creation.icosphere(2)
    removed = m.faces[5]
    faces = np.delete(m.faces, 5, axis=0)
    loop = boundary_loops(faces)[0]
    tri = minimum_weight_triangulation(m.vertices, loop, faces)
    assert tri.shape == (1, 3)
    # the removed face comes back with its orientation (up to rotation)
    k = int(np.flatnonzero(tri[0] == removed[0])[0])
    assert np.roll(tri[0], -k).tolist() == removed.tolist()


def test_dihedral_weight_restores_removed_octahedron_faces():
    """Two faces of an octahedron sharing edge top–b leave a non-planar quad; the other
    diagonal would cut through the solid (dihedral angles near 90°), so Liepa's weight must
    bring back the original diagonal even though both choices are valid triangulations."""
    m = trimesh.creation.icosahedron()
    v = np.array([[0, 0, 1], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0], [0, 0, -1]],
                 float)
    hull = trimesh.convex.convex_hull(v)
    v, f = hull.vertices, hull.faces
    top = int(np.argmax(v[:, 2]))
    around = np.flatnonzero((f == top).any(axis=1))
    # two faces around `top` that share an edge
    f0, f1 = next((a, b) for a in around for b in around
                  if a < b and len(set(f[a]) & set(f[b])) == 2)
    faces = np.delete(f, [f0, f1], axis=0)
    loop = boundary_loops(faces)[0]
    assert len(loop) == 4
    tri = minimum_weight_triangulation(v, loop, faces)
    assert {tuple(sorted(t)) for t in tri} == {tuple(sorted(f[f0])), tuple(sorted(f[f1]))}
    del m


@pytest.mark.parametrize("reverse", [False, True])
@pytest.mark.parametrize("shift", [0, 7])
def test_orientation_detected_from_faces(reverse, shift):
    m = trimesh.creation.icosphere(3)
    v, f = np.asarray(m.vertices), np.asarray(m.faces)
    d = np.linalg.norm(v - v[0], axis=1)
    faces = f[~(d[f] < 0.45).all(axis=1)]
    loop = boundary_loops(faces)[0]
    given = np.roll(loop, shift)
    if reverse:
        given = given[::-1]
    tri = minimum_weight_triangulation(v, given, faces)
    closed = np.vstack([faces, tri])
    _, _, count = unique_edges(closed)
    assert (count == 2).all()
    assert len(_directed(closed)) == 3 * len(closed)  # consistent orientation
    # same triangulation whatever the caller's orientation and start
    ref = minimum_weight_triangulation(v, loop, faces)
    assert {tuple(sorted(t)) for t in tri} == {tuple(sorted(t)) for t in ref}


def test_large_loop():
    k = 400
    t = np.linspace(0, 2 * np.pi, k, endpoint=False)
    p = np.column_stack([np.cos(t), np.sin(t), 0.2 * np.sin(3 * t)])
    tri = minimum_weight_triangulation(p, np.arange(k))
    assert tri.shape == (k - 2, 3)
    _, _, count = unique_edges(tri)
    assert (count <= 2).all() and (count == 1).sum() == k


def test_bad_loops_raise():
    p = _convex_polygon(5)
    with pytest.raises(MeshError, match="at least 3"):
        minimum_weight_triangulation(p, np.array([0, 1]))
    with pytest.raises(MeshError, match="out of range"):
        minimum_weight_triangulation(p, np.array([0, 1, 9]))
    with pytest.raises(MeshError, match="more than once"):
        minimum_weight_triangulation(p, np.array([0, 1, 2, 1]))
    m = trimesh.creation.icosphere(1)
    with pytest.raises(MeshError, match="not edges of the mesh"):
        minimum_weight_triangulation(m.vertices, np.array([0, 5, 33]), m.faces)


def test_avoids_diagonals_that_are_already_mesh_edges():
    """A hexagonal hole whose vertices 2 and 5 are also joined outside the hole (a bridge
    of two faces): the patch must not add a second copy of edge (2, 5), which the
    unconstrained triangulation of this hexagon uses."""
    t = np.arange(6) * np.pi / 3
    p = np.column_stack([np.cos(t), np.sin(t), np.zeros(6)])
    v = np.vstack([p, 2 * p, [[0, 0, 1], [0, 0, -1]]])
    i = np.arange(6)
    j = (i + 1) % 6
    band = np.concatenate([np.column_stack([i, i + 6, j]), np.column_stack([j, i + 6, j + 6])])
    bridge = np.array([[2, 5, 12], [5, 2, 13]])
    faces = np.vstack([band, bridge])
    hole = np.array([0, 1, 2, 3, 4, 5])
    free = minimum_weight_triangulation(v, hole)  # without the mesh (2, 5) is used
    assert (2, 5) in {tuple(e) for e in unique_edges(free)[0].tolist()}
    tri = minimum_weight_triangulation(v, hole, faces)
    assert tri.shape == (4, 3)
    assert (2, 5) not in {tuple(e) for e in unique_edges(tri)[0].tolist()}
    assert face_areas(v, tri).sum() == pytest.approx(face_areas(v, free).sum())


def test_numpy_fallback_matches_compiled_kernel(monkeypatch):
    from surfinpaint.fill.liepa import triangulation

    m = trimesh.creation.icosphere(3)
    v, f = np.asarray(m.vertices), np.asarray(m.faces)
    d = np.linalg.norm(v - v[5], axis=1)
    faces = f[~(d[f] < 0.5).all(axis=1)]
    loop = boundary_loops(faces)[0]
    compiled = minimum_weight_triangulation(v, loop, faces)
    monkeypatch.setattr(triangulation, "_compiled_dp", lambda: None)
    plain = minimum_weight_triangulation(v, loop, faces)
    assert np.array_equal(compiled, plain)


@pytest.mark.parametrize("seed", range(24))
def test_numpy_fallback_matches_compiled_kernel_on_random_holes(monkeypatch, seed):
    # bumpy holes with and without the surrounding faces (no normal across the loop: NaN),
    # forbidden diagonals, both searches; a grid's straight borders give degenerate triangles
    from surfinpaint.fill.liepa import triangulation

    rng = np.random.default_rng(seed)
    if seed % 4 == 3:
        v, f = _tilted_grid(7)
        v = v + [0, 0, 1e-3] * rng.random((len(v), 1))
    else:
        m = trimesh.creation.icosphere(3)
        v, f = np.asarray(m.vertices) * (1 + 0.05 * rng.random((len(m.vertices), 1))), m.faces
    d = np.linalg.norm(v - v[rng.integers(len(v))], axis=1)
    faces = f[~(d[f] < rng.uniform(0.3, 0.8)).all(axis=1)]
    loop = max(boundary_loops(faces), key=len)
    pairs = loop[rng.integers(0, len(loop), (4, 2))]
    args = (v, loop, faces if seed % 2 else None)
    kwargs = {"search": ("all", "delaunay")[seed % 3 == 0], "avoid": pairs}
    compiled = minimum_weight_triangulation(*args, **kwargs)
    monkeypatch.setattr(triangulation, "_compiled_dp", lambda: None)
    plain = minimum_weight_triangulation(*args, **kwargs)
    assert np.array_equal(compiled, plain)


def _tilted_grid(n: int = 9):
    x, y = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n), indexing="ij")
    v = np.column_stack([x.ravel(), y.ravel(), 0.5 * x.ravel() - 0.2 * y.ravel()])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    f = np.concatenate([np.column_stack([a, a + n, a + n + 1]),
                        np.column_stack([a, a + n + 1, a + 1])])
    return v, f


@pytest.mark.parametrize("with_faces", [False, True])
def test_collinear_border_points_give_no_degenerate_triangles(with_faces):
    """A square hole with several vertices on each side (as cut from a grid): some
    sub-polygons are collinear triples, and the weight must steer around them."""
    v, f = _tilted_grid()
    centre = v[f][:, :, :2].mean(axis=1)
    f = f[np.abs(centre).max(axis=1) > 0.5]  # a 4 x 4 cell square hole: 16 loop edges
    loop = min(boundary_loops(f), key=len)
    assert len(loop) == 16
    tri = minimum_weight_triangulation(v, loop, f if with_faces else None)
    area = face_areas(v, tri)
    assert area.min() > 0.1 * area.mean()
    assert area.sum() == pytest.approx(4 * 0.5**2 * np.sqrt(1 + 0.5**2 + 0.2**2))


def test_lid_over_a_flat_sheet_has_no_degenerate_triangles():
    """Closing the border of a flat sheet folds back by 180° along every loop edge; a
    collinear (zero-area) triangle must still not count as the flatter choice."""
    v, f = _tilted_grid()
    loop = boundary_loops(f)[0]
    tri = minimum_weight_triangulation(v, loop, f)
    area = face_areas(v, tri)
    assert area.min() > 0.1 * area.mean()


def test_search_spaces():
    m = trimesh.creation.icosphere(3)
    v, f = np.asarray(m.vertices), np.asarray(m.faces)
    d = np.linalg.norm(v - v[9], axis=1)
    faces = f[~(d[f] < 0.6).all(axis=1)]
    loop = boundary_loops(faces)[0]
    for search in ("delaunay", "all", "cdt"):
        tri = minimum_weight_triangulation(v, loop, faces, search=search)
        _, _, count = unique_edges(np.vstack([faces, tri]))
        assert (count == 2).all()
    with pytest.raises(ValueError, match="search"):
        minimum_weight_triangulation(v, loop, faces, search="greedy")


def _locally_delaunay(q: np.ndarray, tri: np.ndarray) -> bool:
    """Every edge shared by two triangles has opposite angles summing to at most π: with
    the polygon's edges as the constraints, that is the constrained Delaunay property."""
    opposite: dict = {}
    for f in tri:
        for c in range(3):
            a, b, o = f[c], f[(c + 1) % 3], f[(c + 2) % 3]
            u, w = q[a] - q[o], q[b] - q[o]
            angle = np.arctan2(abs(u[0] * w[1] - u[1] * w[0]), u @ w)
            opposite.setdefault(tuple(sorted((int(a), int(b)))), []).append(angle)
    return all(sum(x) <= np.pi + 1e-9 for x in opposite.values() if len(x) == 2)


@pytest.mark.parametrize("k", [5, 12, 40])
def test_planar_cdt_of_a_convex_polygon_is_its_delaunay_triangulation(k):
    from scipy.spatial import Delaunay

    p = _convex_polygon(k, seed=k + 1)
    tri = _planar_cdt(p, np.zeros((k, k), dtype=bool))
    assert {tuple(sorted(f)) for f in tri.tolist()} == \
        {tuple(sorted(f)) for f in Delaunay(p[:, :2]).simplices.tolist()}
    assert np.allclose(face_normals(p, tri), [0, 0, -1])  # oriented as _solve's faces


def test_planar_cdt_of_a_star_polygon_is_inside_and_locally_delaunay():
    # a non-convex star: the triangles cover exactly its area (none outside it), every
    # loop edge is used once, and every inner edge is locally Delaunay
    k = 30
    t = np.arange(k) * 2 * np.pi / k
    r = np.where(np.arange(k) % 2 == 0, 1.0, 0.45) * (1 + 0.1 * np.sin(3 * t))
    p = np.column_stack([r * np.cos(t), r * np.sin(t), 0.05 * np.cos(2 * t)])
    tri = minimum_weight_triangulation(p, np.arange(k), search="cdt")
    q = p[:, :2]
    assert face_areas(np.column_stack([q, np.zeros(k)]), tri).sum() == \
        pytest.approx(_shoelace(p), rel=1e-9)
    _, _, count = unique_edges(tri)
    assert (count == 1).sum() == k
    assert _locally_delaunay(q, tri)
    # the dynamic program's (max dihedral, area) triangulation is another one
    dp = minimum_weight_triangulation(p, np.arange(k))
    assert {tuple(sorted(f)) for f in dp.tolist()} != {tuple(sorted(f)) for f in tri.tolist()}


def test_planar_cdt_declines_a_loop_whose_projection_is_not_simple():
    # a figure eight with unequal lobes, seen along its area vector (nearly z): it crosses
    # itself, so the search falls back on the dynamic program
    t = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    p = np.column_stack([np.cos(t), np.sin(2 * t) * (1 + 0.6 * np.cos(t)), 0.05 * np.sin(t)])
    assert _planar_cdt(p, np.zeros((24, 24), dtype=bool)) is None
    tri = minimum_weight_triangulation(p, np.arange(24), search="cdt")
    assert tri.shape == (22, 3)
    assert {tuple(sorted(f)) for f in tri.tolist()} == {
        tuple(sorted(f)) for f in minimum_weight_triangulation(p, np.arange(24)).tolist()}


def test_planar_cdt_keeps_off_existing_mesh_edges():
    # the hexagon of test_avoids_diagonals_that_are_already_mesh_edges: its Delaunay
    # triangulation uses the bridge (2, 5), so the CDT is declined and the program avoids it
    t = np.arange(6) * np.pi / 3
    p = np.column_stack([np.cos(t), np.sin(t), np.zeros(6)])
    forbidden = np.zeros((6, 6), dtype=bool)
    forbidden[2, 5] = True
    free = _planar_cdt(p + [[0.0, 0.01 * i, 0.0] for i in range(6)], np.zeros_like(forbidden))
    assert (2, 5) in {tuple(e) for e in unique_edges(free)[0].tolist()}
    assert _planar_cdt(p + [[0.0, 0.01 * i, 0.0] for i in range(6)], forbidden) is None
