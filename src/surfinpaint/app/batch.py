"""Batch filling: many mesh files at once, on local worker processes or a Dask cluster.

:func:`fill_files` finds the mesh files named by files, folders (searched recursively) and
glob patterns, fills each one in a worker (:func:`fill_file`, a top-level function, so that
worker processes and Dask workers can import it), and writes ``summary.csv`` and
``summary.json`` with one :class:`FileRow` per input file.

A file that cannot be read or filled becomes a ``failed`` row, the others still written; each
is checked cheaply before any is filled (:func:`surfinpaint.io.formats.check_file`), as the
inputs are listed (:mod:`surfinpaint.app.batch_listing`); this module runs the fills.
Every output is written atomically (a complete file or none), so an interrupted run, or a
worker killed mid-file, leaves no partial output, and a rerun skips the outputs that are
newer than every file their fill reads: it picks up where the last run stopped. The progress
callback hears of each file done and, from this process and local workers (not from Dask
workers), of the holes of the files in flight; the ``on_result`` callback gets each file's
row as that file finishes (the command line prints a bad file's error then, not at the end).
"""

from __future__ import annotations

import dataclasses
import gc
import os
import signal
import threading
import time
import uuid
import warnings
from collections import deque
from collections.abc import Mapping, Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import Any

import numpy as np
from threadpoolctl import threadpool_limits

from surfinpaint.app.batch_inputs import FileJob, Inputs, find_inputs
from surfinpaint.app.batch_listing import (
    ProgressCallback,
    ResultCallback,
    RunRows,
    list_jobs,
    remove_temporaries,
)
from surfinpaint.app.batch_summary import (
    MESSAGE_SEPARATOR,
    STATUSES,
    SUMMARY_CSV,
    SUMMARY_JSON,
    FileRow,
    FileRows,
    error_text,
    fill_messages,
    named_in_summary,
    read_summary,
    row_of,
    write_summary,
)
from surfinpaint.app.interrupts import Interrupted, raise_interruption
from surfinpaint.app.outputs import write_with_materials
from surfinpaint.compiled import announce_once_across
from surfinpaint.errors import how_many
from surfinpaint.fill.objects import fill_mesh_data
from surfinpaint.fill.parallel import end_workers, exit_with_parent, start_context, wait_first
from surfinpaint.fill.pipeline import METHODS, FillResult, fill_holes
from surfinpaint.fill.warmup import warm_kernels
from surfinpaint.io.formats import MeshData, read_mesh_data
from surfinpaint.lazy import lazy_module

__all__ = ["MESSAGE_SEPARATOR", "FileJob", "FileRow", "FileRows", "STATUSES", "SUMMARY_CSV",
           "SUMMARY_JSON", "fill_file", "fill_files", "find_inputs", "read_summary",
           "write_summary"]

#: How often a file whose worker process died is tried again (alone) before it is reported
#: failed: Dask's default ``distributed.scheduler.allowed-failures`` too.
WORKER_RETRIES = 3

# imported by the first picture: a batch without pictures does without the module
figures = lazy_module("surfinpaint.app.figures")

# The queue a local worker process sends the hole progress of its file through (set by the
# pool's initializer; None in the calling process and on Dask workers).
_HOLE_PROGRESS: Any = None
# How long the parent waits for a file to finish before it shows the holes' progress again.
_PROGRESS_SECONDS = 0.1


# -------------------------------------------------------------------------- one file's fill


def _draw(job: FileJob, mesh: MeshData, result: FillResult) -> str:
    """Draw the before/after picture of ``job`` (when it has one) in this process, the
    worker that filled it: the fill's result is here, and sending it to the parent to draw
    would copy the mesh twice (PyVista renders off-screen in forked and spawned workers
    alike). Returns why it could not be drawn, or "": a picture that fails (no OpenGL on
    a cluster node, a full disk) is noted in the file's row, its output is kept."""
    if job.picture is None:
        return ""
    try:
        figures.before_after(mesh.vertices, mesh.faces, result, job.picture)
    except Exception as exc:  # the picture's failure is the row's note, not the file's
        raise_interruption(exc)
        return named_in_summary(job, f"{job.picture}: picture not drawn: "
                                f"{type(exc).__name__}: {exc}")
    return ""


