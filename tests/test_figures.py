"""Pictures: each hole framed along its normal, from outside, zoomed to it, with nothing
drawn over it; scale bars that measure; the before/after picture and the report's panels
drawn with their legend.

The folded case is a strip bent into a U, like the two banks of a sulcus: the hole is in
the lower bank, whose outside faces the upper one, so the upper bank lies between any
camera on the outside and the hole.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import grid_mesh

from surfinpaint.app.figures import (
    add_scale_bar,
    before_after,
    before_after_figure,
    close_up,
    frame_hole,
    render_hole,
)
from surfinpaint.app.fill_report import written
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.geometry.cutting import cut_holes

WHITE = 245


def _u_fold(gap: float = 0.4, n: int = 60):
    """A strip bent into a U: lower bank z = 0 (x in [0, 2]), a half circle of diameter
    ``gap``, upper bank z = gap back over it; oriented so the lower bank's normal is +z
    (towards the upper bank: the outside of a sulcus's walls is the gap between them)."""
    r = gap / 2
    length = 2.0 + np.pi * r + 2.0
    v, f = grid_mesh(n * 3, n // 2)  # x in [0, 1] along the strip, y across
    s = v[:, 0] * length
    t = (v[:, 1] - 0.5) * 1.6
    theta = np.clip((s - 2.0) / r, 0.0, np.pi)
    x = np.where(s < 2.0, s, np.where(s <= 2.0 + np.pi * r, 2.0 + r * np.sin(theta),
                                      2.0 - (s - 2.0 - np.pi * r)))
    z = np.where(s < 2.0, 0.0, np.where(s <= 2.0 + np.pi * r, r * (1 - np.cos(theta)), gap))
    return np.column_stack([x, t, z]), f


def _hole_in_lower_bank(gap: float = 0.4):
    # near the bend, so the upper bank is joined to the hole's surroundings within the
    # picture (a piece not joined there is left out anyway)
    v, f = _u_fold(gap)
    centre = int(np.argmin(np.linalg.norm(v - [1.65, 0.0, 0.0], axis=1)))
    cut = cut_holes(v, f, [centre], [0.3])
    return cut.vertices, cut.faces, cut.holes[0].loop


def test_the_frame_looks_along_the_holes_normal_from_outside():
    v, f, loop = _hole_in_lower_bank()
    frame = frame_hole(v, f, loop)
    # the lower bank's normal is +z: the camera is above it, looking down
    assert frame.direction @ [0.0, 0.0, 1.0] > 0.999
    assert abs(frame.up @ frame.direction) < 1e-12
    uv, _ = frame.project(v[loop])
    # zoomed to the hole: its outline spans 1/1.8 of the half height
    assert np.abs(uv).max() == pytest.approx(frame.half_height / 1.8)
    # a loop given backwards frames the same
    backwards = frame_hole(v, f, loop[::-1])
    np.testing.assert_allclose(backwards.direction, frame.direction)


def test_nothing_is_drawn_over_the_hole():
    v, f, loop = _hole_in_lower_bank()
    frame = frame_hole(v, f, loop)
    view = close_up(v, f, loop, frame)
    from matplotlib.path import Path as Outline

    uv, depth = frame.project(view.vertices)
    centres = uv[view.faces].mean(axis=1)
    inside = Outline(uv[view.loops[0]]).contains_points(centres)
    # the upper bank (z = gap, in front of the hole) is in the picture around the hole
    assert (view.vertices[view.faces][..., 2] > 0.39).all(axis=1).any()
    # but none of it over the hole
    assert not inside.any()


def test_the_rendered_hole_is_open_and_its_fill_shows():
    v, f, loop = _hole_in_lower_bank()
    result = fill_holes(v, f, method="fair")
    patch = result.faces[result.n_original_faces:]
    images, _ = render_hole(v, f, loop, [(result.vertices, patch)], size=(600, 480))
    before, after = images
    height, width = before.shape[:2]
    middle = (slice(height // 2 - 5, height // 2 + 5), slice(width // 2 - 5, width // 2 + 5))
    # the background shows through the hole (before the fix, the upper bank covered it)
    assert (before[middle] >= WHITE).all()
    # the fill, in the patch colour (orange: red well above blue), but for its edges
    red, blue = after[middle][..., 0].astype(int), after[middle][..., 2].astype(int)
    assert np.mean(red - blue > 60) > 0.75


def test_the_scale_bar_measures_the_picture():
    # a flat square with a round hole of diameter 0.6, seen head-on: the hole's width in
    # pixels, read off the picture, times the units per pixel is its diameter
    v, f = grid_mesh(60, 60)
    centre = int(np.argmin(np.linalg.norm(v - [0.5, 0.5, 0.0], axis=1)))
    cut = cut_holes(v, f, [centre], [0.3])
    loop = cut.holes[0].loop
    images, units_per_pixel = render_hole(cut.vertices, cut.faces, loop, [], size=(400, 320))
    row = (images[0][images[0].shape[0] // 2] >= WHITE).all(axis=1)
    middle = len(row) // 2
    assert row[middle]
    # the white run through the middle: the hole (the square's edges are in the picture)
    left = middle - np.argmin(row[middle::-1])
    right = middle + np.argmin(row[middle:])
    measured = (right - left - 1) * units_per_pixel
    points = cut.vertices[loop]
    assert measured == pytest.approx(np.ptp(points[:, 0]), rel=0.03)

    from matplotlib.figure import Figure

    ax = Figure().add_subplot()
    ax.imshow(images[0])
    length = add_scale_bar(ax, units_per_pixel)
    width_units = images[0].shape[1] * units_per_pixel
    assert length in (0.1, 0.2, 0.5) and length <= width_units / 4 < 2.5 * length
    bar = ax.lines[0].get_xdata()
    assert (bar[1] - bar[0]) * units_per_pixel == pytest.approx(length)


def test_before_after_frames_every_filled_hole_with_a_legend(tmp_path):
    v, f, loop = _hole_in_lower_bank()
    result = fill_holes(v, f, method="fair")
    path = before_after(v, f, result, tmp_path / "ba.png")
    import matplotlib.image

    image = matplotlib.image.imread(path)
    assert image.shape[0] > 600 and image.shape[1] > 1000


def test_before_after_close_ups_say_which_fill_was_written():
    v, f, loop = _hole_in_lower_bank()
    for method, words in (("fair", "faired fill (bilaplacian)"), ("conformal", None)):
        result = fill_holes(v, f, method=method)
        report = result.reports[0]
        expected = words or written(report)
        titles = [ax.get_title() for ax in before_after_figure(v, f, result).axes]
        assert f"hole {report.index} ({report.n_edges} edges),\nbefore" in titles
        assert f"hole {report.index} ({report.n_edges} edges),\nafter: {expected}" in titles


def test_render_meshes_draws_each_mesh_view_as_a_panel(tmp_path, monkeypatch):
    """A :class:`MeshView` per panel: the highlighted patch in its colour, the loop in red,
    side by side at the window's size."""
    from PIL import Image

    from surfinpaint.app.figures import PATCH, MeshView, render_meshes
    from surfinpaint.data import sphere

    monkeypatch.delenv("DISPLAY", raising=False)
    v, f = sphere(2)
    loop = np.unique(f[:3])  # any vertices: drawn as a closed red line
    panels = [MeshView(v, f, loops=[loop], title="before"),
              MeshView(v, f, highlight=np.arange(len(f) // 2), title="after")]
    path = render_meshes(panels, tmp_path / "panels.png", window_size=(400, 200))
    rgb = np.asarray(Image.open(path).convert("RGB")).astype(int)
    assert rgb.shape == (200, 400, 3)
    patch = np.array([int(PATCH[k:k + 2], 16) for k in (1, 3, 5)])
    orange = (np.abs(rgb - patch).sum(axis=2) < 90)
    red = (rgb[..., 0] > 150) & (rgb[..., 1] < 90) & (rgb[..., 2] < 90)
    assert orange[:, 200:].sum() > 100 and orange[:, :200].sum() < 10  # highlight: right only
    assert red[:, :200].sum() > 20  # the loop: left


def _long_thin_tube(length: float = 50.0, radius: float = 0.2, sides: int = 6):
    """A hexagonal tube one face long, capped at its far end and open at z = 0: its loop
    of ``sides`` edges is a hole whose every face reaches ``length`` away (an ant's leg in
    PyVista's ``ant.ply``, a thin part's end)."""
    angle = 2 * np.pi * np.arange(sides) / sides
    ring = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), np.zeros(sides)])
    v = np.vstack([ring, ring + [0, 0, length], [[0, 0, length]]])
    k, nxt = np.arange(sides), (np.arange(sides) + 1) % sides
    f = np.vstack([np.column_stack([k, nxt, sides + nxt]),
                   np.column_stack([k, sides + nxt, sides + k]),
                   np.column_stack([sides + k, sides + nxt, np.full(sides, 2 * sides)])])
    return v, f


def test_a_hole_whose_faces_all_reach_far_is_drawn_with_its_loop(tmp_path):
    # PyVista's ant: `fill --png` failed with IndexError (no face of the hole's close-up
    # was near enough, its loop's ids -1) and `batch --png` drew no picture
    v, f = _long_thin_tube()
    result = fill_holes(v, f, method="fair")
    assert [r.n_edges for r in result.reports if not r.skipped] == [6]
    loop = result.reports[0].loop
    view = close_up(v, f, loop, frame_hole(v, f, loop))
    assert (view.loops[0] >= 0).all()
    np.testing.assert_array_equal(view.vertices[view.loops[0]], v[loop])
    path = before_after(v, f, result, tmp_path / "tube.png")
    assert path.stat().st_size > 0
