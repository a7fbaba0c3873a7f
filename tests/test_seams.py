"""Loops that span no area (slits, seams of duplicated vertices) are never filled and never
stop the run; a hole whose fill raises is reported failed and the others are still filled.

The meshes are built here: a UV sphere whose seam has duplicated vertices (as exporters write
a texture seam), a flat grid cut along an interior segment by duplicating its vertices, each
with an ordinary hole beside it.
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

import surfinpaint.fill.liepa.baseline as baseline
from surfinpaint import MeshWarning, fill_holes, find_holes, validate_mesh
from surfinpaint.data import sphere
from surfinpaint.errors import MeshError
from surfinpaint.fill.seams import find_seam_part, find_slit, zip_faces
from surfinpaint.geometry.validation import zero_area_faces

METHODS = ["conformal", "fair"]


def uv_sphere(n_lat: int = 12, n_lon: int = 24):
    """A UV sphere whose seam (longitude 0 = 2π) has its vertices twice, bit-identical;
    the poles are shared. Its seam is one boundary loop of 2 (n_lat - 1) + 2 edges."""
    theta = np.linspace(0, np.pi, n_lat + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, n_lon + 1)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    rings = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), -np.cos(t)], axis=-1)
    rings[:, -1] = rings[:, 0]
    v = np.vstack([[0, 0, -1.0], rings.reshape(-1, 3), [0, 0, 1.0]])
    south, north = 0, len(v) - 1

    def at(j, i):
        return 1 + j * (n_lon + 1) + i

    f = []
    for i in range(n_lon):
        f += [[south, at(0, i + 1), at(0, i)], [north, at(n_lat - 2, i), at(n_lat - 2, i + 1)]]
        for j in range(n_lat - 2):
            f += [[at(j, i), at(j, i + 1), at(j + 1, i + 1)], [at(j, i), at(j + 1, i + 1),
                                                               at(j + 1, i)]]
    return v, np.array(f)


def slit_grid(n: int = 12, width: float = 0.0):
    """A flat n x n grid cut along x = n/2 for 3 < y < n - 3: the faces right of the cut use
    copies of its vertices (moved ``width`` to the right). Returns the mesh and the
    (copy, original) pairs."""
    x, y = np.meshgrid(np.arange(n + 1.0), np.arange(n + 1.0), indexing="ij")
    v = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    at = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = at[:-1, :-1].ravel(), at[1:, :-1].ravel(), at[1:, 1:].ravel(), at[:-1, 1:].ravel()
    f = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    cut = at[n // 2, 4:n - 3]
    copies = len(v) + np.arange(len(cut))
    v = np.vstack([v, v[cut] + [width, 0, 0]])
    right = v[f].mean(axis=1)[:, 0] > n // 2
    mapping = np.arange(len(v))
    mapping[cut] = copies
    f[right] = mapping[f[right]]
    return v, f, np.column_stack([copies, cut])


def without_faces_near(v, f, centre, radius):
    return f[np.linalg.norm(v[f].mean(axis=1) - np.asarray(centre, float), axis=1) > radius]


@pytest.fixture(scope="module")
def seamed_sphere():
    """The UV sphere with its seam and an ordinary hole on the far side."""
    v, f = uv_sphere()
    return v, without_faces_near(v, f, [-1, 0, 0], 0.35)


@pytest.fixture(scope="module")
def slit_plane():
    """The slit grid with an ordinary hole beside the slit."""
    v, f, pairs = slit_grid()
    return v, without_faces_near(v, f, [2.5, 2.5, 0], 1.2), pairs


def _run(*args, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(*args, jobs=1, **kwargs)
    return result, caught


def _slit_and_hole(vertices, faces):
    holes = find_holes(vertices, faces)
    slits = [k for k, h in enumerate(holes) if find_slit(vertices, h.loop) is not None]
    others = [k for k, h in enumerate(holes) if k not in slits and not h.is_border]
    assert len(slits) == 1 and len(others) == 1
    return slits[0], others[0]


def _no_folded_sheet(result):
    """No zero-area face and no two faces on the same three vertices (a folded sheet)."""
    assert len(zero_area_faces(result.vertices, result.faces)) == 0
    assert len(np.unique(np.sort(result.faces, axis=1), axis=0)) == len(result.faces)
    validate_mesh(result.vertices, result.faces)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("mesh", ["seamed_sphere", "slit_plane"])
def test_a_loop_that_spans_no_area_is_left_open_with_a_warning(mesh, method, request):
    # before: the sphere's seam was 'filled' by a sheet folded onto itself (no warning), the
    # plane's aborted the whole call (FillError: fairing system is singular)
    v, f = request.getfixturevalue(mesh)[:2]
    slit, hole = _slit_and_hole(v, f)
    result, caught = _run(v, f, method=method)
    reports = {r.index: r for r in result.reports}
    assert reports[slit].skipped and "spans no area" in reports[slit].skipped
    assert reports[slit].method == "none" and reports[slit].new_faces == 0
    assert reports[hole].new_faces > 0 and not reports[hole].skipped
    named = [w for w in caught if str(w.message).startswith(f"hole {slit}: ")]
    assert len(named) == 1 and issubclass(named[0].category, MeshWarning)
    assert "--zip-seams" in str(named[0].message)
    np.testing.assert_array_equal(result.faces[:len(f)], f)
    _no_folded_sheet(result)
    left = [set(h.loop.tolist()) for h in find_holes(result.vertices, result.faces)
            if not h.is_border]
    assert left == [set(find_holes(v, f)[slit].loop.tolist())]  # the slit, and only it


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("mesh", ["seamed_sphere", "slit_plane"])
def test_zip_seams_closes_the_seam_and_fills_the_hole(mesh, method, request):
    v, f = request.getfixturevalue(mesh)[:2]
    slit, hole = _slit_and_hole(v, f)
    result, caught = _run(v, f, method=method, zip_seams=True)
    reports = {r.index: r for r in result.reports}
    assert reports[slit].outcome == "zipped" and not reports[slit].skipped
    assert reports[hole].new_faces > 0
    merged = result.merged_vertices
    np.testing.assert_array_equal(v[merged[:, 0]], v[merged[:, 1]])  # coincident pairs
    assert (merged[:, 0] > merged[:, 1]).all()  # the first in the file is kept
    np.testing.assert_array_equal(result.vertices[:len(v)], v)  # nothing moved or dropped
    assert not np.isin(result.faces, merged[:, 0]).any()  # the duplicates are unused
    mapping = np.arange(len(v))
    mapping[merged[:, 0]] = merged[:, 1]
    np.testing.assert_array_equal(result.faces[:len(f)], mapping[f])  # only ids replaced
    assert any(str(w.message).startswith(f"hole {slit}: a seam of {len(merged)} coincident")
               for w in caught)
    _no_folded_sheet(result)
    borders = [h for h in find_holes(result.vertices, result.faces) if not h.is_border]
    assert borders == []  # the seam and the hole are closed
    if mesh == "seamed_sphere":
        after = validate_mesh(result.vertices, result.faces)
        assert after.n_components == 1 and after.euler_characteristic == 2  # a sphere


@pytest.mark.parametrize("pinned", [False, True])
def test_seams_are_found_on_both_kinds_of_surface_at_any_scale(seamed_sphere, slit_plane,
                                                               pinned):
    # pinned: the loops given explicitly (the caller's holes=) are treated alike
    for v, f in (seamed_sphere, slit_plane[:2]):
        slit, hole = _slit_and_hole(v, f)
        loops = [h.loop for h in find_holes(v, f)]
        for scale in (1e-200, 1.0, 1e200):
            found = find_slit(v * scale, loops[slit])
            assert found is not None and found.is_seam
            assert find_slit(v * scale, loops[hole]) is None
        if pinned:
            result, _ = _run(v, f, holes=[slit, hole], method="fair")
            assert [(r.index, bool(r.skipped)) for r in result.reports] == [(slit, True),
                                                                            (hole, False)]
    v, f, pairs = slit_plane
    found = find_slit(v, find_holes(v, f)[_slit_and_hole(v, f)[0]].loop)
    np.testing.assert_array_equal(found.merges, pairs[np.argsort(pairs[:, 0])])


def test_ordinary_holes_are_not_slits():
    v, f = sphere(3)
    for centre, radius in (([1, 0, 0], 0.5), ([0, 0, 1], 0.15), ([0, 1, 0], 0.9)):
        g = without_faces_near(v, f, centre, radius)
        assert [find_slit(v, h.loop) for h in find_holes(v, g)] == [None]
        assert [find_seam_part(v, h.loop) for h in find_holes(v, g)] == [None]


@pytest.mark.parametrize(("width", "is_slit"), [(0.0, True), (1e-4, True), (0.01, False),
                                                (0.2, False)])
def test_a_crack_is_a_slit_only_within_the_tolerance(width, is_slit):
    # the tolerance is SLIT_RTOL (1e-3) of the edge length; a crack wider than that is a
    # (thin) hole and is filled
    v, f, _ = slit_grid(width=width)
    (loop,) = [h.loop for h in find_holes(v, f) if not h.is_border]
    assert (find_slit(v, loop) is not None) == is_slit
    if not is_slit:
        result, _ = _run(v, f, method="fair")
        assert result.reports[-1].new_faces > 0
        _no_folded_sheet(result)


def test_a_seam_that_cannot_be_zipped_is_left_open():
    # the copies' faces turned over: zipping would join two sheets facing opposite ways
    v, f, pairs = slit_grid()
    loops = [h.loop for h in find_holes(v, f) if not h.is_border]
    slit = find_slit(v, loops[0])
    flipped = f.copy()
    right = np.isin(f, pairs[:, 0]).any(axis=1)
    flipped[right] = flipped[right][:, ::-1]
    zipped, problem = zip_faces(flipped, slit.merges)
    assert problem is not None and "opposite" in problem
    assert zip_faces(f, slit.merges)[1] is None
    np.testing.assert_array_equal(zipped[~np.isin(f, pairs[:, 0]).any(axis=1)],
                                  f[~np.isin(f, pairs[:, 0]).any(axis=1)])


def _failing_fairing(monkeypatch, centre):
    """The fairing solve raises (as on a singular system) for the hole near ``centre``."""
    fair_patch = baseline.fair_patch

    def fair(vertices, faces, free, **kwargs):
        if np.linalg.norm(vertices[free].mean(axis=0) - centre) < 0.5:
            raise MeshError("fairing system is singular (degenerate triangles around the "
                            "free vertices?)", vertices=free[:3].tolist())
        return fair_patch(vertices, faces, free, **kwargs)

    fair_orders = baseline.fair_orders

    def fair_all(vertices, faces, free, orders, **kwargs):  # faired_fills' every order
        if np.linalg.norm(vertices[free].mean(axis=0) - centre) < 0.5:
            return {k: MeshError("fairing system is singular (degenerate triangles around "
                                 "the free vertices?)", vertices=free[:3].tolist())
                    for k in orders}
        return fair_orders(vertices, faces, free, orders, **kwargs)

    monkeypatch.setattr(baseline, "fair_patch", fair)
    monkeypatch.setattr(baseline, "fair_orders", fair_all)


@pytest.mark.parametrize("method", METHODS)
def test_one_unfillable_hole_never_stops_the_others(method, monkeypatch):
    # before: the faired fill's (and the conformal method's faired fallback's) FillError went
    # straight through fill_holes, and the other holes were lost
    v, f = sphere(3)
    centres = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 0, 1]])
    g = f
    for c in centres:
        g = without_faces_near(v, g, c, 0.3)
    _failing_fairing(monkeypatch, centres[1])
    result, caught = _run(v, g, method=method)
    holes = find_holes(v, g)
    failed = [r for r in result.reports if r.failed]
    assert len(failed) == 1
    (k,) = [i for i, h in enumerate(holes) if np.linalg.norm(v[h.loop].mean(0) - centres[1]) < .3]
    assert failed[0].index == k and failed[0].outcome == "failed"
    assert failed[0].skipped.startswith("the fill failed: ") and failed[0].method == "none"
    assert "fairing system is singular" in failed[0].skipped
    assert sum(r.new_faces > 0 for r in result.reports) == 2
    assert any(str(w.message).startswith(f"hole {k}: the fill failed") for w in caught)


def test_failed_holes_are_the_same_in_workers(monkeypatch):
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    from surfinpaint.fill import parallel

    monkeypatch.setattr(parallel, "MIN_PARALLEL_EDGES", {"fair": 0, "conformal": 0})
    context = multiprocessing.get_context("fork")
    monkeypatch.setattr(parallel, "pool", lambda workers: ProcessPoolExecutor(
        workers, mp_context=context))
    v, f = sphere(3)
    centres = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 0, 1], [0, 0, -1]])
    for c in centres:
        f = without_faces_near(v, f, c, 0.3)
    _failing_fairing(monkeypatch, centres[2])
    runs = {}
    for jobs in (1, 2):
        with warnings.catch_warnings(record=True):
            warnings.simplefilter("always")
            runs[jobs] = fill_holes(v, f, method="fair", jobs=jobs)
    assert [(r.failed, r.skipped) for r in runs[1].reports] == \
        [(r.failed, r.skipped) for r in runs[2].reports]
    assert sum(bool(r.failed) for r in runs[1].reports) == 1
    np.testing.assert_array_equal(runs[1].faces, runs[2].faces)


def test_a_mesh_error_inside_a_fill_names_the_hole(monkeypatch):
    from surfinpaint.fill import parallel

    def broken(*args):
        raise MeshError("the neighbourhood is broken", vertices=[7])

    monkeypatch.setattr(parallel, "fill_local", broken)
    v, f = sphere(2)
    with pytest.raises(MeshError, match=r"^hole 0: the neighbourhood is broken") as info:
        fill_holes(v, f[1:], method="fair", jobs=1)
    assert info.value.vertices == [7]


def test_the_command_line_on_a_seamed_obj(seamed_sphere, tmp_path, capsys):
    from surfinpaint.app.cli import main
    from surfinpaint.io.formats import read_mesh, write_mesh

    v, f = seamed_sphere
    source = tmp_path / "seamed.obj"
    write_mesh(source, v, f)
    slit, hole = _slit_and_hole(*read_mesh(source))
    assert main(["fill", str(source), "-o", str(tmp_path / "open.ply")]) == 0
    err = " ".join(capsys.readouterr().err.split())
    assert err.count("the loop spans no area") == 1 and "--zip-seams" in err  # said once
    v2, f2 = read_mesh(tmp_path / "open.ply")
    assert [h.n_edges for h in find_holes(v2, f2)] == [find_holes(v, f)[slit].n_edges]
    assert main(["fill", str(source), "-o", str(tmp_path / "closed.ply"), "--zip-seams"]) == 0
    err = " ".join(capsys.readouterr().err.split())
    assert f"hole {slit}: a seam of" in err and "1 seam zipped" in err
    v3, f3 = read_mesh(tmp_path / "closed.ply")
    assert find_holes(v3, f3) == [] and len(v3) == len(v) + (len(v2) - len(v))


def test_command_line_errors_name_the_file(tmp_path, capsys, monkeypatch):
    from surfinpaint.app import cli
    from surfinpaint.app.cli import main
    from surfinpaint.io.formats import write_mesh

    v, f = sphere(2)
    source = tmp_path / "one.ply"
    write_mesh(source, v, f[1:])

    def broken(*args, **kwargs):
        raise RuntimeError("a solver gave up")

    monkeypatch.setattr(cli, "fill_mesh_data", broken)
    assert main(["fill", str(source), "-o", str(tmp_path / "out.ply"), "-q"]) == 1
    err = " ".join(capsys.readouterr().err.split())
    assert f"{source}: RuntimeError: a solver gave up" in err


def open_tube(n: int = 24, m: int = 10):
    """An open cylinder whose seam (angle 0 = 2π) has its vertices twice: one boundary
    loop, the two rims joined by the seam's two sides."""
    phi, z = np.linspace(0, 2 * np.pi, n + 1), np.linspace(0, 2, m + 1)
    p, h = np.meshgrid(phi, z, indexing="ij")
    v = np.stack([np.cos(p), np.sin(p), h], axis=-1)
    v[-1] = v[0]
    at = np.arange((n + 1) * (m + 1)).reshape(n + 1, m + 1)
    a, b, c, d = at[:-1, :-1].ravel(), at[1:, :-1].ravel(), at[1:, 1:].ravel(), at[:-1, 1:].ravel()
    return v.reshape(-1, 3), np.concatenate([np.column_stack([a, b, c]),
                                              np.column_stack([a, c, d])])


