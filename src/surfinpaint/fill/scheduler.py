"""Holes filled in worker processes, bit-identical to the serial loop.

The rule (:mod:`surfinpaint.fill.parallel`): hole ``p``'s cut of the mesh as filled so far
is the cut the serial loop makes when it holds no vertex of the loop of an earlier hole not
yet stitched in (the faces a fill adds touch the rest of the mesh only at its loop). So a
hole's cut can be made at any time, from any prefix of stitched holes, and checked: once it
reaches no earlier unstitched loop it is final, and the hole can be filled anywhere.

How the work is shared:

- Forked workers inherit the original mesh: each cuts its hole itself, checks its loop and
  fills it, and returns the fill with the cut's vertex ids (no neighbourhood is pickled,
  the parent makes no cut for it). A cut that reaches an earlier hole's loop comes back
  as *dependent* on the holes before the last one it reaches.
- A dependent hole is cut here as soon as those holes are stitched, from the mesh as
  filled so far; if that cut reaches a later unstitched loop (through a fill it took in) it
  waits for that one too. Its final cut is checked here and sent to the first free worker,
  ahead of the holes not yet started. Where workers do not inherit the mesh (forkserver,
  spawn) every hole is cut here that way, just before a worker is free for it.
- Holes start longest first (boundary edges; the serial order among equal lengths); at most
  one more than the workers are in flight, so a released dependent hole waits for at most
  one.
- Here, the fills are stitched in the serial order, each as soon as it and those before it
  are in: vertex numbering, reports, warnings (a worker's are recorded and issued again
  here), progress and errors (a worker's is raised at its hole) are those of the serial run.
  Where someone listens, a worker (forked or not: it gets the queue as it starts,
  :func:`~surfinpaint.fill.parallel.pool_telling`) also tells the stages of its hole's
  conformal fill as they start, and they are said here as they come (the holes stitched the
  count), the last one again every :data:`SAY_AGAIN_SECONDS` without news (a bar's clock
  goes on).
"""

from __future__ import annotations

import functools
import itertools
import time
import warnings
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import dataclass, field

import numpy as np

from surfinpaint.errors import MeshError
from surfinpaint.fill import parallel
from surfinpaint.fill.conformal import ConformalOptions
from surfinpaint.fill.hole_steps import (
    Run,
    around_zero_area,
    at_hole,
    loop_problem,
    stitched,
    with_failure,
)
from surfinpaint.fill.neighbourhood import FilledMesh, Local, zero_area_reason
from surfinpaint.fill.results import Fill, HoleReport
from surfinpaint.lazy import lazy_module

# imported at the first parallel fill (threadpoolctl: 9-17 ms of every process's start
# otherwise; the conformal method's modules import it too, on the thread that loads the kernels)
blas_threads = lazy_module("surfinpaint.representation.blas_threads")

__all__ = ["Outcome", "fill_cut_here", "fill_in_parallel", "fill_sent", "reached"]

#: Seconds without news from the workers after which the last stage is said again (the
#: same message: a bar's clock goes on; a display's cadence, not a fill rule)
SAY_AGAIN_SECONDS = 1.0
#: Seconds between looks for the workers' news while the parent waits for their answers
NEWS_SECONDS = 0.1


@dataclass(frozen=True)
class _Job:
    """What forked workers cut their holes from: the original mesh and the holes."""

    mesh: FilledMesh
    loops: list[np.ndarray]
    indices: list[int]
    rings: list[int]
    run: Run


# the jobs of the calls running in this process, by token; a forked worker finds its own
_INHERITED: dict[int, _Job] = {}
_TOKENS = itertools.count()


@dataclass
class Outcome:
    """A worker's answer for one hole."""

    made: Fill | None = None
    failure: str | None = None  # why the fill raised (a numerical failure)
    problem: str | None = None  # why the loop cannot be filled (no fill made)
    unstitchable: str | None = None  # why ``made`` cannot be stitched (zero_area_reason)
    ids: np.ndarray | None = None  # the global ids of the cut (made in the worker)
    records: list[parallel.WarningRecord] = field(default_factory=list)
    seconds: float = 0.0
    needs: int | None = None  # dependent: the holes before this position go first
    uninherited: bool = False  # the worker has not got the mesh: cut it in the parent


