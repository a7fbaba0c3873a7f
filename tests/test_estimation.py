import numpy as np
import pytest

from surfinpaint.representation.analytic import enneper, grid, stereographic_sphere
from surfinpaint.representation.estimation import fitted_derivatives, robust_lambda_h


def test_quadratic_fit_is_exact_on_quadratics():
    u, v = np.meshgrid(np.arange(11.0), np.arange(9.0), indexing="ij")
    h = 0.25
    f = 1 + 2 * (h * u) - (h * v) + 3 * (h * u) ** 2 + 0.5 * (h * u) * (h * v) - (h * v) ** 2
    d = fitted_derivatives(f[..., None], h, sigma=None)
    inner = (slice(3, -3), slice(3, -3))
    uu = (h * u)[inner]
    vv = (h * v)[inner]
    assert np.allclose(d["u"][inner][..., 0], 2 + 6 * uu + 0.5 * vv)
    assert np.allclose(d["vv"][inner][..., 0], -2)
    assert np.allclose(d["uv"][inner][..., 0], 0.5)


@pytest.mark.parametrize("surface", [stereographic_sphere, enneper])
def test_robust_lambda_h_converges_second_order_inside(surface):
    errors_lam, errors_H = [], []
    for n in (17, 33, 65):
        u, v, h = grid(n, (-0.8, 0.8, -0.8, 0.8))
        phi, lam, H = surface(u, v)
        est_lam, est_H = robust_lambda_h(phi, h)
        inner = (slice(2, -2), slice(2, -2))
        errors_lam.append(np.max(np.abs(est_lam - lam)[inner] / lam[inner]))
        errors_H.append(np.max(np.abs(est_H - H)[inner]))
    # the 5×5 window smooths with an O(h²) bias: about 0.3 % at h = 1.6/64 on the sphere
    assert errors_lam[-1] < 4e-3
    assert errors_lam[0] / errors_lam[1] > 3.5 and errors_lam[1] / errors_lam[2] > 3.5
    if surface is enneper:
        assert errors_H[-1] < 1e-9  # H = 0 and the quadratic fit sees no curvature bias
    else:
        assert errors_H[0] / errors_H[1] > 3.5 and errors_H[1] / errors_H[2] > 3.5


def test_masked_nodes_are_never_used():
    u, v, h = grid(33, (-0.8, 0.8, -0.8, 0.8))
    phi, lam, H = stereographic_sphere(u, v)
    hole = (u**2 + v**2) < 0.3**2
    garbage = phi.copy()
    garbage[hole] = np.array([50.0, -20.0, 7.0])  # what an unfaired initial fill could look like
    est_lam, est_H = robust_lambda_h(garbage, h, valid=~hole)
    clean_lam, clean_H = robust_lambda_h(phi, h, valid=~hole)
    ok = np.isfinite(est_H)
    assert np.array_equal(ok, np.isfinite(clean_H))
    assert np.allclose(est_H[ok], clean_H[ok]) and np.allclose(est_lam[ok], clean_lam[ok])
    # one-sided fits next to the hole still see the sphere (first order there)
    assert np.nanmax(np.abs(est_H - 1.0)) < 0.15


def test_noise_is_averaged_out():
    u, v, h = grid(65, (-0.8, 0.8, -0.8, 0.8))
    phi, lam, H = stereographic_sphere(u, v)
    rng = np.random.default_rng(1)
    noisy = phi + rng.normal(scale=0.02 * h, size=phi.shape)
    from surfinpaint.representation.fields import lambda_h

    _, raw_H = lambda_h(noisy, h)
    _, fit_H = robust_lambda_h(noisy, h, radius=3, sigma=2.0)
    inner = (slice(4, -4), slice(4, -4))
    raw_spread = np.nanstd(raw_H[inner] - 1)
    fit_spread = np.nanstd(fit_H[inner] - 1)
    assert fit_spread < raw_spread / 3


def test_sparse_windows_give_nan():
    phi = np.full((9, 9, 3), np.nan)
    phi[4, :] = np.column_stack([np.arange(9.0), np.zeros(9), np.zeros(9)])  # a single line
    lam, H = robust_lambda_h(phi, 1.0)
    assert np.isnan(lam).all() and np.isnan(H).all()
