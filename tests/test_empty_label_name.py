"""A label table entry without a name (a ``<Label>`` with no text, as nibabel writes an
empty name) is read, and written back named by its key with a warning: nibabel reads such an
entry as having no ``label`` and its ``get_labels_as_dict`` fails (session 45's leftover,
fixed in session 46)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_func_overlay import _surface

from surfinpaint.app.cli import main

nib = pytest.importorskip("nibabel")


def test_a_label_without_a_name_is_read_and_written_named_by_its_key(tmp_path, capsys):
    v = _surface(tmp_path)
    table = nib.gifti.GiftiLabelTable()
    for key, name in ((0, "unknown"), (1, ""), (2, "gyrus")):
        label = nib.gifti.GiftiLabel(key, 1.0, 0.5, 0.0, 1.0)
        label.label = name
        table.labels.append(label)
    values = (v[:, 2] > 0).astype(np.int32) + (v[:, 0] > 0.5)
    nib.save(nib.gifti.GiftiImage(darrays=[nib.gifti.GiftiDataArray(
        values, intent="NIFTI_INTENT_LABEL", datatype="NIFTI_TYPE_INT32")], labeltable=table),
        tmp_path / "lh.pial.parts.label.gii")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["fill", str(tmp_path / "lh.pial.gii"), "-o",
                     str(tmp_path / "out.gii"), "--method", "fair"]) == 0
    assert ("overlay 'parts': label 1 has no name: written as 'label 1' (nibabel cannot read "
            "a label table entry without one)") in capsys.readouterr().err
    written = nib.load(tmp_path / "out.parts.label.gii")
    assert written.labeltable.get_labels_as_dict() == {0: "unknown", 1: "label 1",
                                                       2: "gyrus"}
    np.testing.assert_array_equal(written.darrays[0].data[:len(v)], values)
