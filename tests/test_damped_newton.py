"""Damped Newton's method (representation/damped_newton.py): when a backtracking that finds
no lower residual means convergence."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from surfinpaint.representation.damped_newton import damped_newton


class FlatResidual:
    """A residual stuck at ``level`` whatever φ (no step lowers it), a Jacobian ``slope``·I
    that makes every Newton step long, and a rounding level of ``rounding``."""

    def __init__(self, level: float, slope: float, rounding: float):
        self.level, self.slope, self._rounding = level, slope, rounding
        self.idx = np.arange(6)

    def residual(self, phi, t):
        return np.full(6, self.level)

    def jacobian(self, phi, t):
        return sp.identity(6, format="csc") * self.slope, None

    def factorized(self, J):
        return spla.factorized(J)

    def rounding(self, phi, t):
        return self._rounding


@pytest.mark.parametrize(("level", "rounding", "converged"), [
    (1e-17, 1e-15, True),    # at rounding level: nothing to gain, the point is the answer
    (1e-15, 1e-15 * np.sqrt(6) * 0.99, False),  # just above it: a real failure
    (1e-6, 1e-15, False),    # far above it
])
def test_a_stuck_backtracking_converges_only_at_the_rounding_level(level, rounding,
                                                                   converged):
    system = FlatResidual(level, slope=1e-9, rounding=rounding)
    start = np.zeros((2, 3))
    x, ok, steps, last = damped_newton(system, start, 1.0, tol=1e-10, budget=5, scale=1.0)
    assert ok is converged
    assert steps == 1 and np.isinf(last)  # the first step could not be taken
    np.testing.assert_array_equal(x, start)


def test_a_short_full_step_converges_and_is_taken():
    """A linear system: one full step solves it, the next is below tol."""

    class Linear(FlatResidual):
        def residual(self, phi, t):
            return phi.ravel()[self.idx] - 1.0

    system = Linear(0.0, slope=1.0, rounding=0.0)
    x, ok, steps, _ = damped_newton(system, np.zeros((2, 3)), 1.0, tol=1e-10, budget=5,
                                    scale=1.0)
    assert ok and steps == 2
    np.testing.assert_allclose(x, 1.0, rtol=0, atol=1e-15)
