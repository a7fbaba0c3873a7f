"""Batch filling's summary: one :class:`FileRow` per input file, written to ``summary.csv``
and ``summary.json`` (which also records the fill options and the version) and read back
by a rerun (the counts of the files it skips, the seconds it orders the files by)."""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import os
import re
import time
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from surfinpaint.app.batch_inputs import FileJob, UnknownFile
from surfinpaint.app.fill_report import HoleRecord, plain
from surfinpaint.errors import MeshError, how_many
from surfinpaint.fill.pipeline import METHODS, FillResult
from surfinpaint.io.atomic import atomic_open
from surfinpaint.io.brain import check_overlay
from surfinpaint.io.formats import check_file, files_read

__all__ = ["MESSAGE_SEPARATOR", "FileRow", "FileRows", "STATUSES", "SUMMARY_CSV", "SUMMARY_JSON",
           "checked_row", "error_text", "fill_messages", "kept_rows", "named_in_summary",
           "option_changes", "read_summary", "read_unknown_files", "row_of", "write_summary"]

Status = Literal["filled", "unfilled", "closed", "failed", "skipped"]
#: The statuses of a :class:`FileRow`, in the order the summary counts them.
STATUSES: tuple[str, ...] = ("filled", "unfilled", "closed", "failed", "skipped")

SUMMARY_CSV, SUMMARY_JSON = "summary.csv", "summary.json"
#: What joins a row's warnings and notes into its ``message``.
MESSAGE_SEPARATOR = " | "


@dataclass(frozen=True)
class FileRow:
    """What happened to one input file: a row of ``summary.csv`` / ``summary.json``.

    ``status`` is "filled" (the fill ran, filled at least one hole, and the output was
    written; holes it did not fill are named in ``message``), "unfilled" (holes were found
    and none was filled: each is named in ``message`` with why; the mesh was written
    unchanged), "closed" (no hole to fill: the mesh was written unchanged),
    "failed" (nothing written; ``message`` holds the error) or "skipped" (the output was
    newer than the input and left alone; the counts are those of the run that wrote it,
    when its summary says). ``holes_found`` counts the holes selected for filling (the
    outer border of an open surface only with ``include_border``), ``kept`` the holes
    whose fill was kept per method (a conformal fill can fall back to, or prefer, "fair"),
    ``seconds`` the wall time of reading, filling and writing the file, and ``message``
    the warnings and notes of the fill, or the error. ``path`` is the input as given,
    ``output`` the output's path relative to the output folder, ``holes`` what happened to
    each hole (as ``surfinpaint fill --json`` says it; in ``summary.json`` only).
    ``picture`` is the before/after picture's path relative to the output folder (``png``
    of :func:`surfinpaint.fill_files`, ``batch --png``) when one was written, else None (a
    picture that could not be drawn is named in ``message``; the output is still written).
    """

    path: str
    output: str
    status: Status
    holes_found: int | None = None
    holes_filled: int | None = None
    kept: Mapping[str, int] = field(default_factory=dict)
    new_vertices: int | None = None
    seconds: float = 0.0
    message: str = ""
    holes: tuple[HoleRecord, ...] = ()
    picture: str | None = None
    #: The material files copied beside an OBJ output (relative to its folder) and the
    #: SHA-1 of each copy (:class:`~surfinpaint.io.materials.CopiedMaterials`; in
    #: ``summary.json`` only): a rerun copies one again when the input's changed and the
    #: copy did not.
    materials: Mapping[str, str] = field(default_factory=dict)
    #: Of the holes filled, those whose written fill is the smoothing fill (``fair_smoothing``:
    #: :attr:`~surfinpaint.fill.results.HoleReport.smoothed`; each hole's why in ``holes``).
    smoothed: int | None = None
    #: The fill options the output was written with (in ``summary.json`` only, as its
    #: ``options``): this run's, or a skipped file's earlier run's, so that a rerun with
    #: other options can say which files it did not refill (:func:`option_changes`); set
    #: when the summary is written, so not compared (the rows ``fill_files`` returns have None).
    options: Mapping[str, Any] | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"status must be one of {', '.join(STATUSES)}, got "
                             f"{self.status!r}")


def named_in_summary(job: FileJob, text: str) -> str:
    """``text`` naming files as the summary does (workers see absolute paths): the input by
    its ``path`` (as given), a ``--overlay`` file from where the input's name is (``..``
    resolved), and any other file below the folder the input's name is relative to (where
    the batch was started, for an input given by a relative name) relative to that folder,
    as ``fill`` names the files given to it: the output and its materials too
    (``out/scan.obj: out/scan.mtl ...``; the output named relative to the output folder,
    as its ``output`` column, read as the input where both are ``scan.obj``)."""
    text = text.replace(os.fspath(job.source), job.name)
    try:
        overlays = job.overlay_files()
    except MeshError:  # its error names the pattern
        overlays = {}
    for path, name in overlays.items():
        text = text.replace(os.fspath(path), name)
    name = Path(job.name)
    if name.is_absolute() or len(job.source.parts) <= len(name.parts) + 1:
        return text
    root = Path(*job.source.parts[:-len(name.parts)])
    if root / name != job.source:
        return text
    # the folder where a path starts, not inside another path (/data/tmp/x/ for /tmp/x/)
    return re.sub(rf"(?<![\w.~/-]){re.escape(os.fspath(root) + os.sep)}", "", text)


