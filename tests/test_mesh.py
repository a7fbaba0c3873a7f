import numpy as np
import pytest
import trimesh

from surfinpaint.errors import MeshError
from surfinpaint.geometry.mesh import (
    boundary_loops,
    connected_components,
    cotangent_laplacian,
    face_areas,
    k_ring,
    mass_matrix,
    mean_edge_length,
    orient_loop,
    unique_edges,
    vertex_faces,
    vertex_normals,
)


def grid_mesh(n=6):
    u, v = np.meshgrid(np.arange(n, dtype=float), np.arange(n, dtype=float), indexing="ij")
    vertices = np.column_stack([u.ravel(), v.ravel(), np.zeros(n * n)])
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                            np.stack([a, c, d], -1).reshape(-1, 3)])
    return vertices, faces


def test_unique_edges_counts():
    edges, face_edge, count = unique_edges(np.array([[0, 1, 2], [2, 1, 3]]))
    assert edges.tolist() == [[0, 1], [0, 2], [1, 2], [1, 3], [2, 3]]
    assert count.tolist() == [1, 1, 2, 1, 1]
    # corner k of face t is opposite edge (t[k+1], t[k+2])
    assert edges[face_edge[0, 0]].tolist() == [1, 2]


def test_boundary_loop_of_grid_is_its_border_in_face_orientation():
    vertices, faces = grid_mesh(5)
    loops = boundary_loops(faces)
    assert len(loops) == 1
    assert len(loops[0]) == 16
    # every consecutive pair is a half-edge of some face (same direction)
    half = {(int(f[i]), int(f[(i + 1) % 3])) for f in faces for i in range(3)}
    loop = loops[0]
    assert all((int(a), int(b)) in half for a, b in zip(loop, np.roll(loop, -1), strict=True))


def test_boundary_loops_closed_mesh_and_two_holes():
    sphere = trimesh.creation.icosphere(2)
    assert boundary_loops(sphere.faces) == []
    faces = np.delete(sphere.faces, [0, 100], axis=0)
    loops = boundary_loops(faces)
    assert sorted(len(l) for l in loops) == [3, 3]


def test_pinched_loop_is_split():
    # two triangles sharing only vertex 0 (a bow-tie): boundary visits 0 twice
    faces = np.array([[0, 1, 2], [0, 3, 4]])
    loops = boundary_loops(faces)
    assert sorted(len(l) for l in loops) == [3, 3]


def test_inconsistent_orientation_is_reported():
    # second face reversed: its boundary edges do not chain with the first face's
    faces = np.array([[0, 1, 2], [0, 2, 3], [0, 4, 3]])
    faces_bad = faces.copy()
    faces_bad[1] = faces_bad[1][::-1]
    with pytest.raises(MeshError):
        boundary_loops(faces_bad)


def test_k_ring_and_components():
    vertices, faces = grid_mesh(6)
    ring1 = k_ring(faces, [14], 1, len(vertices))
    assert ring1.sum() == 7  # the vertex and its 6 neighbours in this triangulation
    count, labels = connected_components(np.concatenate([faces, faces + 36]), 72)
    assert count == 2 and labels[0] != labels[40]


def test_areas_and_mean_edge_length():
    vertices, faces = grid_mesh(4)
    assert np.isclose(face_areas(vertices, faces).sum(), 9.0)
    n_axis, n_diag = 2 * 3 * 4, 9
    expected = (n_axis + n_diag * np.sqrt(2)) / (n_axis + n_diag)
    assert np.isclose(mean_edge_length(vertices, faces), expected)


def test_cotangent_laplacian_reproduces_sphere_mean_curvature():
    sphere = trimesh.creation.icosphere(4, radius=2.0)
    v, f = sphere.vertices, sphere.faces
    L = cotangent_laplacian(v, f)
    M = mass_matrix(v, f)
    mean_curvature_normal = -(L @ v) / (2 * M.diagonal()[:, None])
    H = np.linalg.norm(mean_curvature_normal, axis=1)
    assert np.allclose(H, 0.5, rtol=0.02)
    assert np.isclose(M.diagonal().sum(), 4 * np.pi * 4, rtol=0.01)
    # L is symmetric with zero row sums (constants in the kernel)
    assert abs(L - L.T).max() < 1e-12
    assert np.abs(L @ np.ones(len(v))).max() < 1e-10


