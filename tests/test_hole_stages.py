"""Progress inside a hole: the conformal fill says each of its stages as it starts, to the
``progress`` of ``fill_holes`` and so to ``fill``'s bar and ``batch``'s (session 47: a
200-edge hole's fill took 5-30 s, a nut's bore 367 s, with the display standing still)."""

from __future__ import annotations

import re
from types import SimpleNamespace

import numpy as np
import pytest

from surfinpaint import fill_holes
from surfinpaint.app.batch import fill_files
from surfinpaint.app.batch_command import _LoggedRows
from surfinpaint.app.cli import main
from surfinpaint.app.progress import QuietConsole
from surfinpaint.data import sphere
from surfinpaint.fill.conformal.method import STAGES, conformal_fill
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import boundary_loops
from surfinpaint.io import write_mesh


@pytest.fixture(scope="module")
def holed():
    """A sphere with one 15-edge hole, whose fill is the λ-H fill (no plane around it)."""
    v, f = sphere(3)
    cut = cut_geodesic_disk(v, f, 0, 0.5)
    return cut.vertices, cut.faces


def test_the_conformal_fill_tells_its_stages_in_order(holed):
    vertices, faces = holed
    heard: list[str] = []
    fill = conformal_fill(vertices, faces, boundary_loops(faces)[0], stage=heard.append)
    assert fill.kind == "conformal"  # the λ-H fill won: every stage it ran is said
    assert heard[0] == STAGES[0] and heard[-1] == "λ-H fill"
    assert "self-check: hidden-ring test" in heard
    positions = [STAGES.index(name) for name in heard]
    assert positions == sorted(set(positions))  # in order, each once


def test_fill_holes_progress_says_the_hole_and_its_stage(holed):
    vertices, faces = holed
    said: list[tuple[int, int, str]] = []
    result = fill_holes(vertices, faces, jobs=1,
                        progress=lambda done, total, message: said.append((done, total,
                                                                           message)))
    stages = [m for _, _, m in said if "(stage " in m]
    assert said[0] == (0, 1, "hole 0: 15 edges, conformal")
    assert said[-1][:2] == (1, 1) and said[-1][2].startswith("hole 0: done in")
    assert stages[0] == f"hole 0: 15 edges, faired fills (stage 1 of {len(STAGES)})"
    assert stages[-1] == f"hole 0: 15 edges, λ-H fill (stage {len(STAGES)} of {len(STAGES)})"
    # between the hole's start and its end, the holes done still 0 of 1
    assert said[1:-1] == [(0, 1, m) for m in stages]
    numbers = [int(re.search(r"stage (\d) of", m).group(1)) for m in stages]
    assert numbers == sorted(set(numbers))
    # progress only: the same fill as without anyone listening
    quiet = fill_holes(vertices, faces, jobs=1)
    np.testing.assert_array_equal(result.vertices, quiet.vertices)
    np.testing.assert_array_equal(result.faces, quiet.faces)


def test_a_faired_fill_has_no_stages(holed):
    said: list[str] = []
    fill_holes(*holed, method="fair", jobs=1, progress=lambda d, t, m: said.append(m))
    assert not any("stage" in m for m in said) and len(said) == 2


def test_batch_progress_names_the_file_its_hole_and_the_stage(holed, tmp_path):
    (tmp_path / "in").mkdir()
    write_mesh(tmp_path / "in" / "scan.ply", *holed)
    said: list[str] = []
    fill_files([tmp_path / "in"], tmp_path / "out", jobs=1,
               progress=lambda done, total, message: said.append(message))
    assert (f"{tmp_path / 'in' / 'scan.ply'}: 0/1 holes (hole 0: 15 edges, λ-H fill (stage "
            f"{len(STAGES)} of {len(STAGES)}))") in said, said


def test_a_batch_log_has_a_line_as_a_hole_starts_a_long_stage(holed, tmp_path, capsys):
    # stderr captured: no terminal, as a log of an overnight run (the bar drawn at the end)
    (tmp_path / "in").mkdir()
    scan = tmp_path / "in" / "scan.ply"
    write_mesh(scan, *holed)
    assert main(["batch", str(tmp_path / "in"), "-o", str(tmp_path / "out"), "--jobs",
                 "1"]) == 0
    lines = capsys.readouterr().err.splitlines()
    staged = [line for line in lines if "(stage " in line]
    assert f"  {scan}: 0/1 holes (hole 0: 15 edges, λ-H fill (stage 5 of 5))" in staged, lines
    assert f"  {scan}: 0/1 holes (hole 0: 15 edges, self-check: hidden-ring test (stage 3 " \
        "of 5))" in staged, lines
    # the stages every hole runs in a moment are not logged: a log of many small holes
    # stays a line per file
    assert not any("faired fills" in line or "plane test" in line for line in staged)
    assert lines.index(staged[-1]) < next(i for i, line in enumerate(lines)
                                          if line.startswith(f"1/1 {scan}: filled"))


def test_the_log_says_each_files_long_stage_once_while_others_come_and_go(capsys):
    class Log:  # a bar drawn on a console that is no terminal
        console = SimpleNamespace(is_terminal=False)

        def update(self, done, total, message):
            pass

    logged = _LoggedRows(QuietConsole(), Log())
    a = "a.ply: 0/2 holes (hole 1: 212 edges, self-check: hidden-ring test (stage 3 of 5))"
    b = "b.ply: 0/1 holes (hole 0: 9 edges, faired fills (stage 1 of 5))"
    # a second file starts beside it, another ends (its own message), then b's next hole
    for message in (a, f"{a} · {b}", "c.ply: filled", f"{a} · {b}", a):
        logged.update(1, 3, message)
    assert capsys.readouterr().err.splitlines() == [f"  {a}"]