@pytest.mark.parametrize("method", METHODS)
def test_a_seam_along_part_of_a_loop(method):
    # before: the tube's one loop (rims and seam) was 'filled' with a 384-face sheet
    v, f = open_tube()
    (hole,) = find_holes(v, f)
    result, caught = _run(v, f, method=method)
    assert result.reports[0].outcome == "skipped" and len(result.faces) == len(f)
    assert any("runs back along itself" in str(w.message) and "--zip-seams" in str(w.message)
               and issubclass(w.category, MeshWarning) for w in caught)
    result, caught = _run(v, f, method=method, zip_seams=True)
    assert result.reports[0].outcome == "zipped" and len(result.merged_vertices) == 11
    np.testing.assert_array_equal(result.vertices[:len(v)], v)
    rims = sorted(h.n_edges for h in find_holes(result.vertices, result.faces))
    assert rims == [24, 24]  # the seam closed, the rims left open
    _no_folded_sheet(result)


def test_a_zipped_seam_makes_its_own_incidence(seamed_sphere, monkeypatch):
    # a large mesh's vertex-face incidence is made beside its edge table, from the faces
    # before any seam is zipped: a zipped mesh makes its own (a stale one would cut the
    # wrong faces around the other holes)
    from surfinpaint.fill import pipeline, warmup

    v, f = seamed_sphere
    plain, _ = _run(v, f, method="fair", zip_seams=True)
    monkeypatch.setattr(warmup, "BESIDE_MIN_FACES", 1)
    given = []
    filled_mesh = pipeline.FilledMesh
    monkeypatch.setattr(pipeline, "FilledMesh",
                        lambda *a: given.append(a[2]) or filled_mesh(*a))
    result, _ = _run(v, f, method="fair", zip_seams=True)
    assert given == [None]
    np.testing.assert_array_equal(result.faces, plain.faces)
    np.testing.assert_array_equal(result.vertices, plain.vertices)
    unzipped, _ = _run(v, f, method="fair")  # no seam zipped: the incidence is used
    assert given[1] is not None
    assert unzipped.reports[0].new_faces + unzipped.reports[1].new_faces > 0


