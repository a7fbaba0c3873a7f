"""What ``surfinpaint fill`` says about its holes: a few plain lines per hole, a closing
summary, each warning once, and with ``--json REPORT`` the same as a machine-readable file.

Everything here reads the typed results (:class:`~surfinpaint.fill.results.FillResult`,
:class:`~surfinpaint.fill.results.HoleReport`, :class:`~surfinpaint.fill.results.TestScores`,
:class:`~surfinpaint.fill.results.TopologyChange`); the example output and the JSON fields
are in ``docs/report.md``.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from surfinpaint.app.progress import named, warning_line
from surfinpaint.errors import HoleWarning, how_many
from surfinpaint.fill.results import (
    BY_FAIRED_PLANES,
    FillResult,
    HoleReport,
    Smoothing,
    TestScores,
)
from surfinpaint.geometry.flatness import PlaneTest, TwoPlanes
from surfinpaint.geometry.mesh import boundary_loops
from surfinpaint.io.atomic import atomic_open

__all__ = ["FAIRING", "REPORT_VERSION", "HoleRecord", "Summary", "WarningCount", "count_warnings",
           "hole_lines", "plain", "print_warnings", "report_document", "summary_lines", "tell",
           "write_json_report", "written"]

#: The fairing orders by name.
FAIRING = {1: "harmonic", 2: "bilaplacian", 3: "trilaplacian"}
#: The version of the ``--json`` report's layout (raised when a field changes meaning).
REPORT_VERSION = 1

# the candidates of a self-check test, as the report names them
_CANDIDATES = (("lambda_h", "λ-H"), ("bilaplacian", "bilaplacian"),
               ("trilaplacian", "trilaplacian"))


@dataclass(frozen=True)
class WarningCount:
    """One warning's text, its category's name and how many times it was issued."""

    message: str
    category: str
    count: int


@dataclass(frozen=True)
class Summary:
    """The counts of one fill: holes found (selected for filling), filled by the λ-H fill,
    by a faired fill, skipped and failed; vertices and faces added; wall time in seconds."""

    holes_found: int
    lambda_h: int
    faired: int
    skipped: int
    failed: int
    new_vertices: int
    new_faces: int
    seconds: float
    #: seams of duplicated vertices zipped (``--zip-seams``)
    zipped: int = 0
    #: of the faired fills, those that are the smoothing fill (``HoleReport.smoothed``)
    smoothed: int = 0

    @classmethod
    def of(cls, result: FillResult, seconds: float) -> Summary:
        outcomes = [r.outcome for r in result.reports]
        return cls(len(outcomes), outcomes.count("lambda-h"), outcomes.count("faired"),
                   outcomes.count("skipped"), outcomes.count("failed"),
                   len(result.vertices) - result.n_original_vertices,
                   len(result.faces) - result.n_original_faces, seconds,
                   outcomes.count("zipped"), sum(r.smoothed for r in result.reports))


def _hole_warning_names() -> set[str]:
    """The names of HoleWarning and its subclasses (a slit's SlitWarning)."""
    names, todo = set(), [HoleWarning]
    while todo:
        cls = todo.pop()
        names.add(cls.__name__)
        todo.extend(cls.__subclasses__())
    return names


def count_warnings(caught: Iterable[warnings.WarningMessage]) -> list[WarningCount]:
    """The warnings caught, each text once, in the order they first came, counted."""
    counts: dict[str, list] = {}
    for w in caught:
        text = str(w.message)
        if text in counts:
            counts[text][1] += 1
        else:
            counts[text] = [w.category.__name__, 1]
    return [WarningCount(text, category, n) for text, (category, n) in counts.items()]


# ------------------------------------------------------------------------------ in words


def written(report: HoleReport) -> str:
    """What was written for the hole, in words: "λ-H fill", "faired fill (bilaplacian)",
    "skipped: why" or "failed: why"."""
    outcome = report.outcome
    blend = _blend(report)
    if blend:
        return blend
    if outcome == "lambda-h":
        return "λ-H fill"
    if outcome == "faired" and report.ear_cut is not None:
        # the loop's ear-cut triangulation (ConformalOptions.ear_cut_ratio, ear_cut_flat:
        # not faired; ear_cut_faired: faired off its planes only, which its label says)
        faired = "" if report.ear_cut == BY_FAIRED_PLANES else ", not faired"
        return f"ear-cut fill ({report.ear_cut}){faired}"
    if outcome == "faired":
        on_plane = "" if report.plane is None else f", laid on {plane_words(report.plane)}"
        smoothed = ", smoothed" if report.smoothed else ""
        return f"faired fill ({FAIRING.get(report.fair_order, 'order ?')}{smoothed}{on_plane})"
    if outcome == "zipped":
        merged = how_many(len(report.zipped), "duplicate vertex", "duplicate vertices")
        return f"seam zipped ({merged} merged)"
    return f"{outcome}: {report.skipped}"


def outcome_words(reports: Sequence[HoleReport]) -> str:
    """What was written for ``reports``, counted in the words of their hole lines (the
    pictures' overview: "1 λ-H fill, 3 faired fills (1 smoothed)"; was the ``--method``
    names, "conformal, fair", where the close-ups say "λ-H fill" and "faired fill")."""
    lambda_h = sum(r.outcome == "lambda-h" for r in reports)
    faired = sum(r.outcome == "faired" for r in reports)
    smoothed = sum(r.smoothed for r in reports)
    words = ([how_many(lambda_h, "λ-H fill", "λ-H fills")] if lambda_h else []) + (
        [how_many(faired, "faired fill", "faired fills")
         + (f" ({smoothed} smoothed)" if smoothed else "")] if faired else [])
    return ", ".join(words) or "none"


def _percent(score: float | None, diameter: float) -> str:
    if score is None:
        return "not scored"
    if not math.isfinite(score):
        return "failed"
    if not diameter > 0:
        return f"{score:.3g} mesh units"
    percent = 100.0 * score / diameter
    return f"{percent:.0f} %" if percent >= 10 else f"{percent:#.2g} %"


def _test_line(test: TestScores, diameter: float, verbose: bool) -> str:
    parts = []
    for name, word in _CANDIDATES:
        score = getattr(test, name)
        if score is None:
            continue
        if verbose and math.isfinite(score):
            parts.append(f"{word} {score:.3g} ({_percent(score, diameter)})")
        else:
            parts.append(f"{word} {_percent(score, diameter)}")
    if verbose:
        return (f"self-check on {test.test}, mean distance to the hidden surface in mesh "
                "units (% of the hole diameter): " + ", ".join(parts))
    return f"self-check on {test.test}: " + ", ".join(parts) + " of the hole diameter"


def _blend(report: HoleReport) -> str | None:
    """A λ-H fill rejected by its checks, written as its largest blend with a faired fill
    that passes them (:class:`~surfinpaint.fill.results.LambdaHDiagnostics`
    ``blended_with``), in words; None otherwise."""
    d = report.diagnostics
    if report.outcome != "lambda-h" or d is None or not d.blended_with:
        return None
    return (f"blend of the λ-H fill ({d.damping:.2g}) with the {d.blended_with} fill "
            f"({1 - d.damping:.2g})")


def _verdict(report: HoleReport) -> str:
    """How the self-check ended, in words."""
    blend = _blend(report)
    if blend:
        return f"the λ-H fill failed its checks, {blend} written ({report.note})"
    if report.outcome == "lambda-h":
        return "λ-H kept"
    if report.fallback:
        return f"the λ-H fill failed ({report.fallback})"
    if report.plane is not None:
        return report.note or "the faired fill laid on the plane of the surface around it"
    if report.verdict is None and report.note:  # nothing to choose between
        return report.note
    if not report.self_check:
        return "no self-check possible here: the faired fill kept"
    return f"{FAIRING.get(report.fair_order, 'faired')} fill kept"


def nothing_to_fill(faces, *, keep_margins: bool = False) -> str:
    """Why a mesh with the triangles ``faces`` had no hole to fill, as ``fill``, ``holes``
    and ``report`` say it: closed, or open only at its outer border (and, with
    ``keep_margins``, any margin kept open). For a mesh none of whose loops was selected
    (with ``--all`` or ``--holes`` every loop is: it is closed)."""
    if not len(boundary_loops(faces)):
        return "the mesh is closed: no holes"
    return "no holes apart from the outer border" + (
        " and any margin --keep-margins keeps open" if keep_margins else "")


def plane_words(plane: PlaneTest | TwoPlanes) -> str:
    """What a fill laid by the plane test was laid on, in words."""
    return "its two planes" if isinstance(plane, TwoPlanes) else "its plane"


def hole_lines(report: HoleReport, verbose: bool = False) -> list[str]:
    """The lines that say what happened to one hole: a first line (number, size, what was
    written, what it added) and, after a conformal fill, one line per self-check test;
    ``verbose`` adds the scores in mesh units, the time, what the λ-H pass used and what
    became of a crease across the hole."""
    head = (f"hole {report.index}: {report.n_edges} boundary edges, diameter "
            f"{report.diameter:.3g} mesh units → {written(report)}")
    if report.outcome in ("lambda-h", "faired"):
        head += (f", {how_many(report.new_vertices, 'new vertex', 'new vertices')}, "
                 f"{how_many(report.new_faces, 'new face', 'new faces')}")
        if report.crossings:
            # near the hole, farther out, or another hole's fill (fill.far_crossings)
            head += f", {report.crossings} of them crossing the surface"
    if verbose:
        head += f" ({report.seconds:.2f} s)"
    lines = [head]
    if report.requested == "conformal" and report.outcome in ("lambda-h", "faired"):
        tests = [_test_line(t, report.diameter, verbose) for t in report.self_check]
        if tests:
            tests[-1] += f" → {_verdict(report)}"
            lines += ["  " + t for t in tests]
        else:
            lines.append(f"  {_verdict(report)}")
    smoothing = smoothing_line(report, verbose)
    if smoothing:
        lines.append(smoothing)
    diagnostics = report.diagnostics
    least_squares = diagnostics.mesh.least_squares if diagnostics and diagnostics.mesh else None
    if least_squares is not None:
        lines.append(f"  λ-H fill: {least_squares.sentence()}")
    if verbose:
        if diagnostics is not None:
            lines.append(f"  λ-H pass: {diagnostics.discretization} discretization, "
                         f"{how_many(diagnostics.rings, 'ring', 'rings')} of known surface, "
                         "damping "
                         f"{diagnostics.damping:.2g}"
                         + (f", map {diagnostics.mesh.map}" if diagnostics.mesh else ""))
        for note in (report.crease, report.crease_failure):
            if note:
                lines.append(f"  crease: {note}")
    return lines


def smoothing_line(report: HoleReport, shut_too: bool) -> str | None:
    """The line on the bilaplacian fill's smoothing (``fair_smoothing``): where it was
    smoothed, always (the written fill, or a candidate the self-check compared); where the
    noise gate stayed shut, with ``shut_too`` only (``-v``: a clean mesh's every hole);
    none for a fill without a vertex inside the hole."""
    smoothing = report.smoothing
    if (smoothing is None or report.outcome not in ("lambda-h", "faired")
            or not report.new_vertices):  # a bare triangulation: nothing was smoothed
        return None
    if smoothing.length is None and not shut_too:
        return None
    return f"  bilaplacian fill {smoothing.sentence()}"


def summary_lines(summary: Summary) -> list[str]:
    """The closing summary: the counts, what was added, the time."""
    found = how_many(summary.holes_found, "hole found", "holes found")
    return [f"{found}: {summary.lambda_h} filled by the λ-H fill, "
            f"{summary.faired} by a faired fill"
            + (f" ({summary.smoothed} smoothed)" if summary.smoothed else "") + ", "
            + (f"{how_many(summary.zipped, 'seam', 'seams')} zipped, "
               if summary.zipped else "")
            + f"{summary.skipped} skipped, "
            f"{summary.failed} failed; "
            f"{how_many(summary.new_vertices, 'new vertex', 'new vertices')}, "
            f"{how_many(summary.new_faces, 'new face', 'new faces')}; {summary.seconds:.1f} s"]


# ------------------------------------------------------------------------------ as JSON


def plain(value: Any) -> Any:
    """``value`` as JSON types: dataclasses and mappings as objects, sequences as lists,
    numpy scalars as numbers, non-finite floats as None (the options of a fill, say)."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {f.name: plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
    if isinstance(value, Mapping):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [plain(v) for v in value]
    if hasattr(value, "item") and callable(value.item):  # numpy scalars
        value = value.item()
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if value is None or isinstance(value, bool | int | float | str):
        return value
    return str(value)


def _score(value: float | None) -> float | None:
    return value if value is not None and math.isfinite(value) else None


def _smoothing_json(smoothing: Smoothing | None) -> dict[str, Any] | None:
    """A :class:`~surfinpaint.fill.results.Smoothing` as JSON types: the length (null: not
    smoothed), the option, why, and the noise estimate in mean edges (null where none)."""
    if smoothing is None:
        return None
    noise = smoothing.noise
    return {"length": smoothing.length, "asked": smoothing.asked, "why": smoothing.why,
            "noise": None if noise is None else _score(float(noise.relative)),
            "correlation": None if noise is None else _score(float(noise.correlation)),
            "scale_ratio": None if noise is None else _score(float(noise.scale_ratio))}


def _test_json(test: TestScores) -> dict[str, Any]:
    names = [name for name, _ in _CANDIDATES]
    return {"test": test.test, **{name: _score(getattr(test, name)) for name in names},
            "failed": [name for name in names if getattr(test, name) is not None
                       and not math.isfinite(getattr(test, name))]}


def _test_from_json(record: Mapping[str, Any]) -> TestScores:
    failed = set(record.get("failed", ()))
    return TestScores(record["test"], **{
        name: math.inf if name in failed else record.get(name) for name, _ in _CANDIDATES})


@dataclass(frozen=True)
class HoleRecord:
    """One hole of the ``--json`` report (and of ``batch``'s ``summary.json``): what a
    :class:`~surfinpaint.fill.results.HoleReport` says, in JSON types (fields:
    ``docs/report.md``). ``diameter`` and the self-check's scores are in mesh units;
    ``reason`` says why a hole was skipped or failed, ``lambda_h_failure`` why the λ-H fill
    failed where a faired fill was written instead."""

    index: int
    boundary_edges: int
    diameter: float | None
    outcome: str
    requested: str
    fairing: str | None
    fair_order: int | None
    new_vertices: int
    new_faces: int
    seconds: float
    reason: str | None
    lambda_h_failure: str | None
    self_check: tuple[TestScores, ...]
    crease: str | None
    crease_failure: str | None
    note: str | None
    crossings: int = 0
    plane: dict[str, float] | None = None
    islands: tuple[int, ...] = ()
    smoothed: bool = False
    smoothing: dict[str, Any] | None = None
    ear_cut: str | None = None

    @classmethod
    def of(cls, r: HoleReport) -> HoleRecord:
        faired = r.outcome == "faired"
        return cls(index=int(r.index), boundary_edges=int(r.n_edges),
                   diameter=_score(float(r.diameter)), outcome=r.outcome,
                   requested=r.requested,
                   fairing=FAIRING.get(r.fair_order) if faired else None,
                   fair_order=int(r.fair_order) if faired and r.fair_order else None,
                   new_vertices=int(r.new_vertices), new_faces=int(r.new_faces),
                   seconds=float(r.seconds),
                   reason=r.skipped if r.outcome in ("skipped", "failed") else None,
                   lambda_h_failure=r.fallback, self_check=r.self_check, crease=r.crease,
                   crease_failure=r.crease_failure, note=r.note,
                   crossings=int(r.crossings),
                   plane=None if r.plane is None else {
                       "p_curvature": float(r.plane.p_curvature),
                       "p_pattern": float(r.plane.p_pattern), "noise": float(r.plane.noise),
                       "vertices": int(r.plane.points), "left_out": int(r.plane.left_out),
                       "past_edges": int(r.plane.past_edges),
                       "planes": 2 if isinstance(r.plane, TwoPlanes) else 1},
                   islands=tuple(int(k) for k in r.islands), smoothed=r.smoothed,
                   smoothing=_smoothing_json(r.smoothing), ear_cut=r.ear_cut)

    def to_json(self) -> dict[str, Any]:
        """As JSON types: a failed candidate's score is null and named in ``failed``."""
        record = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        record["self_check"] = [_test_json(t) for t in self.self_check]
        record["islands"] = list(self.islands)
        return record

    @classmethod
    def from_json(cls, record: Mapping[str, Any]) -> HoleRecord:
        fields = {f.name for f in dataclasses.fields(cls)}
        values = {k: v for k, v in record.items() if k in fields}
        values["self_check"] = tuple(_test_from_json(t) for t in record.get("self_check", ()))
        values["islands"] = tuple(record.get("islands", ()))
        return cls(**values)


def report_document(result: FillResult, summary: Summary, *,
                    warnings_seen: Sequence[WarningCount] = (),
                    options: Mapping[str, Any] | None = None,
                    files: Mapping[str, str | None] | None = None) -> dict[str, Any]:
    """The ``--json`` report as JSON types: the version, the files, the fill options, one
    record per hole, the summary, the topology warnings and every warning with its count
    (the fields: ``docs/report.md``). Scores are in mesh units; a candidate that failed a
    test has a null score and is listed in that test's ``failed``."""
    # here, not at the top: the package imports this module (through app.batch) before it
    # sets __version__
    from surfinpaint import __version__

    return {
        "surfinpaint": __version__, "report_version": REPORT_VERSION,
        "files": dict(files or {}), "options": plain(dict(options or {})),
        "holes": [HoleRecord.of(r).to_json() for r in result.reports],
        "summary": plain(summary),
        "topology": [plain(change) for change in result.topology],
        "warnings": [plain(w) for w in warnings_seen],
    }


def write_json_report(path: str | os.PathLike, document: Mapping[str, Any]) -> None:
    """Write a report document as JSON, atomically (valid JSON: no NaN or Infinity)."""
    with atomic_open(path, "w", encoding="utf-8") as handle:
        json.dump(document, handle, indent=1, ensure_ascii=False, allow_nan=False)
        handle.write("\n")


# ------------------------------------------------------------------------------ telling


def print_warnings(console, counted: Iterable[WarningCount], *,
                   source: str | os.PathLike | None = None, holes_said: bool = False,
                   other_files: Mapping[str | os.PathLike, str] | None = None) -> None:
    """Each warning once on ``console``, with how many times it came when more than once,
    named for the input ``source`` (:func:`~surfinpaint.app.progress.warning_line`: the one
    form of every command's warnings; a warning that starts with one of ``other_files``,
    the command's outputs say, names it as what the command does with it: ``scan.obj
    (writing out/scan.obj): ...``). ``holes_said``: the lines of each hole were printed
    (``fill``'s report, ``report``'s titles), so a
    :class:`~surfinpaint.errors.HoleWarning`, which says the same, is left out."""
    left_out = _hole_warning_names() if holes_said else set()
    # "x" and "SOURCE: x" are one warning once named: the command's check of the file and
    # the fill each saying it (`report`'s degenerate faces), so counted once, not added
    merged: dict[str, int] = {}
    for w in counted:
        if w.category not in left_out:
            text = named(w.message, source, other_files)
            merged[text] = max(merged.get(text, 0), w.count)
    if not merged:  # a quiet run that warns of nothing never imports rich
        return
    for text, count in merged.items():
        console.print(warning_line(text, count=count))


def tell(result: FillResult, summary: Summary, caught: Iterable[warnings.WarningMessage], *,
         console=None, verbose: bool = False, json_path: str | os.PathLike | None = None,
         files: Mapping[str, str | None] | None = None,
         options: Mapping[str, Any] | None = None, report: bool = True,
         source: str | os.PathLike | None = None,
         other_files: Mapping[str | os.PathLike, str] | None = None) -> list[WarningCount]:
    """Say what a fill did: write the ``--json`` report (``json_path``), and print on
    ``console`` (None: print nothing) the lines of each hole and the summary (``report``)
    and each warning caught once, named for the input ``source`` and the command's
    ``other_files`` (with the report, not a
    :class:`~surfinpaint.errors.HoleWarning`: the hole's lines say it; without it, every
    warning: ``-q`` keeps them; :func:`print_warnings`). Returns the warnings counted (all
    of them: the ``--json`` report lists them too)."""
    seen = count_warnings(caught)
    if json_path is not None:
        write_json_report(json_path, report_document(result, summary, warnings_seen=seen,
                                                     files=files, options=options))
    if console is None:
        return seen
    if not report:
        print_warnings(console, seen, source=source, other_files=other_files)
        return seen
    from rich.markup import escape  # only when printing: a quiet run never imports rich

    for r in result.reports:
        for line in hole_lines(r, verbose=verbose):
            console.print(escape(line))
    if result.reports:
        for line in summary_lines(summary):
            console.print(escape(line))
    # what the hole lines said already is not said again
    print_warnings(console, seen, source=source, holes_said=True, other_files=other_files)
    return seen
