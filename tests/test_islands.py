"""Holes with islands (session 37): a small separate piece of surface whose one loop lies
inside another piece's hole. Detection (fill/islands.py), the fill of the region between
the loops (fill/annulus.py, fill/island_steps.py) and the option (``islands=``,
``--islands``)."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

from surfinpaint.app.cli import build_parser, main
from surfinpaint.app.fill_options import fill_options
from surfinpaint.data import sphere
from surfinpaint.errors import HoleWarning
from surfinpaint.fill.holes import find_holes
from surfinpaint.fill.islands import ISLAND_MAX_OFFSET, find_islands, island_offset
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.geometry.intersection import self_intersections
from surfinpaint.geometry.mesh import boundary_loops, unique_edges
from surfinpaint.geometry.metrics import hole_patch_of, surface_distance
from surfinpaint.geometry.validation import validate_mesh
from surfinpaint.io import MeshWarning, write_mesh


def polar(r_in: float, r_out: float, n_r: int = 6, n_t: int = 32, centre=(0.0, 0.0, 0.0)):
    """A flat ring (a disk for ``r_in=0``) in the plane z = centre's z, faces turning
    counter-clockwise about +z; a ring's outer loop has twice the vertices of its inner
    one (so that it is the longer loop, the piece's outer border)."""
    t = 2 * np.pi * np.arange(n_t) / n_t
    radii = np.linspace(r_in, r_out, n_r + 1)
    first = 1 if r_in == 0 else 0
    rings = [np.column_stack([r * np.cos(t), r * np.sin(t), np.zeros(n_t)])
             for r in radii[first:]]
    j = np.arange(n_t)
    at = lambda i, j: first + i * n_t + (j % n_t)  # noqa: E731
    faces = [np.column_stack([np.zeros(n_t, int), at(0, j), at(0, j + 1)])] if first else []
    for i in range(len(rings) - 1 - (not first)):
        faces += [np.column_stack([at(i, j), at(i + 1, j), at(i + 1, j + 1)]),
                  np.column_stack([at(i, j), at(i + 1, j + 1), at(i, j + 1)])]
    if not first:  # the outer ring with twice the vertices, zipped to the one inside it
        t2 = np.pi * np.arange(2 * n_t) / n_t
        rings[-1] = np.column_stack([r_out * np.cos(t2), r_out * np.sin(t2), np.zeros(2 * n_t)])
        a, b = lambda j: at(len(rings) - 2, j), lambda k: at(len(rings) - 1, 0) + k % (2 * n_t)
        faces += [np.column_stack([a(j), b(2 * j), b(2 * j + 1)]),
                  np.column_stack([a(j), b(2 * j + 1), a(j + 1)]),
                  np.column_stack([a(j + 1), b(2 * j + 1), b(2 * j + 2)])]
    v = np.vstack(([[0.0, 0.0, 0.0]] if first else []) + rings) + np.asarray(centre, float)
    return v, np.vstack(faces).astype(np.int64)


def joined(*pieces):
    """Pieces of surface as one mesh, each piece's vertices after the previous ones'."""
    vs, fs, n = [], [], 0
    for v, f in pieces:
        vs.append(v)
        fs.append(f + n)
        n += len(v)
    return np.vstack(vs), np.vstack(fs)


def sphere_with_island(subdivisions=4, around=(0.0, 0.0, 1.0), inner=8.0, outer=25.0):
    """A sphere with an annular hole (``inner`` to ``outer`` degrees from ``around``): the
    cap inside is an island. Returns the mesh, the kept faces, and the removed annulus."""
    v, f = sphere(subdivisions)
    c = v[f].mean(axis=1)
    c /= np.linalg.norm(c, axis=1)[:, None]
    angle = np.degrees(np.arccos(np.clip(c @ np.asarray(around) / np.linalg.norm(around),
                                         -1, 1)))
    ring = (angle > inner) & (angle < outer)
    return v, f[~ring], f[ring]


def _scan_near_border():
    # a hemisphere (its equator the scan's border) with a hole reaching 8 degrees from the
    # border and an island in it
    v, f, _ = sphere_with_island(5, around=(np.cos(np.radians(26)), 0,
                                            np.sin(np.radians(26))), inner=6, outer=18)
    return v, f[v[f].mean(axis=1)[:, 2] > 0]


RING = polar(1.0, 3.0)

# (name, mesh, the islands found as (hole, island loop, opposite)); loop 0 is the ring's
# outer border, loop 1 its hole (r = 1, diameter 2), loop 2 (3) the small piece(s)
DETECTION_CASES = [
    ("island inside", lambda: joined(RING, polar(0, 0.4, 3, 16, (0, 0, 0.1))), [(1, 2, False)]),
    ("small piece far away", lambda: joined(RING, polar(0, 0.4, 3, 16, (10, 0, 0))), []),
    ("piece beside the hole, outside its polygon",
     lambda: joined(RING, polar(0, 0.3, 3, 16, (1.5, 0, 0.05))), []),
    ("piece over the hole's rim, 9 of its 16 loop vertices inside (a folded hole's case)",
     lambda: joined(RING, polar(0, 0.4, 3, 16, (0.8, 0, 0.05))), [(1, 2, False)]),
    ("piece over the hole's rim, 5 of 16 inside",
     lambda: joined(RING, polar(0, 0.4, 3, 16, (1.1, 0, 0.05))), []),
    ("inside, within the offset allowed (0.45 diameters)",
     lambda: joined(RING, polar(0, 0.4, 3, 16, (0, 0, 0.9))), [(1, 2, False)]),
    ("inside but far off the plane (0.55 diameters)",
     lambda: joined(RING, polar(0, 0.4, 3, 16, (0, 0, 1.1))), []),
    ("two islands in one hole",
     lambda: joined(RING, polar(0, 0.25, 3, 16, (0.45, 0, 0)),
                    polar(0, 0.25, 3, 16, (-0.45, 0, 0))), [(1, 2, False), (1, 3, False)]),
    ("piece not much smaller than the one around the hole",
     lambda: joined(polar(1.0, 1.2, 1), polar(0, 0.8, 3, 16)), []),
    ("island wound opposite",
     lambda: (lambda v, f: (v, np.vstack([f[:len(RING[1])], f[len(RING[1]):, ::-1]])))(
         *joined(RING, polar(0, 0.4, 3, 16))), [(1, 2, True)]),
    ("sphere with an annular hole around a cap", lambda: sphere_with_island()[:2],
     [(0, 1, False)]),
    ("island in a hole near a scan's border", _scan_near_border, [(1, 2, False)]),
]


@pytest.mark.parametrize(("name", "make", "expected"), DETECTION_CASES,
                         ids=[c[0] for c in DETECTION_CASES])
def test_islands_are_the_small_pieces_whose_loop_lies_in_a_hole(name, make, expected):
    v, f = make()
    found = find_holes(v, f)
    islands = find_islands(v, f, found)
    assert [(i.hole, i.loop, i.opposite) for i in islands] == expected, name
    for i in islands:
        assert not found[i.hole].is_border
        assert i.piece == found[i.loop].component != found[i.hole].component
        assert 0 <= i.offset <= ISLAND_MAX_OFFSET


def test_island_offset_is_the_distance_off_the_hole_plane_in_diameters():
    hole = polar(1.0, 3.0, 1)[0][:32]  # the ring's inner loop: diameter 2
    assert island_offset(hole, 0.5 * hole + [0, 0, 0.6]) == pytest.approx(0.3)
    assert island_offset(hole, 0.5 * hole + [1.2, 0, 0]) == np.inf  # partly outside
    assert island_offset(np.zeros((4, 3)), hole) == np.inf  # a hole that spans no area


def _closed_and_clean(result, vertices, faces):
    """The checks every fill with islands must pass."""
    assert np.array_equal(result.vertices[:len(vertices)], vertices)
    assert np.array_equal(result.faces[:len(faces)], faces)  # originals untouched, first
    assert len(self_intersections(result.vertices, result.faces)) == 0
    _, _, count = unique_edges(result.faces)
    assert count.max() <= 2  # edge-manifold
    directed = np.concatenate([result.faces[:, [0, 1]], result.faces[:, [1, 2]],
                               result.faces[:, [2, 0]]])
    assert len(np.unique(directed, axis=0)) == len(directed)  # oriented consistently


def test_the_sphere_case_closes_into_one_piece_near_the_truth():
    v, f, ring = sphere_with_island()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the default fill of it warns of nothing
        result = fill_holes(v, f, jobs=1)
    [report] = result.reports
    assert (report.index, report.outcome, report.islands) == (0, "faired", (1,))
    assert report.note == "with its island, piece 1 (loop 1)"
    assert report.fair_order == 3
    _closed_and_clean(result, v, f)
    assert boundary_loops(result.faces) == []
    check = validate_mesh(result.vertices, result.faces)
    assert check.n_components == 1 and check.euler_characteristic == 2
    # the removed annulus: 0.042 % of the hole diameter measured (order 3; the disk fill
    # through the island, islands="ignore", 0.27 %)
    pv, pf = hole_patch_of(result.vertices, result.faces, len(v), f)
    distance = surface_distance(pv, pf, v, ring).mean
    assert 100 * distance / report.diameter < 0.08


def test_two_islands_in_a_flat_hole_are_filled_flat():
    v, f = joined(RING, polar(0, 0.25, 3, 16, (0.45, 0, 0)), polar(0, 0.25, 3, 16, (-0.45, 0, 0)))
    result = fill_holes(v, f, method="fair", jobs=1)
    [report] = result.reports
    assert report.islands == (2, 3) and report.outcome == "faired"
    assert report.note == "with its islands, piece 1 (loop 2), piece 2 (loop 3)"
    _closed_and_clean(result, v, f)
    assert np.abs(result.vertices[len(v):, 2]).max() < 1e-9  # the plane, faired
    assert [len(loop) for loop in boundary_loops(result.faces)] == [64]  # the outer border


def test_ignore_fills_the_disk_and_warns_naming_the_hole_and_the_island():
    v, f, _ = sphere_with_island()
    with pytest.warns(MeshWarning, match=r"hole 0: piece 1 \(loop 1\) lies inside it, an "
                      r"island; islands='ignore'"):
        result = fill_holes(v, f, islands="ignore", jobs=1)
    assert result.reports[0].islands == ()
    assert [len(loop) for loop in boundary_loops(result.faces)] == [12]  # the island's, open


def test_a_disk_through_the_island_it_ignores_is_said_to_cross_it():
    # islands="ignore": the λ-H disk over the annulus passes through the cap it leaves; the
    # check made with the fill looks only at the rings around the hole's loop, so it is the
    # check after all fills (fill/far_crossings.py) that must count and say it
    v, f, _ = sphere_with_island()
    with pytest.warns(MeshWarning, match="islands='ignore'"), \
            pytest.warns(HoleWarning, match=r"hole 0: \d+ triangles of the fill cross the "
                         r"surface farther out"):
        result = fill_holes(v, f, islands="ignore", jobs=1)
    report = result.reports[0]
    assert report.outcome == "lambda-h" and report.crossings > 0
    assert self_intersections(result.vertices, result.faces).size > 0


def test_an_island_wound_opposite_is_not_joined_and_said_so():
    v, f, _ = sphere_with_island()
    island = np.isin(f, find_holes(v, f)[1].loop).any(axis=1)
    cap = np.linalg.norm(v[f].mean(axis=1) - [0, 0, 1], axis=1) < 0.2
    flipped = np.where((island | cap)[:, None], f[:, ::-1], f)
    with pytest.warns(MeshWarning, match=r"hole 0: piece 1 .*wound opposite"):
        result = fill_holes(v, flipped, jobs=1)
    assert result.reports[0].islands == ()
    assert np.array_equal(result.faces[:len(f)], flipped)  # never flipped back silently


def test_an_island_loop_chosen_too_is_filled_with_its_hole_not_on_its_own():
    v, f, _ = sphere_with_island()
    result = fill_holes(v, f, include_border=True, jobs=1)
    assert [(r.index, r.outcome) for r in result.reports] == [(0, "faired"), (1, "skipped")]
    assert result.reports[1].skipped.startswith("the island of hole 0")
    assert boundary_loops(result.faces) == []


def test_islands_is_checked_and_passed_by_fill_files(tmp_path):
    from surfinpaint.app.batch import fill_files

    v, f, _ = sphere_with_island()
    with pytest.raises(ValueError, match="islands must be one of 'bridge', 'ignore'"):
        fill_holes(v, f, islands="delete")
    with pytest.raises(ValueError, match="islands must be one of"):
        fill_files([tmp_path / "none.ply"], tmp_path / "out", islands=True)
    write_mesh(tmp_path / "island.ply", v, f)
    for mode, loops_left in (("bridge", 0), ("ignore", 1)):  # the island's loop, open
        rows = fill_files([tmp_path / "island.ply"], tmp_path / mode, jobs=1, islands=mode)
        assert rows[0].status != "failed", rows[0].message
        assert len(find_holes(*_read(tmp_path / mode / "island.ply"))) == loops_left


def _read(path):
    from surfinpaint.io import read_mesh

    return read_mesh(path)


@pytest.mark.parametrize("command", [["fill", "m.ply", "-o", "out.ply"],
                                     ["batch", "m.ply", "-o", "out"], ["holes", "m.ply"],
                                     ["report", "m.ply", "-o", "out"]])
def test_every_command_that_fills_or_lists_holes_takes_islands(command):
    # session 38: report had no --islands (its fills always bridged); the one definition of
    # the option (fill_options.add_islands) is used by all four
    parser = build_parser()
    assert parser.parse_args(command).islands == "bridge"
    assert parser.parse_args([*command, "--islands", "ignore"]).islands == "ignore"
    with pytest.raises(SystemExit):
        parser.parse_args([*command, "--islands", "delete"])
    if command[0] in ("fill", "batch"):
        assert fill_options(parser.parse_args([*command, "--islands", "ignore"]))[
            "islands"] == "ignore"


@pytest.mark.parametrize(("options", "hole", "island"), [
    ([], "hole with island loop 1: filled with it", "island of hole 0 (piece 1): joined to it"),
    (["--islands", "ignore"], "hole with island loop 1: filled as a disk through or by it "
     "(--islands ignore)", "island of hole 0 (piece 1): left as it is")])
def test_holes_shows_the_island_of_its_hole(tmp_path, capsys, monkeypatch, options, hole,
                                            island):
    monkeypatch.setenv("COLUMNS", "250")  # one table row a line
    v, f, _ = sphere_with_island()
    write_mesh(tmp_path / "island.ply", v, f)
    assert main(["holes", str(tmp_path / "island.ply"), *options]) == 0
    out = capsys.readouterr().out
    rows = {int(r[0]): r[-1] for r in ([c.strip() for c in re.split(r"[│┃|]", line)
                                         if c.strip()] for line in out.splitlines())
            if r and r[0].isdigit()}
    assert rows == {0: hole, 1: island}, out


@pytest.mark.parametrize(("options", "written"), [
    ([], "the faired fill (order 3) with its island (loop 1) is written"),
    (["--islands", "ignore"], "the λ-H fill (C) is written")])
def test_report_fills_as_fill_does_with_islands(tmp_path, capsys, options, written):
    # session 38: `report --islands ignore` was a usage error, its fills always bridged,
    # and a hole filled with its island was titled "the λ-H fill failed"
    v, f, _ = sphere_with_island(subdivisions=3)
    write_mesh(tmp_path / "island.ply", v, f)
    assert main(["report", str(tmp_path / "island.ply"), "-o", str(tmp_path / "r"),
                 *options]) == 0
    # the disk through the island crosses it: since session 39 the title says so last
    lines = [re.sub(r"; \d+ of its triangles cross the surface$", "", line)
             for line in capsys.readouterr().err.splitlines() if line.startswith("hole 0, ")]
    assert len(lines) == 1 and lines[0].endswith(written), lines
    assert "failed" not in lines[0] and "rejected" not in lines[0]


@pytest.mark.parametrize("quiet", [False, True])
def test_report_says_its_fills_warnings_named_once_and_lists_them_on_its_page(
        tmp_path, capsys, monkeypatch, quiet):
    # session 39: `report` ran its fills with the warnings off: `--islands ignore`'s and a
    # fill reaching through the island were said nowhere
    monkeypatch.chdir(tmp_path)
    v, f, _ = sphere_with_island(subdivisions=3)
    write_mesh("island.ply", v, f)
    assert main(["report", "island.ply", "-o", "r", "--islands", "ignore",
                 *(["-q"] if quiet else [])]) == 0
    err = capsys.readouterr().err
    island = ("hole 0: piece 1 (loop 1) lies inside it, an island; islands='ignore' "
              "(--islands ignore): the hole is filled as a disk through or by it, the island "
              "left as it is")
    crossing = re.compile(r"hole 0: (\d+) triangles of the fill cross the surface farther "
                          r"out than the rings around the hole")
    warned = [line for line in err.splitlines() if line.startswith("warning:")]
    assert all(line.startswith("warning: island.ply: hole 0: ") for line in warned), warned
    assert [line for line in warned if island in line] == [f"warning: island.ply: {island}"]
    # the crossing is said once: in the hole's title where the titles are printed (as
    # `fill` says it in the hole's line), else as a warning
    crossed = [crossing.search(line) for line in warned if crossing.search(line)]
    titles = [line for line in err.splitlines() if line.startswith("hole 0, ")]
    if quiet:
        assert len(crossed) == 1 and not titles
        count = int(crossed[0].group(1))
    else:
        assert not crossed and len(titles) == 1
        count = int(re.search(r"; (\d+) of its triangles cross the surface$",
                              titles[0]).group(1))
    assert count > 0
    # the page lists every warning of the fills, under "Warnings"
    page = (tmp_path / "r" / "index.md").read_text("utf-8")
    listed = page[page.index("## Warnings"):].splitlines()
    assert f"- {island}" in listed
    (listed_crossing,) = [line for line in listed if crossing.search(line)]
    assert listed_crossing.startswith("- hole 0: ")
    assert int(crossing.search(listed_crossing).group(1)) == count
    html = (tmp_path / "r" / "index.html").read_text("utf-8")
    assert "<h2>Warnings</h2>" in html and "<li>hole 0: piece 1 (loop 1) lies inside it" in html


def test_fill_prints_the_island_note(tmp_path, capsys):
    v, f, _ = sphere_with_island()
    write_mesh(tmp_path / "island.ply", v, f)
    report = tmp_path / "report.json"
    assert main(["fill", str(tmp_path / "island.ply"), "-o", str(tmp_path / "out.ply"),
                 "--json", str(report)]) == 0
    assert "with its island, piece 1 (loop 1)" in capsys.readouterr().err  # the console's
    # the JSON report names the island's loop, and reads back as the same typed record
    import json

    from surfinpaint.app.fill_report import HoleRecord

    holes = json.loads(report.read_text("utf-8"))["holes"]
    assert [h["islands"] for h in holes] == [[1]]
    assert HoleRecord.from_json(holes[0]).islands == (1,)
    assert HoleRecord.from_json({**holes[0], "islands": []}).islands == ()


def test_an_island_that_cannot_be_joined_leaves_the_hole_filled_as_a_disk(monkeypatch):
    from surfinpaint.errors import FillError
    from surfinpaint.fill import island_steps

    def fails(*args, **kwargs):
        raise FillError("every bridge folds over")

    monkeypatch.setattr(island_steps, "annulus_fill", fails)
    v, f, _ = sphere_with_island()
    with pytest.warns(MeshWarning, match=r"hole 0: piece 1 \(loop 1\) lies inside it, an "
                      r"island; it could not be joined \(every bridge folds over\)"):
        result = fill_holes(v, f, method="fair", jobs=1)
    assert (result.reports[0].outcome, result.reports[0].islands) == ("faired", ())
    assert [len(loop) for loop in boundary_loops(result.faces)] == [12]  # never deleted


def test_a_fill_with_islands_that_crosses_the_surface_is_not_kept(monkeypatch):
    from surfinpaint.fill import island_steps

    monkeypatch.setattr(island_steps, "crossing_triangles", lambda *args: np.arange(3))
    v, f, _ = sphere_with_island()
    with pytest.warns(MeshWarning, match=r"it could not be joined \(its fill's triangles "
                      r"cross the surface around the loops or one another: 3 at order 3, "
                      r"3 at order 2\)"):
        result = fill_holes(v, f, jobs=1)
    assert result.reports[0].islands == ()
    assert [len(loop) for loop in boundary_loops(result.faces)] == [12]
