"""Texture coordinates of a hole a UV seam runs through (session 37): the new faces split
among the charts along the loop, each part in its own chart's region of the atlas and none
mirrored, the seam running on into the hole."""

import warnings

import numpy as np
import pytest

from surfinpaint import fill_holes
from surfinpaint.fill.face_attributes import fill_result_corner_attributes
from surfinpaint.fill.seam_charts import loop_arcs
from surfinpaint.io import MeshWarning

SEAM_X, SEAM_Y = 0.2, 0.1  # on grid lines (spacing 0.1), off the hole's centre


def _holed_plane(n=21, radius=0.45):
    """A grid on [-1, 1]² (counter-clockwise faces), the faces within ``radius`` of the
    origin removed."""
    t = np.linspace(-1.0, 1.0, n)
    x, y = np.meshgrid(t, t, indexing="ij")
    vertices = np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    b, c, d = a + n, a + n + 1, a + 1
    faces = np.vstack([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    centroids = vertices[faces].mean(axis=1)
    return vertices, faces[np.linalg.norm(centroids[:, :2], axis=1) > radius]


def _charts(centroids, three):
    """Each face's chart: 0 left of the seam x = SEAM_X; right of it 1, or with ``three``
    1 below y = SEAM_Y and 2 above (a seam that forks inside the hole)."""
    right = centroids[:, 0] > SEAM_X
    return np.where(right, 1 + (three & (centroids[:, 1] > SEAM_Y)), 0)


# each chart's place in the atlas: uv = 0.2 (x, y) + offset, apart from the others
OFFSETS = np.array([[0.3, 0.5], [0.6, 0.3], [0.6, 0.8]])


def _atlas(vertices, faces, chart, turned=False):
    """(f, 3, 2) corner UVs, and each chart's rectangle (its island: ``(3, 2, 2)`` low/high);
    ``turned``: chart 0 laid in the atlas a quarter turn round (as packers do)."""
    corners = 0.2 * vertices[faces][:, :, :2]
    if turned:
        corners[chart == 0] = corners[chart == 0][:, :, ::-1] * [-1.0, 1.0]
    corners = corners + OFFSETS[chart][:, None, :]
    boxes = np.array([[corners[chart == k].reshape(-1, 2).min(axis=0),
                       corners[chart == k].reshape(-1, 2).max(axis=0)]
                      if (chart == k).any() else np.full((2, 2), np.nan) for k in range(3)])
    return corners, boxes


def _signed(uv):
    """Twice the signed area of each UV triangle ``(f, 3, 2)``."""
    d1, d2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    return d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]


@pytest.mark.parametrize("turned", [False, True])
@pytest.mark.parametrize("three", [False, True])
def test_new_faces_lie_in_one_chart_each_and_none_is_mirrored(three, turned):
    v, f = _holed_plane()
    result = fill_holes(v, f, method="fair")
    chart = _charts(v[f].mean(axis=1), three)
    corners, boxes = _atlas(v, f, chart, turned)
    assert (_signed(corners) > 0).all()
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshWarning)
        out = fill_result_corner_attributes(result, {"uv": corners})["uv"]
    assert np.array_equal(out[: len(f)], corners)
    new = out[len(f):]
    assert len(new) > 30 and np.isfinite(new).all()
    # mirrored: a UV triangle turned against the charts' (all counter-clockwise); session
    # 36's continuation of one chart mirrored 18 of the 124 where chart 0 is turned
    assert (_signed(new) > 0).all()
    # each new face wholly inside one chart's island (session 36 continued the chart along
    # most of the loop, into the gap between the islands on the seam's other side)
    inside = ((new[:, None] >= boxes[None, :, None, 0] - 1e-12)
              & (new[:, None] <= boxes[None, :, None, 1] + 1e-12)).all(axis=(2, 3))
    assert inside.any(axis=1).all()
    # every chart along the loop has its share of the hole
    assert (inside.sum(axis=0) > 0).sum() == (3 if three else 2)
    # the seam runs on into the hole: where it meets the loop, the new corners take a
    # value in each chart beside it
    loop = result.reports[0].loop
    for p in loop[np.isclose(v[loop, 0], SEAM_X)]:
        assert len(np.unique(new[result.new_faces == p].round(9), axis=0)) >= 2


def test_loop_arcs_cut_the_loop_where_the_seams_meet_it():
    v, f = _holed_plane()
    result = fill_holes(v, f, method="fair")
    loop = result.reports[0].loop
    for three, count in [(False, 2), (True, 3)]:
        corners, _ = _atlas(v, f, _charts(v[f].mean(axis=1), three))
        near = np.isin(f, loop).any(axis=1)
        arcs = loop_arcs(f[near], corners[near], loop)
        assert arcs.count == count
        # each arc's values are one chart's: the positions mapped by it
        for which in range(count):
            ids, values = arcs.vertices(loop, which)
            offset = values - 0.2 * v[ids, :2]
            assert np.allclose(offset, offset[0]) and len(ids) >= 2
    # one chart along the whole loop: nothing to split
    corners, _ = _atlas(v, f, np.zeros(len(f), dtype=int))
    near = np.isin(f, loop).any(axis=1)
    assert loop_arcs(f[near], corners[near], loop) is None
