"""Conformal maps: exactness on planar meshes, low distortion on curved ones, topology checks."""

from __future__ import annotations

import numpy as np
import pytest

from surfinpaint.data import bumpy_disk, sphere, torus
from surfinpaint.errors import MeshError
from surfinpaint.fill.conformal.patch import disk_loop
from surfinpaint.geometry.mean_value import mean_value_map, untangle
from surfinpaint.geometry.mesh import boundary_loops, face_areas
from surfinpaint.geometry.parameterization import (
    angle_distortion,
    check_disk,
    conformal_distortion,
    disk_boundary,
    distortion_histogram,
    flipped_faces,
    lscm,
    pinched_vertices,
    rectangular_conformal_map,
)
from surfinpaint.representation.analytic import stereographic_sphere


def grid_mesh(n: int, m: int | None = None, extent=(0.0, 1.0, 0.0, 1.0), jitter: float = 0.0,
              seed: int = 0):
    """Triangulated rectangle: (n·m, 2) parameter points and CCW faces."""
    m = n if m is None else m
    u, v = np.meshgrid(np.linspace(extent[0], extent[1], n),
                       np.linspace(extent[2], extent[3], m), indexing="ij")
    uv = np.column_stack([u.ravel(), v.ravel()])
    if jitter:
        h = (extent[1] - extent[0]) / (n - 1)
        rng = np.random.default_rng(seed)
        inner = ((u > extent[0]) & (u < extent[1]) & (v > extent[2]) & (v < extent[3])).ravel()
        uv[inner] += rng.uniform(-jitter, jitter, (inner.sum(), 2)) * h
    idx = np.arange(n * m).reshape(n, m)
    a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
    c, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    faces = np.vstack([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return uv, faces


def planar(uv):
    return np.column_stack([uv, np.zeros(len(uv))])


def is_similarity(uv, xy, tol):
    """uv = a·xy + b (complex) for some a ≠ 0, within tol relative to the size."""
    z, w = xy[:, 0] + 1j * xy[:, 1], uv[:, 0] + 1j * uv[:, 1]
    A = np.column_stack([z, np.ones_like(z)])
    coef, *_ = np.linalg.lstsq(A, w, rcond=None)
    return np.abs(A @ coef - w).max() <= tol * np.ptp(w.real)


# ----------------------------------------------------------------------------- check_disk


def test_check_disk_accepts_disk():
    check_disk(*bumpy_disk(6))


def test_check_disk_closed_sphere():
    with pytest.raises(MeshError, match="closed sphere"):
        check_disk(*sphere(2))


def test_check_disk_annulus_counts_loops():
    uv, f = grid_mesh(9, extent=(-1, 1, -1, 1))
    keep = ~(np.abs(uv[f]).max(axis=2) < 0.3).all(axis=1)
    with pytest.raises(MeshError, match="2 boundary loops"):
        check_disk(planar(uv), f[keep])


def test_check_disk_torus_with_hole_has_genus_one():
    v, f = torus()
    with pytest.raises(MeshError, match="genus 1"):
        check_disk(v, f[1:])


def test_check_disk_components_and_degenerate_and_pinched():
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [5, 1, 0.0]])
    with pytest.raises(MeshError, match="2 connected components"):
        check_disk(v, np.array([[0, 1, 2], [3, 4, 5]]))
    v2 = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0.5, 0.5, 0.0]])
    with pytest.raises(MeshError, match=r"^1 degenerate \(zero-area\) triangle: face 1$") as err:
        check_disk(v2, np.array([[0, 1, 2], [0, 2, 3]]))
    assert err.value.faces == [1]
    bowtie = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0.0]])
    with pytest.raises(MeshError, match="pinched") as err:
        check_disk(bowtie, np.array([[0, 1, 2], [0, 3, 4]]))
    assert err.value.vertices == [0]
    assert pinched_vertices(np.array([[0, 1, 2], [0, 3, 4]])).tolist() == [0]


