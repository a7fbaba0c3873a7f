"""Geodesic-disk cuts leave exactly one clean hole and return the removed truth."""

from __future__ import annotations

import numpy as np
import pytest

from surfinpaint import data
from surfinpaint.errors import MeshError
from surfinpaint.geometry.cutting import cut_geodesic_disk, cut_holes
from surfinpaint.geometry.mesh import boundary_loops, mean_edge_length, unique_edges


def face_set(faces):
    return set(map(tuple, np.sort(faces, axis=1).tolist()))


def check_cut(v, f, cut, n_holes=1, original_loops=0):
    # removed and remaining faces partition the original faces
    assert len(cut.faces) + sum(len(h.truth_faces) for h in cut.holes) == len(f)
    remaining = face_set(cut.kept[cut.faces])
    removed = set().union(*(face_set(h.truth_ids[h.truth_faces]) for h in cut.holes))
    assert remaining | removed == face_set(f) and not remaining & removed
    # vertex order preserved, positions untouched
    assert (np.diff(cut.kept) > 0).all()
    np.testing.assert_array_equal(cut.vertices, v[cut.kept])
    # each hole: one simple boundary loop of existing vertices; nothing else opened, and no
    # pinched vertex (a vertex with more than two boundary edges)
    loops = boundary_loops(cut.faces)
    assert len(loops) == n_holes + original_loops
    e, _, count = unique_edges(cut.faces)
    assert count.max() <= 2
    assert np.bincount(e[count == 1].ravel()).max() == 2
    for hole in cut.holes:
        assert hole.loop.min() >= 0 and hole.loop.max() < len(cut.vertices)
        assert len(np.unique(hole.loop)) == len(hole.loop) >= 3
        assert any(len(lp) == len(hole.loop) and set(lp.tolist()) == set(hole.loop.tolist())
                   for lp in loops)
        # the truth is a disk whose border is the hole's loop
        tv, tf = hole.truth_vertices, hole.truth_faces
        e, _, c = unique_edges(tf)
        assert len(np.unique(tf)) - len(e) + len(tf) == 1
        (truth_loop,) = boundary_loops(tf)
        np.testing.assert_array_equal(np.sort(hole.truth_ids[truth_loop]),
                                      np.sort(cut.kept[hole.loop]))
        np.testing.assert_array_equal(tv, v[hole.truth_ids])
    return loops


def test_cap_on_sphere():
    v, f = data.sphere(3)
    v0, f0 = v.copy(), f.copy()
    radius = 0.5
    cut = cut_geodesic_disk(v, f, 0, radius)
    np.testing.assert_array_equal(v, v0)  # inputs untouched
    np.testing.assert_array_equal(f, f0)
    check_cut(v, f, cut)
    # removed vertices are within the (graph-geodesic ≥ Euclidean) radius of the centre
    removed = np.setdiff1d(np.arange(len(v)), cut.kept)
    assert len(removed) > 0
    assert (np.linalg.norm(v[removed] - v[0], axis=1) <= radius + 1e-12).all()
    # the loop lies about one radius away (on the unit sphere: angle ≈ radius)
    h = mean_edge_length(v, f)
    angle = np.arccos(np.clip(cut.vertices[cut.loop] @ v[0], -1, 1))
    assert np.all(angle < radius + 1e-9) and np.all(angle > radius - 1.5 * h)
    # the diameter of a cap's rim of angular radius θ is 2 sin θ
    assert cut.diameter == pytest.approx(2 * np.sin(angle.mean()), rel=0.05)


def test_loop_orientation_follows_the_faces():
    v, f = data.sphere(3)
    cut = cut_geodesic_disk(v, f, 5, 0.4)
    loop = cut.loop
    half = {tuple(e) for e in np.concatenate(
        [cut.faces[:, [0, 1]], cut.faces[:, [1, 2]], cut.faces[:, [2, 0]]]).tolist()}
    assert all((int(a), int(b)) in half for a, b in zip(loop, np.roll(loop, -1), strict=True))


def test_centre_given_as_a_point():
    v, f = data.sphere(3)
    a = cut_geodesic_disk(v, f, v[17] + 1e-3, 0.4)
    b = cut_geodesic_disk(v, f, 17, 0.4)
    np.testing.assert_array_equal(a.faces, b.faces)
    assert a.holes[0].center == 17


@pytest.mark.parametrize("name", ["torus", "cube", "tooth", "snowman"])
def test_random_cuts_always_leave_one_clean_hole(name):
    make = {"torus": lambda: data.torus(n_major=48, n_minor=20), "cube": lambda: data.cube(10),
            "tooth": lambda: data.tooth(0.1), "snowman": lambda: data.snowman(0.12)}[name]
    v, f = make()
    h = mean_edge_length(v, f)
    diag = np.linalg.norm(np.ptp(v, axis=0))
    rng = np.random.default_rng(1)
    for _ in range(12):
        centre = int(rng.integers(len(v)))
        radius = rng.uniform(2 * h, max(0.12 * diag, 6 * h))
        check_cut(v, f, cut_geodesic_disk(v, f, centre, radius))


