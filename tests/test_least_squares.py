"""The Levenberg–Marquardt solver of the λ-H fill's last stage
(:mod:`surfinpaint.representation.least_squares`): the least-squares point where a system has
no root, the root where it has one, and its bound on the step."""

import numpy as np

from surfinpaint.representation.least_squares import forward_jacobian, levenberg_marquardt


def test_an_inconsistent_linear_system_ends_at_its_least_squares_solution():
    rng = np.random.default_rng(3)
    A, b = rng.normal(size=(7, 3)), rng.normal(size=7)
    best, *_ = np.linalg.lstsq(A, b, rcond=None)
    assert np.linalg.norm(A @ best - b) > 0.5  # no root
    out = levenberg_marquardt(lambda x: A @ x - b, np.zeros(3), tol=1e-12)
    assert out.converged
    np.testing.assert_allclose(out.x, best, atol=1e-7)
    np.testing.assert_allclose(out.residual, A @ best - b, atol=1e-7)


def test_a_square_system_without_a_root_ends_at_its_least_squares_minimum():
    # x0² + 1 = 0 has no real root: Newton's method from x0 = 1 lands on x0 = 0, where the
    # Jacobian is singular; the least-squares minimum is (0, 2) with residual (1, 0)
    def residual(x):
        return np.array([x[0] ** 2 + 1.0, x[1] - 2.0])

    out = levenberg_marquardt(residual, np.array([1.0, -3.0]), steps=200, tol=1e-10)
    assert out.converged
    np.testing.assert_allclose(out.x, [0.0, 2.0], atol=1e-4)
    np.testing.assert_allclose(out.residual, [1.0, 0.0], atol=1e-8)
    assert out.size == np.abs(out.residual).max()


def test_a_consistent_system_is_solved_to_its_root():
    # Rosenbrock's function as residuals: the root (1, 1) at the end of a curved valley
    def residual(x):
        return np.array([10.0 * (x[1] - x[0] ** 2), 1.0 - x[0]])

    out = levenberg_marquardt(residual, np.array([-1.2, 1.0]), steps=200, tol=1e-10)
    assert out.converged and out.size < 1e-10
    np.testing.assert_allclose(out.x, [1.0, 1.0], atol=1e-9)


def test_each_step_is_at_most_max_step_and_the_budgets_hold():
    seen = []

    def residual(x):
        seen.append(x.copy())
        return x - 10.0

    out = levenberg_marquardt(residual, np.zeros(2), steps=3, max_step=1.0)
    assert out.steps == 3 and not out.converged
    assert np.abs(out.x).max() <= 3.0 + 1e-12  # three steps of at most 1
    assert out.evaluations == len(seen)
    # a bound on the evaluations stops it before its steps
    few = levenberg_marquardt(lambda x: x - 10.0, np.zeros(2), steps=50, evaluations=7)
    assert few.evaluations <= 7 and not few.converged


def test_a_trial_point_where_the_residual_is_undefined_is_rejected():
    # r(x) = sqrt(x) − 1 is NaN for x < 0: the first full step overshoots there from x = 4
    # (Gauss–Newton: x − 2 sqrt(x)(sqrt(x) − 1) = −4), so it is rejected and damped
    out = levenberg_marquardt(lambda x: np.sqrt(x) - 1.0, np.array([4.0]), steps=100,
                              tol=1e-12)
    assert out.converged
    np.testing.assert_allclose(out.x, [1.0], atol=1e-8)


def test_forward_jacobian_matches_the_analytic_one():
    def residual(x):
        return np.array([np.sin(x[0]) * x[1], x[0] ** 3, np.exp(x[1])])

    x = np.array([0.4, -0.7])
    J = forward_jacobian(residual, x, residual(x), 1e-7)
    exact = np.array([[np.cos(0.4) * -0.7, np.sin(0.4)], [3 * 0.16, 0.0],
                      [0.0, np.exp(-0.7)]])
    np.testing.assert_allclose(J, exact, atol=1e-6)
