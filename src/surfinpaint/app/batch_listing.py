"""A batch's listing: its input files found, each judged before any is filled (up to date:
skipped; failing its pre-flight: failed; else to fill, costliest first), and the run's rows
as they come in, from the listing and then from the runners of
:func:`surfinpaint.app.batch.fill_files`.

An interrupt (Ctrl-C, the command line's SIGTERM) or a callback's error while the files are
listed and judged writes the summary as one during the fills does: the files done (skipped,
failed) recorded, the others left to the rerun (their rows of the earlier summary kept:
:func:`list_jobs`).
"""

from __future__ import annotations

import dataclasses
import glob
import os
import re
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from queue import Empty
from typing import Any

from surfinpaint.app.batch_inputs import (
    FileJob,
    Inputs,
    find_inputs,
    largest_cost_first,
    up_to_date,
)
from surfinpaint.app.batch_reruns import rerun_row
from surfinpaint.app.batch_summary import (
    SUMMARY_JSON,
    FileRow,
    FileRows,
    checked_row,
    kept_rows,
    read_summary,
    write_summary,
)
from surfinpaint.errors import how_many

# the files in flight are said again after as long without news as a hole's stage is (the
# same message: a bar's clock goes on, a log can tell a stage that lasts)
from surfinpaint.fill.scheduler import SAY_AGAIN_SECONDS

__all__ = ["ProgressCallback", "ResultCallback", "RunRows", "files_in_flight", "list_jobs",
           "remove_temporaries"]

ProgressCallback = Callable[[int, int, str], None]
ResultCallback = Callable[[FileRow], None]
# What joins the files in flight, each with its hole, in a progress message, and how each
# says its hole (RunRows.hole)
_IN_FLIGHT_SEPARATOR = " · "
_IN_FLIGHT = re.compile(r": \d+/\d+ holes \(")


def files_in_flight(message: str) -> list[str]:
    """What a ``progress`` message of a batch says of each file in flight, its hole and the
    hole's stage (``scans/a.ply: 0/2 holes (hole 0: 212 edges, λ-H fill (stage 5 of 5))``);
    empty for a message of a file done or of the run."""
    said = message.split(_IN_FLIGHT_SEPARATOR)
    return said if all(_IN_FLIGHT.search(part) for part in said) else []


def remove_temporaries(jobs: Iterable[FileJob]) -> None:
    """Delete what a worker killed mid-write left: the temporary files of the atomic writer
    (:mod:`surfinpaint.io.atomic`: ``.NAME.XXXXXX.tmp`` next to the target, and
    ``.NAME.XXXXXX.png`` next to the picture). Only called while no worker writes them."""
    for job in jobs:
        for path, suffix in ((job.target, ".tmp"), (job.picture, ".png")):
            if path is None:
                continue
            for leftover in path.parent.glob(f".{glob.escape(path.name)}.*{suffix}"):
                leftover.unlink(missing_ok=True)


class RunRows:
    """The rows of a run as they come in, the result callback given each, and the progress
    callback told of each, and of the holes of the files in flight."""

    def __init__(self, total: int, progress: ProgressCallback | None,
                 on_result: ResultCallback | None = None, out_dir: str | os.PathLike = ".",
                 earlier: Sequence[FileRow] = ()) -> None:
        self.total, self.progress, self.on_result = total, progress, on_result
        # the output folder and its summary's rows before this run: kept for the files
        # this run does not record (a rerun on some of them, an interrupted run)
        self.out_dir, self.earlier = Path(out_dir), list(earlier)
        self.by_name: dict[str, FileRow] = {}
        self.holes: dict[str, str] = {}  # the hole progress of each file in flight
        self.said_at = time.monotonic()  # when the progress callback was last told

    def add(self, row: FileRow, *, quiet: bool = False) -> None:
        """Record ``row``; unless ``quiet`` (the run is being stopped: no callback may run
        then), give it to the result callback, then tell the progress callback."""
        self.by_name[row.path] = row
        self.holes.pop(row.path, None)
        if quiet:
            return
        if self.on_result is not None:
            self.on_result(row)
        if self.progress is not None:
            self.said_at = time.monotonic()
            self.progress(len(self.by_name), self.total, f"{row.path}: {row.status}")

    def hole(self, name: str, done: int, total: int, message: str) -> None:
        """A file in flight is at hole ``done`` of ``total``: the files done stay the count,
        the files in flight and their holes the message."""
        if self.progress is None or name in self.by_name:
            return  # a late word from a file already recorded
        self.holes[name] = f"{name}: {done}/{total} holes ({message})"  # "of N holes"
        self._say_holes()

    def _say_holes(self) -> None:
        self.said_at = time.monotonic()
        self.progress(len(self.by_name), self.total,
                      _IN_FLIGHT_SEPARATOR.join(self.holes.values()))

    def hole_progress_of(self, job: FileJob) -> ProgressCallback | None:
        """The ``hole_progress`` of :func:`~surfinpaint.app.batch.fill_file` for ``job``
        filled in this process."""
        if self.progress is None:
            return None
        return lambda done, total, message: self.hole(job.name, done, total, message)

    def read(self, queue: Any) -> None:
        """Show what the workers sent through ``queue`` so far; without news for
        :data:`SAY_AGAIN_SECONDS`, the files in flight again (a hole of minutes: the bar's
        clock goes on, and ``batch``'s log says a stage that lasts)."""
        while True:
            try:
                self.hole(*queue.get_nowait())
            except Empty:
                break
        if self.holes and time.monotonic() - self.said_at >= SAY_AGAIN_SECONDS:
            self._say_holes()

    def ordered(self, jobs: Inputs) -> FileRows:
        """The rows in the inputs' order (files not done, after an interrupt, left out),
        with the count of the earlier summary's rows that the summary keeps beside them
        (:func:`~surfinpaint.app.batch_summary.kept_rows`)."""
        rows = [self.by_name[job.name] for job in jobs if job.name in self.by_name]
        return FileRows(rows, jobs.unknown,
                        earlier=len(kept_rows(rows, self.earlier, self.out_dir)))

    def write_summary(self, jobs: Inputs, options: Mapping[str, Any] | None) -> None:
        """Write the summary of the output folder: the rows of ``jobs`` recorded so far and
        the earlier summary's rows of the other files (:func:`~surfinpaint.app.
        batch_summary.write_summary`)."""
        write_summary(self.ordered(jobs), self.out_dir, options, jobs.unknown,
                      earlier=self.earlier)


