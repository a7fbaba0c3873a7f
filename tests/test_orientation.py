"""orient_faces and ``--repair``'s reorientation: flipped faces flipped back (the fewest, per
piece), the holes filled around them, a Möbius strip still refused, assimp's spider filled."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from conftest import grid_mesh

from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.errors import MeshError
from surfinpaint.fill.objects import fill_mesh_data
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.geometry.orientation import orient_faces
from surfinpaint.geometry.repair import repair_faces
from surfinpaint.geometry.validation import validate_mesh
from surfinpaint.io import MeshData

SPIDER = Path("/usr/share/assimp/models/OBJ/spider.obj")


def _flip(faces, ids):
    """``faces`` with the faces ``ids`` flipped as orient_faces flips (last two ids swapped)."""
    out = np.array(faces, dtype=np.int64, copy=True)
    out[ids] = out[ids][:, [0, 2, 1]]
    return out


def _consistent(faces) -> bool:
    """Every directed edge in at most one face."""
    half = np.column_stack([faces.ravel(), faces[:, [1, 2, 0]].ravel()])
    return len(np.unique(half, axis=0)) == len(half)


def _mobius(n: int = 16):
    """A triangulated Möbius strip: rails t_i, b_i joined with a half twist after the last."""
    u = 2 * np.pi * np.arange(n) / n
    rail = [np.column_stack([(1 + s * np.cos(u / 2)) * np.cos(u),
                             (1 + s * np.cos(u / 2)) * np.sin(u), s * np.sin(u / 2)])
            for s in (0.3, -0.3)]
    v = np.vstack(rail)  # t_i = i, b_i = n + i
    faces = []
    for i in range(n):
        t0, b0 = i, n + i
        t1, b1 = (i + 1, n + i + 1) if i < n - 1 else (n, 0)  # the twist: t_n = b_0, b_n = t_0
        faces += [[t0, b0, b1], [t0, b1, t1]]
    return v, np.array(faces)


def test_closed_sphere_with_three_faces_flipped_is_restored():
    v, f = sphere(2)
    bad = _flip(f, [5, 77, 200])
    v0 = v.copy()
    with pytest.raises(MeshError, match="inconsistent face orientation"):
        fill_holes(v, bad)
    oriented, flipped, non_orientable = orient_faces(bad)
    assert flipped.tolist() == [5, 77, 200] and non_orientable == []
    np.testing.assert_array_equal(oriented, f)
    with pytest.warns(UserWarning, match=r"repair flipped 3 faces \(5, 77, 200\) to orient"):
        result = fill_holes(v, bad, repair=True)
    np.testing.assert_array_equal(result.faces, f)
    np.testing.assert_array_equal(result.vertices, v0)
    np.testing.assert_array_equal(v, v0)
    assert result.flipped_faces.tolist() == [5, 77, 200]
    assert result.removed_faces.size == 0 and result.reports == []


def test_a_consistent_mesh_is_untouched_and_not_warned():
    v, f = sphere(2)
    oriented, flipped, bad = orient_faces(f)
    np.testing.assert_array_equal(oriented, f)
    assert flipped.size == 0 and bad == []
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        result = fill_holes(v, f, repair=True)
    assert result.flipped_faces.size == 0


def test_open_mesh_with_a_hole_and_flipped_faces_is_filled():
    v, f = sphere(3)
    holed = f[~np.isin(f, [0]).any(axis=1)]  # the fan around vertex 0 cut out
    flips = [3, 100, 101, 600]
    bad = _flip(holed, flips)
    with pytest.warns(UserWarning, match=r"repair flipped 4 faces \(3, 100, 101, 600\)"):
        result = fill_holes(v, bad, method="fair", repair=True)
    n = result.n_original_faces
    assert n == len(holed)
    np.testing.assert_array_equal(result.faces[:n], holed)  # the reoriented ones, in order
    assert len(result.reports) == 1 and not result.reports[0].skipped
    assert len(result.new_faces) > 0
    assert _consistent(result.faces)
    validate_mesh(result.vertices, result.faces)  # closed and consistent
    np.testing.assert_array_equal(result.vertices[: len(v)], v)


def test_flipped_ids_count_the_input_faces_when_faces_were_removed():
    v, f = sphere(2)
    a, b = f[10, 0], f[10, 1]
    v = np.vstack([v, (v[a] + v[b]) * 0.7])
    fin = [a, b, len(v) - 1]
    given = np.vstack([[fin], _flip(f, [200, 250])])  # the fin first: every id shifts
    kept, removed, flipped, turned = repair_faces(v, given)
    assert turned == []
    assert 0 in removed and len(removed) == 3
    assert flipped.tolist() == [201, 251]
    np.testing.assert_array_equal(kept, np.delete(np.vstack([[fin], f]), removed, axis=0))
    with pytest.warns(UserWarning, match=r"repair flipped 2 faces \(201, 251\)"):
        result = fill_holes(v, given, method="fair", repair=True)
    assert result.flipped_faces.tolist() == [201, 251]
    assert _consistent(result.faces)


# the grid has 32 faces; its faces 0..15 and 16..31 are two halves of each cell
@pytest.mark.parametrize(("given", "expected"), [
    ([7], [7]),                                   # one of many flipped: it is flipped back
    ([k for k in range(32) if k != 7], [7]),      # all but one: that one follows them
    (list(range(16, 32)), list(range(16, 32))),   # a tie: face 0 keeps its orientation
    (list(range(16)), list(range(16, 32))),       # a tie, face 0 among the flipped: still kept
    (list(range(32)), []),                        # all flipped: consistent, nothing to do
])
def test_majority_orientation_wins(given, expected):
    v, f = grid_mesh(4, 4)
    assert len(f) == 32
    bad = _flip(f, given)
    oriented, flipped, _ = orient_faces(bad)
    assert flipped.tolist() == expected
    assert _consistent(oriented)
    np.testing.assert_array_equal(oriented, _flip(bad, expected))


def test_each_piece_keeps_its_own_majority():
    v, f = grid_mesh(4, 4)
    two = np.vstack([_flip(f, [3]), _flip(f, [k for k in range(32) if k != 3]) + len(v)])
    oriented, flipped, bad = orient_faces(two)
    assert flipped.tolist() == [3, 32 + 3] and bad == []
    np.testing.assert_array_equal(oriented[:32], f)
    np.testing.assert_array_equal(oriented[32:], _flip(f, range(32)) + len(v))


def test_faces_that_repeat_a_vertex_and_crowded_edges_join_nothing():
    # (0, 1) in faces 0, 2 and 3, all but 3 running 0 -> 1; (1, 2) in faces 0 and 1 alike
    f = np.array([[0, 1, 2], [1, 2, 4], [0, 1, 3], [1, 0, 5], [6, 6, 7], [6, 7, 6]])
    oriented, flipped, bad = orient_faces(f)
    assert flipped.tolist() == [1]  # a tie: face 0 keeps its orientation
    assert bad == []
    np.testing.assert_array_equal(np.delete(oriented, 1, axis=0), np.delete(f, 1, axis=0))
    assert orient_faces(np.zeros((0, 3), int))[1].size == 0


def test_mobius_strip_is_left_as_it_is_and_refused():
    v, f = _mobius()
    oriented, flipped, bad = orient_faces(f)
    np.testing.assert_array_equal(oriented, f)
    assert flipped.size == 0
    assert len(bad) == 1 and bad[0].tolist() == list(range(len(f)))
    for repair in (False, True):
        with pytest.raises(MeshError, match="inconsistent face orientation") as caught:
            fill_holes(v, f, repair=repair)
        text = str(caught.value)
        assert "1 non-orientable piece (like a Möbius strip" in text
        assert f"{len(f)} faces (0, 1, 2, 3, 4, ...)" in text and "elsewhere" not in text


def test_mobius_beside_an_orientable_piece():
    mv, mf = _mobius()
    v, f = sphere(1)
    both_v = np.vstack([v, mv])
    both_f = np.vstack([_flip(f, [2]), mf + len(v)])
    with pytest.raises(MeshError) as caught, pytest.warns(UserWarning, match=r"1 face \(2\)"):
        fill_holes(both_v, both_f, repair=True)  # the sphere reoriented, the strip refused
    text = str(caught.value)
    assert "1 non-orientable piece" in text and f"{len(mf)} faces ({len(f)}, " in text
    assert "elsewhere --repair (repair=True) reorients each piece consistently" not in text
    with pytest.raises(MeshError) as caught:
        validate_mesh(both_v, both_f)  # without the repair, the sphere's face is still off
    assert ("elsewhere --repair (repair=True) reorients each piece consistently, flipping 1 "
            "face (") in str(caught.value)


def test_corner_attributes_follow_the_flipped_corners():
    v, f = sphere(2)
    holed = f[~np.isin(f, [0]).any(axis=1)]
    bad = _flip(holed, [4, 50])
    corners = {"where": v[bad]}  # each corner's own vertex position
    with pytest.warns(UserWarning, match="repair flipped 2 faces"):
        result, filled = fill_mesh_data(MeshData(v, bad, corner_attributes=corners),
                                        method="fair", repair=True)
    n = result.n_original_faces
    np.testing.assert_array_equal(filled.corner_attributes["where"][:n], v[result.faces[:n]])


@pytest.mark.skipif(not SPIDER.is_file(), reason="assimp-testmodels")
def test_assimps_spider_fills_with_repair(tmp_path, capsys):
    out = tmp_path / "out.obj"
    assert main(["fill", str(SPIDER), "-o", str(out), "--repair"]) == 0
    captured = capsys.readouterr()
    said = " ".join((captured.out + captured.err).split())
    assert "repair flipped 4 faces (1061, 1097, 1171, 1207)" in said
    assert out.is_file()
    assert main(["holes", str(SPIDER), "--repair"]) == 0
    printed = " ".join(capsys.readouterr().out.split())
    assert "--repair flipped 4 faces (1061, 1097, 1171, 1207)" in printed


# --------------------------------------------------- closed pieces outward (session 35)


def _volume(v, f) -> float:
    return float(np.einsum("ij,ij->i", v[f[:, 0]], np.cross(v[f[:, 1]], v[f[:, 2]])).sum() / 6)


def _pieces():
    """A closed sphere, the same with a hole (open), each away from the other."""
    v, f = sphere(2)
    ball = (v, f)
    cut = cut_holes(v, f, [0], [2.5 * mean_edge_length(v, f)])
    cup = (cut.vertices + [4.0, 0, 0], cut.faces)
    return ball, cup


@pytest.mark.parametrize(("ball_inward", "few_flipped", "cup_inward", "turned"), [
    (True, False, False, 1),   # a closed piece wound inward: turned outward
    (True, True, False, 1),    # ... with a few faces against the rest: all made outward
    (False, True, False, 0),   # outward already: only the few faces flipped back
    (False, False, True, 0),   # an open piece wound inward keeps its majority winding
    (True, False, True, 1),    # each piece by its own rule
])
def test_repair_turns_closed_pieces_outward_and_leaves_open_ones(ball_inward, few_flipped,
                                                                 cup_inward, turned):
    (v, f), (cv, cf) = _pieces()
    ball = f[:, [0, 2, 1]] if ball_inward else f
    if few_flipped:
        ball = _flip(ball, [5, 77])
    cup = cf[:, [0, 2, 1]] if cup_inward else cf
    vertices = np.vstack([v, cv])
    given = np.vstack([ball, cup + len(v)])
    repair = repair_faces(vertices, given)
    kept = repair.faces
    assert len(repair.turned) == turned
    assert _volume(vertices, kept[: len(f)]) > 0  # the closed piece: outward in every case
    # the open piece: its majority winding, as before
    np.testing.assert_array_equal(kept[len(f):], cup + len(v))
    assert _consistent(kept)
    changed = np.flatnonzero((kept != given).any(axis=1))
    np.testing.assert_array_equal(repair.flipped, changed)
    if turned:
        np.testing.assert_array_equal(repair.turned[0], np.arange(len(f)))
        (note,) = [n for n in repair.notes() if n.startswith("turned")]
        assert note.startswith(f"turned 1 closed piece outward (negative volume): its "
                               f"{len(f)} faces (0, 1,")
    # the fill says so, and its result is the repaired mesh
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(vertices, given, method="fair", repair=True)
    said = [str(w.message) for w in caught if "turned" in str(w.message)]
    assert len(said) == (1 if turned else 0)
    np.testing.assert_array_equal(result.faces[: len(kept)], kept)
    np.testing.assert_array_equal(result.flipped_faces, repair.flipped)
