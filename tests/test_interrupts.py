"""Interrupts and outputs on the command line, with real signals and real subprocesses.

Ctrl-C (SIGINT) and SIGTERM stop `surfinpaint fill` with one line on stderr and exit
130 / 143, leaving neither the output nor the atomic writer's temporary file, whether the
signal comes while holes are filled or while the output is being written. Where the output
goes is checked before the input is even read; `-o` naming the input is refused unless
`--in-place`.
"""

from __future__ import annotations

import hashlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from conftest import grid_mesh

from surfinpaint.app import cli, interrupts
from surfinpaint.app.cli import main
from surfinpaint.app.interrupts import Interrupted, signals_raise
from surfinpaint.data import sphere
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.io.formats import read_mesh, write_mesh

SIGNALS = [pytest.param(signal.SIGINT, 130, id="SIGINT"),
           pytest.param(signal.SIGTERM, 143, id="SIGTERM")]


def _fill_process(*args: str) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "surfinpaint", "fill", *args, "-q"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _sent_signal(tmp_path: Path) -> dict[str, str]:
    """The environment of a script that creates ``tmp_path / "sent"`` as it sends itself
    the signal (:func:`_assert_stopped_after`)."""
    return dict(os.environ, SURFINPAINT_TEST_SENT=str(tmp_path / "sent"))


def _assert_stopped_after(proc: subprocess.Popen, sent: Path, code: int,
                          out_dir: Path) -> None:
    """:func:`_assert_stopped`, its limit counted from the signal, once the script has sent
    it (made ``sent``): the start (the interpreter, the imports, reading the mesh and, with
    an empty cache, compiling a kernel) is no part of it, and under load it took the 30 s
    before the signal was sent (session 50: a kernel-compile test so, in 2 full runs of the
    suite at load ~25)."""
    deadline = time.monotonic() + 300
    while not sent.exists():
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, "the script never sent the signal"
        time.sleep(0.01)
    _assert_stopped(proc, code, out_dir)


def _assert_stopped(proc: subprocess.Popen, code: int, out_dir: Path) -> None:
    """Exited promptly with ``code``, said so in one line (the last; no traceback), and left
    nothing in ``out_dir``."""
    try:
        _, err = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        pytest.fail("the signal did not stop the fill within 30 s")
    lines = err.strip().splitlines()
    assert proc.returncode == code, err
    assert lines[-1].startswith("surfinpaint: interrupted"), err
    assert sum("interrupted" in line for line in lines) == 1 and "Traceback" not in err, err
    assert sorted(os.listdir(out_dir)) == []


@pytest.mark.slow
@pytest.mark.parametrize(("signum", "code"), SIGNALS)
def test_signal_while_writing_removes_the_temporary_file(tmp_path, signum, code):
    # a 10^6-vertex grid has no hole but its outer border, so `fill` writes it unchanged;
    # as text OBJ that takes seconds, and the signal is sent as soon as the writer's
    # temporary file appears next to the target
    source = tmp_path / "grid.ply"
    write_mesh(source, *grid_mesh(999, 999))
    before = _digest(source)
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    proc = _fill_process(str(source), "-o", str(out_dir / "filled.obj"))
    deadline = time.monotonic() + 120
    while not any("filled.obj" in name and name != "filled.obj"
                  for name in os.listdir(out_dir)):
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, "the temporary output file never appeared"
        time.sleep(0.005)
    proc.send_signal(signum)
    _assert_stopped(proc, code, out_dir)
    assert _digest(source) == before


def _many_holes() -> tuple[np.ndarray, np.ndarray]:
    """A sphere with 60 small holes: several seconds of filling."""
    v, f = sphere(5)
    centres = [0]
    distance = np.linalg.norm(v - v[0], axis=1)
    for _ in range(59):  # farthest-point picks: holes apart from each other
        centres.append(int(np.argmax(distance)))
        distance = np.minimum(distance, np.linalg.norm(v - v[centres[-1]], axis=1))
    cut = cut_holes(v, f, centres, [3.0 * mean_edge_length(v, f)] * len(centres))
    return cut.vertices, cut.faces


