import warnings

import numpy as np
import pytest
import trimesh
from conftest import grid_mesh

from surfinpaint import fill_holes
from surfinpaint.errors import MeshError
from surfinpaint.fill.holes import find_holes, orient_loop, select_holes
from surfinpaint.geometry.mesh import boundary_loops


def sphere_with_caps(centres, radius=0.35, subdivisions=3):
    s = trimesh.creation.icosphere(subdivisions)
    v, f = np.asarray(s.vertices), np.asarray(s.faces)
    centroid = v[f].mean(axis=1)
    drop = np.zeros(len(f), bool)
    for c in centres:
        drop |= np.linalg.norm(centroid - np.asarray(c, float), axis=1) < radius
    return v, f[~drop]


def disk(n=12):
    u, w = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n), indexing="ij")
    keep = (u**2 + w**2) <= 1.0001
    ids = -np.ones(u.shape, int)
    ids[keep] = np.arange(keep.sum())
    vertices = np.column_stack([u[keep], w[keep], 0.1 * u[keep] ** 2])
    a, b, c, d = ids[:-1, :-1], ids[1:, :-1], ids[1:, 1:], ids[:-1, 1:]
    faces = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                            np.stack([a, c, d], -1).reshape(-1, 3)])
    return vertices, faces[(faces >= 0).all(axis=1)]


def test_closed_mesh_has_no_holes():
    s = trimesh.creation.icosphere(2)
    assert find_holes(s.vertices, s.faces) == []
    assert select_holes(s.vertices, s.faces) == []


def test_holes_of_a_sphere_are_holes_not_borders():
    v, f = sphere_with_caps([(0, 0, 1), (1, 0, 0)])
    holes = find_holes(v, f)
    assert len(holes) == 2
    assert not any(h.is_border for h in holes)
    for h in holes:
        pts = v[h.loop]
        # faces with centroids within 0.35 of the cap centre were removed, so the loop runs
        # between 0.35 - e and 0.35 + e from it (e: the edge length, < 0.2 here)
        assert 2 * (0.35 - 0.2) < h.diameter < 2 * (0.35 + 0.2)
        assert h.n_edges == len(h.loop)
        seg = np.linalg.norm(pts - np.roll(pts, -1, axis=0), axis=1).sum()
        assert np.isclose(h.perimeter, seg)


def test_components_are_numbered_over_the_surface_not_left_over_vertices():
    # two spheres with a hole each: the faces cut away leave vertices no face uses, which
    # must not push the second sphere's number past 1 (`holes` showed "component 13")
    v, f = sphere_with_caps([(0, 0, 1)], radius=0.5)
    w, g = sphere_with_caps([(0, 0, -1)], radius=0.5)
    holes = find_holes(np.vstack([v, w + [3.0, 0, 0]]), np.vstack([f, g + len(v)]))
    assert [h.component for h in holes] == [0, 1]
    # a closed piece between them counts (it has faces, no loop), whatever the faces' order
    c, d = sphere_with_caps([], radius=0.5)
    vertices = np.vstack([v, c + [6.0, 0, 0], w + [3.0, 0, 0]])
    faces = np.vstack([f, d + len(v), g + len(v) + len(c)])
    order = np.random.default_rng(3).permutation(len(faces))
    holes = find_holes(vertices, faces[order][:, [1, 2, 0]])
    assert [h.component for h in holes] == [0, 2]


def test_a_third_of_a_sphere_removed_is_still_a_hole():
    s = trimesh.creation.icosphere(3)
    v, f = np.asarray(s.vertices), np.asarray(s.faces)
    keep = v[f].mean(axis=1)[:, 2] < 1 / 3  # a cap of a third of the area
    holes = find_holes(v, f[keep])
    assert len(holes) == 1 and not holes[0].is_border