@pytest.mark.parametrize("zip_seams", [False, True])
def test_a_seam_s_warning_points_at_the_caller_of_fill_holes(slit_plane, zip_seams):
    # the line that called fill_holes, as every other warning of the fill does (stacklevel)
    import inspect

    v, f = slit_plane[:2]
    slit, _ = _slit_and_hole(v, f)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        line = inspect.currentframe().f_lineno + 1
        fill_holes(v, f, method="fair", zip_seams=zip_seams, jobs=1)
    (named,) = [w for w in caught if str(w.message).startswith(f"hole {slit}: ")]
    assert (named.filename, named.lineno) == (__file__, line)


@pytest.mark.parametrize("mesh", ["seamed_sphere", "slit_plane"])
def test_holes_says_fill_leaves_the_slit_open(mesh, request, tmp_path, capsys):
    # `holes` called a slit or a seam "hole" though `fill` leaves it open (session 35): it
    # now says what fill does with each loop, the slit's reason included
    from surfinpaint.app.cli import main
    from surfinpaint.io.formats import write_mesh

    v, f = request.getfixturevalue(mesh)[:2]
    path = tmp_path / "mesh.ply"
    write_mesh(path, v, f)
    slit, hole = _slit_and_hole(v, f)
    assert main(["holes", str(path)]) == 0
    out = capsys.readouterr().out
    rows = [[c.strip() for c in re.split(r"[│┃|]", line) if c.strip()]
            for line in out.splitlines()]
    kinds = {int(r[0]): r[-1] for r in rows if r and r[0].isdigit()}
    assert kinds[slit] == "left open: see below" and kinds[hole] == "hole"
    said = " ".join(out.split())
    assert f"hole {slit}: the loop spans no area" in said and "fill skips it" in said
    assert "left open (zip_seams=True, or --zip-seams, closes it)" in said  # both are seams
    result, _ = _run(v, f, method="fair")
    assert [r.index for r in result.reports if r.skipped] == [slit]
