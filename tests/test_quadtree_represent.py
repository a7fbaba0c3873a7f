"""The λ-H representation on quadtrees: trees refined where the map squeezes the surface,
their round trip down to the sampling floor, files, edits, failures reported, the CLI."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from test_representation import finger, pushed_over

import surfinpaint
from surfinpaint.app.cli import main
from surfinpaint.data import bumpy_disk
from surfinpaint.geometry.metrics import surface_distance
from surfinpaint.io.formats import read_mesh, write_mesh
from surfinpaint.representation.exports import quadtree_export
from surfinpaint.representation.quadtree_represent import (
    QuadtreeLambdaH,
    level_solves,
    represent_quadtree,
    sampled_tree_vertices,
)
from surfinpaint.representation.reconstruction import NotConvergedWarning
from surfinpaint.representation.represent import (
    CoarseGridWarning,
    load_representation,
    rebuild,
    represent,
)


def diagonal(v: np.ndarray) -> float:
    return float(np.linalg.norm(np.ptp(v, axis=0)))


def tree_edges_on_the_surface(level) -> np.ndarray:
    """Every triangle side of a tree, measured between its sampled nodes in space."""
    p = level.phi[level.faces]
    return np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2).ravel()


@pytest.fixture(scope="module")
def tall_finger():
    """λ varies ~60× over it: a uniform grid or tree resolving its tip is ~60² too dense
    elsewhere."""
    return finger(height=1.5, rings=12)


# ---------------------------------------------------------------------------- the trees


@pytest.mark.parametrize("target", [0.2, 0.1, 0.05])
def test_every_tree_triangle_is_at_most_its_target_long_on_the_surface(tall_finger, target):
    v, f = tall_finger
    rep = represent_quadtree(v, f, targets=(target,))
    sides = tree_edges_on_the_surface(rep.finest)
    # the refinement test: a cell's side in the plane × σ ≤ target × diagonal, so its
    # triangles' sides (half a diagonal to a side of the cell) are no longer in space
    assert sides.max() <= target * diagonal(v)
    # and the tree is adaptive: a uniform tree this fine everywhere would have far more nodes
    finest_cell = sides.min() * np.sqrt(2)  # the shortest side: half a cell's diagonal
    uniform_nodes = (np.ptp(rep.finest.uv, axis=0) / (
        finest_cell / _sigma_range(rep.finest))).prod()
    assert len(rep.finest.uv) < uniform_nodes / 4


def _sigma_range(level) -> float:
    """The largest stretch σ (space / plane) of a tree's triangle sides."""
    p, q = level.phi[level.faces], level.uv[level.faces]
    space = np.linalg.norm(p - np.roll(p, 1, axis=1), axis=2)
    plane = np.linalg.norm(q - np.roll(q, 1, axis=1), axis=2)
    return float((space / plane).max())


def test_a_uniform_tree_would_break_the_side_bound_at_the_fingertip(tall_finger):
    """The bound above fails without refinement where the map squeezes: the check has
    teeth."""
    v, f = tall_finger
    shallow = represent_quadtree(v, f, targets=(0.05,), max_depth=4)  # at most 16² cells
    assert tree_edges_on_the_surface(shallow.finest).max() > 0.05 * diagonal(v)


def test_the_finer_trees_keep_every_node_of_the_coarser_ones(tall_finger):
    v, f = tall_finger
    rep = represent_quadtree(v, f, targets=(0.2, 0.1, 0.05))
    sizes = [len(level.keys) for level in rep.levels]
    assert sizes == sorted(sizes) and sizes[0] < sizes[-1]
    for coarse, fine in zip(rep.levels, rep.levels[1:], strict=False):
        assert np.isin(coarse.keys, fine.keys).all()
        # a shared node is the same point of the plane, with the same sampled φ
        pos = np.searchsorted(fine.keys, coarse.keys)
        np.testing.assert_array_equal(fine.uv[pos], coarse.uv)
        np.testing.assert_allclose(fine.phi[pos], coarse.phi, atol=1e-12)


