"""Creases across holes (surfinpaint.fill.creases): found, continued, cut along, filled."""

import numpy as np
import pytest

from surfinpaint import fill_holes
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
from surfinpaint.geometry.validation import validate_mesh


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
    from surfinpaint.fill.conformal import ConformalOptions, conformal_fill

    cut = _slab_hole()
    # the λ-H fill's crease fill (the default writes the ear-cut fill here: session 51)
    fill = conformal_fill(cut.vertices, cut.faces, cut.loop,
                          ConformalOptions(ear_cut_flat=None))
    assert fill.kind == "conformal" and fill.crease.startswith("2 creases (90°, 90°)")
    assert _slab_distance(fill.vertices).max() < 1e-9
    default = conformal_fill(cut.vertices, cut.faces, cut.loop)
    assert default.ear_cut == "flat planes" and _slab_distance(default.vertices).max() < 1e-9


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


# a piece of PyVista's nut around a slot cut across a crease (session 46's fuzz campaign,
# seed 340872011, reduced to the faces it needs): the hole's loop runs along two sides of
# face 489 of the nut, and the crease split filled its third side, the same face again
_NUT_VERTICES = np.array([
    (93.729, -96.373, -88.502), (65.084, -68.966, -97.638), (64.025, -72.256, -96.579),
    (58.342, -91.159, -87.122), (58.342, -94.849, -86.128), (58.342, -89.672, -90.896),
    (58.342, -94.849, -90.896), (60.715, -91.356, -93.269), (61.34, -87.013, -93.893),
    (58.342, -84.496, -90.896), (90.541, -96.373, -92.301), (95.356, -96.373, -92.344),
    (91.999, -91.555, -90.888), (93.504, -82.28, -101.772), (96.583, -84.67, -98.693),
    (93.416, -77.51, -101.859), (95.713, -80.244, -99.562), (61.713, -68.966, -94.267),
    (63.014, -67.442, -93.412), (66.162, -67.442, -96.56), (73.792, -96.373, -98.15), (96.572,
    -72.367, -98.704), (94.267, -68.966, -101.009), (63.667, -76.149, -96.22), (60.962,
    -77.468, -93.516), (61.099, -72.936, -93.653), (63.436, -80.115, -95.99), (65.005,
    -84.594, -97.559), (75.023, -87.594, -94.157), (73.619, -92.045, -93.367), (77.62, -92.18,
    -95.141), (71.472, -87.553, -91.663), (76.477, -96.373, -94.781), (81.361, -96.373,
    -95.649), (90.265, -67.442, -102.856), (90.896, -68.966, -104.38), (85.813, -67.442,
    -102.856), (86.128, -68.966, -104.38), (64.251, -96.373, -88.329), (59.866, -96.373,
    -90.265), (63.095, -96.373, -83.896), (59.866, -96.373, -85.813), (67.297, -96.373,
    -83.841), (67.37, -96.373, -92.378), (68.993, -96.373, -88.502), (98.642, -79.971,
    -96.634), (96.182, -76.374, -99.094), (99.537, -84.174, -95.739), (99.088, -88.071,
    -96.188), (96.179, -90.301, -99.097), (81.361, -68.966, -104.38), (101.725, -91.01,
    -93.551), (99.082, -91.806, -96.194), (86.245, -96.373, -94.781), (88.931, -96.373,
    -98.149), (78.881, -67.442, -98.876), (73.792, -67.442, -98.149), (61.267, -82.273,
    -93.82), (69.31, -67.442, -99.708), (69.893, -67.442, -95.787), (85.094, -92.561,
    -95.151), (92.829, -96.373, -95.787), (96.56, -96.373, -96.56), (67.875, -92.349,
    -86.054), (72.181, -96.373, -92.301), (70.188, -92.173, -90.253), (99.708, -96.373,
    -93.412), (88.666, -93.046, -93.637), (76.909, -67.442, -102.856), (97.638, -94.849,
    -97.638), (93.639, -72.994, -101.637), (101.009, -94.849, -94.267), (81.361, -67.442,
    -102.856)])
_NUT_FACES = np.array([
    (3, 6, 4), (3, 5, 6), (5, 7, 6), (5, 8, 7), (5, 9, 8), (0, 10, 11), (0, 12, 10), (13, 15,
    16), (13, 16, 14), (18, 19, 1), (18, 1, 17), (23, 25, 2), (23, 26, 24), (28, 31, 29), (30,
    29, 32), (30, 32, 33), (34, 22, 35), (34, 35, 37), (38, 40, 41), (38, 43, 44), (38, 44,
    42), (38, 41, 39), (45, 16, 46), (45, 47, 14), (45, 14, 16), (47, 48, 14), (14, 48, 49),
    (48, 52, 49), (48, 51, 52), (39, 41, 4), (33, 53, 60), (61, 62, 11), (61, 10, 54), (42,
    44, 63), (44, 64, 65), (44, 43, 64), (32, 64, 20), (10, 12, 67), (10, 67, 53), (10, 53,
    54), (26, 27, 57), (64, 29, 65), (65, 29, 31), (35, 22, 70), (21, 70, 22), (21, 46, 70),
    (71, 52, 51), (71, 69, 52), (71, 66, 69), (69, 66, 62), (55, 68, 56), (55, 72, 68), (19,
    59, 58), (19, 58, 1), (58, 59, 56), (17, 2, 25), (8, 9, 57), (68, 72, 50), (72, 36, 50),
    (36, 37, 50)])


def test_a_crease_region_does_not_make_a_face_of_the_mesh_again():
    result = fill_holes(_NUT_VERTICES, _NUT_FACES, method="conformal")
    assert any("crease" in (r.note or "") for r in result.reports)
    known = {tuple(t) for t in np.sort(_NUT_FACES, axis=1).tolist()}
    made = {tuple(t) for t in np.sort(result.new_faces, axis=1).tolist()}
    assert not known & made
    validate_mesh(result.vertices, result.faces)  # no duplicate face, edge-manifold