def test_cube_corner_cut_spans_three_sides():
    v, f = data.cube(10)
    cut = cut_geodesic_disk(v, f, np.zeros(3), 0.35)
    check_cut(v, f, cut)
    p = cut.vertices[cut.loop]
    # the rim crosses all three sides meeting at the corner
    for axis in range(3):
        assert (np.abs(p[:, axis]) < 1e-12).any()


def jittered_grid():
    from conftest import grid_mesh

    v, f = grid_mesh(20, 20)
    rng = np.random.default_rng(5)
    v[:, :2] += rng.normal(scale=0.012, size=(len(v), 2))
    return v, f


def raw_removal(v, f, centre, radius):
    """Faces with all corners within the Dijkstra radius, without any cleanup."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import dijkstra

    e, _, _ = unique_edges(f)
    w = np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1)
    g = sp.coo_matrix((w, (e[:, 0], e[:, 1])), shape=(len(v), len(v))).tocsr()
    d = dijkstra(g, directed=False, indices=centre, limit=radius)
    return (d <= radius)[f].all(axis=1)


@pytest.mark.parametrize(("centre", "radius"), [(69, 0.0717), (240, 0.0668)])
def test_pinch_is_cleaned(centre, radius):
    # on an irregular mesh the plain rule "remove faces inside the radius" can leave a vertex
    # where two hole-boundary edges start (a bow-tie); the cut must grow the hole instead
    v, f = jittered_grid()
    raw = raw_removal(v, f, centre, radius)
    kept = f[~raw]
    e, _, count = unique_edges(kept)
    outer = np.zeros(len(v), bool)
    outer[unique_edges(f)[0][unique_edges(f)[2] == 1].ravel()] = True
    border = e[(count == 1) & ~outer[e].any(axis=1)]
    assert np.bincount(border.ravel()).max() > 2  # the raw cut is pinched
    cut = cut_geodesic_disk(v, f, centre, radius)
    check_cut(v, f, cut, original_loops=1)
    assert len(cut.truth_faces) > raw.sum()
    # flat and regular elsewhere: rings of the jittered grid never pinch at these radii
    for r in np.linspace(0.08, 0.3, 6):
        check_cut(v, f, cut_geodesic_disk(v, f, 220, r), original_loops=1)


def test_several_disjoint_holes():
    v, f = data.sphere(3)
    centres = [int(np.argmax(v[:, k])) for k in range(3)]
    cut = cut_holes(v, f, centres, [0.3, 0.4, 0.5])
    check_cut(v, f, cut, n_holes=3)
    assert [h.center for h in cut.holes] == centres
    with pytest.raises(ValueError, match="overlap"):
        cut_holes(v, f, [0, 0], [0.3, 0.3])
    with pytest.raises(AttributeError, match="3 holes"):
        _ = cut.loop


def test_bad_requests_raise():
    v, f = data.sphere(2)
    with pytest.raises(ValueError, match="no whole face"):
        cut_geodesic_disk(v, f, 0, 1e-3)
    with pytest.raises(ValueError, match="positive"):
        cut_geodesic_disk(v, f, 0, -1.0)
    with pytest.raises(ValueError, match="out of range"):
        cut_geodesic_disk(v, f, len(v), 0.5)
    dv, df = data.bumpy_disk(8)
    with pytest.raises(ValueError, match="boundary"):
        cut_geodesic_disk(dv, df, 0, 1.5)
    # a band around the torus tube is not a disk
    tv, tf = data.torus(n_major=32, n_minor=12)
    with pytest.raises(ValueError, match="disk|loops"):
        cut_geodesic_disk(tv, tf, 0, 1.5)
    bad = np.vstack([f, f[:1]])
    with pytest.raises(MeshError, match="edge-manifold"):
        cut_geodesic_disk(v, bad, 0, 0.5)


def test_ring_distances_and_submesh_keep_rings_and_order():
    from surfinpaint.geometry.cutting import ring_distances, submesh
    from surfinpaint.geometry.mesh import k_ring

    v, f = data.sphere(3)
    seeds = np.array([0, 5])
    ring = ring_distances(f, len(v), seeds, 3.5)
    for k in range(4):
        assert np.array_equal(ring <= k, k_ring(f, seeds, k, len(v)))
    assert np.isinf(ring[~k_ring(f, seeds, 3, len(v))]).all()
    sv, sf, ids = submesh(v, f, ring <= 3)
    assert np.array_equal(ids, np.sort(ids)) and np.array_equal(sv, v[ids])
    whole = f[(ring <= 3)[f].all(axis=1)]
    assert np.array_equal(ids[sf], whole)  # the same faces, in the same order


def _outcome(v, f, centres, radii):
    """A cut's arrays, or its error message."""
    try:
        cut = cut_holes(v, f, centres, radii)
    except ValueError as exc:
        return str(exc)
    return [cut.vertices, cut.faces, cut.kept] + [
        a for h in cut.holes for a in (h.loop, h.truth_faces, h.truth_ids)]


def _same(a, b):
    if isinstance(a, str) or isinstance(b, str):
        return a == b
    return len(a) == len(b) and all(x.dtype == y.dtype and np.array_equal(x, y)
                                    for x, y in zip(a, b, strict=True))


