"""Hole fills side by side, for judging by eye: ``surfinpaint report``.

Every hole is filled twice, by the conventional fill (Liepa: triangulate, refine, fair) and by
the conformal λ-H inpainting (Lui, Wen, Gu), and drawn as one panel in the layout of the
paper's figures:

(A) the surface with the hole, (B) the conventional fill, (C) the conformal fill (and (W) the
written fill where neither (B) nor (C) draws it), seen from one camera facing the hole;
(D)/(E) the conformal factor λ before and after inpainting and (F)/(G) the mean curvature H
before and after, over the conformal parameter domain of the hole's patch, with the hole
(solid) and the inpainted region (dashed) outlined (drawn by :mod:`surfinpaint.app.report_panel`).

"Before" is what the known surface says (:func:`surfinpaint.app.lambda_h_images.lambda_h_images`):
λ, H of the surface around the hole on its patch's triangles, or the robust grid estimate
with ``discretization="grid"``; the part that sees the initial fill is grey, since the
initial fill's own λ, H are not data the method uses.

Every hole's panel draws the fill ``surfinpaint fill`` writes, titled "written", and the
λ-H fill, so that the two can be compared (:func:`panel_fills` decides what each panel
draws). (C) draws the conformal method's own fill: the λ-H fill, kept or rejected by the
self-check (computed again with ``select=False`` where it was rejected), or, where the
surface around the hole is a plane within its noise (the method's plane test,
``HoleComparison.on_plane``), the faired fill laid on that plane that is written there (the
λ-H fill the plane test made unnecessary is still computed, with ``select=False``, for
(E)/(G), whose titles say that it was not written, and for the page's ``conformal raw``
errors). Where the written fill is not (C)'s, it is the faired fill the self-check (or a
failure of the λ-H fill) chose: (B) is titled "written" when it draws exactly that fill
(the same faces over the same positions: the bilaplacian fill, as a rule), and otherwise
(W), a fourth 3D panel from the same camera, draws it (the trilaplacian fill, or a faired
fill the method's ``s0_search``/``s0_refinement`` made unlike (B)'s).

A page (``index.md`` and ``index.html``) lists the holes with their sizes, times, the
self-check scores and, given the ground truth, each method's distance to it.
"""

from __future__ import annotations

import argparse
import os
import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from surfinpaint.app.fill_options import (
    add_fair_smoothing,
    add_hole_numbers,
    add_islands,
    add_keep_margins,
)
from surfinpaint.app.fill_report import (
    count_warnings,
    hole_lines,
    nothing_to_fill,
    plane_words,
    print_warnings,
    smoothing_line,
    written,
)
from surfinpaint.app.progress import QuietConsole, add_quiet, hole_news, progress_bar
from surfinpaint.app.report_page import (
    LEGEND,
    NOT_MEASURED,
    HoleComparison,
    PageSection,
    TruthDistance,
    WrittenPanel,
    hole_title,
    table_rows,
    write_page,
)
from surfinpaint.app.report_panel import PANEL_SIZE, Patch, hole_panel
from surfinpaint.app.report_truth import hole_truths
from surfinpaint.app.report_warnings import fills_warnings, said_once
from surfinpaint.errors import how_many, mesh_size
from surfinpaint.fill.conformal import ConformalOptions
from surfinpaint.fill.holes import hole_numbers, loop_diameter, select_holes, warn_degenerate
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.fill.results import FillResult, LambdaHDiagnostics
from surfinpaint.geometry.cutting import compact
from surfinpaint.geometry.metrics import surface_distance
from surfinpaint.geometry.repair import repair_faces
from surfinpaint.io.formats import read_mesh

__all__ = [
    "LEGEND",
    "PANEL_SIZE",
    "ComparedFills",
    "HoleComparison",
    "PanelFills",
    "add_report_parser",
    "compare_holes",
    "hole_panel",
    "hole_truths",
    "panel_fills",
    "run_report",
    "table_rows",
    "write_page",
    "write_report",
]

# a progress hook: step(message, advance=1); one with a ``holes(label)`` method (the command
# line's bar) is also told each hole's news of the fills (progress.hole_news)
Step = Callable[..., None]


# --------------------------------------------------------------------------- fills


