"""The default simulated scanner's three BLAS calls, computed as the kernels that made the
committed manifests computed them, on every CPU and BLAS (session 38).

``validation_meshes.simulated_scan`` (without ``portable``) normalised its view frame with
``np.linalg.norm`` (a BLAS ``ddot``), projected the mesh with a matmul (``dgemm``) and tested
grazing faces with ``n @ d`` (``dgemv``). Their last bits depend on the kernel: holdout 6's
``scan_clevis`` came out with 7547 vertices against its manifest's 7546, and holdout 5's
``scan_standoff`` with its manifest's counts but every vertex moved by an ulp. Emulating
the candidate arithmetics exactly (``Fraction``) against the manifests' hole centres (which
are vertex positions of the committed meshes, to the bit) found what made them: the
``ddot`` of the view's 3-vector summed with fused multiply-adds (``fma(x2, x2, fma(x1, x1,
x0 x0))``), where this machine's OpenBLAS (0.3.31, Haswell kernels) rounds each product
and sum; the projection and the grazing test as OpenBLAS's Haswell kernels compute them,
chains of fused multiply-adds (the ``dgemm`` over k = 0, 1, 2; the ``dgemv`` over 1, 0, 2,
bit for bit on 20,000 random rows). docs/validation.md, "Session 38 (helper)".

Each is computed here with LLVM's ``llvm.fma.f64`` (numba): one rounding a fused operation,
on a CPU with FMA instructions or without (then the C library's ``fma``, correctly rounded
too), so no BLAS kernel, thread count or CPU changes a bit.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

__all__ = ["fma_norm", "fma_rows_dot", "fused_multiply_add"]


@intrinsic
def _fma(typingctx, a, b, c):  # pragma: no cover - compiled
    """``a b + c`` rounded once (LLVM's ``llvm.fma.f64``)."""
    signature = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, sig, args):
        double = ir.DoubleType()
        function = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(double, [double, double, double]), "llvm.fma.f64")
        return builder.call(function, args)

    return signature, codegen


@njit(cache=True)
def _rows_dot(rows, columns, order):  # pragma: no cover - compiled
    """``rows @ columns`` (k = 3 terms each), each entry ``fma(r[k3] c[k3], fma(r[k2] c[k2],
    r[k1] c[k1]))`` for ``order = (k1, k2, k3)``: the first product rounded, then two fused
    multiply-adds."""
    out = np.empty((rows.shape[0], columns.shape[1]))
    k1, k2, k3 = order[0], order[1], order[2]
    for i in range(rows.shape[0]):
        for j in range(columns.shape[1]):
            s = rows[i, k1] * columns[k1, j]
            s = _fma(rows[i, k2], columns[k2, j], s)
            out[i, j] = _fma(rows[i, k3], columns[k3, j], s)
    return out


@njit(cache=True)
def fused_multiply_add(a, b, c):  # pragma: no cover - compiled
    """``a b + c`` rounded once, elementwise over 1-D float arrays (for the tests)."""
    out = np.empty(a.shape[0])
    for i in range(a.shape[0]):
        out[i] = _fma(a[i], b[i], c[i])
    return out


def fma_rows_dot(rows: np.ndarray, columns: np.ndarray, order=(0, 1, 2)) -> np.ndarray:
    """``rows @ columns`` for ``(n, 3)`` rows and ``(3, m)`` (or ``(3,)``) columns, summed in
    ``order`` as a chain of fused multiply-adds (:func:`_rows_dot`); ``(n, m)`` (or ``(n,)``)."""
    columns = np.asarray(columns, np.float64)
    vector = columns.ndim == 1
    out = _rows_dot(np.ascontiguousarray(rows, np.float64),
                    np.ascontiguousarray(columns[:, None] if vector else columns),
                    np.asarray(order, np.int64))
    return out[:, 0] if vector else out


def fma_norm(vector) -> float:
    """The length of a 3-vector, its squares summed as ``fma(x2, x2, fma(x1, x1, x0 x0))``."""
    x = np.asarray(vector, np.float64).reshape(1, 3)
    return math.sqrt(float(fma_rows_dot(x, x[0])[0]))
