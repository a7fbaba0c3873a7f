"""Rebuilding a removed disk of an analytic conformal surface from its λ and H."""

import warnings

import numpy as np
import pytest

from surfinpaint.errors import FillError
from surfinpaint.representation.analytic import (
    SURFACES,
    enneper,
    grid,
    removed_disk,
    stereographic_sphere,
)
from surfinpaint.representation.fields import lambda_h
from surfinpaint.representation.reconstruction import METHODS, reconstruct

SIZES = (17, 33, 65)


def rel_error(out, phi, known):
    diameter = np.linalg.norm(np.ptp(phi[~known], axis=0))
    return np.abs(out - phi)[~known].max() / diameter


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("name", sorted(SURFACES))
@pytest.mark.parametrize("data", ["exact", "discrete"])
def test_disk_rebuild_converges_second_order(name, method, data):
    errs = []
    for n in SIZES:
        phi, lam, H, known, h = removed_disk(name, n)
        if data == "discrete":  # λ, H of the discrete surface itself
            lam, H = lambda_h(phi, h)
        given = np.where(known[..., None], phi, np.nan)
        out = reconstruct(lam, H, given, known, h, method=method)
        assert np.all(np.isfinite(out))
        assert np.array_equal(out[known], phi[known])  # known nodes bitwise unchanged
        errs.append(rel_error(out, phi, known))
    errs = np.array(errs)
    assert errs[-1] < 1e-3, errs
    if errs[0] > 1e-12:  # Enneper's cubic φ is rebuilt to round-off by the laplacian form
        assert np.all(errs[:-1] / errs[1:] >= 3.5), errs


@pytest.mark.parametrize("name", ["sphere", "torus"])
def test_gauss_codazzi_normal_integration_converges(name):
    errs = []
    for n in SIZES:
        phi, lam, H, known, h = removed_disk(name, n)
        out = reconstruct(lam, H, phi, known, h, integrate="normal")
        errs.append(rel_error(out, phi, known))
    errs = np.array(errs)
    assert errs[-1] < 1e-3 and np.all(errs[:-1] / errs[1:] >= 3.5), errs
    with pytest.raises(ValueError, match="integrate"):
        reconstruct(lam, H, phi, known, h, integrate="simpson")


def test_laplacian_form_is_exact_where_the_discretization_is():
    # Δh is exact on Enneper's cubic coordinates, so the discrete λ, H reproduce φ to
    # round-off. (On general surfaces Δhφ has an O(h²) tangential part that (λ, H) do not
    # carry, so no rebuild from them alone can be exact to round-off.)
    phi, _, _, known, h = removed_disk("enneper", 33)
    lam, H = lambda_h(phi, h)
    out = reconstruct(lam, H, phi, known, h, method="laplacian")
    assert np.abs(out - phi).max() < 1e-13


@pytest.mark.parametrize("method", METHODS)
def test_inputs_unchanged_and_phi_inside_ignored(method):
    phi, lam, H, known, h = removed_disk("sphere", 33)
    garbage = phi.copy()
    garbage[~known] = 1e3
    args = [a.copy() for a in (lam, H, garbage, known)]
    out1 = reconstruct(*args, h, method=method)
    for a, b in zip(args, (lam, H, garbage, known), strict=True):
        assert np.array_equal(a, b)
    out2 = reconstruct(lam, H, phi, known, h, method=method)
    assert np.array_equal(out1, out2)


@pytest.mark.parametrize("method", METHODS)
def test_irregular_domain(method):
    u, v, h = grid(49)
    phi, lam, H = stereographic_sphere(u, v)
    domain = (u / 0.95) ** 2 + (v / 0.7) ** 2 < 1
    hole = (u - 0.2) ** 2 + v**2 < 0.25**2
    known = domain & ~hole
    given = np.where(known[..., None], phi, np.nan)
    lam_d = np.where(domain, lam, np.nan)
    H_d = np.where(domain, H, np.nan)
    out = reconstruct(lam_d, H_d, given, known, h, method=method, domain=domain)
    assert np.all(np.isnan(out[~domain]))  # outside the domain: returned as given
    assert np.all(np.isfinite(out[domain]))
    assert rel_error(out, phi, ~hole) < 2e-3


