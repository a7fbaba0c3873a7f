"""The edge table (geometry/edges.py) against brute-force dictionaries, and its reuse by
validate_mesh, find_holes and boundary_loops."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from surfinpaint.data import sphere
from surfinpaint.errors import MeshError
from surfinpaint.fill.holes import find_holes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.edges import EdgeTable, edge_keys
from surfinpaint.geometry.mesh import boundary_loops
from surfinpaint.geometry.validation import validate_mesh


def _brute(faces: np.ndarray) -> dict:
    """Half-edges per undirected edge, by dictionary: {(lo, hi): [(face, k, tail, head)]}."""
    table: dict = {}
    for t, face in enumerate(faces.tolist()):
        for k in range(3):
            a, b = face[(k + 1) % 3], face[(k + 2) % 3]
            table.setdefault((min(a, b), max(a, b)), []).append((t, k, a, b))
    return table


def _meshes():
    v, f = sphere(2)
    rng = np.random.default_rng(3)
    shuffled = f[rng.permutation(len(f))]
    open_part = shuffled[: len(f) // 2]  # an open mesh with a ragged border
    fin = np.vstack([f, [[f[0, 0], f[0, 1], len(v)]]])  # a third face on one edge
    return {"closed": f, "shuffled-half": open_part, "fin": fin,
            "two": np.array([[0, 1, 2], [2, 1, 3]]), "bowtie": np.array([[0, 1, 2], [0, 3, 4]])}


@pytest.mark.parametrize("name", list(_meshes()))
def test_table_matches_brute_force(name):
    faces = _meshes()[name]
    table = EdgeTable.build(faces)
    brute = _brute(faces)
    keys = sorted(brute)
    assert table.edges.tolist() == [list(k) for k in keys]
    assert table.count.tolist() == [len(brute[k]) for k in keys]
    assert table.start[-1] == 3 * len(faces)
    for e, k in enumerate(keys):
        group = table.halfedges[table.start[e]:table.start[e + 1]]
        assert group.tolist() == sorted(3 * t + c for t, c, _, _ in brute[k])
        assert table.edge_faces(e).tolist() == sorted(t for t, _, _, _ in brute[k])
        for t, c, a, b in brute[k]:
            h = 3 * t + c
            assert table.face_edge[t, c] == e
            assert (table.tails(np.array([h]))[0], table.heads(np.array([h]))[0]) == (a, b)
            assert table.forward[h] == (a < b)
        owners = sorted(t for t, _, _, _ in brute[k])[:2]
        assert table.owners[e].tolist() == owners + [-1] * (2 - len(owners))
    lonely = sorted((3 * t + c, a, b) for k in keys if len(brute[k]) == 1
                    for t, c, a, b in brute[k])
    assert table.boundary_halfedges().tolist() == [[a, b] for _, a, b in lonely]



@pytest.mark.parametrize("name", list(_meshes()))
def test_packed_and_argsort_orders_agree(name):
    # build sorts the keys with their half-edge ids packed in the low bits when that fits
    # in an int64; with a huge vertex count it cannot, and np.argsort(stable) is used: the
    # two must give the same table (the brute-force test above checks the first)
    faces = _meshes()[name]
    huge = 2**62 // (int(np.max(faces)) + 1)  # keys near 2**62: no bits left to pack into
    packed, argsorted = EdgeTable.build(faces), EdgeTable.build(faces, huge)
    keys = edge_keys(argsorted.edges[:, 0], argsorted.edges[:, 1], huge)
    assert int(keys.max()) >= 2 ** (63 - (3 * len(faces) - 1).bit_length())
    for field in ("halfedges", "start", "count", "face_edge", "forward", "edges"):
        assert np.array_equal(getattr(packed, field), getattr(argsorted, field)), field
    f = np.asarray(faces, dtype=np.int64)
    tails, heads = f[:, [1, 2, 0]].ravel(), f[:, [2, 0, 1]].ravel()
    n = packed.n_vertices
    order = np.argsort(edge_keys(tails, heads, n), kind="stable")
    assert np.array_equal(packed.halfedges, order)

def test_interior_pairs_are_the_two_halfedges_of_each_two_face_edge():
    faces = _meshes()["fin"]
    table = EdgeTable.build(faces)
    h1, h2 = table.interior_pairs()
    brute = _brute(faces)
    expected = [tuple(sorted(3 * t + c for t, c, _, _ in hs)) for _, hs in sorted(brute.items())
                if len(hs) == 2]
    assert list(zip(h1.tolist(), h2.tolist(), strict=True)) == expected


def test_find_edges_either_direction_and_missing():
    faces = np.array([[0, 1, 2], [2, 1, 3]])
    table = EdgeTable.build(faces)
    got = table.find(np.array([1, 2, 0, 3, -1, 9]), np.array([2, 1, 3, 2, 0, 1]))
    assert got.tolist() == [2, 2, -1, 4, -1, -1]
    assert table.edges[got[:2]].tolist() == [[1, 2], [1, 2]]


@pytest.mark.parametrize("shuffled", [False, True])
def test_vertex_components_match_scipy_on_the_adjacency(shuffled):
    v, f = sphere(2)
    faces = np.vstack([f, f + len(v)])  # two spheres
    n = 2 * len(v) + 3  # three unreferenced vertices at the end
    if shuffled:  # the components' and the lonely vertices' ids interleaved
        faces = np.random.default_rng(5).permutation(n)[faces]
    table = EdgeTable.build(faces, n)
    count, label = table.vertex_components
    rows = faces[:, [0, 1, 2]].ravel()
    cols = faces[:, [1, 2, 0]].ravel()
    graph = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    want_count, want = connected_components(graph, directed=False)
    assert count == want_count == 5
    np.testing.assert_array_equal(label, want)


def test_edge_keys_are_symmetric_and_sort_lexicographically():
    a = np.array([5, 1, 3, 0])
    b = np.array([1, 5, 0, 3])
    k = edge_keys(a, b, 10)
    assert k[0] == k[1] == 15 and k[2] == k[3] == 3
    pairs = np.array([[0, 9], [1, 2], [1, 3], [2, 1]])
    assert np.argsort(edge_keys(pairs[:, 0], pairs[:, 1], 10), kind="stable").tolist() == \
        [0, 1, 3, 2]


def test_empty_faces():
    table = EdgeTable.build(np.zeros((0, 3), np.int64), 4)
    assert table.n_edges == 0 and table.boundary_halfedges().shape == (0, 2)
    assert table.vertex_components[0] == 4


def _holed_sphere():
    v, f = sphere(3)
    cut = cut_holes(v, f, [0, len(v) // 2], 0.35)
    return cut.vertices, cut.faces


def test_validate_and_find_holes_reuse_a_table():
    v, f = _holed_sphere()
    table = EdgeTable.build(f, len(v))
    fresh = validate_mesh(v, f)
    reused = validate_mesh(v, f, table=table)
    for field in ("n_vertices", "n_faces", "n_edges", "n_components", "boundary_loop_lengths",
                  "euler_characteristic"):
        assert getattr(fresh, field) == getattr(reused, field)
    assert fresh.boundary_loop_lengths == [len(l) for l in boundary_loops(f)]
    holes, holes_reused = find_holes(v, f), find_holes(v, f, table)
    assert len(holes) == len(holes_reused) == 2
    for a, b in zip(holes, holes_reused, strict=True):
        np.testing.assert_array_equal(a.loop, b.loop)
        assert (a.perimeter, a.component, a.is_border) == (b.perimeter, b.component, b.is_border)
    for a, b in zip(boundary_loops(f), boundary_loops(f, table), strict=True):
        np.testing.assert_array_equal(a, b)


def test_a_table_of_other_faces_is_refused():
    v, f = _holed_sphere()
    stale = EdgeTable.build(f[:-1], len(v))
    with pytest.raises(ValueError, match="built for"):
        validate_mesh(v, f, table=stale)
    with pytest.raises(ValueError, match="built for"):
        find_holes(v, f, stale)


def test_triplicate_face_on_a_nonmanifold_edge_names_each_copy():
    v, f = sphere(1)
    extra = np.vstack([f, f[[3]], f[[3]][:, ::-1]])  # face 3 three times: count 3 edges
    with pytest.raises(MeshError) as info:
        validate_mesh(v, extra)
    last = len(f)
    assert f"2 duplicate faces: {last} (same vertices as 3), {last + 1} (same vertices as " \
           f"{last})" in str(info.value)
    assert info.value.faces == [last, last + 1]


def _fan_counts_brute_force(faces: np.ndarray) -> dict[int, int]:
    """Fans per vertex by flood fill over the faces at it, joined across two-face edges."""
    table = _brute(faces)
    fans = {}
    for vertex in np.unique(faces).tolist():
        mine = [t for t, face in enumerate(faces.tolist()) if vertex in face]
        seen, count = set(), 0
        for t in mine:
            if t in seen:
                continue
            count += 1
            stack = [t]
            seen.add(t)
            while stack:
                s = stack.pop()
                for other in faces[s].tolist():
                    if other == vertex:
                        continue
                    on_edge = table[(min(vertex, other), max(vertex, other))]
                    if len(on_edge) != 2:
                        continue  # border, or a non-manifold edge: joins nothing
                    for u, _, _, _ in on_edge:
                        if u not in seen:
                            seen.add(u)
                            stack.append(u)
        fans[vertex] = count
    return fans


@pytest.mark.parametrize("seed", range(4))
def test_bowtie_walk_matches_flood_fill_on_sphere_subsets(seed):
    # random face subsets of a closed sphere: open fans, closed fans, several of each
    from surfinpaint.geometry.validation import nonmanifold_vertices

    _, f = sphere(2)
    rng = np.random.default_rng(seed)
    sub = f[rng.random(len(f)) < 0.7]
    fans = _fan_counts_brute_force(sub)
    expected = sorted(v for v, n in fans.items() if n > 1)
    assert expected  # the subsets do make bow-ties
    assert nonmanifold_vertices(sub).tolist() == expected


def test_bowtie_walk_closed_fans_and_fins():
    from surfinpaint.geometry.validation import nonmanifold_vertices

    v, f = sphere(1)
    touching = np.vstack([f, np.where(f == 0, 0, f + len(v))])  # two spheres share vertex 0
    assert nonmanifold_vertices(touching).tolist() == [0]
    fin = np.vstack([f, [[f[0, 0], f[0, 1], len(v)]]])  # a third face on edge f[0, :2]
    expected = sorted(v for v, n in _fan_counts_brute_force(fin).items() if n > 1)
    assert nonmanifold_vertices(fin).tolist() == expected == sorted(f[0, :2].tolist())