def test_open_disk_border_and_inner_hole():
    v, f = disk(16)
    centroid = v[f].mean(axis=1)
    f = f[np.linalg.norm(centroid[:, :2] - [0.3, 0.2], axis=1) > 0.2]
    holes = find_holes(v, f)
    assert [h.is_border for h in holes] == [True, False]
    chosen = select_holes(v, f)
    assert len(chosen) == 1 and set(chosen[0]) == set(holes[1].loop)
    assert len(select_holes(v, f, include_border=True)) == 2


def test_select_by_index_and_by_loop_any_orientation_and_start():
    v, f = sphere_with_caps([(0, 0, 1), (1, 0, 0)])
    holes = find_holes(v, f)
    assert np.array_equal(select_holes(v, f, [1])[0], holes[1].loop)
    given = np.roll(holes[0].loop[::-1], 3)  # reversed, other start
    oriented = orient_loop(f, given)
    loops = {tuple(np.roll(l, -int(np.argmin(l)))) for l in boundary_loops(f)}
    assert tuple(np.roll(oriented, -int(np.argmin(oriented)))) in loops


def test_a_hole_named_twice_is_chosen_once():
    # `fill --holes 1,1` filled hole 1, then failed on it again ("loop edges are not
    # boundary edges"): a hole named twice, by number or by loop, is filled once
    v, f = sphere_with_caps([(0, 0, 1), (1, 0, 0)])
    holes = find_holes(v, f)
    chosen = select_holes(v, f, [1, 0, 1])
    assert [len(loop) for loop in chosen] == [holes[1].n_edges, holes[0].n_edges]
    assert np.array_equal(chosen[0], holes[1].loop)
    twice = select_holes(v, f, [holes[0].loop, np.roll(holes[0].loop[::-1], 2)])
    assert len(twice) == 1
    assert len(select_holes(v, f, [holes[1].loop, holes[0].loop, holes[1].loop])) == 2
    result = fill_holes(v, f, holes=[1, 1], method="fair")
    assert [r.index for r in result.reports] == [1] and not result.reports[0].failed


def test_find_holes_takes_a_trimesh_or_pyvista_mesh_as_fill_holes_does():
    v, f = sphere_with_caps([(0, 0, 1), (1, 0, 0)])
    expected = [h.n_edges for h in find_holes(v, f)]
    assert [h.n_edges for h in find_holes(trimesh.Trimesh(v, f, process=False))] == expected
    pyvista = pytest.importorskip("pyvista")
    poly = pyvista.PolyData(v, np.column_stack([np.full(len(f), 3), f]).ravel())
    assert [h.n_edges for h in find_holes(poly)] == expected
    with pytest.raises(TypeError, match="needs faces"):
        find_holes(v)


def test_bad_hole_selection_is_named():
    v, f = sphere_with_caps([(0, 0, 1)])
    with pytest.raises(MeshError, match="out of range"):
        select_holes(v, f, [3])
    with pytest.raises(MeshError, match="not joined by a boundary edge"):
        select_holes(v, f, [[0, 1, 2]])


def test_holes_of_a_real_scan():
    pytest.importorskip("pymeshlab")
    from surfinpaint.data import pymeshlab_sample

    v, f = pymeshlab_sample("rangemaps/face000.ply")
    holes = find_holes(v, f)
    main = np.bincount([h.component for h in holes]).argmax()
    on_face = [h for h in holes if h.component == main]
    # the face itself: one outer border (its longest loop) and many small scanning holes
    assert [h.is_border for h in on_face].count(True) == 1
    assert on_face[0].is_border and on_face[0].n_edges == max(h.n_edges for h in holes)
    assert len(on_face) > 10
    # small floating pieces of the scan are bounded by their own outer border
    first_of = {}
    for h in holes:
        first_of.setdefault(h.component, h)
    assert all(h.is_border for h in first_of.values())
    # each loop is made of boundary edges of the mesh
    for h in holes:
        orient_loop(f, h.loop)


