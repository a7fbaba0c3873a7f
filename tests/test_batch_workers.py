"""How ``surfinpaint batch`` starts its local workers and orders their files: the start
method's rule, the same outputs whichever method starts them."""

from __future__ import annotations

import multiprocessing

import pytest
from test_batch import FAIR, _check_outputs, _check_rows, _expected, _scans

import surfinpaint.app.batch as batch
from surfinpaint.fill import parallel


@pytest.mark.parametrize(("methods", "threads", "expected"), [
    (["fork", "spawn", "forkserver"], 1, "fork"),        # Linux, one thread: forked
    (["fork", "spawn", "forkserver"], 2, "forkserver"),  # another thread runs (a bar)
    (["spawn", "fork", "forkserver"], 1, "fork"),        # macOS lists spawn first
    (["spawn"], 1, "spawn"),                             # Windows
])
def test_workers_are_forked_only_while_one_thread_runs(monkeypatch, methods, threads,
                                                        expected):
    monkeypatch.setattr(parallel.multiprocessing, "get_all_start_methods", lambda: methods)
    monkeypatch.setattr(parallel.threading, "active_count", lambda: threads)
    context = parallel.start_context("surfinpaint.app.batch")
    assert context.get_start_method() == expected


@pytest.mark.parametrize("method", ["fork", "forkserver", "spawn"])
def test_every_start_method_fills_the_same_files(tmp_path, monkeypatch, method):
    if method not in multiprocessing.get_all_start_methods():
        pytest.skip(f"no {method} here")
    monkeypatch.setattr(batch, "start_context",
                        lambda preload: multiprocessing.get_context(method))
    scans = _scans(tmp_path)
    out = tmp_path / "out"
    expected = _expected(scans, **FAIR)
    rows = batch.fill_files([scans], out, jobs=2, **FAIR)
    _check_rows(rows, expected)
    _check_outputs(out, expected)
