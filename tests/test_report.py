"""`surfinpaint report`: both fills per hole, drawn off-screen, indexed by a page."""

from __future__ import annotations

import argparse
import struct

import numpy as np
import pytest

from surfinpaint.app.report import (
    PANEL_SIZE,
    HoleComparison,
    add_report_parser,
    compare_holes,
    hole_title,
    hole_truths,
    panel_c_fill,
    table_rows,
)
from surfinpaint.data import sphere
from surfinpaint.errors import MeshError
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.io.formats import write_mesh


def png_size(path) -> tuple[int, int]:
    with open(path, "rb") as handle:
        head = handle.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    return struct.unpack(">II", head[16:24])


@pytest.fixture(scope="module")
def holed_sphere():
    v, f = sphere(3)
    cut = cut_holes(v, f, [np.array([0, 0, 1.0]), np.array([1.0, 0, 0])], [0.45, 0.35])
    return v, f, cut


def test_hole_truths_recovers_the_removed_patches(holed_sphere):
    v, f, cut = holed_sphere
    truths = hole_truths(cut.vertices, cut.faces, [h.loop for h in cut.holes], v, f)
    for hole, (tv, tf) in zip(cut.holes, truths, strict=True):
        assert len(tf) == len(hole.truth_faces)
        assert np.allclose(np.sort(tv, axis=0), np.sort(hole.truth_vertices, axis=0))


def test_hole_truths_rejects_an_unrelated_truth(holed_sphere):
    v, f, cut = holed_sphere
    with pytest.raises(MeshError, match="truth"):
        hole_truths(cut.vertices, cut.faces, [h.loop for h in cut.holes], 2.0 * v, f)


def test_hole_title_says_which_fill_is_written():
    errors = {name: {"mean": m, "hausdorff": 2 * m}
              for name, m in (("fair", 0.3), ("conformal", 0.2), ("conformal raw", 0.5))}
    rejected = HoleComparison(index=2, n_edges=40, diameter=1.5, kept=False,
                              fallback="self-check (hidden rings) preferred ...", fair_order=3,
                              errors=errors)
    title = hole_title(rejected, "snowman")
    assert title.startswith("snowman: hole 2, 40 boundary edges")
    assert "rejected the λ-H fill; the faired fill (order 3) is written" in title
    assert "(B) 0.3 / 0.6, (C) 0.5 / 1, written 0.2 / 0.4" in title
    failed = HoleComparison(index=0, n_edges=9, diameter=1.0, kept=False,
                            fallback="FillError: folds", fair_order=2)
    assert "the λ-H fill failed; the faired fill (order 2) is written" in hole_title(failed)
    assert "(C) is written" in hole_title(HoleComparison(index=0, n_edges=9, diameter=1.0))


def test_compare_holes_measures_both_fills(holed_sphere):
    _, _, cut = holed_sphere
    truth = [(h.truth_vertices, h.truth_faces) for h in cut.holes]
    comparisons, fills = compare_holes(cut.vertices, cut.faces, [h.loop for h in cut.holes],
                                       truth=truth)
    assert [c.index for c in comparisons] == [0, 1]
    for c, hole in zip(comparisons, cut.holes, strict=True):
        # the page says what was written in the words of `fill`'s report, no jargon
        outcome = table_rows([c])[1][0][5]
        assert outcome.startswith("λ-H fill; self-check on hidden rings: λ-H " if c.kept
                                  else "faired fill (")
        assert "fair2" not in outcome and "inf" not in outcome
        assert c.n_edges == len(hole.loop)
        assert c.diameter == pytest.approx(hole.diameter, rel=1e-9)
        assert set(c.errors) == {"fair", "conformal", "conformal raw"}
        # a sphere cap fill is within a few % of the hole diameter of the truth; the
        # patch-vs-nothing distance would be ~ the cap height, 10-20 %
        for method, e in c.errors.items():
            assert 0 < e["mean"] < 3.0, (method, e)
            assert e["mean"] <= e["hausdorff"]
    # what `fill` writes is the conformal fill where the self-check kept it, and the
    # method's own (triharmonic) faired fill elsewhere
    written = fills["conformal"]
    offset = written.n_original_vertices
    for c, hole, report in zip(comparisons, cut.holes, written.reports, strict=True):
        new = written.vertices[offset: offset + report.new_vertices]
        offset += report.new_vertices
        # not on a plane: (C) draws the λ-H fill, kept or rejected by the self-check
        assert not c.on_plane
        assert panel_c_fill(c, fills, c.index) is fills["filled"]["conformal raw"][c.index]
        if c.kept:
            assert c.errors["conformal"] == c.errors["conformal raw"]
        else:
            alone = fill_holes(cut.vertices, cut.faces, holes=[hole.loop], method="fair",
                               fair_order=3)
            assert np.array_equal(new, alone.vertices[len(cut.vertices):])
    # each fill's vertices start with the mesh's, unchanged
    for name in ("fair", "conformal", "conformal raw"):
        for fill_v, fill_f in fills["filled"][name]:
            assert np.array_equal(fill_v[: len(cut.vertices)], cut.vertices)
            assert fill_f.max() < len(fill_v)


