"""The validation benchmark's mesh helpers (``benchmarks/validation_meshes.py``): a simulated
range scan of a sphere lies on the sphere, faces the viewer and is a clean open manifold;
bow-tie vertices are split without moving the surface."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from surfinpaint import data
from surfinpaint.geometry.mesh import boundary_loops, unique_edges

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
validation_meshes = pytest.importorskip("validation_meshes")


def test_scan_of_a_sphere():
    v, f = data.sphere(3)
    view = np.array([0.0, 0.0, 1.0])
    scan = validation_meshes.simulated_scan(v, f, view, pixels=40, noise_h=0.05,
                                            quantum_h=0.05, seed=3)
    pixel = 2.0 / 40
    # the truth lies on the icosphere (within its flat facets) on the side facing the viewer
    r = np.linalg.norm(scan.truth, axis=1)
    assert r.max() <= 1 + 1e-9 and r.min() > 0.98
    assert (scan.truth[:, 2] > 0).all()
    # the noisy copy differs along the view only, by quantization and noise (≤ 5 sigma)
    diff = scan.vertices - scan.truth
    assert np.abs(diff[:, :2]).max() < 1e-12
    assert 0 < np.abs(diff[:, 2]).max() < (0.025 + 5 * 0.05) * pixel
    # one open, edge-manifold piece, one border, no grazing faces near the silhouette
    _, _, count = unique_edges(scan.faces)
    assert count.max() == 2
    assert len(boundary_loops(scan.faces)) == 1
    t = scan.truth[scan.faces]
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    cos = n @ view / np.linalg.norm(n, axis=1)
    assert cos.min() >= 0.25  # every face faces the viewer, none grazing
    # it covers the non-grazing part of the visible disk, |z| >= 0.25: projected area
    # π (1 - 0.25²), less a border ring about a pixel wide
    proj = 0.5 * np.abs(n[:, 2]).sum()
    disk = np.pi * (1 - 0.25**2)
    assert disk - 2 * np.pi * pixel < proj < disk


def test_split_bowties_gives_one_vertex_per_fan():
    from surfinpaint.geometry.validation import nonmanifold_vertices

    # two closed tetrahedra touching at vertex 0 (a bow-tie), then a closed sphere
    tet = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    v = np.vstack([np.zeros(3), np.eye(3), -np.eye(3)])
    f = np.vstack([tet, np.where(tet > 0, tet + 3, 0)[:, ::-1]])
    mesh = validation_meshes.BenchMesh(v, f, truth=v + 1.0)
    out, bowties = validation_meshes.split_bowties(mesh)
    assert bowties.tolist() == [0]
    assert len(out.vertices) == len(v) + 1 and len(nonmanifold_vertices(out.faces)) == 0
    # same triangles in space, same truth, ids of the other vertices kept
    assert np.array_equal(out.vertices[out.faces], v[f])
    assert np.array_equal(out.truth[out.faces], (v + 1.0)[f])
    assert np.array_equal(out.faces[f != 0], f[f != 0])
    sv, sf = data.sphere(2)
    same, none = validation_meshes.split_bowties(validation_meshes.BenchMesh(sv, sf))
    assert len(none) == 0 and same.faces is sf


def _entry(mesh):
    return {"mesh": "sphere", "n_vertices": len(mesh.vertices), "n_faces": len(mesh.faces)}


def test_a_mesh_made_in_a_fresh_process_is_the_same_mesh():
    mesh = validation_meshes.load("sphere")
    fresh = validation_meshes._load_in_fresh_process("sphere")
    assert np.array_equal(fresh.vertices, mesh.vertices)
    assert np.array_equal(fresh.faces, mesh.faces) and fresh.truth is None


@pytest.mark.parametrize(("fresh_matches", "outcome"), [
    (True, "the fresh mesh, with a warning"),
    (False, "RuntimeError naming the mesh"),
])
def test_a_mesh_that_differs_from_its_manifest_entry_is_made_again(monkeypatch,
                                                                  fresh_matches, outcome):
    good = validation_meshes.BenchMesh(np.zeros((4, 3)), np.array([[0, 1, 2], [0, 2, 3]]))
    bad = validation_meshes.BenchMesh(np.zeros((5, 3)), good.faces)
    made = []
    monkeypatch.setattr(validation_meshes, "load", lambda mesh_id: bad)
    monkeypatch.setattr(validation_meshes, "_load_in_fresh_process",
                        lambda mesh_id: made.append(mesh_id) or (good if fresh_matches else bad))
    if fresh_matches:
        with pytest.warns(UserWarning, match="sphere has 5 vertices .* made again"):
            assert validation_meshes.load_entry(_entry(good)) is good
        assert made == ["sphere"]
    else:
        with pytest.warns(UserWarning), pytest.raises(RuntimeError,
                                                      match="sphere .* source changed"):
            validation_meshes.load_entry(_entry(good))
        assert made == ["sphere", "sphere"]