def test_one_numbering_for_holes_and_reports():
    # an open sheet (its outer border is loop 0 or 1) with one inner hole: fill's reports,
    # warnings and --holes use find_holes' numbers, the border included
    from surfinpaint import fill_holes
    from surfinpaint.fill.holes import hole_numbers

    v, f = grid_mesh(8, 8)
    centre = int(np.argmin(np.linalg.norm(v[:, :2] - 0.5, axis=1)))
    f = f[~np.isin(f, centre).any(axis=1)]
    found = find_holes(v, f)
    inner = next(k for k, h in enumerate(found) if not h.is_border)
    assert [h.is_border for h in found].count(True) == 1
    result = fill_holes(v, f, method="fair")
    assert [r.index for r in result.reports] == [inner]
    again = fill_holes(v, f, holes=[inner], method="fair")
    assert [r.index for r in again.reports] == [inner]
    np.testing.assert_array_equal(again.faces, result.faces)
    by_loop = fill_holes(v, f, holes=[found[inner].loop[::-1]], method="fair")
    assert [r.index for r in by_loop.reports] == [inner]
    assert hole_numbers(v, f, [h.loop for h in found]) == list(range(len(found)))
    assert hole_numbers(v, f, [np.array([0, 1, 2])]) == [-1]


def test_select_holes_and_hole_numbers_reuse_a_given_find_holes_answer(monkeypatch):
    from surfinpaint.data import sphere
    from surfinpaint.fill import holes as holes_module
    from surfinpaint.geometry.cutting import cut_holes

    v, f = sphere(3)
    cut = cut_holes(v, f, [[0, 0, 1.0], [1.0, 0, 0], [0, 1.0, 0]], 0.35)
    found = holes_module.find_holes(cut.vertices, cut.faces)
    expected = [holes_module.select_holes(cut.vertices, cut.faces, h) for h in (None, [2, 0])]
    numbers = holes_module.hole_numbers(cut.vertices, cut.faces, expected[1])

    def refuse(*args, **kwargs):
        raise AssertionError("find_holes called again")

    monkeypatch.setattr(holes_module, "find_holes", refuse)
    for h, want in zip((None, [2, 0]), expected, strict=True):
        got = holes_module.select_holes(cut.vertices, cut.faces, h, found=found)
        assert len(got) == len(want) and all(np.array_equal(a, b)
                                             for a, b in zip(got, want, strict=True))
    assert holes_module.hole_numbers(cut.vertices, cut.faces, expected[1],
                                     found=found) == numbers == [2, 0]


def _borders_by_whole_sum(v, f):
    """The outer-border flags as one sum of every face's area per component (the rule)."""
    from surfinpaint.fill.holes import BORDER_SPAN_FRACTION, spanned_area
    from surfinpaint.geometry.edges import EdgeTable
    from surfinpaint.geometry.mesh import face_areas

    _, label = EdgeTable.build(f, len(v)).vertex_components
    area = np.bincount(label[f[:, 0]], weights=face_areas(v, f), minlength=label.max() + 1)
    flags, seen = [], set()
    for loop in sorted(boundary_loops(f), key=lambda l: (label[l[0]], -len(l))):
        c = int(label[loop[0]])
        flags.append(c not in seen
                     and bool(spanned_area(v[loop]) >= BORDER_SPAN_FRACTION * area[c]))
        seen.add(c)
    return flags


@pytest.mark.parametrize("block", [7, 50, 1 << 16])
def test_border_flags_from_partial_areas_match_the_whole_sum(monkeypatch, block):
    # find_holes stops summing a component's face areas once part of them exceeds what its
    # longest loop spans; in small blocks, the stop comes early (sphere), late or never
    # (disk: a border), and components of both kinds decided together
    import surfinpaint.geometry.mesh as mesh

    monkeypatch.setattr(mesh, "FACE_BLOCK", block)
    sv, sf = sphere_with_caps([(0, 0, 1), (1, 0, 0)])
    dv, df = disk(16)
    third = trimesh.creation.icosphere(3)
    tv, tf = np.asarray(third.vertices), np.asarray(third.faces)
    tf = tf[tv[tf].mean(axis=1)[:, 2] < 1 / 3]
    both_v = np.vstack([dv, sv + 5, tv - 5])
    both_f = np.vstack([df, sf + len(dv), tf + len(dv) + len(sv)])
    for v, f in ((sv, sf), (dv, df), (tv, tf), (both_v, both_f), (both_v, both_f[::-1])):
        holes = find_holes(v, f)
        assert [h.is_border for h in holes] == _borders_by_whole_sum(v, f)
    assert [h.is_border for h in find_holes(both_v, both_f)].count(True) == 1


