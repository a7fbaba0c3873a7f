"""Holes filled in worker processes (fill/parallel.py): the same result as one after
another, bit for bit, with the holes that depend on earlier ones filled after them."""

from __future__ import annotations

import multiprocessing
import re
import warnings
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.errors import MeshError
from surfinpaint.fill import parallel
from surfinpaint.fill.conformal import ConformalOptions
from surfinpaint.fill.pipeline import _FilledMesh, _Run, fill_holes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.io.formats import read_mesh, write_mesh

# five holes far apart and a sixth next to the fifth (0.53 rad from it: inside the
# conformal method's neighbourhood of a 12-edge hole, outside the faired fill's 3 rings)
CENTERS = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0.5, 0.0, 0.85)]


@pytest.fixture(scope="module")
def holed():
    vertices, faces = sphere(4)
    centers = [np.array(c) / np.linalg.norm(c) for c in CENTERS]
    cut = cut_holes(vertices, faces, centers, 0.2)
    return cut.vertices, cut.faces, [h.loop for h in cut.holes]


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
    mesh = _FilledMesh(vertices, faces)
    run = _Run(method, ConformalOptions(), None, False, len(loops), None, None)

    class Hole:
        def __init__(self, loop):
            self.n_edges = len(loop)

    reach = {k: mesh.cut(loop, run.rings_of(Hole(loop))).ids for k, loop in enumerate(loops)}
    return parallel.independent(reach, dict(enumerate(loops)), len(vertices))


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
    loops = {0: np.array([0, 1, 2]), 1: np.array([10, 11, 12]), 2: np.array([20, 21, 22])}
    reaches = {0: np.array([0, 1, 2, 3, 10]), 1: np.array([10, 11, 12, 13]),
               2: np.array([12, 20, 21, 22])}
    assert parallel.independent(reaches, loops, 30) == {0, 1}
    # an added vertex (id past the original ones) in a reach is ignored
    assert parallel.independent({0: np.array([0, 1, 2, 40])}, {0: loops[0]}, 30) == {0}


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
