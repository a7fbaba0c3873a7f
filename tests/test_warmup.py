"""The kernels loaded once before a parallel fill's workers fork, and a large mesh's work
beside its whole-mesh passes (the kernels' loading, find_holes, the incidence), every
thread joined before a hole is filled (fill/warmup.py)."""

from __future__ import annotations

import multiprocessing
import subprocess
import sys
import threading
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

from surfinpaint import MeshError, fill_holes
from surfinpaint.data import sphere
from surfinpaint.fill import parallel, pipeline, warmup
from surfinpaint.geometry import metrics
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.geometry.validation import validate_mesh
from surfinpaint.representation import blas_threads

numba = pytest.importorskip("numba")


def _dispatchers():
    from surfinpaint.fill.liepa import refinement, triangulation
    from surfinpaint.geometry import metrics, vertex_measures
    from surfinpaint.representation import face_derivatives

    return {"triangulation": triangulation._DP_KERNEL.get(),
            "flip": refinement._flip_kernel(), "distance": metrics._numba_kernel(),
            "ball": metrics._BALL_KERNEL.get(),
            "measures": vertex_measures._MEASURES_KERNEL.get(),
            "blocks": face_derivatives._BLOCKS_KERNEL.get(),
            "rhs": face_derivatives._RHS_KERNEL.get()}


@pytest.mark.parametrize("method, made", [("conformal", 1), ("fair", 0)])
def test_loading_the_kernels_makes_the_blas_controller_for_conformal_fills(monkeypatch, method,
                                                                          made):
    """The λ-H fill's BLAS thread-pool controller is made with its kernels (beside the
    passes; forked workers inherit it), once: not where the holes start. A faired fill makes
    none (its fills use no BLAS limit)."""
    count = []
    controller = blas_threads.ThreadpoolController
    monkeypatch.setattr(blas_threads, "_CONTROLLER", [])  # none made yet in this process
    monkeypatch.setattr(blas_threads, "ThreadpoolController",
                        lambda: count.append(1) or controller())
    warmup.warm_kernels(method)
    warmup.warm_kernels(method)
    assert len(count) == made
    assert (blas_threads.blas_controller() is not None) and len(count) == 1


def test_the_warmup_mesh_is_a_valid_annulus_with_the_hole_given():
    v, f, loop = warmup.warmup_mesh()
    report = validate_mesh(v, f)
    assert report.n_components == 1 and sorted(report.boundary_loop_lengths) == [10, 10]
    from surfinpaint.fill.holes import find_holes

    assert any(np.array_equal(h.loop, np.roll(loop, -k)) for h in find_holes(v, f)
               for k in range(len(loop)))


def _forget_warmup():
    for done in warmup._done.values():
        done.clear()


def test_warm_kernels_loads_what_real_fills_use():
    _forget_warmup()
    warmup.warm_kernels()
    loaded = {name: list(d.signatures) for name, d in _dispatchers().items()}
    assert all(loaded.values()), loaded  # every kernel loaded, none skipped
    v, f = sphere(3)
    cut = cut_holes(v, f, [np.array([0.0, 0, 1])], 4 * mean_edge_length(v, f))
    for method in ("fair", "conformal"):
        fill_holes(cut.vertices, cut.faces, method=method, jobs=1)
    # a real fill needed no specialisation the warm-up did not load
    assert {name: list(d.signatures) for name, d in _dispatchers().items()} == loaded


@pytest.fixture(scope="module")
def two_holes():
    v, f = sphere(3)
    h = mean_edge_length(v, f)
    cut = cut_holes(v, f, [np.array([0.0, 0, 1]), np.array([1.0, 0, 0]),
                           np.array([0.0, -1, 0])], 3 * h)
    return cut.vertices, cut.faces


def _forked_workers(monkeypatch):
    """Workers on forked processes for any hole (a test process may run threads)."""
    monkeypatch.setattr(parallel, "MIN_PARALLEL_EDGES", {"fair": 0, "conformal": 0})
    monkeypatch.setattr(parallel, "forks", lambda: True)
    context = multiprocessing.get_context("fork")
    monkeypatch.setattr(parallel, "pool", lambda workers: ProcessPoolExecutor(
        workers, mp_context=context))


