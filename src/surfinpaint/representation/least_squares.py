"""A small Levenberg–Marquardt solver for ``min ½‖r(x)‖²``, for the λ-H fill's last stage.

Where the coupled λ-H system has no root near the start (the inpainted λ and H are not the
data of a surface there: docs/convergence.md), Newton's method stops with "no step lowers its
residual". Levenberg–Marquardt steps ``(JᵀJ + μI) dx = −Jᵀr`` are descent directions for
``‖r‖²`` at every ``μ > 0``, so they go on to the nearest local minimum of the residual
instead: the root where there is one, and otherwise the point whose residual is smallest.

``μ`` follows Nielsen's rule (H. B. Nielsen, *Damping parameter in Marquardt's method*,
IMM-REP-1999-05): after a step that lowers ``‖r‖²`` by a fraction ρ of what the linear
model predicts, ``μ ← μ · max(1/3, 1 − (2ρ − 1)³)``; after one that does not, ``μ ← μ ν``,
``ν ← 2ν``. Each step is at most ``max_step`` long (max-norm), scaled down otherwise. The
Jacobian is dense, the caller's or forward differences (one residual a column); the
systems are the fill's free coordinates, a few hundred unknowns.

Also here: :class:`AndersonMixing`, the acceleration of the λ-H fill's lagged iteration.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["AndersonMixing", "LeastSquares", "forward_jacobian", "levenberg_marquardt"]


@dataclass(frozen=True)
class LeastSquares:
    """The outcome of :func:`levenberg_marquardt`.

    Attributes
    ----------
    x : (n,) float array
        The point reached.
    residual : (m,) float array
        ``r(x)``.
    steps : int
        Accepted steps.
    evaluations : int
        Residual evaluations, the Jacobians' included.
    converged : bool
        Stopped because the residual, the gradient or the step became small (a root or a
        stationary point of ``‖r‖²``), not because the steps or evaluations ran out.
    """

    x: np.ndarray
    residual: np.ndarray
    steps: int
    evaluations: int
    converged: bool

    @property
    def size(self) -> float:
        """The residual's largest entry, in absolute value."""
        return float(np.abs(self.residual).max()) if self.residual.size else 0.0


def forward_jacobian(residual: Callable[[np.ndarray], np.ndarray], x: np.ndarray,
                     r: np.ndarray, eps: float) -> np.ndarray:
    """The (m, n) Jacobian of ``residual`` at ``x`` (where it is ``r``) by forward
    differences of step ``eps``."""
    J = np.empty((r.size, x.size))
    for j in range(x.size):
        step = x.copy()
        step[j] += eps
        J[:, j] = (residual(step) - r) / eps
    return J


def levenberg_marquardt(
    residual: Callable[[np.ndarray], np.ndarray],
    x0: np.ndarray,
    *,
    jacobian: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
    steps: int = 30,
    evaluations: int | None = None,
    jacobians: int | None = None,
    max_step: float = np.inf,
    tol: float = 1e-8,
    eps: float = 1e-6,
) -> LeastSquares:
    """A local minimum of ``½‖residual(x)‖²`` from ``x0`` by Levenberg–Marquardt steps.

    Parameters
    ----------
    residual : callable
        ``r(x)``, an (m,) array from an (n,) one. It may raise ``ArithmeticError`` or
        ``ValueError`` (or return non-finite values) for a trial point: that step is
        rejected like one that does not lower the residual.
    x0 : (n,) float array
    jacobian : callable, optional
        ``J(x, r)``, the (m, n) Jacobian; by default forward differences of step ``eps``.
    steps : int
        Accepted steps at most.
    evaluations : int, optional
        Residual evaluations at most (forward-difference Jacobians' included): a bound on
        the cost.
    jacobians : int, optional
        Jacobians at most (the first included): the solver stops at the accepted step that
        would need one more.
    max_step : float
        The longest step (max-norm); longer ones are scaled down.
    tol : float
        Stop when the residual's largest entry, the gradient ``Jᵀr`` relative to ``‖r‖²``,
        or the step falls below it.
    eps : float
        The forward-difference step.

    Returns
    -------
    LeastSquares
    """
    x = np.array(x0, dtype=float)
    r = np.asarray(residual(x), dtype=float)
    count = 1
    budget = np.inf if evaluations is None else evaluations
    jac = jacobian or (lambda x, r: forward_jacobian(residual, x, r, eps))
    made = 0
    most = np.inf if jacobians is None else jacobians

    def jacobian_at(x, r):
        nonlocal count, made
        count += 0 if jacobian else x.size
        made += 1
        return jac(x, r)

    J = jacobian_at(x, r)
    A, g = J.T @ J, J.T @ r
    mu, nu = 1e-3 * max(float(np.diag(A).max(initial=0.0)), 1e-12), 2.0
    accepted = 0
    converged = False
    while accepted < steps and count < budget:
        cost = float(r @ r)
        if float(np.abs(r).max(initial=0.0)) < tol or float(np.abs(g).max(initial=0.0)) \
                <= tol * max(cost, 1e-300):
            converged = True
            break
        dx = np.linalg.solve(A + mu * np.eye(x.size), -g)
        longest = float(np.abs(dx).max())
        if longest > max_step:
            dx *= max_step / longest
        if float(np.abs(dx).max()) < tol * (1.0 + float(np.abs(x).max())):
            converged = True
            break
        predicted = -(2.0 * float(g @ dx) + float(dx @ (A @ dx)))  # cost − ‖r + J dx‖²
        try:
            trial = np.asarray(residual(x + dx), dtype=float)
        except (ArithmeticError, ValueError):
            trial = None
        count += 1
        if trial is not None and np.isfinite(trial).all() and predicted > 0:
            rho = (cost - float(trial @ trial)) / predicted
        else:
            rho = -1.0
        if rho > 0:
            x, r = x + dx, trial
            accepted += 1
            mu *= max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0) ** 3)
            nu = 2.0
            if accepted < steps and made < most and \
                    count + (0 if jacobian else x.size) < budget:
                J = jacobian_at(x, r)
                A, g = J.T @ J, J.T @ r
            else:
                break
        else:
            mu *= nu
            nu *= 2.0
    return LeastSquares(x=x, residual=r, steps=accepted, evaluations=count,
                        converged=converged)


class AndersonMixing:
    """Anderson mixing of the last ``depth`` steps of a fixed-point iteration: the lagged
    iteration is nearly linear near its fixed point, and this takes it there in fewer
    solves."""

    def __init__(self, depth: int):
        self.depth = depth
        self.previous = None  # (residual, solution) of the last step
        self.d_res: list = []
        self.d_new: list = []

    def mix(self, new: np.ndarray, current: np.ndarray) -> np.ndarray:
        """The next iterate from the iteration's ``new`` one and the ``current`` one."""
        residual, flat = (new - current).ravel(), new.ravel()
        if self.previous is not None:
            self.d_res.append(residual - self.previous[0])
            self.d_new.append(flat - self.previous[1])
            del self.d_res[:-self.depth], self.d_new[:-self.depth]
            gamma = np.linalg.lstsq(np.column_stack(self.d_res), residual, rcond=None)[0]
            new = (flat - np.column_stack(self.d_new) @ gamma).reshape(new.shape)
        self.previous = (residual, flat)
        return new
