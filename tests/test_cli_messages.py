"""What every command says, and leaves, for the inputs and outputs a user gets wrong most
(session 37): a missing or unreadable input, a mesh with no holes, an output in a folder
that does not exist. Each names the file, exits as the README says (1 for an error, 0 for
"nothing to fill"), and leaves nothing half-written."""

from __future__ import annotations

import os
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from conftest import mark_fill_starts

from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.errors import MeshError
from surfinpaint.io.formats import read_mesh, write_mesh


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
    ``open``, ``Path.open`` or ``Path.read_bytes``, is made to fail as it fails for other
    users)."""
    path.chmod(0)
    if os.geteuid() != 0:
        return
    import builtins

    real_open, real_read_bytes, real_path_open = builtins.open, Path.read_bytes, Path.open

    def check(file) -> None:
        if isinstance(file, str | os.PathLike) and Path(file).resolve() == path.resolve():
            raise PermissionError(13, "Permission denied", os.fspath(file))

    def open_checked(file, *args, **kwargs):
        check(file)
        return real_open(file, *args, **kwargs)

    def read_bytes_checked(self: Path) -> bytes:
        check(self)
        return real_read_bytes(self)

    def path_open_checked(self: Path, *args, **kwargs):
        check(self)
        return real_path_open(self, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", open_checked)
    monkeypatch.setattr(Path, "read_bytes", read_bytes_checked)
    monkeypatch.setattr(Path, "open", path_open_checked)


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
     "face 1 (line 6) uses vertex index 9, past the file's 4 vertices"),
    ("cloud.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float "
     "y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
     "PLY file has no face element (a point cloud, not a mesh)"),
    ("fin.obj", _obj([*_SQUARE, (0.5, 0.5, 1.0), (0.5, 0.5, -1.0)],
                     [(1, 2, 3), (1, 3, 4), (1, 3, 5), (3, 1, 6)]), "1 non-manifold edge ("),
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


# ------------------------- a warning that names another file: each file named once, clearly


def _with_materials(path: Path) -> Path:
    """``odd.ply``'s mesh (a hole, a face repeating a vertex) as an OBJ naming a material
    library beside it."""
    odd = _odd(path.with_name("odd-mesh.ply"))
    from surfinpaint.io.formats import read_mesh

    vertices, faces = read_mesh(odd, data_warning=False)
    write_mesh(path, vertices, faces)
    path.write_text(f"mtllib {path.stem}.mtl\n" + path.read_text())
    path.with_suffix(".mtl").write_text("newmtl skin\nKd 1 1 1\n")
    return path


def _coloured(path: Path) -> Path:
    """``odd.ply``'s mesh with a colour per vertex, which an STL cannot store."""
    from surfinpaint.io.formats import MeshData, read_mesh, write_mesh_data

    vertices, faces = read_mesh(_odd(path.with_name("odd-mesh.ply")), data_warning=False)
    write_mesh_data(path, MeshData(vertices, faces,
                                   {"color": np.full((len(vertices), 3), 200, np.uint8)}))
    return path


def _truth_with_lines(path: Path) -> Path:
    """The mesh ``odd.ply`` was cut from, as an OBJ with a line record (not kept: its
    reader warns, naming it)."""
    x, y = np.meshgrid(np.linspace(0, 1, 10), np.linspace(0, 1, 10))
    vertices = np.column_stack([x.ravel(), y.ravel(), 0.05 * np.sin(3 * x.ravel())])
    corner = (np.arange(9)[:, None] * 10 + np.arange(9)[None, :]).ravel()
    faces = np.vstack([np.column_stack([corner, corner + 1, corner + 11]),
                       np.column_stack([corner, corner + 11, corner + 10])])
    write_mesh(path, vertices, faces)
    path.write_text(path.read_text() + "l 1 2\n")
    return path


MATERIALS_KEPT = "out/scan.mtl exists with other content than"
# per case: the inputs made, the command, and the one warning line it must print for the
# other file (after "warning: "); session 40: each read "INPUT: OTHER: ..."
OTHER_FILE_WARNINGS = {
    "fill writing an OBJ whose materials differ": (
        ["fill", "scan.obj", "-o", "out/scan.obj"],
        f"scan.obj (writing out/scan.obj): {MATERIALS_KEPT} scan.mtl"),
    "fill writing an STL, which drops the colours": (
        ["fill", "col.ply", "-o", "out/col.stl"],
        "col.ply (writing out/col.stl): STL stores triangles only: per-vertex color not "
        "written"),
    # the input scan.obj filled into out/scan.obj, "scan.obj" in the output folder: its
    # materials' warning read as one of the input ("scan.obj: out/scan.mtl ...")
    "batch of a file named as its output": (
        ["batch", "scan.obj", "-o", "out", "--jobs", "1"],
        f"scan.obj (writing out/scan.obj): {MATERIALS_KEPT} scan.mtl"),
    "batch of a folder": (
        ["batch", "in", "-o", "out", "--jobs", "1"],
        f"in/scan.obj (writing out/scan.obj): {MATERIALS_KEPT} in/scan.mtl"),
    "report reading a truth": (
        ["report", "odd.ply", "--truth", "truth.obj", "-o", "report"],
        "odd.ply (reading truth.obj): OBJ records l (smoothing groups, lines, points, ...) "
        "are not kept"),
}


