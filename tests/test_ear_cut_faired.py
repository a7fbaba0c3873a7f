"""The ear-cut fill faired off its planes (ConformalOptions.ear_cut_faired,
surfinpaint.fill.conformal.ear_cut.faired_off_planes): where the ear cut's share of area in
the known faces' planes is below ear_cut_flat but at least ear_cut_faired and a crease
crosses the hole, the refined ear cut is written with its vertices off the planes faired
(docs/candidates.md, "Session 52 (helper): CAD holes PyMeshFix still wins after the ear-cut
default")."""

import numpy as np
import pytest

from surfinpaint.data import cube, sphere, torus
from surfinpaint.fill.conformal import conformal_fill
from surfinpaint.fill.conformal.ear_cut import (
    BY_FAIRED_PLANES,
    BY_FLAT_PLANES,
    PIECE_ANGLE,
    ear_cut_flat,
    faired_off_planes,
    plane_pieces,
    refined_in_planes,
)
from surfinpaint.fill.conformal.options import ConformalOptions
from surfinpaint.fill.liepa.ear_cutting import ear_cut_triangulation
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import mean_edge_length

FAIRED = 0.4  # the tests' lower bound (the cube corner's ear cut is 0.49 in planes)


def _hole(mesh, at, radius=6):
    v, f = mesh
    centre = int(np.argmin(np.linalg.norm(v - np.asarray(at), axis=1)))
    return cut_geodesic_disk(v, f, centre, radius * mean_edge_length(v, f))


def _noisy(mesh, fraction, seed=0):
    """A scan-like copy: every vertex moved by Gaussian noise of ``fraction`` of the mean
    edge length."""
    v, f = mesh
    rng = np.random.default_rng(seed)
    return v + rng.normal(0.0, fraction * mean_edge_length(v, f), v.shape), f


def _inside_the_unit_cube(p):
    """Each point's depth below the unit cube's surface (0 on it)."""
    q = np.clip(p, 0.0, 1.0)
    return np.minimum(q, 1.0 - q).min(axis=1)


# case: (mesh, hole centre, what ear_cut_flat(0.9, FAIRED) writes: the label or None)
CASES = {
    # a cube's corner taken with the hole: the ear cut chamfers it, 0.49 of it in the
    # three faces' planes: the faired rule's
    "cube corner": (lambda: cube(16), (0.0, 0.0, 0.0), BY_FAIRED_PLANES),
    # a cube's edge: all of it in the two faces' planes: the flat rule's, not faired
    "cube edge": (lambda: cube(16), (0.5, 0.0, 0.0), BY_FLAT_PLANES),
    # inside one face: no crease, the plane test's hole
    "cube face": (lambda: cube(16), (0.5, 0.5, 0.0), None),
    # curved: no patch triangle within the angle of a known face
    "sphere": (lambda: sphere(4), (0.0, 0.0, 1.0), None),
    "torus": (lambda: torus(), (1.4, 0.0, 0.0), None),
    # scan-like noise of 5 % of an edge: the faces turn by more than the angle everywhere
    # (0.10 of the edge's ear cut in planes, 0.04 of the corner's, 0.02 of the sphere's)
    "noisy cube edge": (lambda: _noisy(cube(16), 0.05), (0.5, 0.0, 0.0), None),
    "noisy cube corner": (lambda: _noisy(cube(16), 0.05), (0.0, 0.0, 0.0), None),
    "noisy sphere": (lambda: _noisy(sphere(4), 0.05), (0.0, 0.0, 1.0), None),
}


@pytest.mark.parametrize("name", CASES)
def test_what_the_rules_write_on_pinned_holes(name):
    mesh, at, label = CASES[name]
    cut = _hole(mesh(), at)
    made = ear_cut_flat(cut.vertices, cut.faces, cut.loop, 0.9, FAIRED)
    assert (None if made is None else made.ear_cut) == label
    # without the faired rule only the flat one writes; the flat rule's fill is the same
    alone = ear_cut_flat(cut.vertices, cut.faces, cut.loop, 0.9)
    assert (None if alone is None else alone.ear_cut) == (
        None if label == BY_FAIRED_PLANES else label)
    if label == BY_FLAT_PLANES:
        np.testing.assert_array_equal(made.vertices, alone.vertices)
    # with the flat rule off the faired one takes every share from its bound up
    only = ear_cut_flat(cut.vertices, cut.faces, cut.loop, None, FAIRED)
    assert (None if only is None else only.ear_cut) == (
        None if label is None else BY_FAIRED_PLANES)


