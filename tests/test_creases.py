"""Creases across holes (surfinpaint.fill.creases): found, continued, cut along, filled."""

import numpy as np
import pytest

from surfinpaint.data import cube, lens, sphere
from surfinpaint.errors import FillError
from surfinpaint.fill.creases import (
    corner_point,
    crease_curve,
    cut_along,
    hole_creases,
    paired_ends,
    sharp_edges,
    split_fill,
)
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import (
    boundary_loops,
    connected_components,
    mean_edge_length,
    unique_edges,
)


def _cube_hole(n=16, at=(0.5, 0.0, 0.0), radius_h=6):
    v, f = cube(n)
    centre = int(np.argmin(np.linalg.norm(v - at, axis=1)))
    return cut_geodesic_disk(v, f, centre, radius_h * mean_edge_length(v, f))


def _cube_distance(points):
    """Distance of points to the unit cube's surface (all inside or on it here)."""
    return np.minimum(points, 1 - points).min(axis=1)


def _min_angle(points, faces):
    p = points[faces]
    angles = []
    for k in range(3):
        a, b = p[:, (k + 1) % 3] - p[:, k], p[:, (k + 2) % 3] - p[:, k]
        cos = (a * b).sum(1) / np.linalg.norm(a, axis=1) / np.linalg.norm(b, axis=1)
        angles.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return float(np.min(angles))


def test_sharp_edges_of_a_cube_and_a_sphere():
    v, f = cube(4)
    edges, turn = sharp_edges(v, f)
    assert len(edges) == 12 * 4 and np.allclose(turn, 90.0)
    # every sharp edge lies on a cube edge: two coordinates at 0 or 1
    on = np.isclose(v[edges], 0) | np.isclose(v[edges], 1)
    assert (on.sum(axis=2) >= 2).all()
    assert len(sharp_edges(*sphere(3))[0]) == 0
    assert len(sharp_edges(v, f, angle=95.0)[0]) == 0


def test_crease_of_a_cube_edge_hole():
    cut = _cube_hole()
    crease, = hole_creases(cut.vertices, cut.faces, cut.loop)
    assert crease is not None
    ends = cut.vertices[cut.loop[crease.ends]]
    # both ends on the edge y = z = 0, one on each side of the hole, pointing at each other
    assert np.allclose(ends[:, 1:], 0)
    assert np.allclose(crease.directions, [[1, 0, 0], [-1, 0, 0]]) or np.allclose(
        crease.directions, [[-1, 0, 0], [1, 0, 0]])
    assert np.isclose(crease.angle, 90.0)
    for chain in crease.chains:
        assert len(chain) >= 3 and np.allclose(cut.vertices[chain][:, 1:], 0)
    # a higher threshold than the cube's 90° finds nothing
    assert hole_creases(cut.vertices, cut.faces, cut.loop, angle=100.0) == []


def test_no_crease_inside_a_face():
    cut = _cube_hole(at=(0.5, 0.5, 0.0), radius_h=4)
    assert hole_creases(cut.vertices, cut.faces, cut.loop) == []


@pytest.mark.parametrize("at", [(0.0, 0.0, 0.0), (1.0, 1.0, 1.0), (1.0, 0.0, 1.0)])
def test_a_corner_in_a_hole_is_found_and_rebuilt_exactly(at):
    # three chains that meet at the cube's corner: one Crease with the corner, whose fill
    # (each crease continued straight to it, each face filled on its own) is the cube
    cut = _cube_hole(n=24, at=at, radius_h=5)
    corner, = hole_creases(cut.vertices, cut.faces, cut.loop)
    assert np.allclose(corner.corner, at, atol=1e-12) and len(corner.ends) == 3
    assert np.isclose(corner.angle, 90.0) and list(corner.ends) == sorted(corner.ends)
    new_v, new_f, _ = split_fill(cut.vertices, cut.faces, cut.loop, [corner])
    assert _cube_distance(new_v).max() < 1e-12
    assert len(boundary_loops(np.vstack([cut.faces, new_f]))) == 0


def test_no_crease_on_a_smooth_surface():
    v, f = sphere(4)
    cut = cut_geodesic_disk(v, f, 0, 0.5)
    assert hole_creases(cut.vertices, cut.faces, cut.loop) == []


def test_crease_curve_continues_a_circle_at_fourth_order():
    # a Hermite curve with the circle's tangents at both ends: error O(arc⁴)
    errors = []
    for arc in (0.4, 0.2, 0.1):
        a, b = np.array([1.0, 0, 0]), np.array([np.cos(arc), np.sin(arc), 0])
        ta, tb = np.array([0.0, 1, 0]), -np.array([-np.sin(arc), np.cos(arc), 0])
        points = crease_curve(a, ta, b, tb, arc / 8)
        assert len(points) == 7
        errors.append(np.abs(np.linalg.norm(points, axis=1) - 1).max())
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert (orders > 3.8).all(), orders


