"""The progress bar's clock while a hole is filled in the process that draws it (``fill``,
``batch --jobs 1``, ``report``, ``experiments``): a thread draws the bar again every
``TICK_SECONDS`` while a stage runs, and runs only where no other thread does (session 48;
session 47 left the clock standing through a 6-s stage; session 50: report's and
experiments'). Each stage here is a fake one that waits for the clock's ticks: no test times
a fill."""

from __future__ import annotations

import threading

import pytest

from surfinpaint.app import batch_command, progress
from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.fill import parallel
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import boundary_loops
from surfinpaint.io import write_mesh

CLOCK = "surfinpaint-bar-clock"


def _clocks() -> list[threading.Thread]:
    return [t for t in threading.enumerate() if t.name == CLOCK]


@pytest.fixture(autouse=True)
def threads_of_this_test(monkeypatch):
    """``threading.active_count()`` counts the main thread and the threads this test starts,
    not those an earlier test left in this process for its life (a Dask client's
    ``Dask-Offload`` thread): the clock runs only where no other thread does, and whether
    pytest-xdist ran a Dask test in this process before is chance (session 50: these tests
    failed after ``test_batch.py``'s Dask test in one process). No test here forks."""
    left = [t for t in threading.enumerate() if t is not threading.main_thread()]
    count = threading.active_count
    monkeypatch.setattr(threading, "active_count",
                        lambda: count() - sum(t.is_alive() for t in left))


@pytest.fixture
def ticks(monkeypatch):
    """The bar's ticks, counted; a tick every 10 ms."""
    monkeypatch.setattr(progress, "TICK_SECONDS", 0.01)
    # stage_ticks: those that came while a slow stage waited (the clock of a log's test)
    counted = {"ticks": 0, "stage_ticks": 0, "in_stage": False,
               "event": threading.Condition()}
    tick = progress._Bar._tick

    def counting(self):
        tick(self)
        with counted["event"]:
            counted["ticks"] += 1
            counted["stage_ticks"] += counted["in_stage"]
            counted["event"].notify_all()

    monkeypatch.setattr(progress._Bar, "_tick", counting)
    return counted


def _wait_for_ticks(counted, n: int) -> int:
    """Wait (at most a minute) until ``n`` more ticks came; how many came."""
    with counted["event"]:
        start = counted["ticks"]
        counted["event"].wait_for(lambda: counted["ticks"] >= start + n, timeout=60)
        return counted["ticks"] - start


@pytest.fixture
def slow_stage(monkeypatch, ticks):
    """Each hole's fill says its λ-H stage, then waits for 10 of the bar's ticks (the GIL let
    go, as in a long solve), then fills the hole; the ticks seen during each stage."""
    fill_local = parallel.fill_local
    seen: list[int] = []

    def slow(vertices, faces, loop, method, options, fair_order, stage=None):
        if stage is not None:
            stage("λ-H fill")
            ticks["in_stage"] = True
            seen.append(_wait_for_ticks(ticks, 10))
            ticks["in_stage"] = False
        return fill_local(vertices, faces, loop, method, options, fair_order)

    monkeypatch.setattr(parallel, "fill_local", slow)
    return seen


def test_a_ticking_bar_draws_again_while_work_runs_and_stops_after(ticks):
    with progress.progress_bar(True, None, "filling", ticking=True) as bar:
        bar.update(0, 1, "hole 0: 212 edges, λ-H fill (stage 5 of 5)")
        assert _wait_for_ticks(ticks, 3) == 3  # this thread busy: the clock draws the bar
        assert len(_clocks()) == 1
        bar.update(1, 1, "hole 0: done in 3.1 s")  # nothing left to do: no more ticks
        assert not _clocks()
        bar.update(0, 2, "hole 1: 12 edges, conformal")
        assert len(_clocks()) == 1
    assert not _clocks()  # the bar's end stops it


