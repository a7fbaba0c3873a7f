"""An OBJ's material library (``mtllib``) and the textures it names go with the filled OBJ:
``fill`` and ``batch`` copy them beside the output (atomically, the inputs untouched), keep
an existing file of other content (with a warning), and write nothing outside the output's
folder (session 35)."""

from __future__ import annotations

import hashlib
import json
import os
import warnings
from pathlib import Path

import pytest

from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.io.base import MeshWarning
from surfinpaint.io.materials import copy_materials, material_files, recorded_copies

TEXTURE = b"\x89PNG\r\n\x1a\n not a real picture"


def _textured_scan(folder: Path, library: str = "scan.mtl",
                   texture: str = "textures/skin tex.png") -> Path:
    """A sphere with a hole as an OBJ naming ``library``, which names ``texture`` (with
    options before it, and a space in its name)."""
    v, f = sphere(1)
    cut = cut_holes(v, f, [0], [2.5 * mean_edge_length(v, f)])
    folder.mkdir(parents=True, exist_ok=True)
    lines = [f"mtllib {library}", *(f"v {x!r} {y!r} {z!r}" for x, y, z in cut.vertices.tolist()),
             "usemtl skin", *("f " + " ".join(str(i + 1) for i in row) for row in cut.faces)]
    (folder / "scan.obj").write_text("\n".join(lines) + "\n")
    if not library.startswith(".."):
        (folder / library).write_text(f"newmtl skin\nKd 1 1 1\nmap_Kd -s 1 1 1 {texture}\n")
        (folder / texture).parent.mkdir(parents=True, exist_ok=True)
        (folder / texture).write_bytes(TEXTURE)
    return folder / "scan.obj"


def _snapshot(folder: Path) -> dict[str, tuple[bytes, int]]:
    return {str(p.relative_to(folder)): (p.read_bytes(), p.stat().st_mtime_ns)
            for p in sorted(folder.rglob("*")) if p.is_file()}


def _run(command: str, source: Path, out: Path) -> tuple[int, Path]:
    """``fill`` into ``out/filled.obj``, or ``batch`` of the input's folder into ``out``."""
    if command == "fill":
        out.mkdir(parents=True, exist_ok=True)
        return main(["fill", str(source), "-o", str(out / "filled.obj"), "--method", "fair",
                     "-q"]), out / "filled.obj"
    return main(["batch", str(source.parent), "-o", str(out), "--method", "fair", "--jobs",
                 "1", "-q"]), out / source.name


@pytest.mark.parametrize("command", ["fill", "batch"])
def test_the_material_library_and_its_textures_go_beside_the_output(tmp_path, capsys,
                                                                     command):
    source = _textured_scan(tmp_path / "in")
    before = _snapshot(tmp_path / "in")
    code, output = _run(command, source, tmp_path / "out")
    err = capsys.readouterr().err
    assert code == 0, err
    assert "not beside the output" not in err and "not copied" not in err
    assert output.read_text().splitlines()[1] == "mtllib scan.mtl"
    folder = output.parent
    assert (folder / "scan.mtl").read_bytes() == (tmp_path / "in" / "scan.mtl").read_bytes()
    assert (folder / "textures" / "skin tex.png").read_bytes() == TEXTURE
    assert _snapshot(tmp_path / "in") == before  # inputs untouched
    assert not list(folder.rglob(".*.tmp"))  # the atomic writer left nothing behind
    if command == "batch":
        (row,) = json.loads((folder / "summary.json").read_text())["files"]
        assert row["status"] == "filled" and "material" not in row["message"]


@pytest.mark.parametrize("command", ["fill", "batch"])
def test_an_existing_material_file_of_other_content_is_kept_with_a_warning(tmp_path, capsys,
                                                                          command):
    source = _textured_scan(tmp_path / "in")
    out = tmp_path / "out"
    out.mkdir()
    (out / "scan.mtl").write_text("newmtl other\n")  # someone else's, not to be replaced
    (out / "textures").mkdir()
    (out / "textures" / "skin tex.png").write_bytes(TEXTURE)  # the same: left alone
    stamp = (out / "textures" / "skin tex.png").stat().st_mtime_ns
    code, _ = _run(command, source, out)
    err = "".join(capsys.readouterr().err.split())
    assert code == 0
    assert (out / "scan.mtl").read_text() == "newmtl other\n"
    assert "scan.mtlexistswithothercontent" in err and "kept,notreplaced" in err
    assert (out / "textures" / "skin tex.png").stat().st_mtime_ns == stamp


