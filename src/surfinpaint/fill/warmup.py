"""The compiled kernels loaded once before a parallel fill's workers are forked.

A process's first fill waits for numba's import and for the kernels' machine code to be
loaded from the disk cache (about 0.3 s CPU; several seconds when they must be compiled
after an install). Forked workers inherit what their parent has loaded, so before it forks
them :func:`fill_holes` loads the kernels once (:func:`load_for_workers`) instead of each
worker loading them itself (measured on the 651k case: workers +0.5 s CPU without it). A
small mesh's serial fill loads them at its first hole, as any call would.

A large mesh's whole-mesh passes (edge table, topology check, holes) run one after another
in one thread and leave a core idle: the kernels are loaded meanwhile, in a thread beside
them (:func:`loading_beside`), whatever the method, so that neither the first hole nor the
fork of the workers waits for them (651k case, default method on 2 workers, 8 alternated
runs: 2.88 -> 2.58 s). The price is memory: numba's and LLVM's (about 100 MB) is then
resident beside the edge table, at the peak (319 -> 422 MB on that case; the faired fill
peaks there already: docs/scale.md, sessions 13 and 22).

:func:`warm_kernels` fills a small hole of a fixed mesh with the faired fill (the
triangulation and the edge-flip kernels) and, for the conformal method only, measures a
point-to-mesh distance (its self-check's kernel; a ``fair`` fill never uses it), the
vertex normals and areas (its lagged solves' kernel) and the faces' derivative blocks (its
Newton steps' Jacobians), through the same functions a real fill calls, so numba loads
exactly the specialisations real fills use, not new ones. It only computes: no file, no
warning, no message besides numba's "compiling" notice. The batch command and the dask
workers call it too.

Run as a program (``surfinpaint.compiled``'s background compilation, :func:`main`), it
compiles every kernel into numba's disk cache.
"""

from __future__ import annotations

import functools
import gc
import importlib.util
import os
import sys
import threading
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import contextmanager, nullcontext
from typing import TypeVar

import numpy as np

from surfinpaint.fill import parallel
from surfinpaint.fill.liepa.baseline import faired_fill
from surfinpaint.geometry.vertex_measures import vertex_normals_and_areas
from surfinpaint.lazy import lazy_module
from surfinpaint.representation import face_derivatives

# the conformal self-check's distances: a faired fill never imports them
metrics = lazy_module("surfinpaint.geometry.metrics")
# the BLAS thread-pool controller (threadpoolctl: not imported by the command line's start)
blas_threads = lazy_module("surfinpaint.representation.blas_threads")

__all__ = ["BESIDE_MIN_FACES", "Beside", "compile_kernels", "freeze_loaded", "kernels_loaded",
           "load_ahead", "load_for_workers", "loading_beside", "main", "warm_kernels",
           "warmup_mesh"]

# below this many faces the whole-mesh passes take too little time to hide the loading
BESIDE_MIN_FACES = 100_000

T = TypeVar("T")

# the kernels each method uses, loaded (the conformal method's include the faired fill's)
_done = {"fair": threading.Event(), "conformal": threading.Event()}
# set by a process that ends after its command (freeze_loaded)
_freezing = threading.Event()


def warmup_mesh() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A small bumpy annulus (3 rings of 10 vertices around an 10-edge hole): vertices,
    consistently oriented faces and the hole's loop."""
    n, rings = 10, 4
    angle = 2 * np.pi * np.arange(n) / n
    radius = np.repeat(1.0 + np.arange(rings), n)
    theta = np.tile(angle, rings)
    vertices = np.column_stack([radius * np.cos(theta), radius * np.sin(theta),
                                0.1 * np.sin(3 * theta) * radius])
    faces = []
    for r in range(rings - 1):
        a = r * n + np.arange(n)
        b = r * n + (np.arange(n) + 1) % n
        faces += [np.column_stack([a, a + n, b]), np.column_stack([b, a + n, b + n])]
    return vertices, np.concatenate(faces).astype(np.int64), np.arange(n)[::-1].copy()


def kernels_loaded(method: str = "conformal") -> bool:
    """Whether :func:`warm_kernels` has loaded ``method``'s kernels in this process."""
    return _done[method].is_set()


def warm_kernels(method: str = "conformal") -> None:
    """Load (or compile) the kernels a fill by ``method`` ("conformal" or "fair") uses by
    running them once on :func:`warmup_mesh`; a no-op once they are loaded in this process
    and without numba. For "conformal" the λ-H fill's modules are imported too (a faired fill
    never imports them) and the process's BLAS thread-pool controller made
    (:func:`~surfinpaint.representation.blas_threads.blas_controller`), so that forked
    workers inherit them as they inherit the kernels."""
    if method == "conformal":
        parallel.conformal_method.module  # noqa: B018  (imported now)
        # made here, beside the passes, not where the holes start: the λ-H solves and the
        # parallel fill's one-thread limits use it, and forked workers inherit it (making
        # one lists the loaded libraries: 15-23 ms in the 651k command; docs/scale.md,
        # session 41)
        blas_threads.blas_controller()
    if _done[method].is_set() or importlib.util.find_spec("numba") is None:
        _done[method].set()
        return
    vertices, faces, loop = warmup_mesh()
    if not _done["fair"].is_set():
        faired_fill(vertices, faces, loop, 2)
        _done["fair"].set()
    if method == "conformal":
        metrics.warm(vertices, faces)
        vertex_normals_and_areas(vertices, faces)  # the λ-H fill's lagged solves
        face_derivatives.warm(vertices, faces)  # its Newton steps' Jacobians
    _done[method].set()


