"""The options that choose which loops ``fill`` fills (``--keep-margins``, ``--zip-seams``,
``--max-hole-edges``) taken by ``holes`` and ``report`` too, with fill's meaning: ``holes``
says per loop what ``fill`` with the same options does, ``report`` compares the holes that
``fill`` with them fills (session 35's audits: docs/robustness.md)."""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest
import trimesh
from test_seams import uv_sphere, without_faces_near

from surfinpaint.app.cli import main
from surfinpaint.app.fill_options import hole_list
from surfinpaint.data import sphere
from surfinpaint.fill.holes import find_holes
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.io import write_mesh


def _crown():
    """A sphere cut above z = 0.3 (its loop spans about 39 % of what remains: "the
    margin?", hole 0) with a small hole cut at its bottom (hole 1)."""
    s = trimesh.creation.icosphere(3)
    v, f = np.asarray(s.vertices), np.asarray(s.faces)
    f = f[v[f].mean(axis=1)[:, 2] < 0.3]
    near = np.linalg.norm(v[f].mean(axis=1) - v[np.argmin(v[:, 2])], axis=1) < 0.25
    return v, f[~near]


def _seamed_sphere():
    """A UV sphere whose seam has its vertices twice (hole 0, 24 edges, spans no area) and
    an ordinary hole of 8 edges (hole 1)."""
    v, f = uv_sphere()
    return v, without_faces_near(v, f, [-1, 0, 0], 0.35)


def _large_and_small():
    """A closed sphere with a large hole and a small one."""
    v, f = sphere(2)
    h = mean_edge_length(v, f)
    cut = cut_holes(v, f, [0, int(np.argmin(v @ v[0]))], [4.5 * h, 1.5 * h])
    return cut.vertices, cut.faces


def _disk_with_holes():
    """A bumpy disk (its outer border, hole 0, 101 edges) with two holes (1: 12 edges, 2:
    6 edges)."""
    from surfinpaint.data import bumpy_disk

    v, f = bumpy_disk(16)
    h = mean_edge_length(v, f)
    near = [int(np.argmin(np.linalg.norm(v[:, :2] - p, axis=1)))
            for p in ([0.3, 0.1], [-0.4, -0.2])]
    cut = cut_holes(v, f, near, [2.5 * h, 1.5 * h])
    return cut.vertices, cut.faces


MESHES = {"crown": _crown, "seamed sphere": _seamed_sphere, "large and small": _large_and_small,
          "disk": _disk_with_holes}


# (mesh, options, the loops `fill` leaves open, what `holes` says of each)
HOLES_CASES = [
    ("crown", [], [], {}),
    ("crown", ["--keep-margins"], [0], {0: "left open (--keep-margins)"}),
    ("crown", ["--max-hole-edges", "20"], [0], {0: "44 boundary edges > max_hole_edges=20"}),
    ("crown", ["--keep-margins", "--max-hole-edges", "5"], [0, 1],
     {0: "left open (--keep-margins)", 1: "12 boundary edges > max_hole_edges=5"}),
    ("seamed sphere", [], [0], {0: "a seam of 11 coincident vertex pairs"}),
    ("seamed sphere", ["--zip-seams"], [], {0: "zipped (--zip-seams)"}),
    ("seamed sphere", ["--zip-seams", "--max-hole-edges", "20"], [0],
     {0: "24 boundary edges > max_hole_edges=20"}),
    ("large and small", [], [], {}),
    ("large and small", ["--max-hole-edges", "10"], [0],
     {0: "20 boundary edges > max_hole_edges=10"}),
    ("large and small", ["--max-hole-edges", "4"], [0, 1],
     {1: "5 boundary edges > max_hole_edges=4"}),
]


def _fill_keywords(options: list[str]) -> dict:
    keywords = {"keep_margins": "--keep-margins" in options,
                "zip_seams": "--zip-seams" in options,
                "include_border": "--all" in options}
    if "--max-hole-edges" in options:
        keywords["max_hole_edges"] = int(options[options.index("--max-hole-edges") + 1])
    if "--holes" in options:
        keywords["holes"] = hole_list(options[options.index("--holes") + 1])
    return keywords


def _holes_table(tmp_path, capsys, monkeypatch, v, f, options):
    """``surfinpaint holes`` on the mesh with ``options``: its output, and each loop's last
    table column by loop number."""
    monkeypatch.setenv("COLUMNS", "250")  # one table row a line
    path = tmp_path / "mesh.ply"
    write_mesh(path, v, f)
    assert main(["holes", str(path), *options]) == 0
    out = capsys.readouterr().out
    rows = [[c.strip() for c in re.split(r"[│┃|]", line) if c.strip()]
            for line in out.splitlines()]
    return out, {int(r[0]): r[-1] for r in rows if r and r[0].isdigit()}