def _sphere_cut_below(height, subdivisions=4):
    """A unit sphere with the faces whose centroid lies above ``height`` removed: one loop,
    a cap of (1 - height) / 2 of the sphere's area gone."""
    s = trimesh.creation.icosphere(subdivisions)
    v, f = np.asarray(s.vertices), np.asarray(s.faces)
    return v, f[v[f].mean(axis=1)[:, 2] < height]


# (what, height the sphere is cut at, is_border, may_be_border): the loop spans
# (1 - h²) / (2 (1 + h)) = (1 - h) / 2 of what remains, so the border rule (40 %) falls at
# h = 0.2 and the warning's (10 %) at h = 0.8
SPAN_CASES = [
    ("a small cap removed (5 %)", 0.9, False, False),
    ("a fifth removed: may be the margin", 0.6, False, True),
    ("a crown-like cup (35 %)", 0.3, False, True),
    ("a bowl, past the border rule (45 %)", 0.1, True, False),
    ("a hemisphere: the border", 0.0, True, False),
]


@pytest.mark.parametrize("what, height, border, may_be", SPAN_CASES,
                         ids=[c[0] for c in SPAN_CASES])
def test_span_fraction_tells_border_from_hole_and_flags_the_large_holes(what, height,
                                                                        border, may_be):
    v, f = _sphere_cut_below(height)
    (hole,) = find_holes(v, f)
    assert (hole.is_border, hole.may_be_border) == (border, may_be)
    if border or may_be:  # measured exactly: the spanned disk over the area left
        assert hole.span_fraction == pytest.approx((1 - height) / 2, abs=0.03)
    else:  # a part of the area sufficed
        assert np.isnan(hole.span_fraction)


def test_filling_a_hole_that_may_be_the_margin_warns_and_says_how_to_keep_it_open():
    from surfinpaint.io.base import MeshWarning

    v, f = _sphere_cut_below(0.3, subdivisions=3)
    with pytest.warns(MeshWarning, match=r"hole 0: .* spans 3\d% .* keep it open"):
        filled = fill_holes(v, f, method="fair")
    assert len(filled.new_faces) > 0  # filled all the same: the rule is unchanged
    small_v, small_f = _sphere_cut_below(0.9, subdivisions=3)
    for args, kwargs in (((v, f), {"holes": [0]}), ((small_v, small_f), {})):
        with warnings.catch_warnings():
            warnings.simplefilter("error", MeshWarning)  # a hole named, or a small one
            fill_holes(*args, method="fair", **kwargs)


def test_a_margin_hole_left_open_gets_no_warning_that_it_was_filled():
    # the warning says "so it was filled": a hole skipped (here by its size; a bow-tie
    # vertex on its loop skips one too) was not, and its skip is reported instead
    from surfinpaint.io.base import MeshWarning

    v, f = _sphere_cut_below(0.3, subdivisions=3)
    (hole,) = find_holes(v, f)
    assert hole.may_be_border
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(v, f, method="fair", max_hole_edges=hole.n_edges - 1)
    assert result.reports[0].outcome == "skipped"
    assert not [w for w in caught if issubclass(w.category, MeshWarning)
                and "outer border" in str(w.message)]


@pytest.mark.parametrize("fraction, text", [(0.3999, "39%"), (0.4, "40%"), (0.38, "38%"),
                                            (0.1, "10%"), (0.349, "34%")])
def test_a_span_below_the_border_rule_never_reads_as_the_rule_itself(fraction, text):
    # "spans 40% of its surface's area, below the 40%" read as a contradiction
    from surfinpaint.fill.holes import percent_below

    assert percent_below(fraction) == text


