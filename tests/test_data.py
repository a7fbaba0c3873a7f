"""Synthetic meshes are clean closed (or one-boundary) surfaces; real-data loaders work or skip."""

from __future__ import annotations

import importlib
import warnings

import numpy as np
import pytest

from surfinpaint import data
from surfinpaint.geometry.mesh import (
    boundary_loops,
    connected_components,
    edge_lengths,
    face_areas,
    face_normals,
    unique_edges,
)


def signed_volume(v, f):
    t = v[f]
    return np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6.0


def check_surface(v, f, euler, n_boundary_loops=0):
    assert v.dtype == np.float64 and f.dtype == np.int64
    assert v.shape[1] == 3 and f.shape[1] == 3
    assert np.unique(f).size == len(v), "unreferenced vertices"
    assert (f[:, 0] != f[:, 1]).all() and (f[:, 1] != f[:, 2]).all() and (f[:, 0] != f[:, 2]).all()
    edges, _, count = unique_edges(f)
    assert count.max() <= 2, "non-manifold edge"
    # consistent orientation: every directed edge appears in at most one face
    half = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    assert len(np.unique(half, axis=0)) == len(half)
    assert len(v) - len(edges) + len(f) == euler
    assert len(boundary_loops(f)) == n_boundary_loops
    assert connected_components(f, len(v))[0] == 1
    # reasonably regular triangles: no slivers
    lengths = edge_lengths(v, f)
    quality = 4 * np.sqrt(3) * face_areas(v, f) / (lengths**2).sum(axis=1)
    assert quality.min() > 0.5


SMALL = {
    "sphere": (lambda: data.sphere(2), 2),
    "torus": (lambda: data.torus(n_major=24, n_minor=10), 0),
    "cube": (lambda: data.cube(4), 2),
    "snowman": (lambda: data.snowman(edge_length=0.15), 2),
    "tooth": (lambda: data.tooth(edge_length=0.12), 2),
    "lens": (lambda: data.lens(edge_length=0.15), 2),
}


@pytest.mark.parametrize("name", sorted(SMALL))
def test_closed_meshes_are_clean_and_outward(name):
    make, euler = SMALL[name]
    v, f = make()
    check_surface(v, f, euler)
    assert signed_volume(v, f) > 0
    v2, f2 = make()
    np.testing.assert_array_equal(v, v2)  # deterministic
    np.testing.assert_array_equal(f, f2)


def test_bumpy_disk_has_one_boundary_loop_and_upward_normals():
    v, f = data.bumpy_disk(8)
    check_surface(v, f, euler=1, n_boundary_loops=1)
    loop = boundary_loops(f)[0]
    np.testing.assert_allclose(np.hypot(v[loop, 0], v[loop, 1]), 1.0, atol=1e-12)
    assert (face_normals(v, f)[:, 2] > 0).all()
    assert np.ptp(v[:, 2]) > 0.1  # actually bumpy


def test_sphere_counts_and_radius():
    for s in range(4):
        v, f = data.sphere(s, radius=2.5)
        assert len(v) == 10 * 4**s + 2 and len(f) == 20 * 4**s
        np.testing.assert_allclose(np.linalg.norm(v, axis=1), 2.5, rtol=1e-12)
    # inscribed polyhedron: volume converges to 4/3 π r³ from below
    v, f = data.sphere(4)
    vol = signed_volume(v, f)
    assert 0.99 * 4 / 3 * np.pi < vol < 4 / 3 * np.pi


def test_torus_lies_on_torus_and_has_its_volume():
    v, f = data.torus(R=1.5, r=0.5, n_major=64, n_minor=32)
    np.testing.assert_allclose((np.hypot(v[:, 0], v[:, 1]) - 1.5) ** 2 + v[:, 2] ** 2, 0.25,
                               rtol=1e-12)
    exact = 2 * np.pi**2 * 1.5 * 0.5**2
    assert abs(signed_volume(v, f) / exact - 1) < 0.01


def test_cube_is_the_unit_cube_with_sharp_edges():
    n = 5
    v, f = data.cube(n)
    assert len(v) == 6 * n * n + 2 and len(f) == 12 * n * n
    assert signed_volume(v, f) == pytest.approx(1.0, abs=1e-12)
    on_face = (np.isclose(v, 0) | np.isclose(v, 1)).any(axis=1)
    assert on_face.all()
    normals = face_normals(v, f)
    # every face normal is an outward axis direction: no bevel at the edges
    assert np.allclose(np.abs(normals).max(axis=1), 1.0)
    centre_dir = v[f].mean(axis=1) - 0.5
    assert (np.einsum("ij,ij->i", normals, centre_dir) > 0).all()


def max_dihedral_degrees(v, f):
    """Largest angle between the normals of two faces sharing an edge."""
    _, face_edge, _ = unique_edges(f)
    order = np.argsort(face_edge.ravel(), kind="stable")
    owner = np.repeat(np.arange(len(f)), 3)[order]  # closed mesh: two faces per edge
    n = face_normals(v, f)
    cos = (n[owner[0::2]] * n[owner[1::2]]).sum(axis=1)
    return np.degrees(np.arccos(np.clip(cos, -1, 1))).max()