def list_jobs(inputs: Sequence[str | os.PathLike] | str | os.PathLike,
              out_dir: str | os.PathLike, overwrite: bool, progress: ProgressCallback | None,
              png: bool, overlays: Sequence[str], on_result: ResultCallback | None = None,
              options: Mapping[str, Any] | None = None,
              ) -> tuple[Inputs, list[FileJob], RunRows]:
    """The input files (:func:`~surfinpaint.app.batch_inputs.find_inputs`), those to fill
    (the others recorded in the rows: skipped as up to date, or failed by their pre-flight,
    :func:`~surfinpaint.app.batch_summary.checked_row`), costliest first, and the rows.

    On an interrupt, or an error of a callback, while the files are judged, the summary is
    written (with ``options``) before it propagates, as during the fills: the rows recorded
    so far and, for the other files, their rows of the earlier summary (so an interrupted
    rerun forgets none of its skipped rows' counts and copied materials). An interrupt
    while the files are found leaves an earlier summary as it is, else writes an empty
    one."""
    paths = [inputs] if isinstance(inputs, str | os.PathLike) else list(inputs)
    out = Path(out_dir)
    try:
        todo = find_inputs(paths, out, png=png, overlays=overlays)
    except Exception:
        raise  # bad inputs: the caller's error, before anything is done
    except BaseException:
        # interrupted before any file was judged: nothing done, which the summary says
        if not (out / SUMMARY_JSON).is_file():
            out.mkdir(parents=True, exist_ok=True)
            write_summary([], out, options)
        raise
    out.mkdir(parents=True, exist_ok=True)
    before_run = read_summary(out)
    earlier = {row.path: row for row in before_run}
    rows = RunRows(len(todo), progress, on_result, out, before_run)
    pending: list[FileJob] = []
    try:
        if progress is not None:
            progress(0, len(todo), how_many(len(todo), 'file', 'files'))
        for job in todo:
            before = earlier.get(job.name)
            if before is not None and before.output == job.output and before.materials:
                # the materials the last run copied: copied again if they changed, unless
                # the copies did (their SHA-1 recorded)
                job = dataclasses.replace(job, copied=tuple(sorted(before.materials.items())))
            # up to date: skipped, its changed materials (.mtl, textures) copied again
            row = rerun_row(job, before) if not overwrite and up_to_date(job) else None
            # each file to fill checked cheaply before any is filled: a bad one is said now,
            # not when the largest-first order reaches it (an empty or truncated file: near
            # the end)
            row = checked_row(job) if row is None else row
            if row is not None:
                rows.add(row)
            else:
                pending.append(job)
    except BaseException:
        rows.write_summary(todo, options)  # the files not judged yet keep their earlier rows
        raise
    remove_temporaries(pending)
    # the costliest files first (by the earlier run's seconds, else by size), so that the
    # workers run out of work at about the same time
    pending = largest_cost_first(pending, {name: row.seconds for name, row in earlier.items()})
    return todo, pending, rows
