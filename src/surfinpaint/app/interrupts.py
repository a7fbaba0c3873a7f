"""Ctrl-C and SIGTERM on the command line: one line, the conventional exit code, no debris.

SIGTERM is what ``timeout``, ``docker stop`` and batch schedulers send; by default it kills
Python on the spot, skipping every ``finally`` and leaving the atomic writers' temporary files
behind. Inside :func:`signals_raise`, SIGINT and SIGTERM instead raise :class:`Interrupted`
(a :class:`BaseException`, so no ``except Exception`` of the library swallows it), the stack
unwinds, and each atomic writer removes its temporary file on the way out, as it does for any
other exception. The command line catches it and exits with 128 + the signal number.

A signal the process inherited as *ignored* stays ignored, as Python itself and most Unix
tools leave it: a non-interactive shell's background job (``cmd &`` in a script) starts with
SIGINT ignored, ``nohup`` with SIGHUP, and a Ctrl-C meant for the shell must not stop it.
"""

from __future__ import annotations

import _thread
import contextlib
import importlib
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator

HANDLED = (signal.SIGINT, signal.SIGTERM)
_NAMES = {signal.SIGINT: "Ctrl-C (SIGINT)", signal.SIGTERM: "SIGTERM"}


class Interrupted(BaseException):
    """The process received SIGINT or SIGTERM.

    Attributes
    ----------
    signum : int
        The signal received.
    """

    def __init__(self, signum: int) -> None:
        self.signum = int(signum)
        super().__init__(f"interrupted by {_NAMES.get(self.signum, f'signal {self.signum}')}")

    @property
    def exit_code(self) -> int:
        """The shell's convention: 128 + the signal number (130 for SIGINT, 143 for SIGTERM)."""
        return 128 + self.signum


def _raise_interrupted(signum: int, frame) -> None:
    if _within(frame, _send_again.__code__):  # raised in the hook it would be lost for good
        _send_later(signum)
        return
    # Further signals are ignored while the stack unwinds, so that a second Ctrl-C does not
    # cut short the removal of temporary files; the previous handlers come back on exit.
    for s in HANDLED:
        signal.signal(s, signal.SIG_IGN)
    raise Interrupted(signum)


def _within(frame, code) -> bool:
    """Whether ``frame`` or a frame it was called from runs ``code``."""
    while frame is not None:
        if frame.f_code is code:
            return True
        frame = frame.f_back
    return False


