"""Holes filled in worker processes (fill/parallel.py): the same result as one after
another, bit for bit, with the holes that depend on earlier ones filled after them."""

from __future__ import annotations

import multiprocessing
import os
import re
import signal
import subprocess
import sys
import threading
import time
import warnings
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.errors import FillError, MeshError
from surfinpaint.fill import parallel, scheduler
from surfinpaint.fill.conformal import ConformalOptions
from surfinpaint.fill.hole_steps import Run
from surfinpaint.fill.holes import find_holes
from surfinpaint.fill.neighbourhood import FilledMesh
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.io.formats import read_mesh, write_mesh
from surfinpaint.representation import blas_threads

# ``holed`` (conftest.py): six holes on a sphere, the sixth dependent on the fifth


@pytest.fixture
def always_parallel(monkeypatch):
    """Workers even for these small holes (the size rule keeps them serial otherwise)."""
    monkeypatch.setattr(parallel, "MIN_PARALLEL_EDGES", {"fair": 0, "conformal": 0})


@pytest.fixture
def forked(monkeypatch):
    """Forked workers (what a one-thread process gets), which inherit this test's patches."""
    monkeypatch.setattr(parallel, "MIN_PARALLEL_EDGES", {"fair": 0, "conformal": 0})
    context = multiprocessing.get_context("fork")
    monkeypatch.setattr(parallel, "pool", lambda workers: ProcessPoolExecutor(
        workers, mp_context=context))


@pytest.fixture(scope="module")
def filled(holed):
    """method -> (the serial fill, the fill on 2 workers)."""
    vertices, faces, _ = holed
    runs = {}
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(parallel, "MIN_PARALLEL_EDGES", {"fair": 0, "conformal": 0})
        for method in ("fair", "conformal"):
            runs[method] = tuple(fill_holes(vertices, faces, method=method, jobs=jobs)
                                 for jobs in (1, 2))
    return runs


def _independent(vertices, faces, loops, method):
    mesh = FilledMesh(vertices, faces)
    run = Run(method, ConformalOptions(), None, False, len(loops), None, None)
    reach = [mesh.cut(loop, run.rings_for(len(loop))).ids for loop in loops]
    return parallel.independent(reach, loops)


def _summary(result):
    return [(r.method, r.new_vertices, r.new_faces, r.fallback, r.skipped, r.fair_order)
            for r in result.reports]


@pytest.mark.parametrize("method", ["fair", "conformal"])
def test_two_jobs_bit_identical_to_one(filled, method):
    serial, both = filled[method]
    assert len(serial.reports) == 6
    assert all(r.new_faces > 0 for r in serial.reports)
    assert np.array_equal(serial.vertices, both.vertices)
    assert np.array_equal(serial.faces, both.faces)
    assert _summary(serial) == _summary(both)


def test_forkserver_workers_bit_identical(holed, filled, always_parallel, monkeypatch):
    """Where this process runs threads, the workers come from a forkserver (no fork of the
    threads): the same result."""
    vertices, faces, _ = holed
    monkeypatch.setattr(parallel.threading, "active_count", lambda: 2)
    served = fill_holes(vertices, faces, method="fair", jobs=2)
    assert np.array_equal(served.vertices, filled["fair"][0].vertices)
    assert np.array_equal(served.faces, filled["fair"][0].faces)


def test_dependent_hole_found(holed):
    """The sixth hole's conformal neighbourhood reaches the fifth's loop; the faired
    fill's 3 rings reach no other loop."""
    vertices, faces, loops = holed
    assert _independent(vertices, faces, loops, "conformal") == {0, 1, 2, 3, 4}
    assert _independent(vertices, faces, loops, "fair") == set(range(6))


def test_dependent_hole_sees_the_earlier_fill(holed, filled):
    """Filled from the original mesh (the fifth hole open), the sixth hole's fill differs:
    the parallel run matching the serial one shows it was filled after the fifth."""
    vertices, faces, loops = holed
    serial, both = filled["conformal"]
    alone = fill_holes(vertices, faces, holes=[loops[5]], method="conformal", jobs=1)
    last = serial.vertices[len(serial.vertices) - serial.reports[5].new_vertices:]
    assert not np.array_equal(last, alone.vertices[len(vertices):])
    assert np.array_equal(serial.vertices, both.vertices)
    assert np.array_equal(serial.faces, both.faces)


