"""The one progress display of the command line (a rich progress bar on stderr), and its
one ``-q`` (:func:`add_quiet`, :class:`QuietConsole`)."""

from __future__ import annotations

import contextlib
import os
import threading
from collections.abc import Callable, Iterator, Mapping

__all__ = ["QUIET_HELP", "LazyConsole", "QuietConsole", "add_quiet", "console", "hole_news",
           "named", "progress_bar", "stages", "warning_line"]


def console():
    """The command line's console: stderr, no highlighting, long lines wrapped softly."""
    from rich.console import Console

    return Console(stderr=True, highlight=False, soft_wrap=True)


#: What ``-q`` does, the same for every command (:class:`QuietConsole` does it).
QUIET_HELP = ("-q: no progress display, report or notices on stderr, only the warnings and "
              "errors (what the command writes on stdout, as the table of `holes`, is kept); "
              "-qq: errors only")


def add_quiet(parser) -> None:
    """The commands' one ``-q``/``--quiet`` (:data:`QUIET_HELP`), read by
    :class:`QuietConsole`. A warning is how a run says it dropped or changed something, so
    one ``-q`` keeps them (as pip's does); ``-qq`` leaves them out too."""
    parser.add_argument("-q", "--quiet", action="count", default=0, help=QUIET_HELP)


def _spelled_first(text: str, path: str | os.PathLike) -> str | None:
    """How ``text`` spells ``path`` where it starts with it and a colon (as given, or as
    ``Path`` spells it: ``./scan.ply`` or ``scan.ply``); None where it does not."""
    given = os.fspath(path)
    return next((name for name in dict.fromkeys((given, os.path.normpath(given)))
                 if text.startswith(f"{name}:")), None)


def named(text: str, source: str | os.PathLike | None,
          other_files: Mapping[str | os.PathLike, str] | None = None) -> str:
    """``text`` said of the input ``source``, each file named once:

    - ``"SOURCE: text"``;
    - ``text`` unchanged where it starts with that name already (the readers' warnings
      do) or there is no input (None);
    - ``"SOURCE (VERB FILE): rest"`` where it starts with the name of another file of the
      command instead, one of ``other_files``, each mapped to what the command does with it
      (``{"out/scan.obj": "writing"}``): the writers' warnings start with the output's
      name (its materials, what its format cannot store), and ``scan.obj: out/scan.obj:
      ...`` read as two names of one file.

    Either spelling of a path is recognised: ``./scan.ply`` or ``scan.ply``.

    Every warning the command line prints for an input goes through here (with
    :func:`warning_line`): in a batch log of thousands of files, each line says which."""
    if source is None or _spelled_first(text, source) is not None:
        return text
    given = os.fspath(source)
    for path, verb in (other_files or {}).items():
        spelled = _spelled_first(text, path)
        if spelled is not None:
            return f"{given} ({verb} {spelled}):{text[len(spelled) + 1:]}"
    return f"{given}: {text}"


def warning_line(text: str, source: str | os.PathLike | None = None, count: int = 1,
                 other_files: Mapping[str | os.PathLike, str] | None = None) -> str:
    """The line that prints one warning (rich markup): ``warning: SOURCE: text``
    (:func:`named`, ``other_files`` as there), with ``(×count)`` when it came more than
    once."""
    from rich.markup import escape  # only when a warning is printed

    times = f" (×{count})" if count > 1 else ""
    return f"[yellow]warning:[/yellow] {escape(named(text, source, other_files))}{times}"


class LazyConsole:
    """:func:`console`, made when something is first printed on it: a quiet command that
    prints nothing never imports rich (13-40 ms of a start, ``python -X importtime``)."""

    def __init__(self) -> None:
        self._made = None

    def made(self):
        """The console, made now if not yet."""
        if self._made is None:
            self._made = console()
        return self._made

    def print(self, *args, **kwargs) -> None:
        self.made().print(*args, **kwargs)