@pytest.mark.parametrize("method", METHODS)
def test_missing_lambda_H_on_known_nodes_is_filled_from_phi(method):
    # NaN (λ, H) on known nodes is replaced by lambda_h of the known surface where that is
    # defined (not on the first known ring, whose stencils reach into the unknown region).
    phi, lam, H, known, h = removed_disk("torus", 33)
    lam_k, H_k = lambda_h(np.where(known[..., None], phi, np.nan), h)
    lam_nan = np.where(np.isfinite(lam_k), np.nan, lam)
    H_nan = np.where(np.isfinite(H_k), np.nan, H)
    out = reconstruct(lam_nan, H_nan, phi, known, h, method=method)
    ref = reconstruct(lam, H, phi, known, h, method=method)
    assert rel_error(out, phi, known) < 2 * rel_error(ref, phi, known)


@pytest.mark.parametrize("method", METHODS)
def test_region_touching_border_raises(method):
    u, v, h = grid(17)
    phi, lam, H = enneper(u, v)
    known = u > -0.7  # unknown strip along the border
    with pytest.raises(ValueError, match="grid border"):
        reconstruct(lam, H, phi, known, h, method=method)


def test_region_touching_domain_edge_raises():
    u, v, h = grid(33)
    phi, lam, H = enneper(u, v)
    domain = u < 0.5
    known = domain & ((u - 0.3) ** 2 + v**2 > 0.2**2)
    with pytest.raises(ValueError, match="outside the domain"):
        reconstruct(lam, H, phi, known, h, domain=domain)


def test_gauss_codazzi_needs_three_rings():
    phi, lam, H, _, h = removed_disk("sphere", 17)
    known = np.ones((17, 17), bool)
    known[8, 3] = False  # 3 rings to the border: fine
    reconstruct(lam, H, phi, known, h)
    known[8, 3], known[8, 2] = True, False  # only 2 rings
    reconstruct(lam, H, phi, known, h, method="laplacian")
    with pytest.raises(ValueError, match="3 ring"):
        reconstruct(lam, H, phi, known, h)


def test_grid_too_small():
    phi = np.zeros((5, 5, 3))
    known = np.ones((5, 5), bool)
    known[2, 2] = False
    with pytest.raises(ValueError, match="too small"):
        reconstruct(np.ones((5, 5)), np.ones((5, 5)), phi, known, 0.1)


def test_bad_inputs():
    phi, lam, H, known, h = removed_disk("sphere", 17)
    with pytest.raises(ValueError, match="method"):
        reconstruct(lam, H, phi, known, h, method="magic")
    with pytest.raises(ValueError, match="options"):
        reconstruct(lam, H, phi, known, h, tolerance=3)
    with pytest.raises(ValueError, match="shape"):
        reconstruct(lam[:-1], H, phi, known, h)
    with pytest.raises(ValueError, match="boolean"):
        reconstruct(lam, H, phi, known.astype(int), h)
    with pytest.raises(ValueError, match="positive"):
        reconstruct(lam, H, phi, known, -h)
    bad = phi.copy()
    bad[0, 0] = np.nan
    with pytest.raises(ValueError, match=r"non-finite positions, e.g. \(0, 0\)"):
        reconstruct(lam, H, bad, known, h)
    lam_bad = lam.copy()
    lam_bad[~known] = np.nan
    with pytest.raises(ValueError, match="lam is not finite"):
        reconstruct(lam_bad, H, phi, known, h, method="laplacian")


def test_nothing_unknown_returns_copy():
    phi, lam, H, _, h = removed_disk("sphere", 9)
    known = np.ones((9, 9), bool)
    out = reconstruct(lam, H, phi, known, h)
    assert np.array_equal(out, phi) and out is not phi


def test_laplacian_iteration_budget_warns():
    phi, lam, H, known, h = removed_disk("sphere", 33)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        reconstruct(lam, H, phi, known, h, method="laplacian", max_iter=1)
    assert any(issubclass(x.category, RuntimeWarning) for x in w)


def test_degenerate_known_surface_raises():
    u, v, h = grid(17)
    phi = np.zeros((17, 17, 3))  # all nodes coincide: no normal anywhere
    known = (u**2 + v**2) > 0.3**2
    with pytest.raises((ValueError, FillError)):
        reconstruct(np.ones_like(u), np.ones_like(u), phi, known, h, method="laplacian")
    with pytest.raises((ValueError, FillError)):
        reconstruct(np.ones_like(u), np.ones_like(u), phi, known, h)
