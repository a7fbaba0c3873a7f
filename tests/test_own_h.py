"""The kept λ-H fill's own H against the biharmonic continuation of its rim's (session 40):
the departure measured, the rule's table of cases, and the faired choice written where the
rule drops the fill."""

from dataclasses import replace

import numpy as np
import pytest

import surfinpaint.fill.conformal.method as method
from surfinpaint.data import torus
from surfinpaint.fill.conformal.options import PATCH_RINGS
from surfinpaint.fill.conformal.own_h import OWN_H_DEPARTURE, keeps_own_h, own_h_departure
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import mean_edge_length

RINGS = PATCH_RINGS["mesh"]


@pytest.fixture(scope="module")
def torus_hole():
    """A hole on the torus' outer equator and the fill the self-check keeps there."""
    v, f = torus()
    h = mean_edge_length(v, f)
    cut = cut_geodesic_disk(v, f, v[np.argmax(v[:, 0])], 3 * h)
    return cut, method.conformal_fill(cut.vertices, cut.faces, cut.loop)


@pytest.mark.parametrize("departure, crease, kept", [
    (None, False, True),                     # not measured: the verdict stands
    (0.017, False, True),                    # the tuning side's median
    (OWN_H_DEPARTURE, False, True),          # at the threshold: not above it
    (1.01 * OWN_H_DEPARTURE, False, False),  # above it: the faired choice
    (1.49, False, False),                    # octopus #2 of the smooth tuning set
    (5.0, True, True),                       # a crease fill: its sides are their own
])
def test_the_rule(departure, crease, kept):
    assert keeps_own_h(departure, crease) is kept


def test_a_smooth_fill_follows_its_rim_and_a_bump_does_not(torus_hole):
    cut, fill = torus_hole
    assert fill.kind == "conformal"
    departure = own_h_departure(cut.vertices, cut.faces, cut.loop, fill, RINGS)
    assert departure < 0.01  # measured 0.0019
    # a bump mid-hole, flat where it meets the rim: H the rim does not predict
    centre = fill.vertices.mean(axis=0)
    rim = np.linalg.norm(cut.vertices[cut.loop] - centre, axis=1).min()
    spread = np.linalg.norm(fill.vertices - centre, axis=1)
    outwards = centre / np.linalg.norm(centre)
    bump = fill.vertices + 0.3 * rim * np.clip(1.0 - (spread / rim) ** 2, 0.0, None)[:, None] \
        ** 3 * outwards
    bumped = own_h_departure(cut.vertices, cut.faces, cut.loop, replace(fill, vertices=bump),
                             RINGS)
    assert bumped > OWN_H_DEPARTURE
    empty = replace(fill, vertices=np.zeros((0, 3)), faces=fill.faces[:0])
    assert own_h_departure(cut.vertices, cut.faces, cut.loop, empty, RINGS) is None


def test_a_fill_off_its_rims_continuation_is_not_kept(torus_hole, monkeypatch):
    cut, kept = torus_hole
    monkeypatch.setattr(method, "own_h_departure", lambda *args: 1.5)
    dropped = method.conformal_fill(cut.vertices, cut.faces, cut.loop)
    # the faired fill the self-check chose next, saying why
    assert dropped.kind == "fair" and dropped.failure is None
    assert dropped.fair_order == int(kept.verdict.faired[-1])
    assert not dropped.verdict.keep and dropped.verdict.hidden == kept.verdict.hidden
    assert "own H is 1.50 (relative RMS) off the biharmonic continuation" in dropped.selection
    monkeypatch.setattr(method, "own_h_departure", lambda *args: OWN_H_DEPARTURE)
    again = method.conformal_fill(cut.vertices, cut.faces, cut.loop)
    assert again.kind == "conformal" and np.array_equal(again.vertices, kept.vertices)
