"""Mesh validation: every defect is rejected with its ids named; the rest is reported."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import grid_mesh, tetrahedron_mesh

from surfinpaint.errors import MeshError
from surfinpaint.geometry.validation import (
    check_arrays,
    check_loop,
    nonmanifold_vertices,
    validate_mesh,
    zero_area_faces,
)


def _shifted_tetrahedron(offset: float, shift: int) -> tuple[np.ndarray, np.ndarray]:
    v, f = tetrahedron_mesh()
    return v + offset, f + shift


# ------------------------------------------------------------------------ valid meshes


def test_closed_tetrahedron(tetrahedron):
    report = validate_mesh(*tetrahedron)
    assert (report.n_vertices, report.n_faces, report.n_edges) == (4, 4, 6)
    assert report.n_components == 1 and report.is_closed
    assert report.euler_characteristic == 2
    assert report.unreferenced_vertices.size == 0 and report.nonmanifold_vertices.size == 0


def test_open_grid(grid):
    v, f = grid
    report = validate_mesh(v, f, path="grid.ply")
    assert report.n_components == 1
    assert report.boundary_loop_lengths == [2 * (4 + 3)]  # the grid's border
    assert report.euler_characteristic == 1  # a disk
    assert report.path == "grid.ply" and "grid.ply" in report.summary()


def test_components_and_unreferenced_are_reported_not_rejected(tetrahedron):
    v1, f1 = tetrahedron
    v2, f2 = _shifted_tetrahedron(5.0, 5)  # leaves vertex 4 unused
    v = np.concatenate([v1, [[9.0, 9, 9]], v2])
    f = np.concatenate([f1, f2])
    v0, f0 = v.copy(), f.copy()
    report = validate_mesh(v, f)
    assert report.n_components == 2
    assert report.unreferenced_vertices.tolist() == [4]
    assert report.euler_characteristic == 4
    assert any("unreferenced" in note and "4" in note for note in report.notes)
    np.testing.assert_array_equal(v, v0)  # inputs untouched
    np.testing.assert_array_equal(f, f0)


def test_hole_gives_second_boundary_loop():
    v, f = grid_mesh(6, 6)
    # remove the two triangles of an inner cell and its neighbour: one 6-vertex hole
    inner = (3 * 7 + 3)
    cell = [k for k in range(len(f)) if inner in f[k] and inner + 7 in f[k]]
    report = validate_mesh(v, np.delete(f, cell, axis=0))
    assert sorted(report.boundary_loop_lengths) == [4, 24]


# ------------------------------------------------------------------------- rejections


def _rejects(v, f, *fragments):
    with pytest.raises(MeshError) as info:
        validate_mesh(v, f, path="m.obj")
    text = str(info.value)
    assert text.startswith("m.obj: ")
    for fragment in fragments:
        assert fragment in text, text
    return info.value


def test_wrong_shapes_and_dtypes(tetrahedron):
    v, f = tetrahedron
    _rejects(v[:, :2], f, "(n, 3)", "(4, 2)")
    _rejects(v, np.column_stack([f, f[:, :1]]), "(f, 3)", "(4, 4)")
    _rejects(v, f.astype(complex), "integer", "complex128")
    _rejects(v, f + 0.5, "not whole numbers")  # never truncated to other ids
    validate_mesh(v, f.astype(float))  # whole-number floats are exact: taken
    _rejects(v.ravel(), f, "(n, 3)")


def test_empty(tetrahedron):
    v, f = tetrahedron
    _rejects(np.zeros((0, 3)), np.zeros((0, 3), int), "no vertices")
    _rejects(v, np.zeros((0, 3), int), "no faces")


def test_non_finite_coordinates_name_vertices(tetrahedron):
    v, f = tetrahedron
    v = v.copy()
    v[1, 0], v[3, 2] = np.nan, -np.inf
    err = _rejects(v, f, "2 vertices", "NaN or infinite", ": 1, 3")
    assert err.vertices == [1, 3]



@pytest.mark.parametrize("seed", range(6))
def test_array_checks_name_every_offending_row(seed):
    # check_arrays reduces each whole array first and masks rows only when that fails:
    # the rows it names must be those of the per-row masks, whatever the pattern
    rng = np.random.default_rng(seed)
    v, f = grid_mesh(14, 14)  # 225 vertices, 392 faces
    rows = np.sort(rng.choice(len(v), size=int(rng.integers(1, 120)), replace=False))
    bad_v = v.astype(float).copy()
    bad_v[rows, rng.integers(0, 3, len(rows))] = rng.choice([np.nan, np.inf, -np.inf],
                                                            len(rows))
    with pytest.raises(MeshError, match=f"{len(rows)} vert(ex has|ices have) NaN") as err:
        check_arrays(bad_v, f)
    assert err.value.vertices == rows[:100].tolist()
    for value, words in ((-1 - int(rng.integers(0, 5)), "negative vertex ids"),
                         (len(v) + int(rng.integers(0, 5)), "vertex ids >= the vertex count")):
        picked = np.sort(rng.choice(len(f), size=int(rng.integers(1, 120)), replace=False))
        bad_f = f.copy()
        bad_f[picked, rng.integers(0, 3, len(picked))] = value
        with pytest.raises(MeshError, match=f"{len(picked)} faces .*{words}") as err:
            check_arrays(v, bad_f)
        assert err.value.faces == picked[:100].tolist()
    check_arrays(v, f)  # and the good mesh passes

def test_index_range_names_faces(tetrahedron):
    v, f = tetrahedron
    bad = f.copy()
    bad[2, 1] = 4
    assert _rejects(v, bad, "vertex ids >= the vertex count 4", ": 2").faces == [2]
    bad = f.copy()
    bad[3, 0] = -1
    assert _rejects(v, bad, "negative", ": 3").faces == [3]


def test_long_id_lists_are_previewed():
    v, f = grid_mesh(10, 10)
    v = v.copy()
    v[:25] = np.nan
    err = _rejects(v, f, "25 vertices", "0, 1, 2", "and 15 more")
    assert err.vertices == list(range(25))


def test_repeated_vertex_in_face_is_reported_and_left_out_of_the_topology(tetrahedron):
    # no triangle: kept by a fill, left out of the edges and loops (tests/test_degenerate_faces.py)
    v, f = tetrahedron
    report = validate_mesh(v, np.concatenate([f, [[1, 2, 1]]]))
    assert report.repeated_vertex_faces.tolist() == [4] and report.is_closed
    assert (report.n_faces, report.n_edges, report.euler_characteristic) == (5, 6, 2)
    assert any("same vertex twice" in n and "4 (1, 2, 1)" in n for n in report.notes)


def test_duplicate_faces_even_with_other_orientation(tetrahedron):
    v, f = tetrahedron
    bad = np.concatenate([f, [[3, 2, 1]]])  # face 3 is (1, 2, 3)
    assert _rejects(v, bad, "1 duplicate face:", "4 (same vertices as 3)").faces == [4]


def test_zero_area_faces_are_reported():
    # triangles of the surface: a fill refuses only the holes whose neighbourhood holds one
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0], [0.5, 0, 0]])
    f = np.array([[0, 1, 2], [0, 3, 1]])  # collinear corners
    report = validate_mesh(v, f)
    assert report.zero_area_faces.tolist() == [1]
    assert any("zero area" in n and "1 (0, 3, 1)" in n for n in report.notes)
    v2 = v.copy()
    v2[4] = v2[1]  # coincident corners
    assert validate_mesh(v2, np.array([[0, 1, 2], [1, 4, 2]])).zero_area_faces.tolist() == [1]


def test_thin_but_real_triangle_is_accepted():
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0.5, 1e-8, 0]])
    validate_mesh(v, np.array([[0, 1, 2]]))


def test_nonmanifold_edge_is_named():
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1]])
    f = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])  # three faces on edge (0, 1)
    err = _rejects(v, f, "1 non-manifold edge (", "(0, 1) in 3 faces")
    assert err.edges == [(0, 1)]


def _fins(n: int) -> tuple[np.ndarray, np.ndarray]:
    """A triangle with a fin of two more faces on ``n`` of its edges: ``n`` edges of three
    faces."""
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [-1, 0, 0],
                  [0, 0, -1]])
    fins = [[1, 0, 3], [0, 1, 4], [2, 0, 5], [0, 2, 6]][:2 * n]
    return v, np.array([[0, 1, 2], *fins])


def _tetrahedron_plus(copies: int = 0, loose: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """The tetrahedron with ``copies`` of its first faces again and ``loose`` vertices that
    no face uses."""
    v, f = tetrahedron_mesh()
    return np.vstack([v, np.full((loose, 3), 2.0)]), np.vstack([f, f[:copies]])


# session 40: "1 non-manifold edges" and its siblings; each count agrees with its noun
@pytest.mark.parametrize(("mesh", "said"), [
    (lambda: _fins(1), "m.obj: 1 non-manifold edge (shared by more than two faces): (0, 1)"),
    (lambda: _fins(2), "m.obj: 2 non-manifold edges (shared by more than two faces): "),
    (lambda: _tetrahedron_plus(copies=1), "m.obj: 1 duplicate face: 4 (same vertices as 0)"),
    (lambda: _tetrahedron_plus(copies=2), "m.obj: 2 duplicate faces: "),
])
def test_a_count_of_one_or_two_agrees_with_its_noun(mesh, said):
    with pytest.raises(MeshError) as info:
        validate_mesh(*mesh(), path="m.obj")
    assert str(info.value).startswith(said), str(info.value)


@pytest.mark.parametrize(("loose", "said"), [
    (1, "1 unreferenced vertex (kept untouched): 4"),
    (2, "2 unreferenced vertices (kept untouched): 4, 5"),
])
def test_a_count_of_unreferenced_vertices_agrees_with_its_noun(loose, said):
    assert validate_mesh(*_tetrahedron_plus(loose=loose)).notes == [said]


@pytest.mark.parametrize(("n_bad", "said"), [
    (1, "1 loop edge is not a boundary edge of the mesh: "),
    (2, "2 loop edges are not boundary edges of the mesh: "),
])
def test_a_count_of_loop_edges_agrees_with_its_noun(n_bad, said):
    # a grid's border with one vertex, then two, moved inside: the edges into it are no
    # boundary edges (a loop of 3 vertices, the fewest, for the border's corner cut)
    v, f = grid_mesh(3, 3)
    loop = {1: [0, 1, 4], 2: [0, 4, 8, 3]}[n_bad]
    with pytest.raises(MeshError) as info:
        check_loop(f, np.array(loop))
    assert said in str(info.value), str(info.value)


def test_inconsistent_orientation_names_edge_and_faces():
    v, f = grid_mesh(3, 3)
    bad = f.copy()
    bad[4] = bad[4, ::-1]
    err = _rejects(v, bad, "inconsistent face orientation")
    assert 4 in err.faces
    # every named edge is traversed in the same direction by two faces
    for a, b in err.edges:
        half = {(int(x), int(y)) for t in bad for x, y in zip(t, np.roll(t, -1), strict=True)}
        assert (a, b) in half
        owners = [k for k, t in enumerate(bad)
                  if any((t[i], t[(i + 1) % 3]) == (a, b) for i in range(3))]
        assert len(owners) == 2 and 4 in owners


def test_flipped_separate_component_is_fine(tetrahedron):
    v1, f1 = tetrahedron
    v2, f2 = _shifted_tetrahedron(3.0, 4)
    validate_mesh(np.concatenate([v1, v2]), np.concatenate([f1, f2[:, ::-1]]))


# ------------------------------------------------------------------ bow-tie vertices


def _fans_brute_force(faces: np.ndarray) -> np.ndarray:
    """Reference: per vertex, flood-fill its faces through shared edges at the vertex."""
    out = []
    for vtx in np.unique(faces):
        around = [t for t in range(len(faces)) if vtx in faces[t]]
        seen, fans = set(), 0
        for start in around:
            if start in seen:
                continue
            fans += 1
            stack = [start]
            seen.add(start)
            while stack:
                t = stack.pop()
                for u in around:
                    if u not in seen and len(set(faces[t]) & set(faces[u])) == 2:
                        seen.add(u)
                        stack.append(u)
        if fans > 1:
            out.append(vtx)
    return np.array(out, dtype=np.int64)


def test_bowtie_two_triangles():
    assert nonmanifold_vertices(np.array([[0, 1, 2], [0, 3, 4]])).tolist() == [0]


def test_two_tetrahedra_sharing_a_vertex(tetrahedron):
    v1, f1 = tetrahedron
    v2, f2 = _shifted_tetrahedron(1.0, 3)  # vertex 3 is shared
    v = np.concatenate([v1, v2[1:]])
    f = np.concatenate([f1, f2])
    assert nonmanifold_vertices(f).tolist() == [3]
    report = validate_mesh(v, f)  # allowed, but reported
    assert report.nonmanifold_vertices.tolist() == [3] and report.n_components == 1


def test_manifold_meshes_have_no_bowties(tetrahedron, grid):
    assert nonmanifold_vertices(tetrahedron[1]).size == 0
    assert nonmanifold_vertices(grid[1]).size == 0


@pytest.mark.parametrize("seed", range(6))
def test_bowties_match_brute_force_on_random_face_subsets(seed):
    rng = np.random.default_rng(seed)
    _, f = grid_mesh(6, 5)
    sub = f[rng.random(len(f)) < 0.55]
    expected = _fans_brute_force(sub)
    assert expected.size > 0 or seed > 2  # the subsets do produce bow-ties
    np.testing.assert_array_equal(nonmanifold_vertices(sub), expected)


def test_bowties_fast_on_large_mesh():
    # vectorization check by size, not time: 200k faces must go through without loops
    _, f = grid_mesh(300, 300)
    assert nonmanifold_vertices(f).size == 0


# ------------------------------------------------------------------------- check_loop


def test_check_loop_accepts_a_boundary_loop(grid):
    v, f = grid
    from surfinpaint.geometry.mesh import boundary_loops

    check_loop(f, boundary_loops(f)[0])


def test_check_loop_rejects_interior_edges(grid):
    _, f = grid
    with pytest.raises(MeshError, match="not boundary edges") as info:
        check_loop(f, f[5])  # a face's corners: interior edges
    assert len(info.value.edges) >= 1


def test_check_loop_rejects_repeats_and_short_loops(grid):
    _, f = grid
    with pytest.raises(MeshError, match="more than once: 0"):
        check_loop(f, [0, 1, 0, 2])
    with pytest.raises(MeshError, match="at least 3"):
        check_loop(f, [0, 1])


def test_check_loop_names_bowtie_vertex():
    # two fans meet at vertex 0; the loop around one fan passes through it
    f = np.array([[0, 1, 2], [0, 2, 3], [0, 4, 5], [0, 5, 6]])
    with pytest.raises(MeshError, match=r"bow-tie\) vertex 0:") as info:
        check_loop(f, [0, 1, 2, 3])
    assert info.value.vertices == [0]


def test_check_loop_names_the_given_ids_when_they_are_large():
    # the same fans as above with vertex ids near 10^7 (a hole's neighbourhood in a large
    # mesh): the check runs on compact ids and names the caller's ids
    big = 10_000_000
    f = np.array([[0, 1, 2], [0, 2, 3], [0, 4, 5], [0, 5, 6]]) + big
    with pytest.raises(MeshError, match=rf"bow-tie\) vertex {big}:") as info:
        check_loop(f, np.array([0, 1, 2, 3]) + big)
    assert info.value.vertices == [big]
    with pytest.raises(MeshError, match="not boundary edges") as info:
        check_loop(f, np.array([1, 2, 7]) + big)  # (2, 7) and (7, 1) are no edges
    assert info.value.edges == [(2 + big, 7 + big), (7 + big, 1 + big)]


def test_zero_area_faces_block_by_block_equals_all_at_once(monkeypatch):
    from surfinpaint.geometry import mesh as mesh_module
    from surfinpaint.geometry.mesh import face_areas

    rng = np.random.default_rng(3)
    v = rng.normal(size=(60, 3))
    v[50:] = v[0]  # coincident corners: zero-area faces in several blocks
    f = rng.integers(0, 60, size=(500, 3))
    f = f[(f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 2] != f[:, 0])]
    whole_flat, whole_area = zero_area_faces(v, f), face_areas(v, f)
    assert whole_flat.size > 3
    monkeypatch.setattr(mesh_module, "FACE_BLOCK", 7)
    assert len(mesh_module.face_blocks(len(f))) > 10
    assert np.array_equal(zero_area_faces(v, f), whole_flat)
    assert np.array_equal(face_areas(v, f), whole_area)  # the same bits


def test_duplicate_faces_say_what_repair_does_with_them(tetrahedron):
    # the error named the copies but not the option that fixes them, where the
    # non-manifold edges' error did (session 34)
    import trimesh

    from surfinpaint import fill_holes

    v, f = tetrahedron
    _rejects(v, np.concatenate([f, f[3:]]), "1 duplicate face:",
             "--repair (repair=True) removes the faces around")
    s = trimesh.creation.icosphere(2)
    v, f = np.asarray(s.vertices), np.asarray(s.faces)
    result = fill_holes(v, np.concatenate([f, f[7:8]]), method="fair", repair=True)
    assert 7 in result.removed_faces and len(f) in result.removed_faces
    assert validate_mesh(result.vertices, result.faces).is_closed  # no copy left, no hole
