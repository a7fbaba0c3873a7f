"""Creases across holes (surfinpaint.fill.creases): found, continued, cut along, filled."""

import numpy as np
import pytest

from surfinpaint.data import cube, lens, sphere
from surfinpaint.errors import FillError
from surfinpaint.fill.creases import crease_curve, cut_along, hole_crease, sharp_edges, split_fill
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
    crease = hole_crease(cut.vertices, cut.faces, cut.loop)
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
    assert hole_crease(cut.vertices, cut.faces, cut.loop, angle=100.0) is None


@pytest.mark.parametrize("at", [(0.0, 0.0, 0.0), (0.5, 0.5, 0.0)])
def test_no_crease_at_a_corner_or_inside_a_face(at):
    # a corner hole has three chains (not one crease); a face hole none
    cut = _cube_hole(at=at, radius_h=4)
    assert hole_crease(cut.vertices, cut.faces, cut.loop) is None


def test_no_crease_on_a_smooth_surface():
    v, f = sphere(4)
    cut = cut_geodesic_disk(v, f, 0, 0.5)
    assert hole_crease(cut.vertices, cut.faces, cut.loop) is None


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
    crease = hole_crease(cut.vertices, cut.faces, cut.loop)
    new_v, new_f, cut_edges = split_fill(cut.vertices, cut.faces, cut.loop, crease)
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
    crease = hole_crease(cut.vertices, cut.faces, cut.loop)
    assert crease is not None
    new_v, new_f, cut_edges = split_fill(cut.vertices, cut.faces, cut.loop, crease)
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
    crease = hole_crease(cut.vertices, cut.faces, cut.loop)

    def broken(*args, **kwargs):
        raise MeshError("no triangulation")

    monkeypatch.setattr(creases, "minimum_weight_triangulation", broken)
    with pytest.raises(FillError, match="two sides of the crease"):
        split_fill(cut.vertices, cut.faces, cut.loop, crease)


def test_a_crease_along_the_loop_enters_the_hole_where_it_leaves_the_loop():
    # this hole's loop runs along the edge x = 0, z = 1 for one edge at each end: the crease
    # enters the hole at the last loop vertex on it, else its continuation would lie on a
    # loop edge and give flat, flipped triangles
    cut = _cube_hole(n=40, at=(0.0, 0.5, 1.0), radius_h=10)
    crease = hole_crease(cut.vertices, cut.faces, cut.loop)
    loop = cut.loop
    on_edge = np.isclose(cut.vertices[:, 0], 0) & np.isclose(cut.vertices[:, 2], 1)
    for end in crease.ends:
        ahead = [loop[(end - 1) % len(loop)], loop[(end + 1) % len(loop)]]
        assert on_edge[loop[end]] and on_edge[ahead].sum() == 1
    new_v, new_f, _ = split_fill(cut.vertices, cut.faces, cut.loop, crease)
    points = np.vstack([cut.vertices, new_v])
    normals = np.cross(points[new_f[:, 1]] - points[new_f[:, 0]],
                       points[new_f[:, 2]] - points[new_f[:, 0]])
    outward = np.where(np.abs(normals[:, 0]) > np.abs(normals[:, 2]), -normals[:, 0],
                       normals[:, 2])
    assert (outward > 0).all() and _cube_distance(new_v).max() < 1e-12


def test_one_sharp_edge_before_a_corner_is_enough_when_asked():
    # a hole reaching to one edge from both corners: chains of one edge
    cut = _cube_hole(n=24, radius_h=10.5)
    assert hole_crease(cut.vertices, cut.faces, cut.loop) is None
    crease = hole_crease(cut.vertices, cut.faces, cut.loop, min_edges=1)
    assert crease is not None and [len(c) for c in crease.chains] == [2, 2]
    assert np.allclose(np.abs(crease.directions[:, 0]), 1)