def test_independent_rule():
    """A hole is independent when its reach holds no vertex of an earlier hole's loop (a
    later loop does not count)."""
    loops = [np.array([0, 1, 2]), np.array([10, 11, 12]), np.array([20, 21, 22])]
    reaches = [np.array([0, 1, 2, 3, 10]), np.array([10, 11, 12, 13]),
               np.array([12, 20, 21, 22])]
    assert parallel.independent(reaches, loops) == {0, 1}
    # an added vertex (id past the original ones) in a reach is ignored
    assert parallel.independent([np.array([0, 1, 2, 40])], loops[:1]) == {0}


def test_warnings_and_progress_in_hole_order(holed, forked, monkeypatch):
    """A warning raised while a hole is filled (in a worker) is issued here, in hole order;
    progress is called per hole, in hole order."""
    vertices, faces, _ = holed
    fill_local = parallel.fill_local

    def warning_fill(local_vertices, local_faces, loop, *args):
        warnings.warn(f"hole at {np.round(local_vertices[loop].mean(axis=0), 2)}",
                      UserWarning, stacklevel=1)
        return fill_local(local_vertices, local_faces, loop, *args)

    monkeypatch.setattr(parallel, "fill_local", warning_fill)  # forked workers inherit it
    calls = {1: [], 2: []}
    caught = {}
    for jobs in (1, 2):
        with warnings.catch_warnings(record=True) as caught[jobs]:
            warnings.simplefilter("always")
            fill_holes(vertices, faces, method="fair", jobs=jobs,
                       progress=lambda done, total, msg, j=jobs: calls[j].append((done, msg)))
    assert [c[0] for c in calls[2]] == [0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6]
    untimed = {j: [re.sub(r"[0-9.]+ s$", "", c[1]) for c in calls[j]] for j in (1, 2)}
    assert untimed[1] == untimed[2]
    messages = {j: [str(w.message) for w in caught[j] if "hole at" in str(w.message)]
                for j in (1, 2)}
    assert len(messages[1]) == 6 and len(set(messages[1])) > 1
    assert messages[1] == messages[2]


def test_one_blas_controller_made_before_the_workers_fork(holed, filled, forked, monkeypatch,
                                                          tmp_path):
    """The BLAS thread-pool controller (making one lists the loaded libraries) is made once,
    here, before the workers fork: they inherit it for their one-thread limit and their λ-H
    solves, and make none (on main each worker made two and this process one more per
    call). The same fill as one after another."""
    made = tmp_path / "made"
    controller = blas_threads.ThreadpoolController

    def counted(*args, **kwargs):
        with made.open("a") as out:
            out.write(f"{os.getpid()}\n")
        return controller(*args, **kwargs)

    monkeypatch.setattr(blas_threads, "_CONTROLLER", [])  # none made yet in this process
    monkeypatch.setattr(blas_threads, "ThreadpoolController", counted)
    vertices, faces, _ = holed
    both = fill_holes(vertices, faces, method="conformal", jobs=2)
    assert made.read_text().split() == [str(os.getpid())]
    assert sum(r.outcome == "lambda-h" for r in both.reports) > 0  # λ-H solves ran
    assert np.array_equal(both.vertices, filled["conformal"][0].vertices)
    assert np.array_equal(both.faces, filled["conformal"][0].faces)


def test_worker_error_raised_as_serial(holed, forked, monkeypatch):
    vertices, faces, _ = holed

    def failing_fill(*args):
        raise MeshError("the neighbourhood is broken", vertices=[7])

    monkeypatch.setattr(parallel, "fill_local", failing_fill)
    for jobs in (1, 2):
        with pytest.raises(MeshError, match="the neighbourhood is broken") as info:
            fill_holes(vertices, faces, method="fair", jobs=jobs)
        assert info.value.vertices == [7]


def test_worker_reissues_warnings():
    records = [("first", UserWarning, __file__, 1), ("second", RuntimeWarning, __file__, 2)]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        parallel.reissue(records)
    assert [(str(w.message), w.category) for w in caught] == [
        ("first", UserWarning), ("second", RuntimeWarning)]


@pytest.mark.parametrize("jobs", [0, -1, 1.5, True, "2"])
def test_bad_jobs(holed, jobs):
    vertices, faces, _ = holed
    with pytest.raises(ValueError, match="jobs"):
        fill_holes(vertices, faces, method="fair", jobs=jobs)


