"""Holes filled in worker processes, bit-identical to one after another: the rule, and
what runs in a worker.

A hole's fill depends only on its neighbourhood (the faces within the method's rings of its
loop). In the serial loop, a later hole's neighbourhood takes in the faces an earlier hole
added when it reaches that hole's loop; otherwise it is the same cut of the original mesh.
So a hole whose neighbourhood in the original mesh holds no vertex of an earlier hole's
loop is *independent*: its fill can be made at once, anywhere, from that cut. The others
are *dependent*: they are cut once the holes they reach are stitched in. The schedule is in
:mod:`surfinpaint.fill.scheduler`.

A worker gets the hole's neighbourhood arrays and the options, or (forked: it inherited the
mesh) only the hole's number, and returns the :class:`~surfinpaint.fill.results.Fill` and
the warnings it raised; the parent stitches the fills in hole order, so vertex numbering,
warnings and progress are those of the serial run.
"""

from __future__ import annotations

import dataclasses
import multiprocessing
import os
import sys
import threading
import time
import warnings
import weakref
from collections.abc import Callable, Collection
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from multiprocessing.connection import wait as ready_connections

import numpy as np

from surfinpaint.errors import NUMERICAL_ERRORS, FillError, MeshError
from surfinpaint.fill.conformal import ConformalOptions
from surfinpaint.fill.liepa.baseline import faired_fills, smoothing_decision
from surfinpaint.fill.results import Fill
from surfinpaint.geometry.intersection import patch_intersects_surroundings
from surfinpaint.geometry.rows import rows_any
from surfinpaint.lazy import lazy_module

# the λ-H fill at its first use: a faired fill never imports it (a forked worker finds it
# imported by warmup.warm_kernels("conformal"); docs/scale.md, session 14)
conformal_method = lazy_module("surfinpaint.fill.conformal.method")

__all__ = ["crossing_triangles", "exit_with_parent", "fill_local", "fill_or_failure", "forks",
           "independent", "pool", "pool_telling", "reissue", "resolve_jobs", "start_context",
           "told_queue", "wait_first", "worth_parallel"]

# fewer holes than this, or fewer boundary edges in all, and the holes are filled in this
# process: starting workers costs more than such holes take (a faired fill of a 60-edge
# hole takes ~12 ms, a conformal one ~170 ms: benchmarks/parallel.py)
MIN_PARALLEL_HOLES = 3
MIN_PARALLEL_EDGES = {"conformal": 120, "fair": 3000}

WarningRecord = tuple[str, type[Warning], str, int]


def resolve_jobs(jobs) -> int:
    """The number of worker processes: ``None`` all the cores this process may use."""
    if jobs is None:
        if hasattr(os, "sched_getaffinity"):
            return len(os.sched_getaffinity(0))
        return os.cpu_count() or 1
    if isinstance(jobs, bool) or not isinstance(jobs, int | np.integer) or jobs < 1:
        raise ValueError(f"jobs must be a positive integer or None (all cores), got {jobs!r}")
    return int(jobs)


# the surface around a fill that its triangles are checked against: a fill that crosses the
# surface does so next to its loop (where the loop folds over); against the whole
# neighbourhood the check took 11-14 ms a hole on the demo's holes, within 2 rings 2-3 ms
CROSSING_RINGS = 2


def crossing_triangles(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                       fill: Fill) -> np.ndarray:
    """Which of ``fill``'s triangles pierce or overlap the surface within ``CROSSING_RINGS``
    vertex rings of ``loop`` (touching it along the loop does not count).

    Parameters
    ----------
    vertices, faces : arrays
        The surface around the hole (a neighbourhood, local ids).
    loop : (k,) int array
        The hole's boundary loop.
    fill : Fill
        Its fill, over ``faces``' ids and ``len(vertices) + j`` for new vertex ``j``.

    Returns
    -------
    (c,) int64 array
        Their rows in ``fill.faces``, sorted; empty for a clean fill. A folded boundary loop
        (at a sharp corner, on a folded brain surface) can make any fill of it cross the
        surface there.
    """
    near = np.zeros(len(vertices), dtype=bool)
    near[loop] = True
    for _ in range(CROSSING_RINGS):
        near[faces[rows_any(near[faces])]] = True
    around = faces[rows_any(near[faces])]
    new_f = np.asarray(fill.faces, dtype=np.int64).reshape(-1, 3)
    if not len(new_f) or not len(around):
        return np.empty(0, dtype=np.int64)
    positions = np.concatenate([vertices, np.asarray(fill.vertices, float).reshape(-1, 3)])
    pairs = patch_intersects_surroundings(positions, new_f, around)
    return np.unique(pairs[:, 0]).astype(np.int64)


