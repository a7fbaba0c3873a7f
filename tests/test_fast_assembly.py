"""The faster assemblies of the self-check's hot paths give the same bits as the code they
replaced (issue 15: the self-check's cost; its results must not change)."""

import numpy as np
import pytest
import scipy.sparse as sp
import trimesh

from surfinpaint.geometry import mesh
from surfinpaint.geometry.closest_point import closest_point_on_triangles
from surfinpaint.geometry.linalg import laplacian_from_weights
from surfinpaint.geometry.metrics import _TriangleIndex


def scipy_chain(i, j, w, n):
    """The assembly ``cotangent_laplacian`` used before ``laplacian_from_weights``."""
    off = sp.coo_matrix((w, (i, j)), shape=(n, n))
    off = off + off.T
    return (off - sp.diags(np.asarray(off.sum(axis=1)).ravel())).tocsr()


def same_csr(a, b):
    return (a.shape == b.shape and a.indices.dtype == b.indices.dtype
            and np.array_equal(a.indptr, b.indptr) and np.array_equal(a.indices, b.indices)
            and np.array_equal(a.data.view(np.int64), b.data.view(np.int64)))


def meshes():
    rng = np.random.default_rng(3)
    sphere = trimesh.creation.icosphere(3)
    bumpy = sphere.vertices * (1 + 0.1 * np.sin(5 * sphere.vertices[:, :1]))
    u, v = np.meshgrid(np.arange(15.0), np.arange(15.0), indexing="ij")
    grid = np.column_stack([u.ravel(), v.ravel()])
    idx = np.arange(225).reshape(15, 15)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    tri = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                          np.stack([a, c, d], -1).reshape(-1, 3)])
    return [
        (sphere.vertices, sphere.faces),  # closed
        (bumpy, sphere.faces[7:]),  # a hole: edges with one face
        (grid, tri),  # planar (n, 2), right angles: exact zero weights
        (grid + rng.normal(0, 0.3, grid.shape), tri),  # obtuse corners, negative weights
        (np.column_stack([grid, np.zeros(len(grid))]), tri),
    ]


def weights(vertices, faces, nonnegative=False):
    f = np.asarray(faces, dtype=np.int64)
    cot = mesh._cotangents(vertices, f)
    if nonnegative:
        cot = np.clip(cot, 0.0, mesh._CLAMPED_COT)
    return (np.concatenate([f[:, 1], f[:, 2], f[:, 0]]),
            np.concatenate([f[:, 2], f[:, 0], f[:, 1]]),
            0.5 * np.concatenate([cot[:, 0], cot[:, 1], cot[:, 2]]))


@pytest.mark.parametrize("case", range(5))
@pytest.mark.parametrize("nonnegative", [False, True])
def test_laplacian_from_weights_is_scipys_matrix_bit_for_bit(case, nonnegative):
    vertices, faces = meshes()[case]
    i, j, w = weights(vertices, faces, nonnegative)
    made = laplacian_from_weights(i, j, w, len(vertices))
    assert same_csr(made, scipy_chain(i, j, w, len(vertices)))
    assert same_csr(mesh.cotangent_laplacian(vertices, faces, nonnegative=nonnegative), made)


def test_laplacian_from_weights_falls_back_on_repeated_and_diagonal_pairs():
    vertices, faces = meshes()[1]
    i, j, w = weights(vertices, faces)
    # a face listed twice repeats its directed edges; a degenerate face puts weights on
    # the diagonal: both take scipy's chain, whose duplicates are summed its own way
    for extra in (faces[:1], np.array([[0, 0, 1]])):
        fi, fj, fw = weights(vertices, np.vstack([faces, extra]))
        assert same_csr(laplacian_from_weights(fi, fj, fw, len(vertices)),
                        scipy_chain(fi, fj, fw, len(vertices)))


@pytest.mark.parametrize("case", range(5))
def test_vertex_areas_and_shared_pass_equal_the_separate_calls(case):
    vertices, faces = meshes()[case]
    for kind in ("voronoi", "barycentric"):
        assert np.array_equal(mesh.vertex_areas(vertices, faces, kind),
                              mesh.mass_matrix(vertices, faces, kind).diagonal())
    for nonnegative in (False, True):
        lap, area = mesh.laplacian_and_areas(vertices, faces, nonnegative=nonnegative)
        assert same_csr(lap, mesh.cotangent_laplacian(vertices, faces,
                                                       nonnegative=nonnegative))
        assert np.array_equal(area, mesh.vertex_areas(vertices, faces))
    with pytest.raises(ValueError, match="unknown mass matrix kind"):
        mesh.vertex_areas(vertices, faces, "lumped")


