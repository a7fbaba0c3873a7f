"""Numba kernels, compiled once into numba's disk cache and loaded from it by later processes.

numba writes a kernel's machine code next to its source (``__pycache__``) or, where that is
not writable (a read-only or system-wide install), to the user's cache directory
(``~/.cache/numba``); ``NUMBA_CACHE_DIR`` overrides both. Each kernel has a numpy version
that gives the same results bit for bit; callers go through :func:`run`.

The first run after an install (or an upgrade) finds the cache empty. Compiling the
kernels costs about 4 s CPU, more than the numpy versions cost on most fills, so by default
(``SURFINPAINT_COMPILE=background``) that run does not wait: a kernel missing from the cache
is replaced by its numpy version, and one detached, low-priority process
(:data:`BUILDER`) compiles every kernel into the cache for the later runs; the run says so
once (:data:`BACKGROUND_MESSAGE`, INFO on the ``surfinpaint`` logger). A lock file makes
concurrent first runs, and the workers of a parallel fill, share that one process; a kernel
that appears in the cache meanwhile is picked up at its first call
:data:`RECHECK_SECONDS` after its last look-up. Where the numpy version
would cost more than compiling (a long hole's triangulation: its dynamic program is ~100×
slower in numpy), or once it has cost a process ``budget`` seconds, the kernel is compiled
in the process, as when there is no disk cache at all (a kernel numba cannot cache), when the
background compilation failed once, or with ``SURFINPAINT_COMPILE=foreground``; the first
such compilation in a process is announced once (:data:`COMPILING_MESSAGE`). Without numba,
:func:`kernel` gives None and callers use their numpy versions.

Whether a kernel is in the cache is numba's own decision: its dispatcher looks the call's
signature up in memory, then on disk, and only on a miss starts compiling, with a
``numba:compile`` event (numba's public event API) before any work. :func:`run` calls the
kernel with a listener that raises :class:`NotCompiled` on that event, so nothing is
compiled and nothing is left half-made.
"""

from __future__ import annotations

import contextlib
import hashlib
import logging
import math
import os
import sys
import tempfile
import threading
import time
from collections.abc import Callable, Iterator

__all__ = ["BACKGROUND_MESSAGE", "BUILDER", "COMPILING_MESSAGE", "MODE_VARIABLE", "Kernel",
           "NotCompiled", "RECHECK_SECONDS", "announce_once_across", "in_foreground", "kernel",
           "lock_path", "run"]

logger = logging.getLogger("surfinpaint")

# both can come in one run (a worker past its budget compiles after the background line):
# each says what the process does, so that together they do not read as a contradiction
COMPILING_MESSAGE = ("compiling surfinpaint's numba kernels in this process (first run after an "
                     "install only; a few seconds, cached for later runs)")
BACKGROUND_MESSAGE = ("surfinpaint's numba kernels are not compiled yet (first run after an "
                      "install): this run uses their numpy versions (the same results) while a "
                      "background process compiles them for later runs; a process whose numpy "
                      "versions cost more than compiling compiles them itself, and says so")
MODE_VARIABLE = "SURFINPAINT_COMPILE"  # "background" (the default) or "foreground"
BUILDER = "surfinpaint.fill.warmup"  # its main(lock_fd, lock_path) compiles every kernel

_state: dict = {"listening": False, "told": False, "launched": None}
_OURS: set = set()  # the Python functions handed to kernel()
_UNCACHED: set = set()  # kernels numba has no disk cache for
_spent: dict = {}  # kernel -> estimated seconds its numpy version has cost this process
_missed: dict = {}  # kernel -> time.monotonic() of its last look-up that missed the cache
# While the background compilation runs, a kernel that missed the cache is looked up again
# at most this often: a look-up that misses costs ~0.5 ms (numba searches its disk cache),
# and a λ-H fill calls the kernels ~350 times a hole (~0.2 s of a CAD hole's ~0.6 s,
# session 52 helper); a kernel compiled meanwhile is picked up this much later at most.
RECHECK_SECONDS = 1.0
_local = threading.local()  # .cached_only: the current call may load a kernel, not compile;
# .lost: signal handlers' exceptions lost in ctypes callbacks during the current call
_launch_lock = threading.Lock()


class NotCompiled(Exception):
    """Raised inside a kernel call that would have to compile the kernel (see :func:`run`)."""


def _listen() -> None:
    """Register the ``numba:compile`` listener once: it stops a compilation of one of our
    kernels during a cache-only call, and logs :data:`COMPILING_MESSAGE` at the first
    compilation of one of them in this process (loading one from the disk cache raises no
    compile event)."""
    if _state["listening"]:
        return
    from numba.core import event

    class _Notice(event.Listener):
        def on_start(self, ev) -> None:
            func = getattr((ev.data or {}).get("dispatcher"), "py_func", None)
            if func not in _OURS:
                return
            if getattr(_local, "cached_only", False):
                raise NotCompiled(func.__qualname__)
            if not _state["told"]:
                _state["told"] = True
                logger.info(COMPILING_MESSAGE)

        def on_end(self, ev) -> None:
            pass

    event.register("numba:compile", _Notice())
    _state["listening"] = True