def test_a_tree_with_nothing_to_solve_for_is_left_out():
    """A nearly flat disk's 0.4 tree is a few cells, all cut by LSCM's free border."""
    rep = represent_quadtree(*bumpy_disk(12), targets=(0.9, 0.4, 0.1))
    assert [level.target for level in rep.levels] == [0.1]
    assert all((~level.known).any() for level in rep.levels)
    with pytest.raises(ValueError, match="no tree of targets"):
        represent_quadtree(*bumpy_disk(12), targets=(0.9,))


def test_the_border_nodes_are_the_known_ones_and_h_is_not_defined_there(tall_finger):
    v, f = tall_finger
    level = represent_quadtree(v, f, targets=(0.1,)).finest
    counts = np.zeros(len(level.uv), dtype=int)
    sides = np.sort(np.stack([level.faces, np.roll(level.faces, 1, axis=1)], axis=2)
                    .reshape(-1, 2), axis=1)
    _, index, once = np.unique(sides, axis=0, return_index=True, return_counts=True)
    np.add.at(counts, sides[index[once == 1]].ravel(), 1)
    np.testing.assert_array_equal(level.known, counts > 0)
    assert np.isnan(level.H[level.known]).all() and np.isfinite(level.H[~level.known]).all()
    assert np.isfinite(level.lam).all() and (level.lam > 0).all()


def test_a_map_that_folds_is_untangled_before_the_trees_sample_it(monkeypatch):
    """A folded map sampled piecewise linearly gives one sheet where the mesh has two: the
    trees fold with it (a 72-vertex cow cap: 1,816 folded edges at 0.1 before)."""
    import surfinpaint.representation.mapping as mapping
    from surfinpaint.geometry.parameterization import flipped_faces

    v, f = bumpy_disk(12)
    folded, _ = pushed_over(v, f, part=3)
    assert len(flipped_faces(f, folded)) > 0
    monkeypatch.setattr(mapping, "lscm", lambda *_: folded.copy())
    with pytest.warns(mapping.FoldedMapWarning, match="untangled locally"):
        rep = represent_quadtree(v, f, targets=(0.1,))
    assert len(flipped_faces(f, rep.uv)) == 0
    level = rep.finest
    p = level.phi[level.faces]
    normal = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    assert (normal[:, 2] > 0).all()  # the bumpy disk is a graph over z: no sampled fold
    with pytest.raises(surfinpaint.MeshError, match="folds"):
        represent_quadtree(v, f, targets=(0.1,), strict=True)


def test_a_map_that_overlaps_itself_gives_way_to_the_rectangle(monkeypatch):
    """LSCM's border can curl over itself with no triangle flipped (a 50 mm pial disk's
    crosses 3 times): trees over it would sample one sheet where the mesh has two."""
    from test_parameterization import coiled_strip

    import surfinpaint.representation.mapping as mapping

    uv, f = coiled_strip(1.3)
    v = np.column_stack([uv, 0.1 * uv[:, 0] ** 2])
    monkeypatch.setattr(mapping, "lscm", lambda *_: uv.copy())
    with pytest.warns(mapping.FoldedMapWarning, match="overlaps itself .* rectangular map"):
        rep = represent_quadtree(v, f, targets=(0.2,))
    assert rep.map == "rectangular"
    assert np.ptp(rep.uv, axis=0).max() > 0 and rep.finest.known.any()
    with pytest.raises(surfinpaint.MeshError, match="overlaps itself"):
        represent_quadtree(v, f, targets=(0.2,), strict=True)
    monkeypatch.undo()
    assert represent_quadtree(*bumpy_disk(6), targets=(0.2,)).map == "lscm"


# ------------------------------------------------------------------------- the round trip


