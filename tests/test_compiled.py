"""Numba kernels: cached on disk across processes, the first compilation announced once,
and a kernel without any cache location still compiled (surfinpaint/compiled.py)."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("numba")

from surfinpaint.compiled import COMPILING_MESSAGE, Kernel, kernel  # noqa: E402

SRC = str(Path(__file__).resolve().parents[1] / "src")

SCRIPT = """
import logging, sys
logging.basicConfig(level=logging.INFO, format="%(name)s: %(message)s", stream=sys.stderr)
sys.path.insert(0, {moddir!r})
from surfinpaint.compiled import Kernel
import kernels
twice, add = Kernel(kernels.twice), Kernel(kernels.add)
values = twice.get()(21), add.get()(1, 2)
print(*values, *[sum(k.get().stats.cache_hits.values()) for k in (twice, add)])
"""


def _run(tmp_path: Path, cache: Path) -> subprocess.CompletedProcess:
    moddir = tmp_path / "mods"
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), PYTHONPATH=SRC)
    return subprocess.run([sys.executable, "-c", SCRIPT.format(moddir=str(moddir))], env=env,
                          capture_output=True, text=True, timeout=300, check=True)


def test_kernels_are_cached_across_processes_and_the_compile_is_told_once(tmp_path):
    moddir = tmp_path / "mods"
    moddir.mkdir()
    (moddir / "kernels.py").write_text(textwrap.dedent("""
        def twice(x):
            return 2 * x

        def add(a, b):
            return a + b
    """))
    cache = tmp_path / "cache"
    first = _run(tmp_path, cache)
    out = first.stdout.split()
    assert out == ["42", "3", "0", "0"]
    assert first.stderr.count(COMPILING_MESSAGE) == 1, first.stderr  # two kernels, one line
    assert "surfinpaint: " + COMPILING_MESSAGE in first.stderr
    assert list(cache.rglob("kernels.twice-*.nbi")) and list(cache.rglob("kernels.add-*.nbi"))
    second = _run(tmp_path, cache)
    assert second.stdout.split() == ["42", "3", "1", "1"]  # both loaded from the cache
    assert COMPILING_MESSAGE not in second.stderr  # nothing compiled: nothing to say


def test_a_kernel_with_no_cache_location_is_compiled_in_memory():
    namespace: dict = {}
    # source that lives in no file: numba has no place to cache it and refuses cache=True
    exec(compile("def triple(x):\n    return 3 * x\n", "<no file>", "exec"), namespace)
    fn = kernel(namespace["triple"])
    assert fn(np.int64(5)) == 15


def test_kernel_is_built_once():
    k = Kernel(lambda x: x + 1)
    assert k.get() is k.get()


def test_the_command_line_says_once_that_it_compiles(tmp_path):
    # a fresh numba cache: the first fill compiles (and says so once), the second does not
    from surfinpaint.data import sphere
    from surfinpaint.geometry.cutting import cut_geodesic_disk
    from surfinpaint.io import write_mesh

    v, f = sphere(2)
    cut = cut_geodesic_disk(v, f, 0, 0.5)
    source = tmp_path / "holed.ply"
    write_mesh(source, cut.vertices, cut.faces)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"), PYTHONPATH=SRC)
    command = [sys.executable, "-m", "surfinpaint", "fill", str(source), "-o",
               str(tmp_path / "out.ply"), "--method", "fair"]
    runs = [subprocess.run(command, env=env, capture_output=True, text=True, timeout=600)
            for _ in range(2)]
    assert [r.returncode for r in runs] == [0, 0], runs[0].stderr
    assert runs[0].stderr.count(COMPILING_MESSAGE) == 1, runs[0].stderr
    assert COMPILING_MESSAGE not in runs[1].stderr, runs[1].stderr