@pytest.mark.parametrize("method", ["fair", "conformal"])
def test_a_parallel_fill_loads_the_kernels_before_its_workers_fork(two_holes, method,
                                                                   monkeypatch):
    plain = fill_holes(*two_holes, method=method, jobs=1)
    _forked_workers(monkeypatch)
    loaded_at_fork = []
    original = pipeline.fill_in_parallel

    def fill_in_parallel(mesh, todo, run, workers):
        loaded_at_fork.append({m: warmup.kernels_loaded(m) for m in ("fair", "conformal")})
        return original(mesh, todo, run, workers)

    monkeypatch.setattr(pipeline, "fill_in_parallel", fill_in_parallel)
    _forget_warmup()
    both = fill_holes(*two_holes, method=method, jobs=2)
    # loaded once, here, and only what the method uses (a fair fill needs no distance)
    assert loaded_at_fork == [{"fair": True, "conformal": method == "conformal"}]
    assert np.array_equal(both.vertices, plain.vertices)
    assert np.array_equal(both.faces, plain.faces)


def test_kernels_are_not_loaded_for_workers_that_are_not_forked(monkeypatch):
    called = []
    monkeypatch.setattr(warmup, "warm_kernels", called.append)
    monkeypatch.setattr(parallel, "forks", lambda: False)
    warmup.load_for_workers("conformal")
    assert called == []  # a forkserver's or spawned worker loads its own
    monkeypatch.setattr(parallel, "forks", lambda: True)
    warmup.load_for_workers("conformal")
    assert called == ["conformal"]


def test_a_failed_warmup_leaves_the_fill_to_its_holes(two_holes, monkeypatch):
    plain = fill_holes(*two_holes, method="fair", jobs=1)
    _forked_workers(monkeypatch)

    def broken(method):
        raise RuntimeError("no kernels")

    monkeypatch.setattr(warmup, "warm_kernels", broken)
    both = fill_holes(*two_holes, method="fair", jobs=2)
    assert np.array_equal(both.vertices, plain.vertices)


@pytest.mark.parametrize("method", ["conformal", "fair"])
@pytest.mark.parametrize("large", [True, False])
def test_a_large_fill_loads_its_kernels_beside_the_whole_mesh_passes(monkeypatch, method,
                                                                     large):
    # the passes of a large mesh leave a core idle: its kernels load meanwhile, in a thread
    # joined before the first hole is filled (or the workers forked); a small mesh's
    # passes are too short to hide anything, and its first hole loads them
    v, f = sphere(7)  # 327,680 faces: above BESIDE_MIN_FACES
    assert len(f) >= warmup.BESIDE_MIN_FACES
    if not large:
        monkeypatch.setattr(warmup, "BESIDE_MIN_FACES", 2 * len(f))
    cut = cut_holes(v, f, [np.array([0.0, 0, 1])], 3 * mean_edge_length(v, f))
    _forget_warmup()
    warmed, holes_started = [], []
    warm = warmup.warm_kernels
    monkeypatch.setattr(warmup, "warm_kernels", lambda m: (warmed.append(
        (m, threading.current_thread().name, len(holes_started))), warm(m)))
    fill_hole = pipeline.fill_hole
    monkeypatch.setattr(pipeline, "fill_hole", lambda *a: (holes_started.append(
        [t.name for t in threading.enumerate() if t.name == "surfinpaint-warmup"]),
        fill_hole(*a))[1])
    result = fill_holes(cut.vertices, cut.faces, method=method, jobs=1)
    assert result.reports[0].new_faces > 0
    if large:  # loaded in the thread, before the hole, which starts once it has ended
        assert warmed == [(method, "surfinpaint-warmup", 0)]
        assert holes_started == [[]]
    else:
        assert warmed == []


def test_a_large_parallel_fill_forks_its_workers_after_the_thread_loaded_the_kernels(
        monkeypatch):
    # the workers inherit what the thread loaded (no load of their own, none here after
    # the passes) and fill the holes as one after another would, bit for bit
    v, f = sphere(7)
    h = mean_edge_length(v, f)
    cut = cut_holes(v, f, [np.array([0.0, 0, 1]), np.array([1.0, 0, 0]),
                           np.array([0.0, -1, 0])], 3 * h)
    plain = fill_holes(cut.vertices, cut.faces, method="conformal", jobs=1)
    _forked_workers(monkeypatch)
    _forget_warmup()
    warmed = []
    warm = warmup.warm_kernels
    monkeypatch.setattr(warmup, "warm_kernels", lambda m: (warmed.append(
        (m, threading.current_thread().name)), warm(m)))
    at_fork = []
    original = pipeline.fill_in_parallel

    def fill_in_parallel(mesh, todo, run, workers):
        at_fork.append((threading.active_count(), warmup.kernels_loaded("conformal")))
        return original(mesh, todo, run, workers)

    monkeypatch.setattr(pipeline, "fill_in_parallel", fill_in_parallel)
    before = threading.active_count()
    both = fill_holes(cut.vertices, cut.faces, method="conformal", jobs=2)
    assert warmed[0] == ("conformal", "surfinpaint-warmup")
    assert at_fork == [(before, True)]  # the thread has ended, the kernels are loaded
    assert np.array_equal(both.vertices, plain.vertices)
    assert np.array_equal(both.faces, plain.faces)