def test_nothing_is_written_outside_the_output_folder_nor_copied_onto_itself(tmp_path):
    # a library named above the OBJ's folder: not copied (it would land outside the output's)
    source = _textured_scan(tmp_path / "a" / "in", library="../shared.mtl")
    (tmp_path / "a" / "shared.mtl").write_text("newmtl skin\n")
    (tmp_path / "b" / "out").mkdir(parents=True)
    with pytest.warns(MeshWarning, match="'../shared.mtl' is outside the input's folder"):
        assert copy_materials(source, tmp_path / "b" / "out" / "x.obj", "../shared.mtl") == []
    assert not (tmp_path / "b" / "shared.mtl").exists()
    # the output beside the input: the files are already there, nothing is written
    source = _textured_scan(tmp_path / "c")
    before = _snapshot(tmp_path / "c")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert copy_materials(source, tmp_path / "c" / "filled.obj", "scan.mtl") == []
    assert _snapshot(tmp_path / "c") == before
    # another format has no use for them; another output's name is not taken
    assert copy_materials(source, tmp_path / "b" / "x.ply", "scan.mtl") == []
    with pytest.warns(MeshWarning, match="another output takes its name"):
        written = copy_materials(source, tmp_path / "b" / "x.obj", "scan.mtl",
                                 reserved=(tmp_path / "b" / "scan.mtl",))
    assert written == [tmp_path / "b" / "textures" / "skin tex.png"]
    assert not (tmp_path / "b" / "scan.mtl").exists()


@pytest.mark.parametrize(("statement", "expected"), [
    ("map_Kd skin.png", ["skin.png"]),
    ("map_Kd -s 1 1 1 -o 0 0 0 skin.png", ["skin.png"]),
    ("map_Kd -s 1 1 1 skin tex.png", ["skin tex.png"]),   # a name with a space, found
    ("bump -bm 0.5 skin.png", ["skin.png"]),
    ("norm maps\\skin.png", ["maps/skin.png"]),            # Windows separators
    ("Kd 1 1 1", []),
])
def test_the_textures_a_material_library_names(tmp_path, statement, expected):
    (tmp_path / "maps").mkdir()
    for name in ("skin.png", "skin tex.png", "maps/skin.png"):
        (tmp_path / name).write_bytes(TEXTURE)
    (tmp_path / "m.mtl").write_text(f"newmtl skin\n{statement}\n")
    found, notes = material_files(tmp_path / "scan.obj", "m.mtl")
    assert [str(p) for p in found] == ["m.mtl", *expected] and notes == []


def test_one_mtllib_statement_may_name_several_libraries(tmp_path):
    (tmp_path / "a.mtl").write_text("newmtl a\nmap_Kd a.png\n")
    (tmp_path / "b.mtl").write_text("newmtl b\n")
    (tmp_path / "a.png").write_bytes(TEXTURE)
    (tmp_path / "my skin.mtl").write_text("newmtl c\n")
    found, notes = material_files(tmp_path / "scan.obj", "a.mtl b.mtl\nmy skin.mtl")
    assert [str(p) for p in found] == ["a.mtl", "a.png", "b.mtl", "my skin.mtl"]
    assert notes == []


def _later(path: Path, than: Path) -> None:
    """Give ``path`` an mtime a second after ``than``'s (as an edit made later)."""
    when = than.stat().st_mtime_ns + 10**9
    os.utime(path, ns=(when, when))


def _mesh_lines(obj: Path) -> list[bytes]:
    """The OBJ's lines but its record of copied material files (rewritten by a rerun that
    copies them again, the mesh itself not refilled)."""
    return [line for line in obj.read_bytes().splitlines()
            if not line.startswith(b"# surfinpaint copied ")]


def _sha1(path: Path) -> str:
    return hashlib.sha1(path.read_bytes()).hexdigest()


def _summary_row(out: Path) -> dict:
    (row,) = json.loads((out / "summary.json").read_text())["files"]
    return row