def test_a_step_stops_the_clock_its_fills_news_started(ticks):
    # report's and experiments' bars (session 50): a fill's hole news run the clock as at
    # fill's; a step ends a stage, and the next one may start workers, which fork only
    # where no other thread runs
    with progress.progress_bar(True, 4, "filling", ticking=True) as bar:
        news = bar.holes("conformal fills")
        news(0, 3, "hole 0: 212 edges, λ-H fill (stage 5 of 5)")
        assert _wait_for_ticks(ticks, 3) == 3 and len(_clocks()) == 1
        bar("conformal fills done")
        assert not _clocks()
        news(3, 3, "hole 2: done in 3.1 s")  # no hole left: no clock
        assert not _clocks()
    with progress.progress_bar(False, 4, "filling", ticking=True) as bar:
        assert bar.holes("conformal fills") is None  # a fill told nothing: no stage news


def test_no_clock_beside_another_thread_nor_unasked(ticks):
    # another thread (a pool's, whose workers were forked from a process of one thread):
    # the clock does not start, so it never runs beside workers
    done = threading.Event()
    other = threading.Thread(target=done.wait)
    other.start()
    try:
        with progress.progress_bar(True, None, "filling", ticking=True) as bar:
            bar.update(0, 1, "hole 0: 212 edges, λ-H fill (stage 5 of 5)")
            assert not _clocks()
    finally:
        done.set()
        other.join()
    with progress.progress_bar(True, None, "filling") as bar:  # not a ticking bar
        bar.update(0, 1, "hole 0: 212 edges, λ-H fill (stage 5 of 5)")
        assert not _clocks()
    with pytest.raises(KeyError), progress.progress_bar(True, None, "x", ticking=True) as bar:
        bar.update(0, 1, "hole 0")
        raise KeyError("a run that fails")
    assert not _clocks()


@pytest.fixture(scope="module")
def one_hole(tmp_path_factory):
    """A sphere with one hole, as a file, and its hole's boundary edges."""
    path = tmp_path_factory.mktemp("clock") / "holed.ply"
    v, f = sphere(3)
    cut = cut_holes(v, f, [0], 0.5)
    write_mesh(path, cut.vertices, cut.faces)
    (loop,) = boundary_loops(cut.faces)
    return path, len(loop)


def test_fill_draws_its_bar_while_a_stage_runs(one_hole, slow_stage, tmp_path):
    assert main(["fill", str(one_hole[0]), "-o", str(tmp_path / "out.ply"), "--jobs", "1"]) == 0
    assert slow_stage == [10]  # the stage waited for ticks, and they came
    assert not _clocks()


def test_a_batch_log_with_one_job_says_a_stage_that_lasts(one_hole, slow_stage, ticks,
                                                          monkeypatch, tmp_path, capsys):
    # stderr captured: a log; a stage that lasts 0.05 s is said (10 s in a real run), by the
    # bar's clock: the fill runs in this process, which says nothing else meanwhile. The
    # log's clock runs only while the slow stage waits (10 ticks of 0.01 s): under load the
    # real steps before and after it (cutting the hole, writing) can last 0.05 s too, and
    # would be said as well (session 49: the test failed so under load)
    monkeypatch.setattr(batch_command, "LOG_AFTER_SECONDS", 0.05)
    logged_rows = batch_command._LoggedRows

    def stage_clock(out, bar):
        return logged_rows(out, bar, clock=lambda: 0.01 * ticks["stage_ticks"])

    monkeypatch.setattr(batch_command, "_LoggedRows", stage_clock)
    path, n_edges = one_hole
    assert main(["batch", str(path), "-o", str(tmp_path / "out"), "--jobs", "1"]) == 0
    assert slow_stage == [10]
    lines = capsys.readouterr().err.splitlines()
    assert [line for line in lines if "so far" in line] == [
        f"  {path}: 0/1 holes (hole 0: {n_edges} edges, λ-H fill (stage 5 of 5)), "
        "0 s so far"]


def test_report_draws_its_bar_while_a_stage_runs(one_hole, slow_stage, tmp_path):
    # session 50: report's bar stood still through its fills (it told them nothing)
    assert main(["report", str(one_hole[0]), "-o", str(tmp_path / "report")]) == 0
    assert slow_stage == [10]
    assert not _clocks()


def test_experiments_draw_their_bar_while_a_stage_runs(slow_stage, tmp_path):
    assert main(["experiments", "--quick", "--cases", "cube", "-o", str(tmp_path)]) == 0
    assert slow_stage and set(slow_stage) == {10}
    assert not _clocks()
