"""One hole, start to end: cut its neighbourhood, check its loop, fill it, stitch the fill in
and say what happened in its report. The serial loop of :mod:`surfinpaint.fill.pipeline` runs
these steps one hole after another; :mod:`surfinpaint.fill.parallel` runs the cut, the check
and the fill in worker processes and the rest here, in hole order. Before any hole is filled,
the loops that span no area are zipped or left open (:func:`open_seams`; what ``surfinpaint
holes`` says of them: :func:`left_open`).
"""

from __future__ import annotations

import dataclasses
import sys
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from surfinpaint.errors import HoleWarning, MeshError, agreeing, how_many, preview
from surfinpaint.fill import parallel
from surfinpaint.fill.conformal import ConformalOptions
from surfinpaint.fill.holes import Hole
from surfinpaint.fill.neighbourhood import FilledMesh, Local, zero_area_reason
from surfinpaint.fill.results import Fill, HoleReport
from surfinpaint.fill.seams import (
    ALONG_OTHER_LOOPS,
    ALONG_OTHER_LOOPS_NOT_ZIPPED,
    NO_AREA_FACES,
    SlitWarning,
    spanless,
    zip_or_leave,
)
from surfinpaint.geometry.degenerate import triangle_rows
from surfinpaint.geometry.repair import unjoined_bowties
from surfinpaint.geometry.rows import rows_any
from surfinpaint.geometry.validation import check_loop, zero_area_faces
from surfinpaint.io.base import MeshWarning

__all__ = ["FAIR_NEIGHBOURHOOD_RINGS", "Run", "around_zero_area", "at_hole", "fill_hole",
           "left_open", "loop_problem", "open_seams", "record", "skip", "stitched",
           "warn_at_caller", "with_failure"]

# vertex rings of the surface handed to the faired fill (its fairing needs up to 2)
FAIR_NEIGHBOURHOOD_RINGS = 3

ProgressCallback = Callable[[int, int, str], None]


def warn_at_caller(message: str, category: type[Warning]) -> None:
    """``warnings.warn`` pointed at the first caller outside ``surfinpaint.fill`` (the line
    that called ``fill_holes``), whichever loop (serial, parallel) this runs in."""
    frame, level = sys._getframe(1), 2  # the frame stacklevel=2 names
    while frame is not None and frame.f_globals.get("__name__", "").startswith(
            "surfinpaint.fill."):
        frame, level = frame.f_back, level + 1
    warnings.warn(message, category, stacklevel=level)


def skip(report: HoleReport, reason: str, category: type[Warning] = HoleWarning,
         stacklevel: int | None = None) -> None:
    """Report the hole as skipped for ``reason``, with a warning (at ``stacklevel``; None:
    at the caller of ``fill_holes``)."""
    report.skipped = reason
    report.method = "none"
    message = f"hole {report.index}: {reason}; skipped"
    if stacklevel is None:
        warn_at_caller(message, category)
    else:
        warnings.warn(message, category, stacklevel=stacklevel)


def _zero_area_faces_lie(n: int) -> str:
    """``n`` faces of zero area, said with the verb that agrees: "1 face ... lies"."""
    return how_many(n, "face of zero area (collinear or coincident corners) lies",
                    "faces of zero area (collinear or coincident corners) lie")


def loop_problem(local: Local, index: int, explicit: bool) -> str | None:
    """Why the hole cannot be filled (None: it can); a hole the caller named is an error.

    The loop is checked on the faces at its vertices only: whether its edges are boundary
    edges and its vertices bow-ties is decided there (the same answer and message as on the
    whole neighbourhood, at the cost of the loop's faces, not of the many rings around).
    A neighbourhood that holds faces of zero area is refused too: the fill's cotangent
    weights, normals and conformal map are undefined on them."""
    if len(local.zero_area):
        message = (f"{_zero_area_faces_lie(len(local.zero_area))} in the neighbourhood its "
                   f"fill uses: {local.zero_area_text}"
                   "; their angles and normals are undefined")
        if explicit:
            raise MeshError(f"hole {index}: {message}; a hole not named (leave it out of "
                            "holes=, --holes) is skipped with a warning",
                            faces=local.zero_area[:100].tolist())
        return message
    on_loop = np.isin(local.faces_global, local.loop)
    touching = local.faces_global[rows_any(on_loop)]
    try:
        check_loop(touching, local.loop)
    except MeshError as exc:
        # a loop pinched at a bow-tie (split into pieces): filling each piece joins the
        # fans there, so the result is manifold once all pieces are filled
        if "bow-tie" not in exc.message or unjoined_bowties(touching, local.loop).size:
            if explicit:
                raise MeshError(f"hole {index}: {exc.message}", vertices=exc.vertices,
                                edges=exc.edges) from None
            return exc.message
    if on_loop[rows_any(on_loop)].all():
        # a lone triangle or a strip one face wide: the loop bounds nothing but the faces
        # along it, and a fill would lay a second sheet on them (duplicate faces)
        return "the loop bounds only the faces along it (a lone sheet)"
    return None