def test_a_fair_fill_warms_no_distance_kernel(monkeypatch):
    # the distance kernel is the conformal self-check's: a fair fill would only pay for it
    measured = []
    monkeypatch.setattr(metrics, "warm", lambda *a: measured.append(a))
    _forget_warmup()
    warmup.warm_kernels("fair")
    assert warmup._done["fair"].is_set() and not warmup._done["conformal"].is_set()
    assert measured == []
    warmup.warm_kernels("conformal")
    assert len(measured) == 1 and warmup._done["conformal"].is_set()


def _made_on(monkeypatch, name):
    """Record the thread that runs ``pipeline.<name>`` (vertex_faces, find_holes)."""
    threads = []
    inner = getattr(pipeline, name)
    monkeypatch.setattr(pipeline, name, lambda *a, **k: (threads.append(
        threading.current_thread().name), inner(*a, **k))[1])
    return threads


@pytest.mark.parametrize("large", [True, False])
@pytest.mark.parametrize("validate", [True, False])
def test_a_large_mesh_passes_run_beside_its_edge_table_and_checks(monkeypatch, large,
                                                                    validate):
    # find_holes and the vertex-face incidence run on a thread while the mesh is checked
    # (from the edge table); the thread is joined before the first hole; the same fill,
    # bit for bit
    v, f = sphere(4)
    cut = cut_holes(v, f, [np.array([0.0, 0, 1]), np.array([1.0, 0, 0])],
                    3 * mean_edge_length(v, f))
    plain = fill_holes(cut.vertices, cut.faces, method="fair", jobs=1)
    monkeypatch.setattr(warmup, "BESIDE_MIN_FACES", 1 if large else 10**9)
    incidence = _made_on(monkeypatch, "triangle_incidence")
    holes_found = _made_on(monkeypatch, "find_holes")
    threads_at_holes = []
    fill_hole = pipeline.fill_hole
    monkeypatch.setattr(pipeline, "fill_hole", lambda *a: (threads_at_holes.append(
        threading.active_count()), fill_hole(*a))[1])
    before = threading.active_count()
    result = fill_holes(cut.vertices, cut.faces, method="fair", jobs=1, validate=validate)
    beside = "surfinpaint-passes_0" if large else "MainThread"
    assert incidence == [beside] and holes_found == [beside]
    assert threads_at_holes == [before, before]  # the thread has ended before the holes
    np.testing.assert_array_equal(result.vertices, plain.vertices)
    np.testing.assert_array_equal(result.faces, plain.faces)


def _zero_area_face(v, f):
    """A sliver: face 5's first corner moved onto its opposite edge's midpoint."""
    v = v.copy()
    a, b, c = f[5]
    v = np.vstack([v, 0.5 * (v[b] + v[c])])
    f = f.copy()
    f[5, 0] = len(v) - 1
    return v, f


def _fin(v, f):
    """A third face on the edge of face 0 opposite its first corner, over a new vertex."""
    a, b = f[0][1], f[0][2]
    return np.vstack([v, 2 * v[a]]), np.vstack([f, [b, a, len(v)]])


def _flipped(v, f):
    """Face 7 turned over: its edges run as its neighbours' do."""
    f = f.copy()
    f[7] = f[7, ::-1]
    return v, f


@pytest.mark.parametrize("large", [True, False])
@pytest.mark.parametrize(("broken", "match", "ids"), [
    # find_holes runs beside the checks on meshes they refuse: their errors are raised,
    # in their order (a duplicate before a non-manifold edge, as validate_mesh names them;
    # a zero-area face is no error)
    (lambda v, f: _zero_area_face(v, np.vstack([f, f[9:10]])), "1 duplicate face:", None),
    (lambda v, f: _zero_area_face(*_fin(v, np.vstack([f, f[9:10]]))), "1 duplicate face:",
     None),
    (lambda v, f: _zero_area_face(*_fin(v, f)), "non-manifold edge", None),
    (_fin, "non-manifold edge", None),
    (_flipped, "inconsistent face orientation: 3 shared edges", None),
])
def test_the_passes_beside_the_table_keep_the_errors_and_their_order(monkeypatch, large,
                                                                     broken, match, ids):
    v, f = broken(*sphere(3))
    monkeypatch.setattr(warmup, "BESIDE_MIN_FACES", 1 if large else 10**9)
    with pytest.raises(MeshError, match=match) as info:
        fill_holes(v, f, method="fair", jobs=1)
    with pytest.raises(MeshError, match=match):
        validate_mesh(v, f)
    if ids is not None:
        assert info.value.faces == ids
    assert not any(t.name.startswith("surfinpaint-passes") for t in threading.enumerate())