def load_for_workers(method: str) -> None:
    """:func:`warm_kernels` before a parallel fill's workers are forked (they inherit the
    loaded kernels); nothing where they are not forked (:func:`~surfinpaint.fill.parallel.
    forks`: each worker process loads its own)."""
    if parallel.forks():
        _quietly(method)


class Beside:
    """Whole-mesh work started early and collected where it is needed: on one thread beside
    the caller's passes for a large mesh (``threaded``), else done when collected, where
    the passes would have done it.

    :meth:`submit` returns the collector, a function that waits for the work and returns
    its result or raises what it raised. The thread runs the work in the order submitted.
    """

    def __init__(self, threaded: bool) -> None:
        self._executor = (ThreadPoolExecutor(max_workers=1, thread_name_prefix="surfinpaint-passes")
                          if threaded else None)

    def submit(self, function: Callable[..., T], *args, **kwargs) -> Callable[[], T]:
        if self._executor is None:
            return functools.partial(function, *args, **kwargs)
        return self._executor.submit(function, *args, **kwargs).result

    def join(self) -> None:
        """Wait for the work under way and drop the rest (the thread ends)."""
        if self._executor is not None:
            self._executor.shutdown(wait=True, cancel_futures=True)


# the loading thread started ahead of a fill (load_ahead); loading_beside joins it
_ahead: list[threading.Thread] = []


def load_ahead(method: str) -> None:
    """Start loading ``method``'s kernels in a background thread now (the one
    :func:`loading_beside` starts for a large mesh), for a caller with other work to do
    before it fills one (the command line reads the file meanwhile); the next
    :func:`loading_beside` joins it when its passes end. Nothing when they are loaded or
    loading. The thread is a daemon: a process that fails before the fill does not wait
    for it."""
    if _done[method].is_set() or _ahead:
        return
    thread = threading.Thread(target=_quietly, args=(method, _freezing.is_set()),
                              name="surfinpaint-warmup", daemon=True)
    thread.start()
    _ahead.append(thread)


@contextmanager
def loading_beside(n_faces: int, method: str) -> Iterator[Beside]:
    """While the block runs (the whole-mesh passes), for a mesh of at least
    ``BESIDE_MIN_FACES`` faces, :func:`warm_kernels` for ``method`` in a background thread
    (unless the kernels are loaded), and the block's own work handed to the yielded
    :class:`Beside` on another; both joined when the block ends, before any hole is filled
    or worker forked (a fork copies one thread). A smaller mesh's passes are too short to
    hide anything: its first hole loads the kernels, and its ``Beside`` does the work where
    it is collected.

    Measured on the 651k case, alternated runs (docs/scale.md): the faired fill (serial: its
    first hole waited for the load) 1.97-2.08 -> 1.69-1.72 s of wall, quiet (session 13);
    the default method (parallel: the workers were forked after a load here) 2.88 -> 2.58 s
    median of 8 at load 1.8-2.2, and 4.21 -> 4.11 s with other processes on the cores
    (load 3), the CPU unchanged (session 22). The numpy work of the passes releases the
    GIL; the loading's Python holds it meanwhile.
    """
    large = n_faces >= BESIDE_MIN_FACES
    if large:
        load_ahead(method)
    beside = Beside(large)
    try:
        yield beside
    finally:
        beside.join()
        while _ahead:
            _ahead.pop().join()


def freeze_loaded() -> None:
    """For a process that ends after its command (the program's, :mod:`surfinpaint.app.
    program`): the thread :func:`load_ahead` starts then loads without garbage collections
    and freezes what it made (``gc.freeze``). numba's types and registries, ~85k objects
    that live to the end, were otherwise walked as they were made by ~190 collections
    (27-33 ms of the thread's ~290 ms CPU on the 651k case, on the path to the workers'
    fork; docs/scale.md, session 45) and by later full ones."""
    _freezing.set()


@contextmanager
def _frozen_when_made() -> Iterator[None]:
    """No collection while the block runs; the objects alive after it frozen (those of
    other threads too: in a process that ends after its command, nothing is lost)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        gc.freeze()
        if enabled:
            gc.enable()


def _quietly(method: str, frozen: bool = False) -> None:
    # a failure here is not the caller's: the first hole then loads or compiles the kernels
    # itself and raises whatever there is to raise
    with _frozen_when_made() if frozen else nullcontext():
        try:
            warm_kernels(method)
        except Exception:  # noqa: BLE001
            pass


def compile_kernels() -> None:
    """Compile (or load) every kernel, in the order the fallbacks of a first run cost most
    per second of compilation: the distances (conformal self-checks), the triangulation's
    dynamic program, the edge flips, the vertex normals and areas (λ-H lagged solves), the
    faces' derivative blocks (λ-H Newton steps)."""
    vertices, faces, loop = warmup_mesh()
    metrics.warm(vertices, faces)
    faired_fill(vertices, faces, loop, 2)
    vertex_normals_and_areas(vertices, faces)
    face_derivatives.warm(vertices, faces)


def main(argv: list[str]) -> int:
    """The background compilation started by ``surfinpaint.compiled``: ``argv`` is the
    inherited descriptor holding the lock and the lock's path. A failure leaves
    ``path + ".failed"`` (later runs then compile in their own process)."""
    fd, path = int(argv[0]), argv[1]
    try:
        compile_kernels()
    except Exception as exc:  # noqa: BLE001 - reported through the marker, then raised
        with open(path + ".failed", "w") as marker:
            marker.write(f"{type(exc).__name__}: {exc}\n")
        raise
    finally:
        os.close(fd)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