# ----------------------------------------------------------------------------- the maps


@pytest.mark.parametrize("jitter", [0.0, 0.3])
def test_lscm_of_planar_mesh_is_a_similarity(jitter):
    uv0, f = grid_mesh(15, 11, extent=(0, 1.4, 0, 1), jitter=jitter)
    uv = lscm(planar(uv0), f)
    assert np.nanmax(conformal_distortion(planar(uv0), f, uv)) < 1e-9
    assert is_similarity(uv, uv0, 1e-9)
    # normalization: parameter area equals surface area, box starts at the origin
    assert face_areas(uv, f).sum() == pytest.approx(1.4, rel=1e-12)
    assert np.allclose(uv.min(axis=0), 0.0)
    assert len(flipped_faces(f, uv)) == 0


def test_lscm_keeps_orientation():
    uv0, f = grid_mesh(8)
    uv = lscm(planar(uv0), f)
    d1, d2 = uv[f[:, 1]] - uv[f[:, 0]], uv[f[:, 2]] - uv[f[:, 0]]
    assert np.all(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] > 0)
    uv_rev = lscm(planar(uv0), f[:, ::-1])
    d1, d2 = uv_rev[f[:, 1]] - uv_rev[f[:, 0]], uv_rev[f[:, 2]] - uv_rev[f[:, 0]]
    assert np.all(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] < 0)  # CCW for the reversed faces


def test_rectangular_map_of_a_rectangle_is_the_identity_up_to_scale():
    uv0, f = grid_mesh(13, 7, extent=(0, 2, 0, 1), jitter=0.25)
    uv, corners = rectangular_conformal_map(planar(uv0), f)
    assert np.nanmax(conformal_distortion(planar(uv0), f, uv)) < 1e-9
    assert np.allclose(uv, uv0 - uv0[corners[0]], atol=1e-10) or is_similarity(uv, uv0, 1e-9)
    assert np.ptp(uv[:, 0]) / np.ptp(uv[:, 1]) == pytest.approx(2.0, rel=1e-9)
    # the corners are the rectangle's
    box = np.array([uv.min(0), [uv[:, 0].max(), uv[:, 1].min()], uv.max(0),
                    [uv[:, 0].min(), uv[:, 1].max()]])
    assert np.allclose(uv[corners], box, atol=1e-12)


def sphere_cap(n=21, half=0.6):
    uv0, f = grid_mesh(n, extent=(-half, half, -half, half))
    phi, _, _ = stereographic_sphere(uv0[:, 0], uv0[:, 1])
    return uv0, phi, f


def cylinder(n=25):
    uv0, f = grid_mesh(n, extent=(0, np.pi, 0, 1.5))
    return uv0, np.column_stack([np.cos(uv0[:, 0]), np.sin(uv0[:, 0]), uv0[:, 1]]), f


@pytest.mark.parametrize("surface", [sphere_cap, cylinder])
def test_maps_of_curved_conformal_meshes_have_low_distortion(surface):
    uv0, v, f = surface()
    for uv in (lscm(v, f), rectangular_conformal_map(v, f)[0]):
        mu = conformal_distortion(v, f, uv)
        # |μ| of the piecewise-linear sampling itself (the exact conformal coordinates)
        mu0 = conformal_distortion(v, f, uv0)
        assert np.median(mu) < 2 * np.median(mu0) + 1e-3
        assert np.percentile(np.abs(angle_distortion(v, f, uv)), 99) < 3.0
        assert len(flipped_faces(f, uv)) == 0


@pytest.mark.parametrize("mapper", [lscm, lambda v, f: rectangular_conformal_map(v, f)[0]])
def test_distortion_on_a_sphere_cap_vanishes_under_refinement(mapper):
    # a free-boundary conformal map is only unique up to a holomorphic change of
    # coordinates, so compare conformality, not coordinates: |μ| of the per-triangle affine
    # maps is O(h) (it is for the exact stereographic coordinates too)
    medians = []
    for n in (21, 41):
        _, v, f = sphere_cap(n)
        medians.append(np.median(conformal_distortion(v, f, mapper(v, f))))
    assert medians[0] < 0.02
    assert 1.8 < medians[0] / medians[1] < 2.2


