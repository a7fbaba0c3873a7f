"""The truth-free test of a hole reaching across a thin part (its loop on two opposite faces)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh

from surfinpaint.data import cube, sphere
from surfinpaint.geometry.cutting import cut_geodesic_disk

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from loop_sheets import loop_sheets  # noqa: E402


def _slab():
    """A plate 1 × 1 × 0.1 (about 2 edge lengths thick), sharp-edged."""
    v, f = cube(20)
    return v * np.array([1.0, 1.0, 0.1]), f


def _rod():
    """A rod 0.1 across (about 3 edge lengths), 1.2 long, round-ended, along z."""
    mesh = trimesh.creation.capsule(height=1.0, radius=0.05, count=[24, 24])
    return np.asarray(mesh.vertices), np.asarray(mesh.faces)


def _inside_out(mesh):
    """The same surface with its faces turned: the plate's rim seen from inside a slot."""
    v, f = mesh
    return v, f[:, ::-1]


# (name, mesh, hole centre, geodesic radius, across a thin part)
CASES = [
    ("slab's edge", _slab, (0.5, 0.0, 0.05), 0.16, True),
    ("rod's tip", _rod, (0.0, 0.0, 0.55), 0.2, True),
    ("plate's face away from its rim", _slab, (0.5, 0.5, 0.1), 0.16, False),
    ("sphere", lambda: sphere(3), (0.0, 0.0, 1.0), 0.5, False),
    ("slot's facing walls", lambda: _inside_out(_slab()), (0.5, 0.0, 0.05), 0.16, False),
]


@pytest.mark.parametrize(("name", "make", "centre", "radius", "thin"), CASES,
                         ids=[c[0] for c in CASES])
def test_loop_sheets_tells_holes_across_thin_parts(name, make, centre, radius, thin):
    v, f = make()
    cut = cut_geodesic_disk(v, f, np.array(centre), radius)
    sheets = loop_sheets(cut.vertices, cut.faces, cut.loop)
    assert (sheets.opposed > 0) == thin
    assert np.isfinite(sheets.gap) == thin


def test_gap_is_the_parts_thickness_over_the_holes_width():
    v, f = _slab()
    cut = cut_geodesic_disk(v, f, np.array([0.5, 0.0, 0.05]), 0.16)
    sheets = loop_sheets(cut.vertices, cut.faces, cut.loop)
    # the two faces 0.1 apart, the loop about 0.3 wide along the rim
    assert 0.1 / (cut.diameter * 1.05) <= sheets.gap <= 0.1 * 1.5 / cut.diameter
    assert sheets.opposed > 0.5


def test_the_truth_label_sees_the_far_face_a_hole_reaches():
    """``benchmarks/thin_holes.py``'s truth-based label: removed vertices facing away from
    the centre's normal, behind its tangent plane (the plate's underside), and their depth."""
    import sys
    from pathlib import Path

    from surfinpaint.geometry.mesh import mean_edge_length, vertex_normals

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    thin_holes = pytest.importorskip("thin_holes")
    v, f = _slab()
    h = mean_edge_length(v, f)
    normals = vertex_normals(v, f)
    near_rim = cut_geodesic_disk(v, f, np.array([0.5, 0.1, 0.1]), 0.35)
    label = thin_holes.truth_label(v, f, normals, near_rim, h)
    assert label["thin"] and label["far"] > 0
    assert label["far_depth_h"] == pytest.approx(0.1 / h, rel=1e-6)  # the plate's thickness
    inside = cut_geodesic_disk(v, f, np.array([0.5, 0.5, 0.1]), 0.3)
    assert not thin_holes.truth_label(v, f, normals, inside, h)["thin"]
