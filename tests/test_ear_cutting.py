"""MeshFix's greedy ear cutting of a hole's loop (surfinpaint.fill.liepa.ear_cutting) and
the conformal method's option that writes it (ConformalOptions.ear_cut_ratio)."""

import numpy as np
import pytest

from surfinpaint.data import cube
from surfinpaint.fill.conformal import conformal_fill
from surfinpaint.fill.conformal.options import ConformalOptions
from surfinpaint.fill.liepa import ear_cutting
from surfinpaint.fill.liepa.ear_cutting import ear_cut_triangulation
from surfinpaint.fill.liepa.triangulation import minimum_weight_triangulation
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import boundary_loops, mean_edge_length, unique_edges
from surfinpaint.geometry.validation import zero_area_faces


def _cube_hole(at):
    v, f = cube(16)
    centre = int(np.argmin(np.linalg.norm(v - at, axis=1)))
    return cut_geodesic_disk(v, f, centre, 6 * mean_edge_length(v, f))


def _off_the_cube(points):
    """Distance of points inside the unit cube to its surface."""
    return np.minimum(points, 1 - points).min(axis=1)


def test_ear_cutting_continues_both_faces_across_a_cube_edge():
    cut = _cube_hole((0.5, 0.0, 0.0))
    p = cut.vertices
    ears = ear_cut_triangulation(p, cut.faces, cut.loop)
    assert len(ears) == len(cut.loop) - 2
    assert _off_the_cube(p[ears].mean(axis=1)).max() < 1e-12  # every triangle on a face
    # the minimum-weight triangulation (area second) cuts the edge off: what ear cutting is for
    liepa = minimum_weight_triangulation(p, cut.loop, cut.faces)
    assert _off_the_cube(p[liepa].mean(axis=1)).max() > 0.01


@pytest.mark.parametrize("at", [(0.5, 0.0, 0.0), (0.0, 0.0, 0.0), (0.5, 0.5, 0.0)])
def test_ear_cutting_closes_the_hole_oriented_as_the_mesh(at):
    cut = _cube_hole(at)
    for loop in (cut.loop, cut.loop[::-1], np.roll(cut.loop, 5)):
        faces = np.vstack([cut.faces, ear_cut_triangulation(cut.vertices, cut.faces, loop)])
        assert (unique_edges(faces)[2] == 2).all()  # closed and manifold
        half = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
        assert len(np.unique(half, axis=0)) == len(half)  # each half-edge once: oriented


@pytest.mark.parametrize("bad", [0, -1.0, True, np.inf, "0.5"])
def test_ear_cut_ratio_is_checked(bad):
    with pytest.raises(ValueError, match="ear_cut_ratio"):
        ConformalOptions(ear_cut_ratio=bad)


def test_ear_cut_written_only_where_the_hidden_rings_prefer_it():
    cut = _cube_hole((0.5, 0.0, 0.0))
    assert ConformalOptions().ear_cut_ratio is None  # off by default
    # the flatness rule (the default since session 51) would write its ear cut first
    flat_off = ConformalOptions(ear_cut_flat=None)
    default = conformal_fill(cut.vertices, cut.faces, cut.loop, flat_off)
    assert not default.selection.startswith("ear cutting")
    # the λ-H fill's hidden-ring score is the best here, the ear cut's a few times it:
    # written with a generous ratio, not with 1
    generous = conformal_fill(cut.vertices, cut.faces, cut.loop,
                              ConformalOptions(ear_cut_ratio=100.0, ear_cut_flat=None))
    assert generous.selection.startswith("ear cutting")
    assert len(generous.vertices) == 0
    np.testing.assert_array_equal(
        generous.faces, ear_cut_triangulation(cut.vertices, cut.faces, cut.loop))
    strict = conformal_fill(cut.vertices, cut.faces, cut.loop,
                            ConformalOptions(ear_cut_ratio=1.0, ear_cut_flat=None))
    assert strict.kind == default.kind
    np.testing.assert_array_equal(strict.vertices, default.vertices)


def _bent_sheet_hole():
    """A 12 × 12 grid of squares bent along x = 6 (z = x - 6 beyond), without the 4 × 5
    squares at rows 1-4, columns 1-5: a loop with straight runs on which greedy cutting
    ends with a flat ear."""
    n = 12
    x, y = np.meshgrid(np.arange(n + 1.0), np.arange(n + 1.0))
    v = np.column_stack([x.ravel(), y.ravel(), np.maximum(x.ravel() - 6, 0)])
    a = (np.arange(n)[:, None] * (n + 1) + np.arange(n)).ravel()
    faces = np.stack([np.column_stack([a, a + 1, a + n + 2]),
                      np.column_stack([a, a + n + 2, a + n + 1])], axis=1)
    rows, cols = np.divmod(np.arange(n * n), n)
    kept = ~((rows >= 1) & (rows < 5) & (cols >= 1) & (cols < 6))
    faces = faces[kept].reshape(-1, 3)
    loop = min(boundary_loops(faces), key=len)
    return v, faces, loop


def test_a_flat_ear_is_flipped_away_keeping_the_surface(monkeypatch):
    v, faces, loop = _bent_sheet_hole()
    flipped = ear_cut_triangulation(v, faces, loop)
    assert len(zero_area_faces(v, flipped)) == 0
    closed = np.vstack([faces, flipped])
    half = np.concatenate([closed[:, [0, 1]], closed[:, [1, 2]], closed[:, [2, 0]]])
    assert len(np.unique(half, axis=0)) == len(half)
    # the flip is what removes it, and the two triangles cover what the flat one and its
    # neighbour did: the same area
    monkeypatch.setattr(ear_cutting, "_flattened_straight_ears", lambda v, t: t)
    greedy = ear_cut_triangulation(v, faces, loop)
    assert len(zero_area_faces(v, greedy)) == 1

    def area(t):
        return np.linalg.norm(np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]]),
                              axis=1).sum() / 2

    assert area(flipped) == pytest.approx(area(greedy), rel=1e-12)


def test_an_ear_cut_fill_is_reported_as_a_triangulation_not_a_faired_fill():
    from surfinpaint import fill_holes
    from surfinpaint.app.fill_report import written

    cut = _cube_hole((0.5, 0.0, 0.0))
    report = fill_holes(cut.vertices, cut.faces,
                        options=ConformalOptions(ear_cut_ratio=100.0,
                                                 ear_cut_flat=None)).reports[0]
    assert report.note.startswith("ear cutting") and report.new_vertices == 0
    assert report.ear_cut == "hidden rings" and report.method == "fair"
    assert written(report) == "ear-cut fill (hidden rings), not faired"
