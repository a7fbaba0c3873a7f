"""The summary of a batch's output folder lists every file filled into it (session 47: a
lab's rerun on some of the files, or after one failed, rewrote ``summary.csv`` and
``summary.json`` with that run's rows only, and the earlier rows were lost)."""

from __future__ import annotations

import csv
import json

import pytest

from surfinpaint.app.batch import fill_files, read_summary
from surfinpaint.app.batch_summary import SUMMARY_CSV, SUMMARY_JSON
from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.io import write_mesh

FAIR = {"method": "fair"}


@pytest.fixture
def scans(tmp_path):
    """Four copies of a sphere with a hole, ``in/a.ply`` ... ``in/d.ply``."""
    v, f = sphere(1)
    cut = cut_geodesic_disk(v, f, 0, 0.6)
    folder = tmp_path / "in"
    folder.mkdir()
    for name in "abcd":
        write_mesh(folder / f"{name}.ply", cut.vertices, cut.faces)
    return folder


def _csv_outputs(out) -> list[str]:
    with open(out / SUMMARY_CSV, newline="") as handle:
        return [row["output"] for row in csv.DictReader(handle)]


def test_a_run_on_other_files_keeps_the_earlier_rows_in_their_places(scans, tmp_path):
    out = tmp_path / "out"
    first = fill_files([scans / "a.ply", scans / "b.ply"], out, jobs=1, **FAIR)
    assert first.earlier == 0
    later = fill_files([scans / "c.ply"], out, jobs=1, max_hole_edges=500, **FAIR)
    assert [r.output for r in later] == ["c.ply"] and later.earlier == 2  # this run's rows
    rows = read_summary(out)
    assert [r.output for r in rows] == ["a.ply", "b.ply", "c.ply"] == _csv_outputs(out)
    assert rows[:2] == list(first)  # kept as they were
    # each with the options it was filled with; the run's own are this run's
    document = json.loads((out / SUMMARY_JSON).read_text())
    assert [f["options"].get("max_hole_edges") for f in document["files"]] == [None, None,
                                                                                500]
    assert document["options"]["max_hole_edges"] == 500
    # a rerun's row takes its file's place; the order stays
    again = fill_files([scans / "b.ply", scans / "d.ply"], out, jobs=1, overwrite=True,
                       **FAIR)
    assert again.earlier == 2
    rows = read_summary(out)
    assert [r.output for r in rows] == ["a.ply", "b.ply", "c.ply", "d.ply"]
    assert rows[1] == again[0] and rows[1] != first[1]  # refilled: its seconds are new
    assert rows[0] == first[0] and rows[2] == later[0]


def test_a_rerun_after_a_failed_file_keeps_the_files_that_were_filled(scans, tmp_path):
    out = tmp_path / "out"
    good = (scans / "b.ply").read_bytes()
    (scans / "b.ply").write_bytes(b"")  # empty: failed by the pre-flight
    first = fill_files([scans], out, jobs=1, **FAIR)
    assert [r.status for r in first] == ["filled", "failed", "filled", "filled"]
    (scans / "b.ply").write_bytes(good)
    rerun = fill_files([scans / "b.ply"], out, jobs=1, **FAIR)
    assert [r.status for r in rerun] == ["filled"]
    rows = read_summary(out)
    assert [(r.output, r.status) for r in rows] == [
        ("a.ply", "filled"), ("b.ply", "filled"), ("c.ply", "filled"), ("d.ply", "filled")]
    assert [rows[0], rows[2], rows[3]] == [first[0], first[2], first[3]]


def test_an_output_deleted_since_is_not_listed_a_failed_row_is(scans, tmp_path):
    out = tmp_path / "out"
    (scans / "d.ply").write_bytes(b"")
    fill_files([scans], out, jobs=1, **FAIR)
    (out / "a.ply").unlink()  # the lab removed it: the folder has no such file now
    fill_files([scans / "c.ply"], out, jobs=1, **FAIR)
    assert [(r.output, r.status) for r in read_summary(out)] == [
        ("b.ply", "filled"), ("c.ply", "skipped"), ("d.ply", "failed")]


def test_the_command_says_how_many_earlier_rows_the_summary_keeps(scans, tmp_path, capsys):
    out = tmp_path / "out"
    command = ["batch", "-o", str(out), "--jobs", "1", "--method", "fair"]
    assert main([*command, str(scans / "a.ply"), str(scans / "b.ply")]) == 0
    assert "earlier runs" not in capsys.readouterr().err
    assert main([*command, str(scans / "c.ply")]) == 0
    said = " ".join(capsys.readouterr().err.split())
    assert (f"1 file: 1 filled, 0 unfilled, 0 closed, 0 failed, 0 skipped; wrote "
            f"{out / SUMMARY_CSV} and summary.json (with the rows of 2 files earlier runs "
            "filled into it)") in said, said
    assert _csv_outputs(out) == ["a.ply", "b.ply", "c.ply"]


def test_a_file_given_alone_after_its_folder_is_said_to_land_beside_its_output(scans, tmp_path,
                                                                              capsys):
    out = tmp_path / "out"
    (scans / "sub").mkdir()
    (scans / "a.ply").rename(scans / "sub" / "a.ply")
    command = ["batch", "-o", str(out), "--jobs", "1", "--method", "fair"]
    assert main([*command, str(scans)]) == 0
    assert "earlier run filled it" not in capsys.readouterr().err
    # the one file again, given alone: it goes to the top of OUTDIR, not to sub/
    assert main([*command, str(scans / "sub" / "a.ply")]) == 0
    said = " ".join(capsys.readouterr().err.split())
    assert (f"warning: {scans / 'sub' / 'a.ply'} was filled into {out / 'a.ply'}, but an "
            f"earlier run filled it into {out / 'sub' / 'a.ply'}: both are kept") in said, said
    assert [r.output for r in read_summary(out)] == ["b.ply", "c.ply", "d.ply", "sub/a.ply",
                                                     "a.ply"]
    # the folder again: its file in its place, skipped as up to date, without the warning
    assert main([*command, str(scans)]) == 0
    assert "earlier run filled it" not in capsys.readouterr().err
