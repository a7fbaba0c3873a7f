"""The self-check's per-sample record, the paired advantage of a candidate over the
reference, and the opt-in rule that keeps a choice only when its advantage is significant
(session 26, a noise-aware self-check on scans: measured on the tuning side,
benchmarks/scan_noise_selfcheck.py; not the default)."""

import numpy as np
import pytest

from surfinpaint.data import torus
from surfinpaint.fill.conformal import ConformalOptions
from surfinpaint.fill.conformal.candidates import Candidates
from surfinpaint.fill.conformal.selection import choose, demoted
from surfinpaint.fill.selfcheck import (
    advantages_over,
    hidden_ring_scores,
    paired_advantage,
    sibling_scores,
)
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.geometry.metrics import (
    mean_surface_distances,
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


def test_sample_surface_s_faces_are_those_its_points_lie_on():
    v, f = torus(R=1.0, r=0.3, n_major=24, n_minor=12)
    pts, t = sample_surface(v, f, 500, seed=3, return_faces=True)
    np.testing.assert_array_equal(pts, sample_surface(v, f, 500, seed=3))  # the same draw
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


def test_advantages_over_the_reference_in_each_test():
    g = np.repeat(np.arange(10), 5)
    ref = np.linspace(1.0, 2.0, 50)
    hidden = {"distances": {"fair2": ref, "fair3": ref - 0.1, "conformal": ref + 0.2},
              "groups": g}
    siblings = [{"distances": {"fair2": ref, "fair3": ref - 0.3}, "groups": g}] * 2
    adv = advantages_over(hidden, siblings)
    assert adv["hidden"]["fair3"] == (pytest.approx(0.1), pytest.approx(0.0, abs=1e-12))
    assert adv["hidden"]["conformal"][0] == pytest.approx(-0.2)
    assert set(adv["sibling"]) == {"fair3"}
    assert adv["sibling"]["fair3"][0] == pytest.approx(0.3)
    assert advantages_over({}, []) == {}


def _verdict(hidden, sibling):
    return choose(hidden, sibling, reference="fair2", choose_faired=True)


def test_demoted_keeps_only_significant_choices():
    kept = _verdict({"fair2": 1.0, "fair3": 0.9, "conformal": 0.8}, {})
    assert kept.keep and kept.faired == "fair3"
    # clearly ahead: unchanged (the same object)
    strong = {"hidden": {"conformal": (0.2, 0.01), "fair3": (0.1, 0.01)}}
    assert demoted(kept, strong, 2.326) is kept
    # the λ-H fill within the noise, fair3 ahead: fair3 written
    weak = {"hidden": {"conformal": (0.2, 0.1), "fair3": (0.1, 0.01)}}
    v = demoted(kept, weak, 2.326)
    assert (v.keep, v.make, v.faired) == (False, False, "fair3")
    assert "not significant" in v.scores
    # both within the noise: fair2
    v = demoted(kept, {"hidden": {"conformal": (0.2, 0.1), "fair3": (0.1, 0.1)}}, 2.326)
    assert (v.keep, v.faired) == (False, "fair2")
    # no hidden-ring test: the sibling test weighs the λ-H fill
    by_siblings = _verdict({}, {"fair2": 1.0, "fair3": 1.1, "conformal": 0.8})
    assert by_siblings.keep
    assert demoted(by_siblings, {"sibling": {"conformal": (0.2, 0.01)}}, 2.326).keep
    assert not demoted(by_siblings, {"sibling": {"conformal": (0.2, 0.1)}}, 2.326).keep
    # a crease fill kept where no test spoke is left
    crossed = choose({}, {}, reference="fair2", crossed=True)
    assert demoted(crossed, {}, 2.326, crossed=True).keep


@pytest.mark.parametrize(("given", "expected"), [
    ("default", 2.326),  # one-sided 1 %, the default since session 26
    (None, None),  # the scores alone decide, as before
    (1.645, 1.645),
])
def test_significance_option_defaults_to_one_sided_one_percent(given, expected):
    options = ConformalOptions() if given == "default" else ConformalOptions(significance=given)
    assert options.significance == expected


@pytest.mark.parametrize("bad", [-1.0, 0.0, float("nan")])
def test_a_significance_that_is_not_positive_is_an_error(bad):
    with pytest.raises(ValueError, match="significance"):
        ConformalOptions(significance=bad)