@pytest.mark.parametrize("ahead", [True, False])
def test_the_fill_command_loads_the_kernels_while_it_reads_a_large_file(tmp_path, monkeypatch,
                                                                       ahead):
    # the loading starts before the read (a large file); the fill's passes join it, so no
    # thread is left at the fork of the workers or after the command
    from surfinpaint import write_mesh
    from surfinpaint.app import cli

    v, f = sphere(3)
    cut = cut_holes(v, f, [np.array([0.0, 0, 1])], 3 * mean_edge_length(v, f))
    mesh, out = tmp_path / "holed.ply", tmp_path / "out.ply"
    write_mesh(mesh, cut.vertices, cut.faces)
    monkeypatch.setattr(cli, "LOAD_AHEAD_MIN_BYTES", 0 if ahead else 10**12)
    _forget_warmup()
    started_at_read = []  # the loading threads started and not yet joined (they may end)
    read = cli.read_mesh_data
    monkeypatch.setattr(cli, "read_mesh_data", lambda *a, **k: (started_at_read.append(
        [t.name for t in warmup._ahead]), read(*a, **k))[1])
    assert cli.main(["fill", str(mesh), "-o", str(out), "-q", "--method", "fair"]) == 0
    assert started_at_read == [["surfinpaint-warmup"] if ahead else []]
    assert warmup.kernels_loaded("fair") == ahead  # a small mesh loads none beside
    assert not any(t.name == "surfinpaint-warmup" for t in threading.enumerate())
    assert warmup._ahead == []


def test_a_load_started_ahead_is_started_once_and_joined_by_the_next_fill(monkeypatch):
    _forget_warmup()
    started = []
    monkeypatch.setattr(warmup, "warm_kernels", lambda m: (started.append(m),
                                                           warmup._done[m].set()))
    warmup.load_ahead("fair")
    warmup.load_ahead("fair")  # loading: nothing more
    with warmup.loading_beside(10, "fair"):  # a small mesh: no thread of its own
        pass
    assert started == ["fair"] and warmup._ahead == []
    warmup.load_ahead("fair")  # loaded: nothing
    assert started == ["fair"] and warmup._ahead == []


def _collections_while_loading_ahead(freeze: bool) -> list[int]:
    """In a fresh process (the collector's state is the process's): the collections run on
    the loading thread of ``load_ahead``, the objects frozen meanwhile, whether the
    collector is on after the thread is joined, and whether the kernels were loaded."""
    code = ("import gc, sys, threading\n"
            "from surfinpaint.fill import warmup\n"
            "seen = []\n"
            "gc.callbacks.append(lambda phase, info: phase == 'start' and seen.append(\n"
            "    threading.current_thread().name))\n"
            + ("warmup.freeze_loaded()\n" if freeze else "") +
            "before = gc.get_freeze_count()\n"
            "warmup.load_ahead('conformal')\n"
            "with warmup.loading_beside(0, 'conformal'):\n"  # joins it
            "    pass\n"
            "print(seen.count('surfinpaint-warmup'), gc.get_freeze_count() - before,\n"
            "      int(gc.isenabled()), int(warmup.kernels_loaded('conformal')))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=300).stdout.split()
    return [int(x) for x in out]


def test_a_process_that_ends_after_its_command_loads_without_collections():
    # the program's process (app/program.py): numba's objects live to its end; made
    # without collections and frozen, no collection walks them (docs/scale.md, session 45)
    collections, frozen, enabled, loaded = _collections_while_loading_ahead(freeze=True)
    assert (collections, enabled, loaded) == (0, 1, 1) and frozen > 10_000
    # a library caller's process is left as it was: collected as it goes, nothing frozen
    collections, frozen, enabled, loaded = _collections_while_loading_ahead(freeze=False)
    assert collections > 0 and (frozen, enabled, loaded) == (0, 1, 1)


def test_the_program_sets_its_loading_to_freeze_and_a_library_import_does_not():
    code = ("from surfinpaint.fill import warmup\n"
            "print(warmup._freezing.is_set())\n"
            "from surfinpaint.app import program\n"
            "program.command_line()\n"
            "print(warmup._freezing.is_set())\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, timeout=120).stdout.split()
    assert out == ["False", "True"]