def test_cut_along_splits_fans_and_keeps_faces():
    v, f = cube(3)
    edges, _ = sharp_edges(v, f)
    cut, parent = cut_along(f, edges)
    assert np.array_equal(parent[cut], f)
    # cut along all its edges, the cube falls apart into its six sides
    count, label = connected_components(cut, len(parent))
    assert len(np.unique(label[cut[:, 0]])) == 6
    assert len(boundary_loops(cut)) == 6
    # nothing to cut: the same mesh, the same ids
    same, identity = cut_along(f, np.empty((0, 2), int))
    assert np.array_equal(same, f) and np.array_equal(identity, np.arange(len(v)))


def test_split_fill_rebuilds_the_cube_edge_exactly():
    cut = _cube_hole()
    crease, = hole_creases(cut.vertices, cut.faces, cut.loop)
    new_v, new_f, cut_edges = split_fill(cut.vertices, cut.faces, cut.loop, [crease])
    assert _cube_distance(new_v).max() < 1e-12
    faces = np.vstack([cut.faces, new_f])
    assert (unique_edges(faces)[2] == 2).all()  # closed and manifold again
    # the crease's points lie on the edge, and every fill triangle on one side of it
    n = len(cut.vertices)
    curve = np.unique(cut_edges[(cut_edges >= n).any(axis=1)])
    assert np.allclose(new_v[curve[curve >= n] - n][:, 1:], 0)
    points = np.vstack([cut.vertices, new_v])
    normals = np.cross(points[new_f[:, 1]] - points[new_f[:, 0]],
                       points[new_f[:, 2]] - points[new_f[:, 0]])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    assert (np.abs(normals).max(axis=1) > 1 - 1e-12).all()  # axis-aligned: no corner cut
    # fairing with the crease as a cut border keeps the triangles' shape (no slivers)
    assert _min_angle(points, new_f) > 10.0


def test_split_fill_of_a_curved_crease_stays_on_the_lens():
    v, f = lens(0.05)
    centre = int(np.argmin(np.linalg.norm(v - [1.0, 0, 0], axis=1)))
    cut = cut_geodesic_disk(v, f, centre, 6 * mean_edge_length(v, f))
    crease, = hole_creases(cut.vertices, cut.faces, cut.loop)
    assert crease is not None
    new_v, new_f, cut_edges = split_fill(cut.vertices, cut.faces, cut.loop, [crease])
    n = len(cut.vertices)
    curve = np.unique(cut_edges[cut_edges >= n]) - n
    # the continued rim stays on the unit circle: measured 0.16 % of the hole's diameter off
    # (the faired fills stay 21-24 % of it inside the rim)
    rim = new_v[curve]
    assert np.abs(np.linalg.norm(rim[:, :2], axis=1) - 1).max() < 3e-3 * cut.diameter
    assert np.abs(rim[:, 2]).max() < 1e-9


def test_split_fill_failure_is_a_fill_error(monkeypatch):
    import surfinpaint.fill.creases as creases
    from surfinpaint.errors import MeshError

    cut = _cube_hole()
    crease, = hole_creases(cut.vertices, cut.faces, cut.loop)

    def broken(*args, **kwargs):
        raise MeshError("no triangulation")

    monkeypatch.setattr(creases, "minimum_weight_triangulation", broken)
    with pytest.raises(FillError, match="sides of the crease"):
        split_fill(cut.vertices, cut.faces, cut.loop, [crease])


def test_a_crease_along_the_loop_enters_the_hole_where_it_leaves_the_loop():
    # this hole's loop runs along the edge x = 0, z = 1 for one edge at each end: the crease
    # enters the hole at the last loop vertex on it, else its continuation would lie on a
    # loop edge and give flat, flipped triangles
    cut = _cube_hole(n=40, at=(0.0, 0.5, 1.0), radius_h=10)
    crease, = hole_creases(cut.vertices, cut.faces, cut.loop)
    loop = cut.loop
    on_edge = np.isclose(cut.vertices[:, 0], 0) & np.isclose(cut.vertices[:, 2], 1)
    for end in crease.ends:
        ahead = [loop[(end - 1) % len(loop)], loop[(end + 1) % len(loop)]]
        assert on_edge[loop[end]] and on_edge[ahead].sum() == 1
    new_v, new_f, _ = split_fill(cut.vertices, cut.faces, cut.loop, [crease])
    points = np.vstack([cut.vertices, new_v])
    normals = np.cross(points[new_f[:, 1]] - points[new_f[:, 0]],
                       points[new_f[:, 2]] - points[new_f[:, 0]])
    outward = np.where(np.abs(normals[:, 0]) > np.abs(normals[:, 2]), -normals[:, 0],
                       normals[:, 2])
    assert (outward > 0).all() and _cube_distance(new_v).max() < 1e-12


