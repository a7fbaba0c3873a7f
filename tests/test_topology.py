"""Which pairs of filled holes :func:`surfinpaint.fill.topology.topology_changes` takes for
the two ends of a tube cut across, and :func:`wall_alignment`, the test that tells a tube's
cut end from a hole in a sheet (the two banks of a sulcus face each other as tube ends do)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from surfinpaint.data import fsaverage5, torus
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.fill.topology import TUBE_WALL_COSINE, topology_changes, wall_alignment
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import boundary_loops


def _grid(n: int = 12) -> tuple[np.ndarray, np.ndarray]:
    """A flat n × n square of 2n² triangles in the plane z = 0, normals +z."""
    x, y = np.meshgrid(np.arange(n + 1.0), np.arange(n + 1.0), indexing="ij")
    v = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    k = (np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]).ravel()
    f = np.concatenate([np.column_stack([k, k + n + 1, k + 1]),
                        np.column_stack([k + 1, k + n + 1, k + n + 2])])
    return v, f


def _open_cylinder(n_around: int = 24, n_along: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """A tube of radius 1 along z, open at both ends."""
    t = 2 * np.pi * np.arange(n_around) / n_around
    z = np.arange(n_along + 1.0) * 0.3
    v = np.column_stack([np.tile(np.cos(t), len(z)), np.tile(np.sin(t), len(z)),
                         np.repeat(z, n_around)])
    i = np.arange(n_around)
    j = (i + 1) % n_around
    rows = [np.column_stack([r * n_around + i, r * n_around + j, (r + 1) * n_around + i])
            for r in range(n_along)]
    rows += [np.column_stack([r * n_around + j, (r + 1) * n_around + j, (r + 1) * n_around + i])
             for r in range(n_along)]
    return v, np.concatenate(rows)


def test_wall_alignment_of_a_sheet_a_tube_end_and_no_face():
    v, f = _grid()
    hole = np.flatnonzero(np.linalg.norm(v[:, :2] - 6, axis=1) < 2.5)
    keep = ~np.isin(f, hole).any(axis=1)
    # the hole's loop, not the square's border
    (loop,) = [lp for lp in boundary_loops(f[keep])
               if np.linalg.norm(v[lp, :2] - 6, axis=1).max() < 4]
    assert len(loop) >= 8
    # a hole in a flat sheet: every face next to it lies across the fill's normal
    assert wall_alignment(v, f[keep], loop, np.array([0, 0, 2.0])) == pytest.approx(1.0)
    assert wall_alignment(v, f[keep], loop, np.array([0, 0, -1.0])) == pytest.approx(1.0)
    # a tube's cut end: the wall runs along the axis, the fill's normal
    v, f = _open_cylinder()
    end = np.arange(24)
    assert wall_alignment(v, f, end, np.array([0, 0, -1.0])) < 1e-12
    # tilted 30 degrees: |cos| of the wall's normals against it averages (2/pi) sin 30
    tilted = np.array([np.sin(np.radians(30)), 0, -np.cos(np.radians(30))])
    assert wall_alignment(v, f, end, tilted) == pytest.approx(1 / np.pi, rel=0.02)
    # no face touches the loop
    assert wall_alignment(v, f, np.array([10_000]), np.array([0, 0, 1.0])) == 0.0


def _torus_cut(half_width: float) -> tuple[np.ndarray, np.ndarray]:
    v, f = torus(n_major=48, n_minor=16)
    c = v[f].mean(1)
    keep = np.abs(np.arctan2(c[:, 1], c[:, 0])) > half_width
    return v, f[keep]


def _quiet_fill(v, f):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fill_holes(v, f, method="fair", jobs=1)


# (surface, hole centres (fsaverage5 vertex ids) or a torus cut's half-width, radius, warned):
# the torus's tube cut across is the case the warning is for; the fsaverage5 pairs sit on the
# two banks of a sulcus, 4-8 mm apart, and were taken for tube ends before session 37
CASES = [
    ("torus", 0.1, None, True),
    ("torus", 0.2, None, True),
    ("torus", 0.3, None, True),
    ("pial", (706, 7465), 4.0, False),
    ("pial", (3533, 7543), 4.0, False),
    ("pial", (1828, 3381), 3.0, False),
    ("white", (5877, 7465), 4.0, False),
    ("white", (4398, 6389), 4.0, False),
]


@pytest.mark.parametrize(("surface", "where", "radius", "warned"), CASES)
def test_tube_ends_warn_and_the_banks_of_a_sulcus_do_not(surface, where, radius, warned):
    if surface == "torus":
        v, f = _torus_cut(where)
    else:
        v, f = fsaverage5(surface, "left")
        cut = cut_holes(v, f, list(where), radius)
        v, f = cut.vertices, cut.faces
    result = _quiet_fill(v, f)
    assert len(result.reports) == 2
    assert (len(topology_changes(result)) == 1) is warned
    assert (len(result.topology) == 1) is warned
    # the fills face each other on every case: the wall test is what tells them apart
    known = result.faces[:result.n_original_faces]
    counts = np.array([r.new_faces for r in result.reports])
    starts = np.cumsum(counts) - counts
    alignments = []
    for report, start, count in zip(result.reports, starts, counts, strict=True):
        corners = result.vertices[result.faces[result.n_original_faces + start:][:count]]
        normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]).sum(0)
        alignments.append(wall_alignment(result.vertices, known, report.loop, normal))
    assert (max(alignments) < TUBE_WALL_COSINE) is warned
