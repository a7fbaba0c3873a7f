"""The λ-H representation of meshes: analytic λ and H, round trips, storage, plotting."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_parameterization import grid_mesh

from surfinpaint.analytic import stereographic_sphere
from surfinpaint.data import bumpy_disk, sphere
from surfinpaint.errors import MeshError
from surfinpaint.metrics import surface_distance
from surfinpaint.representation import (
    FoldedMapWarning,
    LambdaH,
    disk_from_mesh,
    plot_representation,
    rebuild,
    represent,
)


def stereographic_patch(n: int, radius: float = 2.0):
    """A sphere patch of radius R sampled on the stereographic square [-½, ½]²; faces CCW in
    (u, v), so n = φu × φv points to the centre and H = +1/R."""
    uv0, f = grid_mesh(n, extent=(-0.5, 0.5, -0.5, 0.5))
    phi, _, _ = stereographic_sphere(uv0[:, 0], uv0[:, 1])
    return uv0, radius * phi, f


def relative_distance(v2, f2, v, f):
    d = surface_distance(v2, f2, v, f, n_samples=10000)
    diag = float(np.linalg.norm(np.ptp(v, axis=0)))
    return d["mean"] / diag, d["hausdorff"] / diag


# ------------------------------------------------------------------------ analytic λ and H


@pytest.mark.parametrize("map_name", ["lscm", "rectangular"])
def test_planar_disk_has_zero_curvature(map_name):
    v, f = bumpy_disk(10)
    v[:, 2] = 0.0
    rep = represent(v, f, 64, map=map_name)
    finite = np.isfinite(rep.H)
    assert finite[rep.unknown].all()
    assert np.abs(rep.H[finite]).max() < 1e-9
    if map_name == "lscm":  # an exact similarity, scaled to the surface's area: λ ≡ 1
        lam = rep.lam[np.isfinite(rep.lam)]
        assert np.abs(lam - 1.0).max() < 1e-9


def test_stereographic_patch_lambda_and_H_match_the_analytic_values():
    errors = []
    for n in (21, 41):
        uv0, v, f = stereographic_patch(n)
        # grid nodes on the mesh vertices: the PL surface has no curvature inside triangles
        rep = represent(v, f, n, map="rectangular")
        # the rectangular map of a conformal square with its corners is the identity
        s = np.ptp(rep.uv[:, 0])
        assert np.abs(rep.uv / s - (uv0 + 0.5)).max() < 2e-3
        U, W = rep.grid.nodes()
        u0, w0 = U / s - 0.5, W / s - 0.5
        lam_exact = 2 * 2.0 / (1 + u0**2 + w0**2) / s  # R · 2/(1+|z|²) per parameter unit
        m = rep.unknown
        errors.append(np.abs(rep.lam / lam_exact - 1)[m].max())
        assert np.abs(rep.H[m] - 0.5).max() < 2e-3  # H = +1/R with n = φu × φv inward
    assert errors[0] < 5e-3
    assert errors[0] / errors[1] > 3.5  # O(h²)


def test_spherical_cap_H_sign_follows_the_orientation():
    _, v, f = stereographic_patch(33)
    for faces, sign in ((f, 1.0), (f[:, ::-1], -1.0)):
        rep = represent(v, faces, 97, map="lscm")
        H = rep.H[rep.unknown]
        # finer than the mesh, H is spiky on the edges, but right on average
        assert np.mean(H) == pytest.approx(sign * 0.5, rel=0.02)
        assert np.median(sign * H) > 0


# ------------------------------------------------------------------------ round trips


@pytest.mark.parametrize("map_name", ["lscm", "rectangular"])
def test_round_trip_bumpy_disk_within_targets(map_name):
    v, f = bumpy_disk(20)
    rep = represent(v, f, 80, map=map_name)
    v2, f2 = rebuild(rep)
    assert np.array_equal(f2, f)
    moved = np.linalg.norm(v2 - v, axis=1) > 0
    assert moved.mean() > 0.6  # the test is not passed by leaving the vertices alone
    mean, hausdorff = relative_distance(v2, f2, v, f)
    assert mean < 1e-3 and hausdorff < 1e-2


def test_round_trip_gauss_codazzi():
    v, f = bumpy_disk(16)
    rep = represent(v, f, 48, map="lscm")
    v2, f2 = rebuild(rep, "gauss-codazzi")
    mean, hausdorff = relative_distance(v2, f2, v, f)
    assert mean < 1e-3 and hausdorff < 1e-2


def test_rebuild_keeps_band_vertices_and_uses_given_lambda_h():
    v, f = bumpy_disk(12)
    rep = represent(v, f, 40, map="lscm")
    v2, _ = rebuild(rep)
    v3, _ = rebuild(rep, lam=rep.lam.copy(), H=rep.H.copy())
    assert np.array_equal(v2, v3)
    # with H = 0 inside the surface comes out different (flatter)
    v4, _ = rebuild(rep, H=np.where(rep.unknown, 0.0, rep.H))
    assert np.abs(v4 - v2).max() > 1e-3
    # vertices whose cell touches no rebuilt node are exactly the originals
    from surfinpaint.grid import interpolate

    touch = interpolate(rep.unknown.astype(float), rep.grid, rep.uv, order=1)
    still = ~(np.isfinite(touch) & (touch > 0))
    assert still.any() and np.array_equal(v2[still], v[still])


def face_scan_disk(radius: float = 40.0):
    pytest.importorskip("pymeshlab")
    import scipy.sparse as sp
    from scipy.sparse.csgraph import dijkstra

    from surfinpaint.data import pymeshlab_sample
    from surfinpaint.mesh import connected_components

    v, f = pymeshlab_sample("rangemaps/face000.ply")
    _, label = connected_components(f, len(v))
    f = f[label[f[:, 0]] == np.argmax(np.bincount(label[f[:, 0]]))]
    used = np.unique(f)
    centre = used[np.argmin(np.linalg.norm(v[used] - v[used].mean(0), axis=1))]
    e = np.vstack([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    w = np.linalg.norm(v[e[:, 0]] - v[e[:, 1]], axis=1)
    d = dijkstra(sp.csr_matrix((w, (e[:, 0], e[:, 1])), shape=(len(v), len(v))),
                 directed=False, indices=centre, limit=radius)
    return disk_from_mesh(v, f[(d[f] < radius).all(axis=1)])


def test_round_trip_face_scan_within_targets():
    v, f = face_scan_disk(30.0)
    assert len(v) > 10000
    rep = represent(v, f, 96, map="lscm")
    v2, f2 = rebuild(rep)
    mean, hausdorff = relative_distance(v2, f2, v, f)
    assert mean < 1e-3 and hausdorff < 1e-2


def pial_disk():
    pytest.importorskip("nilearn")
    from surfinpaint.cutting import cut_geodesic_disk
    from surfinpaint.data import fsaverage5

    v, f = fsaverage5("pial", "left")
    cut = cut_geodesic_disk(v, f, 5000, 25.0)
    return cut.truth_vertices, cut.truth_faces


@pytest.mark.xfail(strict=True, reason="measured mean 0.13 % of the diagonal at 64 (target "
                   "0.1 %), 0.23 % at 256: the sampled Δφ of this coarse LSCM-mapped disk has "
                   "a tangential part of 22-24 % of |Δφ| at every resolution, which (λ, H) do "
                   "not carry; placing the vertices on the sampled grid itself (no rebuild) "
                   "gives 0.043 / 0.012 % at 64 / 256, so the loss is the representation's")
def test_round_trip_pial_disk_within_targets():
    v, f = pial_disk()
    rep = represent(v, f, 64, map="lscm")
    v2, f2 = rebuild(rep)
    mean, hausdorff = relative_distance(v2, f2, v, f)
    assert mean < 1e-3 and hausdorff < 1e-2


def test_pial_disk_round_trip_hausdorff_and_folding():
    v, f = pial_disk()
    rep = represent(v, f, 64, map="lscm")
    v2, f2 = rebuild(rep)
    _, hausdorff = relative_distance(v2, f2, v, f)
    assert hausdorff < 1e-2
    # the rectangular map folds a few triangles of this coarse, irregular disk
    with pytest.warns(FoldedMapWarning, match="folds"):
        represent(v, f, 32, map="rectangular")
    with pytest.raises(MeshError, match="folds"):
        represent(v, f, 32, map="rectangular", strict=True)


# ------------------------------------------------------------------------ input and output


def test_represent_rejects_non_disks_and_bad_parameters():
    with pytest.raises(MeshError, match="closed"):
        represent(*sphere(2), 32)
    v, f = bumpy_disk(4)
    with pytest.raises(ValueError, match="unknown conformal map"):
        represent(v, f, 32, map="sphere")
    with pytest.raises(ValueError, match="band"):
        represent(v, f, 32, band=0)


def test_disk_from_mesh_closes_inner_holes_and_drops_islands():
    uv, f = grid_mesh(13, extent=(-1, 1, -1, 1))
    v = np.column_stack([uv, 0.1 * uv[:, 0] ** 2])
    hole = (np.abs(uv[f]).max(axis=2) < 0.3).all(axis=1)
    island = np.array([[0, 0, 5.0], [1, 0, 5.0], [0, 1, 5.0]])
    v_all = np.vstack([v, island])
    f_all = np.vstack([f[~hole], len(v) + np.array([[0, 1, 2]])])
    v2, f2 = disk_from_mesh(v_all, f_all)
    assert len(f2) >= len(f[~hole]) + hole.sum() // 2
    assert v2[:, 2].max() < 1.0  # the island is gone
    with pytest.raises(MeshError, match="closed"):
        disk_from_mesh(*sphere(1))


def test_save_and_load_round_trip(tmp_path):
    v, f = bumpy_disk(6)
    rep = represent(v, f, 24, map="rectangular")
    path = tmp_path / "rep.npz"
    rep.save(path)
    assert [p.name for p in tmp_path.iterdir()] == ["rep.npz"]  # no temporary file left
    back = LambdaH.load(path)
    assert back.grid == rep.grid and back.map == rep.map and back.band == rep.band
    for name in ("domain", "lam", "H", "phi", "known", "uv", "vertices", "faces", "corners"):
        assert np.array_equal(getattr(back, name), getattr(rep, name), equal_nan=True), name
    assert np.array_equal(rebuild(back)[0], rebuild(rep)[0])
    np.savez(tmp_path / "other.npz", x=np.zeros(3))
    with pytest.raises(ValueError, match="not a λ-H representation"):
        LambdaH.load(tmp_path / "other.npz")


def test_plot_representation_writes_png(tmp_path):
    rep = represent(*bumpy_disk(6), 24)
    path = tmp_path / "rep.png"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # headless: no backend warnings
        plot_representation(rep, path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_boundary_band_width_and_inputs_unchanged():
    from surfinpaint.representation import boundary_band

    domain = np.zeros((20, 20), dtype=bool)
    domain[2:18, 3:17] = True
    band = boundary_band(domain, 4)
    assert not band[~domain].any()
    assert np.array_equal(domain & ~band, np.pad(np.ones((8, 6), bool), ((6, 6), (7, 7))))
    v, f = bumpy_disk(6)
    v0, f0 = v.copy(), f.copy()
    rep = represent(v, f, 24)
    rebuild(rep)
    assert np.array_equal(v, v0) and np.array_equal(f, f0)
