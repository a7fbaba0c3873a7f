"""``batch --overlay PATTERN``: the overlays of a FreeSurfer subject's surface that are not
beside it (``label/lh.aparc.annot`` for ``surf/lh.white``) read with each surface of a batch,
a missing one a failed row; and a batch's messages naming files as ``fill`` does, relative,
not by the workers' absolute paths (docs/robustness.md, "Session 36 (helper)")."""

from __future__ import annotations

import json
import os
import warnings
from pathlib import Path

import numpy as np
import pytest

from surfinpaint.app.batch_inputs import FileJob, check_overlay_patterns
from surfinpaint.app.cli import main
from surfinpaint.errors import MeshError

nib = pytest.importorskip("nibabel")

NAMES = [b"frontal", b"parietal", b"temporal", b"occipital"]


def _subjects(root: Path, with_annot=(True, True, False)) -> tuple[np.ndarray, np.ndarray]:
    """FreeSurfer-like subjects ``sub-0K/surf/lh.white`` (fsaverage5's LEFT white surface,
    the faces within 5 mm of one vertex removed, all vertices kept), ``surf/lh.thickness``
    beside it and ``label/lh.aparc.annot`` (4 areas; missing where ``with_annot`` says);
    returns the vertices and the parcellation."""
    pytest.importorskip("nilearn")
    from surfinpaint.data import fsaverage5

    v, f = fsaverage5("white", "left")
    band = np.digitize(v[:, 1], np.quantile(v[:, 1], [0.25, 0.5, 0.75])).astype(np.int32)
    ctab = np.array([[200, 10, 10, 0, 0], [10, 200, 10, 0, 0], [10, 10, 200, 0, 0],
                     [90, 90, 90, 0, 0]])
    ctab[:, 4] = ctab[:, 0] + ctab[:, 1] * 256 + ctab[:, 2] * 65536
    for k, (centre, annot) in enumerate(zip([100, 4000, 7000], with_annot, strict=False)):
        subject = root / f"sub-{k + 1:02d}"
        (subject / "surf").mkdir(parents=True)
        (subject / "label").mkdir()
        near = np.linalg.norm(v[f].mean(axis=1) - v[centre], axis=1) < 5.0
        nib.freesurfer.write_geometry(str(subject / "surf" / "lh.white"), v.astype(np.float32),
                                      f[~near].astype(np.int32))
        nib.freesurfer.write_morph_data(str(subject / "surf" / "lh.thickness"),
                                        (2 + v[:, 2] / 100).astype(np.float32))
        if annot:
            nib.freesurfer.write_annot(str(subject / "label" / "lh.aparc.annot"), band, ctab,
                                       NAMES)
    return v, band


def _batch(*arguments: str) -> int:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return main(["batch", *arguments, "--method", "fair", "--jobs", "1", "-q"])


