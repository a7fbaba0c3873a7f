"""The kernels loaded in a background thread while the whole-mesh passes run
(fill/warmup.py)."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from surfinpaint import fill_holes
from surfinpaint.data import sphere
from surfinpaint.fill import warmup
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.geometry.validation import validate_mesh

numba = pytest.importorskip("numba")


def _dispatchers():
    from surfinpaint.fill.liepa import refinement, triangulation
    from surfinpaint.geometry import metrics

    return {"triangulation": triangulation._DP_KERNEL.get(),
            "flip": refinement._flip_kernel(), "distance": metrics._numba_kernel()}


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


def test_fill_holes_with_the_warmup_thread_is_bit_identical_and_leaves_no_thread(
        monkeypatch):
    v, f = sphere(3)
    h = mean_edge_length(v, f)
    cut = cut_holes(v, f, [np.array([0.0, 0, 1]), np.array([1.0, 0, 0])], 3 * h)
    plain = fill_holes(cut.vertices, cut.faces, method="fair", jobs=1)
    started = []
    original = threading.Thread.start

    def start(self):
        started.append(self.name)
        original(self)

    monkeypatch.setattr(threading.Thread, "start", start)
    monkeypatch.setattr(warmup, "WARMUP_MIN_FACES", 0)
    _forget_warmup()
    warmed = fill_holes(cut.vertices, cut.faces, method="fair", jobs=1)
    assert started == ["surfinpaint-warmup"]
    assert not any(t.name == "surfinpaint-warmup" for t in threading.enumerate())
    assert np.array_equal(warmed.vertices, plain.vertices)
    assert np.array_equal(warmed.faces, plain.faces)
    # once loaded, later calls start no thread
    fill_holes(cut.vertices, cut.faces, method="fair", jobs=1)
    assert started == ["surfinpaint-warmup"]


def test_a_fair_fill_warms_no_distance_kernel(monkeypatch):
    # the distance kernel is the conformal self-check's: a fair fill would only pay for it
    measured = []
    monkeypatch.setattr(warmup, "point_mesh_distance", lambda *a: measured.append(a))
    _forget_warmup()
    warmup.warm_kernels("fair")
    assert warmup._done["fair"].is_set() and not warmup._done["conformal"].is_set()
    assert measured == []
    w = warmup.KernelWarmup.for_mesh(warmup.WARMUP_MIN_FACES, "fair")
    assert not w.running  # loaded already
    warmup.warm_kernels("conformal")
    assert len(measured) == 1 and warmup._done["conformal"].is_set()


def test_a_small_mesh_starts_no_warmup():
    _forget_warmup()
    w = warmup.KernelWarmup.for_mesh(warmup.WARMUP_MIN_FACES - 1)
    assert not w.running
    w.join()  # nothing to wait for