# The warnings filter and the BLAS thread limit are per process: a Dask worker with several
# threads fills one file at a time, so that no file's warnings land in another's row.
_ONE_FILE_AT_A_TIME = threading.Lock()


def fill_file(job: FileJob, options: Mapping[str, Any],
              hole_progress: ProgressCallback | None = None) -> FileRow:
    """Read, fill and write one file, and draw its picture when the job has one; never
    raises for a bad file (it becomes a "failed" row, with nothing written). A top-level
    function: worker processes and Dask workers import it. Runs with one BLAS thread: the
    parallelism is over files.

    ``hole_progress(done, total, message)`` is told of the file's holes (the ``progress``
    of :func:`surfinpaint.fill_holes`); in a local worker process they go to the parent
    through the pool's queue instead."""
    if hole_progress is None and _HOLE_PROGRESS is not None:
        queue = _HOLE_PROGRESS

        def hole_progress(done: int, total: int, message: str) -> None:
            queue.put((job.name, done, total, message))

    started = time.perf_counter()
    with _ONE_FILE_AT_A_TIME, warnings.catch_warnings(record=True) as caught, \
            threadpool_limits(limits=1):
        warnings.simplefilter("always")
        try:
            # every attribute the file carries, filled in at the new vertices and faces
            # the parallelism is over files: the holes of each are filled one by one
            mesh = read_mesh_data(job.source, overlays=job.overlays_read())
            result, filled = fill_mesh_data(mesh, **options, jobs=1, progress=hole_progress)
            job.target.parent.mkdir(parents=True, exist_ok=True)
            # an OBJ's .mtl and textures beside it, as `surfinpaint fill` copies them; a
            # copy an earlier run made is replaced when the input's changed (job.copied)
            materials = write_with_materials(job.source, job.target, filled,
                                             len(mesh.vertices), ours=dict(job.copied),
                                             reserved=[job.picture] if job.picture else [])
        except Exception as exc:  # any failure of one file is that file's row, not the batch's
            raise_interruption(exc)
            return FileRow(job.name, job.output, "failed",
                           seconds=time.perf_counter() - started, message=error_text(job, exc))
        unfinished = _draw(job, mesh, result)
    message = MESSAGE_SEPARATOR.join(
        t for t in (fill_messages(job, result, caught), unfinished) if t)
    return dataclasses.replace(row_of(job, result, time.perf_counter() - started, message,
                                      None if unfinished else job.picture_output),
                               materials=materials.record)


def _worker_died(job: FileJob, why: str) -> FileRow:
    return FileRow(job.name, job.output, "failed",
                   message=f"{job.name}: the worker process died while filling it ({why})")


# ------------------------------------------------------------------------- the runners


def _start_worker(queue: Any | None, method: str, told: Any = None) -> None:
    """Worker initializer. Ctrl-C reaches the whole process group; the parent decides (it
    records the files done and ends the workers: :func:`_drain`). SIGTERM ends the worker
    (a forked one inherits the command's handler, which would raise in the middle of a
    file instead). ``queue`` takes the hole progress of the worker's files to the parent
    (None: nobody listens). The compiled kernels of ``method`` are loaded now, while the
    parent still lists and checks the inputs (:func:`_launch`), not in the first file; on a
    cold cache the first worker to compile says so, the others not (``told``). A worker
    ends with its parent (:func:`~surfinpaint.fill.parallel.exit_with_parent`)."""
    global _HOLE_PROGRESS
    exit_with_parent()
    if told is not None:
        announce_once_across(told)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if queue is not None:
        queue.cancel_join_thread()  # a worker's exit does not wait for the parent to read
    _HOLE_PROGRESS = queue
    warm_kernels(method)


