"""The learned-chooser study's tools (docs/selfcheck.md, session 49): the score table's
guard and its record of what the library wrote (``benchmarks/selfcheck_table.py``), and the
replay of the library's rule and the measures (``benchmarks/chooser_replay.py``)."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from conftest import grid_mesh

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
table = pytest.importorskip("selfcheck_table")
replay = pytest.importorskip("chooser_replay")

from surfinpaint.geometry.cutting import cut_geodesic_disk  # noqa: E402

INF = float("inf")


@pytest.mark.parametrize("split, allowed", [
    ("tuning", True), ("cad_tuning", True), ("holdout9", True), ("holdout24", True),
    ("holdout25", True), ("holdout26", True), ("holdout27", True), ("validation", False),
    ("holdout28", False),
    ("holdout8", False),
])
def test_the_table_reads_only_study_sets(tmp_path, split, allowed):
    path = tmp_path / "manifest.json"
    path.write_text(json.dumps({"meshes": [{"mesh": "m", "split": split, "holes": []}]}))
    if allowed:
        assert [e["mesh"] for e in table._manifest_holes(None, None, path)] == ["m"]
    else:
        with pytest.raises(SystemExit, match="spent holdouts 9-27 only"):
            list(table._manifest_holes(None, None, path))


def _cut(height):
    """A hole cut from a 30 × 30 grid lifted to ``height`` (a function of x, y), as
    ``validation._cut`` returns it."""
    v, f = grid_mesh(30, 30)
    v[:, 2] = height(v[:, 0], v[:, 1])
    cut = cut_geodesic_disk(v, f, int(np.argmin(np.linalg.norm(v[:, :2] - 0.5, axis=1))),
                            0.25)
    hole = cut.holes[0]
    return SimpleNamespace(vertices=cut.vertices, faces=cut.faces, loop=hole.loop,
                           truth_vertices=hole.truth_vertices, truth_faces=hole.truth_faces,
                           diameter=hole.diameter)


def test_the_library_row_on_a_plane_says_the_plane_test_laid_it():
    row = table.library_row(_cut(lambda x, y: 0.0 * x), n_samples=2000)
    assert row["plane"] and row["method"] == "fair" and row["verdict"] is None
    assert row["true"] < 1e-6
    assert replay.written({"library": row}) == "plane"


@pytest.mark.parametrize("library, expected", [
    ({"plane": False, "ear_cut": "flat planes", "note": "ear cutting: …"}, "ear_cut"),
    ({"plane": False, "note": "ear cutting: 100 % of its area …"}, "ear_cut"),  # older rows
    ({"plane": False, "ear_cut": None, "note": "self-check kept the λ-H fill (…)",
      "blended_with": None, "method": "conformal", "fair_order": None}, "conformal"),
])
def test_an_ear_cut_fill_is_no_candidate(library, expected):
    """The ear-cut rules write without a self-check (session 51's default): the replay must
    not read such a hole as a fair2 choice."""
    assert replay.written({"library": library}) == expected


def test_the_library_row_on_a_bump_records_the_self_check():
    row = table.library_row(_cut(lambda x, y: 0.3 * np.exp(-((x - .5) ** 2 + (y - .5) ** 2)
                                                           / 0.05)), n_samples=2000)
    v = row["verdict"]
    assert not row["plane"] and v is not None and v["hidden"]
    assert row["method"] == ("conformal" if v["keep"] else "fair")
    assert 0 < row["true"] < INF
    json.dumps(row)  # a cache line


def _row(hidden, sibling=None, *, true=(1.0, 1.0, 1.0), written="fair2", advantages=None,
         cgal=1.0, mesh="m", split="holdout20"):
    return {"hidden": hidden, "sibling": sibling or {}, "crossed": False, "failure": None,
            "true": dict(zip(replay.CANDIDATES, true, strict=True)), "cgal": cgal,
            "mesh": mesh, "split": split, "kind": "other", "hole": 0,
            **({"advantages": advantages} if advantages is not None else {}),
            "library": {"plane": written == "plane", "blended_with": None,
                        "method": "conformal" if written == "conformal" else "fair",
                        "fair_order": 3 if written == "fair3" else 2, "true": 9.0}}


def test_the_replay_is_the_library_rule_with_its_significance_cut():
    wins = {"fair2": 2.0, "fair3": 3.0, "conformal": 1.0}
    assert replay.replayed(_row(wins)) == "conformal"
    # far ahead of its standard error: kept; within 2.326 of them: fair2
    assert replay.replayed(_row(wins, advantages={"hidden": {"conformal": [1.0, 0.1]}})) \
        == "conformal"
    assert replay.replayed(_row(wins, advantages={"hidden": {"conformal": [1.0, 0.5]}})) \
        == "fair2"
    # losing the hidden rings: the faired fill that wins them against fair2
    assert replay.replayed(_row({"fair2": 2.0, "fair3": 1.5, "conformal": 3.0})) == "fair3"


def test_the_measures():
    rows = [_row({}, true=(1.0, 2.0, 3.0), written="fair2", cgal=2.0, mesh="a"),
            _row({}, true=(1.0, 0.5, 4.0), written="conformal", cgal=1.0, mesh="a"),
            _row({}, true=(2.0, 2.0, 1.0), written="plane", cgal=4.0, mesh="b")]
    chosen = [replay.written(r) for r in rows]
    m = replay.measures(rows, chosen)
    # the plane hole is no choice, but counts above 1.5× (its fill 9 against 2) as the λ-H
    # fill written at 8× the better faired fill does
    assert (m["chose"], m["rate"], m["above"]) == (2, 0.5, 2)
    assert m["regret"] == pytest.approx((1.0 + 8.0) / 2)
    # per hole: 1/2, 4/1, 9/4 (the plane hole's written fill is the library's own)
    assert m["cgal"] == pytest.approx(9.0 / 4.0)
    # mesh a: median written 2.5 against median fair2 1.0; mesh b: 9 against 2
    assert m["worst"] == ("holdout20:b", pytest.approx(4.5)) and m["over"] == [
        "holdout20:a", "holdout20:b"]
    assert replay.fold_of(rows[0]) == "holdout20"
    assert replay.fold_of({**rows[0], "split": "cad_tuning"}) == "cad_tuning:a"
