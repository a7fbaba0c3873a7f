"""The self-check's per-sample record and the paired advantage of a candidate over the
reference (session 26, a noise-aware self-check on scans: measured on the tuning side,
benchmarks/scan_noise_selfcheck.py, not the default)."""

import numpy as np
import pytest

from surfinpaint.data import torus
from surfinpaint.fill.conformal import ConformalOptions
from surfinpaint.fill.conformal.candidates import Candidates
from surfinpaint.fill.selfcheck import hidden_ring_scores, paired_advantage, sibling_scores
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.geometry.metrics import (
    mean_surface_distances,
    sample_faces,
    sample_surface,
    surface_distance_samples,
)

FAIRED = Candidates(options=ConformalOptions(), orders=(2, 3), s0_order=3, crease_angle=None,
                    crossed=False).for_tests(with_lambda_h=False)


def test_paired_advantage_is_the_mean_difference_with_a_cluster_robust_error():
    rng = np.random.default_rng(1)
    groups = np.repeat(np.arange(50), 20)
    shared = np.repeat(rng.normal(size=50), 20)  # one value per cluster: fully dependent
    ref = 1.0 + shared
    adv, se = paired_advantage(ref, ref - 0.1 - 0.01 * shared, groups)
    assert adv == pytest.approx(0.1 + 0.01 * shared.mean())
    # 50 independent clusters, not 1000 samples: the error of a mean of 50 values
    assert se == pytest.approx(0.01 * shared[::20].std(ddof=1) / np.sqrt(50), rel=1e-9)
    # no spread, no error; one cluster: no estimate
    assert paired_advantage(ref, ref - 0.1, groups) == (pytest.approx(0.1), pytest.approx(0.0))
    assert paired_advantage(ref[:20], ref[:20], groups[:20])[1] == np.inf


def test_sample_faces_are_those_of_sample_surface():
    v, f = torus(R=1.0, r=0.3, n_major=24, n_minor=12)
    pts = sample_surface(v, f, 500, seed=3)
    t = sample_faces(v, f, 500, seed=3)
    a, b, c = (v[f[t, i]] for i in range(3))
    # each point lies in the plane of its face
    normal = np.cross(b - a, c - a)
    assert np.abs(np.einsum("ij,ij->i", pts - a, normal)).max() < 1e-12


def test_details_give_the_scores_and_change_nothing():
    v, f = torus(R=1.0, r=0.35, n_major=60, n_minor=24)
    h = mean_edge_length(v, f)
    cut = cut_geodesic_disk(v, f, 0, 3.5 * h)
    hidden = hidden_ring_scores(cut.vertices, cut.faces, cut.loop, FAIRED, n_samples=400)
    detail: dict = {}
    again = hidden_ring_scores(cut.vertices, cut.faces, cut.loop, FAIRED, n_samples=400,
                               detail=detail)
    assert again == hidden
    for name, d in detail["distances"].items():
        assert d.mean() == pytest.approx(hidden[name])
    assert len(detail["groups"]) == 400
    sib = sibling_scores(cut.vertices, cut.faces, cut.loop, FAIRED, n_samples=400)
    records: list = []
    assert sibling_scores(cut.vertices, cut.faces, cut.loop, FAIRED, n_samples=400,
                          detail=records) == sib
    assert len(records) == 2
    for name in sib:
        assert np.mean([r["distances"][name].mean() for r in records]) == \
            pytest.approx(sib[name])


def test_surface_distance_samples_give_the_mean_surface_distances():
    v, f = torus(R=1.0, r=0.3, n_major=24, n_minor=12)
    moved = v + 0.01
    both = surface_distance_samples([(moved, f)], v, f, n_samples=300)
    assert 0.5 * (both[0][0].mean() + both[0][1].mean()) == \
        pytest.approx(mean_surface_distances([(moved, f)], v, f, n_samples=300)[0])