_Launched = tuple[ProcessPoolExecutor, Any]


def _launch(workers: int, progress: bool, method: str) -> _Launched:
    """A pool of ``workers`` processes, started now (how:
    :func:`surfinpaint.fill.parallel.start_context`), each loading the kernels of
    ``method`` as it starts; and the queue they send their holes' progress through (None
    without ``progress``; a new one per pool: a worker killed while it sent may leave one
    locked)."""
    context = start_context(__name__)
    holes = context.Queue() if progress else None
    # the objects a forked worker inherits are left out of its garbage collections, which
    # would otherwise write to (and so copy) every page holding them
    gc.freeze()
    try:
        pool = ProcessPoolExecutor(workers, mp_context=context, initializer=_start_worker,
                                   initargs=(holes, method, context.Value("b", 0)))
        for _ in range(workers):  # each task starts a worker (all of them, when forked)
            pool.submit(os.getpid)
    finally:
        gc.unfreeze()
    return pool, holes


def _drain(pool: ProcessPoolExecutor, queue: deque, options: Mapping[str, Any], workers: int,
           rows: RunRows, holes: Any | None) -> list[FileJob]:
    """Keep ``workers`` files of ``queue`` in flight on ``pool`` until the queue is empty or
    a worker dies (the pool is then broken); returns the files that were in flight then.
    ``holes``: the queue the workers send their holes' progress through, if any."""
    running: dict[Future, FileJob] = {}
    lost: list[FileJob] = []
    broken = False
    try:
        while (queue and not broken) or running:
            while queue and not broken and len(running) < workers:
                job = queue.popleft()
                try:
                    running[pool.submit(fill_file, job, options)] = job
                except BrokenProcessPool:  # an idle worker died: this file never started
                    queue.appendleft(job)
                    broken = True
            # not for ever on a pool stuck on a dead worker's half-sent result
            done, _ = wait_first(pool, running, _PROGRESS_SECONDS if rows.progress else None)
            if holes is not None:
                rows.read(holes)
            for future in done:
                # a file leaves `running` once recorded: an interrupt here loses no row
                if isinstance(future.exception(), BrokenProcessPool):
                    lost.append(running[future])
                    broken = True
                else:
                    rows.add(future.result())
                del running[future]
    except BaseException:
        # Ctrl-C, SIGTERM or a callback's error: stop now, not after the files in flight
        # (a large one can take minutes, longer than a scheduler's grace before SIGKILL)
        _stop_workers(pool)
        for future in running:
            if not future.cancelled() and future.exception() is None:
                rows.add(future.result(), quiet=True)
        raise
    return lost


def _stop_workers(pool: ProcessPoolExecutor) -> None:
    """End the worker processes of ``pool`` at once, then shut it down. Their files in
    flight are dropped (an output is written whole or not at all; a write cut short leaves
    a temporary file, which the run removes): a rerun fills them. The files whose result
    reached the pool before its workers ended are done (their futures hold the rows): the
    pool reads what its workers sent before it finds them gone. A file written in the
    instant between its last byte and its result sent is complete but not recorded: a
    rerun keeps it, as an output newer than its input."""
    end_workers(pool)


