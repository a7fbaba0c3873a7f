"""Bad option values and unknown option names are usage errors at the entry point: exit 2
on the command line (before any file is read), an exception naming the option in the API,
for every method."""

from __future__ import annotations

import numpy as np
import pytest

from surfinpaint import fill_files, fill_holes
from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.fill.objects import fill_mesh_data
from surfinpaint.io import MeshData
from surfinpaint.io.formats import write_mesh


@pytest.fixture(scope="module")
def holed_file(tmp_path_factory):
    v, f = sphere(2)
    path = tmp_path_factory.mktemp("usage") / "holed.ply"
    write_mesh(path, v, f[1:])
    return path


def _exit_code(argv) -> int:
    """The command's exit code, argparse's own refusals (SystemExit) included."""
    try:
        return main(argv)
    except SystemExit as exc:
        return exc.code


@pytest.mark.parametrize("argv", [
    ["--max-hole-edges", "0"], ["--max-hole-edges", "-3"], ["--max-hole-edges", "2.5"],
    ["--jobs", "0"], ["--fair-order", "5"], ["--crease-angle", "200"], ["--holes", "x"],
    ["--holes", ""], ["--holes", " , "],
])
@pytest.mark.parametrize("command", ["fill", "batch"])
def test_bad_fill_option_values_exit_2(command, argv, holed_file, tmp_path, capsys):
    # before: --max-hole-edges 0 and -3 reached fill_holes' ValueError (exit 1)
    if command == "batch" and argv[0] == "--holes":
        pytest.skip("batch has no --holes")
    out = tmp_path / ("out.ply" if command == "fill" else "outdir")
    assert _exit_code([command, str(holed_file), "-o", str(out), "-q", *argv]) == 2
    assert argv[0] in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("command", ["fill", "represent"])
def test_a_png_not_named_png_exits_2(command, holed_file, tmp_path, capsys):
    # `--png out.jpg` wrote PNG bytes into a file named .jpg
    out = tmp_path / ("out.ply" if command == "fill" else "r.npz")
    picture = tmp_path / "picture.jpg"
    assert _exit_code([command, str(holed_file), "-o", str(out), "--png", str(picture)]) == 2
    assert "--png" in capsys.readouterr().err
    assert not out.exists() and not picture.exists()


@pytest.mark.parametrize("output, extra", [("r.txt", []), ("r.npz", ["--export-grid", "g.txt"]),
                                           ("r.npz", ["--export-quadtree", "q"])])
def test_a_representation_not_named_npz_exits_2(output, extra, holed_file, tmp_path, capsys):
    # `represent -o r.txt` wrote a NumPy archive into a file named .txt
    extra = [a if a.startswith("-") else str(tmp_path / a) for a in extra]
    assert _exit_code(["represent", str(holed_file), "-o", str(tmp_path / output),
                       *extra]) == 2
    assert "name it .npz" in capsys.readouterr().err
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize("argv", [["--resolution", "0"], ["--resolution", "-2"],
                                  ["--subdivide", "-1"]])
def test_bad_represent_option_values_exit_2(argv, holed_file, tmp_path, capsys):
    # before: --resolution 0 was taken as "the default"
    out = tmp_path / "r.npz"
    assert _exit_code(["represent", str(holed_file), "-o", str(out), *argv]) == 2
    assert argv[0] in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("method", ["conformal", "fair"])
def test_misspelled_options_are_refused_at_every_entry_point(method, holed_file, tmp_path):
    v, f = sphere(2)
    for call in (lambda: fill_holes(v, f[1:], method=method, max_hole_edge=3),
                 lambda: fill_mesh_data(MeshData(v, f[1:]), method=method, max_hole_edge=3),
                 lambda: fill_files([holed_file], tmp_path / "out", jobs=1, method=method,
                                    max_hole_edge=3)):
        with pytest.raises(TypeError, match="max_hole_edge"):
            call()
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("name", ["include_border", "repair", "validate", "zip_seams"])
def test_flags_must_be_booleans(name):
    v, f = sphere(2)
    with pytest.raises(ValueError, match=name):
        fill_holes(v, f[1:], method="fair", **{name: "no"})
    assert fill_holes(v, f[1:], method="fair", **{name: np.bool_(False)}).reports