def _pipe_opened(proc: subprocess.Popen, pipe: Path) -> int:
    """The write end of the named pipe ``pipe``, once ``proc`` has opened it to read (so is
    inside the command line's handlers); waits without blocking, should the process die
    first."""
    deadline = time.monotonic() + 120
    while True:
        try:
            return os.open(pipe, os.O_WRONLY | os.O_NONBLOCK)
        except OSError:  # ENXIO: nobody has the pipe open for reading yet
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() < deadline, "the fill never opened its input"
            time.sleep(0.01)


def _feed(fd: int, source: Path) -> None:
    os.set_blocking(fd, True)
    with os.fdopen(fd, "wb") as feed:
        feed.write(source.read_bytes())


@pytest.mark.slow
@pytest.mark.parametrize(("signum", "code"), SIGNALS)
def test_signal_while_filling_stops_with_one_line(tmp_path, signum, code):
    # the input is a named pipe: once the test has written the mesh into it, the process
    # has read it and is filling (which takes far longer than the one second waited)
    holes = tmp_path / "holes.ply"
    write_mesh(holes, *_many_holes())
    pipe = tmp_path / "pipe.ply"
    os.mkfifo(pipe)
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    proc = _fill_process(str(pipe), "-o", str(out_dir / "filled.ply"))
    _feed(_pipe_opened(proc, pipe), holes)
    time.sleep(1.0)
    assert proc.poll() is None, "the fill ended before the signal was sent"
    proc.send_signal(signum)
    _assert_stopped(proc, code, out_dir)


# A fill whose numba object-cache hook (called by llvmlite through a ctypes callback, while a
# kernel is compiled or loaded from the disk cache) sends the process a signal the first time
# it runs: the handler's exception comes inside the callback, where Python cannot raise it.
_SIGNAL_IN_CALLBACK = """
import os, signal, sys
from numba.core import codegen
real = getattr(codegen.CPUCodeLibrary, sys.argv[1]).__func__
sent = []
def hooked(cls, *args):
    if not sent:
        sent.append(1)
        open(os.environ["SURFINPAINT_TEST_SENT"], "w").close()
        os.kill(os.getpid(), int(sys.argv[2]))
    return real(cls, *args)
setattr(codegen.CPUCodeLibrary, sys.argv[1], classmethod(hooked))
from surfinpaint.app import cli, interrupts
from surfinpaint.app.cli import main
from surfinpaint.app.interrupts import Interrupted, signals_raise
sys.exit(main(sys.argv[3:]))
"""