def _flat_ring(inner_radius, outer_points=96, inner_points=48):
    """A flat disk of radius 1 with a round opening of ``inner_radius``: its outer loop
    (``outer_points`` edges) longer than the inner one, as a scanned ring's or washer's."""
    from scipy.spatial import Delaunay

    t_out = np.linspace(0, 2 * np.pi, outer_points, endpoint=False)
    t_in = np.linspace(0, 2 * np.pi, inner_points, endpoint=False)
    grid = np.stack(np.meshgrid(np.linspace(-1, 1, 25), np.linspace(-1, 1, 25)), -1)
    grid = grid.reshape(-1, 2)
    r = np.linalg.norm(grid, axis=1)
    grid = grid[(r < 0.95) & (r > inner_radius + 0.04)]
    xy = np.vstack([np.c_[np.cos(t_out), np.sin(t_out)],
                    inner_radius * np.c_[np.cos(t_in), np.sin(t_in)], grid])
    tri = Delaunay(xy).simplices
    tri = tri[np.linalg.norm(xy[tri].mean(axis=1), axis=1) > inner_radius]
    return np.c_[xy, np.zeros(len(xy))], tri


# (what, the opening's radius, may_be_border): the opening spans r² / (1 - r²) of the ring
# (a disk of radius 1): the warning's 20 % falls at r ≈ 0.41
INNER_CASES = [
    ("a small hole inside a scan's border (1 %)", 0.1, False),
    ("a larger hole (7 %)", 0.25, False),
    ("a plate's hole a third of its width (14 %)", 0.35, False),
    ("a washer's opening (25 %)", 0.45, True),
    ("a thin ring's opening (56 %): never the border", 0.6, True),
]


@pytest.mark.parametrize("what, inner_radius, may_be", INNER_CASES,
                         ids=[c[0] for c in INNER_CASES])
def test_a_loop_inside_the_border_that_spans_a_large_part_may_be_an_inner_margin(
        what, inner_radius, may_be):
    v, f = _flat_ring(inner_radius)
    border, opening = find_holes(v, f)
    assert border.is_border and not border.inside_border
    assert opening.inside_border and not opening.is_border
    def polygon(n):  # a regular n-gon's area in the unit circle
        return n / 2 * np.sin(2 * np.pi / n)

    spanned = inner_radius ** 2 * polygon(48)
    assert opening.span_fraction == pytest.approx(spanned / (polygon(96) - spanned),
                                                  rel=1e-12)
    assert opening.may_be_border is may_be


def test_a_closed_surface_s_holes_are_never_inside_a_border():
    v, f = _sphere_cut_below(0.9)
    (hole,) = find_holes(v, f)
    assert not hole.inside_border and not hole.is_border


def test_an_inner_margin_filled_warns_as_such_and_keep_margins_leaves_it_open():
    from surfinpaint.app.hole_kinds import hole_kind
    from surfinpaint.io.base import MeshWarning

    v, f = _flat_ring(0.5)
    opening = find_holes(v, f)[1]
    assert hole_kind(opening) == \
        "hole (spans 33% of its surface, inside its border: an inner margin?)"
    with pytest.warns(MeshWarning, match=r"hole 1: .* spans 33% .* inside the surface's "
                      r"outer border.* inner edge of a scanned ring or bore.* keep it open"):
        filled = fill_holes(v, f, method="fair")
    assert len(filled.new_faces) > 0  # filled by default: only the warning is new
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshWarning)
        kept = fill_holes(v, f, method="fair", keep_margins=True)
    assert len(kept.new_faces) == 0 and kept.reports == []


