"""Shared test fixtures: small meshes with known structure.

Each fixture returns fresh ``(vertices, faces)`` arrays (float64 (n, 3), int64 (f, 3)).
The helper functions are importable too (``from conftest import grid_mesh``).
"""

from __future__ import annotations

import os
import signal

import numpy as np
import pytest

# the kernels' tests compare them with their numpy versions: compiled in the test processes
# (and their subprocesses), never stood in for by the numpy versions while a background
# process compiles them (surfinpaint/compiled.py; tests/test_compiled.py tests that mode)
os.environ["SURFINPAINT_COMPILE"] = "foreground"

# a test run started in a script's background (`pytest &`, nohup under a non-interactive
# shell) inherits SIGINT ignored, and the command line keeps an inherited ignored signal
# ignored (session 47): the tests that send SIGINT, here and to their subprocesses (which
# start with the default once this process has a handler), take it back
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


def grid_mesh(nx: int = 4, ny: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """A flat (nx+1) x (ny+1) vertex grid in z = 0, two triangles per cell, normals +z."""
    i, j = np.meshgrid(np.arange(nx + 1), np.arange(ny + 1), indexing="ij")
    vertices = np.column_stack([i.ravel() / nx, j.ravel() / ny, np.zeros(i.size)])
    a = (i[:-1, :-1] * (ny + 1) + j[:-1, :-1]).ravel()
    b, c, d = a + (ny + 1), a + (ny + 1) + 1, a + 1
    faces = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return vertices, faces.astype(np.int64)


def tetrahedron_mesh() -> tuple[np.ndarray, np.ndarray]:
    """A closed, consistently outward-oriented tetrahedron."""
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int64)
    return vertices, faces


def shuffled_mesh(seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """A bumpy grid with randomly permuted vertex ids, full-precision float64 coordinates
    and two unreferenced vertices (one at the front, one in the middle): the vertex order is
    nothing a loader could reconstruct by itself."""
    rng = np.random.default_rng(seed)
    v, f = grid_mesh(5, 4)
    v = v + rng.normal(scale=0.01, size=v.shape)
    v[:, 2] += 0.1 * np.sin(3 * v[:, 0]) + np.pi / 7
    n = len(v)
    extra = np.array([[1e6 / 3, -np.e, 1e-7], [np.sqrt(2), 2.0**-30, -0.0]])
    # new position of every old vertex; positions 0 and n//2 stay free for the extras
    slots = np.setdiff1d(np.arange(n + 2), [0, n // 2])
    new_of_old = rng.permutation(slots)
    vertices = np.empty((n + 2, 3))
    vertices[new_of_old] = v
    vertices[0], vertices[n // 2] = extra
    faces = new_of_old[f]
    return vertices, faces.astype(np.int64)


@pytest.fixture
def grid() -> tuple[np.ndarray, np.ndarray]:
    return grid_mesh()


@pytest.fixture
def tetrahedron() -> tuple[np.ndarray, np.ndarray]:
    return tetrahedron_mesh()


@pytest.fixture
def shuffled() -> tuple[np.ndarray, np.ndarray]:
    return shuffled_mesh()


# five holes far apart and a sixth next to the fifth (0.53 rad from it: inside the
# conformal method's neighbourhood of a 12-edge hole, outside the faired fill's 3 rings)
SIX_HOLES = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0.5, 0.0, 0.85)]


@pytest.fixture(scope="module")
def holed():
    """A sphere (``sphere(4)``) with the holes of ``SIX_HOLES``: vertices, faces, loops
    (the parallel fills' tests: the sixth hole is filled after the fifth)."""
    from surfinpaint.data import sphere
    from surfinpaint.geometry.cutting import cut_holes

    vertices, faces = sphere(4)
    centers = [np.array(c) / np.linalg.norm(c) for c in SIX_HOLES]
    cut = cut_holes(vertices, faces, centers, 0.2)
    return cut.vertices, cut.faces, [h.loop for h in cut.holes]


def mark_fill_starts(monkeypatch, batch, say) -> None:
    """Make ``batch.fill_file`` call ``say(job)`` as each file's fill starts in this process
    (the batch tests' way of seeing the order of fills and messages)."""
    filled = batch.fill_file

    def marked(job, options, hole_progress=None):
        say(job)
        return filled(job, options, hole_progress)

    monkeypatch.setattr(batch, "fill_file", marked)


@pytest.fixture
def on_forked_workers(monkeypatch) -> list[int]:
    """Holes filled on worker processes whatever their size (the size rule set aside), the
    workers forked (as a one-thread process's are: they inherit the test's patches); the
    calls of ``fill_holes`` that used them, counted (one 1 each)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    from surfinpaint.fill import parallel, pipeline

    monkeypatch.setattr(parallel, "MIN_PARALLEL_EDGES", {"fair": 0, "conformal": 0})
    # forked whatever other threads an earlier test of this process left running (the
    # scheduler asks parallel.forks() whether the workers inherit its jobs and stage queue)
    monkeypatch.setattr(parallel, "forks", lambda: True)
    context = multiprocessing.get_context("fork")
    monkeypatch.setattr(parallel, "pool", lambda workers: ProcessPoolExecutor(
        workers, mp_context=context))
    used: list[int] = []
    in_parallel = pipeline.fill_in_parallel
    monkeypatch.setattr(pipeline, "fill_in_parallel",
                        lambda *args: used.append(1) or in_parallel(*args))
    return used