def test_few_or_small_holes_stay_serial():
    assert not parallel.worth_parallel([100, 100], 2, "conformal")  # two holes
    assert not parallel.worth_parallel([10, 10, 10, 10], 2, "conformal")  # tiny holes
    assert not parallel.worth_parallel([100, 100, 100], 1, "conformal")  # one worker
    assert parallel.worth_parallel([60, 60, 60], 2, "conformal")
    # a faired fill is ~15x cheaper: ten 60-edge holes stay here
    assert not parallel.worth_parallel([60] * 10, 2, "fair")
    assert parallel.worth_parallel([100] * 40, 2, "fair")


def test_resolve_jobs():
    assert parallel.resolve_jobs(None) >= 1
    assert parallel.resolve_jobs(3) == 3


def test_cli_jobs(tmp_path, holed):
    vertices, faces, _ = holed
    path = tmp_path / "holed.ply"
    write_mesh(path, vertices, faces)
    outs = []
    for jobs in ("1", "2"):
        out = tmp_path / f"out{jobs}.ply"
        assert main(["fill", str(path), "-o", str(out), "--method", "fair", "--jobs", jobs,
                     "-q"]) == 0
        outs.append(read_mesh(out))
    assert np.array_equal(outs[0][0], outs[1][0]) and np.array_equal(outs[0][1], outs[1][1])
    assert len(outs[0][1]) > len(faces)
    assert main(["fill", str(path), "-o", str(tmp_path / "x.ply"), "--jobs", "0", "-q"]) == 2


def test_the_fill_command_with_its_progress_bar_adds_no_thread(tmp_path, holed, monkeypatch,
                                                              capsys):
    # the holes' workers are forked only from a process of one thread (else a forkserver
    # starts them, and each imports and loads everything again): the bar must not add one
    vertices, faces, _ = holed
    path = tmp_path / "holed.ply"
    write_mesh(path, vertices, faces)
    before = threading.active_count()  # pytest-xdist's own threads, if any
    seen = []
    forks = parallel.forks

    def counted():
        seen.append(threading.active_count())
        return forks()

    monkeypatch.setattr(parallel, "forks", counted)
    monkeypatch.setattr(parallel, "MIN_PARALLEL_EDGES", {"fair": 0, "conformal": 0})
    assert main(["fill", str(path), "-o", str(tmp_path / "out.ply"), "--method", "fair",
                 "--jobs", "2"]) == 0
    assert "6 holes found" in capsys.readouterr().err
    assert seen and set(seen) == {before}


# ------------------------------------------------------- where the work runs, in what order

# eight holes, six of them in a cluster around the north pole: conformal neighbourhoods
# reach each other's loops, and with 9 rings so do the faired fill's
CLUSTER = [(1, 0, 0), (0, 0, 1), (0.45, 0.0, 0.9), (0.0, 0.45, 0.9), (-0.45, 0, 0.9),
           (0, -0.45, 0.9), (0, 0, -1), (0.9, 0, 0.45)]
CLUSTER_RUNS = {"conformal": {}, "fair": {"neighbourhood_rings": 9}}


@pytest.fixture(scope="module")
def clustered():
    vertices, faces = sphere(4)
    cut = cut_holes(vertices, faces, [np.array(c) / np.linalg.norm(c) for c in CLUSTER], 0.18)
    return cut.vertices, cut.faces


@pytest.fixture(scope="module")
def clustered_serial(clustered):
    """(method, holes) -> the serial fill of the cluster."""
    return {}


def _forked_pool(monkeypatch, inherit: bool):
    monkeypatch.setattr(parallel, "MIN_PARALLEL_EDGES", {"fair": 0, "conformal": 0})
    context = multiprocessing.get_context("fork")
    monkeypatch.setattr(parallel, "pool", lambda workers: ProcessPoolExecutor(
        workers, mp_context=context))
    monkeypatch.setattr(parallel, "forks", lambda: inherit)