def _polar_plate(inner_radii, outer_points, rings=6, bend=0.0, noise=0.0, seed=0):
    """A plate around an opening: rings of ``len(inner_radii)`` points from the opening's
    loop (radius ``inner_radii[i]`` at angle i) out to radius 0.95, then an outer loop of
    ``outer_points`` (a divisor of the rings' count) at radius 1: the opening's loop has
    more edges than the outer one. ``bend`` curves it (z = bend x²) and ``noise`` adds depth
    noise, as a range scan's."""
    m = len(inner_radii)
    step = m // outer_points
    assert step * outer_points == m
    theta = 2 * np.pi * np.arange(m) / m
    t = np.linspace(0, 1, rings)[:, None]
    radius = (1 - t) * np.asarray(inner_radii)[None, :] + t * 0.95
    xy = np.concatenate([(radius[..., None] * np.c_[np.cos(theta), np.sin(theta)]).reshape(
        -1, 2), np.c_[np.cos(theta[::step]), np.sin(theta[::step])]])
    at = np.arange(rings * m).reshape(rings, m)
    a, b = at[:-1], np.roll(at[:-1], -1, axis=1)
    c, d = np.roll(at[1:], -1, axis=1), at[1:]
    faces = [np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)]
    last, outer = at[-1], rings * m + np.arange(outer_points)
    for s in range(step):  # each outer point fans over `step` edges of the last ring
        faces.append(np.c_[last[s::step], last[(np.arange(s, m, step) + 1) % m], outer])
    faces.append(np.c_[last[::step], outer, np.roll(outer, 1)])  # between two fans
    faces = np.concatenate(faces)[:, [0, 2, 1]]  # wound as above they face down: face up
    z = bend * xy[:, 0] ** 2 + noise * np.random.default_rng(seed).standard_normal(len(xy))
    return np.c_[xy, z], faces


def _star(points, radius, depth):
    """An opening's radii: ``points`` alternately ``depth`` out and in (a jagged bore)."""
    return radius + depth * (-1.0) ** np.arange(points)


# (what, mesh, may_be_border): scanned rings whose opening's loop has as many or more edges
# than the outer border; the outer loop is the border and the opening lies inside it
# (main took the loop with the most edges for the border's candidate: then neither was)
MORE_EDGES_INSIDE = [
    ("a washer, 96 edges inside 48 (25 %)", lambda: _flat_ring(0.45, 48, 96), True),
    ("a washer, 48 edges inside 48 (25 %)", lambda: _flat_ring(0.45, 48, 48), True),
    ("a small hole, 48 edges inside 24 (1 %)", lambda: _flat_ring(0.1, 24, 48), False),
    ("a thin ring, 96 edges inside 48 (56 %)", lambda: _flat_ring(0.6, 48, 96), True),
    ("a curved noisy scan's opening, 96 inside 48 (24 %)",
     lambda: _polar_plate(np.full(96, 0.45), 48, bend=0.3, noise=0.005), True),
    ("a finer scan at a small opening, 192 inside 48 (9 %)",
     lambda: _polar_plate(np.full(192, 0.3), 48, bend=0.3, noise=0.005), False),
    ("a jagged bore, longer than the border (17 %)",
     lambda: _polar_plate(_star(96, 0.45, 0.2), 48, bend=0.3, noise=0.005), False),
]


@pytest.mark.parametrize("what, make, may_be", MORE_EDGES_INSIDE,
                         ids=[c[0] for c in MORE_EDGES_INSIDE])
def test_the_outer_border_is_the_loop_spanning_the_most_area_not_the_most_edges(
        what, make, may_be):
    v, f = make()
    holes = find_holes(v, f)
    assert len(holes) == 2
    reach = [np.linalg.norm(v[h.loop, :2], axis=1).max() for h in holes]
    outer, opening = (holes[0], holes[1]) if reach[0] > reach[1] else (holes[1], holes[0])
    assert opening.n_edges >= outer.n_edges  # the case: the edge count cannot tell them
    assert outer.is_border and not outer.inside_border and not outer.may_be_border
    assert opening.inside_border and not opening.is_border
    assert opening.may_be_border is may_be
    assert opening.span_fraction < outer.span_fraction
    assert [h.n_edges for h in holes] == sorted((h.n_edges for h in holes), reverse=True)
    assert [len(loop) for loop in select_holes(v, f)] == [opening.n_edges]
    if "jagged" in what:  # the border is not the longer loop either: the area decides
        assert opening.perimeter > outer.perimeter