class _FirstAcross(logging.Filter):
    """Lets :data:`COMPILING_MESSAGE` through in the first of the processes sharing
    ``told`` (a ``multiprocessing`` ``Value``) to log it; every other record passes."""

    def __init__(self, told) -> None:
        super().__init__()
        self.told = told

    def filter(self, record: logging.LogRecord) -> bool:
        if record.msg != COMPILING_MESSAGE:
            return True
        with self.told.get_lock():
            first = not self.told.value
            self.told.value = True
        return first


def announce_once_across(told) -> None:
    """In a worker process: :data:`COMPILING_MESSAGE` (once per process otherwise) is logged
    by the first of the workers sharing ``told`` only, a ``Value("b", 0)`` of the
    ``multiprocessing`` context that started them. Each worker of a batch compiles the
    kernels it misses on a cold cache: one line says so, not one per worker. Costs nothing
    on a warm cache (nothing is logged)."""
    logger.addFilter(_FirstAcross(told))


def kernel(func: Callable, **options) -> Callable | None:
    """``func`` compiled by ``numba.njit(cache=True, **options)``, or None without numba.

    Where numba finds no writable cache location at all, the kernel is compiled without a
    disk cache (every process then compiles it once, in the process) rather than failing.
    """
    with _signals_kept():  # numba's first dispatcher makes and frees llvmlite's objects
        return _jitted(func, options)


def _jitted(func: Callable, options: dict) -> Callable | None:
    """:func:`kernel`'s dispatcher (or None without numba)."""
    try:
        import numba
    except ImportError:  # pragma: no cover - numba is optional
        return None
    func = getattr(func, "py_func", func)
    _OURS.add(func)
    _listen()
    try:
        return numba.njit(cache=True, **options)(func)
    except RuntimeError as exc:  # "cannot cache function ...: no locator available"
        logger.debug("numba cannot cache %s (%s): compiling it in memory", func.__name__, exc)
        compiled = numba.njit(**options)(func)
        _UNCACHED.add(compiled)
        return compiled


def run(compiled, call: Callable, fallback: Callable, cost: float = 0.0,
        budget: float = 2.0):
    """``call(compiled)``, or ``fallback()`` (the same results) while the kernel is not in
    numba's cache and compiling it here would cost more than the fallback.

    Parameters
    ----------
    compiled : numba dispatcher or None
        The kernel (None without numba: the fallback runs).
    call, fallback : callables
        The kernel's call, given the kernel, and its numpy version.
    cost : float
        What ``fallback()`` costs, estimated in seconds from the size of the call (a
        deterministic count, not a clock).
    budget : float
        Estimated seconds of fallbacks of this kernel a process may spend before it compiles
        the kernel itself rather than wait for the background compilation.
    """
    if compiled is None:
        return fallback()
    if compiled in _UNCACHED or os.environ.get(MODE_VARIABLE) == "foreground":
        return _called(compiled, call)
    spent = _spent.get(compiled, 0.0) + cost
    if spent > budget:
        return _called(compiled, call)
    if time.monotonic() - _missed.get(compiled, -math.inf) >= RECHECK_SECONDS:
        _local.cached_only = True
        try:
            return _called(compiled, call)
        except NotCompiled:
            pass
        finally:
            _local.cached_only = False
        if not compile_in_background():
            return _called(compiled, call)
        _missed[compiled] = time.monotonic()
    _spent[compiled] = spent
    return fallback()


@contextlib.contextmanager
def in_foreground() -> Iterator[None]:
    """Within the block, :func:`run` compiles a kernel missing from the cache in this
    process (as with ``SURFINPAINT_COMPILE=foreground``): ``surfinpaint compile``."""
    before = os.environ.get(MODE_VARIABLE)
    os.environ[MODE_VARIABLE] = "foreground"
    try:
        yield
    finally:
        if before is None:
            os.environ.pop(MODE_VARIABLE, None)
        else:
            os.environ[MODE_VARIABLE] = before


def _called(compiled, call: Callable):
    """``call(compiled)``, with the exception of a signal handler that raised while the
    kernel ran (Ctrl-C's, the command line's SIGTERM handler's) raised as itself.

    Why: numba's dispatcher runs Python code (loading a cached kernel, boxing its result);
    a handler that raises there comes back as ``SystemError: ... returned a result with an
    exception set``, the handler's exception only its context, and a Ctrl-C would end in
    a traceback instead of the command line's one line. Worse, llvmlite calls numba's
    object-cache hooks (compiling a kernel, or loading it from the disk cache) through
    ctypes callbacks, where an exception cannot propagate: Python reports it as
    "Exception ignored on calling ctypes callback function" and the call goes on, the
    signal lost (the command line's handler ignores further ones). Such an exception is
    kept (:func:`_keep_lost_signal`) and raised here once the call returns."""
    with _signals_kept():
        try:
            return call(compiled)
        except SystemError as exc:
            context = exc.__context__
            if _is_signal_exception(context):
                raise context from None
            raise