@dataclass(frozen=True)
class ComparedFills:
    """What :func:`compare_holes` made, hole by hole (the ``k``-th entry of each list is
    the hole of ``loops[k]``).

    A hole's fill is ``(vertices, faces)``: the vertices of the whole filled mesh (they
    start with the holed mesh's) and the hole's new faces.

    Attributes
    ----------
    fair, conformal : FillResult
        The ``"fair"`` and the ``"conformal"`` method's fill of the mesh.
    fair_fills, written_fills : list of (vertices, faces)
        Each hole's fill by the ``"fair"`` method, and by the ``"conformal"`` method: the
        fill ``surfinpaint fill`` writes.
    lambda_h_fills : list of (vertices, faces) or None
        Each hole's λ-H fill before the self-check and the plane test (made again with
        ``select=False`` where it is not the written fill); None where it failed.
    diagnostics : list of LambdaHDiagnostics or None
        The λ-H fill's :class:`~surfinpaint.fill.results.LambdaHDiagnostics` (None where it
        failed).
    loops : list of (k,) int arrays
        The holes' loops, oriented.
    """

    fair: FillResult
    conformal: FillResult
    fair_fills: list[Patch]
    written_fills: list[Patch]
    lambda_h_fills: list[Patch | None]
    diagnostics: list[LambdaHDiagnostics | None]
    loops: list[np.ndarray]

    def by_method(self) -> dict[str, list[Patch | None]]:
        """Each hole's fill under the method names of :attr:`HoleComparison.errors`."""
        return {"fair": self.fair_fills, "conformal": self.written_fills,
                "conformal raw": self.lambda_h_fills}


def _error(patch: tuple[np.ndarray, np.ndarray] | None,
           truth: tuple[np.ndarray, np.ndarray] | None, diameter: float) -> TruthDistance:
    """A compacted fill's distance to its truth patch, in % of the hole's diameter."""
    if patch is None or truth is None or len(patch[1]) == 0:
        return NOT_MEASURED
    d = surface_distance(patch[0], patch[1], truth[0], truth[1], n_samples=10000)
    return TruthDistance(100.0 * d.mean / diameter, 100.0 * d.hausdorff / diameter)


def compare_holes(
    vertices: np.ndarray,
    faces: np.ndarray,
    loops: Sequence[np.ndarray] | None,
    *,
    truth: Sequence[tuple[np.ndarray, np.ndarray]] | None = None,
    step: Step | None = None,
    options: ConformalOptions | None = None,
    keep_margins: bool = False,
    islands: str = "bridge",
) -> tuple[list[HoleComparison], ComparedFills]:
    """Fill the given holes by both methods and measure them.

    Parameters
    ----------
    vertices, faces : arrays
        The mesh with holes.
    loops : sequence of (k,) int arrays, or None
        The holes' boundary loops (as :func:`surfinpaint.fill_holes` accepts them): named,
        so a hole that cannot be filled for the mesh around it (a zero-area face in its
        fill's rings) is a ``MeshError`` naming it. None: every hole but the outer border,
        as :func:`surfinpaint.fill_holes` chooses them: such a hole is skipped instead, with
        a :class:`~surfinpaint.errors.HoleWarning`, and compared as skipped
        (:attr:`HoleComparison.skipped`).
    truth : sequence of (vertices, faces) or None, optional
        The ground-truth patch of each hole (e.g. :attr:`surfinpaint.geometry.cutting.CutHole`'s
        ``truth_vertices``/``truth_faces``), to measure each fill against; None for a hole
        without one (its errors are NaN).
    step : callable(message, advance=1), optional
        Progress hook, called after each stage: 2 + one per hole (and with ``advance=0``
        for each conformal fill that is computed again because the self-check rejected it).
        One with a ``holes(label)`` method (the command line's bar) gives the fills their
        ``progress`` callback: ``holes("conformal fills")``.
    options : ConformalOptions, optional
        The conformal method's options.
    keep_margins : bool
        As :func:`surfinpaint.fill_holes`: with ``loops`` None, the loops that may be a
        margin are left open, not compared.
    islands : {"bridge", "ignore"}
        As :func:`surfinpaint.fill_holes` (``--islands``): a hole with an island is filled
        with it (faired, by both methods) or as a disk through or by it, with a warning.

    Warns
    -----
    Each warning of the conventional and the conformal fills (an island left unjoined, a
    fill that crosses the surface, ...) once, in its category, saying which fill it came
    from where only one gave it
    (:func:`~surfinpaint.app.report_warnings.fills_warnings`), and a
    :class:`~surfinpaint.errors.HoleWarning` for a hole skipped without one; the λ-H fills
    made again for the panels are not said (they repeat the conformal fill's).

    Returns
    -------
    comparisons : list of HoleComparison
    fills : ComparedFills
        Each method's fill of each hole, and the λ-H fill's diagnostics.
    """
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    named = None if loops is None else list(loops)  # None: chosen by fill_holes' rule
    loops = select_holes(vertices, faces, named, keep_margins=keep_margins)
    if truth is not None and len(truth) != len(loops):
        raise ValueError(f"{how_many(len(truth), 'truth patch', 'truth patches')} for "
                         f"{how_many(len(loops), 'hole', 'holes')}")
    step = step or (lambda message, advance=1: None)
    options = ConformalOptions() if options is None else options
    made = _both_fills(vertices, faces, loops, None if named is None else loops,
                       step=step, options=options, keep_margins=keep_margins, islands=islands)
    return _measured(vertices, made, truth, step), made


