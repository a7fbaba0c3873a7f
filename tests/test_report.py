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
    panel_fills,
    table_rows,
)
from surfinpaint.app.report_page import WRITTEN_ERROR, PageSection, TruthDistance
from surfinpaint.data import lens, sphere
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
    errors = {name: TruthDistance(m, 2 * m)
              for name, m in (("fair", 0.3), ("conformal", 0.2), ("conformal raw", 0.5))}
    rejected = HoleComparison(index=2, n_edges=40, diameter=1.5, kept=False,
                              fallback="self-check (hidden rings) preferred ...", fair_order=3,
                              errors=errors, written_panel="W")
    title = hole_title(rejected, "snowman")
    assert title.startswith("snowman: hole 2, 40 boundary edges")
    assert "rejected the λ-H fill; the faired fill (order 3) is written (W)" in title
    assert "(B) 0.3 / 0.6, (C) 0.5 / 1, (W, written) 0.2 / 0.4" in title
    bilaplacian = HoleComparison(index=2, n_edges=40, diameter=1.5, kept=False, fair_order=2,
                                 fallback=rejected.fallback, errors=errors, written_panel="B")
    assert "(B, written) 0.3 / 0.6, (C) 0.5 / 1" in hole_title(bilaplacian)
    failed = HoleComparison(index=0, n_edges=9, diameter=1.0, kept=False,
                            fallback="FillError: folds", fair_order=2)
    assert "the λ-H fill failed; the faired fill (order 2) is written" in hole_title(failed)
    assert "(C) is written" in hole_title(HoleComparison(index=0, n_edges=9, diameter=1.0))
    kept = HoleComparison(index=0, n_edges=9, diameter=1.0, errors=errors)
    assert "(B) 0.3 / 0.6, (C, written) 0.5 / 1" in hole_title(kept)


def test_a_hole_with_no_vertex_inside_is_titled_as_its_triangulation():
    # no λ-H fill failed there and no self-check ran: every candidate is the triangulation
    from surfinpaint.fill.conformal.method import NO_INNER_VERTEX

    v, f = sphere(3)
    kept = np.delete(f, [0], axis=0)  # a hole of one face: 3 edges, no vertex inside
    (comparison,), _ = compare_holes(v, kept, [np.array(f[0][::-1])])
    assert comparison.new_vertices == {"fair": 0, "conformal": 0}
    title = hole_title(comparison)
    assert f"{NO_INNER_VERTEX}; the triangulation is written" in title
    assert "failed" not in title and "rejected" not in title


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
            assert 0 < e.mean < 3.0, (method, e)
            assert e.mean <= e.hausdorff
    # what `fill` writes is the conformal fill where the self-check kept it, and the
    # method's own (triharmonic) faired fill elsewhere
    written = fills.conformal
    offset = written.n_original_vertices
    for c, hole, report in zip(comparisons, cut.holes, written.reports, strict=True):
        new = written.vertices[offset: offset + report.new_vertices]
        offset += report.new_vertices
        # not on a plane: (C) draws the λ-H fill, kept or rejected by the self-check
        assert not c.on_plane
        assert panel_fills(fills, c.index).conformal is fills.lambda_h_fills[c.index]
        if c.kept:
            assert c.errors["conformal"] == c.errors["conformal raw"]
            assert c.written_panel == "C" and panel_fills(fills, c.index).written is None
        else:
            alone = fill_holes(cut.vertices, cut.faces, holes=[hole.loop], method="fair",
                               fair_order=3)
            assert np.array_equal(new, alone.vertices[len(cut.vertices):])
    # each fill's vertices start with the mesh's, unchanged
    for name in ("fair", "conformal", "conformal raw"):
        for fill_v, fill_f in fills.by_method()[name]:
            assert np.array_equal(fill_v[: len(cut.vertices)], cut.vertices)
            assert fill_f.max() < len(fill_v)


@pytest.fixture(scope="module")
def lens_holes():
    """Three holes in the lens where the self-check wrote, in turn, the λ-H fill, the
    trilaplacian fill and the bilaplacian fill (measured; asserted where used)."""
    from surfinpaint.geometry.mesh import mean_edge_length

    v, f = lens()
    h = mean_edge_length(v, f)
    cut = cut_holes(v, f, [15, 872, 2762], [5.0 * h, 3.1 * h, 3.135 * h])
    truth = [(x.truth_vertices, x.truth_faces) for x in cut.holes]
    comparisons, fills = compare_holes(cut.vertices, cut.faces, [x.loop for x in cut.holes],
                                       truth=truth)
    return cut, comparisons, fills


def _patch(vertices, faces):
    """A fill's new faces over its own vertices only (as the report measures it)."""
    ids, inverse = np.unique(faces, return_inverse=True)
    return vertices[ids], inverse.reshape(-1, 3)