@pytest.mark.parametrize("case", sorted(OTHER_FILE_WARNINGS))
@pytest.mark.parametrize("quiet", [[], ["-q"]])
def test_a_warning_of_another_file_names_the_input_and_that_file_once(tmp_path, capsys,
                                                                       monkeypatch, case,
                                                                       quiet):
    monkeypatch.chdir(tmp_path)
    _odd(tmp_path / "odd.ply")
    _with_materials(tmp_path / "scan.obj")
    (tmp_path / "in").mkdir()
    _with_materials(tmp_path / "in" / "scan.obj")
    _coloured(tmp_path / "col.ply")
    _truth_with_lines(tmp_path / "truth.obj")
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "scan.mtl").write_text("newmtl mine\n")  # the user's: kept
    argv, expected = OTHER_FILE_WARNINGS[case]
    capsys.readouterr()
    assert main([*argv, "--method", "fair", *quiet] if argv[0] != "report"
                else [*argv, *quiet]) == 0
    warned = [line for line in capsys.readouterr().err.splitlines()
              if line.startswith("warning:")]
    said = [line for line in warned if expected in line]
    assert len(said) == 1 and said[0].startswith(f"warning: {expected}"), warned
    name = argv[1]
    # every warning starts with the input's name, and none names a file twice in a row
    assert all(line.startswith(f"warning: {name}") for line in warned), warned
    assert not any(f"{other}: " in line.split(")", 1)[0] for line in warned
                   for other in ("out/", "truth.obj")), warned


@pytest.mark.parametrize(("text", "other_files", "said"), [
    ("out/scan.obj: its .mtl differs", {"out/scan.obj": "writing"},
     "scan.obj (writing out/scan.obj): its .mtl differs"),
    ("out/scan.obj: x", {"./out/scan.obj": "writing"}, "scan.obj (writing out/scan.obj): x"),
    ("truth.ply: x", {"truth.ply": "reading"}, "scan.obj (reading truth.ply): x"),
    ("scan.obj: x", {"scan.obj": "writing"}, "scan.obj: x"),  # --in-place: the input first
    ("out/scan.obj.bak: x", {"out/scan.obj": "writing"}, "scan.obj: out/scan.obj.bak: x"),
    ("hole 2: x", {"out/scan.obj": "writing"}, "scan.obj: hole 2: x"),
])
def test_named_with_other_files(text, other_files, said):
    from surfinpaint.app.progress import named

    assert named(text, "scan.obj", other_files) == said
    assert named(text, None, other_files) == text  # no input: the text as it is


# ------------------------------------------------ a batch of many files, a few of them bad

# per bad file: how it is made, and the reason its error line must give
BAD_FILES = {
    "unreadable.ply": (lambda path, v, f: path.write_bytes(b"ply\nformat garbage\n\x00\x01"),
                       "PLY header has no 'end_header' line"),
    "empty.ply": (lambda path, v, f: path.write_bytes(b""), "file is empty"),
    "no-faces.obj": (lambda path, v, f: path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
                     "OBJ file has no faces"),
    "non-manifold.ply": (lambda path, v, f: write_mesh(
        path, np.vstack([v, [[0.0, 0.0, 3.0]]]),
        np.vstack([f, [[f[0, 0], f[0, 1], len(v)]]])), "1 non-manifold edge ("),
}