def _measures_case(case):
    """The vertex-measure tests' meshes: ``meshes()``'s, a soup with repeated and degenerate
    faces and unreferenced vertices, or no faces at all."""
    if case == "soup":
        rng = np.random.default_rng(7)
        vertices = rng.normal(size=(200, 3)) * 10.0 ** rng.uniform(-3, 3, (200, 1))
        faces = np.vstack([rng.integers(0, 150, (400, 3)), [[0, 0, 1], [2, 3, 4], [2, 3, 4]]])
        return vertices, faces
    if case == "empty":
        return np.ones((4, 3)), np.zeros((0, 3), dtype=np.int64)
    return meshes()[case]


@pytest.mark.parametrize("case", [0, 1, 4, "soup", "empty"])
def test_vertex_normals_and_areas_are_the_two_calls_bit_for_bit(case):
    # the λ-H fill's lagged solve takes both from one pass over the corners (session 30):
    # the same bits as the two calls, on closed and open meshes, obtuse and right-angled
    # corners, and a soup with repeated and degenerate faces and unreferenced vertices
    from surfinpaint.geometry.vertex_measures import vertex_normals_and_areas

    vertices, faces = _measures_case(case)
    with np.errstate(all="ignore"):  # the soup's degenerate faces divide by zero in both
        normals, areas = vertex_normals_and_areas(vertices, faces)
        want = mesh.vertex_normals(vertices, faces), mesh.vertex_areas(vertices, faces)
    for got, ref in zip((normals, areas), want, strict=True):
        assert got.shape == ref.shape and got.dtype == ref.dtype
        assert np.array_equal(got.view(np.int64), ref.view(np.int64))


@pytest.mark.parametrize("case", [0, 1, 4, "soup", "empty"])
def test_the_compiled_vertex_measures_are_numpy_s_bit_for_bit(case):
    # the lagged solves' normals and areas from a numba kernel (session 30): the same bits
    # as the numpy version, whatever run() chooses, on the cases above
    from surfinpaint.geometry import vertex_measures

    kernel = pytest.importorskip("numba") and vertex_measures._MEASURES_KERNEL.get()
    vertices, faces = _measures_case(case)
    vertices = np.ascontiguousarray(vertices, dtype=float)
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    with np.errstate(all="ignore"):
        got = vertex_measures._compiled(kernel, vertices, faces)
        want = vertex_measures._measures_numpy(vertices, faces)
    for a, b in zip(got, want, strict=True):
        assert a.shape == b.shape and a.dtype == b.dtype
        assert np.array_equal(a.view(np.int64), b.view(np.int64))


def test_point_mesh_distance_is_the_brute_force_minimum():
    # the nearest-centroid count is a speed setting: the answer must stay the exact
    # minimum over every triangle, whatever it is
    rng = np.random.default_rng(0)
    vertices, faces = meshes()[1]
    points = rng.normal(0, 0.7, (300, 3))
    index = _TriangleIndex(vertices, faces)
    tri = vertices[faces]
    p = np.repeat(points, len(faces), axis=0)
    t = np.tile(tri, (len(points), 1, 1))
    q = closest_point_on_triangles(p, t[:, 0], t[:, 1], t[:, 2])
    brute = np.linalg.norm(q - p, axis=1).reshape(len(points), -1).min(axis=1)
    assert np.allclose(index.distance(points), brute, rtol=0, atol=1e-12)
    index.use_numba = False
    assert np.allclose(index.distance(points), brute, rtol=0, atol=1e-12)


def _bad_meshes():
    import trimesh as tm

    m = tm.creation.icosphere(2)
    v, f = np.array(m.vertices), np.array(m.faces)
    flipped = f.copy()
    flipped[3] = flipped[3, ::-1]
    third = np.vstack([f, [[f[0, 0], f[0, 1], len(v)]]])  # an edge in three faces
    # (a face that repeats a vertex, or of zero area, is reported, not refused: its own tests)
    return {
        "duplicate face": (v, np.vstack([f, f[5:6]])),
        "non-manifold edge": (np.vstack([v, [[2.0, 2.0, 2.0]]]), third),
        "orientation": (v, flipped),
    }


@pytest.mark.parametrize("case", list(_bad_meshes()))
def test_check_topology_raises_what_validate_mesh_raises(case):
    from surfinpaint.errors import MeshError
    from surfinpaint.geometry.edges import EdgeTable
    from surfinpaint.geometry.validation import check_topology, validate_mesh

    v, f = _bad_meshes()[case]
    with pytest.raises(MeshError) as full:
        validate_mesh(v, f)
    with pytest.raises(MeshError) as checks:
        check_topology(v, f, EdgeTable.build(f, len(v)))
    assert str(checks.value) == str(full.value)
    assert checks.value.faces == full.value.faces and checks.value.edges == full.value.edges


def test_check_topology_passes_a_valid_mesh_and_returns_its_table():
    from surfinpaint.geometry.validation import check_topology

    v, f = meshes()[1]
    table, flat = check_topology(v, f)
    assert flat.size == 0
    assert table.n_edges == len(unique_edges_of(f))


def unique_edges_of(f):
    e = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    return np.unique(e, axis=0)


