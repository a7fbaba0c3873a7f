"""How ``surfinpaint batch`` starts its local workers and orders their files: the start
method's rule, the same outputs whichever method starts them; the costliest files first."""

from __future__ import annotations

import json
import multiprocessing
import os
import subprocess
import sys
import threading

import pytest
from test_batch import FAIR, _check_outputs, _check_rows, _expected, _scans

import surfinpaint.app.batch as batch
from surfinpaint.app.batch_inputs import FileJob, largest_cost_first
from surfinpaint.app.cli import main
from surfinpaint.fill import parallel


@pytest.mark.parametrize(("platform", "methods", "threads", "expected"), [
    ("linux", ["fork", "spawn", "forkserver"], 1, "fork"),        # one thread: forked
    ("linux", ["fork", "spawn", "forkserver"], 2, "forkserver"),  # another thread (a bar)
    ("darwin", ["spawn", "fork", "forkserver"], 1, "forkserver"),  # macOS: never forked
    ("win32", ["spawn"], 1, "spawn"),                             # Windows
])
def test_workers_are_forked_only_on_linux_while_one_thread_runs(monkeypatch, platform,
                                                                 methods, threads, expected):
    monkeypatch.setattr(parallel.sys, "platform", platform)
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


def _jobs(tmp_path, sizes: dict[str, int]) -> list[FileJob]:
    jobs = []
    for name, size in sizes.items():
        source = tmp_path / name
        if size >= 0:  # a negative size: no such file
            source.write_bytes(b"x" * size)
        jobs.append(FileJob(source, tmp_path / "out" / name, name, name))
    return jobs


@pytest.mark.parametrize(("sizes", "measured", "order"), [
    # nothing measured: the largest file first, ties in the inputs' order, a missing one last
    ({"a": 10, "b": 30, "c": 20, "d": 30, "e": -1}, {}, "bdcae"),
    # all measured (a rerun with --overwrite): by the seconds, whatever the sizes
    ({"a": 10, "b": 30, "c": 20}, {"a": 3.0, "b": 1.0, "c": 2.0}, "acb"),
    # b unmeasured: 100 bytes at the measured files' 40 ms per byte (6 s over 150 bytes)
    # is 4 s, between c and a
    ({"a": 100, "b": 100, "c": 50}, {"a": 1.0, "c": 5.0}, "cba"),
    # a skipped file's row has 0 seconds: not a measurement (a and c are the 1 s per byte)
    ({"a": 1, "b": 4, "c": 2}, {"a": 1.0, "b": 0.0, "c": 2.0, "z": 9.0}, "bca"),
])
def test_the_costliest_files_start_first(tmp_path, sizes, measured, order):
    jobs = _jobs(tmp_path, sizes)
    assert "".join(job.name for job in largest_cost_first(jobs, measured)) == order


def test_a_rerun_starts_the_files_that_took_longest_first(tmp_path):
    scans = _scans(tmp_path)
    out = tmp_path / "out"
    batch.fill_files([scans], out, jobs=1, **FAIR)
    summary = json.loads((out / "summary.json").read_text())
    names = [row["path"] for row in summary["files"]]
    # the earlier run's seconds, made up: the inputs' order reversed
    for i, row in enumerate(summary["files"]):
        row["seconds"] = float(i + 1)
    (out / "summary.json").write_text(json.dumps(summary))
    started = []
    batch.fill_files([scans], out, jobs=1, overwrite=True, **FAIR,
                     progress=lambda done, total, message: started.append(message)
                     if done and "holes (" not in message else None)
    # the corrupt file fails its pre-flight (session 41), said before any file is filled;
    # the others are filled longest first
    corrupt = [name for name in names if name.endswith("corrupt.ply")]
    assert len(corrupt) == 1
    assert [message.split(": ")[0] for message in started] == \
        corrupt + [name for name in names[::-1] if name not in corrupt]


def test_the_batch_command_with_its_progress_bar_adds_no_thread(tmp_path, monkeypatch, capsys):
    # workers are forked only from a process of one thread: the bar must not add one
    scans = _scans(tmp_path)
    before = threading.active_count()  # pytest-xdist's own threads, if any
    seen = []

    def start_context(preload):
        seen.append(threading.active_count())
        return multiprocessing.get_context("spawn" if "fork" not in
                                           multiprocessing.get_all_start_methods() else "fork")

    monkeypatch.setattr(batch, "start_context", start_context)
    assert main(["batch", str(scans), "-o", str(tmp_path / "out"), "--jobs", "2",
                 "--method", "fair"]) == 1  # the corrupt file
    assert "7 files: 4 filled, 0 unfilled, 2 closed, 1 failed" in capsys.readouterr().err
    assert seen and set(seen) == {before}


FAULTS = '''
import resource, sys
import numpy as np
from surfinpaint.app.dask_worker import keep_freed_memory

def faults():
    for _ in range(50):
        np.ones(2**18).sum()  # 2 MB, allocated and freed
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for _ in range(200):
        np.ones(2**18).sum()
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before

untouched = faults()
set_here = keep_freed_memory()
print(untouched, faults(), set_here)
'''


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc's allocator")
def test_the_dask_preload_makes_glibc_reuse_freed_arrays(tmp_path):
    # Dask's nanny starts workers with MALLOC_TRIM_THRESHOLD_=65536: every array over
    # 128 kB is then a fresh mmap, its pages faulted in one by one (512 for 2 MB)
    env = {**os.environ, "MALLOC_TRIM_THRESHOLD_": "65536"}
    done = subprocess.run([sys.executable, "-c", FAULTS], env=env, capture_output=True,
                          text=True, check=True)
    untouched, kept, set_here = done.stdout.split()
    assert set_here == "True"
    assert int(untouched) >= 200 * 500  # each array faulted in afresh
    assert int(kept) < 2000  # the freed memory reused
