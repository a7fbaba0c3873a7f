"""The flatness rule on the ear-cut patch (surfinpaint.fill.conformal.ear_cut.plane_pieces,
ear_cut_flat; ConformalOptions.ear_cut_flat): the ear-cut triangulation is written where
(nearly) all of it continues the known faces' planes and two of them meet inside the hole,
refined within its planes (refined_in_planes)."""

import numpy as np
import pytest

from surfinpaint.data import cube, sphere, torus
from surfinpaint.fill.conformal import conformal_fill
from surfinpaint.fill.conformal.ear_cut import (
    BY_FLAT_PLANES,
    PIECE_ANGLE,
    ear_cut_flat,
    plane_pieces,
    refined_in_planes,
)
from surfinpaint.fill.conformal.options import EAR_CUT_FLAT, ConformalOptions
from surfinpaint.fill.creases import sharp_edges
from surfinpaint.fill.liepa.ear_cutting import ear_cut_triangulation
from surfinpaint.fill.liepa.refinement import boundary_scales
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import face_normals, mean_edge_length, unique_edges


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
    assert ConformalOptions().ear_cut_flat == EAR_CUT_FLAT == 0.9  # the default (session 51)
    off = ConformalOptions(ear_cut_flat=None)
    edge = _hole(cube(16), (0.5, 0.0, 0.0))
    unruled = conformal_fill(edge.vertices, edge.faces, edge.loop, off)
    assert not unruled.selection.startswith("ear cutting") and unruled.ear_cut is None
    ruled = conformal_fill(edge.vertices, edge.faces, edge.loop)
    assert ruled.selection.startswith("ear cutting") and ruled.ear_cut == BY_FLAT_PLANES
    made = refined_in_planes(edge.vertices, edge.faces, edge.loop,
                             ear_cut_triangulation(edge.vertices, edge.faces, edge.loop))
    np.testing.assert_array_equal(ruled.vertices, made[0])
    np.testing.assert_array_equal(ruled.faces, made[1])
    corner = _hole(cube(16), (0.0, 0.0, 0.0))
    unruled = conformal_fill(corner.vertices, corner.faces, corner.loop, off)
    ruled = conformal_fill(corner.vertices, corner.faces, corner.loop)
    assert ruled.selection == unruled.selection and ruled.ear_cut is None
    np.testing.assert_array_equal(ruled.vertices, unruled.vertices)


def _off_the_unit_cube(p):
    """Each point's distance to the surface of the unit cube (``cube()``'s)."""
    outside = np.linalg.norm(p - np.clip(p, 0.0, 1.0), axis=1)
    return np.where(outside > 0, outside, np.minimum(p, 1.0 - p).min(axis=1))


# hole: (centre, radius in edges, crease count of the ear cut). The corner's hole reaches
# three faces and keeps the corner vertex on its loop (the ear cut rebuilds it; CASES'
# corner, whose hole takes the corner vertex, is chamfered and the rule does not fire)
REFINED = {"cube edge": ((0.5, 0.0, 0.0), 6, 1), "cube corner": ((0.1875, 0.1875, 0.0), 4, 2)}


@pytest.mark.parametrize("name", REFINED)
def test_the_written_patch_is_the_ear_cut_refined_within_its_planes(name):
    at, radius, n_creases = REFINED[name]
    cut = _hole(cube(16), at, radius)
    fill = ear_cut_flat(cut.vertices, cut.faces, cut.loop, 0.9)
    v = np.vstack([cut.vertices, fill.vertices])
    # exact: every new vertex on the cube, every triangle within one of its faces' planes
    assert _off_the_unit_cube(fill.vertices).max() <= 1e-12 * cut.diameter
    corners = v[fill.faces]
    on_a_face = ((np.abs(corners) <= 1e-12) | (np.abs(corners - 1.0) <= 1e-12)).all(axis=1)
    assert on_a_face.any(axis=1).all()
    # the density of the surroundings: as many new vertices as the hole took, within a
    # factor 1.5, every edge within [σ/4, 2σ] and their mean within 0.8-1.25 σ (σ: the
    # mean edge length at the loop)
    removed = len(np.unique(cube(16)[1])) - len(np.unique(cut.faces))
    assert removed / 1.5 <= len(fill.vertices) <= 1.5 * removed
    edges, _, _ = unique_edges(fill.faces)
    length = np.linalg.norm(v[edges[:, 0]] - v[edges[:, 1]], axis=1)
    sigma = boundary_scales(cut.vertices, cut.faces, cut.loop).mean()
    assert sigma / 4 <= length.min() and length.max() <= 2 * sigma
    assert 0.8 * sigma <= length.mean() <= 1.25 * sigma
    # the creases kept: the refined patch's sharp edges are pieces of the ear cut's
    # crease edges, and cover them
    ears = ear_cut_triangulation(cut.vertices, cut.faces, cut.loop)
    creases, _ = sharp_edges(cut.vertices, ears, PIECE_ANGLE)
    pieces, _ = sharp_edges(v, fill.faces, PIECE_ANGLE)
    assert len(creases) == n_creases and len(pieces) > n_creases
    a, b = cut.vertices[creases[:, 0]], cut.vertices[creases[:, 1]]
    ends = np.stack([v[pieces[:, 0]], v[pieces[:, 1]]])  # (2, pieces, 3)
    t = np.einsum("kpcj,cj->kpc", ends[:, :, None] - a, b - a) / ((b - a) ** 2).sum(axis=1)
    off = np.linalg.norm(ends[:, :, None] - (a + t[..., None] * (b - a)), axis=3)
    on = (off <= 1e-12 * cut.diameter) & (t >= -1e-12) & (t <= 1 + 1e-12)
    assert on.all(axis=0).any(axis=1).all()  # each piece on one crease, both ends
    piece_length = np.linalg.norm(ends[1] - ends[0], axis=1).sum()
    assert piece_length == pytest.approx(np.linalg.norm(b - a, axis=1).sum(), rel=1e-12)