def left_open(vertices: np.ndarray, faces: np.ndarray, loops: list[np.ndarray], *,
              zip_seams: bool = False) -> list[str | None]:
    """Per loop of ``loops`` (boundary loops of the mesh, each one fill tries: chosen, and
    within the size limit), why :func:`surfinpaint.fill_holes` leaves it open, or None where
    it fills it (or, with ``zip_seams``, zips it): a loop that spans no area
    (:func:`~surfinpaint.fill.seams.spanless`: a slit, a seam, zipped only with
    ``zip_seams``: :func:`~surfinpaint.fill.seams.zip_or_leave`), else the check each hole's
    fill makes (:func:`loop_problem`: a bow-tie vertex the fill would leave pinched, a lone
    sheet, faces of zero area in the faired fill's rings). As in ``fill_holes``, the seams
    are zipped first and the other loops checked on the zipped faces, with
    :data:`FAIR_NEIGHBOURHOOD_RINGS` rings: the fewest either method cuts by default, and
    those a λ-H fill falls back to when zero-area faces lie further out (then filled,
    faired). For ``surfinpaint holes``: it says what ``fill`` will do."""
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    triangles, _, rows = triangle_rows(faces)
    flat = zero_area_faces(vertices, triangles)  # zipping moves no corner: the same faces
    out: list[str | None] = [None] * len(loops)
    mapping = np.arange(len(vertices))  # a zipped duplicate -> its kept partner
    surfaces = []
    for k, loop in enumerate(loops):
        slit = spanless(vertices, np.asarray(loop))  # found before anything is filled
        if slit is None:
            surfaces.append(k)
            continue
        zipped, out[k] = zip_or_leave(faces, slit[0], slit[1], zip_seams)
        if zipped is not None:
            faces = zipped
            mapping[slit[0].merges[:, 0]] = slit[0].merges[:, 1]
    mesh = FilledMesh(vertices, faces, zero_area=flat if rows is None else rows[flat])
    for k in surfaces:
        out[k] = loop_problem(mesh.cut(mapping[np.asarray(loops[k])],
                                       FAIR_NEIGHBOURHOOD_RINGS), k, explicit=False)
    return out


def open_seams(vertices: np.ndarray, faces: np.ndarray, todo: list[HoleReport],
                zip_seams: bool, unfillable: dict[int, Hole]
                ) -> tuple[np.ndarray, np.ndarray, list[HoleReport]]:
    """The holes of ``todo`` whose loop spans no area (:func:`find_slit`, or a loop of a
    piece of surface whose faces all have zero area: :attr:`Hole.spans_no_area`), runs back
    along itself over a seam (:func:`find_seam_part`) or runs along other loops edge for
    edge (:attr:`Hole.runs_along_other_loops`) taken out of it, before anything is filled:
    seams zipped with ``zip_seams`` (the faces returned use each kept vertex in place of its
    duplicate), the others skipped with a SlitWarning. ``unfillable``: the holes of the
    first and last kind, by number.

    Returns the faces, the merged ``(duplicate, kept)`` pairs and the holes left to fill
    (their loops in the zipped faces' ids).
    """
    left, merged = [], []
    for report in todo:
        hole = unfillable.get(report.index)
        if hole is not None and hole.spans_no_area:  # not zipped: faces would repeat a vertex
            skip(report, NO_AREA_FACES, SlitWarning, stacklevel=4)
            continue
        found = spanless(vertices, report.loop)
        if found is None and hole is not None:  # along other loops
            skip(report, ALONG_OTHER_LOOPS_NOT_ZIPPED if zip_seams else ALONG_OTHER_LOOPS,
                 SlitWarning, stacklevel=4)
            continue
        if found is None:
            left.append(report)
            continue
        slit, reason, rest = found
        zipped, why = zip_or_leave(faces, slit, reason, zip_seams)
        if zipped is not None:
            faces = zipped
            report.method, report.zipped = "zipped", slit.merges
            merged_count = how_many(len(slit.merges), "duplicate vertex", "duplicate vertices")
            report.note = (f"seam zipped: {merged_count} merged "
                           f"into their coincident partners{rest}")
            merged.append(slit.merges)
            n_pairs = len(slit.merges)
            pairs = how_many(n_pairs, "coincident vertex pair", "coincident vertex pairs")
            warnings.warn(f"hole {report.index}: a seam of {pairs} zipped: the faces use "
                          f"{agreeing(n_pairs, 'vertex', 'vertices')} "
                          f"{preview(slit.merges[:, 1])} in place of "
                          f"{agreeing(n_pairs, 'its duplicate', 'their duplicates')} "
                          f"{preview(slit.merges[:, 0])} (left unused){rest}",
                          MeshWarning, stacklevel=3)
            continue
        skip(report, why, SlitWarning, stacklevel=4)
    pairs = np.concatenate(merged) if merged else np.empty((0, 2), dtype=np.int64)
    if len(pairs):  # a later loop through a duplicate (a bow-tie there) goes through its partner
        mapping = np.arange(len(vertices))
        mapping[pairs[:, 0]] = pairs[:, 1]
        for report in left:
            report.loop = mapping[report.loop]
    return faces, pairs, left