@contextlib.contextmanager
def _signals_kept() -> Iterator[None]:
    """Within the block, a signal handler's exception that Python reports as unraisable (in
    a ctypes callback, or a ``__del__``: llvmlite frees its objects in ``__del__``) is kept,
    and raised as itself when the block ends (session 43: kernel calls; 44: making a
    kernel's dispatcher, where numba makes its first code generator)."""
    _hook_unraisable()
    outer = getattr(_local, "lost", None)
    lost = _local.lost = []
    try:
        yield
    except BaseException:
        _raise_lost(lost)
        raise
    finally:
        _local.lost = outer
    _raise_lost(lost)


def _raise_lost(lost: list) -> None:
    if lost:
        raise lost[0] from None


def _is_signal_exception(exc) -> bool:
    """What a signal handler raises: KeyboardInterrupt, the command line's Interrupted
    (BaseExceptions that are not Exceptions)."""
    return isinstance(exc, BaseException) and not isinstance(exc, Exception)


def _keep_lost_signal(unraisable) -> None:
    """``sys.unraisablehook`` (installed by :func:`_hook_unraisable`): within
    :func:`_signals_kept` in this thread (a kernel call, a kernel's making), a signal
    handler's exception that Python could not raise (it came in a ctypes callback or a
    ``__del__``) is kept, not printed; anything else goes to the hook that was there
    before."""
    lost = getattr(_local, "lost", None)
    if lost is not None and _is_signal_exception(unraisable.exc_value):
        lost.append(unraisable.exc_value)
        return
    _state["unraisablehook"](unraisable)


def _hook_unraisable() -> None:
    if sys.unraisablehook is not _keep_lost_signal:
        _state["unraisablehook"] = sys.unraisablehook
        sys.unraisablehook = _keep_lost_signal


def lock_path() -> str:
    """The lock file held by the background compilation, one per user, interpreter, source
    tree and ``NUMBA_CACHE_DIR`` (``lock_path() + ".failed"`` says it failed)."""
    key = "|".join([str(os.getuid() if hasattr(os, "getuid") else ""), sys.executable,
                    os.path.dirname(os.path.abspath(__file__)),
                    os.environ.get("NUMBA_CACHE_DIR", "")])
    digest = hashlib.sha1(key.encode()).hexdigest()[:16]
    return os.path.join(tempfile.gettempdir(), f"surfinpaint-kernels-{digest}.lock")


def compile_in_background() -> bool:
    """Start the background compilation, once per process, unless another process (a
    concurrent run, another worker of this one) runs it already; the process that starts
    it says so (:data:`BACKGROUND_MESSAGE`). False when it cannot run: no ``fcntl``
    (Windows) or ``posix_spawn``, an unusable lock file, or an earlier background
    compilation failed; the caller then compiles in its process."""
    with _launch_lock:
        if _state["launched"] is None:
            _state["launched"] = _launch()
        return _state["launched"]


def _launch() -> bool:
    try:
        import fcntl
    except ImportError:  # pragma: no cover - Windows
        return False
    path = lock_path()
    if not hasattr(os, "posix_spawn") or os.path.exists(path + ".failed"):
        return False
    try:
        fd = os.open(path, os.O_RDONLY | os.O_CREAT, 0o600)
    except OSError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:  # held: another process compiles them now
        os.close(fd)
        logger.debug("another process compiles the kernels: their numpy versions meanwhile")
        return True
    try:
        _spawn_builder(fd, path)
    except OSError:
        return False
    finally:
        os.close(fd)  # the child holds the lock now (its copy of the descriptor)
    logger.info(BACKGROUND_MESSAGE)
    return True


def _spawn_builder(fd: int, path: str) -> None:
    """Start :data:`BUILDER` detached (its own session, no terminal, lowest priority),
    handing it the locked descriptor ``fd``. Linux schedules a session's processes as one
    group ("autogroup") with a niceness of its own, so the child lowers its group's too:
    ``os.nice`` alone would leave it an equal share against the run that started it."""
    code = ("import os, runpy, sys\n"
            "os.nice(19)\n"
            "try:\n"
            "    with open('/proc/self/autogroup', 'w') as group:\n"
            "        group.write('19')\n"
            "except OSError:\n"
            "    pass\n"
            f"sys.argv[1:] = [{str(fd)!r}, {path!r}]\n"
            f"runpy.run_module({BUILDER!r}, run_name='__main__', alter_sys=True)\n")
    env = dict(os.environ, **{MODE_VARIABLE: "foreground"})
    devnull = [(os.POSIX_SPAWN_OPEN, i, os.devnull, os.O_RDWR, 0) for i in range(3)]
    os.set_inheritable(fd, True)
    try:
        os.posix_spawn(sys.executable, [sys.executable, "-c", code], env,
                       file_actions=devnull, setsid=True)
    finally:
        os.set_inheritable(fd, False)


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