def _count_whole_mesh_cleanups(monkeypatch) -> list[bool]:
    """Per call of cutting's cleanup from now on: whether it ran on the whole mesh."""
    from surfinpaint.geometry import cutting

    whole_calls: list[bool] = []
    clean = cutting._clean

    def counted(patch, *args):
        whole_calls.append(patch.border is None)
        return clean(patch, *args)

    monkeypatch.setattr(cutting, "_clean", counted)
    return whole_calls


@pytest.mark.parametrize("name", ["sphere", "torus", "snowman", "jittered"])
def test_a_cut_cleaned_in_a_window_equals_the_whole_mesh_cleanup(name, monkeypatch):
    from surfinpaint.geometry import cutting

    v, f = {"sphere": lambda: data.sphere(3), "torus": lambda: data.torus(n_major=48, n_minor=20),
            "snowman": lambda: data.snowman(0.12), "jittered": jittered_grid}[name]()
    h = mean_edge_length(v, f)
    diag = np.linalg.norm(np.ptp(v, axis=0))
    rng = np.random.default_rng(7)
    cases = [([int(rng.integers(len(v)))], [rng.uniform(h, max(0.3 * diag, 6 * h))])
             for _ in range(10)]
    cases.append((list(rng.integers(len(v), size=3)), list(rng.uniform(2 * h, 5 * h, 3))))
    if name == "jittered":  # the cuts whose raw removal is pinched
        cases += [([69], [0.0717]), ([240], [0.0668])]
    whole_calls = _count_whole_mesh_cleanups(monkeypatch)
    windowed = [_outcome(v, f, c, r) for c, r in cases]
    assert whole_calls.count(False) >= len(cases)  # the windows did the work ...
    monkeypatch.setattr(cutting, "WINDOW_RINGS", ())
    whole = [_outcome(v, f, c, r) for c, r in cases]
    assert all(_same(a, b) for a, b in zip(windowed, whole, strict=True))
    # ... and a window too small to decide falls back to the whole mesh, same result (the
    # faces at the disk's vertices hold a plain cut, not the stars a pinch adds)
    monkeypatch.setattr(cutting, "WINDOW_RINGS", (0,))
    whole_calls.clear()
    narrow = [_outcome(v, f, c, r) for c, r in cases]
    assert any(whole_calls) == (name == "jittered")
    assert all(_same(a, b) for a, b in zip(narrow, whole, strict=True))


def test_a_band_around_a_tube_is_decided_on_the_whole_mesh(monkeypatch):
    # a disk as wide as a thin tube's girth cuts the tube in two: which side stays depends
    # on the pieces' sizes far beyond any window, so the whole mesh decides
    from surfinpaint.geometry import cutting

    v, f = data.torus(R=1.0, r=0.05, n_major=160, n_minor=8)
    whole_calls = _count_whole_mesh_cleanups(monkeypatch)
    windowed = _outcome(v, f, [0], [0.3])
    assert whole_calls[-1]  # the windows could not tell
    monkeypatch.setattr(cutting, "WINDOW_RINGS", ())
    assert _same(windowed, _outcome(v, f, [0], [0.3]))


def test_renumber_numbers_the_used_vertices_in_id_order():
    from surfinpaint.geometry.cutting import renumber

    f = np.array([[6, 2, 4], [4, 2, 7], [9, 6, 7]])
    ids, local = renumber(f)
    assert ids.tolist() == [2, 4, 6, 7, 9]
    assert local.tolist() == [[2, 0, 1], [1, 0, 3], [4, 2, 3]]
    np.testing.assert_array_equal(ids[local], f)  # the same triangles, renumbered
    ids, local = renumber(f[:1].astype(np.int32))
    assert ids.tolist() == [2, 4, 6] and local.tolist() == [[2, 0, 1]]
    ids, local = renumber(np.empty((0, 3), int))
    assert ids.size == 0 and local.shape == (0, 3)
    # ids far apart (sorted) and close together (marked): the same numbering
    for spread in (1, 10**6):
        ids, local = renumber(f * spread)
        assert ids.tolist() == [2 * spread, 4 * spread, 6 * spread, 7 * spread, 9 * spread]
        assert local.tolist() == [[2, 0, 1], [1, 0, 3], [4, 2, 3]]


def test_compact_keeps_only_the_faces_vertices_in_id_order():
    from surfinpaint.geometry.cutting import compact

    v = np.arange(24, dtype=float).reshape(8, 3)
    f = np.array([[6, 2, 4], [4, 2, 7]])
    cv, cf, ids = compact(v, f)
    assert ids.tolist() == [2, 4, 6, 7]
    assert cf.tolist() == [[2, 0, 1], [1, 0, 3]]
    np.testing.assert_array_equal(cv, v[ids])
    np.testing.assert_array_equal(ids[cf], f)  # the same triangles, renumbered
    ev, ef, eids = compact(v, np.empty((0, 3), int))
    assert ev.shape == (0, 3) and ef.shape == (0, 3) and eids.size == 0
