"""The stages of holes filled on worker processes, said where the progress is shown: ``fill
--jobs 2``'s holes (fill/scheduler.py) and ``batch --jobs 2``'s files (session 48; before,
a hole on a worker said its start and its end only)."""

from __future__ import annotations

import itertools
import multiprocessing

import pytest

from surfinpaint.app.batch import fill_files
from surfinpaint.data import sphere
from surfinpaint.fill import parallel, pipeline, scheduler
from surfinpaint.fill.conformal.method import STAGES
from surfinpaint.fill.hole_steps import Run
from surfinpaint.fill.results import HoleReport
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.io import write_mesh

LAST = f"λ-H fill (stage {len(STAGES)} of {len(STAGES)})"


@pytest.fixture(scope="module")
def two_holes():
    """A sphere with two holes far apart, each filled by the λ-H fill."""
    v, f = sphere(3)
    cut = cut_holes(v, f, [0, 40], [0.5, 0.5])
    return cut.vertices, cut.faces


@pytest.fixture
def on_workers(monkeypatch, on_forked_workers):
    """Two holes are enough for (forked) workers; the calls that used them counted."""
    monkeypatch.setattr(parallel, "MIN_PARALLEL_HOLES", 2)
    return on_forked_workers


def _heard(vertices, faces, jobs):
    said: list[tuple[int, int, str]] = []
    result = pipeline.fill_holes(vertices, faces, jobs=jobs,
                                 progress=lambda done, total, m: said.append((done, total, m)))
    return result, said


def _assert_stages_as_serial(result, said, alone):
    """Each hole's stages said in ``said``, in order, as in the serial fill's ``alone``
    (a stage said again after a second without news, as one: under load a stage on a
    worker can take that long)."""
    for report in result.reports:
        mine = f"hole {report.index}: "
        stages = [m for m, _ in itertools.groupby(
            m for _, _, m in said if m.startswith(mine) and "(stage " in m)]
        assert stages == [m for _, _, m in alone if m.startswith(mine) and "(stage " in m]
        assert stages[-1] == f"{mine}{report.n_edges} edges, {LAST}"


def test_fill_on_workers_says_each_holes_stages_as_one_process_does(two_holes, on_workers):
    serial, alone = _heard(*two_holes, jobs=1)
    assert not on_workers
    result, said = _heard(*two_holes, jobs=2)
    assert on_workers == [1]
    assert result.vertices.tobytes() == serial.vertices.tobytes()
    assert [r.outcome for r in result.reports] == ["lambda-h", "lambda-h"]
    _assert_stages_as_serial(result, said, alone)
    # the count is the holes stitched: it never goes back, and ends with both
    counts = [done for done, _, _ in said]
    assert counts == sorted(counts) and said[-1][:2] == (2, 2)
    assert {total for _, total, _ in said} == {2}


@pytest.mark.skipif("forkserver" not in multiprocessing.get_all_start_methods(),
                    reason="no forkserver here")
def test_workers_not_forked_say_each_holes_stages_too(two_holes, monkeypatch):
    # a process running other threads (a Dask client's offload thread, say) starts its
    # workers from a forkserver: they inherit nothing, and said each hole's start and end
    # only (session 48)
    monkeypatch.setattr(parallel, "MIN_PARALLEL_EDGES", {"fair": 0, "conformal": 0})
    monkeypatch.setattr(parallel, "MIN_PARALLEL_HOLES", 2)
    monkeypatch.setattr(parallel, "forks", lambda: False)
    methods: list[str] = []
    start_context = parallel.start_context
    monkeypatch.setattr(parallel, "start_context", lambda preload: methods.append(
        start_context(preload).get_start_method()) or start_context(preload))
    serial, alone = _heard(*two_holes, jobs=1)
    assert not methods
    result, said = _heard(*two_holes, jobs=2)
    assert methods == ["forkserver"]
    assert result.vertices.tobytes() == serial.vertices.tobytes()
    assert result.faces.tobytes() == serial.faces.tobytes()
    assert [r.outcome for r in result.reports] == ["lambda-h", "lambda-h"]
    _assert_stages_as_serial(result, said, alone)
    counts = [done for done, _, _ in said]
    assert counts == sorted(counts) and said[-1][:2] == (2, 2)


def test_the_last_stage_is_said_again_without_news():
    said = []
    reports = [HoleReport(index=k, loop=None, n_edges=10 * (k + 1), requested="conformal",
                          method="none") for k in range(2)]
    run = Run("conformal", None, None, False, 2, lambda d, t, m: said.append((d, m)), None,
              position={id(r): k for k, r in enumerate(reports)})
    queue = multiprocessing.get_context("fork").SimpleQueue()
    now = [100.0]
    news = scheduler._StageNews(queue, run, reports, clock=lambda: now[0])
    queue.put((1, "λ-H fill"))
    news.read({0, 1}, 0)
    news.read({0, 1}, 0)  # no news, no time gone: nothing said
    now[0] += scheduler.SAY_AGAIN_SECONDS
    news.read({0, 1}, 0)  # no news for a while: the same again
    assert said == [(0, f"hole 1: 20 edges, {LAST}")] * 2
    now[0] += scheduler.SAY_AGAIN_SECONDS
    news.read({0}, 1)  # its hole is done: not said again
    queue.put((1, "λ-H fill"))
    news.read({0}, 1)  # nor a stage of a hole no longer in flight
    assert len(said) == 2


def test_batch_on_workers_says_each_files_stages(two_holes, monkeypatch, tmp_path):
    (tmp_path / "in").mkdir()
    paths = [tmp_path / "in" / f"{name}.ply" for name in ("a", "b")]
    for path in paths:
        write_mesh(path, *two_holes)
    # each file's worker (forked: it inherits this) waits at its first λ-H stage until this
    # process has said both files there: the news is read while the files are in flight
    both_said = multiprocessing.get_context("fork").Event()
    fill_local = parallel.fill_local

    def waiting(vertices, faces, loop, method, options, fair_order, stage=None):
        def told(name):
            stage(name)
            if name == "λ-H fill":
                both_said.wait(60)
        return fill_local(vertices, faces, loop, method, options, fair_order,
                          told if stage else None)

    monkeypatch.setattr(parallel, "fill_local", waiting)
    # the workers forked whatever threads an earlier test of this process left running
    monkeypatch.setattr(parallel, "forks", lambda: True)
    said: list[str] = []

    def heard(done, total, message):
        said.append(message)
        parts = message.split(" · ")
        if all(any(p.startswith(f"{path}: ") and p.endswith(f", {LAST})") for p in parts)
               for path in paths):
            both_said.set()

    rows = fill_files([tmp_path / "in"], tmp_path / "out", jobs=2, progress=heard)
    assert [r.status for r in rows] == ["filled", "filled"]
    assert both_said.is_set(), said
