"""``surfinpaint batch --png`` (``fill_files(png=True)``): a before/after picture beside
every output, drawn in the worker that filled it; named in the summary; part of what a
rerun checks is up to date; a picture that fails leaves the mesh written and says why."""

from __future__ import annotations

import csv
import json
import multiprocessing
from pathlib import Path

import pytest
from test_batch import FAIR, _holey

import surfinpaint.app.batch as batch
from surfinpaint.app.batch import fill_files, find_inputs, read_summary
from surfinpaint.app.batch_inputs import picture_path
from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.io.formats import write_mesh

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def _folder(root: Path) -> Path:
    """Two spheres with holes (one nested), a closed one and a corrupt file."""
    folder = root / "scans"
    (folder / "sub").mkdir(parents=True)
    write_mesh(folder / "a.ply", *_holey(*sphere(2), 1))
    write_mesh(folder / "sub" / "b.obj", *_holey(*sphere(2), 2))
    write_mesh(folder / "sub" / "closed.off", *sphere(1))
    (folder / "sub" / "corrupt.ply").write_bytes(b"ply\nformat binary_little_endian 1.0\n"
                                                 b"element vertex 9\n" + bytes(50))
    return folder


PICTURES = {"a.ply": "a.png", "sub/b.obj": "sub/b.png", "sub/closed.off": "sub/closed.png"}


def _check_pictures(out: Path, rows, pictures=PICTURES) -> None:
    """A PNG beside every output written, named by its row; none for the failed file and
    no temporary file anywhere."""
    by_output = {row.output: row for row in rows}
    for output, picture in pictures.items():
        assert (out / output).is_file()
        data = (out / picture).read_bytes()
        assert data.startswith(PNG_MAGIC) and len(data) > 1000
        assert by_output[output].picture == picture
    assert by_output["sub/corrupt.ply"].status == "failed"
    assert by_output["sub/corrupt.ply"].picture is None
    written = {p.relative_to(out).as_posix() for p in out.rglob("*.png")}
    assert written == set(pictures.values())
    assert [p for p in out.rglob(".*")] == []


@pytest.mark.parametrize("method", ["fork", "spawn"])
def test_png_draws_one_picture_beside_each_output_in_the_workers(tmp_path, monkeypatch,
                                                                  method):
    if method not in multiprocessing.get_all_start_methods():
        pytest.skip(f"no {method} here")
    monkeypatch.setattr(batch, "start_context",
                        lambda preload: multiprocessing.get_context(method))
    out = tmp_path / "out"
    rows = fill_files([_folder(tmp_path)], out, jobs=2, png=True, **FAIR)
    assert [r.status for r in rows] == ["filled", "filled", "closed", "failed"]
    _check_pictures(out, rows)
    assert read_summary(out) == rows
    with open(out / "summary.csv", newline="") as handle:
        table = {t["output"]: t["picture"] for t in csv.DictReader(handle)}
    assert table == {**PICTURES, "sub/corrupt.ply": ""}
    files = json.loads((out / "summary.json").read_text())["files"]
    assert {f["output"]: f["picture"] for f in files} == {**PICTURES, "sub/corrupt.ply": None}


def test_without_png_no_picture_is_drawn(tmp_path):
    out = tmp_path / "out"
    rows = fill_files([_folder(tmp_path)], out, jobs=1, **FAIR)
    assert list(out.rglob("*.png")) == []
    assert all(r.picture is None for r in rows)


def test_a_rerun_skips_what_is_up_to_date_and_draws_a_missing_picture(tmp_path):
    scans = _folder(tmp_path)
    out = tmp_path / "out"
    fill_files([scans], out, jobs=1, **FAIR)  # no pictures: with png, none is up to date
    first = fill_files([scans], out, jobs=1, png=True, **FAIR)
    assert [r.status for r in first] == ["filled", "filled", "closed", "failed"]
    _check_pictures(out, first)
    stamps = {p: p.stat().st_mtime_ns for p in out.rglob("*.*") if "summary" not in p.name}
    again = fill_files([scans], out, jobs=1, png=True, **FAIR)
    assert [r.status for r in again] == ["skipped", "skipped", "skipped", "failed"]
    _check_pictures(out, again)
    assert {p: p.stat().st_mtime_ns for p in stamps} == stamps
    # a missing picture (and what a killed worker left) makes its file filled again
    (out / "sub" / "b.png").unlink()
    (out / "sub" / ".b.png.0123abcd.png").write_bytes(PNG_MAGIC)
    third = fill_files([scans], out, jobs=1, png=True, **FAIR)
    assert [r.status for r in third] == ["skipped", "filled", "skipped", "failed"]
    _check_pictures(out, third)
    assert (out / "a.png").stat().st_mtime_ns == stamps[out / "a.png"]
    # without png a rerun asks for no picture, and names those an earlier run wrote
    fourth = fill_files([scans], out, jobs=1, **FAIR)
    assert [r.picture for r in fourth] == [*PICTURES.values(), None]
    (out / "a.png").unlink()
    assert fill_files([scans], out, jobs=1, **FAIR)[0].picture is None


