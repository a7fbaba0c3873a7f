"""Numba kernels, compiled on first use and cached on disk for every later process.

numba writes a kernel's machine code next to its source (``__pycache__``) or, where that is
not writable (a read-only or system-wide install), to the user's cache directory
(``~/.cache/numba``); ``NUMBA_CACHE_DIR`` overrides both. Only the first run after an
install (or an upgrade) compiles, a few seconds in all; the first compilation in a process
is announced once, at INFO level on the ``surfinpaint`` logger, so a command line can tell its
user why the first fill waits. Without numba, :func:`kernel` gives None and callers use their
numpy versions.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

__all__ = ["COMPILING_MESSAGE", "Kernel", "kernel"]

logger = logging.getLogger("surfinpaint")

COMPILING_MESSAGE = ("compiling surfinpaint's numba kernels (first run after an install only; "
                     "a few seconds, cached for later runs)")

_state = {"listening": False, "told": False}
_OURS: set = set()  # the Python functions handed to kernel()


def _announce_first_compilation() -> None:
    """Log :data:`COMPILING_MESSAGE` when numba starts compiling one of our kernels for the
    first time in this process (loading one from the disk cache raises no compile event)."""
    if _state["listening"]:
        return
    from numba.core import event

    class _Notice(event.Listener):
        def on_start(self, ev) -> None:
            if not _state["told"] and getattr((ev.data or {}).get("dispatcher"), "py_func",
                                              None) in _OURS:
                _state["told"] = True
                logger.info(COMPILING_MESSAGE)

        def on_end(self, ev) -> None:
            pass

    event.register("numba:compile", _Notice())
    _state["listening"] = True


def kernel(func: Callable, **options) -> Callable | None:
    """``func`` compiled by ``numba.njit(cache=True, **options)``, or None without numba.

    Where numba finds no writable cache location at all, the kernel is compiled without a
    disk cache (every process then compiles it once) rather than failing.
    """
    try:
        import numba
    except ImportError:  # pragma: no cover - numba is optional
        return None
    func = getattr(func, "py_func", func)
    _OURS.add(func)
    _announce_first_compilation()
    try:
        return numba.njit(cache=True, **options)(func)
    except RuntimeError as exc:  # "cannot cache function ...: no locator available"
        logger.debug("numba cannot cache %s (%s): compiling it in memory", func.__name__, exc)
        return numba.njit(**options)(func)


class Kernel:
    """A kernel compiled on first :meth:`get` (numba imports slowly: only when needed).

    Examples
    --------
    >>> def add(a, b):
    ...     return a + b
    >>> k = Kernel(add)
    >>> fn = k.get()
    >>> (fn or add)(1, 2)
    3
    """

    def __init__(self, func: Callable, **options) -> None:
        self.func = func
        self.options = options
        self._compiled: list = []

    def get(self) -> Callable | None:
        """The compiled kernel, or None without numba."""
        if not self._compiled:
            self._compiled.append(kernel(self.func, **self.options))
        return self._compiled[0]