def test_one_sharp_edge_before_a_corner_is_enough():
    # a hole reaching to one edge from both corners: chains of one edge, each into a corner
    # (three sharp edges meet there), so they count as the default asks for two edges
    cut = _cube_hole(n=24, radius_h=10.5)
    for min_edges in (2, 1):
        crease, = hole_creases(cut.vertices, cut.faces, cut.loop, min_edges=min_edges)
        assert [len(c) for c in crease.chains] == [2, 2]
        assert np.allclose(np.abs(crease.directions[:, 0]), 1)


def test_a_loop_vertex_that_only_zigzags_near_the_crease_does_not_bend_it():
    # the loop vertex next to the crease's end, moved towards the edge within its face: the
    # loop edge to it turns 22° from the crease (under CREASE_TURN, over CREASE_ALONG_LOOP).
    # Taken as the crease running on along the loop, it would bend the crease's tangent
    # into the hole and the crease would be lost; it is not, and the edge is rebuilt exactly
    cut = _cube_hole()
    v, loop = cut.vertices.copy(), cut.loop
    crease, = hole_creases(v, cut.faces, loop)
    end = int(crease.ends[0])
    off = [j for j in ((end - 1) % len(loop), (end + 1) % len(loop))
           if not np.allclose(v[loop[j], 1:], 0)]
    moved = loop[off[0]]
    step = v[moved] - v[loop[end]]
    along = crease.directions[0] * (step @ crease.directions[0])
    v[moved] = v[loop[end]] + along + 0.4 * (step - along)
    turn = np.degrees(np.arccos((v[moved] - v[loop[end]]) @ crease.directions[0]
                                / np.linalg.norm(v[moved] - v[loop[end]])))
    assert 10.0 < turn < 35.0
    again, = hole_creases(v, cut.faces, loop)
    assert sorted(again.ends) == sorted(crease.ends)
    new_v, _, _ = split_fill(v, cut.faces, loop, [again])
    assert _cube_distance(new_v).max() < 1e-12

def test_an_edge_one_mesh_edge_short_of_a_corner_still_counts():
    # a hole on a cube's vertical edge whose loop crosses it one mesh edge below the top
    # corner: that chain has one sharp edge before the corner, where three edges meet. It
    # is an edge cut short by the corner, not noise: the crease is found and rebuilt
    v, f = cube(16)
    cut = cut_geodesic_disk(v, f, np.array([0.0, 0.0, 0.72]), 0.22)
    crease, = hole_creases(cut.vertices, cut.faces, cut.loop)
    assert sorted(len(c) for c in crease.chains) == [2, 4]  # one edge, and a full chain
    assert np.allclose(np.abs(crease.directions[:, 2]), 1.0)
    new_v, _, _ = split_fill(cut.vertices, cut.faces, cut.loop, [crease])
    assert _cube_distance(new_v).max() < 1e-12

def _slab_hole(radius=0.26):
    """A hole on the side y = 0 of a thin box (1 × 1 × 0.3) that crosses both its edges."""
    v, f = cube(40)
    v = v * [1.0, 1.0, 0.3]
    centre = int(np.argmin(np.linalg.norm(v - [0.5, 0.0, 0.15], axis=1)))
    return cut_geodesic_disk(v, f, centre, radius)


def _slab_distance(points):
    return np.minimum(points, [1.0, 1.0, 0.3] - points).min(axis=1)


def test_two_creases_across_a_thin_plate_side_are_rebuilt_exactly():
    cut = _slab_hole()
    creases = hole_creases(cut.vertices, cut.faces, cut.loop)
    assert len(creases) == 2 and np.allclose([c.angle for c in creases], 90.0)
    ends = cut.vertices[cut.loop[np.concatenate([c.ends for c in creases])]]
    # one crease on each edge of the side: z = 0 and z = 0.3, both on y = 0
    assert np.allclose(ends[:, 1], 0) and sorted(np.unique(ends[:, 2].round(9))) == [0, 0.3]
    for c in creases:  # each along one edge
        z = cut.vertices[cut.loop[c.ends], 2]
        assert np.isclose(z[0], z[1])
    new_v, new_f, cut_edges = split_fill(cut.vertices, cut.faces, cut.loop, creases)
    assert _slab_distance(new_v).max() < 1e-12
    # the fill closes the hole: every loop edge is now interior
    all_faces = np.vstack([cut.faces, new_f])
    assert len(boundary_loops(all_faces)) == 0


