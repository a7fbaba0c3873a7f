"""``batch``'s pre-flight, its last gaps (session 42): a FreeSurfer ``.annot`` overlay's
header, a truncated GIFTI found from its last bytes, and an interrupt while the files are
listed and checked, which writes the summary as one during the fills does."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from test_batch_preflight import _batch_events, _count_reads, _surface_and_overlay

from surfinpaint.app import batch_listing
from surfinpaint.app.batch import fill_files, read_summary
from surfinpaint.app.batch_summary import SUMMARY_CSV, SUMMARY_JSON
from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.errors import MeshError
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.io.brain import check_overlay
from surfinpaint.io.formats import check_file, read_mesh, read_mesh_data, write_mesh

nib = pytest.importorskip("nibabel")


def _said(call, path) -> str:
    with pytest.raises(MeshError) as raised:
        call(path)
    return str(raised.value)


# ------------------------------------------------------------------ a truncated GIFTI


def _gifti(path: Path) -> bytes:
    """A GIFTI surface larger than the 8 KiB the check reads from its start."""
    write_mesh(path, *sphere(4))
    data = path.read_bytes()
    assert len(data) > 3 << 13 and data.endswith(b"</GIFTI>")
    return data


# where a copy cut short ends: in its data, in its last DataArray's closing tags, in the
# root's closing tag
CUTS = {"half": lambda data: data[:len(data) // 2],
        "in the last tags": lambda data: data[:-len(b"</DataArray></GIFTI>") + 3],
        "in the closing tag": lambda data: data[:-3]}


@pytest.mark.parametrize("cut", CUTS)
def test_check_file_finds_a_truncated_gifti(tmp_path, monkeypatch, cut):
    cut_short = tmp_path / "cut.gii"
    cut_short.write_bytes(CUTS[cut](_gifti(tmp_path / "whole.gii")))
    said = _said(read_mesh, cut_short)
    assert said == f"{cut_short}: GIFTI file is truncated (it does not end with its closing " \
        "tag </GIFTI>)"
    given = _count_reads(monkeypatch)
    assert _said(check_file, cut_short) == said  # the reader's words
    # its first 8 KiB (its format), then all of it (its end and its data: session 43)
    assert given == [1 << 13, cut_short.stat().st_size], given


def test_a_gifti_ending_in_blanks_and_comments_passes(tmp_path):
    # what XML allows after the root element: the reader takes it, so the check must
    data = _gifti(tmp_path / "whole.gii")
    padded = tmp_path / "padded.gii"
    padded.write_bytes(data + b"\n<!-- exported by a lab tool -->\n<?note x?>\n\n" + b" " * 5000)
    assert len(read_mesh(padded)[0]) == len(sphere(4)[0])
    assert check_file(padded) is None
    # past the last 4 KiB the check reads: blanks, or a comment, tell nothing; left to the
    # reader, which takes them
    for trailer in (b" " * 5000, b"<!-- " + b"notes " * 1000 + b"-->\n"):
        padded.write_bytes(data + trailer)
        assert len(read_mesh(padded)[0]) == len(sphere(4)[0])
        assert check_file(padded) is None
    # a long run of blanks after the closing tag, then text: not XML's end, found at once
    # (no backtracking over the blanks)
    stray = tmp_path / "stray.gii"
    stray.write_bytes(data + b" " * 3000 + b"x")
    assert _said(check_file, stray) == _said(read_mesh, stray)
    assert "GIFTI file is truncated" in _said(check_file, stray)


def test_check_overlay_finds_a_truncated_gifti_overlay_from_its_last_bytes(tmp_path):
    def cut_shape_gii(path: Path, n: int) -> None:
        values = nib.gifti.GiftiDataArray(np.linspace(1, 3, n).astype(np.float32),
                                          intent="NIFTI_INTENT_SHAPE", encoding="ASCII")
        data = nib.gifti.GiftiImage(darrays=[values]).to_bytes()
        # notes before the root element: the file runs past the head the check reads
        data = data.replace(b"<GIFTI", b"<!-- " + b"notes " * 2000 + b"-->\n<GIFTI", 1)
        assert len(data) > 1 << 13
        path.write_bytes(data[:-100])

    surface, overlay = _surface_and_overlay(tmp_path, ("lh.pial.thickness.shape.gii",
                                                       cut_shape_gii))
    said = _said(lambda p: read_mesh_data(surface, overlays=[p]), overlay)
    assert said == f"{overlay}: GIFTI file is truncated (it does not end with its closing " \
        "tag </GIFTI>)"
    assert _said(check_overlay, overlay) == said


# ---------------------------------------------------------------------- .annot overlays


def _annot(path: Path, n: int) -> None:
    ctab = np.array([[255, 0, 0, 0, 0], [0, 255, 0, 0, 0], [0, 0, 255, 0, 0]])
    nib.freesurfer.write_annot(str(path), np.arange(n) % 3, ctab, [b"a", b"b", b"c"],
                               fill_ctab=True)


def _cut_annot(path: Path, n: int) -> None:
    _annot(path, n)
    path.write_bytes(path.read_bytes()[:100])


BAD_ANNOTS = {
    "truncated": (_cut_annot, "FreeSurfer annotation is truncated, or no annotation (its "
                  "header announces {n} vertices = {need} bytes before its colour table, the "
                  "file has 100)"),
    "text": (lambda p, n: p.write_text("aparc labels\n"), "FreeSurfer annotation is truncated, "
             "or no annotation (its header announces 1634754930 vertices = 13078039452 bytes "
             "before its colour table, the file has 13)"),
}


@pytest.mark.parametrize("case", BAD_ANNOTS)
def test_check_overlay_says_a_bad_annot_as_the_reader_does(tmp_path, case):
    make, reason = BAD_ANNOTS[case]
    surface, overlay = _surface_and_overlay(tmp_path, ("lh.aparc.annot", make))
    n = len(read_mesh(surface)[0])
    said = _said(lambda p: read_mesh_data(surface, overlays=[p]), overlay)
    assert said == f"{overlay}: " + reason.format(n=n, need=4 + 8 * n + 8)
    assert _said(check_overlay, overlay) == said  # from its first bytes


def test_check_overlay_passes_a_good_annot(tmp_path):
    surface, overlay = _surface_and_overlay(tmp_path, ("lh.aparc.annot", _annot))
    assert "aparc" in read_mesh_data(surface, overlays=[overlay]).attributes
    assert check_overlay(overlay) is None


def test_a_batch_says_a_truncated_annot_before_any_fill(tmp_path, monkeypatch):
    subjects = tmp_path / "subjects"
    good = _surface_and_overlay(subjects / "sub-good", ("lh.aparc.annot", _annot))[0]
    bad = _surface_and_overlay(subjects / "sub-bad", ("lh.aparc.annot", _cut_annot))[0]
    events, failed = _batch_events(monkeypatch, subjects, tmp_path / "out",
                                   overlays=["../label/{hemi}.aparc.annot"])
    assert events[0] == f"failed {bad}" and f"fill {bad}" not in events, events
    assert f"fill {good}" in events and list(failed) == [str(bad)]
    assert "FreeSurfer annotation is truncated" in failed[str(bad)]


# ----------------------------------------------------------- an interrupt while listing


def _holey_files(folder: Path, names: list[str]) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    v, f = sphere(1)
    cut = cut_geodesic_disk(v, f, 0, 0.6)
    for name in names:
        write_mesh(folder / name, cut.vertices, cut.faces)


def _interrupt_at(monkeypatch, step: str, name: str) -> None:
    """Ctrl-C while the listing's ``step`` (``checked_row``, ``up_to_date``) is at the file
    whose output is ``name``."""
    real = getattr(batch_listing, step)

    def interrupted(job, *args):
        if job.output == name:
            raise KeyboardInterrupt
        return real(job, *args)

    monkeypatch.setattr(batch_listing, step, interrupted)


def test_an_interrupt_while_checking_writes_the_summary_of_the_files_done(tmp_path,
                                                                          monkeypatch):
    folder, out = tmp_path / "scans", tmp_path / "out"
    _holey_files(folder, ["b.ply", "c.ply"])
    (folder / "a_empty.ply").write_bytes(b"")  # failed by the pre-flight: done
    _interrupt_at(monkeypatch, "checked_row", "c.ply")
    with pytest.raises(KeyboardInterrupt):
        fill_files([folder], out, jobs=1, method="fair")
    rows = read_summary(out)
    assert [(r.output, r.status) for r in rows] == [("a_empty.ply", "failed")]
    assert "file is empty" in rows[0].message
    assert not any(out.glob("*.ply"))  # nothing filled
    assert not any(p.name.startswith(".") for p in out.iterdir())  # written atomically
    monkeypatch.undo()  # the same command again fills the rest
    rows = fill_files([folder], out, jobs=1, method="fair")
    assert [(r.output, r.status) for r in rows] == [
        ("a_empty.ply", "failed"), ("b.ply", "filled"), ("c.ply", "filled")]


def test_an_interrupted_rerun_keeps_the_earlier_rows_of_the_files_not_judged(tmp_path,
                                                                           monkeypatch):
    folder, out = tmp_path / "scans", tmp_path / "out"
    names = ["b.ply", "c.ply", "d.ply", "e.ply"]
    _holey_files(folder, names)
    fill_files([folder], out, jobs=1, method="fair")
    first = {r.output: r for r in read_summary(out)}
    assert all(r.status == "filled" for r in first.values())
    changed = folder / "c.ply"  # newer than its output: to fill again
    os.utime(changed, ns=(changed.stat().st_atime_ns, changed.stat().st_mtime_ns + 10**10))
    _interrupt_at(monkeypatch, "up_to_date", "d.ply")
    with pytest.raises(KeyboardInterrupt):
        fill_files([folder], out, jobs=1, method="fair")
    rows = {r.output: r for r in read_summary(out)}
    # b judged up to date (skipped, with the first run's counts); c judged to fill, not
    # filled, d (being judged) and e not judged: their rows of the earlier summary (since
    # session 47 the summary keeps the rows of every file filled into the folder; c's
    # output is the one its row describes), in their places
    assert list(rows) == ["b.ply", "c.ply", "d.ply", "e.ply"]
    assert rows["b.ply"].status == "skipped"
    assert rows["b.ply"].holes_filled == first["b.ply"].holes_filled == 1
    assert all(rows[name] == first[name] for name in ("c.ply", "d.ply", "e.ply"))


def test_an_interrupt_while_finding_the_inputs_leaves_a_summary(tmp_path, monkeypatch):
    folder, out = tmp_path / "scans", tmp_path / "out"
    _holey_files(folder, ["b.ply"])

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(batch_listing, "find_inputs", interrupted)
    with pytest.raises(KeyboardInterrupt):
        fill_files([folder], out, jobs=1, method="fair")
    assert (out / SUMMARY_CSV).is_file() and read_summary(out) == []  # nothing done
    # an earlier run's summary is the record still: left as it was
    monkeypatch.undo()
    fill_files([folder], out, jobs=1, method="fair")
    before = (out / SUMMARY_JSON).read_bytes()
    monkeypatch.setattr(batch_listing, "find_inputs", interrupted)
    with pytest.raises(KeyboardInterrupt):
        fill_files([folder], out, jobs=1, method="fair")
    assert (out / SUMMARY_JSON).read_bytes() == before


def test_the_command_interrupted_while_checking_says_so_and_exits_130(tmp_path, monkeypatch,
                                                                      capsys):
    folder, out = tmp_path / "scans", tmp_path / "out"
    _holey_files(folder, ["b.ply", "c.ply"])
    (folder / "a_empty.ply").write_bytes(b"")
    _interrupt_at(monkeypatch, "checked_row", "c.ply")
    assert main(["batch", str(folder), "-o", str(out), "--jobs", "1", "--method", "fair",
                 "-q"]) == 130
    said = " ".join(capsys.readouterr().err.split())
    assert "a_empty.ply" in said and "file is empty" in said, said  # said as it came
    assert f"the files done are in {out / SUMMARY_CSV}" in said, said
    assert "picks up the rest" in said and "Traceback" not in said, said
    # nothing was in flight: it says the files were being listed, not that fills stopped
    assert "no file was being filled yet" in said and "in flight" not in said, said
    assert [(r.output, r.status) for r in read_summary(out)] == [("a_empty.ply", "failed")]
