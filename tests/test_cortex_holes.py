"""benchmarks/cortex_holes.py: the rim measures, the replay of ``lambda_h_over_fair3`` on
table rows, the measures and the parts (session 52 helper)."""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import grid_mesh

sys.path.insert(0, str(Path(__file__).parent.parent / "benchmarks"))
import cortex_holes as study  # noqa: E402

from surfinpaint.data import sphere  # noqa: E402
from surfinpaint.geometry.cutting import cut_geodesic_disk  # noqa: E402


def _cut_rim(vertices, faces, centre, radius):
    cut = cut_geodesic_disk(vertices, faces, centre, radius)
    return study.rim_measures(cut.vertices, cut.faces, cut.loop), cut


def test_rim_on_a_sphere_is_even():
    """On a unit sphere H is 1 everywhere: no sign change, little variation along the
    rim, and H times the hole's radius is the radius."""
    v, f = sphere(4)
    rim, cut = _cut_rim(v, f, 0, 0.6)
    assert rim["rim_h_sign_changes"] == 0
    assert rim["rim_h_variation"] < 0.1
    radius = np.linalg.norm(cut.vertices[cut.loop] - cut.vertices[cut.loop].mean(0),
                            axis=1).mean()
    assert rim["curvature_radius"] == pytest.approx(radius, rel=0.1)
    assert 0 < rim["normal_spread"] < 0.2


def test_rim_on_folds_changes_sign_along_the_loop():
    """A height field folded across the hole: the rim crosses crests and troughs, so H
    changes sign along it and varies far more than on the sphere."""
    v, f = grid_mesh(60, 60)
    v = v.copy()
    v[:, 2] = 0.04 * np.sin(2 * np.pi * 4 * v[:, 0])
    centre = int(np.argmin(np.linalg.norm(v[:, :2] - 0.5, axis=1)))
    rim, _ = _cut_rim(v, f, centre, 0.2)
    assert rim["rim_h_sign_changes"] >= 4
    assert rim["rim_h_variation"] > 0.2
    flat = grid_mesh(60, 60)
    rim_flat, _ = _cut_rim(*flat, centre, 0.2)
    assert rim_flat["curvature_radius"] < 1e-6 < rim["curvature_radius"]


def _row(split="holdout20", written="conformal", hidden=None, note="", crossed=False,
         true=None, kind="brain", mesh="m", hole=0):
    method, order = {"conformal": ("conformal", None), "fair2": ("fair", 2),
                     "fair3": ("fair", 3)}[written]
    hidden = {"fair2": 2.0, "fair3": 1.0, "conformal": 1.1} if hidden is None else hidden
    return {"split": split, "mesh": mesh, "hole": hole, "kind": kind, "failure": None,
            "crossed": crossed, "hidden": hidden,
            "true": true or {"fair2": 1.0, "fair3": 0.5, "conformal": 0.8},
            "library": {"plane": False, "blended_with": None, "method": method,
                        "fair_order": order, "note": note, "true": math.nan,
                        "verdict": {"keep": written == "conformal", "faired": "fair2",
                                    "reference": "fair2", "hidden": hidden}}}


# (row, ratio, written with it)
WRITTEN = {
    "the default: as written": (_row(), None, "conformal"),
    "λ-H 1.1 × fair3 on the hidden rings, ratio 1.05: fair3": (_row(), 1.05, "fair3"),
    "ratio 1.2: kept": (_row(), 1.2, "conformal"),
    "a faired fill written: unchanged": (_row(written="fair2"), 1.05, "fair2"),
    "the library ran the hidden rings shallower: unchanged": (
        _row(note="(…; hidden rings one ring shallower (the deeper ones met a crease))"),
        1.05, "conformal"),
    "a crease crosses the hole: unchanged": (_row(crossed=True), 1.05, "conformal"),
}


@pytest.mark.parametrize("case", list(WRITTEN))
def test_written_with(case):
    row, ratio, expected = WRITTEN[case]
    assert study.written_with(row, ratio) == expected


def test_measures_count_what_the_ratio_changes():
    """Two meshes; the rule changes one hole of each, one closer, one farther."""
    rows = [_row(mesh="a", hole=0, true={"fair2": 1.0, "fair3": 0.5, "conformal": 0.8}),
            _row(mesh="a", hole=1, written="fair2",
                 true={"fair2": 1.0, "fair3": 0.9, "conformal": 0.95}),
            _row(mesh="b", hole=0, true={"fair2": 1.0, "fair3": 0.6, "conformal": 0.3})]
    before, after = study.measures(rows, None), study.measures(rows, 1.05)
    assert before["changed"] == 0 and after["changed"] == 2
    assert (after["closer"], after["farther"]) == (1, 1)
    assert after["geomean"] == pytest.approx(math.sqrt(0.5 / 0.8 * 0.6 / 0.3))
    # mesh a: median of (0.8, 1.0) over fair2's median 1.0 before, of (0.5, 1.0) after
    assert before["vs_fair"][("holdout20", "a")] == pytest.approx(0.9)
    assert after["vs_fair"][("holdout20", "a")] == pytest.approx(0.75)
    assert after["worst_mesh"] == "a" and after["worst"] == pytest.approx(0.75)
    # a #0: 0.8 / min(1.0, 0.5) = 1.6 before, 1 after; b #0: 0.5 before, 1 after
    assert before["above_1.5"] == 1 and after["above_1.5"] == 0
    regret_after = np.mean([math.log(0.5 / 0.5), math.log(1.0 / 0.9), math.log(0.6 / 0.3)])
    assert after["mean_log_regret"] == pytest.approx(regret_after)


@pytest.mark.parametrize("split, expected", [("tuning", "A"), ("holdout11", "A"),
                                             ("holdout19", "A"), ("holdout20", "B"),
                                             ("holdout27", "B")])
def test_parts(split, expected):
    assert study.part({"split": split}) == expected


def test_auc():
    assert study.auc([3.0, 4.0], [1.0, 2.0]) == 1.0
    assert study.auc([1.0, 2.0], [3.0, math.nan]) == 0.0
    assert study.auc([1.0], [1.0]) == 0.5
    assert math.isnan(study.auc([], [1.0]))


@pytest.mark.parametrize("split", ["validation", "holdout28", "holdout29"])
def test_the_table_refuses_sets_a_study_must_not_fill(tmp_path, split):
    manifest = tmp_path / "m.json"
    manifest.write_text(json.dumps({"meshes": [
        {"mesh": "x", "split": split, "kind": "brain", "holes": [{}]}]}))
    with pytest.raises(SystemExit, match="spent holdouts"):
        study.build(tmp_path / "rows.jsonl", manifest, None, None, "brain")
    assert not (tmp_path / "rows.jsonl").exists()
