"""Session 41's thin-wall signals (``benchmarks/thin_wall_signal.py``): the far side of a hole
and its distance, on hand-made plates, and the screen over hand-made study rows. No benchmark
mesh is loaded and no fill is made."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
signal = pytest.importorskip("thin_wall_signal")

from surfinpaint.geometry.cutting import cut_geodesic_disk  # noqa: E402


def plate(n: int = 41, z: float = 0.0, flip: bool = False):
    """A flat square grid of ``n`` × ``n`` vertices, spacing 1/(n-1), at height ``z``."""
    xs = np.linspace(0.0, 1.0, n)
    x, y = np.meshgrid(xs, xs, indexing="ij")
    v = np.column_stack([x.ravel(), y.ravel(), np.full(n * n, z)])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    f = np.vstack([np.column_stack([a, a + n, a + n + 1]), np.column_stack([a, a + n + 1, a + 1])])
    return v, (f[:, ::-1] if flip else f)


def two_plates(gap: float):
    """Two parallel plates ``gap`` apart (two components), facing away from each other."""
    v0, f0 = plate()
    v1, f1 = plate(z=-gap, flip=True)
    return np.vstack([v0, v1]), np.vstack([f0, f1 + len(v0)])


def test_the_other_plate_is_the_far_side_and_its_gap_is_over_the_diameter():
    v, f = two_plates(0.05)
    cut = cut_geodesic_disk(v, f, np.array([0.5, 0.5, 0.0]), 0.1)
    loop = np.asarray(cut.loop)
    ids, diameter = signal.far_side(cut.vertices, cut.faces, loop)
    lower = cut.vertices[:, 2] < -0.01
    assert lower[ids].sum() == lower.sum()  # the whole other component is far
    assert 0.15 < diameter < 0.21
    s = signal.wall_signals(cut.vertices, cut.faces, loop)
    # the lower plate's grid lies under the loop's vertices: the gap is the plates' distance
    assert s["gap loop"] == pytest.approx(0.05 / diameter, rel=1e-9)
    assert s["gap centre"] == pytest.approx(
        np.hypot(0.05, np.linalg.norm(cut.vertices[loop].mean(0)[:2] - [0.5, 0.5])) / diameter,
        abs=0.02 / diameter)
    assert s["wrap"] < 1e-9  # flat


def test_on_one_plate_the_far_side_is_far_in_space_too():
    v, f = plate()
    cut = cut_geodesic_disk(v, f, np.array([0.5, 0.5, 0.0]), 0.1)
    loop = np.asarray(cut.loop)
    ids, diameter = signal.far_side(cut.vertices, cut.faces, loop)
    assert len(ids) > 0
    s = signal.wall_signals(cut.vertices, cut.faces, loop)
    # along the edges' graph a far vertex is at least 2 diameters off; in space, on a flat
    # grid, no less than 2 / sqrt(2) of that (a graph path is at most sqrt(2) too long)
    assert s["gap loop"] >= signal.FAR / np.sqrt(2) - 1e-9
    nothing_far = signal.wall_signals(cut.vertices, cut.faces, loop, far=100.0)
    assert nothing_far["gap loop"] == np.inf and nothing_far["gap centre"] == np.inf


def row(mesh, lh, fair2, fair3=9.0):
    """A study row where the library keeps the λ-H fill (decisive on the hidden rings)."""
    ev = {"hidden": {"fair2": 1.0, "fair3": 0.9, "conformal": 0.4}, "sibling": {},
          "shallower": False, "crossed": False, "n_edges": 30,
          "adv2": {"hidden": {"conformal": (0.6, 0.06), "fair3": (0.1, 0.05)}},
          "adv3": {"hidden": {"conformal": (0.5, 0.05)}}}
    return {"set": "thin_shells", "mesh": mesh, "hole": 0, "evidence": ev,
            "errors": {"fair": fair2, "fair3": fair3, "conformal_raw": lh, "conformal": lh,
                       "cgal": 1.0},
            "status": {"conformal_raw": "ok"}}


def test_the_screen_counts_the_kept_fills_a_threshold_would_hand_back():
    import smooth_selfcheck_study as study

    rows = [row("a", 3.0, 1.0), row("b", 1.0, 3.0), row("c", 1.0, 1.1)]
    assert [study.library_rule(r["evidence"]) for r in rows] == ["conformal"] * 3
    assert study._faired(rows[0]["evidence"]) == "fair2"
    signals = [{"set": "thin_shells", "mesh": m, "hole": 0, "gap loop": g, "wrap": w}
               for m, g, w in (("a", 0.1, 0.5), ("b", 0.3, 0.4), ("c", 0.5, 0.6))]
    text = signal.screen(signals, rows)
    assert text.startswith("3 holes where the λ-H fill is kept: 1.5× farther than the faired "
                           "fill written without it on 1, 1.5× closer on 1")
    # a gap of at most 0.1 hands back hole a only; a wrap of at least 0.5 hands back a and
    # c (c's λ-H fill is not 1.5x closer: nothing broken, but one more hole switched)
    assert "| gap loop | <= 0.1 | 1 | 1 | 0 |" in text
    assert "| wrap | >= 0.5 | 2 | 1 | 0 |" in text
    assert "| thin_shells a #0 | 3.00 | 0.100 | 0.500 |" in text
