"""A mesh whose faces carry their own copies of shared vertices is told so, not filled
in silence (assimp's Wuson.ply: 'wrote' and nothing filled, session 34)."""

import warnings

import numpy as np
import pytest
import trimesh

from surfinpaint import fill_holes, write_mesh
from surfinpaint.app.cli import main
from surfinpaint.fill.holes import find_holes
from surfinpaint.fill.unjoined import unjoined_borders_note
from surfinpaint.io.base import MeshWarning


def _sphere(subdivisions=2):
    s = trimesh.creation.icosphere(subdivisions)
    return np.asarray(s.vertices), np.asarray(s.faces)


def _soup(vertices, faces):
    """Every face with its own three vertices, as a flat-shaded export writes them."""
    return vertices[faces.ravel()], np.arange(faces.size).reshape(-1, 3)


def _split_in_two(vertices, faces):
    """The sphere's upper faces given their own copies of the vertices they share with
    the lower ones: two open pieces whose borders lie on each other."""
    upper = vertices[faces].mean(axis=1)[:, 2] > 0
    copies = np.unique(faces[upper])
    renumber = np.arange(len(vertices))
    renumber[copies] = len(vertices) + np.arange(len(copies))
    out = faces.copy()
    out[upper] = renumber[faces[upper]]
    return np.vstack([vertices, vertices[copies]]), out


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