def test_batch_overlay_reads_each_subjects_parcellation(tmp_path, monkeypatch, capsys):
    # batch had no --overlay: a subject's label/lh.aparc.annot (not beside surf/lh.white)
    # could not be read in a batch, and `--overlay` was a usage error (exit 2)
    monkeypatch.chdir(tmp_path)
    v, band = _subjects(Path("subjects"))
    arguments = ["subjects/*/surf/lh.white", "-o", "out", "--overlay",
                 "../label/{hemi}.aparc.annot"]
    assert _batch(*arguments) == 1  # one subject has no parcellation
    rows = {row["path"]: row for row in json.loads(Path("out/summary.json").read_text())["files"]}
    for k in (1, 2):
        assert rows[f"subjects/sub-0{k}/surf/lh.white"]["status"] == "filled"
        written = nib.load(f"out/sub-0{k}/surf/lh.white.aparc.label.gii")
        assert written.labeltable.get_labels_as_dict() == {
            key: name.decode() for key, name in enumerate(NAMES)}
        labels = written.darrays[0].data
        np.testing.assert_array_equal(labels[:len(v)], band)  # the originals, in order
        assert len(labels) > len(v) and np.isin(labels[len(v):], band).all()
        thickness = nib.freesurfer.read_morph_data(f"out/sub-0{k}/surf/lh.white.thickness")
        assert len(thickness) == len(labels)  # the overlay beside is read as well
    # the subject without one: a failed row naming the surface and the missing overlay as
    # they were given (relative), nothing written for it; the others are
    failed = rows["subjects/sub-03/surf/lh.white"]
    assert failed["status"] == "failed"
    assert failed["message"] == ("subjects/sub-03/surf/lh.white: "
                                 "subjects/sub-03/label/lh.aparc.annot: no such file")
    assert "error: subjects/sub-03/surf/lh.white: subjects/sub-03/label/lh.aparc.annot: no " \
        "such file" in capsys.readouterr().err.replace("\n", " ")
    assert not Path("out/sub-03").exists()
    # a rerun fills what changed: sub-03 once its parcellation is there, sub-01 whose
    # parcellation is newer than its output; sub-02 is up to date
    (Path("subjects/sub-03/label/lh.aparc.annot")).write_bytes(
        Path("subjects/sub-02/label/lh.aparc.annot").read_bytes())
    later = Path("out/sub-01/surf/lh.white").stat().st_mtime_ns + 10**9
    os.utime("subjects/sub-01/label/lh.aparc.annot", ns=(later, later))
    assert _batch(*arguments) == 0
    rows = json.loads(Path("out/summary.json").read_text())["files"]
    assert [row["status"] for row in rows] == ["filled", "skipped", "filled"]


def test_overlay_patterns_fill_in_each_files_name(tmp_path):
    source = tmp_path / "sub" / "surf" / "lh.pial.gii"
    job = FileJob(source, tmp_path / "out" / "lh.pial.gii", "sub/surf/lh.pial.gii",
                  "lh.pial.gii", overlays=check_overlay_patterns(
                      ["../label/{hemi}.aparc.annot", "{stem}.thickness.shape.gii",
                       "/atlas/{name}.annot"]))
    assert job.overlay_files() == {
        source.parent / "../label/lh.aparc.annot": "sub/label/lh.aparc.annot",
        source.parent / "lh.pial.thickness.shape.gii": "sub/surf/lh.pial.thickness.shape.gii",
        Path("/atlas/lh.pial.gii.annot"): "/atlas/lh.pial.gii.annot"}
    nameless = FileJob(tmp_path / "pial.gii", tmp_path / "o.gii", "pial.gii",
                       "pial.gii", overlays=("{hemi}.aparc.annot",))
    with pytest.raises(MeshError, match=r"pial.gii: --overlay '\{hemi\}.aparc.annot': "
                       r"the name says no hemisphere \(FreeSurfer lh./rh., BIDS hemi-L/R, "):
        nameless.overlay_files()
    for pattern, words in (("{subject}.annot", "unknown placeholder {subject}"),
                           ("{hemi.annot", "expected '}' before end of string")):
        with pytest.raises(ValueError, match=words):
            check_overlay_patterns([pattern])


def test_hemi_is_the_hemisphere_as_each_naming_convention_writes_it(tmp_path):
    """BIDS (fMRIPrep), nilearn's fsaverage and Workbench names, not only FreeSurfer's: the
    hemisphere as written, so a pattern in the file's own convention names its companion."""
    cases = {"sub-01_hemi-L_pial.surf.gii": ("sub-01_hemi-{hemi}_thickness.shape.gii",
                                             "sub-01_hemi-L_thickness.shape.gii"),
             "sub-01_ses-1_hemi-R_white.surf.gii": ("hemi-{hemi}.aparc.label.gii",
                                                    "hemi-R.aparc.label.gii"),
             "pial_left.gii.gz": ("sulc_{hemi}.gii.gz", "sulc_left.gii.gz"),
             "infl_right.gii": ("curv_{hemi}.gii", "curv_right.gii"),
             "S1200.L.midthickness_MSMAll.32k_fs_LR.surf.gii": (
                 "S1200.{hemi}.thickness.shape.gii", "S1200.L.thickness.shape.gii"),
             "rh.pial": ("{hemi}.thickness", "rh.thickness")}
    for name, (pattern, overlay) in cases.items():
        job = FileJob(tmp_path / name, tmp_path / "out" / name, name, name,
                      overlays=check_overlay_patterns([pattern]))
        assert job.overlay_files() == {tmp_path / overlay: overlay}, name