def raise_interruption(exc: BaseException) -> None:
    """Raise the interruption (:class:`Interrupted`, :exc:`KeyboardInterrupt`) that caused
    ``exc``, if one did; for an ``except Exception`` that would otherwise swallow it. An
    extension module's import that a signal cuts short raises an exception *caused by* the
    interruption (pybind11's ``ImportError: initialization failed``, matplotlib's modules):
    without this, a SIGTERM while ``--png`` imported matplotlib was a warning, and the
    command exited 0 (session 46)."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, Interrupted | KeyboardInterrupt):
            raise exc
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__


@contextlib.contextmanager
def interruptions_raised() -> Iterator[None]:
    """Within the block, an exception an interruption caused is raised as that interruption
    (:func:`raise_interruption`)."""
    try:
        yield
    except Exception as exc:
        raise_interruption(exc)
        raise


@contextlib.contextmanager
def signals_held() -> Iterator[list[int]]:
    """Within the block, SIGINT and SIGTERM are only noted (in the list given to the
    block); after it, the first one that came is sent again, to whatever handled it before
    (ours: :class:`Interrupted`; Python's default: :exc:`KeyboardInterrupt`, or the end of
    the process for SIGTERM). An ignored signal stays ignored. Outside the main thread the
    block runs unchanged."""
    came: list[int] = []
    if threading.current_thread() is not threading.main_thread():
        yield came
        return
    # not an ignored signal, nor one whose handler was not set from Python (None: it could
    # not be put back)
    previous = {s: h for s in HANDLED
                if (h := signal.getsignal(s)) is not signal.SIG_IGN and h is not None}
    for s in previous:
        signal.signal(s, lambda signum, frame: came.append(signum))
    try:
        yield came
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        if came:
            os.kill(os.getpid(), came[0])


def imported_whole(*names: str):
    """The module ``names[0]``, after importing each of ``names`` with :func:`signals_held`.

    A handler that raises inside an extension module's initialization can crash the
    process: VTK's modules import their dependencies from C, and an exception there
    segfaulted in ``libvtkWrappingPythonCore`` (session 47: ``fill --png`` SIGTERMed while
    pyvista imported VTK's rendering modules, 2 of 50 signals in the drawing stage on a
    fsaverage5-left surface; 1 of 9 in session 46). An import takes a second or two: the
    signal waits that long."""
    with signals_held():
        modules = [importlib.import_module(name) for name in names]
    return modules[0]


@contextlib.contextmanager
def signals_noted() -> Iterator[None]:
    """The program's start (:func:`surfinpaint.app.program.program`): within the block,
    SIGINT and SIGTERM are only noted until :func:`signals_raise` takes over, and a signal
    noted before it is raised in its block by :func:`raise_noted`: the command's one line
    and 130/143, not Python's default (SIGTERM: the process killed on the spot, without a
    word; Ctrl-C: a ``KeyboardInterrupt`` traceback from inside an import) while the
    command line's modules are imported (0.2-2 s; session 48). A signal noted and not
    raised (none came in :func:`signals_raise`'s block) is sent again after the block to
    the handler before (:func:`signals_held`). An ignored signal stays ignored; outside
    the main thread the block runs unchanged."""
    with signals_held() as came:
        _state["noted"] = came
        try:
            yield
        finally:
            _state.pop("noted", None)


def raise_noted() -> None:
    """Raise :class:`Interrupted` for a signal :func:`signals_noted` noted before
    :func:`signals_raise` took over (the first of them), if one was."""
    came = _state.get("noted")
    if came:
        signum = came[0]
        came.clear()
        raise Interrupted(signum)


#: Seconds after which a signal lost in a finalizer or callback is sent again (from another
#: thread: by then the place it was lost in has returned)
AGAIN_AFTER = 0.01
_state: dict = {}  # "previous": the unraisable hook before ours; "again": the signals to
# send again (a list the senders pop; emptied to cancel them); "taken": the signals whose
# handler the block set (not those inherited as ignored)


def _send_again(unraisable) -> None:
    """``sys.unraisablehook`` within :func:`signals_raise`: :class:`Interrupted` raised by
    the handler where Python cannot raise it (a ``__del__``, a weakref callback, a ctypes
    callback: "Exception ignored in ...") would be lost, and every later signal ignored;
    instead the handlers are set again and the signal is sent again :data:`AGAIN_AFTER`
    seconds later, to land outside that place (:func:`_send_later`; sending it from here
    would run the handler inside this hook, where it is lost again: a signal that comes
    while this hook runs, the one sent again included, is sent again after it, by the
    handler). Anything else goes to the previous hook."""
    exc = unraisable.exc_value
    if not isinstance(exc, Interrupted) or \
            threading.current_thread() is not threading.main_thread():
        _state["previous"](unraisable)
        return
    for s in _state["taken"]:
        signal.signal(s, _raise_interrupted)
    _send_later(exc.signum)


def _send_later(signum: int) -> None:
    """Send ``signum`` to this process :data:`AGAIN_AFTER` seconds from now, from a thread
    started without waiting for it: ``threading.Thread.start`` waits until the thread
    runs, and under load the thread sent the signal while this one still waited there,
    inside the hook, where it was lost for good: the fill went on and wrote its output
    (session 49: 3 of 40 runs of a signal in a gc callback at load ~20). Cancelled by
    emptying ``_state["again"]`` (:func:`raise_pending`, the block's end).

    ``threading`` does not know this thread, so :func:`~surfinpaint.fill.parallel.forks`
    may fork workers while it waits (session 50). That is safe: a fork copies only the
    forking thread, and its hazard is a lock another thread holds at that instant, which
    stays held in the child; this one holds none (it sleeps, pops a list under the GIL,
    which the child's interpreter resets at a fork, and calls ``kill``, a system call);
    malloc's locks are taken around a fork by the C library. The child has no copy of the
    thread, so the signal goes to this process alone (the pid is read in the thread), which
    ends its workers as it acts on it; the child's copy of ``_state["again"]`` is never
    raised (only the command line's :func:`raise_pending` reads it, in this process)."""
    again = _state.setdefault("again", [])
    again.append(signum)

    def send() -> None:
        time.sleep(AGAIN_AFTER)
        with contextlib.suppress(IndexError):  # popped (sent or cancelled) already
            os.kill(os.getpid(), again.pop())
    _thread.start_new_thread(send, ())


@contextlib.contextmanager
def signals_raise() -> Iterator[None]:
    """Within the block, SIGINT and SIGTERM raise :class:`Interrupted` in the main thread,
    even when they come in a finalizer or callback (:func:`_send_again`); one that is
    ignored (``SIG_IGN``) when the block starts stays ignored (session 47: a shell script's
    ``surfinpaint fill ... &`` was stopped by a Ctrl-C meant for the script).

    Outside the main thread (where Python cannot install handlers) the block runs unchanged.
    """
    if threading.current_thread() is not threading.main_thread() \
            or sys.unraisablehook is _send_again:  # in the main thread's block already
        yield
        return
    previous = {s: signal.getsignal(s) for s in HANDLED}
    _state["taken"] = [s for s, handler in previous.items() if handler is not signal.SIG_IGN]
    _state["previous"] = hook = sys.unraisablehook
    try:
        for s in _state["taken"]:
            signal.signal(s, _raise_interrupted)
        sys.unraisablehook = _send_again
        yield
        raise_pending()
    finally:
        if sys.unraisablehook is _send_again:
            sys.unraisablehook = hook
        _state.pop("again", []).clear()  # a signal sent after the block: no one's
        for s, handler in previous.items():
            signal.signal(s, handler if handler is not None else signal.SIG_DFL)


def raise_pending() -> None:
    """A signal lost (in a finalizer or callback) and not yet sent again: raised now, and
    not sent. :func:`signals_raise` calls it as its block ends (sent after the block, the
    signal would meet the previous handler); a command calls it as its work ends, inside
    its own ``except Interrupted`` (raised at the block's end, it is outside)."""
    again = _state.get("again", [])
    with contextlib.suppress(IndexError):
        signum = again.pop(0)
        again.clear()
        raise Interrupted(signum)