@pytest.mark.parametrize("method", ["conformal", "fair"])
@pytest.mark.parametrize("holes", [None, (1, 3, 0, 5, 2, 7, 4, 6)])
@pytest.mark.parametrize("inherit", [True, False], ids=["workers-cut", "parent-cuts"])
def test_clustered_holes_in_any_order_bit_identical(clustered, clustered_serial, monkeypatch,
                                                    method, holes, inherit):
    """Holes whose neighbourhoods reach each other, filled in the serial order given
    (find_holes', shuffled): the workers cutting the holes from the mesh they
    inherited, or this process cutting each from the mesh as filled so far (forkserver,
    spawn) give the serial run's bytes and reports."""
    vertices, faces = clustered
    key = (method, holes)
    if key not in clustered_serial:
        clustered_serial[key] = fill_holes(vertices, faces, holes=holes, method=method,
                                           jobs=1, **CLUSTER_RUNS[method])
    serial = clustered_serial[key]
    _forked_pool(monkeypatch, inherit)
    both = fill_holes(vertices, faces, holes=holes, method=method, jobs=2,
                      **CLUSTER_RUNS[method])
    assert all(r.new_faces > 0 for r in serial.reports)
    assert np.array_equal(serial.vertices, both.vertices)
    assert np.array_equal(serial.faces, both.faces)
    assert _summary(serial) == _summary(both)
    assert [r.index for r in both.reports] == [r.index for r in serial.reports]


def test_the_cluster_has_a_cut_that_reaches_further_through_a_fill(clustered):
    """The case the parallel loop must wait on twice: hole 2's faired cut (9 rings) in the
    original mesh reaches hole 0's loop only; once hole 0 is filled, it reaches hole 1's
    loop too (through hole 0's fill), so it waits for hole 1 as well."""
    vertices, faces = clustered
    loops = [h.loop for h in find_holes(vertices, faces)]
    original = FilledMesh(vertices, faces).cut(loops[2], 9).ids
    assert [k for k in (0, 1) if np.isin(loops[k], original).any()] == [0]
    first = fill_holes(vertices, faces, holes=[0], method="fair", jobs=1)
    after = FilledMesh(first.vertices, first.faces).cut(loops[2], 9).ids
    assert [k for k in (0, 1) if np.isin(loops[k], after).any()] == [0, 1]


def test_forked_workers_cut_and_fill_every_hole_but_dependent_ones_cut_here(
        holed, filled, monkeypatch):
    """With forked workers this process cuts only the dependent hole (from the mesh as
    filled so far) and fills none: the workers cut, check and fill the others themselves;
    the result is the serial one."""
    vertices, faces, _ = holed
    loops = [h.loop for h in find_holes(vertices, faces)]  # in the order they are filled
    dependent = set(range(len(loops))) - _independent(vertices, faces, loops, "conformal")
    assert dependent == {3, 4}
    _forked_pool(monkeypatch, True)
    parent = os.getpid()
    calls = {"cut": set(), "fill": 0}
    cut, fill_local = FilledMesh.cut, parallel.fill_local

    def counted_cut(self, loop, *args):
        if os.getpid() == parent:
            calls["cut"].update(k for k, other in enumerate(loops)
                                if np.array_equal(loop, other))
        return cut(self, loop, *args)

    def counted_fill(*args):
        calls["fill"] += os.getpid() == parent
        return fill_local(*args)

    monkeypatch.setattr(FilledMesh, "cut", counted_cut)
    monkeypatch.setattr(parallel, "fill_local", counted_fill)
    both = fill_holes(vertices, faces, method="conformal", jobs=2)
    assert calls == {"cut": dependent, "fill": 0}
    assert np.array_equal(both.vertices, filled["conformal"][0].vertices)
    assert np.array_equal(both.faces, filled["conformal"][0].faces)


def test_workers_without_the_mesh_fall_back_to_cuts_made_here(holed, filled, monkeypatch):
    """A worker that did not inherit the mesh (told it would, but started by a forkserver)
    answers so, and the hole is cut here instead: the same result."""
    vertices, faces, _ = holed
    monkeypatch.setattr(parallel, "MIN_PARALLEL_EDGES", {"fair": 0, "conformal": 0})
    monkeypatch.setattr(parallel, "forks", lambda: True)
    context = multiprocessing.get_context("forkserver")
    monkeypatch.setattr(parallel, "pool", lambda workers: ProcessPoolExecutor(
        workers, mp_context=context))
    served = fill_holes(vertices, faces, method="fair", jobs=2)
    assert np.array_equal(served.vertices, filled["fair"][0].vertices)
    assert np.array_equal(served.faces, filled["fair"][0].faces)


