"""The README's Quick start, as a new lab user runs it (session 41): its first line makes the
bundled meshes it names, every ``surfinpaint`` line parses, and each line that picks holes
(``--holes``) runs on them and exits 0 (``--holes 0,2`` failed on the bundled snowman,
which has 2 holes)."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from surfinpaint.app.cli import build_parser, main

README = Path(__file__).resolve().parents[1] / "README.md"


def _quick_start_lines() -> list[str]:
    """The lines of the Quick start's first ``bash`` block, comments left out."""
    text = README.read_text(encoding="utf-8")
    section = text.split("## Quick start", 1)[1]
    block = re.search(r"```bash\n(.*?)```", section, re.S).group(1)
    return [line for line in block.splitlines() if line.strip()]


def _args(line: str) -> list[str]:
    words = shlex.split(line, comments=True)
    assert words[0] == "surfinpaint", line
    return words[1:]


LINES = _quick_start_lines()
COMMANDS = [line for line in LINES if line.startswith("surfinpaint ")]


def test_the_quick_start_is_a_block_of_commands():
    assert LINES[0].startswith("python -c ") and len(COMMANDS) == len(LINES) - 1 >= 4


@pytest.mark.parametrize("line", COMMANDS)
def test_every_quick_start_command_parses(line):
    args = _args(line)
    build_parser(args[0]).parse_args(args)


@pytest.fixture
def bundled(tmp_path, monkeypatch):
    """The bundled meshes the Quick start's first line makes, in a folder of their own."""
    monkeypatch.chdir(tmp_path)
    subprocess.run([sys.executable, *shlex.split(LINES[0])[1:]], check=True)
    assert Path("scan.ply").is_file() and Path("disk.ply").is_file()
    return tmp_path


@pytest.mark.parametrize("line", [line for line in COMMANDS if "--holes" in line])
def test_a_quick_start_line_that_picks_holes_runs_on_the_bundled_mesh(bundled, line, capsys):
    assert main(_args(line)) == 0, capsys.readouterr().err
    for word in _args(line):
        if word.endswith((".ply", ".png", ".json")) and word != "scan.ply":
            assert Path(word).is_file(), word
