"""What every command says, and leaves, for the inputs and outputs a user gets wrong most
(session 37): a missing or unreadable input, a mesh with no holes, an output in a folder
that does not exist. Each names the file, exits as the README says (1 for an error, 0 for
"nothing to fill"), and leaves nothing half-written."""

from __future__ import annotations

import os
import warnings
from pathlib import Path

import numpy as np
import pytest

from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.io.formats import write_mesh


def _flat(text: str) -> str:
    """The text without any whitespace: immune to the console's line wrapping."""
    return "".join(text.split())


def _disk(path: Path) -> Path:
    """A flat 8 × 8 grid: open only at its outer border."""
    x, y = np.meshgrid(np.linspace(0, 1, 8), np.linspace(0, 1, 8))
    vertices = np.column_stack([x.ravel(), y.ravel(), np.zeros(64)])
    corner = (np.arange(7)[:, None] * 8 + np.arange(7)[None, :]).ravel()
    faces = np.vstack([np.column_stack([corner, corner + 1, corner + 9]),
                       np.column_stack([corner, corner + 9, corner + 8])])
    write_mesh(path, vertices, faces)
    return path


def _closed(path: Path) -> Path:
    write_mesh(path, *sphere(2))
    return path


def _files(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


# ------------------------------------------------------------- a missing or unreadable input

# the commands that read one input file, with the arguments that follow it (outputs in out/)
READERS = {
    "fill": ["-o", "out/filled.ply", "--method", "fair", "-q"],
    "holes": [],
    "report": ["-o", "out/report", "-q"],
    "represent": ["-o", "out/rep.npz"],
    "rebuild": ["-o", "out/rebuilt.ply"],
    "batch": ["-o", "out", "--jobs", "1", "-q"],
}


def _unreadable(monkeypatch, path: Path) -> None:
    """Make ``path`` unreadable: no permission (root reads anything, so opening it, by
    ``open`` or ``Path.read_bytes``, is made to fail as it fails for other users)."""
    path.chmod(0)
    if os.geteuid() != 0:
        return
    import builtins

    real_open, real_read_bytes = builtins.open, Path.read_bytes

    def check(file) -> None:
        if isinstance(file, str | os.PathLike) and Path(file).resolve() == path.resolve():
            raise PermissionError(13, "Permission denied", os.fspath(file))

    def open_checked(file, *args, **kwargs):
        check(file)
        return real_open(file, *args, **kwargs)

    def read_bytes_checked(self: Path) -> bytes:
        check(self)
        return real_read_bytes(self)

    monkeypatch.setattr(builtins, "open", open_checked)
    monkeypatch.setattr(Path, "read_bytes", read_bytes_checked)


@pytest.mark.parametrize("problem", ["missing", "directory", "unreadable"])
@pytest.mark.parametrize("command", sorted(READERS))
def test_a_bad_input_is_named_exits_1_and_leaves_nothing(tmp_path, capsys, monkeypatch,
                                                         command, problem):
    monkeypatch.chdir(tmp_path)
    name = "scan.npz" if command == "rebuild" else "scan.ply"
    (tmp_path / "out").mkdir()
    if problem == "directory":
        if command == "batch":  # a folder is an input batch searches
            pytest.skip("batch takes folders")
        (tmp_path / name).mkdir()
    elif problem == "unreadable":
        _closed(tmp_path / "scan.ply")
        if command == "rebuild":
            (tmp_path / "scan.ply").rename(tmp_path / name)
        _unreadable(monkeypatch, tmp_path / name)
    before = _files(tmp_path)
    code = main([command, name, *READERS[command]])
    captured = capsys.readouterr()
    err = _flat(captured.err)
    assert code == 1, captured
    assert "Traceback" not in captured.err
    expected = {"missing": "no such file", "directory": "is a directory",
                "unreadable": "permission denied"}[problem]
    assert _flat(f"{name}: {expected}") in err, captured.err
    after = _files(tmp_path)
    if command == "batch":  # its summary names the failed file; nothing else is written
        assert sorted(set(after) - set(before)) == ["out/summary.csv", "out/summary.json"]
    else:
        assert after == before


# ------------------------------------------------------------------- a mesh with no holes

@pytest.mark.parametrize(("command", "mesh", "said"), [
    ("fill", "closed", "closed.ply: nothing to fill (the mesh is closed: no holes)"),
    ("fill", "disk", "disk.ply: nothing to fill (no holes apart from the outer border)"),
    ("holes", "closed", "closed.ply: the mesh is closed: no holes"),
    ("report", "closed", "closed.ply: nothing to fill (the mesh is closed: no holes)"),
    ("report", "disk", "disk.ply: nothing to fill (no holes apart from the outer border)"),
])
def test_a_mesh_without_holes_is_named_with_why_and_exits_0(tmp_path, capsys, monkeypatch,
                                                            command, mesh, said):
    # before: `holes` printed an empty table and "The mesh is closed: no holes." without
    # the file's name; `report` said "no holes to fill (apart from the outer border)" of a
    # closed mesh too
    monkeypatch.chdir(tmp_path)
    path = (_closed if mesh == "closed" else _disk)(Path(f"{mesh}.ply"))
    # (report without -q: since session 38 its -q leaves out the notices, as fill's does)
    argv = {"fill": ["-o", "out.ply"], "holes": [], "report": ["-o", "report"]}[command]
    code = main([command, str(path), *argv])
    captured = capsys.readouterr()
    assert code == 0, captured
    printed = _flat(captured.out + captured.err)
    assert _flat(said) in printed, captured
    assert "┃hole┃" not in printed  # no table of nothing
    if command == "fill":
        assert Path("out.ply").is_file()  # the mesh written unchanged, as it says


# ---------------------------------------------------------- an output in a missing folder

@pytest.mark.parametrize("argv", [
    ["fill", "disk.ply", "-o", "nowhere/filled.ply"],
    ["fill", "disk.ply", "-o", "filled.ply", "--png", "nowhere/p.png"],
    ["fill", "disk.ply", "-o", "filled.ply", "--json", "nowhere/r.json"],
    ["represent", "disk.ply", "-o", "nowhere/rep.npz"],
    ["represent", "disk.ply", "-o", "rep.npz", "--png", "nowhere/rep.png"],
    ["represent", "disk.ply", "-o", "rep.npz", "--export", "nowhere/images.npz"],
    ["rebuild", "rep.npz", "-o", "nowhere/rebuilt.ply"],
], ids=lambda argv: "-".join(a.lstrip("-") for a in argv[::2]))
def test_an_output_in_a_missing_folder_is_named_before_any_work(tmp_path, capsys,
                                                                monkeypatch, argv):
    monkeypatch.chdir(tmp_path)
    _disk(Path("disk.ply"))
    before = _files(tmp_path)
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 1, err
    bad = next(a for a in argv if a.startswith("nowhere/"))
    assert _flat(f"'{bad}': directory 'nowhere' does not exist") in _flat(err), err
    assert _files(tmp_path) == before  # not the other outputs either


# ------------------------------------------- a broken mesh file: named, said, no traceback

def _obj(vertices, faces) -> str:
    return "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in vertices) + \
        "".join("f " + " ".join(str(i) for i in face) + "\n" for face in faces)


_SQUARE = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0)]
# (file name, content, what the message says after "NAME: ")
BROKEN = [
    ("empty.ply", "", "file is empty"),
    ("nan.obj", _obj([*_SQUARE[:3], (float("nan"), 0.0, 0.0)], [(1, 2, 3), (1, 3, 4)]),
     "1 vertex has NaN or infinite coordinates"),
    ("range.obj", _obj(_SQUARE, [(1, 2, 3), (1, 3, 9)]),
     "1 face uses vertex ids >= the vertex count 4"),
    ("cloud.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
     "y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
     "PLY file has no face element (a point cloud, not a mesh)"),
    ("fin.obj", _obj([*_SQUARE, (0.5, 0.5, 1.0), (0.5, 0.5, -1.0)],
                     [(1, 2, 3), (1, 3, 4), (1, 3, 5), (3, 1, 6)]), "1 non-manifold edges"),
    # session 38: "cannot read as OBJ: OverflowError: Python int too large to convert to C long"
    ("huge.obj", _obj(_SQUARE, [(1, 2, 99999999999999999999)]),
     "a face has an index beyond any vertex of the file (4 vertices): it does not fit in 64 "
     "bits"),
]