def test_the_round_trip_is_the_sampling_floor_and_the_floor_falls_with_the_target(
        tall_finger):
    v, f = tall_finger
    floors = []
    for targets in ((0.2,), (0.2, 0.1), (0.2, 0.1, 0.05)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", CoarseGridWarning)  # tested below
            rep = represent(v, f, discretization="quadtree", targets=targets)
        c = rep.check
        assert isinstance(rep, QuadtreeLambdaH) and c.converged
        # the rebuild gives the trees' own samples back: it adds nothing to the floor
        assert c.mean == pytest.approx(c.floor_mean, rel=1e-6)
        assert c.hausdorff == pytest.approx(c.floor_hausdorff, rel=1e-6)
        floors.append(c.floor_mean / c.diagonal)
    assert floors[1] < 0.7 * floors[0] and floors[2] < 0.7 * floors[1]
    assert floors[2] < 2e-4  # 0.011 % of the diagonal, measured


@pytest.mark.slow
def test_the_default_chain_gives_the_tallest_benchmark_finger_back():
    """The finger h = 2 of ``benchmarks/represent_speed.py`` (λ varies ~1000-fold): from
    the old default's first tree (0.1) the continuation stalls at t = 0.06; from 0.4, each
    tree at most twice finer than the last, every tree converges to its own samples."""
    from surfinpaint.representation.quadtree_represent import DEFAULT_TARGETS

    v, f = finger(height=2.0)
    rep = represent_quadtree(v, f)
    assert [level.target for level in rep.levels] == list(DEFAULT_TARGETS)
    for solve in level_solves(rep):
        assert solve.converged, solve.message
        np.testing.assert_allclose(solve.points, solve.level.phi, atol=1e-9 * diagonal(v))


def test_coarse_to_fine_and_direct_rebuilds_meet(tall_finger):
    v, f = tall_finger
    rep = represent_quadtree(v, f, targets=(0.2, 0.1))
    staged = list(level_solves(rep))
    direct = list(level_solves(rep, direct=True))
    assert all(s.converged for s in staged + direct)
    assert "held, then released" in staged[1].message
    np.testing.assert_allclose(staged[-1].points, direct[-1].points, atol=1e-8 * diagonal(v))
    np.testing.assert_allclose(staged[-1].points, rep.finest.phi, atol=1e-8 * diagonal(v))


def test_a_finer_tree_the_coarser_solution_does_not_lead_to_is_solved_alone(
        monkeypatch, tall_finger):
    """(The 50 mm pial disk's 0.05 tree: its held-then-released Newton from the 0.1 tree
    fails, the tree alone converges by continuation.)"""
    import surfinpaint.representation.quadtree_represent as qr

    v, f = tall_finger
    rep = represent_quadtree(v, f, targets=(0.2, 0.1))
    monkeypatch.setattr(qr, "solve_finer_level",
                        lambda start, *_: (start, False, 7))  # a start that leads nowhere
    coarse, fine = level_solves(rep)
    assert coarse.converged and fine.converged
    assert "not converged, then alone" in fine.message and fine.iterations > 7
    np.testing.assert_allclose(fine.points, rep.finest.phi, atol=1e-8 * diagonal(v))


def test_edited_lambda_and_h_give_another_surface_and_wrong_shapes_are_refused(tall_finger):
    v, f = tall_finger
    rep = represent_quadtree(v, f, targets=(0.2, 0.1))
    same = rebuild(rep)
    flatter = rebuild(rep, H=0.5 * rep.H)
    assert flatter.converged
    moved = np.linalg.norm(flatter.vertices - same.vertices, axis=1)
    assert moved.max() > 0.05 * diagonal(v)  # the finger is lower with half its curvature
    assert flatter.vertices[:, 2].max() < same.vertices[:, 2].max()
    with pytest.raises(ValueError, match="finest tree's"):
        rebuild(rep, lam=rep.lam[:-1])
    with pytest.raises(ValueError, match="not for quadtree"):
        rebuild(rep, method="laplacian")


def test_a_rebuild_that_does_not_converge_says_so_and_stops_at_that_tree(tall_finger):
    v, f = tall_finger
    rep = represent_quadtree(v, f, targets=(0.2, 0.1))
    with pytest.warns(NotConvergedWarning, match="did not converge"):
        out = rebuild(rep, max_iter=1)
    assert not out.converged
    assert f"{len(rep.levels[0].uv)} nodes: 1 (not converged)" in out.message
    assert f"{len(rep.finest.uv)} nodes" not in out.message  # the finer tree is not tried


def test_a_coarse_finest_tree_is_reported(tall_finger):
    v, f = tall_finger
    with pytest.warns(CoarseGridWarning, match="a smaller last target"):
        represent(v, f, discretization="quadtree", targets=(0.2,))
    with warnings.catch_warnings():
        warnings.simplefilter("error", CoarseGridWarning)
        represent(v, f, discretization="quadtree", targets=(0.2, 0.1, 0.05))


# ------------------------------------------------------------------------------ the files


def test_save_and_load_give_the_same_representation_and_rebuild(tmp_path, tall_finger):
    v, f = tall_finger
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CoarseGridWarning)
        rep = quadtree_export(represent(v, f, check=False), targets=(0.2, 0.1))
    rep.save(tmp_path / "tree.npz")
    back = load_representation(tmp_path / "tree.npz")
    assert isinstance(back, QuadtreeLambdaH) and back.check == rep.check
    assert (back.map, back.sampling, back.max_depth) == (rep.map, rep.sampling, rep.max_depth)
    for a, b in zip(rep.levels, back.levels, strict=True):
        for name in ("keys", "uv", "faces", "phi", "known", "lam", "H", "defect"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    np.testing.assert_array_equal(rebuild(back).vertices, rebuild(rep).vertices)
    np.testing.assert_array_equal(sampled_tree_vertices(back), sampled_tree_vertices(rep))


def test_a_file_missing_a_tree_is_refused_by_name(tmp_path, tall_finger):
    v, f = tall_finger
    rep = represent_quadtree(v, f, targets=(0.2, 0.1))
    rep.save(tmp_path / "tree.npz")
    with np.load(tmp_path / "tree.npz") as data:
        arrays = {k: data[k] for k in data.files if k != "level1_phi"}
    np.savez(tmp_path / "cut.npz", **arrays)
    with pytest.raises(ValueError, match="level1_phi"):
        load_representation(tmp_path / "cut.npz")


@pytest.mark.parametrize("options, match", [
    ({"targets": (0.05, 0.1)}, "decreasing"),
    ({"targets": (0.1, 0.0)}, "positive"),
    ({"targets": ()}, "positive"),
    ({"map": "sphere"}, "conformal map"),
    ({"sampling": "cubic"}, "sampling"),
    ({"max_depth": 0}, "max_depth"),
    ({"max_depth": 21}, "max_depth"),
])
def test_bad_options_are_refused(options, match):
    v, f = bumpy_disk(4)
    with pytest.raises(ValueError, match=match):
        represent_quadtree(v, f, **options)


def test_stages_are_said_as_they_start():
    said = []
    represent(*bumpy_disk(6), discretization="quadtree", targets=(0.2, 0.1),
              progress=said.append)
    assert said[0].startswith("mapping") and "quadtrees" in said[0]
    assert said[1].startswith("self-check: rebuilding the quadtrees (")
    # then each tree's solve as it starts, coarse to fine
    assert [line.split(" (")[0] for line in said[2:]] == ["rebuilding tree 1 of 2",
                                                          "rebuilding tree 2 of 2"]
    assert "cells of 0.2 × the diagonal" in said[2]


# -------------------------------------------------------------------------------- the CLI


def test_cli_exports_and_rebuilds_a_quadtree(tmp_path, capsys, tall_finger):
    v, f = tall_finger
    mesh, rep_path, tree_path = tmp_path / "finger.ply", tmp_path / "rep.npz", \
        tmp_path / "tree.npz"
    write_mesh(mesh, v, f)
    assert main(["represent", str(mesh), "-o", str(rep_path), "--export-quadtree",
                 str(tree_path), "--targets", "0.2,0.1", "--png",
                 str(tmp_path / "rep.png")]) == 0
    err = " ".join(capsys.readouterr().err.split())
    tree = load_representation(tree_path)
    assert [level.target for level in tree.levels] == [0.2, 0.1]
    nodes = "/".join(str(len(level.uv)) for level in tree.levels)
    assert f"quadtree export ({nodes} nodes): round trip" in err
    out = tmp_path / "back.ply"
    assert main(["rebuild", str(tree_path), "-o", str(out)]) == 0
    err = " ".join(capsys.readouterr().err.split())
    assert "coarse-to-fine Newton on the quadtrees converged" in err
    assert f"its samples alone (no rebuild can be closer): mean {tree.check.floor_mean:.3g}" \
        in err
    w, g = read_mesh(out)
    np.testing.assert_array_equal(g, f)
    assert surface_distance(w, f, v, f, n_samples=4000).mean < 1e-3 * diagonal(v)
    # the quadtree as the representation itself, drawn on its finest tree
    png = tmp_path / "tree.png"
    assert main(["represent", str(mesh), "-o", str(tmp_path / "q.npz"), "--discretization",
                 "quadtree", "--targets", "0.2", "--no-check", "--png", str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    for method in ("newton", "laplacian"):
        assert main(["rebuild", str(tree_path), "-o", str(out), "--method", method]) == 2


@pytest.mark.parametrize("extra, says", [
    (["--targets", "0.1"], "--targets is for --discretization quadtree"),
    (["--export-quadtree", "T", "--targets", "0.05,0.1"], "decreasing numbers"),
    (["--export-quadtree", "T", "--targets", "0.1,x"], "decreasing numbers"),
    (["--export-quadtree", "T", "--resolution", "64"], "--resolution: for --discretization grid"),
    (["--sampling", "pl"], "--sampling is for a grid or quadtree"),
])
def test_cli_refuses_options_nothing_reads(tmp_path, capsys, extra, says):
    mesh = tmp_path / "disk.ply"
    write_mesh(mesh, *bumpy_disk(4))
    extra = [str(tmp_path / "t.npz") if x == "T" else x for x in extra]
    try:
        code = main(["represent", str(mesh), "-o", str(tmp_path / "r.npz"), *extra])
    except SystemExit as exc:  # argparse's own refusal of a value
        code = exc.code
    assert code == 2
    assert says in " ".join(capsys.readouterr().err.split())
    assert not (tmp_path / "r.npz").exists() and not (tmp_path / "t.npz").exists()


def test_cli_refuses_an_export_that_would_replace_the_input(tmp_path, capsys):
    mesh = tmp_path / "disk.ply"
    write_mesh(mesh, *bumpy_disk(4))
    before = mesh.read_bytes()
    assert main(["represent", str(mesh), "-o", str(tmp_path / "r.npz"), "--export-quadtree",
                 str(mesh)]) == 2
    assert mesh.read_bytes() == before and not (tmp_path / "r.npz").exists()


# ------------------------------------------------- the default: the mesh form or the trees


def glove_finger(length=2.0, radius=0.2, around=8, rings=6, cap_rings=2):
    """A coarse closed-ended tube, open at the top (a cap over a limb's tip): λ varies
    ~8000-fold over its 65 vertices and the mesh form's rebuild does not converge on it
    (its continuation stalls), where the quadtrees' coarse-to-fine rebuild does."""
    t = np.linspace(0, 2 * np.pi, around, endpoint=False)
    a = (np.pi / 2) * np.arange(1, cap_rings + 1) / cap_rings
    z = np.r_[-radius * np.cos(a), length * np.arange(1, rings + 1) / rings]
    r = np.r_[radius * np.sin(a), np.full(rings, radius)]
    v = np.vstack([[0.0, 0.0, -radius],
                   np.column_stack([np.outer(r, np.cos(t)).ravel(),
                                    np.outer(r, np.sin(t)).ravel(),
                                    np.repeat(z, around)])])
    k = np.arange(around)
    fan = np.column_stack([np.zeros(around, int), 1 + k, 1 + (k + 1) % around])
    lower = 1 + np.arange(len(z) - 1)[:, None] * around
    a0, a1 = (lower + k).ravel(), (lower + (k + 1) % around).ravel()
    quads = np.vstack([np.column_stack([a0, a0 + around, a1 + around]),
                       np.column_stack([a0, a1 + around, a1])])
    return v, np.vstack([fan, quads])


def test_the_default_takes_the_quadtrees_where_the_mesh_forms_rebuild_does_not_converge():
    v, f = glove_finger()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh_form = represent(v, f, discretization="mesh")
        said = []
        rep = represent(v, f, progress=said.append)
    assert not mesh_form.check.converged and mesh_form.check.hausdorff_percent > 50
    assert rep.discretization == "quadtree" and rep.check.converged
    assert rep.check.hausdorff < 0.05 * mesh_form.check.hausdorff
    assert "the mesh form's rebuild did not converge; trying the quadtrees" in said


def test_the_default_is_the_mesh_form_wherever_its_rebuild_converges(tall_finger):
    rep = represent(*tall_finger, progress=(said := []).append)
    assert rep.discretization == "mesh" and rep.check.converged
    np.testing.assert_array_equal(rep.lam, represent(*tall_finger, discretization="mesh").lam)
    assert not any("quadtrees" in line for line in said)


@pytest.mark.parametrize("mesh_trip, trees_trip, check, kind", [
    ((True, 1e-9), None, True, "mesh"),           # converged: the trees never made
    ((False, 50.0), (True, 1.0), True, "quadtree"),
    ((False, 50.0), (True, 60.0), True, "mesh"),  # converged, but farther from the mesh
    ((False, 50.0), (False, 1.0), True, "mesh"),  # the trees' rebuild failed as well
    ((False, 50.0), "error", True, "mesh"),       # the trees could not be made
    ((False, 50.0), None, False, "mesh"),         # no check, nothing to choose by
])
def test_the_defaults_rule(monkeypatch, mesh_trip, trees_trip, check, kind):
    import types

    from surfinpaint.errors import MeshError
    from surfinpaint.representation import represent as module

    made = []

    def fake(v, f, *, discretization, check=True, **kw):
        made.append(discretization)
        trip = {"mesh": mesh_trip, "quadtree": trees_trip}[discretization]
        if trip == "error":
            raise MeshError("no tree has a node to solve for")
        checked = types.SimpleNamespace(converged=trip[0], hausdorff=trip[1])
        return types.SimpleNamespace(discretization=discretization,
                                     check=checked if check else None)

    monkeypatch.setattr(module, "represent", fake)
    rep = module._mesh_form_or_quadtrees(None, None, "lscm", check, False, None)
    assert rep.discretization == kind
    assert made == (["mesh"] if trees_trip is None else ["mesh", "quadtree"])


def test_cli_represent_names_the_form_the_default_took(tmp_path, capsys):
    mesh, out = tmp_path / "glove.ply", tmp_path / "rep.npz"
    write_mesh(mesh, *glove_finger())
    assert main(["represent", str(mesh), "-o", str(out)]) == 0
    err = " ".join(capsys.readouterr().err.split())
    assert "quadtree representation: round trip" in err and "converged" in err
    assert load_representation(out).discretization == "quadtree"
    assert main(["represent", str(mesh), "-o", str(out), "--discretization", "mesh"]) == 0
    err = " ".join(capsys.readouterr().err.split())
    assert "mesh representation: round trip" in err and "DID NOT CONVERGE" in err
