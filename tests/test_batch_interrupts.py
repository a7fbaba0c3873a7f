"""An interrupted ``surfinpaint batch`` (Ctrl-C, SIGTERM): it stops at once, the files in
flight unfinished and with no partial output, the files done recorded in the summary, and
the message says so; the same command again fills the rest, nothing lost or duplicated."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from test_batch import _holey, _no_temporaries

import surfinpaint.app.batch as batch
from surfinpaint.app.batch import read_summary
from surfinpaint.app.cli import main
from surfinpaint.data import snowman, sphere
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.io.formats import read_mesh, write_mesh


def _copies(folder: Path, n: int, mesh) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    paths = [folder / f"s{i}.ply" for i in range(n)]
    for path in paths:
        write_mesh(path, *mesh)
    return paths


def _resumed(folder: Path, out: Path, mesh, n: int, done: set[str], **options) -> None:
    """The same run again fills exactly the files the first one did not write; every
    output is the mesh's lone fill."""
    rows = batch.fill_files([folder], out, jobs=1, **options)
    assert {r.output for r in rows if r.status == "skipped"} == done
    assert {r.output for r in rows if r.status == "filled"} == {f"s{i}.ply" for i in
                                                                range(n)} - done
    reference = fill_holes(*mesh, **options)
    for i in range(n):
        np.testing.assert_array_equal(read_mesh(out / f"s{i}.ply")[0], reference.vertices)
    _no_temporaries(out)


def test_sigterm_stops_the_file_in_flight_and_says_so(tmp_path, monkeypatch, capsys):
    # --jobs 1: the command's own process fills; SIGTERM comes after the third file's
    # first hole. That file is left unwritten: the message must not say it was finished.
    mesh = _holey(*sphere(2), 2)
    folder, out = tmp_path / "scans", tmp_path / "out"
    _copies(folder, 5, mesh)
    started: list[str] = []
    original = batch.fill_mesh_data

    def fill_mesh_data(data, *args, progress=None, **kwargs):
        started.append("x")

        def hole_done(done, total, message):
            if len(started) == 3 and done == 1:
                os.kill(os.getpid(), signal.SIGTERM)
        return original(data, *args, progress=hole_done, **kwargs)

    monkeypatch.setattr(batch, "fill_mesh_data", fill_mesh_data)
    assert main(["batch", str(folder), "-o", str(out), "--jobs", "1", "--method", "fair",
                 "-q"]) == 143
    said = " ".join(capsys.readouterr().err.split())
    assert "interrupted by SIGTERM" in said and "were finished" not in said, said
    assert "stopped unfinished, leaving no partial output" in said, said
    assert "picks up the rest, the files in flight included" in said, said
    done = {r.output for r in read_summary(out)}
    assert len(done) == 2 and all(r.status == "filled" for r in read_summary(out))
    assert {p.name for p in out.glob("s*.ply")} == done  # the third file: nothing of it
    _no_temporaries(out)
    monkeypatch.undo()
    _resumed(folder, out, mesh, 5, done, method="fair")


STALL = '''
import os
import time

if os.environ.get("SURFINPAINT_TEST_STALL"):
    import surfinpaint.app.batch as batch

    _read = batch.read_mesh_data

    def read_mesh_data(path, *args, **kwargs):
        if os.path.basename(path) == os.environ["SURFINPAINT_TEST_STALL"]:
            # written whole, then renamed: the test reads the pid as soon as the file exists
            marker = os.environ["SURFINPAINT_TEST_MARKER"]
            with open(marker + ".part", "w") as part:
                part.write(str(os.getpid()))
            os.replace(marker + ".part", marker)
            time.sleep(300)  # a file that takes long: the interrupt must not wait for it
        return _read(path, *args, **kwargs)

    batch.read_mesh_data = read_mesh_data
'''


def _stalling(tmp_path: Path, name: str) -> dict[str, str]:
    """The environment of a command whose reading of the file ``name`` takes 300 s
    (:data:`STALL`); its process writes its pid to ``tmp_path / "stalled"`` first."""
    hook = tmp_path / "hook"
    hook.mkdir()
    (hook / "sitecustomize.py").write_text(STALL)
    return {**os.environ, "SURFINPAINT_TEST_STALL": name,
            "SURFINPAINT_TEST_MARKER": str(tmp_path / "stalled"), "PYTHONPATH": os.pathsep.join(
                [str(hook), *filter(None, [os.environ.get("PYTHONPATH")])])}