@pytest.mark.parametrize("command", ["holes", "fill", "report", "represent", "batch"])
@pytest.mark.parametrize(("name", "content", "said"), BROKEN, ids=[b[0] for b in BROKEN])
def test_a_broken_mesh_file_is_named_and_said_in_words(tmp_path, capsys, monkeypatch,
                                                       command, name, content, said):
    monkeypatch.chdir(tmp_path)
    Path(name).write_text(content)
    argv = {"holes": [], "fill": ["-o", "out.ply", "--method", "fair"],
            "report": ["-o", "report"], "represent": ["-o", "rep.npz"],
            "batch": ["-o", "out", "--jobs", "1"]}[command]
    code = main([command, name, *argv, "-q"])
    err = capsys.readouterr().err
    assert code == 1, err
    assert _flat(f"{name}: {said}") in _flat(err), err
    assert "Traceback" not in err and "Error:" not in err  # no Python exception's name
    assert not Path("out.ply").exists() and not Path("rep.npz").exists()


def test_faces_naming_texture_coordinates_a_file_lacks_are_a_warning(tmp_path, capsys):
    # session 38: "f 1/5 2/6 3/7" in an OBJ without vt records read silently
    path = tmp_path / "scan.obj"
    path.write_text(_obj(_SQUARE, []) + "f 1/5 2/6 3/7\nf 1 3 4\n")
    assert main(["fill", str(path), "-o", str(tmp_path / "out.obj"), "-q"]) == 0
    assert _flat("scan.obj: faces name vt records the file has none of: no uv is kept") in \
        _flat(capsys.readouterr().err)