def fill_local(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, method: str,
               options: ConformalOptions, fair_order: int | None,
               stage: Callable[[str], None] | None = None) -> Fill:
    """Fill one hole of a neighbourhood (local ids) with ``method``, with those of its
    triangles that cross the surface around it (:func:`crossing_triangles`); ``stage`` told of
    the conformal fill's stages (:data:`~surfinpaint.fill.conformal.method.STAGES`)."""
    if method == "fair":  # the baseline, or the conformal method's fallback (its smoothing)
        order = fair_order or 2
        smoothing = smoothing_decision(vertices, faces, loop, options.fair_smoothing)
        new_v, new_f, used = faired_fills(
            vertices, faces, loop, (order,),
            smoothing=None if smoothing is None else smoothing.length)[order]
        fill = Fill(new_v, new_f, "fair", fair_order=used, smoothing=smoothing)
    else:
        fill = conformal_method.conformal_fill(vertices, faces, loop, options,
                                               fair_order=fair_order, stage=stage)
    return dataclasses.replace(fill, crossing_triangles=crossing_triangles(vertices, faces,
                                                                            loop, fill))


def fill_or_failure(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, method: str,
                    options: ConformalOptions, fair_order: int | None,
                    stage: Callable[[str], None] | None = None
                    ) -> tuple[Fill | None, str | None]:
    """:func:`fill_local`'s fill and None, or None and why it failed: a numerical failure
    of this hole's fill (``NUMERICAL_ERRORS``: a ``FillError``, a singular system; the
    conformal method's faired fallback included) is the hole's, reported so that the other
    holes are still filled. Bad input (``MeshError``) is raised."""
    try:
        return fill_local(vertices, faces, loop, method, options, fair_order, stage), None
    except MeshError:
        raise
    except NUMERICAL_ERRORS as exc:
        return None, str(exc) if isinstance(exc, FillError) else f"{type(exc).__name__}: {exc}"


def reissue(records: list[WarningRecord]) -> None:
    """The warnings a worker raised, issued here (the parent's filters apply)."""
    for message, category, filename, lineno in records:
        warnings.warn_explicit(message, category, filename, lineno)


def independent(reaches: list[np.ndarray], loops: list[np.ndarray]) -> set[int]:
    """The holes (positions in the serial order) whose neighbourhood in the original mesh
    (``reaches[k]``: its vertex ids, sorted) holds no vertex of an earlier hole's loop."""
    return {k for k, reach in enumerate(reaches)
            if not np.isin(np.concatenate(loops[:k]) if k else [], reach).any()}


def worth_parallel(n_edges: list[int], workers: int, method: str) -> bool:
    """Whether holes of these sizes are worth starting ``workers`` processes for."""
    return (workers > 1 and len(n_edges) >= MIN_PARALLEL_HOLES
            and sum(n_edges) >= MIN_PARALLEL_EDGES[method])


def forks() -> bool:
    """Whether :func:`start_context` forks the workers (then they inherit this process's
    memory: Linux, one thread)."""
    return ("fork" in multiprocessing.get_all_start_methods()
            and sys.platform.startswith("linux") and threading.active_count() == 1)


def start_context(preload: str) -> multiprocessing.context.BaseContext:
    """How worker processes start: forked on Linux where this process runs one thread (no re-import
    of the caller's script, so it needs no ``if __name__ == "__main__"`` guard, and the
    imported modules and compiled kernels come along; the parent's pages are shared, not
    copied), else from a server that imported the module ``preload`` once ("forkserver":
    a fork while other threads run could copy a lock one of them holds), else spawned
    (no fork: the caller's script then needs the guard). Not forked on macOS even with one
    thread: its system libraries are not safe across fork (why CPython spawns there)."""
    methods = multiprocessing.get_all_start_methods()
    if forks():
        return multiprocessing.get_context("fork")
    method = "forkserver" if "forkserver" in methods else "spawn"
    context = multiprocessing.get_context(method)
    if method == "forkserver":
        context.set_forkserver_preload([preload])
    return context


#: Seconds between a worker's looks at whether the process that started it is still there
PARENT_CHECK_EVERY = 1.0


def exit_with_parent() -> None:
    """Worker initializer: the worker exits when the process that started it is gone.

    A parent killed outright (SIGKILL, the OOM killer) cannot end its workers, and a forked
    worker never sees its task queue close (it holds the queue's write end itself): it
    waited for ever, idle (session 46's fuzz campaign: 3 of 9 ``fill`` runs killed with
    SIGKILL left 2 workers each). A daemon thread looks every :data:`PARENT_CHECK_EVERY`
    seconds whether the worker's parent (the caller, or a forkserver, which exits with
    the caller) changed, and ends the worker at once if so.
    """
    parent = os.getppid()

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(PARENT_CHECK_EVERY)
        os._exit(1)

    threading.Thread(target=watch, name="exit-with-parent", daemon=True).start()


# a forkserver preloads the module of the tasks (it imports this one)
_TASKS = "surfinpaint.fill.scheduler"


def pool(workers: int) -> ProcessPoolExecutor:
    """Worker processes for the holes of one mesh, started as :func:`start_context` says,
    each ending with its parent (:func:`exit_with_parent`)."""
    return ProcessPoolExecutor(workers, mp_context=start_context(_TASKS),
                               initializer=exit_with_parent)


# in a worker of pool_telling: the queue it tells the parent news through
_TOLD: list = []