def test_snowman_is_smooth_with_three_stacked_balls():
    v, f = data.snowman(edge_length=0.08)
    assert v[:, 2].min() == pytest.approx(-1.0, abs=0.01)
    assert v[:, 2].max() == pytest.approx(3.1, abs=0.01)
    r = np.hypot(v[:, 0], v[:, 1])
    # two necks: narrower than the balls on either side
    for lo, neck, hi in ((0.0, 0.94, 1.45), (1.45, 2.18, 2.6)):
        near = lambda z0: r[np.abs(v[:, 2] - z0) < 0.05].max()  # noqa: E731
        assert near(neck) < min(near(lo), near(hi)) - 0.05
    # smooth, no crease at the necks: the largest dihedral angle halves with the edge length
    coarse = max_dihedral_degrees(v, f)
    fine = max_dihedral_degrees(*data.snowman(edge_length=0.04))
    assert coarse < 30
    assert fine < 0.6 * coarse


def test_tooth_has_four_cusps_above_a_central_fossa():
    v, f = data.tooth(edge_length=0.05)
    ang = np.arctan2(v[:, 1], v[:, 0])
    r = np.hypot(v[:, 0], v[:, 1])
    top = v[:, 2] > 0.6
    ring = top & (np.abs(r - 0.42) < 0.05)
    # the crown's top height around the cusp ring: 4 maxima at 45° + k·90°
    bins = np.linspace(-np.pi, np.pi, 37)
    which = np.digitize(ang[ring], bins) - 1
    height = np.array([v[ring][which == b, 2].max() for b in range(36)])
    peaks = np.flatnonzero((height > np.roll(height, 1)) & (height > np.roll(height, -1)))
    assert len(peaks) == 4
    centre = top & (r < 0.08)
    assert v[centre, 2].max() < height.max() - 0.05
    # a root narrower than the crown
    assert r[v[:, 2] < -0.5].max() < 0.5 * r.max()


def test_demo_mesh_is_packaged_small_and_reproducible(tmp_path):
    path = data.DATA_DIR / data.DEMO_FILE
    assert path.is_file()
    assert data.default_demo_path() == path
    assert path.stat().st_size < 300_000
    v, f = data.default_demo_mesh()
    assert len(boundary_loops(f)) == 2
    check_surface(v, f, euler=0, n_boundary_loops=2)
    # regenerating gives the same mesh (the file stores float32 positions)
    (new,) = data.regenerate_default_data(tmp_path)
    from surfinpaint.io.formats import read_mesh

    nv, nf = read_mesh(new)
    np.testing.assert_array_equal(nf, f)
    np.testing.assert_allclose(nv, v, atol=1e-6)


# --------------------------------------------------------------------------- real data


def test_pymeshlab_bunny_loads():
    pytest.importorskip("pymeshlab")
    v, f = data.pymeshlab_sample("bunny.obj")
    assert v.shape == (28088, 3) and f.shape == (56172, 3)
    assert unique_edges(f)[2].max() == 2 and (unique_edges(f)[2] == 2).all()
    with pytest.raises(FileNotFoundError, match="bunny.obj"):
        data.pymeshlab_sample("no_such_mesh.obj")


def test_a_sample_scan_loads_without_warnings():
    # face000.ply holds a camera element and per-vertex quality and flags: nothing a caller
    # of the loader can act on, so nothing is said
    pytest.importorskip("pymeshlab")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        v, f = data.pymeshlab_sample("rangemaps/face000.ply")
    assert v.shape[1] == 3 and len(f) > 1000


def test_fsaverage5_loads():
    pytest.importorskip("nilearn")
    for surface in ("pial", "white"):
        v, f = data.fsaverage5(surface, "left")
        assert v.shape == (10242, 3) and f.shape == (20480, 3)
        assert len(boundary_loops(f)) == 0
    with pytest.raises(ValueError, match="hemi"):
        data.fsaverage5("pial", "middle")


def test_pymeshfix_bunny_has_holes():
    pytest.importorskip("pymeshfix")
    v, f = data.pymeshfix_bunny()
    assert len(v) == 50000
    assert (unique_edges(f)[2] == 1).sum() > 0


def test_missing_package_names_what_to_install(monkeypatch):
    real = importlib.import_module

    def fake(name, *args, **kwargs):
        if name == "nilearn":
            raise ModuleNotFoundError("No module named 'nilearn'")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(importlib, "import_module", fake)
    with pytest.raises(ModuleNotFoundError, match="pip install nilearn"):
        data.fsaverage5()


def test_lens_is_two_spherical_caps_with_a_sharp_rim():
    radius = 1.5
    v, f = data.lens(0.08, radius=radius)
    centre = np.sqrt(radius**2 - 1)
    top, bottom = v[:, 2] > 1e-12, v[:, 2] < -1e-12
    # on the spheres up to the profile's sampling (4000 points per cap: 6e-9)
    np.testing.assert_allclose(np.linalg.norm(v[top] + [0, 0, centre], axis=1), radius,
                               rtol=1e-8)
    np.testing.assert_allclose(np.linalg.norm(v[bottom] - [0, 0, centre], axis=1), radius,
                               rtol=1e-8)
    rim = ~top & ~bottom
    np.testing.assert_allclose(np.hypot(v[rim, 0], v[rim, 1]), 1.0, rtol=1e-12)
    from surfinpaint.fill.creases import sharp_edges

    edges, turn = sharp_edges(v, f)
    assert rim[edges].all() and len(edges) == rim.sum()  # the rim is the one crease
    rim_turn = 180 - np.degrees(2 * np.arcsin(1 / radius))  # 96.4°
    assert (turn > rim_turn).all() and (turn < rim_turn + 5).all()  # + the triangles' own
    with pytest.raises(ValueError, match="radius"):
        data.lens(radius=1.0)
