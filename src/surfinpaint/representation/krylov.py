"""One cycle of GMRES for Newton–Krylov's steps on large patches
(:func:`surfinpaint.representation.on_mesh.newton_solve`).

Why not ``scipy.sparse.linalg.gmres``: its Arnoldi step orthogonalizes against the basis
one vector at a time (modified Gram–Schmidt) and updates its Givens rotations by fancy
indexing, a few dozen small numpy calls per basis vector in Python; on the λ-H fill's
patches (600-1300 unknowns, 30-60 products a step of 0.3-0.6 ms) that cost about as much
as the products themselves (docs/convergence.md, session 31). Here each Arnoldi step is
four matrix-vector products with the whole basis (classical Gram–Schmidt applied twice,
"CGS2", which orthogonalizes as well as modified Gram–Schmidt does: Giraud, Langou,
Rozložník & van den Eshof 2005), and the rotations are applied to one column in Python
floats. The iterates are GMRES's (Saad & Schultz 1986), with another rounding.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import scipy.linalg as sla

__all__ = ["gmres_cycle"]


def gmres_cycle(matvec: Callable[[np.ndarray], np.ndarray], b: np.ndarray, rtol: float,
                size: int) -> tuple[np.ndarray, float]:
    """The x of least residual ``|A x − b|`` in the Krylov space ``span{b, A b, …,
    A^(k−1) b}``, for the least k at which that residual is at most ``rtol |b|``, or
    k = ``size`` (one GMRES cycle from x = 0, not restarted).

    Parameters
    ----------
    matvec : callable
        ``A v`` for an (n,) vector ``v``.
    b : (n,) float array
    rtol : float
        The relative residual that ends the cycle.
    size : int
        At most this many products (the basis' size); ``min(size, n)`` are taken.

    Returns
    -------
    x : (n,) float array
    residual : float
        ``|A x − b| / |b|`` as the rotated least-squares problem gives it (no product is
        spent on checking it); 0 for ``b = 0``.

    Examples
    --------
    >>> A = np.array([[4.0, 1.0], [0.0, 3.0]])
    >>> x, res = gmres_cycle(lambda v: A @ v, np.array([1.0, 2.0]), 1e-12, 10)
    >>> bool(np.allclose(A @ x, [1.0, 2.0])), res < 1e-12
    (True, True)
    """
    b = np.asarray(b, dtype=float)
    beta = float(np.linalg.norm(b))
    if beta == 0.0:
        return np.zeros_like(b), 0.0
    size = max(1, min(int(size), b.size))
    basis = np.empty((size + 1, b.size))
    basis[0] = b / beta
    upper = np.zeros((size, size))  # the Hessenberg matrix, rotated to upper triangular
    cosines: list[float] = []
    sines: list[float] = []
    g = [beta]  # the rotated right-hand side β e₁; |g[k]| is the residual after k products
    target = rtol * beta
    k = 0
    while k < size:
        w = np.asarray(matvec(basis[k]), dtype=float).ravel()
        scale = float(np.linalg.norm(w))
        Vk = basis[:k + 1]
        h = Vk @ w
        w -= h @ Vk
        again = Vk @ w  # the second pass takes out what rounding left in the first
        w -= again @ Vk
        h += again
        below = float(np.linalg.norm(w))
        column = h.tolist()
        for i, (c, s) in enumerate(zip(cosines, sines, strict=True)):
            a, d = column[i], column[i + 1]
            column[i], column[i + 1] = c * a + s * d, c * d - s * a
        rho = math.hypot(column[k], below)
        c, s = (column[k] / rho, below / rho) if rho > 0.0 else (1.0, 0.0)
        column[k] = rho
        cosines.append(c)
        sines.append(s)
        g.append(-s * g[k])
        g[k] *= c
        upper[:k + 1, k] = column
        k += 1
        # an invariant subspace (the residual is exact, and zero): no next basis vector
        if abs(g[k]) <= target or below <= 1e-14 * scale or k == size:
            break
        basis[k] = w / below
    diagonal = np.abs(np.diag(upper[:k, :k]))
    keep = k
    while keep > 1 and diagonal[keep - 1] <= 1e-300:  # a singular A: the columns before
        keep -= 1
    y = sla.solve_triangular(upper[:keep, :keep], np.asarray(g[:keep]), check_finite=False)
    return y @ basis[:keep], abs(g[keep]) / beta
