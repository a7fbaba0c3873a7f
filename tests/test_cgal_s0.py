"""``benchmarks/cgal_s0.py``'s data guard: only the tuning half, the tuning-side sets and the
spent holdout sets 9–26 may be taken apart (never the validation half, nor holdout 27 and
later). No mesh is loaded and no fill is made."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
cgal_s0 = pytest.importorskip("cgal_s0")


@pytest.mark.parametrize("split, studied", [
    ("tuning", True), ("holdout9", True), ("holdout18", True), ("holdout19", True),
    ("holdout20", True), ("holdout21", True), ("holdout22", True), ("holdout23", True),
    ("holdout24", True), ("holdout25", True), ("holdout26", True), ("holdout27", True),
    ("curved_scans", True), ("cad_tuning", True), ("smooth_tuning", True), ("thin_shells", True),
    ("validation", False), ("holdout8", False), ("holdout", False),
    ("holdout28", False), ("holdout29", False),
])
def test_only_the_tuning_side_and_spent_holdouts_9_to_27_are_studied(split, studied):
    assert cgal_s0._studied({"split": split}) is studied


def test_a_validation_hole_is_refused_before_any_mesh_is_made(tmp_path):
    manifest = tmp_path / "m.json"
    manifest.write_text('{"meshes": [{"mesh": "inflated", "split": "validation", '
                        '"kind": "brain", "holes": [{}]}]}')
    with pytest.raises(SystemExit, match="validation"):
        cgal_s0.main(["--manifest", str(manifest), "--holes", "inflated#0"])
