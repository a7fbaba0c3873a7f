"""``benchmarks/accuracy.py``'s bilaplacian columns: ``fair`` (the conventional baseline,
never smoothed) and ``fair_sfauto`` (the default's bilaplacian candidate as its self-check
sees it: the smoothing fill where the noise gate opens). The validation tables score the
self-check as a chooser against the second; where the gate stays closed they must be the
same fill, where it opens another one."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import mean_edge_length, vertex_normals

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
accuracy = pytest.importorskip("accuracy")


def _sphere_hole(noise_edges: float):
    sphere = trimesh.creation.icosphere(4)
    v, f = np.asarray(sphere.vertices), np.asarray(sphere.faces)
    h = mean_edge_length(v, f)
    noise = noise_edges * h * np.random.default_rng(3).standard_normal(len(v))
    v = v + vertex_normals(v, f) * noise[:, None]
    return cut_geodesic_disk(v, f, v[21], 4.0 * h)


@pytest.mark.parametrize("noise_edges, same", [(0.0, True), (0.03, False)])
def test_fair_sfauto_is_the_plain_bilaplacian_fill_unless_the_noise_gate_opens(noise_edges,
                                                                               same):
    cut = _sphere_hole(noise_edges)
    plain_v, plain_f, _, _ = accuracy.run_method("fair", cut.vertices, cut.faces, cut.loop)
    auto_v, auto_f, _, _ = accuracy.run_method("fair_sfauto", cut.vertices, cut.faces,
                                               cut.loop)
    np.testing.assert_array_equal(plain_f, auto_f)  # one triangulation and refinement
    n = len(cut.vertices)
    np.testing.assert_array_equal(plain_v[:n], auto_v[:n])  # the known surface untouched
    moved = np.abs(plain_v[n:] - auto_v[n:]).max() / mean_edge_length(cut.vertices, cut.faces)
    if same:
        assert moved == 0.0
    else:  # the smoothing fill: measurably another fill (not a rounding difference)
        assert moved > 1e-3


def test_triangulation_column_adds_no_vertex_and_closes_the_hole():
    """Session 48's ``triangulation`` column: the loop's triangulation alone."""
    cut = _sphere_hole(0.0)
    v, f, _, _ = accuracy.run_method("triangulation", cut.vertices, cut.faces, cut.loop)
    assert len(v) == len(cut.vertices)
    assert len(f) == len(cut.faces) + len(cut.loop) - 2
    _, refined_f, _, _ = accuracy.run_method("conventional", cut.vertices, cut.faces, cut.loop)
    assert len(refined_f) > len(f)  # the conventional fill refines it




def test_an_ear_cut_fill_is_labelled_as_what_was_written():
    """The validation rows name a fill the ear-cut rules wrote (no self-check chose it)."""
    from surfinpaint.data import cube
    from surfinpaint.fill.conformal.options import ConformalOptions

    v, f = cube(16)
    centre = int(np.argmin(np.linalg.norm(v - [0.5, 0.0, 0.0], axis=1)))
    cut = cut_geodesic_disk(v, f, centre, 6 * mean_edge_length(v, f))
    row = accuracy.score(cut, "conformal_earflat", "cube", 0, 6.0, 2000)
    assert row.note == "ear-cut fill (flat planes)" and row.status == "selected"
    assert row.mean_pct < 1e-9  # it rebuilds the cube's edge
    *_, note = accuracy._run_ours("conformal", cut.vertices, cut.faces, cut.loop,
                                  options=ConformalOptions(ear_cut_ratio=100.0,
                                                           ear_cut_flat=None))
    assert note == "ear-cut fill (hidden rings)"
