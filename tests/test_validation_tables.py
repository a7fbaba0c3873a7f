"""``benchmarks/validation.py``'s headline numbers, on hand-made rows (no mesh is filled).

The table is what the README's accuracy section quotes, so its measures are pinned here: the
per-hole ratio to CGAL, the worst mesh against the bilaplacian fill, the holes above 1.5× the
better faired fill, and a file of our rows only (no peers' rows) giving no peer measures
instead of stopping the table.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
validation = pytest.importorskip("validation")


def _row(mesh: str, hole: int, method: str, mean: float, status: str = "ok") -> dict:
    return {"case": mesh, "hole": hole, "radius_h": 3.0, "boundary_edges": 20,
            "method": method, "status": status, "mean_pct": mean, "seconds": 0.1,
            "note": "", "extra": {"kind": "organic", "split": "tuning",
                                  "near_border": hole == 1, "on_feature": False}}


# (mesh, hole): errors of fair, fair3, conformal_raw, conformal (the default), cgal
ERRORS = {("a", 0): (1.0, 2.0, 0.5, 0.5, 1.0),
          ("a", 1): (1.0, 1.0, 3.0, 3.0, 2.0),   # default 3× the better faired fill
          ("b", 0): (2.0, 1.0, 0.4, 0.4, 0.8),
          ("b", 1): (2.0, 1.0, 1.2, 1.2, 1.2)}
METHODS = ("fair", "fair3", "conformal_raw", "conformal", "cgal")


def _rows(with_peers: bool) -> list[dict]:
    return [_row(m, k, meth, e) for (m, k), errs in ERRORS.items()
            for meth, e in zip(METHODS, errs, strict=True) if with_peers or meth != "cgal"]


def test_headline_measures_on_hand_made_rows():
    hl = validation.headline(_rows(True), list(METHODS))
    # per-hole default / cgal: 0.5, 1.5, 0.5, 1.0 -> median 0.75
    assert hl["default_over_cgal_per_hole"] == pytest.approx(0.75)
    # per-mesh medians: a: default 1.75, fair 1.0; b: default 0.8, fair 2.0
    assert hl["worst_mesh_vs_fair"] == ("a", pytest.approx(1.75))
    assert hl["meshes_above_1.1_fair"] == ["a"]
    assert hl["worst_hole_vs_better_faired"] == (("a", 1), pytest.approx(3.0))
    assert hl["holes_above_1.5_faired"] == 1
    # cgal's per-mesh medians: a 1.5 (default 1.75 loses), b 1.0 (default 0.8 wins)
    assert hl["default_best_of_peers"] == (1, 2)
    # per hole, default against cgal: 0.5 < 1.0, 3.0 > 2.0, 0.4 < 0.8, 1.2 = 1.2 (a tie counts)
    assert hl["default_best_of_peers_per_hole"] == (3, 4)
    assert "| holes where the default is the closest of all peers | 3 / 4 (75 %) |" in \
        validation.report(_rows(True), list(METHODS), "tuning")


def test_a_file_without_the_peers_rows_gives_no_peer_measures():
    rows = _rows(False)
    hl = validation.headline(rows, [m for m in METHODS if m != "cgal"])
    assert hl["default_best_of_peers"] is None
    assert hl["default_best_of_peers_per_hole"] is None
    assert np.isnan(hl["default_over_cgal_per_hole"])
    assert hl["worst_mesh_vs_fair"] == ("a", pytest.approx(1.75))
    text = validation.report(rows, [m for m in METHODS if m != "cgal"], "tuning")
    assert "no peers' rows" in text and "1.750 (a)" in text


def test_the_chooser_scores_the_smoothed_bilaplacian_candidate_when_its_column_is_there():
    # hole ("a", 1): the default wrote the smoothed fair2 (0.9), closer than the plain `fair`
    # column (1.0): the best of its candidates, scored against fair_sfauto; scored against
    # `fair` it would be a miss (0.9 / 1.0 < 1, a "better than best" that is not a choice)
    rows = [_row("a", 0, m, e) for m, e in
            (("fair", 1.0), ("fair_sfauto", 1.0), ("fair3", 2.0), ("conformal_raw", 0.5),
             ("conformal", 0.5), ("cgal", 1.0))]
    rows += [_row("a", 1, m, e) for m, e in
             (("fair", 1.0), ("fair_sfauto", 0.9), ("fair3", 3.0), ("conformal_raw", 2.0),
              ("conformal", 0.9), ("cgal", 1.0))]
    hl = validation.headline(rows, ["fair", "fair_sfauto", "fair3", "conformal_raw",
                                    "conformal", "cgal"])
    assert hl["chooser_candidates"] == ("fair_sfauto", "fair3", "conformal_raw")
    assert hl["chooser_best"] == (2, 2)
    assert hl["chooser_median_regret"] == pytest.approx(1.0)
    assert hl["oracle_over_cgal"] == pytest.approx(np.median([0.5, 0.9]))
    # the same rows without the column (a run made before it existed): the plain `fair`
    old = [r for r in rows if r["method"] != "fair_sfauto"]
    hl = validation.headline(old, ["fair", "fair3", "conformal_raw", "conformal", "cgal"])
    assert hl["chooser_candidates"] == ("fair", "fair3", "conformal_raw")
    assert hl["chooser_median_regret"] == pytest.approx(np.median([1.0, 0.9]))
    text = validation.report(rows, ["fair", "fair_sfauto", "fair3", "conformal_raw",
                                    "conformal", "cgal"], "tuning")
    assert "best of fair_sfauto/fair3/conformal_raw (within 1 %) | 2 / 2 (100 %)" in text


def _printed_tables(path: Path, capsys) -> list[str]:
    validation.main(["--tables", str(path), "--methods", ",".join(METHODS)])
    return capsys.readouterr().out.splitlines()


def test_the_speed_table_has_each_methods_cpu_seconds_and_old_runs_still_print(tmp_path,
                                                                               capsys):
    # session 48: each row has the fill's CPU seconds beside its wall seconds
    rows = _rows(True)
    for k, row in enumerate(rows):
        row["cpu_seconds"] = 0.05 + 0.01 * (row["method"] == "cgal") + 0.001 * k
    cpu = {m: np.median([r["cpu_seconds"] for r in rows if r["method"] == m])
           for m in METHODS}
    saved = tmp_path / "new.json"
    saved.write_text(json.dumps({"rows": rows}))
    lines = _printed_tables(saved, capsys)
    assert ("| method | median s per hole | median CPU s per hole | median s, ≤ 100 edges "
            "| max s | failed/open/error |") in lines
    for method in METHODS:
        assert f"| {method} | 0.100 | {cpu[method]:.3f} | 0.100 | 0.100 | 0 |" in lines
    # a run saved before the field (a .json or a stopped run's .partial.jsonl): "—"
    for row in rows:
        del row["cpu_seconds"]
    old = tmp_path / "old.json"
    old.write_text(json.dumps({"rows": rows}))
    partial = tmp_path / "old.partial.jsonl"
    partial.write_text("".join(json.dumps(row) + "\n" for row in rows))
    for path in (old, partial):
        lines = _printed_tables(path, capsys)
        for method in METHODS:
            assert f"| {method} | 0.100 | — | 0.100 | 0.100 | 0 |" in lines


def test_a_scored_row_has_the_fills_cpu_seconds():
    accuracy = pytest.importorskip("accuracy")
    from surfinpaint.data import sphere
    from surfinpaint.geometry.cutting import cut_geodesic_disk

    v, f = sphere(3)
    cut = cut_geodesic_disk(v, f, v[0], 0.4)
    row = accuracy.score(cut, "fair", "sphere", 0, 3.0, 500)
    assert row.status == "ok"
    assert np.isfinite(row.cpu_seconds) and row.cpu_seconds > 0
    assert json.loads(json.dumps(accuracy.asdict(row)))["cpu_seconds"] == row.cpu_seconds
