"""Balanced quadtree triangulations (representation/quadtree.py)."""

import numpy as np
import pytest

from surfinpaint.representation.quadtree import balanced_splits, quadtree_triangulation


def near(point, depth):
    """Split the cells holding ``point`` down to ``depth`` (a squeezed spot)."""
    def wants(d, i, j):
        x, y = point[0] * 2 ** d, point[1] * 2 ** d
        return (i <= x) & (x <= i + 1) & (j <= y) & (y <= j + 1) & (d < depth)
    return wants


def everywhere(d, i, j):
    return np.ones(len(i), dtype=bool)


def nowhere(d, i, j):
    return np.zeros(len(i), dtype=bool)


def edges_with_counts(faces):
    e = np.sort(np.vstack([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    return np.unique(e, axis=0, return_counts=True)


def signed_areas(points, faces):
    a, b = points[faces[:, 1]] - points[faces[:, 0]], points[faces[:, 2]] - points[faces[:, 0]]
    return 0.5 * (a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])


@pytest.mark.parametrize("wants, depth, faces, nodes", [
    (nowhere, 1, 16, 13),          # the root's 4 leaves, each a fan of 4
    (everywhere, 2, 64, 41),       # 16 leaves: 5×5 corners and 16 centres
    (near((0.0, 0.0), 3), 3, 68, 43),
    (near((0.3, 0.7), 1), 4, 16, 13),  # asks nothing below level 1
])
def test_sizes_of_small_trees(wants, depth, faces, nodes):
    t = quadtree_triangulation(wants, depth)
    assert (len(t.faces), len(t.lattice)) == (faces, nodes)


@pytest.mark.parametrize("wants, depth", [
    (near((0.3, 0.7), 9), 9), (near((0.0, 0.5), 7), 7), (near((1.0, 1.0), 8), 8),
    (lambda d, i, j: (i + j) % 3 == 0, 6), (everywhere, 3)])
def test_the_triangles_tile_the_square_edge_to_edge(wants, depth):
    t = quadtree_triangulation(wants, depth)
    p = t.points
    area = signed_areas(p, t.faces)
    assert (area > 0).all()  # counter-clockwise
    assert area.sum() == pytest.approx(1.0, abs=1e-12)
    edges, count = edges_with_counts(t.faces)
    assert set(count) <= {1, 2}
    # an edge of one triangle only is on the square's sides: no crack at a hanging node
    once = edges[count == 1]
    assert t.border()[once].all()
    on_same_side = ((t.lattice[once[:, 0]] == t.lattice[once[:, 1]])
                    & ((t.lattice[once[:, 0]] == 0) | (t.lattice[once[:, 0]] == t.scale)))
    assert on_same_side.any(axis=1).all()


@pytest.mark.parametrize("wants, depth", [(near((0.3, 0.7), 9), 9),
                                          (lambda d, i, j: (i * 7 + j * 3) % 5 == 0, 7)])
def test_leaves_sharing_an_edge_differ_by_one_level_at_most(wants, depth):
    t = quadtree_triangulation(wants, depth)
    e = np.vstack([t.faces[:, [0, 1]], t.faces[:, [1, 2]], t.faces[:, [2, 0]]])
    owner = np.tile(np.arange(len(t.faces)), 3)
    key = np.sort(e, axis=1) @ np.array([len(t.lattice), 1])
    order = np.argsort(key, kind="stable")
    key, owner = key[order], owner[order]
    pair = np.flatnonzero(key[1:] == key[:-1])
    jump = np.abs(t.leaf_depth[owner[pair]] - t.leaf_depth[owner[pair + 1]])
    assert jump.max() <= 1
    assert t.leaf_depth.max() == depth and t.leaf_depth.min() < depth - 3  # adaptive


def test_every_triangle_is_right_isosceles():
    t = quadtree_triangulation(near((0.62, 0.41), 8), 8)
    p = t.points[t.faces]
    sides = np.sort(np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2), axis=1)
    np.testing.assert_allclose(sides[:, 0], sides[:, 1], rtol=1e-12)
    np.testing.assert_allclose(sides[:, 2], np.sqrt(2) * sides[:, 0], rtol=1e-12)


def test_refines_only_where_asked():
    t = quadtree_triangulation(near((0.3, 0.7), 10), 10)
    # a uniform tree of that depth has 4^10 leaves; this one O(depth) rings of them
    assert len(t.faces) < 1200
    deepest = t.points[t.faces[t.leaf_depth == 10]].mean(axis=1)
    assert np.abs(deepest - [0.3, 0.7]).max() < 3 / 2 ** 10


def test_a_finer_tree_keeps_every_node_of_a_coarser_one():
    coarse = quadtree_triangulation(near((0.3, 0.7), 6), 9)
    fine = quadtree_triangulation(near((0.3, 0.7), 9), 9)
    assert np.isin(coarse.keys, fine.keys).all()
    assert len(fine.keys) > len(coarse.keys)
    assert (np.diff(fine.keys) > 0).all()


def test_a_leaf_next_to_split_children_is_split():
    # asked to split only the corner cell down to level 3: its neighbours at level 1 must
    # split too (they would meet leaves two levels finer)
    split = balanced_splits(near((0.0, 0.0), 3), 3)
    assert list(split[0]) == [0]
    assert sorted(split[1]) == [0, 1, 2]  # the corner cell and both edge neighbours
    assert list(split[2]) == [0]
    assert len(split[3]) == 0


def test_depth_below_one_is_refused():
    with pytest.raises(ValueError, match="max_depth must be at least 1"):
        balanced_splits(nowhere, 0)
