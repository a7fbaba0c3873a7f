"""locate_points (geometry/point_location.py) against scipy's Delaunay point location."""

import warnings

import numpy as np
import pytest
from scipy.spatial import Delaunay

from surfinpaint.geometry.point_location import locate_points


@pytest.mark.parametrize("crowded", [0.0, 1e-4, 1e-7])
def test_finds_the_triangle_scipy_finds(crowded):
    rng = np.random.default_rng(4)
    uv = rng.random((2000, 2))
    if crowded:  # many vertices in a tiny spot, as a map squeezes a fingertip
        uv[:600] = 0.3 + crowded * rng.random((600, 2))
    tri = Delaunay(uv)
    points = np.vstack([rng.random((5000, 2)) * 1.2 - 0.1,
                        0.3 + (crowded or 1e-4) * rng.random((1000, 2))])
    expected = tri.find_simplex(points)
    face, w = locate_points(uv, tri.simplices, points, tolerance=0.0)
    inside = expected >= 0
    # the same triangle, or (on an edge) one whose weights give the same point
    np.testing.assert_array_equal(face >= 0, inside)
    back = np.einsum("pk,pkd->pd", w[inside], uv[tri.simplices[face[inside]]])
    np.testing.assert_allclose(back, points[inside], atol=1e-12)
    assert (w[inside] >= -1e-12).all()
    assert np.isnan(w[~inside]).all()


def test_points_on_vertices_edges_and_the_outer_border_are_found():
    uv = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    faces = np.array([[0, 1, 2], [1, 3, 2]])
    points = np.array([[1.0, 1.0], [0.5, 0.5], [1.0, 0.3], [0.0, 0.0], [1.0 + 1e-12, 0.5]])
    face, w = locate_points(uv, faces, points)
    assert (face >= 0).all()
    np.testing.assert_allclose(np.einsum("pk,pkd->pd", w, uv[faces[face]]), points, atol=1e-11)


def test_of_overlapping_triangles_the_one_it_is_deepest_in_is_taken():
    # a folded map: two triangles cover the point, it lies deeper in the second
    uv = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.4, 0.4], [-1.0, -1.0], [2.0, -1.0]])
    faces = np.array([[0, 1, 2], [4, 5, 3]])
    face, _ = locate_points(uv, faces, np.array([[0.35, 0.02]]))
    assert face.tolist() == [1]


def test_degenerate_triangles_and_empty_input_hold_nothing():
    uv = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    face, w = locate_points(uv, np.array([[0, 1, 2]]), np.array([[0.5, 0.0]]))
    assert face.tolist() == [-1] and np.isnan(w).all()
    face, w = locate_points(uv, np.zeros((0, 3), int), np.array([[0.5, 0.0]]))
    assert face.tolist() == [-1]
    # off its line the weights are ±inf, and their sum no number: nothing to warn about
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        face, w = locate_points(uv, np.array([[0, 1, 2]]), np.array([[0.5, 0.5]]))
    assert face.tolist() == [-1] and np.isnan(w).all()


@pytest.mark.parametrize("chunk", [1, 3, 7, 1000])
def test_chunked_pairs_enumerate_every_pair_once_in_order(chunk):
    from surfinpaint.geometry.point_location import chunked_pairs

    count = np.array([2, 0, 5, 1, 0, 3])
    owner, offset = map(np.concatenate, zip(*chunked_pairs(count, chunk), strict=True))
    np.testing.assert_array_equal(owner, np.repeat(np.arange(6), count))
    np.testing.assert_array_equal(offset, [0, 1, 0, 1, 2, 3, 4, 0, 0, 1, 2])
    chunks = list(chunked_pairs(count, chunk))
    # no id split across chunks; no chunk much above the size asked (one id at least)
    owners = [o for o, _ in chunks if len(o)]
    assert all(o[-1] < p[0] for o, p in zip(owners, owners[1:], strict=False))
    assert all(len(o) <= max(chunk, count.max()) + count.max() for o, _ in chunks)
