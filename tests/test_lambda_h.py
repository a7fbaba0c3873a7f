"""λ, H and μ of analytic conformal grids: O(h²) convergence, NaN handling, bad input."""

import numpy as np
import pytest

from surfinpaint.representation.analytic import (
    SURFACES,
    enneper,
    grid,
    isothermal_torus,
    stereographic_sphere,
)
from surfinpaint.representation.fields import (
    central_derivatives,
    grid_laplacian,
    hopf_differential,
    lambda_h,
    normals,
)

SIZES = (17, 33, 65)


def errors(name):
    f, ext = SURFACES[name]
    out = []
    for n in SIZES:
        u, v, h = grid(n, ext)
        phi, lam, H = f(u, v)
        lam_h, H_h = lambda_h(phi, h)
        inner = np.s_[1:-1, 1:-1]
        assert np.all(np.isfinite(lam_h[inner])) and np.all(np.isfinite(H_h[inner]))
        out.append(
            (np.max(abs(lam_h - lam)[inner]) / lam.max(), np.max(abs(H_h - H)[inner]))
        )
    return np.array(out)


@pytest.mark.parametrize("name", sorted(SURFACES))
def test_lambda_converges_second_order(name):
    e = errors(name)[:, 0]
    assert np.all(e[:-1] / e[1:] >= 3.5), e
    assert e[-1] < 2e-3


@pytest.mark.parametrize("name", ["sphere", "torus"])
def test_H_converges_second_order(name):
    e = errors(name)[:, 1]
    assert np.all(e[:-1] / e[1:] >= 3.5), e
    assert e[-1] < 2e-3


def test_enneper_H_is_zero_to_roundoff():
    # φ is cubic, so Δhφ is the exact Δφ = 0.
    assert np.all(errors("enneper")[:, 1] < 1e-10)


def test_torus_mean_curvature_changes_sign_correctly():
    u, v, h = grid(65, (-1.0, 1.0, 0.0, 2.0))
    phi, lam, H = isothermal_torus(u, v)  # R = 2, r = 1
    assert H.max() < 0  # outward normal: H < 0 everywhere on a torus with R = 2r
    n = normals(phi, h)
    centre = np.stack([2 * np.cos(u), 2 * np.sin(u), 0 * u], axis=-1)
    assert np.all(np.sum(n * (phi - centre), axis=-1)[1:-1, 1:-1] > 0)  # outward


@pytest.mark.parametrize(
    ("name", "exact"),
    [
        ("enneper", lambda u, v, lam: -np.ones_like(u)),
        ("sphere", lambda u, v, lam: np.zeros_like(u)),
        ("torus", lambda u, v, lam: 2.0 * lam / 4.0),  # μ = Rρ/(4r), ρ = λ
    ],
)
def test_hopf_differential_converges(name, exact):
    f, ext = SURFACES[name]
    e = []
    for n in SIZES:
        u, v, h = grid(n, ext)
        phi, lam, _ = f(u, v)
        mu = hopf_differential(phi, h)
        inner = np.s_[1:-1, 1:-1]
        assert np.all(np.isnan(mu[0])) and np.all(np.isfinite(mu[inner]))
        e.append(np.max(abs(mu - exact(u, v, lam))[inner]))
    e = np.array(e)
    assert np.all(e[:-1] / e[1:] >= 3.5), e


def test_outer_ring_is_nan():
    u, v, h = grid(9)
    phi, _, _ = stereographic_sphere(u, v)
    lam, H = lambda_h(phi, h)
    ring = np.ones((9, 9), bool)
    ring[1:-1, 1:-1] = False
    assert np.all(np.isnan(lam[ring])) and np.all(np.isnan(H[ring]))
    assert np.all(np.isfinite(lam[~ring])) and np.all(np.isfinite(H[~ring]))


def test_nan_nodes_poison_exactly_their_stencils():
    u, v, h = grid(21)
    phi, _, _ = stereographic_sphere(u, v)
    lam0, H0 = lambda_h(phi, h)
    domain = u**2 + v**2 < 0.8**2
    holes = np.zeros_like(domain)
    holes[10, 10] = True
    domain &= ~holes
    lam, H = lambda_h(np.where(domain[..., None], phi, np.nan), h)
    # A node is defined iff it and its four neighbours are in the domain (and not on the ring).
    pad = np.pad(domain, 1)
    cross = (
        pad[1:-1, 1:-1] & pad[2:, 1:-1] & pad[:-2, 1:-1] & pad[1:-1, 2:] & pad[1:-1, :-2]
    )
    assert np.array_equal(np.isfinite(lam), cross)
    assert np.array_equal(np.isfinite(H), cross)
    assert np.array_equal(lam[cross], lam0[cross]) and np.array_equal(H[cross], H0[cross])
    mu = hopf_differential(np.where(domain[..., None], phi, np.nan), h)
    assert not np.isfinite(mu[9, 9])  # diagonal neighbour of the NaN node (mixed stencil)
    assert np.isfinite(mu[10, 13])


def test_inputs_are_not_modified():
    u, v, h = grid(9)
    phi, _, _ = enneper(u, v)
    before = phi.copy()
    lambda_h(phi, h)
    hopf_differential(phi, h)
    assert np.array_equal(phi, before)


def test_operators_on_a_quadratic():
    u, v, h = grid(7)
    f = 3 * u**2 + 2 * u * v - v**2
    fu, fv = central_derivatives(f, h)
    assert np.allclose(fu[1:-1, 1:-1], (6 * u + 2 * v)[1:-1, 1:-1])
    assert np.allclose(fv[1:-1, 1:-1], (2 * u - 2 * v)[1:-1, 1:-1])
    assert np.allclose(grid_laplacian(f, h)[1:-1, 1:-1], 4.0)


@pytest.mark.parametrize(
    ("phi", "h", "match"),
    [
        (np.zeros((5, 5)), 0.1, "shape"),
        (np.zeros((5, 5, 2)), 0.1, "shape"),
        (np.zeros((5, 5, 3)), 0.0, "positive"),
        (np.zeros((5, 5, 3)), np.nan, "positive"),
    ],
)
def test_bad_input(phi, h, match):
    with pytest.raises(ValueError, match=match):
        lambda_h(phi, h)


def test_degenerate_surface_gives_nan_not_inf():
    lam, H = lambda_h(np.zeros((5, 5, 3)), 0.1)
    assert np.all(lam[1:-1, 1:-1] == 0) and np.all(np.isnan(H))


def test_analytic_bad_parameters():
    with pytest.raises(ValueError, match="R > r"):
        isothermal_torus(np.zeros(2), np.zeros(2), 1.0, 2.0)
    with pytest.raises(ValueError, match="square"):
        grid(5, (0.0, 1.0, 0.0, 2.0))