def test_laplacian_is_exact_on_linear_functions_in_the_plane():
    vertices, faces = grid_mesh(6)
    rng = np.random.default_rng(0)
    vertices[:, :2] += rng.uniform(-0.2, 0.2, (len(vertices), 2))
    L = cotangent_laplacian(vertices[:, :2], faces)
    f = 2 * vertices[:, 0] - 3 * vertices[:, 1]
    interior = ~np.isin(np.arange(len(vertices)), boundary_loops(faces)[0])
    assert np.abs((L @ f)[interior]).max() < 1e-10


def test_mass_matrix_kinds_agree_on_total_area():
    vertices, faces = grid_mesh(5)
    for kind in ("voronoi", "barycentric"):
        assert np.isclose(mass_matrix(vertices, faces, kind).diagonal().sum(), 16.0)
    with pytest.raises(ValueError):
        mass_matrix(vertices, faces, "nope")


def test_vertex_normals_of_plane():
    vertices, faces = grid_mesh(4)
    assert np.allclose(vertex_normals(vertices, faces), [0, 0, 1])


def test_edge_faces_pairs_the_faces_of_each_edge():
    from surfinpaint.data import cube
    from surfinpaint.geometry.mesh import edge_faces

    v, f = cube(3)
    edges, owners, count = edge_faces(f)
    assert (count == 2).all() and (owners >= 0).all()
    # each listed face holds the edge
    for k in (0, 1):
        held = (f[owners[:, k]] == edges[:, [0]]).any(axis=1) & (
            f[owners[:, k]] == edges[:, [1]]).any(axis=1)
        assert held.all()
    assert (owners[:, 0] != owners[:, 1]).all()
    # an open mesh: border edges have one face and -1
    edges, owners, count = edge_faces(f[1:])
    assert (owners[count == 1, 1] == -1).all() and (count == 1).sum() == 3


def test_faces_near_grows_by_rings():
    from surfinpaint.data import cube
    from surfinpaint.geometry.mesh import faces_near, k_ring

    v, f = cube(6)
    seeds = np.array([0])
    for rings in range(3):
        near = faces_near(f, seeds, rings, len(v))
        # the faces touching the vertices within ``rings`` edges of the seeds
        within = k_ring(f, seeds, rings, len(v))
        assert np.array_equal(near, f[within[f].any(axis=1)])
    assert len(faces_near(f, seeds, 0, len(v))) < len(faces_near(f, seeds, 2, len(v)))


def test_orient_loop_accepts_interior_edges_only_when_asked():
    f = np.array([[0, 1, 2], [0, 2, 3]])
    assert orient_loop(f, [3, 2, 1, 0]).tolist() == [0, 1, 2, 3]
    assert orient_loop(f, np.array([1, 2, 3, 0])).tolist() == [1, 2, 3, 0]
    # (2, 0) is the diagonal between the two faces: a mesh edge, not a boundary edge
    with pytest.raises(MeshError, match="not joined by a boundary edge"):
        orient_loop(f, [0, 1, 2])
    assert orient_loop(f, [2, 1, 0], boundary=False).tolist() == [0, 1, 2]
    with pytest.raises(MeshError, match=r"loop edge \(1, 3\) is not an edge of the mesh"):
        orient_loop(f, [0, 1, 3], boundary=False)
    with pytest.raises(MeshError, match="repeat"):
        orient_loop(f, [0, 1, 2, 1])
    # faces of opposite orientations: the loop runs with one and against the other
    with pytest.raises(MeshError, match="not consistently oriented"):
        orient_loop(np.array([[0, 1, 2], [0, 3, 2]]), [0, 1, 2, 3], boundary=False)


@pytest.mark.parametrize("dtype", [np.int64, np.int32, np.uint16])
def test_vertex_faces_is_the_incidence_with_each_rows_faces_in_order(dtype):
    rng = np.random.default_rng(3)
    faces = np.stack([rng.permutation(40)[:3] for _ in range(90)]).astype(dtype)
    incidence = vertex_faces(faces, 45)  # 5 vertices on no face: empty rows
    dense = np.zeros((45, 90), dtype=np.int8)
    dense[faces.astype(np.int64).ravel(), np.repeat(np.arange(90), 3)] = 1
    np.testing.assert_array_equal(incidence.toarray(), dense)
    assert incidence.has_canonical_format  # faces_at reads each row's ids as they stand
    assert incidence.indices.dtype == np.int32 and incidence.shape == (45, 90)
