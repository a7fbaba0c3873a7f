"""A Dask worker preload for ``surfinpaint batch --dask-scheduler``:

    dask worker tcp://scheduler:8786 --nworkers auto --nthreads 1 \\
        --preload surfinpaint.app.dask_worker

A worker started so imports the batch code and loads the compiled kernels while it starts,
not when its first file arrives: a freshly started worker otherwise spends about 1 CPU
second on them inside the first file's task (measured in ``benchmarks/batch.py``, which
runs its cluster both ways).
"""

from __future__ import annotations

from typing import Any

import surfinpaint.app.batch  # noqa: F401 - imported for the worker, the point of a preload
from surfinpaint.fill.warmup import warm_kernels

__all__ = ["dask_setup"]


def dask_setup(worker: Any = None) -> None:
    """Called by Dask when the worker starts (a preload's entry point): load the kernels of
    the conformal method (they include the faired fill's)."""
    warm_kernels("conformal")