def _batch_inputs_that_cannot_run(tmp_path: Path) -> dict[str, tuple[list[str], str]]:
    """Per case: batch's inputs, and the words its message must hold."""
    (tmp_path / "empty").mkdir()
    v, f = sphere(1)
    (tmp_path / "two").mkdir()
    write_mesh(tmp_path / "two" / "scan.ply", v, f[1:])
    write_mesh(tmp_path / "two" / "scan.obj", v, f[1:])
    return {"a folder with no mesh file": (["empty"], "empty: no mesh files there"),
            "two inputs drawn to one picture": (["two", "--png"], "would both be drawn to")}


@pytest.mark.parametrize("case", ["a folder with no mesh file",
                                  "two inputs drawn to one picture"])
def test_batch_inputs_that_cannot_run_are_said_in_words_before_any_file(tmp_path, capsys,
                                                                         monkeypatch, case):
    # session 38: these printed "error: ValueError: ...", as an unexpected failure would;
    # they are the user's inputs (errors.InputError), said as the other input problems are
    monkeypatch.chdir(tmp_path)
    inputs, expected = _batch_inputs_that_cannot_run(tmp_path)[case]
    before = _files(tmp_path)
    code = main(["batch", *inputs, "-o", "out", "-q"])
    err = capsys.readouterr().err
    assert code == 1, err
    assert _flat(expected) in _flat(err), err
    assert "ValueError" not in err and "Traceback" not in err, err
    assert _files(tmp_path) == before  # nothing written: no output folder, no summary


# ---------------------------------------- every warning printed for an input names it

DEGENERATE = "1 face uses the same vertex twice"


def _odd(path: Path) -> Path:
    """A wavy 10 × 10 grid with a hole in its middle and a face that repeats a vertex (a
    warning of the fill itself, which names no file)."""
    x, y = np.meshgrid(np.linspace(0, 1, 10), np.linspace(0, 1, 10))
    vertices = np.column_stack([x.ravel(), y.ravel(), 0.05 * np.sin(3 * x.ravel())])
    corner = (np.arange(9)[:, None] * 10 + np.arange(9)[None, :]).ravel()
    faces = np.vstack([np.column_stack([corner, corner + 1, corner + 11]),
                       np.column_stack([corner, corner + 11, corner + 10])])
    centre = vertices[faces].mean(axis=1)[:, :2]
    faces = np.vstack([faces[np.linalg.norm(centre - 0.5, axis=1) > 0.2], [[0, 1, 1]]])
    write_mesh(path, vertices, faces)
    return path


