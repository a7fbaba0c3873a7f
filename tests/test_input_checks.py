"""find_holes checks its input as fill_holes does, and face ids given as floats are taken only
when they are whole numbers, never truncated (issue 19, item 5)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from surfinpaint import MeshError, conventional_fill, fill_holes, find_holes, validate_mesh
from surfinpaint.data import sphere
from surfinpaint.fill.holes import hole_numbers, select_holes
from surfinpaint.geometry.validation import face_ids


@pytest.fixture(scope="module")
def holed():
    v, f = sphere(2)
    return v, f[1:]


def _nonmanifold(v, f):
    """A fin: a third face on an interior edge of the last face, over a new vertex."""
    a, b = f[-1][0], f[-1][1]
    v = np.vstack([v, v[a] + v[b]])
    return v, np.vstack([f, [b, a, len(v) - 1]])


@pytest.mark.parametrize(("broken", "match", "ids"), [
    (lambda v, f: (v, np.vstack([f, [0, 1, 10**6]])), "vertex ids >= the vertex count", "faces"),
    (lambda v, f: (v, np.vstack([f, [0, 1, -1]])), "negative vertex ids", "faces"),
    (lambda v, f: (v, f[:, :2]), "faces must be an", None),
    (lambda v, f: (np.where(np.arange(len(v))[:, None] == 3, np.nan, v), f), "NaN", "vertices"),
    (lambda v, f: _nonmanifold(v, f), "1 non-manifold edge ", "edges"),
    (lambda v, f: (v, np.vstack([f, f[-1:]])), "1 duplicate face:", "faces"),
])
def test_find_holes_refuses_what_fill_holes_refuses(holed, broken, match, ids):
    # before: IndexError / "negative axis 0 index" from numpy, a non-manifold edge called
    # "not consistently oriented", NaN coordinates taken
    v, f = broken(*holed)
    for call in (lambda: find_holes(v, f), lambda: fill_holes(v, f, method="fair"),
                 lambda: select_holes(v, f), lambda: hole_numbers(v, f, [])):
        with pytest.raises(MeshError, match=match) as info:
            call()
        if ids:
            assert getattr(info.value, ids), f"the error names no {ids}"
    # the caller that has checked may skip the checks (fill_holes' own path)
    if match == "duplicate faces":
        assert len(find_holes(v, f, validate=False)) == 1


def test_find_holes_checks_loops_given_directly(holed):
    v, f = _nonmanifold(*holed)
    loop = find_holes(*holed)[0].loop
    with pytest.raises(MeshError, match="1 non-manifold edge "):
        select_holes(v, f, [loop])


def test_non_whole_float_face_ids_are_refused(holed):
    # before: faces + 0.3 were truncated to the faces and filled as if nothing were wrong
    v, f = holed
    bad = f.astype(float)
    bad[[4, 9], 1] += 0.3
    for call in (lambda: fill_holes(v, bad, method="fair"), lambda: find_holes(v, bad),
                 lambda: validate_mesh(v, bad), lambda: face_ids(bad)):
        with pytest.raises(MeshError, match="2 faces have vertex ids that are not whole") as e:
            call()
        assert e.value.faces == [4, 9]
    for value in (np.nan, np.inf, 2.0**70):
        worse = f.astype(float)
        worse[7, 0] = value
        with pytest.raises(MeshError, match="not whole numbers: 7") as e:
            face_ids(worse)
    with pytest.raises(MeshError, match="dtype bool"):
        face_ids(f > 3)
    with pytest.raises(MeshError, match="dtype complex"):
        find_holes(v, f.astype(complex))


def test_whole_number_float_face_ids_are_taken(holed):
    # what np.loadtxt, MATLAB and JSON readers give: exact, so the same fill
    v, f = holed
    as_floats = f.astype(np.float64)
    for kind in (np.float32, np.float64):
        ids = face_ids(as_floats.astype(kind))
        assert ids.dtype == np.int64
        np.testing.assert_array_equal(ids, f)
    ints = fill_holes(v, f, method="fair", jobs=1)
    floats = fill_holes(v, as_floats, method="fair", jobs=1)
    np.testing.assert_array_equal(ints.faces, floats.faces)
    np.testing.assert_array_equal(ints.vertices, floats.vertices)
    assert [h.loop.tolist() for h in find_holes(v, as_floats)] == \
        [h.loop.tolist() for h in find_holes(v, f)]
    validate_mesh(v, as_floats)
    np.testing.assert_array_equal(face_ids(np.array([[1, 2, 3]], dtype=np.uint64)), [[1, 2, 3]])
    with pytest.raises(MeshError, match="int64 range"):
        face_ids(np.array([[1, 2, 2**63 + 5]], dtype=np.uint64))


def test_conventional_fill_refuses_non_whole_face_ids(holed):
    v, f = holed
    loop = find_holes(v, f)[0].loop
    with pytest.raises(MeshError, match="not whole numbers"):
        conventional_fill(v, f + 0.5, loop)
    new_v, new_f = conventional_fill(v, f.astype(float), loop)
    assert len(new_f) > 0


def test_conformal_fill_refuses_non_whole_face_ids(holed):
    from surfinpaint.fill.conformal import conformal_fill

    v, f = holed
    loop = find_holes(v, f)[0].loop
    with pytest.raises(MeshError, match="not whole numbers"):
        conformal_fill(v, f + 0.5, loop)


@pytest.mark.parametrize("entry", ["fill_holes", "find_holes", "validate_mesh"])
def test_ragged_face_lists_are_refused_naming_the_odd_faces(entry):
    # a face list whose rows differ in length: numpy's "inhomogeneous shape" ValueError
    # before; now a MeshError naming the faces that are not triangles
    import surfinpaint

    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    faces = [[0, 1, 2], [2, 1], [1, 3, 2], [0, 1, 2, 3]]
    with pytest.raises(MeshError, match=r"most faces have 3 ids, faces 1 \(2 ids\), "
                                        r"3 \(4 ids\) do not"):
        getattr(surfinpaint, entry)(v, faces)


@pytest.mark.parametrize(("n", "expected"), [(0, "0 faces have"), (1, "1 face has"),
                                             (2, "2 faces have"), (101, "101 faces have")])
def test_how_many_agrees_with_its_count(n, expected):
    from surfinpaint.errors import how_many

    assert how_many(n, "face has", "faces have") == expected



def _off_float64(v, dtype):
    """``v`` in ``dtype``, every third vertex off the float64 numbers: a longdouble nudged
    by a quarter of float64's spacing (x86's 64-bit mantissa holds it), an int64 past 2**53
    made odd."""
    if dtype is np.int64:
        given = (v * 2.0**60).astype(np.int64)
        given[::3] |= 1
        return given
    given = v.astype(np.longdouble)
    given[::3] += given[::3] * np.longdouble(np.finfo(np.float64).eps / 4)
    return given


@pytest.mark.parametrize(("dtype", "make"), [
    (np.float32, lambda v: v.astype(np.float32)), (np.float16, lambda v: v.astype(np.float16)),
    (np.int32, lambda v: (v * 1000).astype(np.int32)),
    (np.int16, lambda v: (v * 1000).astype(np.int16)),
    (np.longdouble, lambda v: _off_float64(v, np.longdouble)),
    (np.int64, lambda v: _off_float64(v, np.int64))])
def test_vertices_float64_cannot_hold_are_warned_and_the_others_kept_exactly(holed, dtype,
                                                                              make):
    # float16/32 and small integers are float64 numbers: filled silently, originals equal;
    # a longdouble's or a big int64's may not be: they came back rounded without a word
    v, f = holed
    given = make(v)
    inexact = int(np.count_nonzero((given.astype(np.float64).astype(dtype) != given).any(1)))
    if dtype in (np.longdouble, np.int64) and np.finfo(np.longdouble).nmant > 52:
        assert inexact == -(-len(v) // 3)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(given, f)
    said = [w for w in caught if "cannot be stored as float64" in str(w.message)]
    assert result.vertices.dtype == np.float64
    np.testing.assert_array_equal(result.vertices[:len(v)], given.astype(np.float64))
    if inexact == 0:
        assert said == [] and np.array_equal(result.vertices[:len(v)], given)
    else:
        assert [str(w.message) for w in said] == [
            f"{inexact} vertices of the {np.dtype(dtype)} input cannot be stored as float64, "
            "the fill's and its result's number type: rounded to the nearest float64 (the "
            "original vertices of the result are these rounded values)"]
        assert said[0].filename == __file__