#: How often a ticking bar (:func:`progress_bar`) is drawn again while a fill runs in the
#: process that draws it: its clock goes on through a stage of seconds (a display's
#: cadence, not a fill rule)
TICK_SECONDS = 1.0


class _Clock:
    """A thread that calls ``tick`` every :data:`TICK_SECONDS` between :meth:`start` and
    :meth:`stop`. It gets its turns where the fill's thread lets go of the GIL: in NumPy's,
    SciPy's and LAPACK's calls on large arrays, and every few milliseconds of Python code
    (docs/robustness.md, session 48)."""

    def __init__(self, tick: Callable[[], None]) -> None:
        self.tick = tick
        self._thread: threading.Thread | None = None
        self._stopped = threading.Event()

    @property
    def running(self) -> bool:
        return self._thread is not None

    def start(self) -> None:
        if self._thread is None:
            self._stopped.clear()
            self._thread = threading.Thread(target=self._run, name="surfinpaint-bar-clock",
                                            daemon=True)
            self._thread.start()

    def stop(self) -> None:
        if self._thread is not None:
            self._stopped.set()
            self._thread.join()
            self._thread = None

    def _run(self) -> None:
        while not self._stopped.wait(TICK_SECONDS):
            self.tick()


class _Bar:
    """Moves a progress bar: ``bar(message, advance=1)`` steps it, ``bar.update(done,
    total, message)`` sets it (the ``progress`` callback of :func:`surfinpaint.fill_holes`),
    and either redraws it (a bar without rich's refresh thread). A ticking bar is drawn
    again every :data:`TICK_SECONDS` after an ``update`` that leaves work to do, from a
    thread of its own (:class:`_Clock`; ``on_tick`` is then called too), where no other
    thread runs: the fill is in this process (``fill``'s holes one after another,
    ``batch --jobs 1``); worker processes are forked only from a process of one thread
    (:func:`surfinpaint.fill.parallel.start_context`), and a process with workers has the
    pool's thread, so the clock never runs beside them."""

    def __init__(self, progress=None, task=None, ticking: bool = False):
        self._progress, self._task = progress, task
        self._clock = _Clock(self._tick) if ticking and progress is not None else None
        self.on_tick: Callable[[], None] | None = None

    def __call__(self, message: str, advance: int = 1) -> None:
        """A step of ``report``'s or ``experiments``' bar: ``advance`` steps done, now
        labelled ``message``. The clock stops: a stage has ended, and the next may start
        worker processes (forked only where no other thread runs)."""
        if self._progress is not None:
            self._progress.update(self._task, advance=advance, description=message,
                                  refresh=True)
        self.stop_clock()

    def update(self, done: int, total: int, message: str) -> None:
        if self._progress is not None:
            self._progress.update(self._task, completed=done, total=total,
                                  description=message, refresh=True)
        self._clock_while(total is not None and done < total)

    def holes(self, label: str) -> Callable[[int, int, str], None] | None:
        """The ``progress`` callback of :func:`surfinpaint.fill_holes` within a step of the
        bar (``report``'s, ``experiments``'): each hole's news labels the bar (``conformal
        fills: hole 3: 212 edges, λ-H fill (stage 5 of 5)``), its count unmoved, and the
        clock runs as at :meth:`update` while holes are left; the step after stops it.
        None for a no-op bar (a fill told nothing runs no stage news)."""
        if self._progress is None:
            return None

        def told(done: int, total: int, message: str) -> None:
            self._progress.update(self._task, description=f"{label}: {message}", refresh=True)
            self._clock_while(done < total)
        return told

    def _clock_while(self, work_left: bool) -> None:
        """Start the clock where work is left and no other thread runs; else stop it."""
        if self._clock is not None:
            others = threading.active_count() - self._clock.running
            if work_left and others == 1:
                self._clock.start()
            else:
                self._clock.stop()

    def stop_clock(self) -> None:
        """No more ticks (the bar is ending)."""
        if self._clock is not None:
            self._clock.stop()

    def _tick(self) -> None:
        self._progress.refresh()
        if self.on_tick is not None:
            self.on_tick()

    @property
    def console(self):
        """The console the bar is drawn on (None for a no-op bar): a line printed on it
        while the bar is shown goes above the bar, which rich draws again below it."""
        return None if self._progress is None else self._progress.console