@pytest.mark.parametrize("jobs", [1, 2])
def test_hole_warnings_point_at_the_caller(holed, forked, monkeypatch, jobs):
    """A hole's warning (here: its fill failed) names the line that called fill_holes,
    in the serial loop and in the parallel one."""
    vertices, faces, _ = holed

    def failing_fill(*args):
        raise FillError("no fill today")

    monkeypatch.setattr(parallel, "fill_local", failing_fill)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fill_holes(vertices, faces, method="fair", jobs=jobs)
    failed = [w for w in caught if "the fill failed: no fill today" in str(w.message)]
    assert len(failed) == 6
    assert {w.filename for w in failed} == {__file__}


def test_reached_loops():
    ids = np.array([2, 5, 9, 40])
    loops = [np.array([0, 1]), np.array([1, 5]), np.array([41, 42]), np.array([40])]
    assert scheduler.reached(ids, loops).tolist() == [1, 3]
    assert scheduler.reached(ids, []).tolist() == []
    assert scheduler.reached(np.array([], dtype=np.int64), loops).tolist() == []


@pytest.mark.parametrize("total", [None, 3])
def test_no_progress_bar_runs_a_thread_of_its_own(total, capsys):
    # every command's bar (fill, batch, report, experiments, demo): a second thread would make
    # the fills' workers come from a forkserver, each importing and loading everything again
    from surfinpaint.app.progress import progress_bar

    before = threading.active_count()
    with progress_bar(True, total, "filling") as bar:
        assert threading.active_count() == before
        bar("hole 1")
        bar.update(2, 3, "hole 2")
        assert threading.active_count() == before
    assert "hole 2" in capsys.readouterr().err


def test_a_bar_whose_total_is_not_known_yet_says_so(capsys):
    # the fill command's bar is drawn before the mesh is read: "0/?", not "0/None"
    from surfinpaint.app.progress import progress_bar

    with progress_bar(True, None, "filling"):
        pass
    err = capsys.readouterr().err
    assert "0/?" in err and "None" not in err
    with progress_bar(True, None, "filling") as bar:
        bar.update(2, 5, "hole 2")
    assert "2/5" in capsys.readouterr().err


_KILLED_PARENT = """
import os, sys, time
from surfinpaint.fill import parallel
with parallel.pool(2) as workers:
    pids = set()
    while len(pids) < 2:  # until both workers have run a task
        pids |= {f.result() for f in [workers.submit(os.getpid) for _ in range(4)]}
    print(*pids, flush=True)
    time.sleep(120)
"""


def _gone(pid: int) -> bool:
    """No such process, or a zombie (nobody reaps orphans in some containers)."""
    try:
        with open(f"/proc/{pid}/status") as status:
            return any(line.split()[:2] == ["State:", "Z"] for line in status)
    except FileNotFoundError:
        return True


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="reads /proc")
def test_workers_end_when_their_parent_is_killed():
    # session 46's fuzz campaign: `fill` killed with SIGKILL left its two forked workers
    # waiting for ever on a task queue whose write end they hold themselves
    proc = subprocess.Popen([sys.executable, "-c", _KILLED_PARENT], stdout=subprocess.PIPE,
                            text=True)
    pids = [int(p) for p in proc.stdout.readline().split()]
    assert len(pids) == 2 and proc.pid not in pids
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    deadline = time.monotonic() + 30  # they look every PARENT_CHECK_EVERY (1 s)
    while not all(_gone(p) for p in pids) and time.monotonic() < deadline:
        time.sleep(0.1)
    left = [p for p in pids if not _gone(p)]
    for p in left:
        os.kill(p, signal.SIGKILL)
    assert left == []