def _run_pool(jobs: Sequence[FileJob], options: Mapping[str, Any], workers: int,
              rows: RunRows, launched: _Launched | None = None) -> list[FileJob]:
    """Fill ``jobs`` on ``workers`` processes (:func:`_launch`; ``launched``: the first
    pool, started earlier, which is shut down here in any case). A dead worker breaks the
    pool: a new one takes the files not yet started; the files in flight then are returned.

    Raises
    ------
    RuntimeError
        When pools of several workers break :data:`WORKER_RETRIES` times in a row before
        finishing any file: the workers cannot start (or every file kills them).
    """
    queue: deque[FileJob] = deque(jobs)
    suspects: list[FileJob] = []
    fruitless = 0
    if launched is not None and not queue:
        _stop_workers(launched[0])
    while queue:
        done_before = len(rows.by_name)
        pool, holes = launched or _launch(workers, rows.progress is not None,
                                          _method(options))
        launched = None
        with pool:
            lost = _drain(pool, queue, options, workers, rows, holes)
        if holes is not None:
            holes.close()
        remove_temporaries(lost)
        suspects += lost
        fruitless = fruitless + 1 if len(rows.by_name) == done_before else 0
        if fruitless == WORKER_RETRIES and workers > 1:
            raise RuntimeError(
                f"the worker processes died {how_many(fruitless, 'time', 'times')} before "
                "finishing any file; "
                "can they start? (a script that calls fill_files needs the "
                "`if __name__ == '__main__':` guard where workers are not forked: they "
                "import it)")
    return suspects


def _method(options: Mapping[str, Any]) -> str:
    """The fill method whose kernels a worker loads (``fill_holes``'s default)."""
    method = options.get("method", "conformal")
    return method if method in METHODS else "conformal"


def _run_local(jobs: Sequence[FileJob], options: Mapping[str, Any], n_jobs: int,
               rows: RunRows, launched: _Launched | None = None) -> None:
    """One file after another in this process (``n_jobs=1``), or on worker processes (the
    first pool ``launched`` earlier, if given). The files in flight when a worker died are
    tried again, each alone (so that the one that kills its worker is found), up to
    :data:`WORKER_RETRIES` times."""
    if n_jobs == 1:
        for job in jobs:
            rows.add(fill_file(job, options, rows.hole_progress_of(job)))
        return
    suspects = _run_pool(jobs, options, min(n_jobs, len(jobs)), rows, launched)
    for _ in range(WORKER_RETRIES):
        if not suspects:
            break
        # one file at a time: a worker that dies now names the file that killed it
        suspects = _run_pool(suspects, options, 1, rows)
    for job in suspects:
        rows.add(_worker_died(job, f"tried {how_many(WORKER_RETRIES + 1, 'time', 'times')}"))


def _run_dask(jobs: Sequence[FileJob], options: Mapping[str, Any], client: Any,
              rows: RunRows) -> None:
    """Every file a task on the Dask cluster of ``client`` (its workers must see the
    inputs and the output folder at the same paths). The scheduler retries the task of a
    worker that died; after its ``allowed-failures`` the file is a failed row."""
    from distributed import KilledWorker, as_completed

    run = uuid.uuid4().hex[:8]
    futures = client.map(fill_file, jobs, options=dict(options), pure=False,
                         key=[f"surfinpaint-fill-{run}-{i}" for i in range(len(jobs))])
    job_of = {future.key: job for future, job in zip(futures, jobs, strict=True)}
    try:
        for future in as_completed(futures):
            job = job_of[future.key]
            try:
                row = future.result()
            except KilledWorker as exc:
                row = _worker_died(job, f"KilledWorker: {exc}")
            except Exception as exc:  # the task could not run there (e.g. no surfinpaint)
                row = FileRow(job.name, job.output, "failed",
                              message=f"{job.name}: the cluster could not fill it: "
                              f"{type(exc).__name__}: {exc}")
            rows.add(row)
    except BaseException:
        client.cancel([future for future in futures if not future.done()])
        raise


# ------------------------------------------------------------------------- the entry point