def fill_messages(job: FileJob, result: FillResult,
                  caught: Iterable[warnings.WarningMessage]) -> str:
    """The ``message`` of a file filled: its warnings (``caught``), each once, and the
    holes skipped without one."""
    texts: list[str] = []
    for text in [named_in_summary(job, str(w.message)) for w in caught]:
        if text not in texts and not any(text in t for t in texts):
            texts.append(text)
    # each skipped hole once: its warning, where it had one, already says why
    texts += [f"hole {r.index}: skipped ({r.skipped})" for r in result.reports if r.skipped
              and not any(f"hole {r.index}: {r.skipped}" in t for t in texts)]
    if len(result.removed_faces):
        removed = how_many(len(result.removed_faces), "face", "faces")
        texts.append(f"repair removed {removed} around non-manifold "
                     "edges and bow-tie vertices")
    return MESSAGE_SEPARATOR.join(texts)


def row_of(job: FileJob, result: FillResult, seconds: float, message: str,
           picture: str | None) -> FileRow:
    """The row of ``job`` filled into ``result``: "closed" without a hole to fill,
    "unfilled" when none of its holes was filled, else "filled"."""
    kept: dict[str, int] = {}
    for report in result.reports:
        if not report.skipped:
            kept[report.method] = kept.get(report.method, 0) + 1
    filled = sum(kept.values())
    status = "closed" if not result.reports else "filled" if filled else "unfilled"
    return FileRow(job.name, job.output, status,
                   holes_found=len(result.reports), holes_filled=filled, kept=kept,
                   new_vertices=len(result.vertices) - result.n_original_vertices,
                   seconds=seconds, message=message,
                   holes=tuple(HoleRecord.of(r) for r in result.reports), picture=picture,
                   smoothed=sum(r.smoothed for r in result.reports))


def error_text(job: FileJob, exc: Exception) -> str:
    """The ``message`` of a file that failed with ``exc``, naming it (first: an error that
    names another file, an overlay, follows the input's name)."""
    if isinstance(exc, MeshError):
        text = named_in_summary(job, str(exc if exc.path else exc.with_path(job.name)))
        return text if text.startswith(job.name) else f"{job.name}: {text}"
    return named_in_summary(job, f"{job.name}: {type(exc).__name__}: {exc}")


def checked_row(job: FileJob) -> FileRow | None:
    """The failed row of a file that fails its pre-flight (:func:`~surfinpaint.io.formats.
    check_file`: missing, unreadable, empty, of unknown format or with a header its reader
    cannot parse; and each overlay its fill reads, those beside the surface and those of
    ``--overlay``: :func:`~surfinpaint.io.brain.check_overlay`), with the message its fill
    would give and the check's seconds; None for a file that passes."""
    started = time.perf_counter()
    try:
        check_file(job.source)
        # the reader fails a surface on any overlay it reads, found beside it or given
        for overlay in job.overlays_read() if job.overlays else files_read(job.source)[1:]:
            check_overlay(overlay)
    except MeshError as exc:
        return FileRow(job.name, job.output, "failed", seconds=time.perf_counter() - started,
                       message=error_text(job, exc))
    return None


def _csv_columns() -> list[str]:
    return ["path", "output", "status", "holes_found", "holes_filled",
            *[f"kept_{m}" for m in METHODS], "new_vertices", "seconds", "message",
            "picture", "smoothed"]  # added last: readers by position keep working


def _csv_record(row: FileRow) -> dict[str, Any]:
    record = dataclasses.asdict(dataclasses.replace(row, holes=()))
    del record["holes"], record["materials"], record["options"]  # summary.json only
    kept = record.pop("kept")
    record.update({f"kept_{m}": kept.get(m, 0) if row.holes_found is not None else None
                   for m in METHODS})
    record["seconds"] = f"{row.seconds:.3f}"
    return record


class FileRows(list[FileRow]):
    """What :func:`~surfinpaint.app.batch.fill_files` returns: one :class:`FileRow` per
    input file, in the inputs' order, and ``unknown``, the files of unknown type that were
    not filled (:attr:`.Inputs.unknown`; ``summary.json``'s ``unknown_files``), and
    ``earlier``, how many rows of files filled by earlier runs the summary keeps beside
    them (:func:`kept_rows`)."""

    def __init__(self, rows: Sequence[FileRow] = (), unknown: Sequence[UnknownFile] = (),
                 earlier: int = 0):
        super().__init__(rows)
        self.unknown: tuple[UnknownFile, ...] = tuple(unknown)
        self.earlier = earlier