def test_the_conformal_fill_of_a_hole_across_two_creases():
    from surfinpaint.fill.conformal import conformal_fill

    cut = _slab_hole()
    fill = conformal_fill(cut.vertices, cut.faces, cut.loop)
    assert fill.kind == "conformal" and fill.crease.startswith("2 creases (90°, 90°)")
    assert _slab_distance(fill.vertices).max() < 1e-9


_X = np.array([1.0, 0.0, 0.0])


@pytest.mark.parametrize("at, points, directions, pairs", [
    # one crease: two ends pointing at each other
    ([0, 5], [[0, 0, 0], [1, 0, 0]], [_X, -_X], [(0, 1)]),
    # the ends given in the other order: pairs follow the loop
    ([5, 0], [[1, 0, 0], [0, 0, 0]], [-_X, _X], [(1, 0)]),
    # two parallel creases (a plate's side): each end also sees the other crease's far end
    # within CREASE_TURN; the best match pairs them
    ([0, 4, 10, 14], [[1, 0, 0], [0, 0, 0], [0, 0, 0.2], [1, 0, 0.2]],
     [-_X, _X, _X, -_X], [(0, 1), (2, 3)]),
    # three chains (a corner): nothing
    ([0, 4, 8], [[1, 0, 0], [0, 0, 0], [0.5, 1, 0]], [-_X, _X, [0, -1, 0]], []),
    # ends next to each other on the loop: nothing
    ([0, 1], [[0, 0, 0], [1, 0, 0]], [_X, -_X], []),
    # two ends that do not point at each other (36° off, CREASE_TURN is 35°): nothing
    ([0, 5], [[0, 0, 0], [1, 0, 0]],
     [[np.cos(0.63), np.sin(0.63), 0], -_X], []),
    # two creases whose continuations would cross (their ends interleave on the loop)
    ([0, 5, 10, 15], [[-1, 0, 0], [0, -1, 0], [1, 0, 0], [0, 1, 0]],
     [_X, [0, 1, 0], -_X, [0, -1, 0]], []),
    # a fourth end that points at nothing: nothing
    ([0, 4, 10, 14], [[1, 0, 0], [0, 0, 0], [0, 0, 0.5], [1, 0, 0.5]],
     [-_X, _X, _X, [0, 0, 1]], []),
])
def test_paired_ends_rule(at, points, directions, pairs):
    directions = np.array(directions, dtype=float)
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    assert paired_ends(np.array(at), 20, np.array(points, float), directions) == pairs


@pytest.mark.parametrize("points, directions, corner", [
    # a cube's corner: three edges meeting at the origin
    (np.eye(3), -np.eye(3), [0.0, 0.0, 0.0]),
    # four creases of a pyramid's apex (0, 0, 1)
    ([[1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]],
     [[-1, 0, 1], [0, -1, 1], [1, 0, 1], [0, 1, 1]], [0.0, 0.0, 1.0]),
    # the third line one loop edge off the first two's crossing: no corner
    ([[1, 0, 0], [0, 1, 0], [0.1, 0, 1]], -np.eye(3), None),
    # a quarter of that (0.4 × 0.25 loop edges from the best point): still a corner
    ([[1, 0, 0], [0, 1, 0], [0.025, 0, 1]], -np.eye(3), "near"),
    # the lines meet behind one end (a crease leaving the hole): no corner
    ([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [[-1, 0, 0], [0, -1, 0], [0, 0, 1]], None),
    # they meet far beyond the hole (farther ahead than the ends are apart): no corner
    ([[-0.1, 0, 0], [0.1, 0, 0], [0, 0.1, 0]],
     [[0.02, 1, 0], [-0.02, 1, 0], [0, 1, 0]], None),
])
def test_corner_point_rule(points, directions, corner):
    directions = np.array(directions, dtype=float)
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    found = corner_point(np.array(points, float), directions, 0.1)
    if corner is None:
        assert found is None
    elif corner == "near":
        assert found is not None and np.linalg.norm(found) < 0.025
    else:
        assert np.allclose(found, corner, atol=1e-12)


def test_the_hole_s_creases_are_searched_once(monkeypatch):
    """The creases across the hole are found once, for the candidates (``crossed``) and for
    the hole's own λ-H fill along them (session 44 helper): the same creases, the same fill."""
    from surfinpaint import ConformalOptions
    from surfinpaint.fill.conformal import candidates, conformal_fill

    cut = _cube_hole()
    searched = []
    real = candidates.hole_creases

    def counting(vertices, faces, loop, **kw):
        searched.append(np.asarray(loop).tobytes())
        return real(vertices, faces, loop, **kw)

    monkeypatch.setattr(candidates, "hole_creases", counting)
    fill = conformal_fill(cut.vertices, cut.faces, cut.loop, ConformalOptions(select=False))
    assert fill.kind == "conformal" and fill.crease is not None
    assert searched.count(np.asarray(cut.loop).tobytes()) == 1
