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
from surfinpaint.geometry.mesh import boundary_loops, laplacian_and_areas
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


def torus_with_a_hole():
    """The torus patch of :func:`torus_hole` renumbered as a cut mesh and its fill: (known
    vertices, known faces, the hole's loop, the removed vertices, the fill's faces)."""
    truth, faces, _, free = torus_hole(0.25)
    order = np.concatenate([np.flatnonzero(~free), np.flatnonzero(free)])
    new_id = np.empty(len(order), dtype=np.int64)
    new_id[order] = np.arange(len(order))
    faces = new_id[faces]
    points = truth[order]
    n = int(np.sum(~free))
    in_fill = (faces >= n).any(axis=1)
    loops = boundary_loops(faces[~in_fill])
    loop = min(loops, key=len)  # the hole's (the patch's own border is longer)
    return points[:n], faces[~in_fill], loop, points[n:], faces[in_fill]


def test_the_signals_are_zero_between_equal_fills_and_see_a_bump():
    vertices, faces, loop, removed, fill_faces = torus_with_a_hole()
    same = sources.h_signals(vertices, faces, loop, removed, removed, fill_faces, 4)
    assert same["d lh-f3"] == 0.0 and same["d pos"] == 0.0 and same["d lh-f3 3d"] == 0.0
    # the torus' H is smooth: its continuations from the rim are close to it, not equal
    assert 1e-6 < same["d lh-bih"] < 0.05 and same["d harm-bih"] > same["d lh-bih"]
    centre = removed.mean(axis=0)
    rim = np.linalg.norm(vertices[loop] - centre, axis=1).min()
    spread = np.linalg.norm(removed - centre, axis=1)
    # outwards, largest mid-hole and flat where it meets the rim
    bump = removed + 0.03 * np.clip(1.0 - (spread / rim) ** 2, 0.0, None)[:, None] ** 3 \
        * (centre / np.linalg.norm(centre))
    moved = sources.h_signals(vertices, faces, loop, bump, removed, fill_faces, 4)
    assert moved["d lh-f3"] > 0.1 and moved["d pos"] > 0.03 and moved["d lh-f3 3d"] > 0.1
    # the rim hardly sees the bump: its continuation stays near the torus' H (measured 0.034)
    assert moved["d bih-f3"] < 0.3 * moved["d lh-f3"]
    assert moved["d lh-bih"] > 0.1


def test_the_separation_of_a_signal():
    auc, fewest, tau = sources.separation(np.array([3.0, 4.0, 1.0]), np.array([0.5, 2.0]))
    assert auc == pytest.approx(5 / 6)  # 1.0 is below 2.0 only
    assert (fewest, tau) == (1, 0.5)  # misses ≤ 0.5: none; wins above: 2.0
    assert sources.separation(np.array([1.0]), np.array([1.0]))[0] == 0.5


def test_a_veto_writes_the_faired_fill_where_the_signal_is_above_tau():
    main = [dict(row("a", k, 1.0, 2.0, 0.5, 2.0), status={"conformal": status},
                 evidence={"lib_faired": "fair2"})
            for k, status in enumerate(("ok", "ok", "selected", "ok"))]
    signals = [{"set": "smooth_tuning", "mesh": "a", "hole": k, "d lh-f3": d}
               for k, d in ((0, 0.9), (1, 0.1), (2, 0.9))]  # hole 3: no signal
    got = [r["error"] for r in sources.vetoed(main, signals, "d lh-f3", 0.5)]
    assert got == [0.5, 1.0, 1.0, 1.0]  # only a kept λ-H fill is vetoed
    got = [r["error"] for r in sources.vetoed(main, signals, "d lh-f3", 0.5, "faired")]
    assert got == [2.0, 1.0, 1.0, 1.0]


def test_a_veto_passes_the_bar_only_with_fewer_holes_above_and_nothing_worse():
    main = [dict(row("a", 0, 3.0, 2.0, 1.0, 2.0), status={"conformal": "ok"}),
            dict(row("a", 1, 1.0, 2.0, 4.0, 2.0), status={"conformal": "ok"}),
            dict(row("b", 0, 1.0, 1.0, 1.0, 1.0), status={"conformal": "selected"})]
    signals = [{"set": "smooth_tuning", "mesh": "a", "hole": k, "d lh-f3": d}
               for k, d in ((0, 0.9), (1, 0.5))]
    lines = sources.veto_sweep(main, signals, [0.7, 0.3]).splitlines()
    assert "| main | | 0 | 1.000, 1.000, 1 | 1 | |" in lines
    # a #0 vetoed: 3.0 → 1.0 (fair3), below 1.5×; the medians only fall
    assert "| d lh-f3 | 0.7 | 1 | 0.500, 1.000, 0 | 0 | yes |" in lines
    # a #1 vetoed too: 1.0 → 4.0, now above 1.5×, and mesh a's median / fair2 rises
    assert "| d lh-f3 | 0.3 | 2 | 1.000, 1.250, 1 | 1 | no |" in lines