def around_zero_area(mesh: FilledMesh, local: Local, run: Run
                     ) -> tuple[Local, Run, str | None]:
    """The neighbourhood and the run a hole is filled with, and why they are not those
    asked for (None: they are). Where zero-area faces lie in the rings the λ-H fill and its
    self-check use (``local``) but not in the faired fill's
    (:data:`FAIR_NEIGHBOURHOOD_RINGS`), the faired fill is made from those: a fallback
    (:attr:`Fill.failure`), not a hole left open. Rings the caller chose are kept."""
    if not len(local.zero_area) or run.method != "conformal" or run.rings:
        return local, run, None
    near = mesh.cut(local.loop, FAIR_NEIGHBOURHOOD_RINGS)
    if len(near.zero_area):
        return local, run, None  # refused by loop_problem
    why = (f"not tried: {_zero_area_faces_lie(len(local.zero_area))} in the rings it and "
           f"its self-check use: {local.zero_area_text}; "
           f"none in the faired fill's {FAIR_NEIGHBOURHOOD_RINGS}")
    return near, dataclasses.replace(run, method="fair"), why


def with_failure(made: Fill | None, why: str | None) -> Fill | None:
    """``made`` marked a fallback for ``why`` (:func:`around_zero_area`), if any."""
    return made if made is None or why is None else dataclasses.replace(made, failure=why)


def record(report: HoleReport, fill: Fill, written: bool = True) -> None:
    """What the method did with the hole, in its report (a fallback also as a warning).
    ``written``: False for a fill that is not stitched in (:func:`zero_area_reason`): its
    triangles that cross the surface are then neither reported nor warned of (they would be
    rows of faces never written; the hole is skipped, and says why)."""
    report.method = fill.kind
    report.note = fill.notes
    report.fair_order = fill.fair_order
    report.verdict, report.crease, report.diagnostics = (fill.verdict, fill.crease,
                                                          fill.diagnostics)
    report.crease_failure = fill.crease_failure
    report.plane = fill.plane
    report.smoothing = fill.smoothing
    report.ear_cut = fill.ear_cut
    if written:
        report.crossings, report.crossing_triangles = fill.crossings, fill.crossing_triangles
    if written and fill.crossings:
        triangles = how_many(fill.crossings, "triangle", "triangles")
        warn_at_caller(f"hole {report.index}: {triangles} of the "
              f"fill cross{agreeing(fill.crossings, 'es', '')} the surface around the hole (its "
              "boundary loop folds over itself there): check the result", HoleWarning)
    if fill.failure:
        report.fallback = fill.failure
        warn_at_caller(f"hole {report.index}: conformal fill failed ({fill.failure}); used "
              f"the faired fill (order {fill.fair_order}) instead", HoleWarning)


