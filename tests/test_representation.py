"""The λ-H representation on the mesh's own triangles: exact round trips, the Newton rebuild
and its failures, the stored self-check, the grid export, the layering."""

from __future__ import annotations

import ast
import warnings
from pathlib import Path

import numpy as np
import pytest
from test_parameterization import grid_mesh

import surfinpaint
from surfinpaint.data import bumpy_disk
from surfinpaint.geometry.mesh import boundary_loops
from surfinpaint.geometry.metrics import surface_distance
from surfinpaint.geometry.parameterization import lscm
from surfinpaint.representation.analytic import enneper, stereographic_sphere
from surfinpaint.representation.exports import export_resolution, grid_export
from surfinpaint.representation.grid_represent import LambdaH
from surfinpaint.representation.mesh_lambda_h import (
    mesh_lambda_h,
    normals_with_jacobian,
    rebuild_on_mesh,
)
from surfinpaint.representation.reconstruction import NotConvergedWarning
from surfinpaint.representation.represent import (
    MeshLambdaH,
    load_representation,
    rebuild,
    represent,
)


def sphere_patch(n: int, radius: float = 2.0):
    """A sphere patch of radius R over the stereographic square [-½, ½]², CCW in (u, v)."""
    uv, f = grid_mesh(n, extent=(-0.5, 0.5, -0.5, 0.5))
    phi, _, _ = stereographic_sphere(uv[:, 0], uv[:, 1])
    return radius * phi, f


def enneper_patch(n: int, jitter: float = 0.0):
    """Enneper's minimal surface (H = 0) over [-0.8, 0.8]², optionally jittered."""
    uv, f = grid_mesh(n, extent=(-0.8, 0.8, -0.8, 0.8), jitter=jitter, seed=3)
    phi, _, _ = enneper(uv[:, 0], uv[:, 1])
    return phi, f


def finger(height: float = 1.0, width: float = 0.3, rings: int = 16):
    """A disk with a tall Gaussian bump: λ varies 25× over it (measured), and its triangles
    are stretched to slivers on the flanks."""
    v, f = bumpy_disk(rings)
    v[:, 2] = height * np.exp(-(v[:, 0] ** 2 + v[:, 1] ** 2) / width**2)
    return v, f


