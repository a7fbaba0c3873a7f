"""A Dask worker preload for ``surfinpaint batch --dask-scheduler``, the way to start its
workers:

    dask worker tcp://scheduler:8786 --nworkers auto --nthreads 1 \\
        --preload surfinpaint.app.dask_worker

A worker started so is set up for filling files, one after another, while it starts:

- it imports the batch code and loads the compiled kernels, instead of doing it inside its
  first file (about 1 CPU second on the run's critical path);
- glibc's allocator keeps freed memory of up to 64 MB for reuse, and serves arrays below
  32 MB from it: Dask's nanny starts every worker with ``MALLOC_TRIM_THRESHOLD_=65536``,
  which also fixes the threshold above which an allocation is a fresh ``mmap`` at 128 kB,
  so that every larger numpy array was mapped, zeroed page by page and unmapped again
  (about 360,000 page faults per worker for 20 files of ``benchmarks/batch.py``, against
  50,000 in a local worker; about 4,600 with this setting);
- the worker's statistical profiler (the dashboard's "Profile" page) is not started: every
  10 ms it takes the interpreter lock from the file's thread to walk its stack.

Together the last two cut a file's CPU on a Dask worker from about 1.6x that on a local
worker to about 1.1x (``benchmarks/batch_trace.py --dask``, docs/batch.md).
"""

from __future__ import annotations

import ctypes
import platform
from typing import Any

import surfinpaint.app.batch  # noqa: F401 - imported for the worker, the point of a preload
from surfinpaint.fill.warmup import warm_kernels

__all__ = ["dask_setup", "keep_freed_memory"]

# glibc's mallopt parameters (malloc.h) and the values set: 32 MB is the largest mmap
# threshold glibc accepts (half its heap size), and its own dynamic threshold's ceiling
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
MMAP_THRESHOLD, TRIM_THRESHOLD = 32 * 2**20, 64 * 2**20


def keep_freed_memory() -> bool:
    """Set glibc's allocator to reuse freed memory (arrays below ``MMAP_THRESHOLD`` from
    the heap, trimmed above ``TRIM_THRESHOLD`` free); whether it was set (False where the C
    library is not glibc)."""
    if platform.system() != "Linux" or platform.libc_ver()[0] != "glibc":
        return False
    try:
        libc = ctypes.CDLL("libc.so.6")
    except OSError:
        return False
    return bool(libc.mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD)) and \
        bool(libc.mallopt(_M_TRIM_THRESHOLD, TRIM_THRESHOLD))


def dask_setup(worker: Any = None) -> None:
    """Called by Dask when the worker starts (a preload's entry point), before its periodic
    callbacks start: load the kernels of the conformal method (they include the faired
    fill's), keep freed memory for reuse, leave the statistical profiler off."""
    warm_kernels("conformal")
    keep_freed_memory()
    callbacks = getattr(worker, "periodic_callbacks", None)
    if isinstance(callbacks, dict):
        for name in ("profile", "profile-cycle"):
            callbacks.pop(name, None)