def test_batch_overlay_bad_pattern_is_a_usage_error_and_other_formats_fail(tmp_path, capsys,
                                                                             monkeypatch):
    from surfinpaint.data import sphere
    from surfinpaint.io import write_mesh

    monkeypatch.chdir(tmp_path)
    Path("scans").mkdir()
    write_mesh("scans/scan.ply", *sphere(1))
    assert main(["batch", "scans", "-o", "out", "--overlay", "{subject}.annot"]) == 2
    assert "unknown placeholder {subject}" in capsys.readouterr().err
    assert not Path("out").exists()
    assert _batch("scans", "-o", "out", "--overlay", "x.annot") == 1
    row = json.loads(Path("out/summary.json").read_text())["files"][0]
    assert row["status"] == "failed"
    assert row["message"] == ("scans/scan.ply: not a GIFTI or FreeSurfer surface, which "
                              "overlays go with (other formats carry their per-vertex data "
                              "in the file)")


def test_batch_names_a_bad_overlay_beside_a_surface_as_fill_does(tmp_path, monkeypatch,
                                                                  capsys):
    # session 35: the batch's message named the overlay by its absolute path (the worker's),
    # fill by the path as given
    from surfinpaint.data import sphere
    from surfinpaint.io import write_mesh

    monkeypatch.chdir(tmp_path)
    Path("bad").mkdir()
    v, f = sphere(1)
    write_mesh("bad/lh.pial.gii", v, f)
    short = nib.gifti.GiftiImage(darrays=[nib.gifti.GiftiDataArray(
        np.zeros(5, np.float32), intent="NIFTI_INTENT_SHAPE")])
    nib.save(short, "bad/lh.pial.short.shape.gii")
    said = f"bad/lh.pial.short.shape.gii: overlay has 5 values, the surface {len(v)} vertices"
    assert main(["fill", "bad/lh.pial.gii", "-o", "filled.gii", "-q"]) == 1
    assert f"error: {said}" in capsys.readouterr().err.replace("\n", "")
    assert _batch("bad", "-o", "out") == 1
    row = json.loads(Path("out/summary.json").read_text())["files"][0]
    assert row["message"] == f"bad/lh.pial.gii: {said}"
    assert str(tmp_path) not in Path("out/summary.csv").read_text()


def test_batch_messages_name_files_from_where_the_inputs_are_named():
    from surfinpaint.app.batch_summary import named_in_summary

    job = FileJob(Path("/tmp/x/in/a.obj"), Path("/tmp/x/out/a.obj"), "in/a.obj", "a.obj")
    # the output as its materials are named (session 40: it was "a.obj", its path in the
    # output folder, which read as the input where that is a.obj too)
    assert named_in_summary(job, "/tmp/x/out/a.obj: /tmp/x/out/s.mtl differs from "
                            "/tmp/x/in/s.mtl; /data/tmp/x/y.png") == (
        "out/a.obj: out/s.mtl differs from in/s.mtl; /data/tmp/x/y.png")
    given_whole = FileJob(Path("/tmp/x/in/a.obj"), Path("/tmp/x/out/a.obj"),
                          "/tmp/x/in/a.obj", "a.obj")  # named absolute: kept absolute
    assert named_in_summary(given_whole, "/tmp/x/in/s.mtl") == "/tmp/x/in/s.mtl"