def hole_news(step, label: str) -> Callable[[int, int, str], None] | None:
    """The ``progress`` callback of :func:`surfinpaint.fill_holes` for the fills ``label``
    that the step hook ``step`` of ``report`` or ``experiments`` takes (its
    ``holes(label)``: a bar's, :meth:`_Bar.holes`), or None where it takes none: the bar's
    clock then runs while the holes are filled in this process, as ``fill``'s (session
    50)."""
    holes = getattr(step, "holes", None)
    return None if holes is None else holes(label)


@contextlib.contextmanager
def progress_bar(enabled: bool, total: int | None = None, description: str = "",
                 ticking: bool = False) -> Iterator[_Bar]:
    """A progress bar on stderr (a no-op one when not ``enabled``) of ``total`` steps (None:
    set later by ``update``), first labelled ``description``.

    Redrawn at each step, not by rich's refresh thread: worker processes (the holes', batch's
    files') are forked only from a process of one thread
    (:func:`surfinpaint.fill.parallel.start_context`); from two they come from a forkserver
    and each imports and loads everything again (the 651k case's ``fill``: 4.9 against 3.9 s,
    docs/scale.md, session 22). So no command's bar can slow its fills down. ``ticking``:
    also redrawn every :data:`TICK_SECONDS` while the fill runs in this process, by a
    thread that runs only where no other does (:class:`_Bar`)."""
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
        bar = _Bar(progress, task, ticking)
        try:
            yield bar
        except BaseException:
            bar.stop_clock()
            # a run that fails ends with its error, not with the bar where it stopped: the
            # bar is cleared from a terminal, and never written to a log or a pipe
            progress.live.transient = True
            progress.live.stop()
            progress.disable = True  # whose stop() would still end a log with an empty line
            raise
        bar.stop_clock()
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


class QuietConsole:
    """What a command prints on stderr at its ``-q`` level (:func:`add_quiet`), for every
    command the same: :meth:`say` a notice or a line of the report (not with ``-q``),
    :meth:`warn` a warning (not with ``-qq``), :meth:`error` an error (always);
    :attr:`progress` whether a progress display is shown (not with ``-q``). The console is
    made at its first line: a quiet run that prints nothing never imports rich."""

    def __init__(self, quiet: int = 0) -> None:
        self.quiet = quiet
        self._console = LazyConsole()

    @property
    def progress(self) -> bool:
        """Whether a progress display is shown."""
        return not self.quiet

    @property
    def warnings_console(self) -> LazyConsole | None:
        """The console warnings are printed on (None with ``-qq``: none is printed)."""
        return self._console if self.quiet < 2 else None

    def say(self, *args, **kwargs) -> None:
        """A notice, or a line of the command's report."""
        if not self.quiet:
            self._console.print(*args, **kwargs)

    def warn(self, *args, **kwargs) -> None:
        """A warning (given as the whole line, ``warning:`` included)."""
        if self.quiet < 2:
            self._console.print(*args, **kwargs)

    def error(self, *args, **kwargs) -> None:
        """An error."""
        self._console.print(*args, **kwargs)

    @contextlib.contextmanager
    def above(self, bar: _Bar) -> Iterator[None]:
        """While the progress bar ``bar`` (:func:`progress_bar`) is shown, print on its
        console: a line said while the bar runs (a batch's bad file, as it fails) goes
        above the bar instead of through it. A no-op bar changes nothing."""
        if bar.console is None:
            yield
            return
        own, self._console = self._console, bar.console
        try:
            yield
        finally:
            self._console = own

    @contextlib.contextmanager
    def stages(self) -> Iterator:
        """:func:`stages` on this console; a callback that shows nothing with ``-q``."""
        if self.quiet:
            yield lambda message: None
            return
        with stages(self._console.made()) as stage:
            yield stage