@pytest.mark.parametrize("quiet", [[], ["-q"], ["-qq"]])
def test_a_batch_names_each_bad_file_writes_the_others_and_ends_with_the_count(
        tmp_path, capsys, monkeypatch, quiet):
    # session 40: what a lab sees when a few files of many are bad; with -q or -qq the run
    # ended with the bad files' lines and no count (the summary line is a report line)
    from surfinpaint.app.batch import read_summary
    from surfinpaint.geometry.cutting import cut_geodesic_disk

    monkeypatch.chdir(tmp_path)
    v, f = sphere(1)
    cut = cut_geodesic_disk(v, f, 0, 0.6)
    good = [Path("scans") / f"subject{k}" / "scan.ply" for k in range(8)]
    for path in good:
        path.parent.mkdir(parents=True)
        write_mesh(path, cut.vertices, cut.faces)
    for name, (make, _) in BAD_FILES.items():
        make(Path("scans") / name, cut.vertices, cut.faces)
    capsys.readouterr()
    code = main(["batch", "scans", "-o", "out", "--jobs", "1", "--method", "fair", *quiet])
    lines = capsys.readouterr().err.splitlines()
    assert code == 1, lines
    errors = [line for line in lines if line.startswith("error: ")]
    for name, (_, reason) in BAD_FILES.items():  # one line each, naming it and why
        (said,) = [line for line in errors if f"scans/{name}" in line]
        assert said.startswith(f"error: scans/{name}: ") and reason in said, said
    assert all((Path("out") / path.relative_to("scans")).is_file() for path in good)
    rows = read_summary(Path("out"))
    assert sorted(r.status for r in rows) == ["failed"] * 4 + ["filled"] * 8
    total = len(good) + len(BAD_FILES)
    if quiet:
        assert lines[-1] == f"error: 4 of {total} files failed (each named above; all in " \
            "out/summary.csv)", lines
        assert len(errors) == 5 and not [line for line in lines if line not in errors]
    else:
        assert lines[-1] == f"{total} files: 8 filled, 0 unfilled, 0 closed, 4 failed, 0 " \
            "skipped; wrote out/summary.csv and summary.json", lines
        assert len(errors) == 4


def _bad_first_batch(root: Path) -> tuple[Path, list[Path]]:
    """A folder of three good files and a bad one that the batch starts first: the largest
    (the files are started costliest first, by size on a first run). Its header is a PLY's
    (the pre-flight passes it), its body is not: it fails as it is filled."""
    from surfinpaint.geometry.cutting import cut_geodesic_disk

    v, f = sphere(1)
    cut = cut_geodesic_disk(v, f, 0, 0.6)
    good = [root / f"good{k}.ply" for k in range(3)]
    for path in good:
        write_mesh(path, cut.vertices, cut.faces)
    bad = root / "bad.ply"
    bad.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float "
                    b"x\nproperty float y\nproperty float z\nelement face 1\nproperty list "
                    b"uchar int vertex_indices\nend_header\n"
                    + b"\x00" * (4 * max(p.stat().st_size for p in good)))
    return bad, good


# rich's colours, and its cursor moves and line erasures, which redraw the bar in a terminal
_COLOUR, _CONTROL = r"\x1b\[[0-9;]*m", r"\x1b\[[0-9;?]*[A-Za-z]|\r"


@pytest.mark.parametrize("quiet", [[], ["-q"], ["-qq"]])
def test_a_batch_says_a_bad_file_when_it_fails_not_at_the_end(tmp_path, capsys, monkeypatch,
                                                               quiet):
    # session 40: the error lines came only when the whole run ended. The bad file is
    # started first; each file's start is marked on stderr, so its error line must come
    # before the last good file starts. Without -q, stderr is made a terminal (rich redraws
    # its bar there): the error line must come out whole, above the bar
    import re

    from surfinpaint.app import batch

    monkeypatch.chdir(tmp_path)
    Path("scans").mkdir()
    bad, good = _bad_first_batch(Path("scans"))
    mark_fill_starts(monkeypatch, batch,
                     lambda job: sys.stderr.write(f"\nstarting {job.name}\n"))
    if not quiet:
        monkeypatch.setenv("TTY_COMPATIBLE", "1")
        monkeypatch.setenv("COLUMNS", "200")
    capsys.readouterr()
    code = main(["batch", "scans", "-o", "out", "--jobs", "1", "--method", "fair", *quiet])
    text = capsys.readouterr().err
    plain = re.sub(_CONTROL, "\n", re.sub(_COLOUR, "", text))
    lines = [line for line in plain.splitlines() if line.strip()]
    assert code == 1, text
    with pytest.raises(MeshError) as unread:
        read_mesh(bad)
    error = f"error: {unread.value}"
    assert error.startswith("error: scans/bad.ply: trailing data: ")
    assert lines.count(error) == 1, lines
    starts = [lines.index(f"starting scans/{p.name}") for p in [bad, *good]]
    assert starts[0] < lines.index(error) < max(starts[1:]), lines
    assert sorted(r.status for r in batch.read_summary(Path("out"))) == \
        ["failed"] + ["filled"] * 3
    said = [line for line in lines if not line.startswith("starting ")]
    if quiet:  # the error, and the count at the end, as before
        assert said == [error, "error: 1 of 4 files failed (each named above; all in "
                        "out/summary.csv)"], lines
    else:
        assert said[-1] == "4 files: 3 filled, 0 unfilled, 0 closed, 1 failed, 0 skipped; " \
            "wrote out/summary.csv and summary.json", lines