_INTERRUPTED_PARENT = """
import os, signal, sys, time
import numpy as np
from surfinpaint import fill_holes
from surfinpaint.app.interrupts import Interrupted, signals_raise
from surfinpaint.data import sphere
from surfinpaint.fill import parallel, scheduler
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length

def fill_cut_here(token, position):
    # a hole that takes for ever (a long λ-H fill); the first to start signals the parent,
    # which is then waiting for its workers
    os.kill(os.getppid(), int(sys.argv[1]))
    time.sleep(3600)

scheduler.fill_cut_here = fill_cut_here  # the forked workers find it in __main__
parallel.MIN_PARALLEL_EDGES = {"conformal": 0, "fair": 0}
v, f = sphere(3)
cut = cut_holes(v, f, [0, 1, 2, 3], [2.5 * mean_edge_length(v, f)] * 4)
try:
    with signals_raise():
        fill_holes(cut.vertices, cut.faces, jobs=2)
except Interrupted:
    print("interrupted", flush=True)
import multiprocessing
print(len(multiprocessing.active_children()), flush=True)
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"),
                    reason="the workers find the stuck fill by forking")
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_an_interrupted_parallel_fill_ends_its_workers_at_once(signum):
    # session 47: `fill` stopped by SIGTERM waited for its workers' holes in flight (the
    # pool's shutdown) and exited 15-70 s later; a scheduler's SIGKILL comes sooner
    # the holes take an hour
    out = _script_output(120, "the interrupted fill waited for its workers' holes",
                         _INTERRUPTED_PARENT, str(int(signum)))
    assert out.split() == ["interrupted", "0"]


def _children(pid: int) -> list[int]:
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as children:
            return [int(c) for c in children.read().split()]
    except FileNotFoundError:
        return []


def _script_output(timeout: float, hung: str, script: str, *args: str) -> str:
    """The standard output of ``python -c script args``, which must exit 0 within
    ``timeout`` seconds; else it and its children are killed and the test fails, saying
    ``hung``."""
    proc = subprocess.Popen([sys.executable, "-c", script, *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        for child in _children(proc.pid):
            os.kill(child, signal.SIGKILL)
        proc.kill()
        proc.communicate()
        pytest.fail(hung)
    assert proc.returncode == 0, err
    return out


_HALF_SENT = """
import multiprocessing, os, struct, sys, time
from concurrent.futures import ProcessPoolExecutor
from surfinpaint.fill.parallel import end_workers

marker = sys.argv[1]

def send_half():
    # what a worker killed in the middle of sending its result leaves: a message's length
    # and part of it, in the pipe the pool's reading thread reads whole messages from
    os.write(WRITER.fileno(), struct.pack("!i", 1000) + b"x" * 10)
    open(marker, "w").close()
    time.sleep(3600)

pool = ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("fork"))
WRITER = pool._result_queue._writer  # the worker forks at the first submit and inherits it
pool.submit(send_half)
while not os.path.exists(marker):
    time.sleep(0.01)
time.sleep(0.2)  # the reading thread has read the length and waits for the rest
end_workers(pool)
print("ended", flush=True)
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="forks the worker")
def test_ending_workers_killed_while_sending_a_result_returns(tmp_path):
    # session 50: CI's SIGTERM test hung in the pool's shutdown (1 of 58 SIGTERMs here): a
    # worker killed mid-send left half a message, and the pool's reading thread waited for
    # the rest from a pipe whose write end this process still held
    out = _script_output(60, "ending the workers waited for the rest of a message never sent",
                         _HALF_SENT, str(tmp_path / "sent"))
    assert out.split() == ["ended"]


_DIED_HALF_SENT = """
import multiprocessing, os, struct, time
from concurrent.futures import ProcessPoolExecutor, wait
from surfinpaint.fill import parallel

parallel.STUCK_AFTER = 0.5

def die_half_sent():
    # the OOM killer's worker, ended while it sent its result
    os.write(WRITER.fileno(), struct.pack("!i", 1000) + b"x" * 10)
    os._exit(9)

def sleep():
    time.sleep(3600)

pool = ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("fork"))
WRITER = pool._result_queue._writer  # the workers fork at the first submit and inherit it
# the other worker lives on (holding the pipe's write end): the pool's reading thread
# waits for the rest of the message for ever, and the pool never finds the dead worker
futures = [pool.submit(sleep), pool.submit(die_half_sent)]
parallel.wait_first(pool, futures)
wait(futures, timeout=30)
print(*sorted(type(f.exception()).__name__ for f in futures if f.done()), flush=True)
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="forks the workers")
def test_a_worker_dead_while_sending_a_result_fails_the_futures_instead_of_hanging():
    # session 50: what end_workers fixes for an interrupt can also come from a worker the OOM
    # killer ends mid-send; `fill --jobs` and `batch` waited for ever on its future
    out = _script_output(60, "the futures of a pool stuck on a half-sent result were waited "
                         "for for ever", _DIED_HALF_SENT)
    assert out.split() == ["BrokenProcessPool", "BrokenProcessPool"]