def test_rectangular_corners_validation():
    uv0, f = grid_mesh(6)
    v = planar(uv0)
    with pytest.raises(ValueError, match="4 distinct"):
        rectangular_conformal_map(v, f, corners=np.array([0, 0, 5, 35]))
    with pytest.raises(MeshError, match="not on the boundary"):
        rectangular_conformal_map(v, f, corners=np.array([0, 5, 35, 14]))
    with pytest.raises(ValueError, match="boundary order"):
        rectangular_conformal_map(v, f, corners=np.array([0, 35, 5, 30]))
    uv, c = rectangular_conformal_map(v, f, corners=np.array([0, 30, 35, 5]))
    assert c.tolist() == [0, 30, 35, 5]


# ----------------------------------------------------------------------------- measures


def test_conformal_distortion_of_a_known_stretch():
    uv0, f = grid_mesh(5)
    stretched = uv0 * [2.0, 1.0]
    mu = conformal_distortion(planar(uv0), f, stretched)
    assert np.allclose(mu, 1.0 / 3.0)  # (σ1 − σ2)/(σ1 + σ2) with σ = 1/2, 1 (uv → 3D)
    stretch = conformal_distortion(planar(uv0), f, 3 * uv0, kind="stretch")
    assert np.allclose(stretch, 1.0 / 3.0)  # λ: 3D length per parameter length
    assert np.allclose(conformal_distortion(planar(uv0), f, 3 * uv0, kind="angle"), 0.0)
    with pytest.raises(ValueError, match="unknown distortion"):
        conformal_distortion(planar(uv0), f, uv0, kind="nope")


def test_distortion_histogram_counts_every_angle():
    uv0, f = grid_mesh(6)
    counts, edges = distortion_histogram(planar(uv0), f, uv0 * [1.3, 1.0], bins=20)
    assert counts.sum() == 3 * len(f)
    assert len(edges) == 21
    counts0, _ = distortion_histogram(planar(uv0), f, uv0, bins=21)
    assert counts0[10] == 3 * len(f)  # all differences are 0, the middle bin


def test_flipped_faces_finds_a_fold():
    uv, f = grid_mesh(5)
    folded = uv.copy()
    folded[6] = [0.6, 0.6]  # interior vertex (1, 1) pushed across its neighbours
    flips = flipped_faces(f, folded)
    assert len(flips) > 0
    assert np.all(np.isin(f[flips], 6).any(axis=1))
    assert len(flipped_faces(f, uv)) == 0
    assert len(flipped_faces(f, uv[:, ::-1])) == 0  # globally mirrored is not folded


def _sliver_surface(seed=3):
    """A wavy height field over a grid jittered by 45 % of its spacing: slivers whose
    cotangent weights are negative, where LSCM flips some triangles."""
    uv, faces = grid_mesh(31, extent=(-1.0, 1.0, -1.0, 1.0), jitter=0.45 * 2, seed=seed)
    z = 0.3 * np.sin(3 * uv[:, 0]) * np.cos(3 * uv[:, 1])
    return np.column_stack([uv, z]), faces


def test_mean_value_map_of_a_square_lays_its_border_on_a_circle():
    uv, faces = grid_mesh(11)
    out = mean_value_map(planar(uv), faces)
    border = np.unique(faces[np.isin(faces, np.flatnonzero(
        (uv == 0).any(axis=1) | (uv == 1).any(axis=1)))])
    border = border[((uv[border] == 0) | (uv[border] == 1)).any(axis=1)]
    centre = (out.max(axis=0) + out.min(axis=0)) / 2
    radius = np.linalg.norm(out[border] - centre, axis=1)
    np.testing.assert_allclose(radius, radius[0], rtol=1e-12)  # one circle
    assert len(flipped_faces(faces, out)) == 0
    assert face_areas(out, faces).sum() == pytest.approx(1.0, rel=1e-12)  # area kept