# the commands that print warnings of one input, on odd.ply (as given: ./odd.ply too), and
# the warning each must print once
NAMED_WARNINGS = {
    "fill": (["fill", "odd.ply", "-o", "out.ply", "--method", "fair"], DEGENERATE),
    "fill -q": (["fill", "odd.ply", "-o", "out.ply", "--method", "fair", "-q"], DEGENERATE),
    "fill ./": (["fill", "./odd.ply", "-o", "out.ply", "--method", "fair"], DEGENERATE),
    "holes": (["holes", "odd.ply"], DEGENERATE),
    "report": (["report", "odd.ply", "-o", "report"], DEGENERATE),
    "batch": (["batch", "odd.ply", "-o", "out", "--jobs", "1", "--method", "fair"],
              DEGENERATE),
    # a warning of the representation's own (unnamed), and a round trip that misses
    "represent": (["represent", "disk.ply", "-o", "rep.npz"], "a warning of the map"),
    "rebuild": (["rebuild", "rep.npz", "-o", "rebuilt.ply"],
                "against the stored original: missed by 9 %"),
}


@pytest.mark.parametrize("case", sorted(NAMED_WARNINGS))
def test_every_warning_printed_for_an_input_starts_with_its_name_once(tmp_path, capsys,
                                                                      monkeypatch, case):
    # session 39: `fill` printed the fill's own warnings (a degenerate face) without the
    # file's name, while `batch` and `holes` named it; `represent`/`rebuild` named none
    from surfinpaint.representation import represent as representation

    monkeypatch.chdir(tmp_path)
    _odd(tmp_path / "odd.ply")
    _disk(tmp_path / "disk.ply")
    if case == "rebuild":
        assert main(["represent", "disk.ply", "-o", "rep.npz", "-q"]) == 0

        class Missed:
            converged = False

            def summary(self) -> str:
                return "missed by 9 %"

        monkeypatch.setattr(representation, "round_trip", lambda rep, out: Missed())
    real = representation.represent

    def warning_represent(*args, **kwargs):
        warnings.warn("a warning of the map", UserWarning, stacklevel=2)
        return real(*args, **kwargs)

    monkeypatch.setattr(representation, "represent", warning_represent)
    capsys.readouterr()
    argv, expected = NAMED_WARNINGS[case]
    assert main(argv) == 0
    err = capsys.readouterr().err
    name = argv[1]
    warned = [line for line in err.splitlines() if line.startswith("warning:")]
    assert warned, err
    assert all(line.startswith(f"warning: {name}: ") for line in warned), warned
    assert sum(expected in line for line in warned) == 1, warned  # once, not twice
    assert f"{name}: {name}" not in err and "odd.ply: odd.ply" not in err


def test_the_python_apis_warning_is_a_warning_once_and_names_no_file(tmp_path):
    # the command line names the file; fill_holes, given arrays, warns in its category
    from surfinpaint.fill.pipeline import fill_holes
    from surfinpaint.io import MeshWarning
    from surfinpaint.io.formats import read_mesh

    vertices, faces = read_mesh(_odd(tmp_path / "odd.ply"))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fill_holes(vertices, faces, method="fair", jobs=1)
    said = [w for w in caught if DEGENERATE in str(w.message)]
    assert len(said) == 1 and issubclass(said[0].category, MeshWarning)
    assert str(said[0].message).startswith(DEGENERATE)


@pytest.mark.parametrize(("text", "source", "said"), [
    ("a face repeats", "scan.ply", "scan.ply: a face repeats"),
    ("scan.ply: a face repeats", "scan.ply", "scan.ply: a face repeats"),
    ("scan.ply: a face repeats", "./scan.ply", "scan.ply: a face repeats"),  # as Path says it
    ("./scan.ply: a face repeats", "./scan.ply", "./scan.ply: a face repeats"),
    ("scan.ply.bak: other", "scan.ply", "scan.ply: scan.ply.bak: other"),  # another file
    ("scanning done", "scan", "scan: scanning done"),  # a word, not the name
    ("a face repeats", None, "a face repeats"),
])
def test_named(text, source, said):
    from surfinpaint.app.progress import named

    assert named(text, source) == said
