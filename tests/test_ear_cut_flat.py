"""The flatness rule on the ear-cut patch (surfinpaint.fill.conformal.ear_cut.plane_pieces,
ear_cut_flat; ConformalOptions.ear_cut_flat): the ear-cut triangulation is written where
(nearly) all of it continues the known faces' planes and two of them meet inside the hole."""

import numpy as np
import pytest

from surfinpaint.data import cube, sphere, torus
from surfinpaint.fill.conformal import conformal_fill
from surfinpaint.fill.conformal.ear_cut import PIECE_ANGLE, ear_cut_flat, plane_pieces
from surfinpaint.fill.conformal.options import ConformalOptions
from surfinpaint.fill.liepa.ear_cutting import ear_cut_triangulation
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import face_normals, mean_edge_length


def _hole(mesh, at, radius=6):
    v, f = mesh
    centre = int(np.argmin(np.linalg.norm(v - np.asarray(at), axis=1)))
    return cut_geodesic_disk(v, f, centre, radius * mean_edge_length(v, f))


# case: (mesh, hole centre, the patch's plane-continuing area at least / below, crease °
# inside it, the rule fires at 0.9)
CASES = {
    # a cube's edge: both faces grow into the hole and meet at the edge, all of it flat
    "cube edge": (lambda: cube(16), (0.5, 0.0, 0.0), (1.0, None), 90.0, True),
    # a cube's corner: three faces, but no vertex at the corner: the ear cut chamfers it
    "cube corner": (lambda: cube(16), (0.0, 0.0, 0.0), (None, 0.9), 90.0, False),
    # inside one face: all flat, no crease (the plane test's hole, not this rule's)
    "cube face": (lambda: cube(16), (0.5, 0.5, 0.0), (1.0, None), 0.0, False),
    # curved: no patch triangle within the angle of a known face
    "sphere": (lambda: sphere(4), (0.0, 0.0, 1.0), (None, 0.1), None, False),
    "torus": (lambda: torus(), (1.4, 0.0, 0.0), (None, 0.1), None, False),
}


@pytest.mark.parametrize("name", CASES)
def test_plane_pieces_and_the_rule_on_pinned_holes(name):
    mesh, at, (least, below), crease, fires = CASES[name]
    cut = _hole(mesh(), at)
    ears = ear_cut_triangulation(cut.vertices, cut.faces, cut.loop)
    pieces = plane_pieces(cut.vertices, cut.faces, ears, np.radians(PIECE_ANGLE))
    share = pieces.flat_fraction()
    if least is not None:
        assert share >= least - 1e-12
    if below is not None:
        assert share < below
    if crease is not None:
        assert np.degrees(pieces.crease()) == pytest.approx(crease, abs=1e-6)
    made = ear_cut_flat(cut.vertices, cut.faces, cut.loop, 0.9)
    assert (made is not None) == fires


def _bending_strip(step_degrees, quads=6):
    """A strip of unit squares, each turned ``step_degrees`` further about its edge with
    the one before: its first square (two triangles) the known faces, the rest the patch."""
    turn = np.radians(step_degrees) * np.arange(quads)
    rail = np.vstack([[0.0, 0.0], np.cumsum(np.column_stack([np.cos(turn), np.sin(turn)]),
                                             axis=0)])
    a = np.column_stack([rail[:, 0], np.zeros(len(rail)), rail[:, 1]])
    v = np.vstack([a, a + [0.0, 1.0, 0.0]])
    j, n = np.arange(quads), len(rail)
    tri = np.stack([np.column_stack([j, j + 1, n + j + 1]),
                    np.column_stack([j, n + j + 1, n + j])], axis=1).reshape(-1, 3)
    return v, tri[:2], tri[2:]


def test_a_plane_continues_only_within_the_angle_of_its_known_face():
    # each square turned 1.5 degrees from the one before (under the 2-degree angle): the
    # plane reaches the first patch square only (3 degrees from the known face at the
    # second), though no two neighbours differ by the angle
    v, known, patch = _bending_strip(1.5)
    pieces = plane_pieces(v, known, patch, np.radians(PIECE_ANGLE))
    assert (pieces.plane[:2] >= 0).all() and (pieces.plane[2:] == -1).all()
    assert pieces.flat_fraction() == pytest.approx(0.2)
    # a flat strip continues its known face throughout; the normals are the known face's
    flat_v, known, patch = _bending_strip(0.0)
    pieces = plane_pieces(flat_v, known, patch, np.radians(PIECE_ANGLE))
    assert (pieces.plane >= 0).all() and pieces.crease() == 0.0
    np.testing.assert_allclose(pieces.normal, face_normals(flat_v, known[pieces.plane]))


@pytest.mark.parametrize("bad", [0, -0.5, 1.5, True, np.nan, "0.9"])
def test_ear_cut_flat_is_checked(bad):
    with pytest.raises(ValueError, match="ear_cut_flat"):
        ConformalOptions(ear_cut_flat=bad)


def test_ear_cut_written_where_the_rule_fires_and_nowhere_else():
    assert ConformalOptions().ear_cut_flat is None  # off by default
    edge = _hole(cube(16), (0.5, 0.0, 0.0))
    default = conformal_fill(edge.vertices, edge.faces, edge.loop)
    assert not default.selection.startswith("ear cutting")
    ruled = conformal_fill(edge.vertices, edge.faces, edge.loop,
                           ConformalOptions(ear_cut_flat=0.9))
    assert ruled.selection.startswith("ear cutting") and len(ruled.vertices) == 0
    np.testing.assert_array_equal(
        ruled.faces, ear_cut_triangulation(edge.vertices, edge.faces, edge.loop))
    corner = _hole(cube(16), (0.0, 0.0, 0.0))
    default = conformal_fill(corner.vertices, corner.faces, corner.loop)
    ruled = conformal_fill(corner.vertices, corner.faces, corner.loop,
                           ConformalOptions(ear_cut_flat=0.9))
    assert ruled.selection == default.selection
    np.testing.assert_array_equal(ruled.vertices, default.vertices)
