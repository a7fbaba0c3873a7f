"""Vertices no face uses (a brain lab that cut a region's faces out of fsaverage keeps its
vertices, and their overlay values, at their ids): ``holes`` counts them in its title and
``fill`` says they stay on no face of the output (session 45: neither said a word, and a
lab saw 19 new vertices beside 33 old ones in the hole)."""

from __future__ import annotations

import warnings

import numpy as np
import trimesh

from surfinpaint.app.cli import main
from surfinpaint.io import read_mesh, write_mesh


def _faces_cut(path):
    """A sphere with the faces around vertex 0 removed, every vertex kept: the 6 vertices
    inside the hole lie on no face."""
    s = trimesh.creation.icosphere(3)
    v, f = np.asarray(s.vertices), np.asarray(s.faces)
    near = np.linalg.norm(v[f].mean(axis=1) - v[0], axis=1) < 0.3
    write_mesh(path, v, f[~near])
    unused = np.setdiff1d(np.arange(len(v)), f[~near])
    return v, f[~near], unused


def _run(*arguments):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return main(list(arguments))


def test_fill_and_holes_say_the_vertices_on_no_face(tmp_path, capsys):
    v, f, unused = _faces_cut(tmp_path / "cut.ply")
    k = len(unused)
    assert k > 1 and unused[0] == 0
    assert _run("holes", str(tmp_path / "cut.ply")) == 0
    assert f"{len(v)} vertices ({k} on no face), {len(f)} faces" in capsys.readouterr().out
    assert _run("fill", str(tmp_path / "cut.ply"), "-o", str(tmp_path / "out.ply"),
                "--method", "fair") == 0
    shown = ", ".join(map(str, unused[:5])) + (f" and {k - 5} more" if k > 5 else "")
    assert (f"{k} vertices of the input lie on no face ({shown}): kept at their ids, with "
            "their values, on no face of the output either") in capsys.readouterr().err
    out, faces = read_mesh(tmp_path / "out.ply")
    np.testing.assert_array_equal(out[:len(v)], v)
    assert not np.isin(unused, faces).any()


def test_a_mesh_whose_every_vertex_is_on_a_face_says_nothing_of_it(tmp_path, capsys):
    s = trimesh.creation.icosphere(2)
    write_mesh(tmp_path / "ball.ply", np.asarray(s.vertices), np.asarray(s.faces))
    assert _run("holes", str(tmp_path / "ball.ply")) == 0
    assert _run("fill", str(tmp_path / "ball.ply"), "-o", str(tmp_path / "out.ply")) == 0
    captured = capsys.readouterr()
    assert "on no face" not in captured.out + captured.err
