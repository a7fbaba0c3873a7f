"""Biharmonic and harmonic inpainting of grid fields: exactness, flow, fidelity, domains."""

import numpy as np
import pytest

from surfinpaint.representation.inpainting import biharmonic_flow, inpaint


@pytest.fixture
def plane():
    u, v = np.meshgrid(np.arange(20.0), np.arange(24.0), indexing="ij")
    hole = (u - 9) ** 2 + (v - 11) ** 2 < 25
    return u, v, hole


def cubic(u, v):  # every cubic is biharmonic, and Δh²is exact on it
    return 0.01 * (u**3 - 2 * u * v**2 + 3 * u**2 * v + v**3) + u * v + 2


def test_biharmonic_reproduces_cubic(plane):
    u, v, hole = plane
    f = cubic(u, v)
    out = inpaint(np.where(hole, np.nan, f), hole)
    assert np.abs(out - f).max() < 1e-10
    assert np.array_equal(out[~hole], f[~hole])


def test_biharmonic_is_not_trivially_exact(plane):
    # A non-biharmonic field (r⁴) is *not* reproduced: the test above can fail.
    u, v, hole = plane
    f = ((u - 9) ** 2 + (v - 11) ** 2) ** 2 / 100
    assert np.abs(inpaint(f, hole) - f).max() > 1e-2


def test_vector_values(plane):
    u, v, hole = plane
    f = np.stack([cubic(u, v), -cubic(v, u), u], axis=-1)
    out = inpaint(np.where(hole[..., None], np.nan, f), hole)
    assert out.shape == f.shape and np.abs(out - f).max() < 1e-10


def test_harmonic_reproduces_harmonic(plane):
    u, v, hole = plane
    f = u**2 - v**2 + 3 * u * v + u  # discretely harmonic too
    out = inpaint(np.where(hole, np.nan, f), hole, method="harmonic")
    assert np.abs(out - f).max() < 1e-10
    assert np.abs(inpaint(cubic(u, v), hole, method="harmonic") - cubic(u, v)).max() > 1e-2


def test_flow_approaches_direct_solve(plane):
    u, v, hole = plane
    rng = np.random.default_rng(1)
    f = cubic(u, v) + 0.1 * rng.standard_normal(u.shape)
    direct = inpaint(f, hole)
    gaps = [np.abs(biharmonic_flow(f, hole, 1 / 64, s) - direct).max() for s in (2000, 20000)]
    assert gaps[1] < 1e-3 < gaps[0]  # it does move, and toward the minimizer
    h = 0.5
    slow = biharmonic_flow(f, hole, h**4 / 64, 20000, h=h)
    assert np.abs(slow - direct).max() < 1e-3  # the minimizer does not depend on h
    with pytest.raises(ValueError, match="stability"):
        biharmonic_flow(f, hole, 1.0, 10)


@pytest.mark.parametrize("method", ["biharmonic", "harmonic"])
def test_fidelity_to_infinity_approaches_hard(plane, method):
    u, v, hole = plane
    rng = np.random.default_rng(2)
    f = cubic(u, v) + 0.2 * rng.standard_normal(u.shape)
    hard = inpaint(f, hole, method=method)
    gaps = [np.abs(inpaint(f, hole, method=method, fidelity=w) - hard).max()
            for w in (1.0, 1e3, 1e6)]
    assert gaps[0] > 1e-2 and gaps[1] < 1e-1 and gaps[2] < 1e-4, gaps
    soft = inpaint(f, hole, method=method, fidelity=1.0, rings=2)
    far = ~np.zeros_like(hole)
    far[3:16, 5:18] = False  # beyond 2 rings of the hole: hard data, unchanged
    assert np.array_equal(soft[far], f[far])


def test_fidelity_is_unbiased_and_removes_noise():
    u, v = np.meshgrid(np.arange(40.0), np.arange(40.0), indexing="ij")
    hole = (u - 20) ** 2 + (v - 20) ** 2 < 64
    f = cubic(u, v) / 8
    clean = inpaint(f, hole, fidelity=0.1, rings=8)
    assert np.abs(clean - f).max() < 1e-9  # cubic data is left as it is
    noisy = f + 0.5 * np.random.default_rng(3).standard_normal(f.shape)
    hard = np.abs(inpaint(noisy, hole) - f)[hole].mean()
    soft = np.abs(inpaint(noisy, hole, fidelity=0.1, rings=8) - f)[hole].mean()
    assert soft < 0.3 * hard, (soft, hard)  # measured 0.045 vs 0.40


def test_irregular_domain_nan_free(plane):
    u, v, hole = plane
    domain = (u - 10) ** 2 + (v - 12) ** 2 < 100
    domain[9, 2:5] = False  # a notch
    f = np.where(domain, cubic(u, v), np.nan)
    for method in ("biharmonic", "harmonic"):
        for fid in (None, 10.0):
            out = inpaint(f, hole, domain=domain, method=method, fidelity=fid)
            assert np.all(np.isfinite(out[domain])) and np.all(np.isnan(out[~domain]))
    out = inpaint(f, hole, domain=domain)
    assert np.abs(out - cubic(u, v))[domain].max() < 1e-10


def test_region_reaching_the_domain_edge():
    # Near the domain boundary only full stencils are used; the result is still finite and
    # reproduces a cubic wherever two rings of data surround the region.
    u, v = np.meshgrid(np.arange(16.0), np.arange(16.0), indexing="ij")
    domain = u + v < 24
    region = domain & (u > 8) & (v > 8)
    f = np.where(domain & ~region, cubic(u, v), np.nan)
    out = inpaint(f, region, domain=domain)
    assert np.all(np.isfinite(out[domain]))


def test_unconstrained_region_raises():
    f = np.zeros((8, 8))
    with pytest.raises(ValueError, match="not constrained"):
        inpaint(f, np.ones((8, 8), bool))
    domain = np.ones((12, 12), bool)
    domain[:, 5] = False  # wall: the right half is cut off from every known node
    region = np.zeros_like(domain)
    region[:, 6:] = True
    with pytest.raises(ValueError, match="not constrained"):
        inpaint(np.zeros((12, 12)), region, domain=domain, method="harmonic")


def test_bad_inputs(plane):
    u, v, hole = plane
    f = cubic(u, v)
    with pytest.raises(ValueError, match="method"):
        inpaint(f, hole, method="telea")
    with pytest.raises(ValueError, match="boolean"):
        inpaint(f, hole.astype(int))
    with pytest.raises(ValueError, match="shape"):
        inpaint(f[:, :, None, None], hole)
    with pytest.raises(ValueError, match="fidelity"):
        inpaint(f, hole, fidelity=-1.0)
    with pytest.raises(ValueError, match="options"):
        inpaint(f, hole, smoothness=3)
    g = f.copy()
    g[3, 11] = np.nan  # known node two rings from the hole: read by the stencils
    with pytest.raises(ValueError, match=r"not finite, e.g. \(3, 11\)"):
        inpaint(g, hole)


def test_input_not_modified_and_empty_region(plane):
    u, v, hole = plane
    f = np.where(hole, np.nan, cubic(u, v))
    before = f.copy()
    inpaint(f, hole)
    assert np.array_equal(f, before, equal_nan=True)
    out = inpaint(f, np.zeros_like(hole))
    assert np.array_equal(out, f, equal_nan=True) and out is not f
