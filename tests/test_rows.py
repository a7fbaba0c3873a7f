import numpy as np
import pytest

from surfinpaint.geometry.mesh import faces_near, k_ring
from surfinpaint.geometry.rows import (
    row_cross,
    row_max,
    row_means,
    row_min,
    row_norms,
    row_sums,
    rows_all,
    rows_any,
)

SHAPES = [(0, 3), (6, 0), (1, 1), (9, 2), (9, 3), (5, 4), (4, 3, 3), (2000, 3), (3,)]


@pytest.mark.parametrize("shape", SHAPES)
def test_rows_any_and_all_are_numpys_any_and_all_over_the_last_axis(shape):
    rng = np.random.default_rng(len(shape) * 100 + shape[-1])
    for p in (0.0, 0.2, 0.8, 1.0):  # all False, mixed, all True
        a = rng.random(shape) < p
        assert np.array_equal(rows_any(a), a.any(axis=-1))
        assert np.array_equal(rows_all(a), a.all(axis=-1))
        assert np.asarray(rows_any(a)).dtype == bool


def test_rows_of_numbers_count_nonzero_and_nan_as_true():
    a = np.array([[0.0, 0.0, 0.0], [0.0, -0.0, 2.5], [np.nan, 0.0, 0.0], [1, 1, np.inf]])
    assert rows_any(a).tolist() == a.any(axis=1).tolist() == [False, True, True, True]
    assert rows_all(a).tolist() == a.all(axis=1).tolist() == [False, False, False, True]
    ids = np.array([[0, 3, 1], [2, 2, 2]])
    assert rows_all(ids).tolist() == [False, True]


def test_rows_of_a_strided_view_and_the_input_left_unchanged():
    rng = np.random.default_rng(7)
    shared = rng.random((50, 3, 3)) < 0.3
    kept = shared.copy()
    # the middle axis, as the triangle test reduces it
    assert np.array_equal(rows_any(shared.swapaxes(1, 2)), shared.any(axis=1))
    assert np.array_equal(rows_all(shared[:, ::2, :]), shared[:, ::2, :].all(axis=-1))
    assert np.array_equal(shared, kept)  # the columns are combined in a copy


def test_rows_need_an_axis():
    with pytest.raises(ValueError, match="at least one axis"):
        rows_any(np.bool_(True))


def _grid_faces(n=7):
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    return np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                           np.stack([a, c, d], -1).reshape(-1, 3)])


def test_ring_growth_through_rows_any_is_the_mask_any_growth():
    faces = _grid_faces()
    n = int(faces.max()) + 1
    for rings in (0, 1, 2, 3):
        mask = np.zeros(n, bool)
        mask[[24]] = True
        for _ in range(rings):
            mask[faces[mask[faces].any(axis=1)].ravel()] = True
        assert np.array_equal(faces_near(faces, np.array([24]), rings, n),
                              faces[mask[faces].any(axis=1)])
    ring = k_ring(faces, np.array([0]), 2, n)
    assert np.flatnonzero(ring).tolist() == [0, 1, 2, 7, 8, 9, 14, 15, 16]


def _hard_floats(shape, seed):
    """Floats over 20 decades with signed zeros and exact ties: sums that depend on order."""
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(shape) * 10.0 ** rng.integers(-10, 10, shape)
    x[rng.random(shape) < 0.05] = 0.0
    x[rng.random(shape) < 0.05] *= -0.0
    return x


def _same_bits(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.mark.parametrize("shape", [(500, 3), (500, 2), (300, 3, 3), (200, 4), (50, 7), (40, 8),
                                   (40, 12), (9, 1)])
def test_row_sums_norms_means_maxima_minima_are_numpys_to_the_bit(shape):
    x = _hard_floats(shape, sum(shape))
    assert _same_bits(row_sums(x), x.sum(axis=-1))
    assert _same_bits(row_norms(x), np.linalg.norm(x, axis=-1))
    assert _same_bits(row_means(x), x.mean(axis=-1))
    assert _same_bits(row_max(x), x.max(axis=-1))
    assert _same_bits(row_min(x), x.min(axis=-1))
    if x.ndim == 3:  # a middle axis, as the triangle tests reduce corners
        assert _same_bits(row_means(x.swapaxes(1, 2)), x.mean(axis=1))
        assert _same_bits(row_max(x.swapaxes(1, 2)), x.max(axis=1))


def test_a_sum_in_another_order_differs_so_the_order_is_checked():
    # the control: the data above tell left-to-right sums from others
    x = _hard_floats((500, 3), 503)
    assert not _same_bits(x[:, 0] + (x[:, 1] + x[:, 2]), x.sum(axis=-1))


def test_float_rows_of_integers_nan_and_empty_rows():
    ids = np.array([[3, 4], [0, 0]])
    assert _same_bits(row_norms(ids), np.linalg.norm(ids, axis=-1))
    assert _same_bits(row_means(ids), ids.mean(axis=-1))
    x = np.array([[1.0, np.nan, 2.0], [np.inf, 1.0, -np.inf]])
    with np.errstate(invalid="ignore"):  # inf - inf
        for ours, numpys in ((row_max, np.max), (row_min, np.min), (row_sums, np.sum)):
            assert _same_bits(ours(x), numpys(x, axis=-1))
    assert _same_bits(row_sums(np.zeros((4, 0))), np.zeros((4, 0)).sum(axis=-1))
    with pytest.raises(ValueError, match="zero-size"):
        row_max(np.zeros((4, 0)))


def test_row_cross_is_numpys_cross_to_the_bit():
    a, b = _hard_floats((400, 3), 11), _hard_floats((400, 3), 12)
    assert _same_bits(row_cross(a, b), np.cross(a, b))
    assert _same_bits(row_cross(a[:, None], b[None, :5]), np.cross(a[:, None], b[None, :5]))
    assert _same_bits(row_cross(a, b[:1]), np.cross(a, b[:1]))  # broadcast
    ints = np.array([[1, 2, 3], [4, 5, 6]])
    assert _same_bits(row_cross(ints, ints[::-1]), np.cross(ints, ints[::-1]))
    with pytest.raises(ValueError, match="rows of 3"):
        row_cross(a[:, :2], b[:, :2])
