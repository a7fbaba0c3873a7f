"""The README's Python examples and the λ-H representation's commands, run from the README's
text as a new user runs them (session 42): the Quick start's ``python`` block, the paragraph
on ``trimesh`` / ``pyvista`` meshes after it, the representation's ``bash`` and ``python``
blocks, and the Python API table's signatures and its ``ConformalOptions`` example. Each runs
in a folder of its own made by the Quick start's first line (the bundled ``scan.ply``, the
snowman with 2 holes, and ``disk.ply``, the bumpy disk).

The README's representation block once used the Quick start's ``vertices, faces``
(``scan.ply``, two boundary loops), on which ``represent`` raises "a disk has one"; it now
reads ``disk.ply`` and defines its ``new_H`` itself, so every block here runs as written,
with nothing defined for it.
"""

from __future__ import annotations

import inspect
import re
import shlex
from pathlib import Path

import numpy as np
import pytest

import surfinpaint
from surfinpaint.app.cli import main

README = Path(__file__).resolve().parents[1] / "README.md"
TEXT = README.read_text(encoding="utf-8")
QUICK_START = TEXT.split("## Quick start", 1)[1].split("\n## ", 1)[0]
API_TABLE = TEXT.split("## Python API", 1)[1].split("\n## ", 1)[0]


def _blocks(language: str) -> list[str]:
    """The Quick start section's fenced blocks of one language, in order."""
    return re.findall(rf"```{language}\n(.*?)```", QUICK_START, re.S)


BASH_BLOCKS = _blocks("bash")
PYTHON_BLOCKS = _blocks("python")
# the Quick start's first bash block is the commands' one (tests/test_readme_quick_start.py);
# the representation's bash and python blocks follow the sentence that introduces them
REPRESENTATION_INTRO = "The λ-H representation of a disk-like surface"
REPRESENTATION_BASH, REPRESENTATION_PYTHON = (
    re.search(rf"```{language}\n(.*?)```", QUICK_START.split(REPRESENTATION_INTRO, 1)[1],
              re.S).group(1)
    for language in ("bash", "python"))
FILL_PYTHON = PYTHON_BLOCKS[0]


def _paragraph_after(block: str) -> str:
    """The paragraph that follows a fenced block in the Quick start."""
    return QUICK_START.split(block + "```", 1)[1].strip().split("\n\n", 1)[0]


@pytest.fixture
def bundled(tmp_path, monkeypatch):
    """The bundled meshes the Quick start's first line makes, in a folder of their own."""
    monkeypatch.chdir(tmp_path)
    first_line = BASH_BLOCKS[0].splitlines()[0]
    words = shlex.split(first_line)
    assert words[:2] == ["python", "-c"], first_line
    exec(words[2], {})
    assert Path("scan.ply").is_file() and Path("disk.ply").is_file()
    return tmp_path


def test_the_blocks_are_where_the_tests_look():
    assert len(PYTHON_BLOCKS) == 2 and REPRESENTATION_PYTHON == PYTHON_BLOCKS[1]
    assert "fill_holes" in FILL_PYTHON and "represent(" in REPRESENTATION_PYTHON
    assert REPRESENTATION_BASH == BASH_BLOCKS[-1]
    assert "surfinpaint represent " in REPRESENTATION_BASH


