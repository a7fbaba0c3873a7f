"""The report's page: a row per hole (sizes, times, the self-check's outcome and, given the
ground truth, each fill's distance to it) in ``index.md`` and ``index.html``, and the line
that titles each hole's panel."""

from __future__ import annotations

import html
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import numpy as np

from surfinpaint.errors import agreeing, how_many
from surfinpaint.fill.conformal.method import NO_INNER_VERTEX
from surfinpaint.io.atomic import atomic_open

__all__ = ["LEGEND", "NOT_MEASURED", "WRITTEN_ERROR", "HoleComparison", "PageSection",
           "TruthDistance", "WrittenPanel", "hole_title", "table_rows", "write_page"]

#: The 3D panel of a hole that draws the fill ``surfinpaint fill`` writes: (B) the
#: conventional fill, (C) the conformal method's own, (W) a panel of its own; None where
#: nothing is written.
WrittenPanel = Literal["B", "C", "W"] | None


@dataclass
class HoleComparison:
    """Both fills of one hole, measured.

    Attributes
    ----------
    index : int
        Position in the list of holes filled (:func:`write_report` renumbers holes chosen
        by index with those indices, the numbering of ``surfinpaint holes``).
    n_edges : int
        Boundary edges of the hole.
    diameter : float
        Largest distance between two boundary vertices.
    seconds : dict
        Wall time per method (``"fair"``, ``"conformal"``; the conformal time includes its
        self-check).
    new_vertices : dict
        Vertices added per method.
    kept : bool
        Whether the conformal method kept its own fill (False: it failed, or its self-check
        preferred the faired fill; ``fallback`` says which).
    fallback : str or None
        Why the conformal method used the faired fill.
    scores : dict
        The self-check's tests that ran (``"hidden_rings"``, ``"sibling_holes"``), each a
        dict of the errors of its candidates (``"conformal"``, ``"fair2"``, ``"fair3"``).
    fair_order : int or None
        Fairing order of the faired fill the conformal method wrote (None: it kept its own).
    errors : dict of str to TruthDistance
        With a ground truth: per fill (``"fair"``, ``"conformal"`` = what ``fill`` writes,
        ``"conformal raw"`` = the λ-H fill before the self-check and the plane test) its
        :class:`TruthDistance`.
    picture : str or None
        File name of the panel.
    written : str or None
        What the conformal method wrote, and its self-check, in the words of ``surfinpaint
        fill``'s report (:mod:`surfinpaint.app.fill_report`); None: from ``kept`` and
        ``fallback``.
    on_plane : bool
        The conformal method laid the faired fill on the plane of the surface around the
        hole (its plane test; no self-check ran): that laid fill is written, and panel (C)
        draws it.
    written_panel : {"B", "C", "W"} or None
        The panel that draws the written fill (:func:`surfinpaint.app.report.panel_fills`):
        (C) where it is the conformal method's own, (B) where it is exactly the
        conventional fill, else (W); None where nothing is written.
    skipped : str or None
        Why nothing was written: the hole was skipped or its fill failed (as
        ``surfinpaint fill`` says it, :attr:`~surfinpaint.fill.results.HoleReport.skipped`);
        None: a fill was written.
    islands : tuple of int
        The loops (by number) of the islands the hole was filled with
        (:attr:`~surfinpaint.fill.results.HoleReport.islands`: a faired fill, the λ-H
        method filling disks only); empty for a hole filled as a disk.
    crossings : int
        The written fill's triangles that cross the surface or another hole's fill
        (:attr:`~surfinpaint.fill.results.HoleReport.crossings`; 0 for a clean fill).
    smoothed : bool
        The written fill is the bilaplacian smoothing fill
        (:attr:`~surfinpaint.fill.results.HoleReport.smoothed`): not the conventional
        fill (B), which goes through the surface's noise.
    ear_cut : str or None
        The ear-cut rule that wrote the loop's ear-cut fill
        (:attr:`~surfinpaint.fill.results.HoleReport.ear_cut`; no self-check ran), if one did.
    """

    index: int
    n_edges: int
    diameter: float
    seconds: dict = field(default_factory=dict)
    new_vertices: dict = field(default_factory=dict)
    kept: bool = True
    fallback: str | None = None
    scores: dict = field(default_factory=dict)
    fair_order: int | None = None
    errors: dict[str, TruthDistance] = field(default_factory=dict)
    picture: str | None = None
    written: str | None = None
    on_plane: bool = False
    written_panel: WrittenPanel = "C"
    skipped: str | None = None
    islands: tuple[int, ...] = ()
    crossings: int = 0
    smoothed: bool = False
    ear_cut: str | None = None