@dataclass(frozen=True)
class Run:
    """How the holes of one call are filled, and whom to tell."""

    method: str
    options: ConformalOptions
    fair_order: int | None
    explicit: bool
    n_holes: int
    progress: ProgressCallback | None
    rings: int | None
    # a report's place among the selected holes, for the progress count
    position: dict[int, int] = field(default_factory=dict)

    def rings_of(self, report: HoleReport) -> int:
        """The vertex rings cut out around the hole: what its method looks at."""
        return self.rings_for(report.n_edges)

    def rings_for(self, n_edges: int) -> int:
        """The vertex rings cut out around a hole of ``n_edges`` boundary edges."""
        return self.rings or (self.options.neighbourhood_rings(n_edges)
                              if self.method == "conformal" else FAIR_NEIGHBOURHOOD_RINGS)

    def fill(self, local: Local, stage: Callable[[str], None] | None = None
             ) -> tuple[Fill | None, str | None]:
        return parallel.fill_or_failure(local.vertices, local.faces, local.local_loop, self.method,
                               self.options, self.fair_order, stage)

    def starting(self, report: HoleReport) -> None:
        if self.progress:
            self.progress(self.position.get(id(report), 0), self.n_holes,
                          f"hole {report.index}: {report.n_edges} edges, {self.method}")

    @property
    def tells_stages(self) -> bool:
        """Whether the conformal fill's stages are told (someone listens to progress)."""
        return bool(self.progress) and self.method == "conformal"

    def stages_of(self, report: HoleReport, counted: HoleReport | None = None
                  ) -> Callable[[str], None] | None:
        """The ``stage`` callback of ``report``'s conformal fill: each stage as it starts
        told to ``progress``, as ``hole 3: 212 edges, λ-H fill (stage 5 of 5)`` (the holes
        done still the count: ``counted``'s place, the hole stitched next where the holes
        are filled on workers; ``report``'s own by default); None where nobody listens."""
        if not self.tells_stages:
            return None
        words = parallel.conformal_method.stage_words  # the fill imports it anyway
        done = self.position.get(id(counted or report), 0)

        def stage(name: str) -> None:
            self.progress(done, self.n_holes,
                          f"hole {report.index}: {report.n_edges} edges, {words(name)}")
        return stage

    def finished(self, report: HoleReport) -> None:
        if self.progress and not report.skipped:
            self.progress(self.position.get(id(report), 0) + 1, self.n_holes,
                          f"hole {report.index}: done in {report.seconds:.2f} s")


def at_hole(index: int, call: Callable, *args):
    """``call(*args)`` for hole ``index``: a MeshError raised names the hole."""
    try:
        return call(*args)
    except MeshError as exc:
        raise MeshError(f"hole {index}: {exc.message}", path=exc.path, vertices=exc.vertices,
                        edges=exc.edges, faces=exc.faces) from exc


def stitched(mesh: FilledMesh, report: HoleReport, ids: np.ndarray | None, made: Fill | None,
             problem: str | None, started: float, failure: str | None = None,
             unstitchable: str | None = None) -> None:
    """Stitch ``made`` (over a neighbourhood with the global ``ids``; ``unstitchable``:
    :func:`zero_area_reason` for it) in and report it; None: ``problem`` says why there is
    no fill, or ``failure`` why the fill raised."""
    if failure is not None:  # the fill raised: the hole is left open, the others go on
        report.failed = True
        problem = f"the fill failed: {failure}"
    if made is not None:
        problem = unstitchable
        record(report, made, written=problem is None)
        if problem is None:
            mesh.append(ids, made)
        report.failed = problem is not None  # a fill was made: it is its failure
    if problem is not None:
        skip(report, problem)
        return
    report.new_vertices, report.new_faces = len(made.vertices), len(made.faces)
    report.seconds = time.perf_counter() - started


def fill_hole(mesh: FilledMesh, report: HoleReport, run: Run) -> None:
    """One hole: cut its neighbourhood, check its loop, fill it, stitch the fill in, and
    say what happened in ``report`` (skipped, with a warning, when it cannot be filled)."""
    started = time.perf_counter()
    local, hole_run, why = around_zero_area(mesh, mesh.cut(report.loop, run.rings_of(report)),
                                            run)
    problem = loop_problem(local, report.index, run.explicit)
    made, failure = (None, None) if problem else at_hole(report.index, hole_run.fill, local,
                                                         run.stages_of(report))
    made = with_failure(made, why)
    stitched(mesh, report, local.ids, made, problem, started, failure,
             None if made is None else zero_area_reason(local.vertices, made))
