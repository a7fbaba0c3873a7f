"""The dense solve in mixed precision (geometry.linalg.refined_solve, session 34 helper): a
float32 LU refined with float64 residuals reaches float64's accuracy, and says so (None)
where it cannot."""

import numpy as np
import pytest

from surfinpaint.geometry import linalg
from surfinpaint.geometry.linalg import refined_solve


def _conditioned(n, condition, seed):
    """A random (n, n) matrix with singular values from 1 down to 1/condition, C order."""
    rng = np.random.default_rng(seed)
    u, _ = np.linalg.qr(rng.standard_normal((n, n)))
    v, _ = np.linalg.qr(rng.standard_normal((n, n)))
    return np.ascontiguousarray((u * np.geomspace(1.0, 1.0 / condition, n)) @ v.T)


@pytest.mark.parametrize("condition", [1e2, 1e5])
def test_refinement_reaches_float64_accuracy_on_an_ill_conditioned_matrix(condition):
    A = _conditioned(120, condition, 1)
    x_true = np.random.default_rng(2).standard_normal(120)
    b = A @ x_true
    before = A.copy()
    x = refined_solve(A, b)
    assert x is not None
    assert np.array_equal(A, before)  # A is not overwritten
    # float64's backward error (dsgesv's test), and float64 LU's forward error
    eps = np.finfo(float).eps
    norm = np.abs(A).sum(axis=1).max()
    assert np.abs(b - A @ x).max() <= np.sqrt(120) * norm * np.abs(x).max() * eps
    lapack = np.linalg.solve(A, b)
    error = np.abs(x - x_true).max() / np.abs(x_true).max()
    assert error <= max(4.0 * np.abs(lapack - x_true).max() / np.abs(x_true).max(), 8 * eps)
    assert np.abs(x - lapack).max() <= 10 * condition * eps * np.abs(lapack).max()
    # the float32 solution alone is far from it: the refinement is what gives the digits
    single = np.linalg.solve(A.astype(np.float32), b.astype(np.float32))
    assert np.abs(single - x_true).max() / np.abs(x_true).max() > 1e3 * max(error, eps)


def test_refinement_gives_up_where_float32_cannot_factor_the_matrix():
    # condition 1e10 > 1/ε₃₂: the float32 factors do not contract the error
    A = _conditioned(80, 1e10, 3)
    assert refined_solve(A, A @ np.ones(80)) is None
    # singular in float32 (a zero column)
    B = _conditioned(40, 10.0, 4)
    B[:, 7] = 0.0
    assert refined_solve(B, np.ones(40)) is None
    # not finite
    C = _conditioned(40, 10.0, 5)
    C[3, 3] = np.nan
    assert refined_solve(C, np.ones(40)) is None


def test_refinement_gives_up_after_its_step_count(monkeypatch):
    A = _conditioned(60, 1e5, 6)
    b = A @ np.ones(60)
    monkeypatch.setattr(linalg, "REFINEMENT_STEPS", 1)  # one correction is not enough
    assert refined_solve(A, b) is None
    monkeypatch.setattr(linalg, "REFINEMENT_STEPS", 10)
    assert refined_solve(A, b) is not None
