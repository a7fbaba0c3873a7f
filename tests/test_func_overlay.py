"""A ``.func.gii`` overlay (a time series, a task's contrasts) beside a GIFTI surface comes
back from a fill as ``.func.gii`` with its arrays' intents (session 45: it came back as
``.shape.gii``, every array ``NIFTI_INTENT_SHAPE``, without a word, and a pipeline looking
for ``*.func.gii`` found nothing).
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
import trimesh

from surfinpaint.app.cli import main
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.io import read_mesh_data

nib = pytest.importorskip("nibabel")


def _surface(tmp_path) -> np.ndarray:
    """``lh.pial.gii``: a sphere with two holes; its vertices."""
    s = trimesh.creation.icosphere(3)
    cut = cut_holes(np.asarray(s.vertices), np.asarray(s.faces), [0, 40], [0.35, 0.3])
    v, f = cut.vertices.astype(np.float32), cut.faces.astype(np.int32)
    nib.save(nib.gifti.GiftiImage(darrays=[
        nib.gifti.GiftiDataArray(v, intent="NIFTI_INTENT_POINTSET"),
        nib.gifti.GiftiDataArray(f, intent="NIFTI_INTENT_TRIANGLE")]), tmp_path / "lh.pial.gii")
    return v


def _fill(tmp_path, output: str) -> int:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return main(["fill", str(tmp_path / "lh.pial.gii"), "-o", str(tmp_path / output),
                     "--method", "fair", "-q"])


def _array(values, intent):
    return nib.gifti.GiftiDataArray(np.asarray(values, np.float32), intent=intent,
                                    datatype="NIFTI_TYPE_FLOAT32")


@pytest.mark.parametrize("intents", [["NIFTI_INTENT_TIME_SERIES"] * 3,
                                     ["NIFTI_INTENT_TTEST", "NIFTI_INTENT_ZSCORE"],
                                     ["NIFTI_INTENT_NONE"]])
def test_a_func_gii_overlay_is_written_back_as_func_gii_with_its_intents(tmp_path, intents):
    v = _surface(tmp_path)
    columns = [np.sin(v[:, 0] * 3 + k) for k in range(len(intents))]
    arrays = [_array(c, i) for c, i in zip(columns, intents, strict=True)]
    nib.save(nib.gifti.GiftiImage(darrays=arrays),
             tmp_path / "lh.pial.task.func.gii")
    assert _fill(tmp_path, "lh.pial.filled.gii") == 0
    assert not (tmp_path / "lh.pial.filled.task.shape.gii").exists()
    written = nib.load(tmp_path / "lh.pial.filled.task.func.gii")
    codes = [nib.nifti1.intent_codes.code[i] for i in intents]
    assert [a.intent for a in written.darrays] == codes
    for array, column in zip(written.darrays, columns, strict=True):
        np.testing.assert_array_equal(array.data[:len(v)], column)
        assert len(array.data) > len(v)
    # read again with its surface, the overlay is found and keeps its kind
    again = read_mesh_data(tmp_path / "lh.pial.filled.gii")
    assert again.attributes["task"].shape[0] == len(written.darrays[0].data)
    assert [a["intent"] for a in json.loads(again.metadata["gifti.task"])["arrays"]] == codes


def test_a_gifti_overlays_metadata_is_written_back(tmp_path, capsys):
    # nilearn's sulc_left.gii.gz holds its file's metadata (UserName, Date, ...) and its
    # array's (Name, ShapeDataType); a fill wrote the numbers only, without a word
    v = _surface(tmp_path)
    sulc = _array(v[:, 2], "NIFTI_INTENT_SHAPE")
    sulc.meta = nib.gifti.GiftiMetaData({"Name": "lh.sulc", "ShapeDataType": "SulcalDepth"})
    file_meta = {"UserName": "lab", "Date": "Fri Mar 24 18:13:50 2023"}
    nib.save(nib.gifti.GiftiImage(darrays=[sulc], meta=nib.gifti.GiftiMetaData(file_meta)),
             tmp_path / "lh.pial.sulc.shape.gii")
    assert _fill(tmp_path, "out.gii") == 0
    written = nib.load(tmp_path / "out.sulc.shape.gii")
    assert dict(written.meta) == file_meta
    assert dict(written.darrays[0].meta) == {"Name": "lh.sulc", "ShapeDataType": "SulcalDepth"}
    np.testing.assert_array_equal(written.darrays[0].data[:len(v)], v[:, 2])
    # a FreeSurfer output writes a morphometry file, which holds no metadata: said
    assert _fill(tmp_path, "lh.out.white") == 0
    assert "overlay 'sulc': its GIFTI metadata is not stored in a FreeSurfer morphometry " \
        "file" in capsys.readouterr().err
    assert (tmp_path / "lh.out.white.sulc").is_file()