def reached(ids: np.ndarray, loops: list[np.ndarray]) -> np.ndarray:
    """The positions in ``loops`` of the loops with a vertex among ``ids`` (sorted)."""
    if not loops or not len(ids):
        return np.empty(0, dtype=np.int64)
    flat = np.concatenate(loops)
    owner = np.repeat(np.arange(len(loops)), [len(loop) for loop in loops])
    at = np.minimum(np.searchsorted(ids, flat), len(ids) - 1)
    return np.unique(owner[ids[at] == flat])


def _recorded(call, *args) -> tuple[object, list[parallel.WarningRecord]]:
    """``call(*args)`` with one BLAS thread (the parallelism is over holes), and the
    warnings it raised, for the parent to issue again in hole order. The thread-pool
    controller is the process's (:func:`~surfinpaint.representation.blas_threads.
    blas_controller`, the λ-H solves' too): a forked worker inherits the one the parent made
    before forking it."""
    with warnings.catch_warnings(record=True) as caught, \
            blas_threads.blas_controller().limit(limits=1):
        warnings.simplefilter("always")
        answer = call(*args)
    return answer, [(str(w.message), w.category, w.filename, w.lineno) for w in caught]


def _checked_fill(mesh: FilledMesh, local: Local, index: int, run: Run,
                  stage: Callable[[str], None] | None = None
                  ) -> tuple[Local, str | None, Fill | None, str | None]:
    local, hole_run, why = around_zero_area(mesh, local, run)
    problem = loop_problem(local, index, run.explicit)
    made, failure = (None, None) if problem else at_hole(index, hole_run.fill, local, stage)
    return local, problem, with_failure(made, why), failure


def _tell_stage(queue, position: int, name: str) -> None:
    """In a worker: tell the parent that hole ``position``'s fill starts stage ``name``
    (written at once, a ``SimpleQueue``: before the hole's answer, which the parent reads
    after)."""
    queue.put((position, name))


def _stage_teller(position: int) -> Callable[[str], None] | None:
    """In a worker: the ``stage`` callback of hole ``position``'s fill (None where nobody
    listens: the worker got no queue, :func:`~surfinpaint.fill.parallel.told_queue`)."""
    queue = parallel.told_queue()
    if queue is None:
        return None
    return functools.partial(_tell_stage, queue, position)


def fill_cut_here(token: int, position: int) -> Outcome:
    """In a forked worker: cut hole ``position`` from the original mesh it inherited, and
    check and fill it, unless the cut reaches an earlier hole's loop (then it is dependent)."""
    started = time.perf_counter()
    job = _INHERITED.get(token)
    if job is None:
        return Outcome(uninherited=True)
    local = job.mesh.cut(job.loops[position], job.rings[position])
    earlier = reached(local.ids, job.loops[:position])
    if len(earlier):
        return Outcome(needs=int(earlier.max()) + 1)
    (local, problem, made, failure), records = _recorded(
        _checked_fill, job.mesh, local, job.indices[position], job.run,
        _stage_teller(position))
    return Outcome(made, failure, problem,
                   None if made is None else zero_area_reason(local.vertices, made),
                   local.ids, records, time.perf_counter() - started)


def fill_sent(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, index: int,
              method: str, options: ConformalOptions, fair_order: int | None,
              position: int = 0) -> Outcome:
    """In a worker: fill hole ``index`` from the neighbourhood the parent cut and checked
    (local ids), telling its stages as hole ``position``'s where someone listens."""
    started = time.perf_counter()
    stage = _stage_teller(position)
    (made, failure), records = _recorded(at_hole, index, parallel.fill_or_failure, vertices,
                                         faces, loop, method, options, fair_order, stage)
    return Outcome(made, failure,
                   unstitchable=None if made is None else zero_area_reason(vertices, made),
                   records=records, seconds=time.perf_counter() - started)