def _both_fills(vertices, faces, loops, holes, *, step, options, keep_margins, islands
                ) -> ComparedFills:
    """:func:`compare_holes`' fills of ``loops`` (``holes``: as given to ``fill_holes``),
    conventional, conformal and λ-H before the self-check, with the warnings of the first
    two said once each, saying which fill each is of (at the caller of ``compare_holes``);
    the λ-H fills made again are not said (they repeat the conformal fill's, of fills not
    written)."""
    fair, caught_fair = _with_warnings(fill_holes, vertices, faces, holes=holes, method="fair",
                                       keep_margins=keep_margins, validate=False,
                                       islands=islands,
                                       progress=hole_news(step, "conventional fills"))
    step("conventional fills done")
    conformal, caught = _with_warnings(fill_holes, vertices, faces, holes=holes,
                                       method="conformal", keep_margins=keep_margins,
                                       validate=False, options=options, islands=islands,
                                       progress=hole_news(step, "conformal fills"))
    step("conformal fills done")
    written_fills = [(conformal.vertices, p) for p in conformal.hole_faces()]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        raw, diagnostics = _lambda_h_fills(vertices, faces, loops, conformal,
                                           written_fills, options, step, islands)
    for text, category in fills_warnings(said_once(caught, conformal.reports),
                                         said_once(caught_fair, fair.reports)).items():
        warnings.warn(text, category, stacklevel=3)
    return ComparedFills(fair=fair, conformal=conformal,
                         fair_fills=[(fair.vertices, p) for p in fair.hole_faces()],
                         written_fills=written_fills, lambda_h_fills=raw,
                         diagnostics=diagnostics, loops=list(loops))


def _with_warnings(call: Callable, *args, **kwargs) -> tuple:
    """``call(*args, **kwargs)`` and the warnings it gave (every one, none shown)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = call(*args, **kwargs)
    return result, caught


def _measured(vertices: np.ndarray, made: ComparedFills,
              truth: Sequence[tuple[np.ndarray, np.ndarray]] | None,
              step: Callable) -> list[HoleComparison]:
    """Each hole's comparison (:func:`_comparison`) and, with ``truth``, each fill's errors
    against its hole's truth patch."""
    patches = {name: [None if p is None else compact(*p)[:2] for p in fills]
               for name, fills in made.by_method().items()}
    out = []
    for k, loop in enumerate(made.loops):
        comp = _comparison(k, loop, vertices, made)
        if truth is not None:
            comp.errors = {name: _error(patches[name][k], truth[k], comp.diameter)
                           for name in ("fair", "conformal", "conformal raw")}
        out.append(comp)
        step(f"hole {k}: measured")
    return out


def _lambda_h_fills(vertices, faces, loops, conformal, written, options, step, islands):
    """Each hole's λ-H fill before the self-check, as ``(vertices, new faces)`` (None where
    the conformal method failed), and its diagnostics: the written fill where it is the λ-H
    fill, else made again here without the self-check, since the λ-H fill is not made where
    the self-check rejects it nor where the plane test lays the faired fill on the plane."""
    raw = [fill if r.method == "conformal" else None
           for fill, r in zip(written, conformal.reports, strict=True)]
    diagnostics = [r.diagnostics for r in conformal.reports]
    rejected = [k for k, r in enumerate(conformal.reports)
                if r.method == "fair" and not r.fallback and not r.skipped]
    for k in rejected:
        again = fill_holes(vertices, faces, holes=[loops[k]], method="conformal",
                           validate=False, options=replace(options, select=False),
                           islands=islands,
                           progress=hole_news(step, f"hole {k}'s λ-H fill again"))
        if not again.reports[0].fallback:
            raw[k] = (again.vertices, again.hole_faces()[0])
            diagnostics[k] = again.reports[0].diagnostics
        step(f"hole {k}: conformal fill before the self-check", 0)
    return raw, diagnostics


