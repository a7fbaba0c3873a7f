"""The session 51 decomposition (``benchmarks/lambda_h_losses.py``): its pinned coupled solve
on an analytic torus, and the cases it collects from hand-made rows. No benchmark mesh is
loaded."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
from test_lambda_h_sources import torus_hole as sources_torus_hole

from surfinpaint.representation import on_mesh

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
losses = pytest.importorskip("lambda_h_losses")


def torus_hole():
    """Session 39's torus hole (``test_lambda_h_sources``) and a start far from the surface:
    the hole's vertices squeezed to a twentieth of their spread around their centroid."""
    truth, faces, uv, free = sources_torus_hole()
    start = truth.copy()
    start[free] = truth[free].mean(axis=0) + 0.05 * (truth[free] - truth[free].mean(axis=0))
    return truth, faces, uv, free, start


def test_the_unpinned_system_is_the_librarys_solve():
    truth, faces, uv, free, start = torus_hole()
    library = on_mesh.inpaint_on_mesh(start, faces, uv, free)
    pinned = on_mesh.inpaint_on_mesh(start, faces, uv, free,
                                     system=losses.PinnedSystem(start, faces, uv, free))
    assert np.abs(pinned - library).max() < 1e-12
    # a harmonic term in H's operator changes the fill (it is not the library's)
    harmonic = losses.lagged_solve(losses.PinnedSystem(start, faces, uv, free, harmonic=0.3),
                                   start, 20)
    assert np.abs(harmonic - library)[free].max() > 1e-3  # measured 1.3e-3


def test_the_true_lambda_and_h_pinned_give_the_surface_back():
    truth, faces, uv, free, start = torus_hole()
    lam, H = losses.lambda_h_at(truth, faces, uv)
    scale = np.ptp(truth[free], axis=0).max()
    system = losses.PinnedSystem(start, faces, uv, free)
    system.lam_pin, system.H_pin = lam, H
    rebuilt = losses.lagged_solve(system, start, 20)
    # (the tangential part of L φ is not in the rebuild: not to round-off)
    assert np.abs(rebuilt - truth)[free].max() < 2e-4 * scale
    assert np.array_equal(rebuilt[~free], start[~free])
    # with H alone pinned 20 % off, the rebuilt surface is far from it
    system = losses.PinnedSystem(start, faces, uv, free)
    system.lam_pin, system.H_pin = lam, 1.2 * H
    off = losses.lagged_solve(system, start, 20)
    assert np.abs(off - truth)[free].max() > 1e-2 * scale


def _rows(method_errors: dict, status: str) -> list[dict]:
    extra = {"kind": "smooth", "split": "holdout9"}
    return [{"case": "blob", "hole": 0, "boundary_edges": 20, "method": m, "mean_pct": e,
             "status": status if m == "conformal" else "ok", "extra": extra}
            for m, e in method_errors.items()]


@pytest.mark.parametrize(("errors", "status", "group"), [
    ({"fair": 1.0, "fair3": 0.5, "conformal": 0.8}, "ok", "loss"),  # 1.6x fair3
    ({"fair": 1.0, "fair3": 0.5, "conformal": 0.7}, "ok", ""),  # 1.4x
    ({"fair": 1.0, "fair3": 0.5, "conformal": 0.8}, "selected", ""),  # a faired fill written
    ({"fair": 0.3, "fair3": 0.5, "conformal": 0.19}, "ok", "control"),  # 1.58x closer
    ({"fair": 0.3, "fair3": 0.5, "conformal": 0.21}, "ok", ""),
])
def test_cases_of_validation_rows(tmp_path, errors, status, group):
    path = tmp_path / "rows.json"
    path.write_text(json.dumps({"rows": _rows(errors, status)}))
    (case,) = losses.cases_of_rows(path)
    assert case["group"] == group
    assert case["set"] == "holdout9" and case["closer"] == min(
        ("fair2", errors["fair"]), ("fair3", errors["fair3"]), key=lambda x: x[1])[0]


def test_controls_on_the_meshes_of_the_losses():
    cases = [{"set": "s", "mesh": m, "hole": k, "group": g, "kind": kind}
             for m, k, g, kind in (("a", 0, "loss", "smooth"), ("a", 1, "control", "smooth"),
                                   ("b", 0, "control", "smooth"), ("c", 0, "loss", "cad"),
                                   ("c", 1, "control", "cad"), ("a", 2, "", "smooth"))]
    picked = losses.selected(cases, ["loss", "control"], ["smooth"], same_meshes=True)
    assert [(c["mesh"], c["hole"]) for c in picked] == [("a", 0), ("a", 1)]
    everything = losses.selected(cases, ["loss", "control"])
    assert len(everything) == 5


def test_only_spent_holdouts_are_read():
    losses.set_manifest("holdout27")
    for refused in ("holdout28", "holdout29", "validation"):
        with pytest.raises(SystemExit):
            losses.set_manifest(refused)
