"""A FreeSurfer ``.label`` file (a list of vertices: ``lh.cortex.label``, a region drawn in
freeview) given as an overlay: read as a segmentation, 1 at its vertices and 0 elsewhere,
filled as labels and written as a ``.label.gii`` with its table; a label cut short or naming
vertices the surface lacks is an error naming the file (session 45: the reader took it for
a morphometry file, "not a FreeSurfer overlay (no FF FF FF magic bytes), or an old-format
curv file that is truncated (its header announces 2302305 values ...)").
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest
import trimesh

from surfinpaint.app.cli import main
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.io import MeshWarning, read_mesh_data

nib = pytest.importorskip("nibabel")


def _subject(folder: Path) -> tuple[np.ndarray, np.ndarray]:
    """``surf/lh.white`` (a sphere with two holes) and ``label/lh.top.label``: the vertices
    above z = 0.2, each with a value (as ``mri_label2label`` writes a statistic)."""
    s = trimesh.creation.icosphere(3)
    cut = cut_holes(np.asarray(s.vertices), np.asarray(s.faces), [0, 40], [0.35, 0.3])
    v = cut.vertices.astype(np.float32)
    (folder / "surf").mkdir(parents=True)
    (folder / "label").mkdir()
    nib.freesurfer.write_geometry(str(folder / "surf/lh.white"), v, cut.faces.astype(np.int32))
    ids = np.flatnonzero(v[:, 2] > 0.2)
    rows = "".join(f"{i}  {v[i, 0]:.3f}  {v[i, 1]:.3f}  {v[i, 2]:.3f} {0.5 * (i % 3):.6f}\n"
                   for i in ids)
    (folder / "label/lh.top.label").write_text(
        f"#!ascii label  , from subject sub-01 vox2ras=TkReg\n{len(ids)}\n{rows}")
    return v, ids


def _run(*arguments: str) -> int:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return main(list(arguments))


def test_a_label_file_is_read_filled_as_labels_and_written_as_label_gii(tmp_path, capsys):
    v, ids = _subject(tmp_path)
    assert np.array_equal(nib.freesurfer.read_label(str(tmp_path / "label/lh.top.label")), ids)
    inside = np.zeros(len(v), np.int32)
    inside[ids] = 1
    with pytest.warns(MeshWarning, match="lh.top.label: its value column"):
        mesh = read_mesh_data(tmp_path / "surf/lh.white",
                              overlays=[tmp_path / "label/lh.top.label"])
    np.testing.assert_array_equal(mesh.attributes["top"], inside)
    assert json.loads(mesh.metadata["labels.top"])[1][:2] == [1, "top"]
    out = tmp_path / "lh.filled.white"
    assert _run("fill", str(tmp_path / "surf/lh.white"), "-o", str(out), "--method", "fair",
                "--overlay", str(tmp_path / "label/lh.top.label")) == 0
    err = capsys.readouterr().err
    assert "lh.top.label: its value column (not all 0) is not read" in err
    written = nib.load(tmp_path / "lh.filled.white.top.label.gii")
    assert written.labeltable.get_labels_as_dict() == {0: "unknown", 1: "top"}
    values = written.darrays[0].data
    np.testing.assert_array_equal(values[:len(v)], inside)
    assert len(values) > len(v) and set(np.unique(values[len(v):])) == {0, 1}


@pytest.mark.parametrize("text, words", [
    ("#!ascii\n3\n1 0 0 0 0\n2 0 0 0 0\n", "FreeSurfer label is truncated, or not one: its "
     "header announces 3 vertices (5 numbers each), 10 numbers follow"),
    ("#!ascii\n2\n1 0 0 0 0\n5000 0 0 0 0\n", "label lists 1 vertex the surface does not have "
     "(5000; it has"),
    ("\xff\xff\xff binary", "not a FreeSurfer label (its second line should be its vertex count"),
    ("#!ascii\n1\n-4 0 0 0 0\n",
     "FreeSurfer label: a vertex number is not a whole number >= 0: -4"),
])
def test_a_bad_label_file_is_named_by_fill_and_by_the_batch_pre_flight(
        tmp_path, monkeypatch, capsys, text, words):
    monkeypatch.chdir(tmp_path)
    _subject(Path("sub-01"))
    Path("sub-01/label/lh.top.label").write_text(text)
    assert _run("fill", "sub-01/surf/lh.white", "-o", "out.white",
                "--overlay", "sub-01/label/lh.top.label") == 1
    assert f"error: sub-01/label/lh.top.label: {words}" in capsys.readouterr().err
    assert not Path("out.white").exists()
    assert _run("batch", "sub-01/surf/lh.white", "-o", "out", "--jobs", "1",
                "--overlay", "../label/{hemi}.top.label") == 1
    row = json.loads(Path("out/summary.json").read_text())["files"][0]
    assert row["status"] == "failed" and words in row["message"]
    assert "sub-01/label/lh.top.label" in row["message"]