@dataclass(frozen=True)
class TruthDistance:
    """A fill's distance to the removed surface, in % of the hole's diameter
    (:attr:`HoleComparison.errors`); NaN where it was not measured (no truth, or no fill).

    Attributes
    ----------
    mean : float
        The two-sided mean distance (the benchmarks' error).
    hausdorff : float
        The largest distance either way.
    """

    mean: float
    hausdorff: float

    @property
    def measured(self) -> bool:
        """Whether there was a fill and a truth to measure."""
        return bool(np.isfinite(self.mean))


NOT_MEASURED = TruthDistance(float("nan"), float("nan"))


def _fmt(x: float, digits: int = 3) -> str:
    return "–" if x is None or not np.isfinite(x) else f"{x:.{digits}g}"


def _outcome(c: HoleComparison) -> str:
    if c.written:
        return c.written
    if c.kept:
        return "kept" + (f" ({c.fallback})" if c.fallback else "")
    if c.fallback and c.fallback.startswith("self-check"):
        return f"faired fill kept: {c.fallback}"
    return f"fell back to fair after a failure ({c.fallback})"


def _error_text(c: HoleComparison, method: str) -> str:
    """"mean / Hausdorff" of one fill; "no truth" or "failed" when not measured."""
    if not c.errors or not c.errors["fair"].measured:
        return "no truth"
    e = c.errors[method]
    if not e.measured:
        return "failed"
    return f"{_fmt(e.mean)} / {_fmt(e.hausdorff)}"


# the error column of the fill `surfinpaint fill` writes (the "conformal" errors)
WRITTEN_ERROR = "written (conformal) mean / Hd %"


def table_rows(comparisons: Sequence[HoleComparison]) -> tuple[list[str], list[list[str]]]:
    """Header and rows of the per-hole table (strings), errors included when measured."""
    with_truth = any(c.errors for c in comparisons)
    header = ["hole", "edges", "diameter", "fair: new v, s", "conformal: new v, s",
              "conformal outcome"]
    if with_truth:
        header += ["fair mean / Hd %", WRITTEN_ERROR, "conformal raw mean / Hd %"]
    rows = []
    for c in comparisons:
        row = [str(c.index), str(c.n_edges), _fmt(c.diameter),
               f"{c.new_vertices['fair']}, {c.seconds['fair']:.2f}",
               f"{c.new_vertices['conformal']}, {c.seconds['conformal']:.2f}", _outcome(c)]
        if with_truth:
            row += [_error_text(c, m) for m in ("fair", "conformal", "conformal raw")]
        rows.append(row)
    return header, rows


def _markdown_table(header, rows) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def _html_table(header, rows) -> str:
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(x)}</td>" for x in r) + "</tr>"
                   for r in rows)
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


LEGEND = (
    "Panels: (A) the surface with the hole, (B) the conventional fill (Liepa: triangulate, "
    "refine, fair), (C) the conformal λ-H fill, all from one camera facing the hole (fill "
    "in orange, hole border in red); (D)/(E) the conformal factor λ and (F)/(G) the mean "
    "curvature H over the patch's conformal parameter domain, initial (from the known "
    "surface only: grey where there is no value) and after inpainting; solid outline: the "
    "hole, dashed: the region whose values are inpainted. The conformal method's self-check "
    "keeps its fill where it beats the bilaplacian faired fill on two tests that use no "
    "truth (hidden rings of known surface around the hole, and sibling holes of the same "
    "size cut from the known surface nearby); when it kept a faired fill, (C) shows the "
    "conformal fill it rejected. Where the known surface around the hole is a plane within "
    "its noise, the method writes the bilaplacian faired fill laid on that plane and runs "
    "no self-check: (C) shows that laid fill, (E)/(G) the λ-H fill, which is not written. "
    "The panel that draws the fill `surfinpaint fill` writes is titled 'written': (C), or "
    "(B) where the written faired fill is exactly the conventional fill, or else (W), a "
    "fourth panel (the trilaplacian faired fill, as a rule). "
    "Errors: two-sided mean and Hausdorff distance to the removed truth, in % of the hole "
    "diameter; 'written (conformal)' is what `surfinpaint fill` writes, 'conformal raw' "
    "the λ-H fill before the self-check and the plane test."
)


def _write_text(path: Path, text: str) -> None:
    with atomic_open(path, "w", encoding="utf-8") as handle:
        handle.write(text)


@dataclass(frozen=True)
class PageSection:
    """One section of a page (:func:`write_page`), drawn in this order.

    Attributes
    ----------
    title : str
    text : str
        A paragraph.
    items : sequence of str
        Lines shown as a list (the warnings).
    comparisons : sequence of HoleComparison
        Shown as a table, followed by their pictures.
    table : (header, rows) or None
        A table of strings.
    pictures : sequence of str
        File names relative to the page's folder, after the comparisons' pictures.
    """

    title: str
    text: str = ""
    items: Sequence[str] = ()
    comparisons: Sequence[HoleComparison] = ()
    table: tuple[list[str], list[list[str]]] | None = None
    pictures: Sequence[str] = ()