def test_report_runs_headless_and_indexes_its_pictures(holed_sphere, tmp_path, monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    v, f, cut = holed_sphere
    write_mesh(tmp_path / "holes.ply", cut.vertices, cut.faces)
    write_mesh(tmp_path / "truth.ply", v, f)
    parser = argparse.ArgumentParser()
    add_report_parser(parser.add_subparsers())
    out = tmp_path / "report"
    args = parser.parse_args(["report", str(tmp_path / "holes.ply"), "-o", str(out),
                              "--truth", str(tmp_path / "truth.ply"), "-q"])
    assert args.func(args) == 0
    pictures = sorted(out.glob("hole*.png"))
    assert [p.name for p in pictures] == ["hole0.png", "hole1.png"]
    import matplotlib.image

    for picture in pictures:
        assert png_size(picture) == PANEL_SIZE
        image = matplotlib.image.imread(picture)[..., :3]
        top = image[: image.shape[0] // 2]
        third = top.shape[1] // 3
        # panel A faces the hole: its red boundary outline is in view
        red = (top[:, :third, 0] > 0.6) & (top[:, :third, 1] < 0.35) & (top[:, :third, 2] < 0.35)
        assert red.sum() > 200
        # panels B and C show the orange fill
        for k in (1, 2):
            part = top[:, k * third:(k + 1) * third]
            orange = (part[..., 0] > 0.6) & (part[..., 1] > 0.25) & (part[..., 1] < 0.6) & (
                part[..., 2] < 0.35)
            assert orange.sum() > 300
        # the λ/H images are not blank
        bottom = image[image.shape[0] // 2:]
        assert (bottom.std(axis=(0, 1)) > 0.05).all()
    md = (out / "index.md").read_text()
    page = (out / "index.html").read_text()
    for name in ("hole0.png", "hole1.png"):
        assert f"({name})" in md
        assert f'src="{name}"' in page
    assert "fair mean / Hd %" in md and "conformal raw mean / Hd %" in md


def test_report_cli_rejects_bad_hole_list(tmp_path):
    parser = argparse.ArgumentParser()
    add_report_parser(parser.add_subparsers())
    with pytest.raises(SystemExit) as exc:
        parser.parse_args(["report", "x.ply", "-o", str(tmp_path), "--holes", "1,a"])
    assert exc.value.code == 2


def test_panel_without_a_conformal_fill(holed_sphere, tmp_path, monkeypatch):
    monkeypatch.delenv("DISPLAY", raising=False)
    from surfinpaint.app.report import hole_panel
    from surfinpaint.fill.pipeline import fill_holes

    _, _, cut = holed_sphere
    loop = cut.holes[0].loop
    fair = fill_holes(cut.vertices, cut.faces, holes=[loop], method="fair")
    path = hole_panel(cut.vertices, cut.faces, loop, (fair.vertices, fair.new_faces), None,
                      None, tmp_path / "panel.png")
    assert png_size(path) == PANEL_SIZE
    assert not list(tmp_path.glob("*.tmp")) and len(list(tmp_path.iterdir())) == 1


def test_page_without_truth_has_no_error_columns(tmp_path):
    from surfinpaint.app.report import HoleComparison, table_rows, write_page

    comparisons = [
        HoleComparison(index=3, n_edges=12, diameter=0.5, seconds={"fair": 0.1, "conformal": 1},
                       new_vertices={"fair": 4, "conformal": 4}, kept=True,
                       scores={"conformal": 0.01, "fair": 0.02}, picture="hole3.png"),
        HoleComparison(index=5, n_edges=30, diameter=1.5, seconds={"fair": 0.2, "conformal": 2},
                       new_vertices={"fair": 9, "conformal": 9}, kept=False,
                       fallback="FillError: folds", picture="hole5.png"),
    ]
    header, rows = table_rows(comparisons)
    assert not any("mean" in h for h in header)
    assert [r[0] for r in rows] == ["3", "5"]
    assert "kept" in rows[0][-1] and "FillError: folds" in rows[1][-1]
    md, page = write_page(tmp_path, [{"title": "Holes", "comparisons": comparisons}], "t")
    text = md.read_text()
    assert "(hole3.png)" in text and "(hole5.png)" in text
    assert text.index("(hole3.png)") < text.index("(hole5.png)")
    assert 'src="hole5.png"' in page.read_text()
    assert not list(tmp_path.glob("*.tmp"))
