"""A triangle soup (every face apart: a loop a face) costs no Python call per loop in the
hole finding, only the :class:`Hole` made for each (session 38: ``find_holes`` took 105 s
on a 328k-face soup, several numpy calls per loop). Counted, not timed."""

import sys
import warnings

import numpy as np
import pytest

from surfinpaint import fill_holes, find_holes
from surfinpaint.geometry.mesh import boundary_loops


def soup(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """``n`` separate small triangles scattered in a box (faces shuffled)."""
    rng = np.random.default_rng(seed)
    vertices = (rng.random((n, 3))[:, None, :] * 10 + rng.random((n, 3, 3)) * 0.1)
    return vertices.reshape(-1, 3), np.arange(3 * n).reshape(n, 3)[rng.permutation(n)]


def python_calls(call, *args) -> int:
    """How many Python-level function calls ``call(*args)`` makes (C calls not counted)."""
    count = 0

    def profile(frame, event, arg):
        nonlocal count
        if event == "call":
            count += 1

    sys.setprofile(profile)
    try:
        call(*args)
    finally:
        sys.setprofile(None)
    return count


def quiet_fill(vertices, faces):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fill_holes(vertices, faces, jobs=1)


@pytest.mark.parametrize("function, per_loop", [(find_holes, 1), (boundary_loops, 0),
                                                (quiet_fill, 1)])
def test_soup_costs_no_python_call_per_loop(function, per_loop):
    small, large = soup(1000), soup(3000)
    args = (lambda m: (m[1],)) if function is boundary_loops else (lambda m: m)
    python_calls(function, *args(small))  # lazy imports and caches out of the count
    extra = python_calls(function, *args(large)) - python_calls(function, *args(small))
    # the Hole each loop gets (its dataclass __init__) and nothing else a loop; the old
    # code made about 40 calls a loop (np.roll, np.linalg.norm, np.cross, ...)
    assert extra <= per_loop * 2000 + 200, extra


def test_soup_loops_are_its_faces():
    vertices, faces = soup(500, seed=3)
    holes = find_holes(vertices, faces)
    assert len(holes) == 500
    # each face is its own component and its own outer border, numbered by lowest vertex
    assert [h.component for h in holes] == list(range(500))
    assert all(h.is_border and h.n_edges == 3 for h in holes)
    by_lowest = faces[np.argsort(faces.min(axis=1))]
    for hole, face in zip(holes, by_lowest, strict=True):
        assert sorted(hole.loop.tolist()) == sorted(face.tolist())
        assert hole.diameter == pytest.approx(
            np.linalg.norm(vertices[face][:, None] - vertices[face][None], axis=2).max())
        # the loop runs as the face does (the face's outer border)
        start = int(np.flatnonzero(face == hole.loop[0])[0])
        assert hole.loop.tolist() == np.roll(face, -start).tolist()
    result = quiet_fill(vertices, faces)
    assert result.reports == [] and len(result.faces) == 500


def test_loops_found_at_once_are_the_walks():
    """A mesh with simple loops takes the vectorized way; with a bow-tie piece added (a
    pinched loop: the walk for all) its loops come out the same, in the same order."""
    from surfinpaint.data import sphere

    vertices, faces = sphere(4)
    rng = np.random.default_rng(7)
    for direction in rng.standard_normal((6, 3)):  # caps of different sizes cut away
        centres = vertices[faces].mean(axis=1)
        cosine = centres @ direction / np.linalg.norm(centres, axis=1) / np.linalg.norm(
            direction)
        faces = faces[cosine < rng.uniform(0.9, 0.99)]
    n = len(vertices)
    bow_tie = np.array([[0, 1, 2], [0, 3, 4]]) + n
    fast = boundary_loops(faces)
    walked = boundary_loops(np.vstack([faces, bow_tie]))
    assert len(fast) >= 3 and len({len(loop) for loop in fast}) > 1
    assert [loop.tolist() for loop in walked if loop.max() < n] == [
        loop.tolist() for loop in fast]
    assert sorted(sorted(loop.tolist()) for loop in walked if loop.min() >= n) == [
        [n, n + 1, n + 2], [n, n + 3, n + 4]]