def _comparison(k: int, loop: np.ndarray, vertices: np.ndarray,
                made: ComparedFills) -> HoleComparison:
    """Hole ``k``'s comparison, without the errors: what each method made and wrote."""
    rc, rf = made.conformal.reports[k], made.fair.reports[k]
    return HoleComparison(
        index=k, n_edges=len(loop), diameter=loop_diameter(vertices[loop]),
        seconds={"fair": rf.seconds, "conformal": rc.seconds},
        new_vertices={"fair": rf.new_vertices, "conformal": rc.new_vertices},
        kept=rc.method == "conformal", fallback=rc.fallback or rc.note,
        scores={} if rc.verdict is None else {
            name.replace(" ", "_"): scores for name, scores in rc.verdict.tests.items()},
        fair_order=rc.fair_order,
        written="; ".join([written(rc), *(line.strip() for line in hole_lines(rc)[1:]),
                           *_shut_smoothing(rc)]),
        on_plane=rc.plane is not None,
        written_panel=panel_fills(made, k).written_in,
        skipped=rc.skipped if rc.outcome in ("skipped", "failed") else None,
        islands=rc.islands,
        crossings=rc.crossings,  # 0 where nothing was written (hole_steps.record)
        smoothed=rc.smoothed, ear_cut=rc.ear_cut,
    )


def _shut_smoothing(report) -> list[str]:
    """The page says why a hole's bilaplacian fill was not smoothed too (``fill`` with
    ``-v``): a scan's user asks which holes were."""
    line = smoothing_line(report, shut_too=True)
    return [line.strip()] if line and report.smoothing.length is None else []


# --------------------------------------------------------------------------- panels


@dataclass(frozen=True)
class PanelFills:
    """What the 3D panels of one hole draw, and their titles (:func:`panel_fills`).

    Each fill is ``(vertices, faces)`` as :func:`hole_panel` takes it.

    Attributes
    ----------
    fair : (vertices, faces)
        (B): the conventional fill.
    conformal : (vertices, faces) or None
        (C): the conformal method's own fill (the λ-H fill, or the fill laid on the plane);
        None where the λ-H fill failed.
    written : (vertices, faces) or None
        (W): the fill ``surfinpaint fill`` writes, where neither (B) nor (C) draws it; None
        otherwise.
    written_in : {"B", "C", "W"} or None
        The panel that draws the written fill; None where nothing is written.
    titles : dict
        The panels' titles that differ from :func:`hole_panel`'s.
    """

    fair: Patch
    conformal: Patch | None
    written: Patch | None
    written_in: WrittenPanel
    titles: dict[str, str]


def _same_fill(a: Patch | None, b: Patch | None) -> bool:
    """Whether two fills are the same faces over the same positions. Each lies in its own
    result's vertex ids (which new vertices come first depends on the holes before it), so
    they are compared compacted. Exactly: the conformal method's bilaplacian candidate is
    made bit for bit as the "fair" method's fill is, and were they ever to differ in the
    last bits, (W) would draw a copy of (B), a panel too many but never the written fill
    missing."""
    if a is None or b is None:
        return False
    (av, af, _), (bv, bf, _) = compact(*a), compact(*b)
    return np.array_equal(af, bf) and np.array_equal(av, bv)


