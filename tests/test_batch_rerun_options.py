"""A batch rerun with other fill options says which files it skipped as up to date, filled
with the options of an earlier run (session 46: a scanning practitioner's rerun with
``--fair-smoothing off`` left every file as it was, without a word)."""

from __future__ import annotations

import json

from surfinpaint.app.batch_summary import option_changes
from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.io import write_mesh


def _batch(tmp_path, capsys, *options) -> str:
    assert main(["batch", str(tmp_path / "in"), "-o", str(tmp_path / "out"), "--jobs", "1",
                 "--method", "fair", *options]) == 0
    return capsys.readouterr().err


def test_a_rerun_with_other_options_names_the_files_it_kept_and_the_options(tmp_path, capsys):
    v, f = sphere(2)
    cut = cut_geodesic_disk(v, f, 0, 0.5)
    (tmp_path / "in").mkdir()
    for name in ("a", "b"):
        write_mesh(tmp_path / "in" / f"{name}.ply", cut.vertices, cut.faces)
    assert "warning" not in _batch(tmp_path, capsys)
    said = _batch(tmp_path, capsys, "--max-hole-edges", "50")
    assert (f"warning: 2 files were skipped as up to date ({tmp_path}/in/a.ply, "
            f"{tmp_path}/in/b.ply), but an earlier run filled them with other options "
            f"({tmp_path}/in/a.ply: max_hole_edges None -> 50): kept as they were; "
            "--overwrite refills them with this run's") in said
    # the skipped files keep the options they were filled with, also in the next rerun's
    files = json.loads((tmp_path / "out" / "summary.json").read_text())["files"]
    assert [f["options"]["max_hole_edges"] for f in files] == [None, None]
    assert "max_hole_edges None -> 50" in _batch(tmp_path, capsys, "--max-hole-edges", "50")
    assert "warning" not in _batch(tmp_path, capsys, "--max-hole-edges", "50", "--overwrite")
    assert "warning" not in _batch(tmp_path, capsys, "--max-hole-edges", "50")
    files = json.loads((tmp_path / "out" / "summary.json").read_text())["files"]
    assert [f["options"]["max_hole_edges"] for f in files] == [50, 50]


def test_option_changes_names_a_conformal_option_by_its_own_name():
    before = {"method": "conformal", "options": {"fair_smoothing": "auto", "creases": True}}
    now = {"method": "conformal", "options": {"fair_smoothing": None, "creases": True}}
    assert option_changes(before, now) == ["fair_smoothing 'auto' -> None"]
    assert option_changes(None, now) == []  # not known: an output no summary recorded
    assert option_changes(now, now) == []
