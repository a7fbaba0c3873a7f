"""``surfinpaint batch``: many mesh files filled on worker processes or a Dask cluster
(:func:`surfinpaint.app.batch.fill_files`), each file's error or warnings said as it
finishes, a summary at the end; exit 1 if any file failed, 130/143 after Ctrl-C/SIGTERM."""

from __future__ import annotations

import argparse
import contextlib
import os
import signal
import threading
import time
import warnings
from collections.abc import Iterator
from pathlib import Path

from surfinpaint.app.batch_inputs import check_overlay_patterns, picture_path
from surfinpaint.app.fill_options import UsageError, add_fill_options, fill_options
from surfinpaint.app.interrupts import Interrupted
from surfinpaint.app.progress import QuietConsole, add_quiet, progress_bar, warning_line
from surfinpaint.errors import how_many
from surfinpaint.lazy import lazy_module

#: How long a hole's stage lasts before a batch's log says it (a log, not a terminal)
LOG_AFTER_SECONDS = 10.0

# imported at its first use (surfinpaint.lazy), as the command line's other heavy parts
batch = lazy_module("surfinpaint.app.batch")
batch_summary = lazy_module("surfinpaint.app.batch_summary")
batch_listing = lazy_module("surfinpaint.app.batch_listing")

__all__ = ["add_batch_parser", "run_batch"]


# what an interrupted batch did with the files in flight (fill_files), locally / on Dask;
# or that it was interrupted while the files were listed, before any fill
_STOPPED = (("the files in flight were stopped unfinished, leaving no partial output",
             ", the files in flight included"),
            ("the files in flight were cancelled on the cluster (a task already running there "
             "may still write its output, whole; none is left partial)",
             ", the files in flight included"),
            ("no file was being filled yet (the files were being listed and checked)", ""))


def run_batch(args: argparse.Namespace) -> int:
    """``surfinpaint batch``: fill the files, say each one's trouble as it finishes, and
    return the exit code (1 if any file failed; 128 + the signal after an interrupt)."""
    from rich.markup import escape

    out = QuietConsole(args.quiet)
    options = fill_options(args)
    if args.jobs is not None and args.dask_scheduler:
        raise UsageError("--jobs is for worker processes on this machine; with "
                         "--dask-scheduler the cluster's workers fill the files")
    if args.jobs is not None and args.jobs < 1:
        raise UsageError(f"--jobs must be at least 1, got {args.jobs}")
    try:
        overlays = check_overlay_patterns(args.overlay or ())
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    client = _dask_client(args.dask_scheduler) if args.dask_scheduler else None
    try:
        # each file's error or warnings as it finishes, above the bar: a bad file early in
        # a run of hours is said then, not at the end
        with progress_bar(out.progress, None, "files", ticking=True) as bar, out.above(bar), \
                _warned_now(out):
            logged = _LoggedRows(out, bar)
            rows = batch.fill_files(args.inputs, args.output, jobs=args.jobs, client=client,
                                    overwrite=args.overwrite, png=args.png, overlays=overlays,
                                    progress=logged.update if out.progress else None,
                                    on_result=lambda row: logged.say(row, args.output),
                                    **options)
    except (Interrupted, KeyboardInterrupt) as exc:
        said = _STOPPED[2 if getattr(exc, "while_listing", False) else client is not None]
        if not isinstance(exc, Interrupted):
            exc = Interrupted(signal.SIGINT)
        out.error(f"surfinpaint: {exc}; {said[0]}; the files done are in "
                  f"{Path(args.output) / batch.SUMMARY_CSV}, and the same command again picks "
                  f"up the rest{said[1]}")
        return exc.exit_code
    finally:
        if client is not None:
            client.close()
    _say_other_options(out, rows, options, args.output)
    _say_filled_elsewhere(out, rows, args.output)
    counts = ", ".join(f"{sum(r.status == s for r in rows)} {s}" for s in batch.STATUSES)
    failed = sum(r.status == "failed" for r in rows)
    if out.progress:
        n = len(rows.unknown)
        unknown = f"; {how_many(n, 'file', 'files')} of unknown type not filled (listed in " \
            "summary.json)" if n else ""
        kept = f" (with the rows of {how_many(rows.earlier, 'file', 'files')} earlier runs " \
            "filled into it)" if rows.earlier else ""
        out.say(f"{how_many(len(rows), 'file', 'files')}: {counts}{unknown}; wrote "
                f"{Path(args.output) / batch.SUMMARY_CSV} and summary.json{kept}")
    elif failed:  # -q, -qq: a log of thousands of files still ends with how many failed
        out.error(f"[red]error:[/red] {failed} of {how_many(len(rows), 'file', 'files')} "
                  f"failed (each named above; all in "
                  f"{escape(str(Path(args.output) / batch.SUMMARY_CSV))})")
    return 1 if failed else 0