def panel_fills(fills: ComparedFills, k: int) -> PanelFills:
    """What each 3D panel of a hole draws, and which draws the written fill (see the module
    docstring).

    Parameters
    ----------
    fills : ComparedFills
        As :func:`compare_holes` returns it.
    k : int
        The hole's position in ``fills`` (not its ``index``).

    Returns
    -------
    PanelFills
    """
    report = fills.conformal.reports[k]
    on_plane = report.plane is not None
    # the fill laid on the plane is the conformal method's own, like neither (B) nor the
    # λ-H fill: (C) draws it; elsewhere (C) draws the λ-H fill, kept or not, so that a
    # rejected one can be judged
    conformal = (fills.written_fills if on_plane else fills.lambda_h_fills)[k]
    written = fills.written_fills[k] if report.outcome in ("lambda-h", "faired") else None
    # the written fill is drawn once, in the first panel that draws exactly it: one more
    # panel only where it is new to the eye (the trilaplacian fill, as a rule)
    written_in: WrittenPanel = None
    if written is not None:
        written_in = ("C" if _same_fill(written, conformal)
                      else "B" if _same_fill(written, fills.fair_fills[k]) else "W")
    titles = {}
    if written_in == "B":
        titles["B"] = "(B) conventional fill (faired, written)"
    if fills.fair.reports[k].outcome == "skipped":
        titles["B"] = "(B) conventional fill (skipped)"
    state = ("written" if written_in == "C" else "skipped" if report.outcome == "skipped"
             else "failed" if conformal is None else "not written" if report.ear_cut
             else "rejected by the self-check")
    titles["C"] = (f"(C) conformal: faired fill laid on {plane_words(report.plane)} ({state})"
                   if on_plane
                   else f"(C) conformal fill ({state})")
    if written_in == "W":
        titles["W"] = (f"(W) written: ear-cut fill ({report.ear_cut})" if report.ear_cut
                       else f"(W) written: faired fill (order {report.fair_order}"
                       + (", smoothed)" if report.smoothed else ")"))
    if on_plane and fills.diagnostics[k] is not None:
        # (E)/(G) are of the λ-H fill, which (C) does not draw
        titles["E"] = "(E) inpainted λ (λ-H fill, not written)"
        titles["G"] = "(G) inpainted H (λ-H fill, not written)"
    return PanelFills(fair=fills.fair_fills[k], conformal=conformal,
                      written=written if written_in == "W" else None, written_in=written_in,
                      titles=titles)


def panels_for(vertices, faces, comparisons, fills, out_dir, prefix="hole",
               name: str = "", step: Step | None = None) -> None:
    """Draw the panel of every compared hole into ``out_dir`` as ``<prefix><index>.png``
    (sets ``.picture``); ``comparisons`` and ``fills`` as :func:`compare_holes` returns
    them."""
    out_dir = Path(out_dir)
    for k, c in enumerate(comparisons):
        drawn = panel_fills(fills, k)
        picture = f"{prefix}{c.index}.png"
        hole_panel(vertices, faces, fills.loops[k], drawn.fair, drawn.conformal,
                   fills.diagnostics[k], out_dir / picture, written=drawn.written,
                   titles=drawn.titles, suptitle=hole_title(c, name))
        c.picture = picture
        if step:
            step(f"hole {c.index}: panel drawn")


def write_report(
    vertices: np.ndarray,
    faces: np.ndarray,
    out_dir: str | os.PathLike,
    holes: Sequence | None = None,
    *,
    truth: tuple[np.ndarray, np.ndarray] | None = None,
    title: str = "surfinpaint report",
    step: Step | None = None,
    options: ConformalOptions | None = None,
    keep_margins: bool = False,
    islands: str = "bridge",
) -> list[HoleComparison]:
    """Fill holes by both methods and write a panel per hole and the page indexing them.

    Parameters
    ----------
    vertices, faces : arrays
        The mesh with holes.
    out_dir : path
        Folder for ``hole<k>.png``, ``index.md`` and ``index.html``.
    holes : None, list of int, or list of loops
        As :func:`surfinpaint.fill_holes` (None: every hole but the outer border).
    truth : (vertices, faces), optional
        The complete mesh the holes were cut from: each fill is measured against the part
        of it that fills the hole (:func:`hole_truths`).
    step : callable(message), optional
        Progress hook, called after each stage.
    options : ConformalOptions, optional
        The conformal method's options.
    keep_margins : bool
        As :func:`surfinpaint.fill_holes` (``--keep-margins``): with ``holes`` None, the
        loops that may be a margin are left open, as ``fill`` leaves them, and not reported.
    islands : {"bridge", "ignore"}
        As :func:`surfinpaint.fill_holes` (``--islands``).

    Returns
    -------
    list of HoleComparison

    Warns
    -----
    The warnings of the fills (:func:`compare_holes`), each once; the page lists them too,
    under "Warnings".
    """

    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    loops = select_holes(vertices, faces, holes, keep_margins=keep_margins)
    truths = hole_truths(vertices, faces, loops, *truth) if truth is not None else None
    started = time.perf_counter()
    # holes the caller did not name are chosen by fill_holes' rule: one that cannot be
    # filled is skipped with a warning, as by `surfinpaint fill`, not an error
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        comparisons, fills = compare_holes(vertices, faces, None if holes is None else loops,
                                           truth=truths, step=step, options=options,
                                           keep_margins=keep_margins, islands=islands)
    for c, index in zip(comparisons, hole_numbers(vertices, faces, loops), strict=True):
        c.index = index  # the numbering of `surfinpaint holes`
    panels_for(vertices, faces, comparisons, fills, out_dir, step=step)
    text = (f"{mesh_size(len(vertices), len(faces))}, {how_many(len(loops), 'hole', 'holes')}; "
            f"{time.perf_counter() - started:.1f} s in all.")
    sections = [PageSection("Holes", text=text, comparisons=comparisons)]
    said = [str(w.message) for w in caught]
    if said:  # on the page, as `fill --json` lists them, and to the caller
        sections.append(PageSection("Warnings", items=said))
    write_page(out_dir, sections, title, LEGEND)
    for w in caught:
        warnings.warn(w.message, w.category, stacklevel=2)
    return comparisons


