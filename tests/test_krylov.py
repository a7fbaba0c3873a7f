"""representation.krylov.gmres_cycle: one GMRES cycle, checked against dense solves and
against SciPy's GMRES on the same Krylov spaces."""

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from surfinpaint.representation.krylov import gmres_cycle


def _counted(A):
    calls = [0]

    def matvec(v):
        calls[0] += 1
        return A @ v
    return matvec, calls


def _nonsymmetric(n, seed=0):
    rng = np.random.default_rng(seed)
    return np.eye(n) + 0.4 * rng.standard_normal((n, n)) / np.sqrt(n), rng.standard_normal(n)


def test_it_reaches_the_tolerance_and_reports_the_true_residual():
    A, b = _nonsymmetric(80)
    matvec, calls = _counted(A)
    x, residual = gmres_cycle(matvec, b, 1e-8, 80)
    true = np.linalg.norm(A @ x - b) / np.linalg.norm(b)
    assert true <= 1e-8
    assert residual == pytest.approx(true, rel=1e-3, abs=1e-14)
    assert calls[0] < 80  # stopped at the tolerance, not at the basis' size
    assert np.allclose(x, np.linalg.solve(A, b), rtol=1e-6, atol=1e-8)


@pytest.mark.parametrize("size", [5, 20])
def test_a_short_cycle_gives_scipys_iterate(size):
    # the least-residual x of the same Krylov space: SciPy's one restart cycle, without its
    # last product (the true residual it checks)
    A, b = _nonsymmetric(60, seed=1)
    matvec, calls = _counted(A)
    x, residual = gmres_cycle(matvec, b, 1e-12, size)
    ref, _ = spla.gmres(spla.LinearOperator(A.shape, matvec=lambda v: A @ v, dtype=float), b,
                        rtol=1e-12, restart=size, maxiter=1)
    assert calls[0] == size
    assert np.allclose(x, ref, rtol=1e-10, atol=1e-12)
    assert residual == pytest.approx(np.linalg.norm(A @ x - b) / np.linalg.norm(b), rel=1e-8)


def test_an_invariant_subspace_ends_the_cycle_exactly():
    A = np.diag([2.0, 2.0, 5.0, 5.0])
    b = np.array([1.0, -1.0, 0.0, 0.0])  # A b = 2 b: one product
    matvec, calls = _counted(A)
    x, residual = gmres_cycle(matvec, b, 1e-3, 10)
    assert calls[0] == 1
    assert np.allclose(x, b / 2.0) and residual < 1e-15


def test_a_singular_operator_gives_the_least_residual_it_can():
    A = np.diag([1.0, 0.0])
    b = np.array([1.0, 1.0])  # the second component is out of reach
    x, residual = gmres_cycle(lambda v: A @ v, b, 1e-6, 5)
    assert np.isfinite(x).all()
    assert np.allclose(A @ x, [1.0, 0.0])  # x itself is not unique
    assert residual == pytest.approx(1.0 / np.sqrt(2.0))


def test_a_zero_right_hand_side_gives_zero():
    x, residual = gmres_cycle(lambda v: 3.0 * v, np.zeros(4), 1e-3, 10)
    assert np.array_equal(x, np.zeros(4)) and residual == 0.0