def test_a_batch_rerun_copies_a_changed_texture_and_library_again(tmp_path, capsys):
    # session 36: a rerun skipped the file (its mesh unchanged), and --overwrite kept the
    # copies an earlier run wrote, with a warning: the output kept the old texture and .mtl.
    # Session 37: the changed files are copied again without refilling the mesh (the fill
    # does not read them; a lab recolouring thousands of scans' textures paid a fill each)
    source = _textured_scan(tmp_path / "in")
    code, output = _run("batch", source, tmp_path / "out")
    assert code == 0
    filled = _mesh_lines(output)
    row = _summary_row(tmp_path / "out")
    assert row["status"] == "filled"
    assert sorted(row["materials"]) == ["scan.mtl", "textures/skin tex.png"]
    assert "materials" not in (tmp_path / "out" / "summary.csv").read_text().splitlines()[0]
    texture = tmp_path / "in" / "textures" / "skin tex.png"
    texture.write_bytes(TEXTURE + b" colour-corrected")
    _later(texture, output)
    assert _run("batch", source, tmp_path / "out")[0] == 0
    assert (tmp_path / "out" / "textures" / "skin tex.png").read_bytes() == texture.read_bytes()
    assert "other content" not in capsys.readouterr().err
    assert _mesh_lines(output) == filled  # not refilled
    row = _summary_row(tmp_path / "out")
    assert row["status"] == "skipped" and row["holes_filled"] == 1  # the fill's counts kept
    assert "its materials changed beside the input (textures/skin tex.png): copied again " \
        "(textures/skin tex.png), the mesh not refilled" in row["message"]
    # the .mtl too (it names a new texture: that is copied as well)
    library = tmp_path / "in" / "scan.mtl"
    library.write_text("newmtl skin\nKd 1 1 1\nmap_Kd new.png\n")
    (tmp_path / "in" / "new.png").write_bytes(TEXTURE)
    _later(library, output)
    assert _run("batch", source, tmp_path / "out")[0] == 0
    assert (tmp_path / "out" / "scan.mtl").read_text() == library.read_text()
    assert (tmp_path / "out" / "new.png").read_bytes() == TEXTURE
    assert _mesh_lines(output) == filled
    assert _summary_row(tmp_path / "out")["status"] == "skipped"
    # touched, not changed (a sync tool's copy): nothing copied, the record kept
    _later(texture, output)
    assert _run("batch", source, tmp_path / "out")[0] == 0
    row = _summary_row(tmp_path / "out")
    assert row["status"] == "skipped" and "copied again" not in row["message"]
    assert sorted(row["materials"]) == ["new.png", "scan.mtl"]
    # a copy deleted beside the output is copied again too
    (tmp_path / "out" / "new.png").unlink()
    assert _run("batch", source, tmp_path / "out")[0] == 0
    assert (tmp_path / "out" / "new.png").read_bytes() == TEXTURE
    assert _mesh_lines(output) == filled
    assert "its materials missing beside the output (new.png): copied again (new.png), the " \
        "mesh not refilled" in _summary_row(tmp_path / "out")["message"]
    # nothing changed: skipped, the record kept for the next change
    for path in (library, texture, tmp_path / "in" / "new.png", source):
        earlier = output.stat().st_mtime_ns - 10**9  # _later's times may lie ahead
        os.utime(path, ns=(earlier, earlier))
    assert _run("batch", source, tmp_path / "out")[0] == 0
    (row,) = json.loads((tmp_path / "out" / "summary.json").read_text())["files"]
    assert row["status"] == "skipped" and sorted(row["materials"]) == ["new.png", "scan.mtl"]


def test_a_batch_rerun_that_copies_materials_again_rewrites_the_objs_record(tmp_path,
                                                                            capsys):
    # session 38: the rerun copied the changed texture but left the OBJ's header record
    # (written by the fill) at the first copy's SHA-1; a later `fill` into that OBJ then took
    # the new copy for the user's own and kept it, with a warning, after the texture
    # changed again
    source = _textured_scan(tmp_path / "in")
    code, output = _run("batch", source, tmp_path / "out")
    assert code == 0
    filled = _mesh_lines(output)
    texture = tmp_path / "in" / "textures" / "skin tex.png"
    copy = tmp_path / "out" / "textures" / "skin tex.png"
    texture.write_bytes(TEXTURE + b" colour-corrected")
    _later(texture, output)
    assert _run("batch", source, tmp_path / "out")[0] == 0
    assert copy.read_bytes() == texture.read_bytes()
    record = {"scan.mtl": _sha1(tmp_path / "in" / "scan.mtl"),
              "textures/skin tex.png": _sha1(texture)}
    assert recorded_copies(output) == record == _summary_row(tmp_path / "out")["materials"]
    assert _mesh_lines(output) == filled  # the record rewritten, the mesh not refilled
    assert not list((tmp_path / "out").rglob(".*.tmp"))  # through the atomic writer
    # a rerun with nothing changed leaves the OBJ as it is
    stamp = output.stat().st_mtime_ns
    assert _run("batch", source, tmp_path / "out")[0] == 0
    assert output.stat().st_mtime_ns == stamp
    # the texture changes again: a fill into the same OBJ replaces the copy, unwarned
    texture.write_bytes(TEXTURE + b" recoloured again")
    capsys.readouterr()
    assert main(["fill", str(source), "-o", str(output), "--method", "fair", "-q"]) == 0
    assert "other content" not in capsys.readouterr().err
    assert copy.read_bytes() == texture.read_bytes()


