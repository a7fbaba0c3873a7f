"""Progress inside a hole: the conformal fill says each of its stages as it starts, to the
``progress`` of ``fill_holes`` and so to ``fill``'s bar and ``batch``'s (session 47: a
200-edge hole's fill took 5-30 s, a nut's bore 367 s, with the display standing still)."""

from __future__ import annotations

import re
from queue import Queue
from types import SimpleNamespace

import numpy as np
import pytest

from surfinpaint import fill_holes
from surfinpaint.app import batch_listing
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


def test_a_batch_log_of_quick_holes_is_a_line_per_file(holed, tmp_path, capsys):
    # stderr captured: no terminal, as a log of an overnight run (the bar drawn at the end)
    (tmp_path / "in").mkdir()
    for name in ("a", "b"):
        write_mesh(tmp_path / "in" / f"{name}.ply", *holed)
    assert main(["batch", str(tmp_path / "in"), "-o", str(tmp_path / "out"), "--jobs",
                 "2"]) == 0
    lines = capsys.readouterr().err.splitlines()
    assert not any("(stage " in line for line in lines), lines  # each stage took < 10 s
    assert sum(": filled, 1 of 1 hole" in line for line in lines) == 2, lines


def test_the_log_says_a_stage_that_lasts_once_while_other_files_come_and_go(capsys):
    class Log:  # a bar drawn on a console that is no terminal
        console = SimpleNamespace(is_terminal=False)

        def update(self, done, total, message):
            pass

    now = [0.0]
    logged = _LoggedRows(QuietConsole(), Log(), clock=lambda: now[0])
    a = "a.ply: 0/2 holes (hole 1: 212 edges, self-check: hidden-ring test (stage 3 of 5))"
    a5 = "a.ply: 0/2 holes (hole 1: 212 edges, λ-H fill (stage 5 of 5))"
    b = "b.ply: 0/1 holes (hole 0: 9 edges, faired fills (stage 1 of 5))"
    # (seconds, message): a's self-check lasts 12 s while b starts, c ends, b goes on
    for seconds, message in ((0, a), (3, f"{a} · {b}"), (5, "c.ply: filled"),
                             (9, f"{a} · {b}"), (12, f"{a} · {b}"), (13, f"{a} · {b}"),
                             (14, a5), (23, a5), (24.5, a5), (40, a5), (41, "a.ply: filled")):
        now[0] = seconds
        logged.update(1, 3, message)
    assert capsys.readouterr().err.splitlines() == [f"  {a}, 12 s so far", f"  {b}, 10 s so far",
                                                    f"  {a5}, 10 s so far"]


def test_a_file_in_flight_is_said_again_without_news(monkeypatch):
    said = []
    rows = batch_listing.RunRows(2, lambda done, total, message: said.append(message))
    queue = Queue()
    queue.put(("a.ply", 0, 1, "hole 0: 212 edges, λ-H fill (stage 5 of 5)"))
    now = [100.0]
    monkeypatch.setattr(batch_listing.time, "monotonic", lambda: now[0])
    rows.read(queue)
    rows.read(queue)  # no news, no time gone: nothing said
    now[0] += batch_listing.SAY_AGAIN_SECONDS
    rows.read(queue)  # no news for a while: the same again
    assert said == ["a.ply: 0/1 holes (hole 0: 212 edges, λ-H fill (stage 5 of 5))"] * 2
    assert batch_listing.files_in_flight(said[0]) == [said[0]]
    assert batch_listing.files_in_flight("a.ply: filled") == []