def _say_other_options(out: QuietConsole, rows, options: dict, out_dir: str) -> None:
    """One warning where files were skipped as up to date but written with other fill
    options than this run's: a rerun with other options (``--fair-smoothing off`` on a few
    files) otherwise leaves them as they were, without a word (session 46)."""
    other = [(r, batch_summary.option_changes(r.options, options)) for r in rows
             if r.status == "skipped"]
    other = [(r, changes) for r, changes in other if changes]
    if not other:
        return
    row, changes = other[0]
    files = how_many(len(other), "file was", "files were")
    names = ", ".join(r.path for r, _ in other[:3]) + (
        f" and {len(other) - 3} more" if len(other) > 3 else "")
    out.warn(warning_line(
        f"{files} skipped as up to date ({names}), but an earlier run filled them with other "
        f"options ({row.path + ': ' if len(other) > 1 else ''}{', '.join(changes)}): kept "
        f"as they were; --overwrite refills them with this run's "
        f"({Path(out_dir) / 'summary.json'} records each file's)"))


def _say_filled_elsewhere(out: QuietConsole, rows, out_dir: str) -> None:
    """One warning where a file this run wrote was filled into another output of the folder by
    an earlier run: a file given alone goes to the top of OUTDIR, so a rerun of one file of a
    folder given earlier (``batch scans/sub/a.ply -o out`` after ``batch scans -o out``)
    writes ``out/a.ply`` beside ``out/sub/a.ply``, and the summary lists both (session 47)."""
    written = [row for row in rows if row.status not in ("failed", "skipped")]
    ours, paths = {row.output for row in written}, {row.path for row in written}
    elsewhere: dict[str, str] = {}
    for row in batch.read_summary(out_dir):
        if row.output not in ours and row.path in paths:
            elsewhere.setdefault(row.path, row.output)
    if not elsewhere:
        return
    row = next(r for r in written if r.path in elsewhere)
    more = f" (and {how_many(len(elsewhere) - 1, 'file', 'files')} more)" \
        if len(elsewhere) > 1 else ""
    out.warn(warning_line(
        f"{row.path} was filled into {Path(out_dir) / row.output}, but an earlier run filled "
        f"it into {Path(out_dir) / elsewhere[row.path]}{more}: both are kept, and listed in "
        f"{Path(out_dir) / batch.SUMMARY_CSV}; a file given alone goes to the top of the "
        "output folder: to refill it in its place, give the folder or glob of the earlier "
        "run again (the files up to date are skipped)"))


@contextlib.contextmanager
def _warned_now(out: QuietConsole) -> Iterator[None]:
    """Each warning of this process said as it comes, as ``main`` would say it at the end:
    ``batch``'s own (files of unknown type skipped, found before any file is filled); the
    files' warnings are their rows' (:func:`_say_row`)."""
    with warnings.catch_warnings():
        # no input file is named: a batch's own warnings are of none of its files
        warnings.showwarning = lambda message, *_, **__: out.warn(warning_line(str(message)))
        yield


def _say_row(out: QuietConsole, row: batch.FileRow, out_dir: str) -> None:
    """Say what went wrong with the file of ``row`` (``fill_files``'s ``on_result``): its
    error, or each of its warnings on a line of its own, naming the input, and the output
    where the warning is of writing it (a skipped file's were said by the run that wrote
    it)."""
    from rich.markup import escape

    if row.status == "failed":
        out.error(f"[red]error:[/red] {escape(row.message)}")
    elif row.message and row.status != "skipped":
        written = _written_for(out_dir, row)
        for text in row.message.split(batch.MESSAGE_SEPARATOR):
            out.warn(warning_line(text, row.path, other_files=written))