def _cores() -> int:
    """The cores this process may use (its CPU affinity where the system has one)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def _check_options(options: Mapping[str, Any]) -> None:
    """Bad fill options are the caller's error before any file is read: ``fill_holes``
    checks them on a closed tetrahedron (no hole, so nothing is filled)."""
    for name in ("holes", "progress"):
        if name in options:
            raise TypeError(f"fill_files fills the holes of every file; {name!r} is "
                            "per mesh: call fill_holes for that")
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    fill_holes(vertices, faces, **options)


def _local_workers(jobs: int | None, client: Any) -> int:
    """The worker processes :func:`fill_files` starts on this machine for ``jobs`` (None:
    the cores this process may use; unused with a Dask ``client``, which ``jobs`` must
    then not be given with)."""
    if jobs is not None and client is not None:
        raise ValueError("jobs= is for worker processes on this machine; a Dask client's "
                         "cluster has its own workers")
    if jobs is not None and (not isinstance(jobs, int) or isinstance(jobs, bool) or jobs < 1):
        raise ValueError(f"jobs must be a positive integer, got {jobs!r}")
    return jobs or _cores()


def _listed(launched: _Launched | None, *listing: Any) -> tuple:
    """:func:`~surfinpaint.app.batch_listing.list_jobs` of ``listing`` (its arguments); if
    it raises, the workers ``launched`` are stopped and an interrupt is marked
    ``while_listing``."""
    try:
        return list_jobs(*listing)
    except BaseException as exc:
        if launched is not None:
            _stop_workers(launched[0])
        if isinstance(exc, KeyboardInterrupt | Interrupted):
            exc.while_listing = True  # no file was being filled: the command says so
        raise


def fill_files(
    inputs: Sequence[str | os.PathLike] | str | os.PathLike,
    out_dir: str | os.PathLike,
    jobs: int | None = None,
    client: Any = None,
    *,
    overwrite: bool = False,
    png: bool = False,
    overlays: Sequence[str] = (),
    progress: ProgressCallback | None = None,
    on_result: ResultCallback | None = None,
    **fill_options: Any,
) -> list[FileRow]:
    """Fill the holes of many mesh files, in parallel, into ``out_dir``.

    Parameters
    ----------
    inputs : path or sequence of paths
        Files, folders (searched recursively for known mesh extensions) and glob patterns;
        ``out_dir`` mirrors their layout (see :func:`find_inputs`).
    out_dir : path
        Output folder (created); it also receives ``summary.csv`` and ``summary.json``:
        the rows of this run's files and, kept as they were, those of the files earlier
        runs filled into it (:func:`~surfinpaint.app.batch_summary.kept_rows`; a file of
        this run takes its earlier row's place).
    jobs : int, optional
        Worker processes on this machine (default: the cores this process may use); 1 fills
        the files one after another in this process.
    client : distributed.Client, optional
        Run every file as a task on this Dask cluster instead (the optional extra ``dask``);
        its workers must import surfinpaint and see the files at the same paths.
    overwrite : bool
        Refill files whose output is newer than the input (skipped by default).
    png : bool
        Also draw every output's before/after picture beside it
        (:func:`surfinpaint.app.figures.before_after`, named by
        :func:`~surfinpaint.app.batch_inputs.picture_path`: ``sub/scan.ply`` →
        ``sub/scan.png``), in the worker that filled it (on a Dask cluster too: its workers
        need OpenGL for off-screen rendering). A file is then up to date only with its
        picture; a picture that fails is noted in the row's ``message`` (the output is
        kept, the status unchanged; a rerun refills the file to draw it).
    overlays : sequence of str
        Overlay files read with each GIFTI or FreeSurfer surface besides those found beside
        it (``batch --overlay``): paths taken from each input's folder, with placeholders
        ``{name}``, ``{stem}``, ``{hemi}`` filled in per input
        (:func:`~surfinpaint.app.batch_inputs.check_overlay_patterns`:
        ``../label/{hemi}.aparc.annot``). A file whose overlay is missing, or that is no
        such surface, is a failed row.
    progress : callable(done, total, message), optional
        Called before the first file and once a file is done (skipped files included),
        ``done`` and ``total`` counting files; and, without a Dask client, as the holes of
        the files in flight start and finish, ``message`` naming each such file with its
        holes done and found (``done`` still the files done).
    on_result : callable(FileRow), optional
        Called with each input file's :class:`FileRow` (the row of the summary and of the
        returned list) as soon as that file is recorded: first, in the inputs' order, those
        up to date (skipped) or failing the pre-flight, then as the files finish; before
        ``progress`` hears of that file. With worker processes and on a Dask cluster alike
        (its results are gathered as each task ends), in this process. So a caller can
        report a failed row (``status == "failed"``, ``message`` the error) while the others
        are still being filled. Not called for the files whose results arrive while an
        interrupted run is being stopped (they are in the summary); an exception it raises
        stops the files in flight, as an interrupt does, and propagates.
    **fill_options
        Passed to :func:`surfinpaint.fill_holes` for every file: ``method``, ``options``
        (a :class:`~surfinpaint.ConformalOptions`), ``fair_order``, ``include_border``,
        ``keep_margins``, ``max_hole_edges``, ``repair``; checked before any file is read.

    Returns
    -------
    FileRows
        A :class:`FileRow` per input file in the inputs' order, also written to the summary
        (``.unknown``: the files of unknown type not filled; ``.earlier``: how many rows of
        earlier runs the summary keeps beside them). On ``KeyboardInterrupt`` (or
        the command line's SIGTERM) the files in flight are stopped, leaving no partial
        output (local workers are ended; a Dask cluster's tasks are cancelled, and one
        already running there may still write its output, whole), the summary of the files
        done is written (the others keep their rows of the earlier summary), and the
        interrupt propagates; a rerun fills the rest, the files that were in flight
        included. Likewise while the files are listed and checked, before any is filled
        (:func:`~surfinpaint.app.batch_listing.list_jobs`); the interrupt's
        ``while_listing`` attribute is then True.

    Raises
    ------
    ValueError
        Bad options or inputs (no mesh file, two inputs onto one output, ...).
    """
    # bad arguments are the caller's error, found before any file is read
    n_jobs = _local_workers(jobs, client)
    _check_options(fill_options)
    # the local workers start, and load the kernels, while the inputs are listed and checked
    launched = _early_pool(n_jobs, client, progress is not None, fill_options)
    todo, pending, rows = _listed(launched, inputs, out_dir, overwrite, progress, png,
                                  overlays, on_result, fill_options)
    # the files filled: the summary is written in any case, an interrupted run's too
    _fill_and_summarise(todo, pending, rows, fill_options, n_jobs, client, launched)
    return rows.ordered(todo)


def _early_pool(n_jobs: int, client: Any, progress: bool,
                fill_options: Mapping[str, Any]) -> _Launched | None:
    """The local workers of :func:`fill_files`, started before the inputs are listed (so
    that they load the kernels meanwhile: :func:`_launch`); None with a Dask ``client``
    or with one job (the files are then filled in this process)."""
    if client is None and n_jobs > 1:
        return _launch(n_jobs, progress, _method(fill_options))
    return None


def _fill_and_summarise(todo: Inputs, pending: Sequence[FileJob], rows: RunRows,
                        fill_options: Mapping[str, Any], n_jobs: int, client: Any,
                        launched: _Launched | None) -> None:
    """Fill the ``pending`` files of ``todo`` (on the Dask cluster of ``client``, else here:
    :func:`_run_local`) and write the summary of the output folder (``todo``'s rows, and
    the earlier summary's of the other files: :meth:`RunRows.write_summary`), also when the
    run is interrupted; the temporary files a stopped fill left are removed."""
    try:
        if client is not None:
            _run_dask(pending, fill_options, client, rows)
        else:
            _run_local(pending, fill_options, n_jobs, rows, launched)
    finally:
        if client is None:  # no local worker is left writing: what a killed one left can go
            remove_temporaries(pending)
        rows.write_summary(todo, fill_options)
    if client is not None:  # every task ended (an interrupted one may still be writing)
        remove_temporaries(pending)