def pushed_over(v, f, part: int = 2):
    """The LSCM map of a disk with one interior vertex (the ``1/part``-th) pushed across its
    neighbours, so that the map folds there (as LSCM flips a sliver of the quadruped's leg
    cap); and that vertex's neighbours."""
    uv = lscm(v, f)
    interior = np.setdiff1d(np.arange(len(v)), np.concatenate(boundary_loops(f)))
    moved = int(interior[len(interior) // part])
    neighbours = np.unique(f[np.any(f == moved, axis=1)])
    folded = uv.copy()
    folded[moved] += 2.5 * (uv[neighbours].mean(axis=0) - uv[moved] + 0.3 * np.ptp(
        uv[neighbours], axis=0))
    return folded, neighbours


def diagonal(v):
    return float(np.linalg.norm(np.ptp(v, axis=0)))


# ------------------------------------------------------------------------ λ, H on the mesh


def test_mesh_lambda_h_matches_the_sphere_and_converges():
    errors = []
    for n in (17, 33):
        v, f = sphere_patch(n)
        uv = lscm(v, f)
        lam, H, defect = mesh_lambda_h(v, f, uv)
        inner = np.isfinite(H)
        assert (~inner).sum() == len(boundary_loops(f)[0])  # NaN exactly on the border
        errors.append(np.abs(H[inner] - 0.5).max())  # H = 1/R, n = φu × φv inward
        # the defect is the tangential part of Δφ: small against 2λ²H on a regular mesh
        assert np.median(np.linalg.norm(defect[inner], axis=1)
                         / (2 * lam[inner] ** 2 * np.abs(H[inner]))) < 0.05
    assert errors[1] < 0.01
    assert errors[0] / errors[1] > 3  # O(h²)


def test_normal_jacobian_matches_finite_differences():
    v, f = finger(rings=6)
    rng = np.random.default_rng(1)
    dv = rng.normal(size=v.shape)
    n0, D = normals_with_jacobian(v, f)
    eps = 1e-6
    n_plus, _ = normals_with_jacobian(v + eps * dv, f)
    n_minus, _ = normals_with_jacobian(v - eps * dv, f)
    fd = (n_plus - n_minus).ravel() / (2 * eps)
    assert np.linalg.norm(D @ dv.ravel() - fd) < 1e-6 * np.linalg.norm(fd)


# ------------------------------------------------------------------------- exact round trips


@pytest.mark.parametrize("surface", ["sphere", "enneper", "enneper-jittered", "bumpy",
                                     "finger"])
def test_mesh_round_trip_is_exact(surface):
    v, f = {"sphere": lambda: sphere_patch(21),
            "enneper": lambda: enneper_patch(21),
            "enneper-jittered": lambda: enneper_patch(21, jitter=0.3),
            "bumpy": lambda: bumpy_disk(12),
            "finger": finger}[surface]()
    rep = represent(v, f)
    assert isinstance(rep, MeshLambdaH) and rep.discretization == "mesh"
    assert rep.check.converged
    # exact to the solver's tolerance, not to the discretization's O(h²)
    assert rep.check.vertex_max < 1e-9 * diagonal(v)
    out = rebuild(rep)
    assert out.converged and np.array_equal(out.faces, f)
    border = rep.known
    assert np.array_equal(out.vertices[border], v[border])  # the border is fixed
    assert np.abs(out.vertices - v).max() < 1e-9 * diagonal(v)


def test_a_map_that_folds_is_untangled_and_the_round_trip_stays_exact(monkeypatch):
    # the quadruped's leg cap (benchmarks/represent_speed.py "legcap") has one sliver that
    # LSCM flips; here one interior vertex of the map is pushed across its neighbours
    import surfinpaint.representation.mapping as mapping
    from surfinpaint.geometry.parameterization import flipped_faces

    v, f = bumpy_disk(12)
    folded, neighbours = pushed_over(v, f)
    assert len(flipped_faces(f, folded)) > 0
    monkeypatch.setattr(mapping, "lscm", lambda *_: folded.copy())
    with pytest.warns(mapping.FoldedMapWarning, match="untangled locally"):
        rep = represent(v, f)
    assert len(flipped_faces(f, rep.uv)) == 0
    far = np.ones(len(v), dtype=bool)
    far[np.unique(f[np.isin(f, neighbours).any(axis=1)])] = False
    assert np.array_equal(rep.uv[far][:10], folded[far][:10])  # the map is kept away from it
    assert rep.check.converged and rep.check.vertex_max < 1e-9 * diagonal(v)
    with pytest.raises(surfinpaint.MeshError, match="folds"):
        represent(v, f, strict=True)


def test_the_defect_is_what_makes_the_round_trip_exact():
    v, f = finger()
    rep = represent(v, f, check=False)
    plain = rebuild(rep, defect=np.zeros_like(rep.defect))  # the paper's Δφ = 2λ²H n
    exact = rebuild(rep)
    assert plain.converged and exact.converged
    err_plain = np.abs(plain.vertices - v).max() / diagonal(v)
    err_exact = np.abs(exact.vertices - v).max() / diagonal(v)
    assert err_exact < 1e-9 < 1e-4 < err_plain


def test_rebuild_uses_given_lambda_h():
    v, f = bumpy_disk(10)
    rep = represent(v, f, check=False)
    flat = rebuild(rep, H=np.where(rep.known, np.nan, 0.0), defect=np.zeros_like(rep.defect))
    assert flat.converged
    # H = 0 and no defect: the harmonic surface with the same border
    from surfinpaint.geometry.mesh import cotangent_laplacian

    L = cotangent_laplacian(rep.uv, f)
    inner = ~rep.known
    assert np.abs((L @ flat.vertices)[inner]).max() < 1e-9
    with pytest.raises(ValueError, match="not finite"):
        rebuild(rep, H=np.full(len(v), np.nan))


# ------------------------------------------------------------------- convergence is reported


def test_non_convergence_is_reported_not_silent():
    v, f = finger(height=1.0)
    rep = represent(v, f, check=False)
    with pytest.warns(NotConvergedWarning, match="did not converge"):
        out = rebuild(rep, max_iter=2)
    assert not out.converged and out.iterations == 2
    assert "did not converge" in out.message
    solve = rebuild_on_mesh(v, f, rep.uv, rep.lam, rep.H, rep.defect, rep.known, max_iter=2)
    assert not solve.converged and solve.residual > 1e-6


def test_grid_rebuild_non_convergence_is_reported():
    v, f = bumpy_disk(10)
    rep = represent(v, f, discretization="grid", resolution=40, check=False)
    with pytest.warns(NotConvergedWarning):
        out = rebuild(rep, max_iter=2)
    assert not out.converged and out.iterations == 2
    assert rebuild(rep).converged


# ------------------------------------------------------------------------------- self-check


def test_self_check_numbers_are_stored_and_correct(tmp_path):
    v, f = bumpy_disk(10)
    rep = represent(v, f)
    check = rep.check
    out = rebuild(rep)
    d = surface_distance(out.vertices, f, v, f, n_samples=20000)
    assert check.mean == pytest.approx(d.mean, rel=1e-6, abs=1e-15)
    assert check.hausdorff == pytest.approx(d.hausdorff, rel=1e-6, abs=1e-15)
    assert check.diagonal == pytest.approx(diagonal(v))
    assert check.mean_percent == pytest.approx(100 * check.mean / check.diagonal)
    path = tmp_path / "rep.npz"
    rep.save(path)
    back = load_representation(path)
    assert isinstance(back, MeshLambdaH) and back.check == check
    assert np.array_equal(rebuild(back).vertices, out.vertices)
    # a representation that does not give its mesh back says so in its check
    broken = MeshLambdaH(**{**rep.__dict__, "H": np.where(rep.known, np.nan, rep.H * 1.5),
                            "check": None})
    from surfinpaint.representation.represent import check_representation

    bad = check_representation(broken)
    assert bad.mean_percent > 100 * check.mean_percent + 1e-3


def test_grid_export_follows_lambda_and_reports_its_error(tmp_path):
    v, f = finger(rings=10)
    rep = represent(v, f, check=False)
    n = export_resolution(rep)
    assert 64 <= n <= 1024
    grid = grid_export(rep, 48)
    assert isinstance(grid, LambdaH) and max(grid.grid.shape) == 48
    assert grid.check is not None and grid.check.mean > 0
    grid.save(tmp_path / "grid.npz")
    back = load_representation(tmp_path / "grid.npz")
    assert isinstance(back, LambdaH) and back.check == grid.check
    # a wider λ range asks for a finer grid
    assert export_resolution(represent(*finger(height=1.0, rings=10), check=False)) >= \
        export_resolution(represent(*finger(height=0.2, rings=10), check=False))


def test_represent_rejects_bad_parameters():
    v, f = bumpy_disk(4)
    with pytest.raises(ValueError, match="discretization"):
        represent(v, f, discretization="voxels")
    with pytest.raises(ValueError, match="grid"):
        represent(v, f, resolution=32)
    with pytest.raises(ValueError, match="conformal map"):
        represent(v, f, map="sphere")


def test_plot_representation_of_a_mesh_writes_png(tmp_path):
    from surfinpaint.app.lambda_h_figures import plot_representation

    rep = represent(*bumpy_disk(6), check=False)
    path = tmp_path / "rep.png"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plot_representation(rep, path)
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("lam, logged", [
    ([1.0, 2.0, 50.0], False),
    ([1.0, 2.0, 101.0], True),
    ([0.01, 1.0, np.nan], False),
    ([0.001, 1.0, np.nan], True),
    ([np.nan, np.nan], False),
])
def test_lambda_is_drawn_on_a_log_scale_where_it_varies_more_than_100_fold(lam, logged):
    from surfinpaint.app.lambda_h_figures import lambda_panel

    values, title = lambda_panel(np.array(lam))
    assert ("log" in title) == logged
    expected = np.log10(lam) if logged else np.array(lam)
    np.testing.assert_array_equal(values, expected)


# --------------------------------------------------------------------------------- layering


def _imports(folder: Path) -> set[str]:
    names = set()
    for path in folder.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module:
                names.add(node.module)
            elif isinstance(node, ast.Import):
                names.update(alias.name for alias in node.names)
    return names


def test_representation_imports_nothing_from_fill_or_app():
    root = Path(surfinpaint.__file__).parent
    for layer, banned in (("representation", ("surfinpaint.fill", "surfinpaint.app")),
                          ("geometry", ("surfinpaint.fill", "surfinpaint.app",
                                        "surfinpaint.representation", "matplotlib"))):
        found = {m for m in _imports(root / layer) if m.startswith(banned)}
        assert not found, f"{layer}/ imports {sorted(found)}"


def test_lscm_real_form_for_large_meshes_matches_the_complex_solve(monkeypatch):
    import surfinpaint.geometry.parameterization as parameterization

    v, f = bumpy_disk(12)
    complex_uv = lscm(v, f)
    monkeypatch.setattr(parameterization, "_REAL_FORM_ABOVE", 0)
    real_uv = parameterization.lscm(v, f)
    assert np.abs(real_uv - complex_uv).max() < 1e-9 * np.ptp(complex_uv)


def _spy_on_ordered_factorizations(monkeypatch):
    """With every Jacobian 'large', the orders of the ordered factorizations made, and how
    many Jacobians were factored in all."""
    import surfinpaint.representation.mesh_lambda_h as mesh_lambda_h

    orders, factored = [], []
    ordered, factorized = mesh_lambda_h.factorized_ordered, mesh_lambda_h.RebuildSystem.factorized
    monkeypatch.setattr(mesh_lambda_h, "ORDERED_ABOVE", 0)
    monkeypatch.setattr(mesh_lambda_h, "factorized_ordered",
                        lambda J, order: orders.append(order) or ordered(J, order))
    monkeypatch.setattr(mesh_lambda_h.RebuildSystem, "factorized",
                        lambda self, J: factored.append(J.shape) or factorized(self, J))
    return orders, factored


def test_large_rebuild_jacobians_in_nested_dissection_order_give_the_same_surface(monkeypatch):
    v, f = finger()
    rep = represent(v, f, check=False)
    plain = rebuild(rep)
    orders, factored = _spy_on_ordered_factorizations(monkeypatch)
    out = rebuild(rep)
    assert len(orders) == len(factored) > 0
    # an order of the unknowns that keeps each vertex's three coordinates together
    for order in orders:
        assert np.array_equal(np.sort(order), np.arange(len(order)))
        triples = order.reshape(-1, 3)
        assert (triples % 3 == np.arange(3)).all() and (np.ptp(triples // 3, axis=1) == 0).all()
    assert out.converged and out.iterations == plain.iterations
    assert np.abs(out.vertices - plain.vertices).max() < 1e-12 * diagonal(v)


def test_the_grid_export_factors_its_levels_in_minimum_degree_order(monkeypatch):
    # on the grid's right triangles nested dissection made more fill than minimum degree
    # (docs/representation.md, session 14: the whole 256² export 317 s against 23 s)
    v, f = finger(rings=10)
    rep = represent(v, f, check=False)
    orders, factored = _spy_on_ordered_factorizations(monkeypatch)
    grid = grid_export(rep, 48)
    assert grid.check.converged
    assert len(factored) > 0 and orders == []


def test_represent_and_the_grid_export_say_each_stage_as_it_starts():
    from surfinpaint.representation.exports import grid_export

    said = []
    rep = represent(*bumpy_disk(6), progress=said.append)
    assert said == [f"mapping {len(rep.vertices)} vertices and computing λ, H",
                    f"self-check: rebuilding the {len(rep.vertices)} vertices from λ and H"]
    said.clear()
    grid = grid_export(rep, 24, progress=said.append)
    shape = "×".join(str(n) for n in grid.grid.shape)
    assert said == ["sampling the surface on a grid of 24 nodes along its long side",
                    f"self-check: rebuilding the {shape} grid from its λ and H"]
    said.clear()
    represent(*bumpy_disk(6), check=False, progress=said.append)
    assert len(said) == 1  # no self-check, no second stage


def test_the_stages_show_one_line_each_on_a_terminal_and_nothing_elsewhere():
    import io

    from rich.console import Console

    from surfinpaint.app.progress import stages

    for terminal in (True, False):
        out = io.StringIO()
        with stages(Console(file=out, force_terminal=terminal, width=80)) as stage:
            stage("mapping 10 vertices")
            stage("self-check: rebuilding")
        text = out.getvalue()
        if terminal:
            assert "mapping 10 vertices" in text and "self-check: rebuilding" in text
        else:
            assert text == ""
