"""Ctrl-C and SIGTERM on the command line: one line, the conventional exit code, no debris.

SIGTERM is what ``timeout``, ``docker stop`` and batch schedulers send; by default it kills
Python on the spot, skipping every ``finally`` and leaving the atomic writers' temporary files
behind. Inside :func:`signals_raise`, SIGINT and SIGTERM instead raise :class:`Interrupted`
(a :class:`BaseException`, so no ``except Exception`` of the library swallows it), the stack
unwinds, and each atomic writer removes its temporary file on the way out, as it does for any
other exception. The command line catches it and exits with 128 + the signal number.
"""

from __future__ import annotations

import contextlib
import signal
import threading
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
    # Further signals are ignored while the stack unwinds, so that a second Ctrl-C does not
    # cut short the removal of temporary files; the previous handlers come back on exit.
    for s in HANDLED:
        signal.signal(s, signal.SIG_IGN)
    raise Interrupted(signum)


@contextlib.contextmanager
def signals_raise() -> Iterator[None]:
    """Within the block, SIGINT and SIGTERM raise :class:`Interrupted` in the main thread.

    Outside the main thread (where Python cannot install handlers) the block runs unchanged.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.getsignal(s) for s in HANDLED}
    try:
        for s in HANDLED:
            signal.signal(s, _raise_interrupted)
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler if handler is not None else signal.SIG_DFL)
