"""The one progress display of the command line: a rich progress bar on stderr."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

__all__ = ["LazyConsole", "add_quiet", "console", "progress_bar", "stages"]


def console():
    """The command line's console: stderr, no highlighting, long lines wrapped softly."""
    from rich.console import Console

    return Console(stderr=True, highlight=False, soft_wrap=True)


def add_quiet(parser, what: str) -> None:
    """The commands' one ``-q``: ``-q`` says ``what`` it leaves out (progress, as a rule);
    ``-qq`` also leaves out the warnings, so only errors are printed. A warning is how a
    run says it dropped or changed something, so one ``-q`` keeps them (as pip's does)."""
    parser.add_argument("-q", "--quiet", action="count", default=0,
                        help=f"{what}; -qq: errors only")


class LazyConsole:
    """:func:`console`, made when something is first printed on it: a quiet command that
    prints nothing never imports rich (13-40 ms of a start, ``python -X importtime``)."""

    def __init__(self) -> None:
        self._made = None

    def print(self, *args, **kwargs) -> None:
        if self._made is None:
            self._made = console()
        self._made.print(*args, **kwargs)


class _Bar:
    """Moves a progress bar: ``bar(message, advance=1)`` steps it, ``bar.update(done,
    total, message)`` sets it (the ``progress`` callback of :func:`surfinpaint.fill_holes`),
    and either redraws it (a bar without rich's refresh thread)."""

    def __init__(self, progress=None, task=None):
        self._progress, self._task = progress, task

    def __call__(self, message: str, advance: int = 1) -> None:
        if self._progress is not None:
            self._progress.update(self._task, advance=advance, description=message,
                                  refresh=True)

    def update(self, done: int, total: int, message: str) -> None:
        if self._progress is not None:
            self._progress.update(self._task, completed=done, total=total,
                                  description=message, refresh=True)


@contextlib.contextmanager
def progress_bar(enabled: bool, total: int | None = None, description: str = ""
                 ) -> Iterator[_Bar]:
    """A progress bar on stderr (a no-op one when not ``enabled``) of ``total`` steps (None:
    set later by ``update``), first labelled ``description``.

    Redrawn at each step, not by rich's refresh thread: worker processes (the holes', batch's
    files') are forked only from a process of one thread
    (:func:`surfinpaint.fill.parallel.start_context`); from two they come from a forkserver
    and each imports and loads everything again (the 651k case's ``fill``: 4.9 against 3.9 s,
    docs/scale.md, session 22). So no command's bar can slow its fills down."""
    if not enabled:
        yield _Bar()
        return
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
    )

    # "3/7", or "0/?" while the total is not known (a mesh still being read)
    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                  TimeElapsedColumn(),
                  console=console(), transient=False, auto_refresh=False) as progress:
        task = progress.add_task(description, total=total)
        try:
            yield _Bar(progress, task)
        except BaseException:
            # a run that fails ends with its error, not with the bar where it stopped: the
            # bar is cleared from a terminal, and never written to a log or a pipe
            progress.live.transient = True
            progress.live.stop()
            progress.disable = True  # whose stop() would still end a log with an empty line
            raise
        if total is not None:
            progress.update(task, completed=total)


@contextlib.contextmanager
def stages(out) -> Iterator:
    """A ``progress`` callback of :func:`surfinpaint.representation.represent` and
    :func:`~surfinpaint.representation.exports.grid_export` (a sentence as each stage
    starts), shown on the console ``out`` one line per stage with a spinner while it runs
    and its time; on a console that is not a terminal (a log, a pipe), nothing."""
    if not out.is_terminal:
        yield lambda message: None
        return
    from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    with Progress(SpinnerColumn(finished_text="·"), TextColumn("{task.description}"),
                  TimeElapsedColumn(), console=out) as progress:
        running = []

        def stage(message: str) -> None:
            if running:  # its clock stops
                progress.update(running.pop(), total=1, completed=1)
            running.append(progress.add_task(message, total=None))

        yield stage
        if running:
            progress.update(running.pop(), total=1, completed=1)