class _StageNews:
    """The stages the workers tell through ``queue`` (:func:`_tell_stage`), said to the
    run's ``progress`` as they come, of the holes still in flight; the last one said again
    after :data:`SAY_AGAIN_SECONDS` without news, while its hole is in flight."""

    def __init__(self, queue, run: Run, todo: list[HoleReport],
                 clock: Callable[[], float] = time.monotonic) -> None:
        self.queue, self.run, self.todo, self.clock = queue, run, todo, clock
        self.last: tuple[int, str] | None = None
        self.said_at = 0.0

    def read(self, flying: set[int], stitched: int) -> None:
        """Say the news of the holes at ``flying`` positions; ``stitched`` holes done."""
        news = False
        while not self.queue.empty():  # this process the one reader: a message is there
            p, name = self.queue.get()
            if p in flying:  # read before the answers are filed: only a dependent's is not
                self.last, news = (p, name), True
                self._say(stitched)
        if self.last is not None and self.last[0] not in flying:
            self.last = None
        if not news and self.last and self.clock() - self.said_at >= SAY_AGAIN_SECONDS:
            self._say(stitched)

    def _say(self, stitched: int) -> None:
        p, name = self.last
        counted = self.todo[min(stitched, len(self.todo) - 1)]
        self.run.stages_of(self.todo[p], counted)(name)
        self.said_at = self.clock()


class _Schedule:
    """The state of one parallel fill: which holes are where."""

    def __init__(self, mesh: FilledMesh, todo: list[HoleReport], run: Run, workers: int,
                 token: int | None, news: _StageNews | None = None) -> None:
        self.mesh, self.todo, self.run, self.token = mesh, todo, run, token
        self.news = news
        self.loops = [r.loop for r in todo]
        self.slots = workers + 1
        # longest first (a stable sort: the serial order among equal lengths)
        self.unstarted = sorted(range(len(todo)), key=lambda p: -todo[p].n_edges)
        self.released: list[int] = []  # cut here, checked: to send first
        self.cuts: dict[int, Local] = {}  # the holes cut here
        # the run of each hole cut here, and why it is not the call's (around_zero_area)
        self.runs: dict[int, Run] = {}
        self.fallbacks: dict[int, str | None] = {}
        self.waiting: dict[int, int] = {}  # dependent hole -> holes to stitch before it
        self.outcomes: dict[int, Outcome | BaseException] = {}
        self.flying: dict[Future, int] = {}
        self.stitched = 0  # the holes before this position are stitched in

    def cut_here(self, p: int) -> None:
        """Cut hole ``p`` from the mesh as filled so far: final when it reaches no earlier
        unstitched loop (then checked, and released to a worker), else it waits."""
        report = self.todo[p]
        local = self.mesh.cut(report.loop, self.run.rings_of(report))
        unstitched = reached(local.ids, self.loops[self.stitched:p])
        if len(unstitched):
            self.waiting[p] = self.stitched + int(unstitched.max()) + 1
            return
        local, self.runs[p], self.fallbacks[p] = around_zero_area(self.mesh, local, self.run)
        self.cuts[p] = local
        try:
            problem = loop_problem(local, report.index, self.run.explicit)
        except MeshError as exc:  # raised when its turn comes, as the serial loop would
            self.outcomes[p] = exc
            return
        if problem is not None:
            self.outcomes[p] = Outcome(problem=problem, seconds=0.0)
        else:
            self.released.append(p)

    def release(self) -> None:
        """Cut the dependent holes whose earlier holes are now stitched."""
        for p in sorted(p for p, needs in self.waiting.items() if needs <= self.stitched):
            del self.waiting[p]
            self.cut_here(p)

    def top_up(self, executor) -> None:
        """Keep the workers fed: released holes first, then the unstarted longest first."""
        while len(self.flying) < self.slots and (self.released or self.unstarted):
            if self.released:
                p = self.released.pop(0)
                local, run = self.cuts[p], self.runs[p]
                future = executor.submit(fill_sent, local.vertices, local.faces,
                                         local.local_loop, self.todo[p].index, run.method,
                                         run.options, run.fair_order, p)
            elif self.token is not None:
                p = self.unstarted.pop(0)
                future = executor.submit(fill_cut_here, self.token, p)
            else:
                self.cut_here(self.unstarted.pop(0))
                continue
            self.flying[future] = p

    def collect(self, executor) -> None:
        """Wait for a worker's answer (from ``executor``'s workers) and file it."""
        if not self.flying:
            raise RuntimeError(f"hole {self.todo[self.stitched].index}: nothing to wait for")
        done = None
        while not done:
            done, _ = parallel.wait_first(executor, self.flying,
                                          None if self.news is None else NEWS_SECONDS)
            if self.news is not None:
                self.news.read(set(self.flying.values()), self.stitched)
        for future in done:
            p = self.flying.pop(future)
            try:
                outcome = future.result()
            except Exception as exc:  # raised when its turn comes, as the serial loop would
                self.outcomes[p] = exc
                continue
            if outcome.uninherited:
                self.cut_here(p)
            elif outcome.needs is not None:
                self.waiting[p] = outcome.needs
            else:
                self.outcomes[p] = outcome

    def stitch_next(self) -> None:
        """Stitch in the next hole in the serial order and report it."""
        p = self.stitched
        outcome, report = self.outcomes.pop(p), self.todo[p]
        if isinstance(outcome, BaseException):
            raise outcome
        parallel.reissue(outcome.records)
        ids = outcome.ids if outcome.ids is not None else self.cuts[p].ids
        made = with_failure(outcome.made, self.fallbacks.pop(p, None))
        stitched(self.mesh, report, ids, made, outcome.problem,
                 time.perf_counter() - outcome.seconds, outcome.failure, outcome.unstitchable)
        self.cuts.pop(p, None)
        self.runs.pop(p, None)
        self.stitched += 1
        self.run.finished(report)


