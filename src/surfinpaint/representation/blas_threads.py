"""The process's BLAS thread-pool controller, for the λ-H solves' one-thread limit."""

from __future__ import annotations

from threadpoolctl import ThreadpoolController

__all__ = ["blas_controller"]

_CONTROLLER: list[ThreadpoolController] = []


def blas_controller() -> ThreadpoolController:
    """The process's thread-pool controller, made at the first λ-H solve (making one lists the
    loaded libraries: 1-7 ms, which ``threadpool_limits`` paid on every solve; BLAS is loaded)."""
    if not _CONTROLLER:
        _CONTROLLER.append(ThreadpoolController())
    return _CONTROLLER[0]
