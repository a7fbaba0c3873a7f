"""Every command takes the one ``-q``/``--quiet`` and does the same with it (session 38):
``-q`` leaves out the progress display, the report and the notices on stderr, keeping the
warnings, the errors and what the command writes on stdout (the table of ``holes``);
``-qq`` leaves out the warnings too. Before: ``report -q`` still printed its hole lines and
"wrote ...", and ``holes``, ``represent``, ``rebuild`` and ``demo`` had no ``-q``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from surfinpaint.app.cli import build_parser, main
from surfinpaint.app.progress import QUIET_HELP
from surfinpaint.io.formats import write_mesh


def _grid(n: int = 10, hole: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """A flat n × n grid (a disk), with the faces around its middle removed (a hole)."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    vertices = np.column_stack([x.ravel(), y.ravel(), 0.05 * np.sin(3 * x.ravel())])
    corner = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]).ravel()
    faces = np.vstack([np.column_stack([corner, corner + 1, corner + n + 1]),
                       np.column_stack([corner, corner + n + 1, corner + n])])
    if hole:
        centre = vertices[faces].mean(axis=1)[:, :2]
        faces = faces[np.linalg.norm(centre - 0.5, axis=1) > 0.2]
    return vertices, faces


def _inputs(folder: Path) -> None:
    write_mesh(folder / "holed.ply", *_grid())
    write_mesh(folder / "disk.ply", *_grid(8, hole=False))
    assert main(["represent", str(folder / "disk.ply"), "-o", str(folder / "disk.npz"),
                 "-q"]) == 0


# each command on an input it runs on cleanly (no warning), outputs in the folder; a command
# with "both" is also run without -q, to show that -q is what silenced it (demo and
# experiments take seconds: with -q only)
COMMANDS = {
    "holes": (["holes", "holed.ply"], False),
    "fill": (["fill", "holed.ply", "-o", "filled.ply", "--method", "fair"], True),
    "batch": (["batch", "holed.ply", "-o", "batch", "--method", "fair", "--jobs", "1"], True),
    "represent": (["represent", "disk.ply", "-o", "rep.npz"], True),
    "rebuild": (["rebuild", "disk.npz", "-o", "rebuilt.ply"], True),
    "report": (["report", "holed.ply", "-o", "report"], True),
    "demo": (["demo", "-o", "demo", "--method", "fair"], False),
    "experiments": (["experiments", "-o", "experiments", "--quick", "--cases", "cube"], False),
    "compile": (["compile"], True),
}


def test_every_command_has_the_one_quiet_option():
    parser = build_parser()
    (commands,) = [a for a in parser._actions if a.dest == "command"]
    assert set(commands.choices) == set(COMMANDS)  # the table below covers them all
    for name, sub in commands.choices.items():
        (quiet,) = [a for a in sub._actions if "--quiet" in a.option_strings]
        assert quiet.option_strings == ["-q", "--quiet"], name
        assert quiet.help == QUIET_HELP, name  # one definition (progress.add_quiet)
        assert sub.parse_args([*COMMANDS[name][0][1:], "-qq"]).quiet == 2


def _run(folder: Path, argv: list[str], capsys, monkeypatch):
    folder.mkdir()
    monkeypatch.chdir(folder)
    _inputs(folder)
    capsys.readouterr()
    assert main(argv) == 0
    return capsys.readouterr()


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_quiet_prints_nothing_on_stderr_for_a_clean_run(tmp_path, capsys, monkeypatch,
                                                       command):
    argv, both = COMMANDS[command]
    quiet = _run(tmp_path / "quiet", [*argv, "-q"], capsys, monkeypatch)
    assert quiet.err == "", quiet.err
    if command == "holes":  # the table is the command's output: kept
        assert "holed.ply: 100 vertices" in quiet.out and "│ hole" in quiet.out
    if both:  # without -q it says something: the case tests what -q left out
        assert _run(tmp_path / "loud", argv, capsys, monkeypatch).err.strip()


def test_qq_leaves_out_the_warnings_q_keeps_them(tmp_path, capsys):
    vertices, faces = _grid()
    faces = np.vstack([faces, [[0, 1, 1]]])  # a degenerate face: a warning
    write_mesh(tmp_path / "odd.ply", vertices, faces)
    for command in (["holes", str(tmp_path / "odd.ply")],
                    ["report", str(tmp_path / "odd.ply"), "-o", str(tmp_path / "r")]):
        assert main([*command, "-q"]) == 0
        assert "warning:" in capsys.readouterr().err
        assert main([*command, "-qq"]) == 0
        assert capsys.readouterr().err == ""