def test_the_planes_stay_and_the_rest_is_faired():
    # the cube corner: the vertices of the plane pieces are where the refinement put them,
    # on the cube's faces (exactly); the others moved off the chamfer toward the corner
    cut = _hole(cube(16), (0.0, 0.0, 0.0))
    ears = ear_cut_triangulation(cut.vertices, cut.faces, cut.loop)
    new, patch = refined_in_planes(cut.vertices, cut.faces, cut.loop, ears)
    placed = faired_off_planes(cut.vertices, cut.faces, new, patch)
    everything = np.vstack([cut.vertices, new])
    pieces = plane_pieces(everything, cut.faces, patch, np.radians(PIECE_ANGLE))
    n = len(cut.vertices)
    on_plane = np.zeros(len(everything), bool)
    on_plane[patch[pieces.plane >= 0].ravel()] = True
    kept, free = on_plane[n:], ~on_plane[n:]
    assert kept.sum() > 0 and free.sum() > 0
    np.testing.assert_array_equal(placed[kept], new[kept])
    assert _inside_the_unit_cube(placed[kept]).max() == 0.0
    assert (np.linalg.norm(placed[free] - new[free], axis=1) > 1e-3).all()
    # closer to the corner than the flat chamfer (its deepest point 0.125 inside the cube,
    # the faired patch's 0.096), never outside the cube
    assert _inside_the_unit_cube(placed[free]).max() < 0.8 * _inside_the_unit_cube(
        new[free]).max()
    outside = np.linalg.norm(placed - np.clip(placed, 0.0, 1.0), axis=1)
    assert outside.max() <= 1e-12
    # the fill written is this one
    made = ear_cut_flat(cut.vertices, cut.faces, cut.loop, 0.9, FAIRED)
    np.testing.assert_array_equal(made.vertices, placed)
    np.testing.assert_array_equal(made.faces, patch)


def test_a_patch_all_in_planes_is_not_moved():
    cut = _hole(cube(16), (0.5, 0.0, 0.0))
    ears = ear_cut_triangulation(cut.vertices, cut.faces, cut.loop)
    new, patch = refined_in_planes(cut.vertices, cut.faces, cut.loop, ears)
    np.testing.assert_array_equal(faired_off_planes(cut.vertices, cut.faces, new, patch), new)


@pytest.mark.parametrize("kw", [
    {"ear_cut_faired": 0}, {"ear_cut_faired": -0.5}, {"ear_cut_faired": 1.5},
    {"ear_cut_faired": True}, {"ear_cut_faired": np.nan}, {"ear_cut_faired": "0.5"},
    {"ear_cut_faired": 0.9},  # not below the default ear_cut_flat
    {"ear_cut_faired": 0.6, "ear_cut_flat": 0.5},
    {"ear_cut_faired": 1.5, "ear_cut_flat": None}])
def test_ear_cut_faired_is_checked(kw):
    with pytest.raises(ValueError, match="ear_cut_faired"):
        ConformalOptions(**kw)


def test_ear_cut_faired_off_by_default_and_written_by_the_method():
    assert ConformalOptions().ear_cut_faired is None
    ConformalOptions(ear_cut_faired=1.0, ear_cut_flat=None)  # allowed: every share ≥ 1
    corner = _hole(cube(16), (0.0, 0.0, 0.0))
    default = conformal_fill(corner.vertices, corner.faces, corner.loop)
    assert default.ear_cut is None
    made = conformal_fill(corner.vertices, corner.faces, corner.loop,
                          ConformalOptions(ear_cut_faired=FAIRED))
    assert made.ear_cut == BY_FAIRED_PLANES
    assert made.selection.endswith("refined within its planes, its vertices off them faired")
    ruled = ear_cut_flat(corner.vertices, corner.faces, corner.loop, 0.9, FAIRED)
    np.testing.assert_array_equal(made.vertices, ruled.vertices)


def test_the_report_names_the_faired_ear_cut_fill():
    from surfinpaint import fill_holes
    from surfinpaint.app.fill_report import written

    corner = _hole(cube(16), (0.0, 0.0, 0.0))
    report = fill_holes(corner.vertices, corner.faces,
                        options=ConformalOptions(ear_cut_faired=FAIRED)).reports[0]
    assert report.ear_cut == BY_FAIRED_PLANES
    assert written(report) == "ear-cut fill (planes, faired between)"
