"""``batch`` into a log (stderr no terminal: ``batch scans -o out 2> log``, an overnight
run): a line per file as it is done, so the log shows how far the run is (session 45: rich
draws the bar once, at the end, and a log of a run of hours said nothing of the files done
until it ended). A failed file's line is its error; ``-q`` leaves the lines out.
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import trimesh

from surfinpaint.app.cli import main
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.io import write_mesh

LINE = re.compile(r"^(\d+)/3 (\S+): (\w+)(?:, (\d+) of (\d+) holes?)?, \d+\.\d s$")


def _scans(folder):
    folder.mkdir()
    s = trimesh.creation.icosphere(3)
    v, f = np.asarray(s.vertices), np.asarray(s.faces)
    cut = cut_holes(v, f, [0, 40], [0.35, 0.3])
    write_mesh(folder / "a.ply", cut.vertices, cut.faces)
    write_mesh(folder / "b.ply", v, f)  # closed
    (folder / "c.ply").write_bytes(b"")  # empty: fails the pre-flight


def _batch(*arguments):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return main(["batch", *arguments])


def test_a_batch_into_a_log_says_each_file_as_it_is_done(tmp_path, capsys):
    _scans(tmp_path / "scans")
    assert _batch(str(tmp_path / "scans"), "-o", str(tmp_path / "out"), "--jobs", "1",
                  "--method", "fair") == 1
    lines = capsys.readouterr().err.splitlines()
    done = [LINE.match(line).groups() for line in lines if LINE.match(line)]
    assert {(name.rsplit("/", 1)[1], status, filled, found)
            for _, name, status, filled, found in done} == {
        ("a.ply", "filled", "2", "2"), ("b.ply", "closed", None, None)}
    # counted as they are done, the failed file among them (its error is its line)
    assert sorted(int(k) for k, *_ in done) == [2, 3]
    assert any(line.startswith("error: ") and "c.ply: file is empty" in line
               for line in lines)
    # a rerun: each file up to date, said so
    assert _batch(str(tmp_path / "scans"), "-o", str(tmp_path / "out"), "--jobs", "1") == 1
    rerun = [LINE.match(line) for line in capsys.readouterr().err.splitlines()]
    assert sorted(m[3] for m in rerun if m) == ["skipped", "skipped"]


def test_a_quiet_batch_says_no_file_but_the_failed(tmp_path, capsys):
    _scans(tmp_path / "scans")
    assert _batch(str(tmp_path / "scans"), "-o", str(tmp_path / "out"), "--jobs", "1",
                  "--method", "fair", "-q") == 1
    lines = capsys.readouterr().err.splitlines()
    assert not any(LINE.match(line) for line in lines)
    assert any("c.ply: file is empty" in line for line in lines)