@pytest.mark.parametrize(("mesh", "options", "left_open", "said"), HOLES_CASES)
def test_holes_says_what_fill_with_the_same_options_leaves_open(tmp_path, capsys, monkeypatch,
                                                               mesh, options, left_open, said):
    # `holes` took none of these options: its verdicts were fill's defaults only (before
    # this, every case with an option is a usage error, exit 2)
    v, f = MESHES[mesh]()
    out, rows = _holes_table(tmp_path, capsys, monkeypatch, v, f, options)
    assert len(rows) == len(find_holes(v, f)), out
    said_open = [k for k, kind in rows.items() if "left open" in kind]
    assert said_open == left_open, out
    for k, words in said.items():
        assert words in rows[k] or re.search(rf"^hole {k}: .*{re.escape(words)}.*; fill skips "
                                             "it$", out, re.MULTILINE), out
    # what fill does with the same options: the loops it neither fills nor zips
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = fill_holes(v, f, method="fair", **_fill_keywords(options))
    done = {r.index for r in result.reports if not r.skipped}
    assert [k for k, h in enumerate(find_holes(v, f))
            if not h.is_border and k not in done] == left_open


# (mesh, options, what `holes` says of each loop): the loops fill leaves open say "left
# open"; an outer border fill does not choose says "outer border"
ALL_AND_NAMED_CASES = [
    ("disk", [], {0: "outer border", 1: "hole", 2: "hole"}),
    ("disk", ["--all"], {0: "outer border: filled (--all)", 1: "hole", 2: "hole"}),
    ("disk", ["--all", "--max-hole-edges", "50"], {0: "left open: see below"}),
    ("disk", ["--holes", "2"], {0: "left open (not in --holes)",
                                1: "left open (not in --holes)", 2: "hole"}),
    ("disk", ["--holes", "0,1"], {0: "outer border: filled (--holes)", 1: "hole",
                                  2: "left open (not in --holes)"}),
    ("crown", ["--holes", "1", "--keep-margins"], {0: "left open (not in --holes)",
                                                   1: "hole"}),
    ("crown", ["--holes", "0", "--keep-margins"], {1: "left open (not in --holes)"}),
    ("large and small", ["--holes", "0-1", "--max-hole-edges", "10"],
     {0: "left open: see below", 1: "hole"}),
]


@pytest.mark.parametrize(("mesh", "options", "said"), ALL_AND_NAMED_CASES)
def test_holes_all_and_holes_say_what_fill_all_and_holes_do(tmp_path, capsys, monkeypatch,
                                                            mesh, options, said):
    # `holes` had neither --all nor --holes: a usage error (exit 2) before this
    v, f = MESHES[mesh]()
    out, rows = _holes_table(tmp_path, capsys, monkeypatch, v, f, options)
    for k, words in said.items():
        assert rows[k].startswith(words), out
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = fill_holes(v, f, method="fair", **_fill_keywords(options))
    done = {r.index for r in result.reports if not r.skipped}
    # what holes says fill leaves open (a loop left open, or an outer border not chosen)
    # is what fill with the same options does not fill
    said_open = {k for k, kind in rows.items() if "left open" in kind or kind == "outer border"}
    assert said_open == set(rows) - done, out


def test_holes_names_a_hole_out_of_range_as_fill_does(tmp_path, capsys):
    v, f = _disk_with_holes()
    write_mesh(tmp_path / "disk.ply", v, f)
    for command in (["holes", str(tmp_path / "disk.ply")],
                    ["fill", str(tmp_path / "disk.ply"), "-o", str(tmp_path / "out.ply")]):
        assert main([*command, "--holes", "7"]) == 1
        assert "hole index 7 out of range: the mesh has 3 boundary loops" in \
            capsys.readouterr().err.replace("\n", " ")


@pytest.mark.parametrize("command", [["fill", "m.ply", "-o", "out.ply"],
                                     ["report", "m.ply", "-o", "out"],
                                     ["holes", "m.ply"]])
def test_every_command_that_names_holes_takes_holes_and_all_as_fill_does(command):
    # one definition of each (app/fill_options.add_hole_numbers, add_all_loops)
    from surfinpaint.app.cli import build_parser

    parser = build_parser()
    assert parser.parse_args(command).holes is None
    assert parser.parse_args([*command, "--holes", "0-2,5"]).holes == [0, 1, 2, 5]
    if command[0] != "report":  # report compares the holes fill fills; --all: not asked
        assert parser.parse_args(command).all is False
        assert parser.parse_args([*command, "--all"]).all is True
    assert parser.parse_args(["batch", "m.ply", "-o", "out", "--all"]).all is True