def test_mean_value_map_reproduces_a_flat_mesh_with_a_convex_border_map():
    # on a flat mesh the mean-value weights reproduce linear functions: with the border
    # where it is, the interior comes back exactly (Floater's linear precision)
    uv, faces = grid_mesh(9, jitter=0.3)
    out = mean_value_map(planar(uv), faces)
    assert len(flipped_faces(faces, out)) == 0
    # counter-clockwise like the input
    d1, d2 = out[faces[:, 1]] - out[faces[:, 0]], out[faces[:, 2]] - out[faces[:, 0]]
    assert (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] > 0).all()


def test_mean_value_map_does_not_flip_where_lscm_does():
    vertices, faces = _sliver_surface()
    assert len(flipped_faces(faces, lscm(vertices, faces))) > 0
    assert len(flipped_faces(faces, mean_value_map(vertices, faces))) == 0


def test_untangle_repairs_a_flip_locally():
    # a flat 21x21 grid's map with one interior vertex thrown across two of its neighbours
    uv, faces = grid_mesh(21, jitter=0.2)
    vertices = planar(uv)
    start = lscm(vertices, faces)
    centre = 10 * 21 + 10
    broken = start.copy()
    broken[centre] += 2.5 * (start[centre + 21] - start[centre])
    assert len(flipped_faces(faces, broken)) > 0
    out = untangle(vertices, faces, broken)
    assert out is not None and len(flipped_faces(faces, out)) == 0
    moved = np.flatnonzero(np.abs(out - broken).max(axis=1) > 0)
    assert centre in moved
    # only vertices near the flip move: a few rings, not the map
    assert np.abs(uv[moved] - uv[centre]).max() <= 6.5 / 20
    # a map with nothing flipped comes back as it is
    np.testing.assert_array_equal(untangle(vertices, faces, start), start)


def coiled_strip(turn: float, n: int = 40):
    """A strip bent round by ``turn`` × 2π in the plane: its ends overlap past one turn,
    and no triangle is flipped either way."""
    uv, f = grid_mesh(n, 5)
    theta, r = turn * 2 * np.pi * uv[:, 0], 1.0 + 0.3 * uv[:, 1]
    return np.column_stack([r * np.cos(theta), r * np.sin(theta)]), f


@pytest.mark.parametrize("turn, crossing", [(0.5, False), (0.95, False), (1.2, True),
                                            (1.6, True)])
def test_border_crossings_tell_a_map_that_overlaps_itself(turn, crossing):
    from surfinpaint.geometry.overlap import border_crossings

    uv, f = coiled_strip(turn)
    assert len(flipped_faces(f, uv)) == 0
    found = border_crossings(f, uv, chunk=50)  # small chunks: the rows are split
    assert (len(found) > 0) == crossing
    if crossing:  # each crossing pair is of two edges that share no vertex
        loop = boundary_loops(f)[0]
        n = len(loop)
        assert ((found[:, 1] - found[:, 0]) % n > 1).all()
        assert ((found[:, 0] - found[:, 1]) % n > 1).all()


def test_lscm_with_the_known_boundary_is_the_same_map_and_still_refuses_slivers():
    # a caller that found the patch a disk hands its boundary over: the same map, bit for
    # bit, without the topology checks; degenerate triangles are still refused
    v, f = bumpy_disk(12)
    loop = disk_loop(f)
    assert np.array_equal(loop, disk_boundary(v, f))
    assert np.array_equal(lscm(v, f, boundary=loop), lscm(v, f))
    flat = v.copy()
    flat[f[0, 2]] = 0.5 * (flat[f[0, 0]] + flat[f[0, 1]])  # face 0 collinear
    with pytest.raises(MeshError, match="degenerate"):
        lscm(flat, f, boundary=loop)
