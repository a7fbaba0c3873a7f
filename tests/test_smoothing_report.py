"""A hole's report says whether its bilaplacian fill was the smoothing fill on a scan's
noise (``fair_smoothing``), and why: in the typed result, ``fill``'s text and ``--json``,
``batch``'s summary and ``report``'s page (session 46)."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest
from test_options import _noisy_sphere_hole

from surfinpaint import ConformalOptions, fill_holes
from surfinpaint.app.cli import main
from surfinpaint.app.report_page import HoleComparison, hole_title
from surfinpaint.data import sphere
from surfinpaint.fill.liepa.baseline import AUTO_SMOOTHING, NOISY_SIGMA, faired_fills
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.io import write_mesh


def _clean_sphere_hole():
    v, f = sphere(3)
    return cut_geodesic_disk(v, f, 0, 0.5)


def test_the_report_says_the_written_fill_was_smoothed_with_the_noise_that_decided():
    # seed 0: the self-check keeps the bilaplacian fill, which is the smoothing fill
    cut = _noisy_sphere_hole(0)
    result = fill_holes(cut.vertices, cut.faces)
    (r,) = result.reports
    assert r.outcome == "faired" and r.fair_order == 2 and r.smoothed
    assert r.smoothing.length == AUTO_SMOOTHING and r.smoothing.asked == "auto"
    assert NOISY_SIGMA <= r.smoothing.noise.relative and r.smoothing.noise.correlation < 0
    assert "read as a scanner's" in r.smoothing.why
    # what the report says is what was written: the smoothing fill's positions
    smoothed = faired_fills(cut.vertices, cut.faces, cut.loop, (2,),
                            smoothing=AUTO_SMOOTHING)[2][0]
    np.testing.assert_array_equal(result.vertices[len(cut.vertices):], smoothed)


def test_a_candidate_smoothed_but_not_written_and_a_clean_hole_say_so():
    # seed 1: the λ-H fill is written; its bilaplacian candidate was the smoothing fill
    cut = _noisy_sphere_hole(1)
    (r,) = fill_holes(cut.vertices, cut.faces).reports
    assert r.outcome == "lambda-h" and not r.smoothed
    assert r.smoothing.length == AUTO_SMOOTHING
    clean = _clean_sphere_hole()
    (r,) = fill_holes(clean.vertices, clean.faces).reports
    assert r.smoothing.length is None and not r.smoothed
    assert r.smoothing.noise.relative < NOISY_SIGMA and "a clean surface" in r.smoothing.why


def test_smoothing_given_off_or_as_a_length_is_reported_as_given():
    cut = _noisy_sphere_hole(0)
    off = fill_holes(cut.vertices, cut.faces, options=ConformalOptions(fair_smoothing=None))
    assert off.reports[0].smoothing is None and not off.reports[0].smoothed
    given = fill_holes(cut.vertices, cut.faces, options=ConformalOptions(fair_smoothing=0.5))
    s = given.reports[0].smoothing
    assert (s.length, s.asked, s.noise) == (0.5, 0.5, None)
    # the conventional baseline is never smoothed
    assert fill_holes(cut.vertices, cut.faces, method="fair").reports[0].smoothing is None


def test_fill_says_which_hole_was_smoothed_and_why_in_text_and_json(tmp_path, capsys):
    cut = _noisy_sphere_hole(0)
    write_mesh(tmp_path / "scan.ply", cut.vertices, cut.faces)
    assert main(["fill", str(tmp_path / "scan.ply"), "-o", str(tmp_path / "out.ply"),
                 "--json", str(tmp_path / "r.json")]) == 0
    said = capsys.readouterr().err
    assert "→ faired fill (bilaplacian, smoothed)" in said
    assert "  bilaplacian fill smoothed (length 0.35 edges): noise 0.0" in said
    assert "0 filled by the λ-H fill, 1 by a faired fill (1 smoothed)," in said
    (hole,) = json.loads((tmp_path / "r.json").read_text())["holes"]
    assert hole["smoothed"] is True
    assert hole["smoothing"]["length"] == AUTO_SMOOTHING and hole["smoothing"]["asked"] == "auto"
    assert NOISY_SIGMA <= hole["smoothing"]["noise"] and hole["smoothing"]["correlation"] < 0
    assert main(["fill", str(tmp_path / "scan.ply"), "-o", str(tmp_path / "off.ply"),
                 "--fair-smoothing", "off", "--json", str(tmp_path / "off.json")]) == 0
    assert "smoothed" not in capsys.readouterr().err
    (hole,) = json.loads((tmp_path / "off.json").read_text())["holes"]
    assert hole["smoothed"] is False and hole["smoothing"] is None


def test_fill_says_why_a_hole_was_not_smoothed_with_v_only(tmp_path, capsys):
    clean = _clean_sphere_hole()
    write_mesh(tmp_path / "ball.ply", clean.vertices, clean.faces)
    args = ["fill", str(tmp_path / "ball.ply"), "-o", str(tmp_path / "out.ply")]
    assert main(args) == 0
    assert "smoothed" not in capsys.readouterr().err  # a clean mesh's every hole: no line
    assert main([*args, "-v"]) == 0
    assert "  bilaplacian fill not smoothed: noise 0.00" in capsys.readouterr().err


def test_batch_counts_the_smoothed_holes_per_file(tmp_path):
    (tmp_path / "in").mkdir()
    cut, clean = _noisy_sphere_hole(0), _clean_sphere_hole()
    write_mesh(tmp_path / "in" / "scan.ply", cut.vertices, cut.faces)
    write_mesh(tmp_path / "in" / "ball.ply", clean.vertices, clean.faces)
    assert main(["batch", str(tmp_path / "in"), "-o", str(tmp_path / "out"), "--jobs", "1",
                 "-qq"]) == 0
    with open(tmp_path / "out" / "summary.csv", newline="") as handle:
        rows = {row["path"].rsplit("/", 1)[-1]: row for row in csv.DictReader(handle)}
    assert (rows["scan.ply"]["smoothed"], rows["ball.ply"]["smoothed"]) == ("1", "0")
    files = json.loads((tmp_path / "out" / "summary.json").read_text())["files"]
    smoothed = {f["path"].rsplit("/", 1)[-1]: [h["smoothed"] for h in f["holes"]]
                for f in files}
    assert smoothed == {"scan.ply": [True], "ball.ply": [False]}


@pytest.mark.parametrize(("smoothed", "said"), [(True, "(order 2, smoothed) is written (W)"),
                                                (False, "(order 2) is written (W)")])
def test_the_report_page_says_the_written_fill_was_smoothed(smoothed, said):
    c = HoleComparison(index=1, n_edges=24, diameter=0.05, kept=False,
                       fallback="self-check (sibling holes) preferred the faired fill",
                       fair_order=2, written_panel="W", smoothed=smoothed)
    assert said in hole_title(c)


def test_a_fill_results_repr_counts_the_smoothed_fills():
    cut = _noisy_sphere_hole(0)
    assert "1 hole: 1 faired (1 smoothed))" in repr(fill_holes(cut.vertices, cut.faces))
    clean = _clean_sphere_hole()
    assert "smoothed" not in repr(fill_holes(clean.vertices, clean.faces))


def test_the_pictures_overview_says_the_fills_in_the_close_ups_words():
    # it said the --method names ("filled: fair") where the close-ups say "faired fill"
    from surfinpaint import before_after_figure

    cut = _noisy_sphere_hole(0)
    result = fill_holes(cut.vertices, cut.faces)
    titles = [ax.get_title() for ax in before_after_figure(cut.vertices, cut.faces,
                                                           result).axes]
    assert "filled: 1 faired fill (1 smoothed)" in titles
    assert "after: faired fill (bilaplacian, smoothed)" in titles[-1]


def test_report_takes_fair_smoothing_and_draws_the_fill_fill_writes_with_it(tmp_path, capsys):
    cut = _noisy_sphere_hole(0)
    write_mesh(tmp_path / "scan.ply", cut.vertices, cut.faces)
    for option, said in (("auto", "(order 2, smoothed) is written"),
                         ("off", "(order 2) is written")):
        assert main(["report", str(tmp_path / "scan.ply"), "-o", str(tmp_path / option),
                     "--fair-smoothing", option]) == 0
        assert said in capsys.readouterr().err