def test_the_quick_start_python_block_runs_as_written(bundled, capsys):
    names = {}
    exec(compile(FILL_PYTHON, "README.md (Quick start, python)", "exec"), names)
    printed = capsys.readouterr().out.splitlines()
    # two lines per hole of the bundled snowman: its find_holes row and its report row
    assert len(printed) == 4, printed
    mesh, filled = names["mesh"], names["filled"]
    assert filled.vertices.shape[0] > mesh.vertices.shape[0]
    assert [report.outcome for report in names["result"].reports] == ["lambda-h"] * 2
    written = surfinpaint.read_mesh_data("filled.ply")
    assert written.vertices.shape == filled.vertices.shape
    assert not surfinpaint.find_holes(written.vertices, written.faces)
    assert Path("before_after.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_fill_holes_takes_a_trimesh_and_a_polydata_and_gives_them_back(bundled):
    """The paragraph after the Python block, on the bundled snowman: a Trimesh's given vertex
    normals and a PolyData's active scalars and texture coordinates come back."""
    trimesh = pytest.importorskip("trimesh")
    pyvista = pytest.importorskip("pyvista")
    paragraph = _paragraph_after(FILL_PYTHON)
    for code in ("trimesh.Trimesh", "pyvista.PolyData", "result.to_trimesh()",
                 "result.to_pyvista()"):
        assert f"`{code}`" in paragraph, code
    vertices, faces = surfinpaint.read_mesh("scan.ply")
    n_filled = surfinpaint.fill_holes(vertices, faces).vertices.shape[0]
    normals = vertices / np.linalg.norm(vertices, axis=1)[:, None]

    given = trimesh.Trimesh(vertices, faces, vertex_normals=normals, process=False)
    result = surfinpaint.fill_holes(given)
    back = result.to_trimesh()
    assert isinstance(back, trimesh.Trimesh) and back.vertices.shape == (n_filled, 3)
    np.testing.assert_allclose(back.vertex_normals[: len(vertices)], normals, atol=1e-12)

    polydata = pyvista.PolyData(vertices, np.column_stack([np.full(len(faces), 3), faces]))
    polydata.point_data["height"] = vertices[:, 2]
    polydata.set_active_scalars("height")
    polydata.active_texture_coordinates = vertices[:, :2].copy()
    result = surfinpaint.fill_holes(polydata)
    back = result.to_pyvista()
    assert isinstance(back, pyvista.PolyData) and back.n_points == n_filled
    assert back.active_scalars_name == "height"
    np.testing.assert_array_equal(back.active_scalars[: len(vertices)], vertices[:, 2])
    assert back.active_texture_coordinates.shape == (n_filled, 2)
    # the merge the paragraph advises takes the keywords it names
    assert {"merge_tex", "merge_norm"} <= set(
        inspect.signature(trimesh.Trimesh.merge_vertices).parameters)
    assert "mesh.merge_vertices(merge_tex=True, merge_norm=True)" in paragraph
    # the picture, in a notebook: the paragraph's call, on the PolyData's own arrays
    assert "`surfinpaint.before_after_figure(mesh.vertices, mesh.faces, result)`" in paragraph
    figure = surfinpaint.before_after_figure(polydata.points, polydata.regular_faces, result)
    # the whole mesh before and after, and each of its 2 holes before and after
    assert type(figure).__name__ == "Figure" and len(figure.axes) == 6


def test_the_representation_commands_run_as_written(bundled, capsys):
    lines = [line for line in REPRESENTATION_BASH.splitlines() if line.strip()]
    assert len(lines) == 3
    for line in lines:
        words = shlex.split(line, comments=True)
        assert words[0] == "surfinpaint", line
        assert main(words[1:]) == 0, capsys.readouterr().err
        # each prints its round trip (rebuild: the distance to the stored original), on
        # stderr with the other reports
        assert "round trip: mean" in capsys.readouterr().err, line
        for word in words:
            if word.endswith((".npz", ".png")) or word == "rebuilt.ply":
                assert Path(word).is_file(), word


def test_the_representation_python_block_runs_as_written(bundled, capsys):
    names = {}
    exec(compile(REPRESENTATION_PYTHON, "README.md (λ-H representation, python)", "exec"),
         names)
    assert "round trip: mean" in capsys.readouterr().out
    back, edited = names["back"], names["edited"]
    vertices = names["vertices"]
    assert back.converged and edited.converged
    assert back.vertices.shape == edited.vertices.shape == vertices.shape
    # the edited H moves the surface further than the unedited H's rebuild is from the original
    assert np.abs(edited.vertices - back.vertices).max() > np.abs(back.vertices - vertices).max()


def _table_calls() -> list[tuple[str, list[str]]]:
    """Each ``name(parameters)`` in the API table's first column: the name and its
    parameters' names."""
    calls = []
    for row in API_TABLE.splitlines():
        if not row.startswith("| `"):
            continue
        for name, params in re.findall(r"`(\w+)\(([^`]*)\)`", row.split("|")[1]):
            words = [p.split("=")[0].strip() for p in params.split(",")]
            calls.append((name, [w for w in words if w not in ("", "*", "...")]))
    return calls


TABLE_CALLS = _table_calls()


def test_the_api_table_names_its_calls():
    assert {"fill_holes", "read_mesh", "rebuild", "represent"} <= {n for n, _ in TABLE_CALLS}


@pytest.mark.parametrize(("name", "params"), TABLE_CALLS, ids=[n for n, _ in TABLE_CALLS])
def test_every_call_in_the_api_table_has_the_parameters_it_shows(name, params):
    signature = inspect.signature(getattr(surfinpaint, name))
    assert set(params) <= set(signature.parameters), (name, params)


def test_the_api_tables_conformal_options_example_runs(bundled):
    example = re.search(r"e\.g\. `(fill_holes\(v, f, options=[^`]*)`", API_TABLE).group(1)
    v, f = surfinpaint.read_mesh("scan.ply")
    result = eval(f"surfinpaint.{example}", {"surfinpaint": surfinpaint, "v": v, "f": f})
    assert "creases=False" in example
    assert [report.outcome for report in result.reports] == ["lambda-h"] * 2
    # what the table says a fill returns and find_holes gives: attributes of them
    fields = _row_description("fill_holes(")
    assert {"vertices", "reports", "outcome", "self_check", "topology"} <= fields
    for field in fields - set(surfinpaint.__all__):
        assert hasattr(result, field) or hasattr(result.reports[0], field), field
    fields = _row_description("find_holes(") | {"loop"}
    hole = surfinpaint.find_holes(v, f)[0]
    assert {"n_edges", "diameter", "is_border"} <= fields
    for field in fields - set(surfinpaint.__all__):
        assert hasattr(hole, field), field


def _row_description(call: str) -> set[str]:
    """The backquoted names in the description column of the API table's row of a call."""
    row = next(row for row in API_TABLE.splitlines() if row.startswith(f"| `{call}"))
    return set(re.findall(r"`(\w+)`", row.split("|")[2]))