def kept_rows(rows: Sequence[FileRow], earlier: Sequence[FileRow],
              out_dir: str | os.PathLike) -> list[FileRow]:
    """The rows of ``earlier`` (the output folder's summary before this run,
    :func:`read_summary`) that its summary keeps beside this run's ``rows``: those of the
    outputs this run has no row of, whose output is still in ``out_dir`` (a failed row's
    always: it has none), each once, in their order. So the summary lists every file filled
    into the folder, by this run or an earlier one (a rerun on some of the files, or after
    one failed, dropped the others' rows before session 47); an output deleted since is
    not listed."""
    out, listed = Path(out_dir), {row.output for row in rows}
    kept = []
    for row in earlier:
        if row.output not in listed and (row.status == "failed" or
                                         (out / row.output).is_file()):
            kept.append(row)
            listed.add(row.output)
    return kept


def _in_place(rows: Sequence[FileRow], earlier: Sequence[FileRow], kept: Sequence[FileRow]
              ) -> list[FileRow]:
    """The summary's order: ``earlier``'s, each row replaced by this run's row of its output
    or left out where not ``kept``; then the rest of this run's ``rows``, in their order."""
    ours = {row.output: row for row in rows}
    kept_ids = {id(row) for row in kept}
    listed = [ours.pop(row.output) if row.output in ours else row for row in earlier
              if row.output in ours or id(row) in kept_ids]
    return listed + list(ours.values())


def write_summary(rows: Sequence[FileRow], out_dir: str | os.PathLike,
                  options: Mapping[str, Any] | None = None,
                  unknown: Sequence[UnknownFile] = (),
                  earlier: Sequence[FileRow] = ()) -> tuple[Path, Path]:
    """Write ``summary.csv`` and ``summary.json`` (with the fill options, the version and
    the files of ``unknown`` type that were not filled, :attr:`.Inputs.unknown`: their
    count and paths) into ``out_dir``, each atomically; returns their paths.

    ``earlier``: the rows of the folder's summary before this run (:func:`read_summary`);
    those of the files this run has no row of are kept (:func:`kept_rows`), with the options
    they were filled with, in their places, each row of this run taking the place of its
    output's earlier row, and this run's other rows after them."""
    # here, not at the top: the package imports this module before it sets __version__
    from surfinpaint import __version__

    out = Path(out_dir)
    kept = kept_rows(rows, earlier, out)
    listed = _in_place(rows, earlier, kept)
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=_csv_columns(), lineterminator="\n")
    writer.writeheader()
    writer.writerows(_csv_record(row) for row in listed)
    now = plain(dict(options or {}))
    # a skipped file, or one of an earlier run, keeps the options of the run that filled it
    theirs = {id(row) for row in kept}
    document = {"surfinpaint": __version__, "options": now,
                "files": [{**plain(dataclasses.replace(
                    row, holes=(), options=row.options
                    if row.status == "skipped" or id(row) in theirs else now)),
                           "holes": [h.to_json() for h in row.holes]} for row in listed],
                "unknown_files": {"count": len(unknown), "paths": [u.path for u in unknown]}}
    with atomic_open(out / SUMMARY_CSV, "w") as handle:
        handle.write(text.getvalue())
    with atomic_open(out / SUMMARY_JSON, "w") as handle:
        json.dump(document, handle, indent=1, allow_nan=False)
        handle.write("\n")
    return out / SUMMARY_CSV, out / SUMMARY_JSON


def read_summary(out_dir: str | os.PathLike) -> list[FileRow]:
    """The rows of ``out_dir/summary.json``; empty when there is none (or it is unreadable:
    it is only used to carry the counts of an earlier run into a rerun's skipped rows, its
    seconds into the order a rerun's files are started in, and the rows of the files a
    rerun does not name into its summary, :func:`kept_rows`)."""
    try:
        document = json.loads((Path(out_dir) / SUMMARY_JSON).read_text(encoding="utf-8"))
        # a summary before session 46 has the run's options only
        return [FileRow(**{**entry, "holes": tuple(HoleRecord.from_json(h) for h in
                                                   entry.get("holes", ())),
                           "options": entry.get("options", document.get("options"))})
                for entry in document["files"]]
    except (OSError, ValueError, KeyError, TypeError):
        return []


def option_changes(before: Mapping[str, Any] | None, now: Mapping[str, Any]) -> list[str]:
    """The fill options that differ between ``before`` (a row's :attr:`FileRow.options`)
    and ``now`` (as ``summary.json`` records them), each as ``name before -> now``, a
    conformal option by its own name; empty where ``before`` is unknown (None)."""
    if before is None:
        return []
    flat = [{**{k: v for k, v in o.items() if k != "options"}, **(o.get("options") or {})}
            for o in (before, plain(dict(now)))]
    return [f"{name} {flat[0].get(name)!r} -> {flat[1].get(name)!r}"
            for name in sorted(set(flat[0]) | set(flat[1]))
            if flat[0].get(name) != flat[1].get(name)]


def read_unknown_files(out_dir: str | os.PathLike) -> list[str]:
    """The paths of the files of unknown type that ``out_dir/summary.json`` records as not
    filled; empty when it records none (or there is no readable summary)."""
    try:
        document = json.loads((Path(out_dir) / SUMMARY_JSON).read_text(encoding="utf-8"))
        return [str(path) for path in document.get("unknown_files", {}).get("paths", [])]
    except (OSError, ValueError, AttributeError):
        return []