def _start_telling(queue) -> None:
    """Worker initializer of :func:`pool_telling`: :func:`exit_with_parent`, and ``queue``
    kept for :func:`told_queue`."""
    _TOLD[:] = [queue]
    exit_with_parent()


def told_queue():
    """In a worker of :func:`pool_telling`: the queue to tell the parent news through;
    None in any other process."""
    return _TOLD[0] if _TOLD else None


def pool_telling(workers: int):
    """:func:`pool`'s workers, and a queue (a ``SimpleQueue``: a message is in the pipe
    once ``put`` returns) that each worker gets as it starts (:func:`told_queue` there) to
    tell this process news through. Forked or not: a worker from a forkserver or spawned
    (this process runs other threads, macOS) inherits no queue, and gets one only as an
    argument of its start, made with the pool's start method."""
    context = start_context(_TASKS)
    queue = context.SimpleQueue()
    return ProcessPoolExecutor(workers, mp_context=context, initializer=_start_telling,
                               initargs=(queue,)), queue


def end_workers(pool: ProcessPoolExecutor) -> None:
    """End the worker processes of ``pool`` at once, then shut it down: their work in
    flight is dropped (a Ctrl-C or SIGTERM, a failure: a hole's λ-H fill or a batch's file
    can take minutes, longer than a scheduler's grace before SIGKILL; session 47: ``fill``
    acted on a SIGTERM 15-70 s late, the pool's shutdown waiting for its workers' holes).

    SIGKILL, not SIGTERM: a worker forked by ``fill`` inherits the command line's handler,
    which would raise only after the solver call under way, and then hand the worker its
    next task. The pool's own list of its processes is a private attribute: concurrent.futures
    has no public way to end a pool's workers before Python 3.14 (3.11 here); 3.14's
    ``terminate_workers()`` shuts the pool down without waiting for the thread that reads
    what the workers sent, and so whether the results sent before the end still reach their
    futures (a batch records those files) would rest on that thread's internals.
    ``multiprocessing.active_children()`` would end the caller's other child processes too.
    Without the attribute nothing ends early: the shutdown waits for the work in flight.

    A worker killed while it sent a result leaves half a message in the result pipe: the
    pool's thread that reads it waits for the rest, and the shutdown for that thread, for
    ever, since this process holds the pipe's write end too (session 50: 1 of 58 SIGTERMs
    at load 3; CI's ``test_signal_while_filling_stops_with_one_line``). So that end is
    closed once the workers are dead: the read ends, the pool is marked broken, and the
    shutdown returns."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    for process in processes:
        process.kill()
    for process in processes:
        process.join()
    results = getattr(pool, "_result_queue", None)
    if processes and results is not None:  # nobody writes to it any more
        results._writer.close()
    pool.shutdown(wait=True, cancel_futures=True)



#: Seconds a pool may take to find a dead worker and fail its futures; past them, it is taken
#: to be stuck on half a message (:func:`end_workers`) and its workers are ended
STUCK_AFTER = 5.0
_DEAD_SEEN: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()  # pool: when first seen


def wait_first(pool: ProcessPoolExecutor, futures: Collection[Future],
               timeout: float | None = None) -> tuple[set[Future], set[Future]]:
    """:func:`concurrent.futures.wait` for the first of ``futures`` (submitted to ``pool``) to
    finish, at most ``timeout`` seconds (None: no limit); but a pool one of whose workers
    died while it sent a result is not waited for for ever.

    Such a worker (the OOM killer's, or any SIGKILL) leaves half a message in the result
    pipe, and the pool's reading thread waits for the rest while the other workers live
    (:func:`end_workers`): the pool never finds the dead worker, and its futures never end.
    Where a worker has been dead for :data:`STUCK_AFTER` seconds and the pool has not
    failed its futures, its workers are ended (:func:`end_workers`): the futures in flight
    then fail with ``BrokenProcessPool``, as they do when a worker dies at any other
    moment, and the caller retries or reports them."""
    deadline = None if timeout is None else time.monotonic() + timeout
    while True:
        step = STUCK_AFTER if deadline is None else \
            max(0.0, min(STUCK_AFTER, deadline - time.monotonic()))
        done, pending = wait(futures, timeout=step, return_when=FIRST_COMPLETED)
        if done:
            return done, pending
        if _stuck(pool):  # looked at on every call: a caller's short timeouts add up
            end_workers(pool)  # the pool fails its futures as it shuts down
            return wait(futures, return_when=FIRST_COMPLETED)
        if deadline is not None and time.monotonic() >= deadline:
            return done, pending


def _stuck(pool: ProcessPoolExecutor) -> bool:
    """Whether a worker of ``pool`` has been seen dead for :data:`STUCK_AFTER` seconds and
    the pool is not broken. A dead worker is seen by its sentinel (not ``exitcode``, which
    would reap it under the pool's own thread)."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    dead = not getattr(pool, "_broken", False) and processes and \
        ready_connections([p.sentinel for p in processes], timeout=0)
    if not dead:
        _DEAD_SEEN.pop(pool, None)
        return False
    first = _DEAD_SEEN.setdefault(pool, time.monotonic())
    return time.monotonic() - first >= STUCK_AFTER
