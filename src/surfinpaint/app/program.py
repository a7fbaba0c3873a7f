"""The ``surfinpaint`` program (the console script and ``python -m surfinpaint``): the
process's settings, made before numpy is imported, then the command line
(:func:`surfinpaint.app.cli.main`).

This module imports nothing but the standard library (and the program's stdlib-only
signal handling, :mod:`surfinpaint.app.interrupts`) at its top: numpy reads the settings
below when it is first imported, which :func:`program` does after making them. Only the
program does this; the library (``import surfinpaint``) leaves its caller's process as it
is, and a variable the user set is always kept.

- ``NUMPY_MADVISE_HUGEPAGE=0``: numpy marks each array of 4 MB or more ``MADV_HUGEPAGE``.
  Where the kernel's transparent-huge-page ``defrag`` setting is ``madvise`` (the usual
  default) a fault in such an array may stall on a synchronous compaction instead of
  taking a small page (numpy issue 31590), and in a virtual machine each huge page is first
  made resident by the host. A fill touches its whole-mesh arrays about once, so it pays
  those faults and never gains the TLB's savings: on the 651k-vertex case the first edge
  table in a process took 0.56 s with huge pages and 0.21 s without, and 6 alternated
  whole runs (another process on one core) 3.71 -> 3.44 s wall, system time 0.67 -> 0.36 s
  (docs/scale.md, session 23).
- ``OPENBLAS_NUM_THREADS=1`` and ``MKL_NUM_THREADS=1``, unless the user set any of the
  variables BLAS libraries read for their threads (those two, ``OMP_NUM_THREADS``,
  ``GOTO_NUM_THREADS``): a fill's dense products are small (the λ-H solve asked for one
  BLAS thread already) and its parallelism is over holes in processes; a second BLAS thread
  costs each process its start-up (``import numpy`` 0.07 -> 0.12 s) and, in a parallel
  fill, a forked worker's thread pool. 651k case, 3 alternated runs each: default fill
  user CPU 3.03 -> 2.70 s and wall -0.3 s, ``--jobs 1`` -0.1 s, ``--method fair`` 1.54 ->
  1.41 s; the outputs byte for byte the same; ``represent`` of a 104,635-vertex disk
  2.87-2.98 -> 2.76-2.86 s (docs/scale.md, session 23).

Modules that the command line's packages import but no command uses are deferred
(:data:`UNUSED_MODULES`, :func:`~surfinpaint.lazy.defer_modules`): each runs only where
something reads one of its attributes. The command line's import runs alone, before the
read and the kernels' loading start, so what it imports is on the whole command's path
(651k case, docs/scale.md, session 45):

- scipy's array-API layer (imported by ``scipy.sparse``) lists numpy's attributes with
  ``hasattr``, which imports each of numpy's lazily loaded submodules; ``numpy.f2py`` and
  ``numpy.testing`` alone (with ``charset_normalizer``, ``unittest``, ``email``,
  ``importlib.metadata``) were ~30 ms of the command line's ~190 ms import. (Deferring
  ``scipy.spatial.transform`` and ``yaml``, which the kernels' loading imports unused,
  gained nothing measurable once that loading made no collections.)
"""

from __future__ import annotations

import gc
import importlib
import os
from collections.abc import Callable

from surfinpaint.app.interrupts import signals_noted
from surfinpaint.lazy import defer_modules

__all__ = ["BLAS_THREAD_VARIABLES", "HUGEPAGE_VARIABLE", "UNUSED_MODULES", "command_line",
           "process_settings", "program"]

# numpy's own switch (its "global state" documentation)
HUGEPAGE_VARIABLE = "NUMPY_MADVISE_HUGEPAGE"
# the variables BLAS libraries read for their thread count (OpenBLAS: the first three, in
# that order; MKL: its own, then OpenMP's); the first two are the ones set here
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "GOTO_NUM_THREADS",
                         "OMP_NUM_THREADS")
# numpy's lazily loaded submodules that scipy imports and no command uses (whatever reads
# one of their attributes still gets it)
UNUSED_MODULES = ("numpy.f2py", "numpy.testing", "numpy.char", "numpy.rec", "numpy.ctypeslib")


def process_settings(environ: dict[str, str] | None = None) -> dict[str, str]:
    """Set the program's defaults in ``environ`` (``os.environ`` when None) where the user
    set none, and return those set. They take effect in this process when numpy is imported
    after this call, and in every process started from it."""
    env = os.environ if environ is None else environ
    settings = {}
    if HUGEPAGE_VARIABLE not in env:
        settings[HUGEPAGE_VARIABLE] = "0"
    if not any(name in env for name in BLAS_THREAD_VARIABLES):
        settings.update(dict.fromkeys(BLAS_THREAD_VARIABLES[:2], "1"))
    env.update(settings)
    return settings


def command_line() -> Callable[[], int]:
    """The program's start: :func:`process_settings`, the modules of :data:`UNUSED_MODULES`
    deferred, the command line imported without collections and its objects frozen, the
    kernels' loading set to freeze its own (:func:`~surfinpaint.fill.warmup.freeze_loaded`);
    returns :func:`surfinpaint.app.cli.main`."""
    process_settings()
    gc.disable()  # the imports make ~100k objects that live to the end: no collection walks them
    try:
        # numpy first (after the settings): its own submodules' stand-ins must be its
        # attributes, or its module __getattr__ would import them
        importlib.import_module("numpy")
        defer_modules(UNUSED_MODULES)
        # here, not at the top: numpy is imported with the command line, after the settings
        from surfinpaint.app.cli import main

        # here, not at the top: the fill's modules come with the command line, after them
        from surfinpaint.fill.warmup import freeze_loaded
        freeze_loaded()
    finally:
        gc.freeze()
        gc.enable()
    return main


def program() -> int:
    """The ``surfinpaint`` program: :func:`command_line`, then
    :func:`surfinpaint.app.cli.main` on ``sys.argv``; its exit code returned for
    ``sys.exit``.

    The process ends right after, so the objects alive then (the modules' and numba's:
    ~120k of them after a fill) are frozen out of the cyclic garbage collector
    (``gc.freeze``), once after the imports, once after the kernels' loading (which makes
    them without collections) and once after the command: the interpreter's
    exit otherwise walks all of them in each of its collections, 0.3-0.9 s of a large fill
    (docs/scale.md, session 11). The imports themselves run without collections, which
    would walk the same objects as they are made (``from surfinpaint.app import cli``
    0.324 -> 0.298 s, 5 alternated runs; session 23). Nothing is skipped: the atexit
    handlers, the streams' flush and the freeing by reference counts run as before; only
    garbage in reference cycles among the frozen objects is left to the operating system.

    A SIGINT or SIGTERM while the command line is imported is noted and acted on as the
    command starts (:func:`~surfinpaint.app.interrupts.signals_noted`): its one line and
    130/143."""
    with signals_noted():
        code = command_line()()
    gc.freeze()
    return code