@pytest.mark.slow
def test_sigterm_to_the_command_ends_its_workers_and_leaves_the_files_in_flight(tmp_path):
    # SIGTERM to the command alone (timeout, docker stop): before, it waited for every
    # file in flight, here one that takes 300 s; it stops at once, and says what it did
    mesh = _holey(*sphere(2), 2)
    folder, out = tmp_path / "scans", tmp_path / "out"
    _copies(folder, 6, mesh)
    marker = tmp_path / "stalled"
    proc = subprocess.Popen([sys.executable, "-m", "surfinpaint", "batch", str(folder), "-o",
                             str(out), "--jobs", "2", "--method", "fair", "-q"],
                            stderr=subprocess.PIPE, text=True,
                            env=_stalling(tmp_path, "s2.ply"), start_new_session=True)
    deadline = time.monotonic() + 120
    while not marker.exists():
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, "the stalled file was never started"
        time.sleep(0.01)
    # a pid, never 0: os.kill(0, 0) would signal this test's own process group
    stalled_worker = int(marker.read_text())
    assert stalled_worker > 0
    proc.send_signal(signal.SIGTERM)
    try:
        _, err = proc.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        pytest.fail("SIGTERM did not stop the batch: it waited for the files in flight")
    assert proc.returncode == 143, err
    said = " ".join(err.split())
    assert "stopped unfinished, leaving no partial output" in said and "Traceback" not in said
    with pytest.raises(ProcessLookupError):
        os.kill(stalled_worker, 0)  # ended, not left running
    assert not (out / "s2.ply").exists()
    done = {r.output for r in read_summary(out)}
    assert "s2.ply" not in done and {p.name for p in out.glob("s*.ply")} >= done
    _no_temporaries(out)
    _resumed(folder, out, mesh, 6, {p.name for p in out.glob("s*.ply")}, method="fair")


@pytest.mark.slow
def test_ctrl_c_stops_the_files_in_flight_and_the_same_command_picks_up_the_rest(tmp_path):
    # Ctrl-C in a terminal signals the whole process group: the workers as well
    mesh = _holey(*snowman(0.12), 2)
    folder, out = tmp_path / "scans", tmp_path / "out"
    _copies(folder, 10, mesh)
    command = [sys.executable, "-m", "surfinpaint", "batch", str(folder), "-o", str(out),
               "--jobs", "2", "-q"]
    # one file takes 300 s: the run cannot end before the signal, however late it comes
    # (under load the test's wait after the first output could outlast the other nine)
    proc = subprocess.Popen(command, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, env=_stalling(tmp_path, "s9.ply"))
    deadline = time.monotonic() + 120
    while not (out.is_dir() and any(out.glob("s*.ply"))):
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, "no output appeared"
        time.sleep(0.01)
    os.killpg(proc.pid, signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        pytest.fail("Ctrl-C did not stop the batch within 60 s")
    assert proc.returncode == 130, err
    said = " ".join(err.split())
    assert "picks up the rest" in said and "Traceback" not in said, err
    _no_temporaries(out)
    done = read_summary(out)
    # every file recorded was written (a file finishing as the signal came may be written
    # and not recorded: the rerun skips it, complete); at least one file was left to do
    written = {p.name for p in out.glob("s*.ply")}
    assert {r.output for r in done} <= written
    assert 1 <= len(written) < 10 and all(r.status == "filled" for r in done)
    _resumed(folder, out, mesh, 10, written)


def test_stopping_a_pool_without_its_process_list_waits_for_the_files_in_flight():
    # _stop_workers ends the workers through the pool's private list of its processes; a
    # pool without it (another Python's) is shut down waiting, with the queued files
    # cancelled, rather than failing
    calls = []

    class Pool:
        def shutdown(self, wait=True, *, cancel_futures=False):
            calls.append((wait, cancel_futures))

    batch._stop_workers(Pool())
    assert calls == [(True, True)]