def test_a_flat_hole_is_refined_on_its_plane():
    # one plane, no crease: the rule leaves it to the plane test, but the refinement on
    # its own keeps every new vertex on the plane, at the surroundings' density
    cut = _hole(cube(16), (0.5, 0.5, 0.0))
    ears = ear_cut_triangulation(cut.vertices, cut.faces, cut.loop)
    new, patch = refined_in_planes(cut.vertices, cut.faces, cut.loop, ears)
    assert len(new) > 0 and np.abs(new[:, 2]).max() == 0.0
    removed = len(np.unique(cube(16)[1])) - len(np.unique(cut.faces))
    assert removed / 1.5 <= len(new) <= 1.5 * removed
    assert ear_cut_flat(cut.vertices, cut.faces, cut.loop, 0.9) is None


def test_the_report_names_the_ear_cut_fill():
    from surfinpaint import fill_holes
    from surfinpaint.app.fill_report import HoleRecord, written

    edge = _hole(cube(16), (0.5, 0.0, 0.0))
    report = fill_holes(edge.vertices, edge.faces).reports[0]  # the default's rule
    assert report.ear_cut == BY_FLAT_PLANES and report.new_vertices > 0
    assert report.note.endswith("refined within its planes, not faired")
    assert written(report) == "ear-cut fill (flat planes), not faired"
    record = HoleRecord.of(report).to_json()  # the --json report and batch's summary.json
    assert (record["ear_cut"], record["outcome"], record["fairing"]) == (
        "flat planes", "faired", None)
    assert HoleRecord.from_json(record).ear_cut == "flat planes"
    off = fill_holes(edge.vertices, edge.faces,
                     options=ConformalOptions(ear_cut_flat=None)).reports[0]
    assert off.ear_cut is None and written(off) == "λ-H fill"
    assert HoleRecord.of(off).to_json()["ear_cut"] is None


def test_the_panels_name_the_ear_cut_fill():
    from surfinpaint.app.report import compare_holes, panel_fills
    from surfinpaint.app.report_page import hole_title

    edge = _hole(cube(16), (0.5, 0.0, 0.0))
    comparisons, fills = compare_holes(edge.vertices, edge.faces, [edge.loop],
                                       options=ConformalOptions(ear_cut_flat=0.9))
    titles = panel_fills(fills, 0).titles
    # (C) draws the λ-H fill, made again: no self-check rejected it; (W) the ear cut
    assert titles["C"] == "(C) conformal fill (not written)"
    assert titles["W"] == "(W) written: ear-cut fill (flat planes)"
    assert comparisons[0].ear_cut == BY_FLAT_PLANES
    assert "the ear-cut fill (flat planes) is written (W)" in hole_title(comparisons[0])


@pytest.mark.parametrize("name, turns", [
    ("cube edge", True), ("cube corner", True), ("cube face", False)])
def test_the_crease_precheck_skips_only_holes_the_rule_cannot_fire_on(name, turns, monkeypatch):
    # the known faces on the loop's edges meet at more than PIECE_CREASE only across a
    # crease; where they do not, the rule's answer is None without the ear cut
    import surfinpaint.fill.conformal.ear_cut as ear_cut

    mesh, at, *_ = CASES[name]
    cut = _hole(mesh(), at)
    assert ear_cut._loop_faces_turn(cut.vertices, cut.faces, cut.loop,
                                    ear_cut.PIECE_CREASE) is turns
    fired = ear_cut_flat(cut.vertices, cut.faces, cut.loop, 0.9) is not None
    monkeypatch.setattr(ear_cut, "_loop_faces_turn", lambda *args: True)
    assert (ear_cut_flat(cut.vertices, cut.faces, cut.loop, 0.9) is not None) == fired


def test_the_crease_precheck_agrees_with_the_rule_on_curved_holes():
    # holes on a fine sphere, small to large: the smaller ones are told without their ear
    # cut (their loop's faces turn by less than the crease angle), the rule fires on none
    import surfinpaint.fill.conformal.ear_cut as ear_cut

    v, f = sphere(5)
    told = []
    for radius in (1.5, 3, 5, 8):
        cut = _hole((v, f), v[0], radius)
        told.append(not ear_cut._loop_faces_turn(cut.vertices, cut.faces, cut.loop,
                                                 ear_cut.PIECE_CREASE))
        assert ear_cut_flat(cut.vertices, cut.faces, cut.loop, 0.9) is None
    assert told == [True, True, True, False]