class _LoggedRows:
    """``fill_files``' ``progress`` and ``on_result`` for the bar ``bar``: each file's
    problems as it finishes (:func:`_say_row`), and where stderr is no terminal (a log of an
    overnight run, where rich draws the bar once, at the end) a line per file done too, so
    the log shows how far the run is: ``3/40 scans/a.ply: filled, 2 of 2 holes, 1.2 s``;
    and a line for a hole's stage that has lasted :data:`LOG_AFTER_SECONDS`, once, so that
    the log is not silent while one hole takes minutes: ``  scans/nut.ply: 0/1 holes (hole
    1: 374 edges, λ-H fill (stage 5 of 5)), 10 s so far`` (session 47; the progress of the
    files in flight is said again every second without news: on worker processes, the
    default; with ``--jobs 1``, whose fills run in this process, by the bar's clock, the
    bar's ``on_tick``, from its thread: session 48)."""

    def __init__(self, out: QuietConsole, bar, clock=time.monotonic) -> None:
        self.out, self.bar, self.done, self.total = out, bar, 0, None
        self.log = bar.console is not None and not bar.console.is_terminal
        self.clock = clock
        self.since: dict[str, float] = {}  # when each file's hole and stage was first said
        self.logged: set[str] = set()
        self.last = ""  # the last message, said again at the bar's ticks
        self.lock = threading.Lock()  # the ticks come from the bar's clock thread
        if self.log:
            bar.on_tick = self._tick

    def update(self, done: int, total: int, message: str) -> None:
        self.total = total
        self.bar.update(done, total, message)
        if self.log:
            with self.lock:
                self.last = message
                self._log_lasting(message)

    def _tick(self) -> None:
        with self.lock:
            self._log_lasting(self.last)

    def _log_lasting(self, message: str) -> None:
        from rich.markup import escape

        in_flight = batch_listing.files_in_flight(message)
        if not in_flight:  # a file done: the others' stages go on
            return
        now = self.clock()
        self.since = {said: self.since.get(said, now) for said in in_flight}
        for said, since in self.since.items():
            if now - since >= LOG_AFTER_SECONDS and said not in self.logged:
                self.out.say(f"  {escape(said)}, {now - since:.0f} s so far")
                self.logged.add(said)
        self.logged &= set(self.since)  # what is said no more is never said again

    def say(self, row: batch.FileRow, out_dir: str) -> None:
        from rich.markup import escape

        _say_row(self.out, row, out_dir)
        self.done += 1
        if self.log and row.status != "failed":  # a failed file's error said it
            holes = (f", {row.holes_filled} of {how_many(row.holes_found, 'hole', 'holes')}"
                     if row.holes_found else "")
            self.out.say(f"{self.done}/{self.total or '?'} {escape(row.path)}: {row.status}"
                         f"{holes}, {row.seconds:.1f} s")


def _written_for(out_dir: str, row: batch.FileRow) -> dict[str, str]:
    """The files batch wrote for ``row`` (its output and picture), in each spelling its
    message may name them (:func:`~surfinpaint.app.batch_summary.named_in_summary`: from
    where the input's name is, or absolute), each as "writing"."""
    relative = [row.output, picture_path(Path(row.output)).as_posix()]
    return {spelled: "writing" for name in relative for spelled in (
        os.path.join(out_dir, name), os.path.abspath(os.path.join(out_dir, name)),
        os.fspath(Path(out_dir).absolute() / name))}


def _dask_client(address: str):
    try:
        from distributed import Client
    except ImportError as exc:
        raise UsageError("--dask-scheduler needs Dask's 'distributed' package: "
                         "pip install 'surfinpaint[dask]'") from exc
    try:
        return Client(address, timeout=30)
    except (OSError, TimeoutError) as exc:
        raise OSError(f"cannot reach the Dask scheduler at {address}: {exc}") from exc


def add_batch_parser(sub) -> None:
    """``batch``: many files."""
    p = sub.add_parser("batch", help="fill many mesh files, on all cores or a Dask cluster",
                       description="Fill the holes of every mesh file named by INPUT "
                       "(files, folders searched recursively, glob patterns) into OUTDIR, "
                       "mirroring their layout, and write OUTDIR/summary.csv and "
                       "summary.json: one row per file filled into OUTDIR, this run's and "
                       "earlier runs' (a rerun on some of the files replaces their rows and "
                       "keeps the others'; remove the two files to start afresh). A bad "
                       "file is reported and the others still written (exit 1 if any "
                       "failed). A rerun skips outputs "
                       "newer than their input and any overlay beside it, so an interrupted "
                       "run picks up where it stopped.")
    p.add_argument("inputs", nargs="+", metavar="INPUT", help="mesh file, folder or glob")
    p.add_argument("-o", "--output", required=True, metavar="OUTDIR", help="output folder")
    p.add_argument("--jobs", type=int, metavar="N",
                   help="worker processes on this machine (default: all cores; 1: one file "
                   "after another in this process)")
    p.add_argument("--dask-scheduler", metavar="ADDRESS",
                   help="run every file as a task on this Dask cluster (tcp://host:port; "
                   "its workers must see the files at the same paths; start them with "
                   "--nthreads 1 --preload surfinpaint.app.dask_worker)")
    p.add_argument("--overwrite", action="store_true",
                   help="refill files whose output is newer than their input")
    p.add_argument("--png", action="store_true",
                   help="also draw each file's before/after picture beside its output "
                   "(OUTDIR/sub/scan.png for OUTDIR/sub/scan.ply; lh.pial.png for lh.pial), "
                   "in the worker that filled it; a picture that fails is a warning, the "
                   "mesh is still written")
    p.add_argument("--overlay", action="append", metavar="PATTERN",
                   help="an overlay read with each GIFTI or FreeSurfer surface besides those "
                   "found beside it: a path from the surface's folder, {name} (its file "
                   "name), {stem} (the name without .gii) and {hemi} (the hemisphere as the "
                   "name writes it: lh/rh for lh.white, L/R for BIDS hemi-L or Workbench "
                   ".L., left/right for nilearn's pial_left) filled in "
                   "per file: ../label/{hemi}.aparc.annot; repeat for more. A file whose "
                   "overlay is missing, or of another format, fails (named in the summary)")
    add_fill_options(p)
    add_quiet(p)
    p.set_defaults(func=run_batch)