def test_a_batch_rerun_keeps_a_copy_the_user_changed_with_a_warning(tmp_path, capsys,
                                                                     monkeypatch):
    monkeypatch.chdir(tmp_path)  # the input named relative, as the messages name files
    source = _textured_scan(Path("in"))
    code, output = _run("batch", source, Path("out"))
    assert code == 0
    mine = tmp_path / "out" / "scan.mtl"
    mine.write_text("newmtl skin\nKd 0.5 0.5 0.5\n")  # the user's own edit of the copy
    library = tmp_path / "in" / "scan.mtl"
    library.write_text(library.read_text() + "Ks 0 0 0\n")
    _later(library, mine)
    capsys.readouterr()
    assert _run("batch", source, Path("out"))[0] == 0
    assert mine.read_text() == "newmtl skin\nKd 0.5 0.5 0.5\n"  # kept
    (row,) = json.loads((tmp_path / "out" / "summary.json").read_text())["files"]
    assert row["status"] == "skipped"  # the mesh not refilled: only its .mtl changed
    kept = "out/scan.mtl exists with other content than in/scan.mtl: kept, not replaced " \
        "(changed since an earlier run copied it)"
    assert kept in row["message"]
    err = capsys.readouterr().err
    assert kept in err  # a warning, though the file was skipped
    # naming the input, then the output it is of, each once (session 40: "in/scan.obj:
    # scan.obj: out/scan.mtl ...")
    assert f"warning: in/scan.obj (writing out/scan.obj): {kept}" in " ".join(err.split())
    assert str(tmp_path) not in row["message"]  # named as given, not by absolute paths
    assert "scan.mtl" not in row["materials"]  # not ours any more: never replaced later


def test_a_fill_rerun_copies_a_changed_library_again_unless_the_user_changed_the_copy(
        tmp_path, capsys, monkeypatch):
    # fill kept no record of its copies (batch keeps one in its summary): a rerun after the
    # .mtl changed kept the stale copy, with a warning. Now the OBJ written records its
    # copies in its header, and a rerun into it replaces a copy that is still its own
    monkeypatch.chdir(tmp_path)
    source = _textured_scan(Path("in"))
    code, output = _run("fill", source, Path("out"))
    assert code == 0
    header = output.read_text().splitlines()[:4]
    assert header[1] == "mtllib scan.mtl"
    assert sorted(header[2:]) == sorted(
        f"# surfinpaint copied {hashlib.sha1(p.read_bytes()).hexdigest()} {name}"
        for name, p in (("scan.mtl", Path("in/scan.mtl")),
                        ("textures/skin tex.png", Path("in/textures/skin tex.png"))))
    library, texture = Path("in/scan.mtl"), Path("in/textures/skin tex.png")
    library.write_text("newmtl skin\nKd 0.9 0.8 0.7\nmap_Kd -s 1 1 1 textures/skin tex.png\n")
    texture.write_bytes(TEXTURE + b" colour-corrected")
    capsys.readouterr()
    assert _run("fill", source, Path("out"))[0] == 0
    assert "other content" not in capsys.readouterr().err
    assert Path("out/scan.mtl").read_text() == library.read_text()
    assert Path("out/textures/skin tex.png").read_bytes() == texture.read_bytes()
    # the user's own edit of the copy is kept, and the warning says what to do
    Path("out/scan.mtl").write_text("newmtl skin\nKd 0.5 0.5 0.5\n")
    library.write_text(library.read_text() + "Ks 0 0 0\n")
    assert _run("fill", source, Path("out"))[0] == 0
    err = " ".join(capsys.readouterr().err.split())
    assert Path("out/scan.mtl").read_text() == "newmtl skin\nKd 0.5 0.5 0.5\n"
    assert "out/scan.mtl exists with other content than in/scan.mtl: kept, not replaced " \
        "(changed since an earlier run copied it); the output's materials may differ from " \
        "the input's: to use the input's, copy in/scan.mtl over it" in err
    # no longer recorded: never replaced later
    assert sorted(recorded_copies(output)) == ["textures/skin tex.png"]
    # an OBJ another program wrote over the output carries no record: kept, and said why
    output.write_text(source.read_text())
    library.write_text(library.read_text() + "Ns 10\n")
    Path("out/scan.mtl").write_text("newmtl skin\n")
    assert _run("fill", source, Path("out"))[0] == 0
    assert "(no earlier run recorded writing it); the output's materials may differ" in \
        " ".join(capsys.readouterr().err.split())