def test_a_picture_that_fails_leaves_the_mesh_written_and_says_why(tmp_path, monkeypatch,
                                                                    capsys):
    from matplotlib.figure import Figure

    def half_written(self, path, **kwargs):  # the renderer fails in the middle of the file
        Path(path).write_bytes(PNG_MAGIC)
        raise OSError("No space left on device")

    monkeypatch.setattr(Figure, "savefig", half_written)
    scans = _folder(tmp_path)
    out = tmp_path / "out"
    # a warning, not a failed file: the exit code counts the failed files (the corrupt one)
    assert main(["batch", str(scans / "a.ply"), str(scans / "sub"), "-o", str(out),
                 "--jobs", "1", "--png", "--method", "fair"]) == 1
    err = capsys.readouterr().err
    # the input named, then the picture it was writing (session 40: "a.ply: a.png: ...")
    assert f"warning: {scans / 'a.ply'} (writing {out / 'a.png'}): picture not drawn: " \
        "OSError: No space left" in err, err
    assert "1 failed" in err and "2 filled" in err
    rows = read_summary(out)
    assert [r.status for r in rows] == ["filled", "filled", "closed", "failed"]
    for row in rows[:3]:
        assert (out / row.output).is_file() and row.picture is None
        assert f"{picture_path(Path(row.output)).as_posix()}: picture not drawn" \
            in row.message
    assert list(out.rglob("*.png")) == [] and list(out.rglob(".*")) == []
    # only those files' failure: exit 0 without the corrupt file; -q prints the pictures'
    # warnings and nothing else, -qq nothing
    good = [str(scans / "a.ply"), str(scans / "sub" / "b.obj")]
    assert main(["batch", *good, "-o", str(out / "good"), "--jobs", "1", "--png",
                 "--method", "fair", "-q"]) == 0
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 2 and all(line.startswith("warning: ") and "picture not drawn" in line
                                   for line in lines)
    assert main(["batch", *good, "-o", str(out / "quieter"), "--jobs", "1", "--png",
                 "--method", "fair", "-qq"]) == 0
    assert capsys.readouterr().err == ""
    assert (out / "good" / "b.obj").is_file() and not (out / "good" / "b.png").exists()
    # a rerun draws them once the renderer works
    monkeypatch.undo()
    assert main(["batch", *good, "-o", str(out / "good"), "--jobs", "1", "--png",
                 "--method", "fair", "-q"]) == 0
    assert (out / "good" / "b.png").read_bytes().startswith(PNG_MAGIC)


def test_the_picture_is_named_after_the_output_and_never_shared(tmp_path):
    out = tmp_path / "out"
    assert picture_path(out / "sub" / "scan.ply") == out / "sub" / "scan.png"
    assert picture_path(out / "lh.pial.gii.gz") == out / "lh.pial.png"
    assert picture_path(out / "SCAN.STL") == out / "SCAN.png"
    assert picture_path(out / "lh.pial") == out / "lh.pial.png"  # not lh.png: lh.white's
    v, f = sphere(1)
    for name in ("scan.ply", "scan.obj"):
        write_mesh(tmp_path / name, v, f)
    inputs = [tmp_path / "scan.ply", tmp_path / "scan.obj"]
    assert [j.picture for j in find_inputs(inputs, out)] == [None, None]
    with pytest.raises(ValueError, match="both be drawn to"):
        find_inputs(inputs, out, png=True)
    assert main(["batch", *map(str, inputs), "-o", str(out), "--png"]) == 1
    assert not out.exists()


def test_a_dask_cluster_draws_the_pictures_too(tmp_path):
    distributed = pytest.importorskip("distributed")
    out = tmp_path / "out"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as client:
        rows = fill_files([_folder(tmp_path)], out, client=client, png=True, **FAIR)
    _check_pictures(out, rows)
    assert all(r.seconds > 0 for r in rows)


def test_fill_png_that_fails_is_a_warning_as_in_a_batch(tmp_path, monkeypatch, capsys):
    # session 45: `fill --png` ended in a traceback and exit 1 after writing the mesh and
    # its report, where `batch --png` says the same failure in a warning
    from matplotlib.figure import Figure

    def fails(self, path, **kwargs):
        raise OSError("No space left on device")

    monkeypatch.setattr(Figure, "savefig", fails)
    mesh, out, png = tmp_path / "a.ply", tmp_path / "out.ply", tmp_path / "a.png"
    write_mesh(mesh, *_holey(*sphere(2), 1))
    assert main(["fill", str(mesh), "-o", str(out), "--png", str(png), "--method", "fair",
                 "--json", str(tmp_path / "a.json")]) == 0
    err = capsys.readouterr().err
    assert f"warning: {mesh} (writing {png}): picture not drawn: OSError: No space left " \
        "on device" in err, err
    assert "Traceback" not in err and f"wrote {out}" in err
    assert out.is_file() and (tmp_path / "a.json").is_file() and not png.exists()
    assert [p for p in tmp_path.rglob(".*")] == []