def write_page(out_dir: str | os.PathLike,
               sections: Sequence[PageSection], title: str, intro: str = "") -> tuple[Path, Path]:
    """Write ``index.md`` and ``index.html`` in ``out_dir``, one :class:`PageSection` after
    another."""
    out_dir = Path(out_dir)
    md = [f"# {title}", ""]
    body = [f"<h1>{html.escape(title)}</h1>"]
    if intro:
        md += [intro, ""]
        body.append(f"<p>{html.escape(intro)}</p>")
    for section in sections:
        md += [f"## {section.title}", ""]
        body.append(f"<h2>{html.escape(section.title)}</h2>")
        if section.text:
            md += [section.text, ""]
            body.append(f"<p>{html.escape(section.text)}</p>")
        if section.items:
            md += [f"- {item}" for item in section.items] + [""]
            body.append("<ul>" + "".join(f"<li>{html.escape(item)}</li>"
                                         for item in section.items) + "</ul>")
        tables = []
        pictures = list(section.pictures)
        if section.comparisons:
            tables.append(table_rows(section.comparisons))
            pictures = [c.picture for c in section.comparisons if c.picture] + pictures
        if section.table:
            tables.append(section.table)
        for header, rows in tables:
            md += [_markdown_table(header, rows), ""]
            body.append(_html_table(header, rows))
        for picture in pictures:
            md += [f"![{picture}]({picture})", ""]
            body.append(f'<p><a href="{html.escape(picture)}"><img src="{html.escape(picture)}"'
                        f' alt="{html.escape(picture)}" width="100%"></a></p>')
    style = ("body{font-family:sans-serif;max-width:1650px;margin:auto}table{border-collapse:"
             "collapse}td,th{border:1px solid #999;padding:3px 8px;text-align:right}")
    page = ("<!DOCTYPE html><html><head><meta charset='utf-8'>"
            f"<title>{html.escape(title)}</title><style>{style}</style></head><body>"
            + "\n".join(body) + "</body></html>\n")
    out_dir.mkdir(parents=True, exist_ok=True)
    _write_text(out_dir / "index.md", "\n".join(md))
    _write_text(out_dir / "index.html", page)
    return out_dir / "index.md", out_dir / "index.html"


def hole_title(c: HoleComparison, name: str = "") -> str:
    """One line that says what a hole panel shows, with its numbers."""
    if c.skipped:
        written = f"nothing is written: {c.skipped}"
    elif c.kept:
        written = "the λ-H fill (C) is written"
    else:
        order = (f" (order {c.fair_order}{', smoothed' if c.smoothed else ''})"
                 if c.fair_order else "")
        if c.on_plane:
            written = (f"the surface around it is a plane within its noise; the faired "
                       f"fill{order} laid on it is written")
        elif c.ear_cut:  # nothing failed: a rule wrote it before any self-check
            written = f"the ear-cut fill ({c.ear_cut}) is written"
        elif c.fallback == NO_INNER_VERTEX:  # nothing failed, nothing to choose
            written = f"{NO_INNER_VERTEX}; the triangulation is written"
        elif c.islands:  # nothing failed: the λ-H method fills disks only
            loops = ", ".join(map(str, c.islands))
            n = len(c.islands)
            written = (f"the faired fill{order} with its {agreeing(n, 'island', 'islands')} "
                       f"({agreeing(n, 'loop', 'loops')} {loops}) is written")
        else:
            why = ("the λ-H fill failed" if c.fallback and not c.fallback.startswith(
                "self-check") else "the self-check rejected the λ-H fill")
            written = f"{why}; the faired fill{order} is written"
        if c.written_panel in ("B", "W"):  # where (C) does not draw it
            written += f" ({c.written_panel})"
    if c.crossings and not c.skipped:  # said here as `fill`'s hole line says it
        crossing = how_many(c.crossings, "of its triangles crosses", "of its triangles cross")
        written += f"; {crossing} the surface"
    text = (f"{name + ': ' if name else ''}hole {c.index}, {c.n_edges} boundary edges, "
            f"diameter {_fmt(c.diameter)}; {written}")
    if c.errors:
        # each 3D panel's error, the written fill's labelled so: its panel draws it
        drawn = [("B", "fair"), ("C", "conformal" if c.on_plane else "conformal raw")]
        if c.written_panel == "W":
            drawn.append(("W", "conformal"))
        shown = ", ".join(f"({panel}{', written' if panel == c.written_panel else ''}) "
                          f"{_error_text(c, method)}" for panel, method in drawn)
        if c.on_plane:  # the λ-H fill, drawn in no 3D panel
            shown += f", λ-H fill (not written) {_error_text(c, 'conformal raw')}"
        text += f"\nerror (mean / Hausdorff, % of diameter): {shown}"
    return text