# --------------------------------------------------------------------------- command line


def add_report_parser(subparsers) -> argparse.ArgumentParser:
    """Add ``surfinpaint report`` to an argparse subparsers object."""
    p = subparsers.add_parser(
        "report", help="fill with both methods and write pictures and a page per hole",
        description="Fill the holes of MESH with the conventional and the conformal method "
        "and write, per hole, a PNG panel (the hole, both fills, λ and H before and after "
        "inpainting) and a page (index.md, index.html) with sizes, times and, with --truth, "
        "each method's distance to the truth. Renders off-screen (no display needed).")
    p.add_argument("mesh", help="input mesh with holes")
    p.add_argument("-o", "--output", required=True, help="output folder")
    add_hole_numbers(p)
    p.add_argument("--truth", help="the complete mesh the holes were cut from (same vertex "
                   "positions): measure each fill against it")
    p.add_argument("--repair", action="store_true",
                   help="first remove the faces around non-manifold edges and bow-tie "
                   "vertices and orient the faces consistently, as `fill --repair` does (the "
                   "holes numbered as by `holes --repair`)")
    add_keep_margins(p)
    add_islands(p)
    add_fair_smoothing(p)
    add_quiet(p)
    p.set_defaults(func=run_report)
    return p


def run_report(args: argparse.Namespace) -> int:
    """``surfinpaint report``: returns the exit code (0 on success)."""
    says = QuietConsole(args.quiet)
    # pictures and a page: the file's colours, normals, UVs are not lost, only not drawn
    vertices, faces = read_mesh(args.mesh, data_warning=False)
    if args.repair:
        repair = repair_faces(vertices, faces)
        faces = repair.faces
        removed = how_many(len(repair.removed), "face", "faces")
        says.say(f"--repair removed {removed} around non-manifold "
                 "edges and bow-tie vertices")
        for note in repair.notes():
            says.say(f"--repair {note}")
    with warnings.catch_warnings(record=True) as caught:
        # said once below, with the fills' (which say the degenerate faces again)
        warnings.simplefilter("always")
        warn_degenerate(vertices, faces, str(args.mesh))
        truth = read_mesh(args.truth, data_warning=False) if args.truth else None
        loops = select_holes(vertices, faces, args.holes, keep_margins=args.keep_margins)
        if not loops:
            says.say(f"{args.mesh}: nothing to fill "
                     f"({nothing_to_fill(faces, keep_margins=args.keep_margins)})")
        total = 2 + 2 * len(loops)  # the fills, the measurements, the panels
        with progress_bar(says.progress, total, "filling", ticking=True) as step:
            comparisons = write_report(vertices, faces, args.output, args.holes, truth=truth,
                                       step=step, title=f"surfinpaint report: {args.mesh}",
                                       keep_margins=args.keep_margins, islands=args.islands,
                                       options=ConformalOptions(
                                           fair_smoothing=args.fair_smoothing))
    for c in comparisons:
        says.say(hole_title(c).replace("\n", "; "))
    # as `fill` says them: named, each once, those of a hole left to its title when the
    # titles are printed
    if says.warnings_console is not None:
        print_warnings(says.warnings_console, count_warnings(caught), source=args.mesh,
                       holes_said=says.progress,
                       other_files={str(args.truth): "reading"} if args.truth else None)
    n = len(comparisons)
    says.say(f"wrote {Path(args.output) / 'index.html'} and {how_many(n, 'panel', 'panels')}")
    return 0
