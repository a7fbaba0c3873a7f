"""``FillResult``'s repr, which a notebook shows for ``result``: the counts of vertices,
faces and holes by outcome and the attributes' names, on one line (session 45: the
dataclass's repr printed every array, pages of numbers for one fill)."""

from __future__ import annotations

import warnings

import numpy as np
import trimesh

from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.geometry.cutting import cut_holes


def test_a_fill_result_shows_its_counts_on_one_line():
    s = trimesh.creation.icosphere(3)
    cut = cut_holes(np.asarray(s.vertices), np.asarray(s.faces), [0, 40], [0.35, 0.3])
    height = cut.vertices[:, 2].copy()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = fill_holes(cut.vertices, cut.faces, method="fair",
                            attributes={"height": height})
    new_v = len(result.vertices) - len(cut.vertices)
    new_f = len(result.faces) - len(cut.faces)
    assert new_v > 0 and new_f > 0
    assert repr(result) == (
        f"FillResult({len(result.vertices)} vertices ({new_v} new), {len(result.faces)} "
        f"faces ({new_f} new), 2 holes: 2 faired, attributes=['height'])")
    closed = fill_holes(np.asarray(s.vertices), np.asarray(s.faces))
    assert repr(closed) == (f"FillResult({len(s.vertices)} vertices (0 new), {len(s.faces)} "
                            "faces (0 new), 0 holes: none)")
