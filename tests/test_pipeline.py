"""fill_holes: hole selection, invariants of the output, reports, the local neighbourhood."""

import numpy as np
import pytest

from surfinpaint import FillError, MeshError, fill_holes, find_holes
from surfinpaint.data import sphere
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import boundary_loops, unique_edges


@pytest.fixture(scope="module")
def sphere_with_three_holes():
    v, f = sphere(3)
    cut = cut_holes(v, f, [0, 20, 40], [0.25, 0.3, 0.2])
    return cut.vertices, cut.faces, cut


def assert_valid_fill(vertices, faces, result, expected_loops_left):
    n = len(vertices)
    assert np.array_equal(result.vertices[:n], vertices)  # bitwise, in order
    assert np.array_equal(result.faces[: len(faces)], faces)
    assert np.isfinite(result.vertices).all()
    _, _, count = unique_edges(result.faces)
    assert count.max() <= 2
    assert len(boundary_loops(result.faces)) == expected_loops_left
    used = np.unique(result.faces)
    assert np.array_equal(np.setdiff1d(np.arange(n, len(result.vertices)), used), [])


@pytest.mark.parametrize("fair_order", [None, 1, 3])
def test_faired_fill_closes_every_hole(sphere_with_three_holes, fair_order):
    v, f, _ = sphere_with_three_holes
    result = fill_holes(v, f, method="fair", fair_order=fair_order)
    assert_valid_fill(v, f, result, 0)
    assert [r.method for r in result.reports] == ["fair"] * 3
    assert [r.fair_order for r in result.reports] == [fair_order or 2] * 3
    assert sum(r.new_faces for r in result.reports) == len(result.faces) - len(f)
    assert sum(r.new_vertices for r in result.reports) == len(result.vertices) - len(v)


def test_only_the_chosen_holes_are_filled(sphere_with_three_holes):
    v, f, _ = sphere_with_three_holes
    holes = find_holes(v, f)
    result = fill_holes(v, f, holes=[0, 2], method="fair")
    assert_valid_fill(v, f, result, 1)
    left = boundary_loops(result.faces)[0]
    assert set(left) == set(holes[1].loop)
    # by loop, reversed and rotated
    loop = np.roll(holes[1].loop[::-1], 2)
    result = fill_holes(v, f, holes=[loop], method="fair")
    assert_valid_fill(v, f, result, 2)


def test_max_hole_edges_skips_and_reports(sphere_with_three_holes):
    v, f, _ = sphere_with_three_holes
    sizes = [h.n_edges for h in find_holes(v, f)]
    limit = sorted(sizes)[1]
    result = fill_holes(v, f, method="fair", max_hole_edges=limit)
    skipped = [r for r in result.reports if r.skipped]
    assert len(skipped) == sum(s > limit for s in sizes) and skipped[0].new_faces == 0
    assert_valid_fill(v, f, result, len(skipped))


def test_closed_mesh_returns_a_copy():
    v, f = sphere(2)
    result = fill_holes(v, f, method="fair")
    assert result.reports == [] and np.array_equal(result.faces, f)
    result.vertices[0] = 99.0
    assert v[0, 0] != 99.0


def test_unknown_method_and_bad_holes():
    v, f = sphere(2)
    with pytest.raises(ValueError, match="unknown method"):
        fill_holes(v, f, method="magic")
    with pytest.raises(MeshError, match="out of range"):
        fill_holes(v, f[1:], holes=[5], method="fair")


def test_conformal_failure_falls_back_to_the_faired_fill(sphere_with_three_holes, monkeypatch):
    import surfinpaint.fill.conformal.candidates as candidates

    def broken(*args, **kwargs):
        raise FillError("forced failure")

    monkeypatch.setattr(candidates, "inpaint_patch", broken)
    monkeypatch.setattr(candidates, "inpaint_patch_on_mesh", broken)
    v, f, _ = sphere_with_three_holes
    with pytest.warns(UserWarning, match="forced failure"):
        result = fill_holes(v, f, holes=[0])
    assert result.reports[0].method == "fair"
    assert "forced failure" in result.reports[0].fallback
    assert_valid_fill(v, f, result, 2)
    # the faired fill of the order the self-check chose, or of the order asked for
    order = result.reports[0].fair_order
    assert np.array_equal(result.vertices, fill_holes(v, f, holes=[0], method="fair",
                                                      fair_order=order).vertices)
    for asked_order in (2, 3):
        with pytest.warns(UserWarning, match="forced failure"):
            asked = fill_holes(v, f, holes=[0], fair_order=asked_order)
        assert asked.reports[0].fair_order == asked_order
        assert np.array_equal(asked.vertices, fill_holes(v, f, holes=[0], method="fair",
                                                         fair_order=asked_order).vertices)


def test_fair_order_is_checked(sphere_with_three_holes):
    v, f, _ = sphere_with_three_holes
    for bad in (0, 4, 2.5):
        with pytest.raises(ValueError, match="fair_order"):
            fill_holes(v, f, method="fair", fair_order=bad)


def test_inputs_are_not_modified(sphere_with_three_holes):
    v, f, _ = sphere_with_three_holes
    v0, f0 = v.copy(), f.copy()
    fill_holes(v, f, method="conformal")
    assert np.array_equal(v, v0) and np.array_equal(f, f0)


def test_progress_callback_sees_every_hole(sphere_with_three_holes):
    v, f, _ = sphere_with_three_holes
    seen = []
    fill_holes(v, f, method="fair", progress=lambda done, total, msg: seen.append((done, total)))
    assert (3, 3) in seen and all(total == 3 for _, total in seen)


def _rings_brute_force(faces, seeds, rings):
    """The faces within ``rings`` vertex rings of ``seeds``, ring by ring over all faces."""
    region = set(np.asarray(seeds).tolist())
    picked: set[int] = set()
    for _ in range(rings):
        new = {t for t, face in enumerate(faces.tolist()) if region & set(face)}
        picked |= new
        region |= {v for t in new for v in faces[t].tolist()}
    return sorted(picked)


@pytest.mark.parametrize("rings", [1, 2, 5, 40])
def test_hole_neighbourhoods_are_the_faces_within_the_rings(rings):
    # the cut of a hole, the faces added by an earlier hole included, against a brute-force
    # ring growth over the original and added faces together
    from surfinpaint.fill.neighbourhood import FilledMesh
    from surfinpaint.fill.results import Fill

    v, f = sphere(3)
    cut = cut_holes(v, f, [v[0], v[len(v) // 2]], 0.3)
    mesh = FilledMesh(cut.vertices, cut.faces)
    first, second = cut.holes[0].loop, cut.holes[1].loop
    local = mesh.cut(first, 2)
    centre = local.vertices[local.local_loop].mean(axis=0)
    n = len(local.local_loop)  # a fan from a new centre vertex
    fan = np.column_stack([local.local_loop, np.roll(local.local_loop, -1),
                           np.full(n, len(local.vertices))])
    assert mesh.stitch(local, Fill(centre[None], fan, "fair")) is None
    everything = np.concatenate([cut.faces, *mesh.face_blocks])
    for seeds in (second, first, np.r_[first[:3], second[:2]]):
        got = mesh.cut(seeds, rings)
        want = _rings_brute_force(everything, seeds, rings)
        np.testing.assert_array_equal(got.faces_global, everything[want])
