"""The session 39 decomposition (``benchmarks/lambda_h_sources.py``): its truth-fed rebuild and
inpainting on an analytic torus, and the measures of a candidate's written fills on hand-made
rows. No benchmark mesh is loaded."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from test_on_mesh import grid_mesh

from surfinpaint.errors import FillError
from surfinpaint.geometry.mesh import laplacian_and_areas
from surfinpaint.representation.analytic import isothermal_torus
from surfinpaint.representation.vertex_lambda_h import vertex_lambda_h

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
sources = pytest.importorskip("lambda_h_sources")


def torus_hole(radius=0.3):
    u, v, uv, faces = grid_mesh(25, (0.0, 1.5, -0.75, 0.75))
    truth = isothermal_torus(u, v)[0].reshape(-1, 3)
    free = np.linalg.norm(uv - uv.mean(axis=0), axis=1) < radius
    return truth, faces, uv, free


def test_the_rebuild_from_the_true_lambda_and_h_gives_the_surface_back():
    truth, faces, uv, free = torus_hole()
    lam, H = vertex_lambda_h(truth, faces, uv)
    start = truth.copy()
    start[free] = truth[free].mean(axis=0)  # far from the surface: the rebuild must find it
    rebuilt = sources.rebuild(start, faces, uv, free, lam, H)
    scale = np.ptp(truth[free], axis=0).max()
    # (not to round-off: L φ has a tangential part the vertex normals leave out, measured
    # 0.7e-4 of the hole's size from this start and from the truth itself)
    assert np.abs(rebuilt - truth)[free].max() < 2e-4 * scale
    assert np.array_equal(rebuilt[~free], truth[~free])
    # with H 20 % off the rebuilt surface is 2.9e-2 away
    off = sources.rebuild(start, faces, uv, free, lam, 1.2 * H)
    assert np.abs(off - truth)[free].max() > 1e-2 * scale


def test_the_biharmonic_prediction_keeps_the_data_and_refuses_the_border():
    truth, faces, uv, free = torus_hole()
    L, area = laplacian_and_areas(uv, faces)
    Q = (L @ sp.diags(1.0 / area) @ L).tocsr()
    lam, H = vertex_lambda_h(truth, faces, uv)
    predicted = sources.biharmonic(H, Q, free)
    assert np.array_equal(predicted[~free], H[~free], equal_nan=True)
    # the torus' H varies smoothly: the biharmonic continuation is close, not exact
    error = sources.relative_rms(predicted[free], H[free])
    assert 1e-6 < error < 0.05
    wide = np.linalg.norm(uv - uv.mean(axis=0), axis=1) < 0.65  # up to the NaN border
    with pytest.raises(FillError, match="border"):
        sources.biharmonic(H, Q, wide)


def row(mesh, hole, written, fair2, fair3, cgal, which="smooth_tuning"):
    return {"set": which, "mesh": mesh, "hole": hole,
            "errors": {"conformal": written, "fair": fair2, "fair3": fair3, "cgal": cgal}}


def test_the_measures_of_written_fills():
    rows = [row("a", 0, 1.0, 2.0, 0.5, 2.0), row("a", 1, 1.0, 1.0, 1.0, 4.0),
            row("b", 0, 3.0, 1.0, 1.0, 1.0)]
    median_cgal, worst, above = sources.written_measures(rows, np.array([1.0, 1.0, 3.0]))
    assert median_cgal == pytest.approx(0.5)  # 0.5, 0.25, 3.0
    assert worst == (pytest.approx(3.0), "b")  # mesh b: 3 / 1; mesh a: 1 / 1.5
    assert above == 2  # 1.0 / 0.5 and 3.0 / 1.0
    text = sources.compare(rows, [{"set": "smooth_tuning", "mesh": "b", "hole": 0,
                                   "error": 1.0}])
    # the candidate's rows decide which holes count; the changed hole is listed
    assert "| smooth_tuning | 1 | 3.000, 3.000 (b), 1 | 1.000, 1.000 (b), 0 |" in text
    assert "smooth_tuning b #0: 3.000 → 1.000 (0.33×" in text