def test_holes_rejects_a_bad_size_limit_as_fill_does(tmp_path, capsys):
    v, f = _crown()
    write_mesh(tmp_path / "crown.ply", v, f)
    for command in (["holes", str(tmp_path / "crown.ply")],
                    ["fill", str(tmp_path / "crown.ply"), "-o", str(tmp_path / "out.ply")]):
        with pytest.raises(SystemExit) as exc:
            main([*command, "--max-hole-edges", "0"])
        assert exc.value.code == 2
        assert "--max-hole-edges: must be at least 1, got 0" in capsys.readouterr().err


# (options, the holes the page shows: those `fill` with the options fills)
REPORT_CASES = [
    ([], [0, 1]),
    (["--keep-margins"], [1]),               # the margin is not written by fill: not shown
    (["--keep-margins", "--holes", "0"], [0]),  # named: filled, as by `fill --holes 0`
]


@pytest.mark.parametrize(("options", "shown"), REPORT_CASES)
def test_report_keep_margins_shows_what_fill_keep_margins_writes(tmp_path, capsys, options,
                                                                 shown):
    # `report` had no --keep-margins: its page said the margin's fill "is written" where
    # `fill --keep-margins` leaves it open (session 35 helper 2's dental lab)
    v, f = _crown()
    write_mesh(tmp_path / "crown.ply", v, f)
    out = tmp_path / "report"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # without -q: its "wrote ... and N panels" is a notice (session 38)
        assert main(["report", str(tmp_path / "crown.ply"), "-o", str(out), *options]) == 0
    assert sorted(p.name for p in out.glob("hole*.png")) == [f"hole{k}.png" for k in shown]
    md = (out / "index.md").read_text()
    assert [int(k) for k in re.findall(r"\(hole(\d+)\.png\)", md)] == shown
    said = capsys.readouterr().err  # the command line's console is stderr
    assert f"{len(shown)} panel{'s' * (len(shown) != 1)}" in said
    holes = [int(k) for k in _holes_named(options)] or None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        filled = fill_holes(v, f, holes=holes, method="fair",
                            keep_margins="--keep-margins" in options)
    assert [r.index for r in filled.reports if not r.skipped] == shown


def _holes_named(options: list[str]) -> list[str]:
    return options[options.index("--holes") + 1].split(",") if "--holes" in options else []


@pytest.mark.parametrize("command", [["fill", "m.ply", "-o", "out.ply"],
                                     ["batch", "m.ply", "-o", "out"],
                                     ["report", "m.ply", "-o", "out"],
                                     ["holes", "m.ply"]])
def test_every_command_that_chooses_loops_takes_keep_margins(command):
    # one definition of the option (app/fill_options.add_keep_margins): each command parses
    # it to the same attribute, off unless given
    from surfinpaint.app.cli import build_parser

    parser = build_parser()
    assert parser.parse_args(command).keep_margins is False
    assert parser.parse_args([*command, "--keep-margins"]).keep_margins is True


@pytest.mark.parametrize("holes, error, message", [
    # a loop naming a vertex the mesh does not have: said by its id, not as an edge that
    # does not join (fuzz campaign, session 46)
    ("beyond", "MeshError", r"hole loop vertex {n5} out of range: the mesh has {n} vertices"),
    ("negative", "MeshError", r"hole loop vertex -1 out of range"),
    # a bool is no hole's name (True was hole 1), a fractional id no vertex's (0.5 was 0)
    ("bool", "ValueError", r"hole indices must be integers, got True"),
    ("fraction", "ValueError", r"a hole loop's vertex ids must be integers, got 0\.5"),
])
def test_a_given_hole_that_names_nothing_of_the_mesh_is_refused_by_what_it_names(
        holes, error, message):
    v, f = sphere(3)
    cut = cut_holes(v, f, [0], 3 * mean_edge_length(v, f))
    n = len(cut.vertices)
    loop = [int(i) for i in cut.holes[0].loop]
    given = {"beyond": [loop[:2] + [n + 5]], "negative": [[-1] + loop[:2]],
             "fraction": [[0.5] + loop[1:]], "bool": [True]}[holes]
    with pytest.raises(Exception, match=message.format(n=n, n5=n + 5)) as raised:
        fill_holes(cut.vertices, cut.faces, holes=given)
    assert type(raised.value).__name__ == error


def test_a_given_loop_of_whole_number_floats_is_the_loop():
    v, f = sphere(3)
    cut = cut_holes(v, f, [0], 3 * mean_edge_length(v, f))
    as_ints = fill_holes(cut.vertices, cut.faces, holes=[cut.holes[0].loop])
    as_floats = fill_holes(cut.vertices, cut.faces, holes=[cut.holes[0].loop.astype(float)])
    np.testing.assert_array_equal(as_ints.vertices, as_floats.vertices)
    np.testing.assert_array_equal(as_ints.faces, as_floats.faces)
