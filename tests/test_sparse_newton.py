"""Newton's step with a sparse factorization and the Woodbury identity
(surfinpaint.representation.sparse_newton, docs/convergence.md session 48 helper): the dense
step's system solved to rounding, and where each is taken."""

import numpy as np
import pytest
from test_coupled_jacobian import _near_border, _system

from surfinpaint.representation import on_mesh, sparse_newton
from surfinpaint.representation.coupled_jacobian import _DenseJacobian, lagged_update_jacobian
from surfinpaint.representation.sparse_newton import SparseNewtonStep, newton_step


@pytest.mark.parametrize("n, radius, curvature", [(30, 6, 1.0), (50, 11, 1.0), (50, 11, 0.3)])
def test_the_sparse_step_solves_the_dense_step_s_system(n, radius, curvature):
    # (S + U X) dx = −L̃ r is the dense step's (R − L̃) dx = −L̃ r: the same step to 1e-10
    # relative, and −(J − I)⁻¹ r with J the reference Jacobian; at the full curvature weight
    # and at a continuation's lower one (the least-squares stage's solves)
    system, points, phi, _ = _system(n, radius)
    assert not len(system.natural_data)
    system.curvature = curvature
    r = np.random.default_rng(5).standard_normal(3 * len(system.f))
    want = _DenseJacobian.of(system).step(phi, r)
    got = SparseNewtonStep.of(system).step(phi, r)
    assert np.abs(got - want).max() < 1e-10 * np.abs(want).max()
    J = lagged_update_jacobian(system, phi)
    exact = np.linalg.solve(J - np.eye(len(J)), -r)
    assert np.abs(got - exact).max() < 1e-10 * np.abs(exact).max()
    # the parts: S's entries are (α H_f ⊗ 1₃) dn_f − L̃, made at index arrays made once
    again = SparseNewtonStep.of(system)
    assert again is SparseNewtonStep.of(system)
    assert np.array_equal(again.step(phi, r), got)


def test_newton_step_takes_the_sparse_step_on_large_patches_only(monkeypatch):
    # at SPARSE_STEP_MIN_FREE free vertices and above (no natural border) the sparse step,
    # below it and next to a natural border the dense one; where the sparse one meets an
    # exactly singular matrix, the dense one
    system, points, phi, (local, uv, free) = _system(30, 6)
    r = np.random.default_rng(6).standard_normal(3 * len(system.f))
    taken = []
    sparse_step, dense_step = SparseNewtonStep.step, _DenseJacobian.step
    monkeypatch.setattr(SparseNewtonStep, "step",
                        lambda self, p, v: taken.append("sparse") or sparse_step(self, p, v))
    monkeypatch.setattr(_DenseJacobian, "step",
                        lambda self, p, v: taken.append("dense") or dense_step(self, p, v))
    n_free = len(system.f)
    monkeypatch.setattr(sparse_newton, "SPARSE_STEP_MIN_FREE", n_free + 1)
    dense = newton_step(system, points, phi[system.f], r)
    assert taken == ["dense"]
    monkeypatch.setattr(sparse_newton, "SPARSE_STEP_MIN_FREE", n_free)
    sparse = newton_step(system, points, phi[system.f], r)
    assert taken == ["dense", "sparse"]
    assert np.abs(sparse - dense).max() < 1e-10 * np.abs(dense).max()

    natural = on_mesh._CoupledSystem(points, local, uv, _near_border(points, local),
                                     np.ones(len(points), dtype=bool))
    assert len(natural.natural_data)
    monkeypatch.setattr(sparse_newton, "SPARSE_STEP_MIN_FREE", 0)
    newton_step(natural, points, points[natural.f], np.ones(3 * len(natural.f)))
    assert taken == ["dense", "sparse", "dense"]

    def singular(*args, **kw):
        raise RuntimeError("Factor is exactly singular")

    monkeypatch.setattr(sparse_newton.spla, "splu", singular)
    assert np.array_equal(newton_step(system, points, phi[system.f], r), dense)
    assert taken == ["dense", "sparse", "dense", "sparse", "dense"]