def test_every_hole_panel_draws_the_written_fill(lens_holes, tmp_path, monkeypatch):
    # `surfinpaint report`: the fill `fill` writes is drawn in a panel titled "written":
    # (C) where the λ-H fill is kept, (B) where it is exactly the conventional fill, a
    # fourth panel (W) where it is neither (the trilaplacian fill); (C) keeps the rejected
    # λ-H fill, for comparison
    monkeypatch.delenv("DISPLAY", raising=False)
    from surfinpaint.app import report

    cut, comparisons, fills = lens_holes
    outcomes = [(r.method, r.fair_order, r.fallback) for r in fills.conformal.reports]
    assert outcomes == [("conformal", None, None), ("fair", 3, None), ("fair", 2, None)]
    written = fill_holes(cut.vertices, cut.faces, holes=[x.loop for x in cut.holes],
                         method="conformal")
    drawn = [panel_fills(fills, k) for k in range(3)]
    assert [c.written_panel for c in comparisons] == [d.written_in for d in drawn] == \
        ["C", "W", "B"]
    for k, d in enumerate(drawn):
        shown = {"B": d.fair, "C": d.conformal, "W": d.written}[d.written_in]
        # the panel that says "written" draws what `fill` writes, face for face
        want_v, want_f = _patch(written.vertices, written.hole_faces()[k])
        got_v, got_f = _patch(*shown)
        np.testing.assert_array_equal(got_f, want_f)
        np.testing.assert_array_equal(got_v, want_v)
    # λ-H fill written: as before, (C) draws it, no fourth panel
    assert drawn[0].conformal is fills.lambda_h_fills[0]
    assert drawn[0].written is None and drawn[0].titles == {"C": "(C) conformal fill (written)"}
    # trilaplacian fill written: (B) and (C) draw other fills, (W) draws it
    assert not np.array_equal(_patch(*drawn[1].fair)[0], _patch(*drawn[1].written)[0])
    assert drawn[1].conformal is fills.lambda_h_fills[1]
    assert drawn[1].titles == {"C": "(C) conformal fill (rejected by the self-check)",
                               "W": "(W) written: faired fill (order 3)"}
    # bilaplacian fill written: it is (B)'s, titled so
    assert drawn[2].written is None
    assert drawn[2].titles["B"] == "(B) conventional fill (faired, written)"
    # the page's written column and the title's written panel give the written fill's error
    header, rows = table_rows(comparisons)
    for c, row, panel in zip(comparisons, rows, "CWB", strict=True):
        assert f"({panel}, written) {row[header.index(WRITTEN_ERROR)]}" in hole_title(c)
    assert comparisons[2].errors["conformal"] == comparisons[2].errors["fair"]

    given = []
    hole_panel = report.hole_panel

    def spy(*args, **kwargs):  # draws, and records what it was given
        given.append(kwargs)
        return hole_panel(*args, **kwargs)

    monkeypatch.setattr(report, "hole_panel", spy)
    report.panels_for(cut.vertices, cut.faces, comparisons, fills, tmp_path)
    assert [g["written"] is d.written for g, d in zip(given, drawn, strict=True)] == [True] * 3
    import matplotlib.image

    for c, panels in zip(comparisons, (3, 4, 3), strict=True):
        top = matplotlib.image.imread(tmp_path / c.picture)[:PANEL_SIZE[1] // 2, :, :3]
        orange = (top[..., 0] > 0.6) & (top[..., 1] > 0.25) & (top[..., 1] < 0.6) & (
            top[..., 2] < 0.35)
        # the top row's panels: A without a fill (only its border's antialiased edge is
        # orange-ish), then one fill each
        hole, *filled = [int(part.sum()) for part in np.array_split(orange, panels, axis=1)]
        assert min(filled) > 10 * hole, (hole, filled)


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
    assert WRITTEN_ERROR in md


def test_report_takes_repair_as_holes_and_fill_do(holed_sphere, tmp_path):
    # a fin on the holed sphere: the error says --repair, which `report` did not take
    v, f, cut = holed_sphere
    a, b = cut.faces[0, :2]
    fin_v = np.vstack([cut.vertices, (cut.vertices[a] + cut.vertices[b]) / 2 * 1.2])
    fin_f = np.vstack([cut.faces, [a, b, len(cut.vertices)]])
    write_mesh(tmp_path / "fin.ply", fin_v, fin_f)
    parser = argparse.ArgumentParser()
    add_report_parser(parser.add_subparsers())
    out = tmp_path / "report"
    args = parser.parse_args(["report", str(tmp_path / "fin.ply"), "-o", str(out), "-q"])
    with pytest.raises(MeshError, match="1 non-manifold edge .*--repair"):
        args.func(args)
    args = parser.parse_args(["report", str(tmp_path / "fin.ply"), "-o", str(out), "-q",
                              "--repair", "--holes", "0"])
    assert args.func(args) == 0
    assert (out / "hole0.png").is_file() and (out / "index.html").is_file()


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
    md, page = write_page(tmp_path, [PageSection("Holes", comparisons=comparisons)], "t")
    text = md.read_text()
    assert "(hole3.png)" in text and "(hole5.png)" in text
    assert text.index("(hole3.png)") < text.index("(hole5.png)")
    assert 'src="hole5.png"' in page.read_text()
    assert not list(tmp_path.glob("*.tmp"))


def _fills_that_warn(monkeypatch, said: dict) -> None:
    """Make ``report``'s fills warn, besides their own warnings, ``said[method]``: (text,
    category) pairs, each time a fill of that method runs."""
    import warnings

    from surfinpaint.app import report as report_module

    real = report_module.fill_holes

    def fill_and_warn(*args, **kwargs):
        for text, category in said.get(kwargs.get("method"), ()):
            warnings.warn(text, category, stacklevel=2)
        return real(*args, **kwargs)

    monkeypatch.setattr(report_module, "fill_holes", fill_and_warn)


# what each fill warns, and how `report` must say each (after "warning: odd.ply: ")
FILLS_WARN = {"fair": [("hole 0: the conventional fill's own", UserWarning),
                       ("hole 0: a conventional HoleWarning", "HoleWarning"),
                       ("hole 0: said by both", UserWarning)],
              "conformal": [("hole 0: the conformal fill's own", UserWarning),
                            ("hole 0: said by both", UserWarning)]}
FILLS_SAID = ["hole 0: the conformal fill's own (conformal fill)",
              "hole 0: said by both",
              "hole 0: the conventional fill's own (conventional fill)",
              "hole 0: a conventional HoleWarning (conventional fill)"]


@pytest.mark.parametrize("quiet", [[], ["-q"]])
def test_report_says_the_warnings_of_both_fills_each_once_saying_which(tmp_path, capsys,
                                                                       monkeypatch, quiet):
    # session 40: only the conformal (written) fill's warnings were said; the conventional
    # fill's, which the page draws beside it, were dropped
    from test_cli_messages import DEGENERATE, _odd

    from surfinpaint.app.cli import main
    from surfinpaint.errors import HoleWarning

    monkeypatch.chdir(tmp_path)
    _odd(tmp_path / "odd.ply")
    _fills_that_warn(monkeypatch, {method: [
        (text, HoleWarning if category == "HoleWarning" else category)
        for text, category in said] for method, said in FILLS_WARN.items()})
    assert main(["report", "odd.ply", "-o", "r", *quiet]) == 0
    warned = [line for line in capsys.readouterr().err.splitlines()
              if line.startswith("warning:")]
    # each once, in this order, the conventional fill's HoleWarning too (a title says the
    # written fill only); the mesh's own warning as before, once
    assert [line for line in warned if DEGENERATE not in line] == [
        f"warning: odd.ply: {text}" for text in FILLS_SAID], warned
    assert sum(DEGENERATE in line for line in warned) == 1, warned
    listed = (tmp_path / "r" / "index.md").read_text("utf-8").split("## Warnings")[1]
    assert [line[2:] for line in listed.splitlines()
            if line.startswith("- hole 0: ")] == FILLS_SAID


@pytest.mark.parametrize(("conformal", "conventional", "said"), [
    ({}, {}, {}),
    ({"a": UserWarning}, {"a": UserWarning}, {"a": UserWarning}),  # both: as it is
    ({"a": UserWarning}, {}, {"a (conformal fill)": UserWarning}),
    ({}, {"a": UserWarning}, {"a (conventional fill)": UserWarning}),
    ({}, {"a": "HoleWarning"}, {"a (conventional fill)": UserWarning}),  # not left to a title
    ({"a": "HoleWarning"}, {}, {"a (conformal fill)": "HoleWarning"}),
    ({"b": UserWarning, "a": UserWarning}, {"a": UserWarning, "c": UserWarning},
     {"b (conformal fill)": UserWarning, "a": UserWarning, "c (conventional fill)": UserWarning}),
])
def test_fills_warnings(conformal, conventional, said):
    from surfinpaint.app.report_warnings import fills_warnings
    from surfinpaint.errors import HoleWarning

    def typed(warned):
        return {text: HoleWarning if c == "HoleWarning" else c for text, c in warned.items()}

    got = fills_warnings(typed(conformal), typed(conventional))
    assert list(got.items()) == list(typed(said).items())