def _holes():
    """Holes with their refined, unfaired patch (vertices, faces, patch, loop, n): two of
    a bumpy sphere, and one with a single ring of faces left around it."""
    from surfinpaint.fill.liepa.baseline import conventional_fill
    from surfinpaint.geometry.cutting import cut_geodesic_disk

    out = []
    m = trimesh.creation.icosphere(4)
    v = m.vertices * (1 + 0.05 * np.sin(6 * m.vertices[:, :1]) * np.cos(5 * m.vertices[:, 1:2]))
    for centre, radius in ((0, 0.35), (100, 0.5)):
        cut = cut_geodesic_disk(v, m.faces, centre, radius)
        out.append((cut.vertices, cut.faces, cut.loop))
    # one ring of faces around the hole: the higher orders' stencils reach its border
    cut = cut_geodesic_disk(v, m.faces, 5, 0.35)
    keep = faces_within(cut.faces, cut.loop, len(cut.vertices), 0)
    out.append((cut.vertices, keep, cut.loop))
    made = []
    for vv, ff, loop in out:
        new_v, patch = conventional_fill(vv, ff, loop, refine=True, fair=False)
        made.append((np.vstack([vv, new_v]), ff, np.asarray(patch), loop, len(vv)))
    return made


def faces_within(faces, loop, n, rings):
    from surfinpaint.geometry.mesh import faces_near

    return faces_near(faces, loop, rings, n)


def old_faired_fills(vertices, faces, loop, orders, operator="cotan"):
    """faired_fills as it was: one fairing per order, each on its own neighbourhood."""
    from surfinpaint.errors import FillError, MeshError
    from surfinpaint.fill.liepa.baseline import _neighbourhood, conventional_fill
    from surfinpaint.fill.liepa.fairing import fair

    v = np.asarray(vertices, dtype=float)
    initial_v, patch = conventional_fill(v, faces, loop, refine=True, fair=False)
    n = len(v)
    out = {}
    for order in orders:
        used = order
        while True:
            near = _neighbourhood(faces, np.asarray(loop, dtype=np.int64), n, max(used - 2, 0))
            try:
                new_v = fair(np.vstack([v, initial_v]), np.vstack([near, patch]),
                             np.arange(n, n + len(initial_v)), order=used,
                             operator=operator)[n:]
                break
            except (MeshError, FillError):
                if used <= 2:
                    raise
                used = 2
        out[order] = (new_v, np.asarray(patch), used)
    return out


def test_faired_fills_share_one_laplacian_and_give_the_fills_of_one_fairing_per_order():
    from surfinpaint.fill.liepa.baseline import faired_fills

    holes = _holes()
    for vertices, faces, _, loop, n in holes:
        v = vertices[:n]
        for orders in ([2, 3], [3], [1, 2, 3, 4], [2]):
            for operator in ("cotan", "clamped"):
                new = faired_fills(v, faces, loop, orders, operator=operator)
                old = old_faired_fills(v, faces, loop, orders, operator=operator)
                assert list(new) == list(old)
                for k in orders:
                    assert np.array_equal(new[k][0], old[k][0]), (orders, k, operator)
                    assert np.array_equal(new[k][1], old[k][1]) and new[k][2] == old[k][2]
    # (the fall-back to order 2 where order 3 cannot be anchored:
    # tests/test_conformal.py::test_faired_fill_falls_back_to_order_2_...)


def test_fair_orders_equals_fair_per_order():
    from surfinpaint.fill.liepa.fairing import fair, fair_orders

    vertices, faces, patch, _, n = _holes()[0]
    allf = np.vstack([faces, patch])
    free = np.arange(n, len(vertices))
    made = fair_orders(vertices, allf, free, (1, 2, 3))
    for k in (1, 2, 3):
        assert np.array_equal(made[k], fair(vertices, allf, free, order=k))
    # with two iterations each order keeps its own weights: still the same as fair's
    two = fair_orders(vertices, allf, free, (2, 3), iterations=2)
    for k in (2, 3):
        assert np.array_equal(two[k], fair(vertices, allf, free, order=k, iterations=2))


def test_the_patch_of_a_fill_is_found_from_its_faces_alone():
    # sibling_scores looks for the patch among the fill's faces only: the cut's own faces
    # are never part of it, so the patch is the one found among all the faces
    from surfinpaint.fill.liepa.baseline import faired_fill
    from surfinpaint.geometry.metrics import hole_patch_of

    for vertices, faces, _, loop, n in _holes():
        v = vertices[:n]
        new_v, new_f, _ = faired_fill(v, faces, loop, 2)
        all_v = np.concatenate([v, new_v])
        whole = hole_patch_of(all_v, np.concatenate([faces, new_f]), n, faces)
        alone = hole_patch_of(all_v, new_f, n, faces)
        assert np.array_equal(whole[0], alone[0]) and np.array_equal(whole[1], alone[1])
        assert len(alone[1]) == len(new_f)