@pytest.mark.slow
@pytest.mark.parametrize(("signum", "code"), SIGNALS)
@pytest.mark.parametrize("hook", ["_object_compiled_hook", "_object_getbuffer_hook"])
def test_signal_while_a_kernel_compiles_stops_with_one_line(tmp_path, hook, signum, code):
    # an empty numba cache and foreground compilation: the fill compiles its first kernel
    # in the process, and the signal comes inside llvmlite's callback; it must not be lost
    # ("Exception ignored on calling ctypes callback function", the fill going on to exit 0)
    pytest.importorskip("numba")
    source = _holey(tmp_path)
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    cache = tmp_path / "numba-cache"
    cache.mkdir()
    env = dict(_sent_signal(tmp_path), NUMBA_CACHE_DIR=str(cache),
               SURFINPAINT_COMPILE="foreground")
    proc = subprocess.Popen([sys.executable, "-c", _SIGNAL_IN_CALLBACK, hook,
                             str(int(signum)), "fill",
                             str(source), "-o", str(out_dir / "filled.ply"), "-q"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    _assert_stopped_after(proc, tmp_path / "sent", code, out_dir)


_SIGNAL_IN_DEL = """
import os, sys
from llvmlite.binding import ffi
real = ffi.ObjectRef.__del__
sent = []
def hooked(self):
    if not sent:
        sent.append(1)
        open(os.environ["SURFINPAINT_TEST_SENT"], "w").close()
        os.kill(os.getpid(), int(sys.argv[1]))
    return real(self)
ffi.ObjectRef.__del__ = hooked
from surfinpaint.app import cli, interrupts
from surfinpaint.app.cli import main
from surfinpaint.app.interrupts import Interrupted, signals_raise
sys.exit(main(sys.argv[2:]))
"""


@pytest.mark.slow
@pytest.mark.parametrize(("signum", "code"), SIGNALS)
def test_signal_in_a_finalizer_while_a_kernel_is_made_stops_with_one_line(tmp_path, signum,
                                                                         code):
    # llvmlite frees its objects in a __del__ (Python code, where an exception cannot
    # propagate: "Exception ignored in ..."); its first one in a fill comes as numba makes
    # the first kernel's dispatcher (compiled.kernel, outside any kernel call: session 44),
    # on a warm cache too. A signal arriving there must not be lost (the fill going on to
    # write its output and exit 0)
    pytest.importorskip("numba")
    source = _holey(tmp_path)
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    proc = subprocess.Popen([sys.executable, "-c", _SIGNAL_IN_DEL, str(int(signum)), "fill",
                             str(source), "-o", str(out_dir / "filled.ply"), "-q"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=_sent_signal(tmp_path))
    _assert_stopped_after(proc, tmp_path / "sent", code, out_dir)


_SIGNAL_IN_GC_CALLBACK = """
import gc, os, signal, sys
sent = []
def callback(phase, info):  # once the command line's handlers are set
    handler = getattr(signal.getsignal(signal.SIGTERM), "__name__", "")
    if phase == "start" and not sent and handler == "_raise_interrupted":
        sent.append(1)
        open(os.environ["SURFINPAINT_TEST_SENT"], "w").close()
        os.kill(os.getpid(), int(sys.argv[1]))
gc.callbacks.append(callback)
from surfinpaint.app.cli import main
sys.exit(main(sys.argv[2:]))
"""


@pytest.mark.slow
@pytest.mark.parametrize(("signum", "code"), SIGNALS)
def test_signal_in_a_gc_callback_during_a_fill_stops_with_one_line(tmp_path, signum, code):
    # a callback the garbage collector runs (exceptions there are only reported), outside
    # any kernel call: on main the fill went on, wrote its output and exited 0 (session 44)
    source = _holey(tmp_path)
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    proc = subprocess.Popen([sys.executable, "-c", _SIGNAL_IN_GC_CALLBACK, str(int(signum)),
                             "fill", str(source), "-o", str(out_dir / "filled.ply"), "-q"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            env=_sent_signal(tmp_path))
    _assert_stopped_after(proc, tmp_path / "sent", code, out_dir)


class _SendsInDel:
    """An object whose ``__del__`` sends ``signum`` to its own process: the handler runs,
    and raises, inside the finalizer, where Python can only report the exception."""

    def __init__(self, signum: int) -> None:
        self.signum = signum

    def __del__(self) -> None:
        os.kill(os.getpid(), self.signum)


@pytest.mark.parametrize(("signum", "code"), SIGNALS)
def test_a_signal_lost_in_a_finalizer_is_sent_again(signum, code):
    # any library's finalizer (zipfile's, at an import in a fill; session 44): the signal
    # must not be lost there, nor every later one ignored
    before = signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)
    with pytest.raises(Interrupted) as raised, signals_raise():
        _SendsInDel(int(signum))  # dropped at once: the handler's exception is lost there
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline:
            time.sleep(0.001)
    assert raised.value.exit_code == code
    assert (signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)) == before
    assert sys.unraisablehook is not interrupts._send_again


class _RaisesInDel:
    """An object whose ``__del__`` raises: Python reports it to ``sys.unraisablehook``."""

    def __del__(self) -> None:
        raise ValueError("not an interruption")


@pytest.mark.parametrize(("signum", "code"), SIGNALS)
def test_a_signal_that_comes_while_the_unraisable_hook_runs_is_sent_again(monkeypatch,
                                                                          signum, code):
    # raised inside the hook it is lost for good (and every later signal ignored: the
    # handler set them so): a Ctrl-C while another exception is reported, or under load
    # the re-send of one lost in a gc callback coming while the hook that started it still
    # waited for its thread to start (session 49: the gc-callback test's failures)
    reported = []

    def previous(unraisable):  # the hook before ours: the signal comes as it reports
        reported.append(unraisable.exc_type)
        os.kill(os.getpid(), signum)
    monkeypatch.setattr(sys, "unraisablehook", previous)
    with pytest.raises(Interrupted) as raised, signals_raise():
        _RaisesInDel()  # dropped at once: reported
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline:
            time.sleep(0.001)
    assert raised.value.exit_code == code and reported == [ValueError]
    assert sys.unraisablehook is previous


@pytest.mark.parametrize(("signum", "code"), SIGNALS)
def test_a_signal_lost_as_the_command_ends_stops_it_with_one_line(monkeypatch, capsys,
                                                                  signum, code):
    # lost in a finalizer and not yet sent again when the command's work is done: raised
    # at the end of signals_raise's block it came out of `main` as a traceback
    monkeypatch.setattr(interrupts, "AGAIN_AFTER", 60.0)  # not sent again before the end

    def run(parser, args, console):
        _SendsInDel(int(signum))
        return 0
    monkeypatch.setattr(cli, "_run", run)
    assert cli.main(["holes", "in.ply"]) == code
    assert capsys.readouterr().err.strip().splitlines() == [
        f"surfinpaint: {Interrupted(signum)}; stopped, no partial output left"]


def test_output_directory_is_checked_before_the_input_is_read(tmp_path):
    # the input is a named pipe nobody writes to: reading it would block for ever, so a
    # prompt exit shows that the output was checked first
    pipe = tmp_path / "never.ply"
    os.mkfifo(pipe)
    bad = [tmp_path / "missing" / "out.ply",      # directory does not exist
           pipe / "out.ply",                       # "directory" is not one
           tmp_path,                               # output is a directory
           Path("/proc/surfinpaint-out.ply")]      # a directory no file can be created in
    for out in bad:
        run = subprocess.run([sys.executable, "-m", "surfinpaint", "fill", str(pipe),
                              "-o", str(out), "-q"], capture_output=True, text=True,
                             timeout=60)
        assert run.returncode == 1, run.stderr
        assert str(out) in "".join(run.stderr.split("\n")), run.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["never.ply"]


def _holey(tmp_path: Path) -> Path:
    v, f = sphere(2)
    cut = cut_holes(v, f, [0], [2.5 * mean_edge_length(v, f)])
    path = tmp_path / "in.ply"
    write_mesh(path, cut.vertices, cut.faces)
    return path


def test_output_naming_the_input_is_refused(tmp_path, capsys):
    source = _holey(tmp_path)
    before = _digest(source)
    link = tmp_path / "link.ply"
    os.link(source, link)
    for out in (source, link, tmp_path / "." / "in.ply"):
        assert main(["fill", str(source), "-o", str(out), "-q"]) == 2
        assert "--in-place" in capsys.readouterr().err
    assert main(["fill", str(source), "-o", str(tmp_path / "a.ply"), "--png",
                 str(tmp_path / "a.ply"), "-q"]) == 2
    assert _digest(source) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.ply", "link.ply"]


def test_in_place_replaces_the_input_with_the_filled_mesh(tmp_path):
    source = _holey(tmp_path)
    v0, f0 = read_mesh(source)
    assert main(["fill", str(source), "-o", str(source), "--in-place", "-q"]) == 0
    v1, f1 = read_mesh(source)
    assert len(f1) > len(f0)
    np.testing.assert_array_equal(v1[:len(v0)], v0)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.ply"]


def test_interrupt_inside_main_returns_130_and_restores_the_handler(tmp_path, capsys,
                                                                     monkeypatch):
    # in-process: a real SIGINT sent to this process once the input has been read
    import surfinpaint.app.cli as cli

    source = _holey(tmp_path)
    out = tmp_path / "out.ply"
    previous = signal.getsignal(signal.SIGINT)
    real_read = cli.read_mesh_data  # what `fill` reads with (attributes included)

    def read_then_interrupt(*args, **kwargs):
        result = real_read(*args, **kwargs)
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(1.0)  # the handler raises here, at the next bytecode of the main thread
        return result

    monkeypatch.setattr(cli, "read_mesh_data", read_then_interrupt)
    assert main(["fill", str(source), "-o", str(out), "-q"]) == 130
    assert capsys.readouterr().err.strip().startswith("surfinpaint: interrupted")
    assert not out.exists()
    assert signal.getsignal(signal.SIGINT) is previous


def test_an_interrupt_between_creating_and_guarding_a_temporary_file_leaves_none(
        tmp_path, monkeypatch):
    # the narrowest window: the temporary file exists, the writer's own clean-up is not
    # armed yet; the command line's remove_unfinished() still finds it
    from surfinpaint.app.interrupts import Interrupted
    from surfinpaint.io import atomic

    real_close = os.close

    def close_then_interrupt(fd):
        real_close(fd)
        raise Interrupted(signal.SIGTERM)

    monkeypatch.setattr(atomic.os, "close", close_then_interrupt)
    with pytest.raises(Interrupted), atomic.atomic_path(tmp_path / "out.ply"):
        pass  # pragma: no cover - never entered
    monkeypatch.undo()
    left = os.listdir(tmp_path)
    assert len(left) == 1 and left[0].startswith(".out.ply.")
    assert atomic.remove_unfinished() == [str(tmp_path / left[0])]
    assert os.listdir(tmp_path) == []


def test_finished_and_failed_writes_leave_nothing_registered(tmp_path):
    from surfinpaint.io import atomic

    with atomic.atomic_open(tmp_path / "a.txt", "w") as handle:
        handle.write("done")
    with pytest.raises(OSError, match="disk full"), atomic.atomic_open(tmp_path / "b.txt", "w"):
        raise OSError("disk full")
    assert atomic.remove_unfinished() == []
    assert sorted(os.listdir(tmp_path)) == ["a.txt"]


def _cut_short_import(signum: int):
    """A picture whose drawing imports a pybind11 extension (matplotlib's) that ``signum``
    interrupts: pybind11 turns any exception raised in a module's initialization into
    ``ImportError("initialization failed")`` caused by it."""
    def draw(*args, **kwargs):
        try:
            os.kill(os.getpid(), signum)
            time.sleep(20)
        except BaseException as exc:
            raise ImportError("initialization failed") from exc
    return draw


@pytest.mark.parametrize(("signum", "code"), SIGNALS)
def test_a_signal_that_cuts_an_import_short_stops_the_command(tmp_path, monkeypatch, capsys,
                                                              signum, code):
    # session 46's fuzz campaign: a SIGTERM while --png imported matplotlib became "picture
    # not drawn: ImportError: initialization failed", a warning, and exit 0
    from surfinpaint.app import figures

    monkeypatch.setattr(figures, "before_after", _cut_short_import(int(signum)))
    source = _holey(tmp_path)
    assert main(["fill", str(source), "-o", str(tmp_path / "out.ply"), "-q",
                 "--png", str(tmp_path / "out.png")]) == code
    err = capsys.readouterr().err
    assert err.strip().splitlines()[-1].startswith("surfinpaint: interrupted"), err
    assert "picture not drawn" not in err
    # a batch's picture, drawn where the file was filled (here: in this process)
    assert main(["batch", str(source), "-o", str(tmp_path / "batch"), "-q", "--png",
                 "--jobs", "1"]) == code
    err = capsys.readouterr().err
    assert err.strip().splitlines()[-1].startswith("surfinpaint: interrupted"), err
    # and where nothing catches the ImportError on the way (the demo's picture)
    assert main(["demo", "-o", str(tmp_path / "demo"), "-q"]) == code
    err = capsys.readouterr().err
    assert err.strip().splitlines()[-1].startswith("surfinpaint: interrupted"), err
    assert "Traceback" not in err and "ImportError" not in err, err


@pytest.mark.parametrize("ignored", [
    pytest.param(None, id="none: the input, a named pipe, is read once"),
    pytest.param(signal.SIGINT, id="SIGINT"), pytest.param(signal.SIGTERM, id="SIGTERM")])
def test_a_signal_inherited_as_ignored_stays_ignored(tmp_path, ignored):
    # a shell script's `surfinpaint fill ... &` starts with SIGINT ignored (as `nohup` does
    # SIGHUP): the script's Ctrl-C must not stop it. The child ignores the signal before it
    # execs Python, as the shell does; it is sent once the fill has opened its input (a
    # named pipe), so well inside the command line's handlers, and the fill ends as usual.
    # With no signal: the fill of a named pipe's mesh is written (it opened the input again
    # to see whether it was ascii, waiting for ever for another writer; session 47)
    source = _holey(tmp_path)
    pipe = tmp_path / "pipe.ply"
    os.mkfifo(pipe)
    out = tmp_path / "out.ply"
    proc = subprocess.Popen(
        [sys.executable, "-m", "surfinpaint", "fill", str(pipe), "-o", str(out), "-q"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        preexec_fn=None if ignored is None else lambda: signal.signal(ignored, signal.SIG_IGN))
    fd = _pipe_opened(proc, pipe)
    if ignored is not None:
        proc.send_signal(ignored)
        time.sleep(0.2)  # the handler, were there one, would raise while the read waits
    _feed(fd, source)
    try:
        _, err = proc.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        pytest.fail("the fill did not end within 60 s")
    assert proc.returncode == 0, err
    assert len(read_mesh(out)[1]) > len(read_mesh(source)[1])


def test_signals_raise_leaves_an_ignored_signal_ignored_and_takes_the_other():
    before = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with pytest.raises(Interrupted) as raised, signals_raise():
            assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
            os.kill(os.getpid(), signal.SIGINT)  # ignored
            os.kill(os.getpid(), signal.SIGTERM)  # still ours
            time.sleep(5)
        assert raised.value.signum == signal.SIGTERM
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, before)


_SIGNAL_IN_AN_IMPORT = """
import atexit, os, signal, sys, time

class SignalsDuringImport:  # sends the signal as `name` starts importing
    def find_spec(self, name, path=None, target=None):
        if name == sys.argv[1]:
            sys.meta_path.remove(self)
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.5)  # a live handler raises here, inside the import
        return None

sys.meta_path.insert(0, SignalsDuringImport())
atexit.register(lambda: print("imported:", sys.argv[1] in sys.modules, file=sys.stderr))
from surfinpaint.app.cli import main
sys.exit(main(sys.argv[2:]))
"""


@pytest.mark.parametrize(("command", "module"), [
    ("fill", "pyvista.plotting"), ("report", "pyvista.plotting"), ("fill", "matplotlib.figure"),
    ("report", "matplotlib.figure")])
def test_a_signal_while_a_drawing_library_is_imported_waits_for_the_import(tmp_path, command,
                                                                           module):
    # session 47: a SIGTERM raised inside VTK's module initialization (pyvista importing its
    # rendering modules for --png) segfaulted in libvtkWrappingPythonCore, 2 of 50 times;
    # the import is now finished first, then the command stops as for any signal; likewise
    # matplotlib's (session 46: pybind11 turned the signal into an ImportError)
    pytest.importorskip("pyvista")
    source = _holey(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    args = (["fill", str(source), "-o", str(out / "f.ply"), "--png", str(out / "f.png")]
            if command == "fill" else ["report", str(source), "-o", str(out / "rep")])
    proc = subprocess.run([sys.executable, "-c", _SIGNAL_IN_AN_IMPORT, module,
                           *args, "-q"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 143, proc.stderr
    assert "imported: True" in proc.stderr and "Traceback" not in proc.stderr, proc.stderr
    # no picture, no page, nothing temporary; `fill` wrote its mesh before the picture
    left = sorted(p.name for p in out.rglob("*") if p.is_file())
    assert left == (["f.ply"] if command == "fill" else [])


def test_signals_held_acts_on_the_signal_after_the_block(tmp_path, monkeypatch):
    (tmp_path / "slow_to_import.py").write_text(
        "import os, signal, time\nos.kill(os.getpid(), signal.SIGTERM)\ntime.sleep(0.5)\n"
        "WHOLE = True\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "slow_to_import", raising=False)
    with pytest.raises(Interrupted) as raised, signals_raise():
        interrupts.imported_whole("slow_to_import")
        time.sleep(5)  # not reached: the signal is acted on as the import returns
    assert raised.value.signum == signal.SIGTERM
    assert sys.modules["slow_to_import"].WHOLE


_SIGNAL_WHILE_THE_COMMAND_LINE_IMPORTS = """
import os, signal, sys, time

SIGNUM = int(sys.argv[1])

class SignalsDuringImport:  # sends the signal as the command line starts importing
    def find_spec(self, name, path=None, target=None):
        if name == "surfinpaint.app.cli":
            sys.meta_path.remove(self)
            os.kill(os.getpid(), SIGNUM)
            time.sleep(0.5)  # Python's default handler acts here, inside the import
        return None

sys.meta_path.insert(0, SignalsDuringImport())
from surfinpaint.app.program import program  # the console script's function
sys.argv = ["surfinpaint", *sys.argv[2:]]
sys.exit(program())
"""


@pytest.mark.parametrize(("signum", "code"), SIGNALS)
def test_a_signal_while_the_command_line_is_imported_stops_with_one_line(tmp_path, signum,
                                                                        code):
    # session 48: before the command's handlers were set, SIGTERM killed the process without
    # a word (-15) and Ctrl-C printed a KeyboardInterrupt traceback from inside an import
    source = _holey(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    proc = subprocess.run([sys.executable, "-c", _SIGNAL_WHILE_THE_COMMAND_LINE_IMPORTS,
                           str(int(signum)), "fill", str(source), "-o", str(out / "f.ply")],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == code, proc.stderr
    name = "Ctrl-C (SIGINT)" if signum == signal.SIGINT else "SIGTERM"
    assert proc.stderr.splitlines() == [
        f"surfinpaint: interrupted by {name}; stopped, no partial output left"]
    assert not list(out.iterdir())


def test_signals_noted_are_raised_by_the_command_or_sent_again_after():
    # noted, then raised where the command's handlers run
    with interrupts.signals_noted():
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(0.1)  # noted only: nothing raised
        with pytest.raises(Interrupted) as raised, signals_raise():
            interrupts.raise_noted()
        interrupts.raise_noted()  # raised once
    assert raised.value.signum == signal.SIGTERM
    # noted and never raised: sent again after the block, to the handler before
    got = []
    before = signal.signal(signal.SIGTERM, lambda signum, frame: got.append(signum))
    try:
        with interrupts.signals_noted():
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(0.1)
            assert got == []
        time.sleep(0.1)
        assert got == [signal.SIGTERM]
    finally:
        signal.signal(signal.SIGTERM, before)
