"""A mesh whose faces carry their own copies of shared vertices is told so, not filled
in silence (assimp's Wuson.ply: 'wrote' and nothing filled, session 34)."""

import warnings

import numpy as np
import pytest
import trimesh

from surfinpaint import fill_holes, write_mesh
from surfinpaint.app.cli import main
from surfinpaint.fill.holes import find_holes, seam_edges
from surfinpaint.fill.seams import SlitWarning
from surfinpaint.fill.unjoined import unjoined_borders_note
from surfinpaint.io.base import MeshWarning


def _sphere(subdivisions=2):
    s = trimesh.creation.icosphere(subdivisions)
    return np.asarray(s.vertices), np.asarray(s.faces)


def _soup(vertices, faces):
    """Every face with its own three vertices, as a flat-shaded export writes them."""
    return vertices[faces.ravel()], np.arange(faces.size).reshape(-1, 3)


def _apart(vertices, faces, chosen):
    """The ``chosen`` faces (a mask) given their own copies of the vertices they use, as a
    textured mesh is split along a UV seam: the two sides' borders lie on each other."""
    copies = np.unique(faces[chosen])
    renumber = np.arange(len(vertices))
    renumber[copies] = len(vertices) + np.arange(len(copies))
    out = faces.copy()
    out[chosen] = renumber[faces[chosen]]
    return np.vstack([vertices, vertices[copies]]), out


def _split_in_two(vertices, faces):
    """The sphere's upper faces apart from the lower ones: two open pieces."""
    return _apart(vertices, faces, vertices[faces].mean(axis=1)[:, 2] > 0)


def _unjoined_warnings(caught):
    return [str(w.message) for w in caught if issubclass(w.category, MeshWarning)
            and "run along other boundary edges" in str(w.message)]


def _split_and_a_bowl(vertices, faces):
    """:func:`_split_in_two` beside a bowl whose rim is a true outer border."""
    v, f = _split_in_two(vertices, faces)
    bowl = faces[vertices[faces].mean(axis=1)[:, 2] < 0.0]  # a hemisphere: a border
    return np.vstack([v, vertices + [5.0, 0, 0]]), np.vstack([f, bowl + len(v)])


@pytest.mark.parametrize("make, borders", [(_soup, "all 80 outer borders"),
                                           (_split_in_two, "all 2 outer borders"),
                                           (_split_and_a_bowl, "2 of the 3 outer borders")])
def test_faces_that_do_not_join_are_named_with_how_to_join_them(make, borders):
    v, f = make(*_sphere(1))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(v, f, method="fair")
    (text,) = _unjoined_warnings(caught)
    assert text.startswith(f"{borders} run along other boundary edges")
    assert "merge coincident vertices first" in text
    assert len(result.new_faces) == 0  # nothing filled: the rule is unchanged


def test_the_border_of_an_open_surface_and_a_hole_in_one_piece_are_not_flagged():
    v, f = _sphere(2)
    open_f = f[v[f].mean(axis=1)[:, 2] < 0.3]  # a bowl: its rim is the outer border
    hole_f = f[np.linalg.norm(v[f].mean(axis=1) - v[0], axis=1) > 0.3]
    for faces in (open_f, hole_f):
        assert unjoined_borders_note(v, find_holes(v, faces)) is None
    assert unjoined_borders_note(*_sphere(1)[:1], []) is None  # closed: no loops


def test_the_holes_command_warns_too(tmp_path, capsys):
    path = tmp_path / "soup.ply"
    write_mesh(path, *_soup(*_sphere(1)))
    assert main(["holes", str(path)]) == 0
    err = capsys.readouterr().err
    assert f"{path}: all 80 outer borders run along other boundary edges" in " ".join(
        err.split())


def _patch_apart(vertices, faces, centre, radius):
    """The faces within ``radius`` of ``centre`` apart from the rest: the rest of the surface
    has a loop around them that runs along their border edge for edge."""
    return _apart(vertices, faces,
                  np.linalg.norm(vertices[faces].mean(axis=1) - centre, axis=1) < radius)


@pytest.mark.parametrize("loops, expected", [
    # two triangles side by side, not joined: the shared side is a seam edge of both
    ([[0, 1, 2], [3, 5, 4]], [[False, True, False], [False, False, True]]),
    # the same triangle twice, its copy's ids reversed: every edge on the other loop
    ([[0, 1, 2], [4, 3, 6]], [[True, True, True], [True, True, True]]),
    # one loop alone: nothing to run along (a slit runs along itself: find_slit's)
    ([[0, 1, 2]], [[False, False, False]]),
    ([], []),
])
def test_seam_edges_are_the_loop_edges_on_another_loop(loops, expected):
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0],
                  [0, 0, 0.]])
    got = seam_edges(v, [np.array(loop) for loop in loops])
    assert [m.tolist() for m in got] == expected


def test_a_loop_along_a_patch_apart_is_left_open_and_a_real_hole_is_filled():
    v, f = _sphere(3)
    v, f = _patch_apart(v, f, v[0], 0.35)
    hole = np.linalg.norm(v[f].mean(axis=1) + v[0], axis=1) < 0.3  # across the sphere
    f = f[~hole]
    found = find_holes(v, f)
    # the real hole, the seam around the patch (both of the large piece); the patch's border
    assert [(h.is_border, h.runs_along_other_loops) for h in found] == [
        (False, False), (False, True), (True, True)]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(v, f, method="fair")
    assert [r.outcome for r in result.reports] == ["faired", "skipped"]
    assert "every edge of the loop lies exactly on another boundary edge" in \
        result.reports[1].skipped
    assert any(issubclass(w.category, SlitWarning) for w in caught)
    # the filled hole is the real one: its new faces lie across the sphere from the patch
    new = result.faces[len(f):]
    assert len(new) and (result.vertices[new].mean(axis=(0, 1)) @ v[0] < 0)
    np.testing.assert_array_equal(result.vertices[:len(v)], v)


def test_zip_seams_says_it_does_not_join_loops_along_other_loops():
    """``--zip-seams`` on faces with their own vertices (assimp's Wuson.off): each skipped
    loop's line and the note say that zipping does not join them, and what does."""
    v, f = _sphere(3)
    v, f = _patch_apart(v, f, v[0], 0.35)
    soup_v, soup_f = _soup(*_sphere(1))
    v, f = np.vstack([v, soup_v + [5.0, 0, 0]]), np.vstack([f, soup_f + len(v)])
    for zip_seams in (False, True):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = fill_holes(v, f, method="fair", zip_seams=zip_seams)
        (report,) = result.reports
        (note,) = _unjoined_warnings(caught)
        assert report.outcome == "skipped" and len(result.new_faces) == 0
        for text in (report.skipped, note):
            assert "merge coincident vertices first" in text
            assert ("--zip-seams does not join" in " ".join(text.split())
                    or "--zip-seams (zip_seams=True) does not join" in text) == zip_seams