def fill_in_parallel(mesh: FilledMesh, todo: list[HoleReport], run: Run, workers: int) -> None:
    """The holes of ``todo`` filled in ``workers`` processes and stitched into ``mesh`` in
    their order, bit-identical to one after another (see the module's docstring)."""
    token = next(_TOKENS) if parallel.forks() else None
    if token is not None:  # before the first submit: the workers fork then
        _INHERITED[token] = _Job(mesh, [r.loop for r in todo], [r.index for r in todo],
                                 [run.rings_of(r) for r in todo], run)
    # one BLAS thread here too: the cuts and checks made here share the cores with workers.
    # The process's controller (made with the conformal kernels, warmup.warm_kernels, else
    # here), made before the workers fork, is the one they use: once a process, not once a
    # call here and twice a worker (its own and the λ-H solves'; making one lists the loaded
    # libraries: 15-23 ms in the 651k command, 2-6 ms in a worker; docs/scale.md, session 41)
    blas = blas_threads.blas_controller().limit(limits=1)
    news = None
    if run.tells_stages:  # the queue made with the workers, forked or not
        executor, queue = parallel.pool_telling(workers)
        news = _StageNews(queue, run, todo)
    else:
        executor = parallel.pool(workers)
    schedule = _Schedule(mesh, todo, run, workers, token, news)
    try:
        announced = 0  # progress: the holes whose start was announced
        while schedule.stitched < len(todo):
            schedule.release()
            schedule.top_up(executor)
            # said once the workers are started (with fork, all at the first submit): a
            # ticking bar's clock thread (app/progress.py) starts only where none runs
            if announced == schedule.stitched:
                run.starting(todo[announced])
                announced += 1
            if schedule.stitched in schedule.outcomes:
                schedule.stitch_next()
            else:
                schedule.collect(executor)
    except BaseException:  # Ctrl-C, SIGTERM, a hole's error: the holes in flight are moot
        parallel.end_workers(executor)
        raise
    finally:
        executor.shutdown(wait=True, cancel_futures=True)
        blas.restore_original_limits()
        _INHERITED.pop(token, None)
        if news is not None:
            news.queue.close()
