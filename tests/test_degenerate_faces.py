"""Degenerate faces (docs/robustness.md): a face that uses a vertex twice is no triangle, left
out of the topology and kept in the output as it is; a face of zero area is a triangle of
the surface, kept, and refused only by the fill of a hole whose neighbourhood holds it. The
fills of the holes away from them are bit-identical to the fills without them, and no hole
is invented from them."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest

from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.errors import HoleWarning, MeshError
from surfinpaint.fill.holes import find_holes
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.geometry.validation import check_topology, validate_mesh
from surfinpaint.io import read_mesh, write_mesh

ASSIMP = Path("/usr/share/assimp/models/OBJ")


def _holed(subdivisions: int = 3):
    """A sphere with one hole, and a vertex far from it (the far side)."""
    v, f = sphere(subdivisions)
    cut = cut_holes(v, f, [0], [2.5 * mean_edge_length(v, f)])
    far = int(np.argmin(cut.vertices @ cut.vertices[0]))
    return cut.vertices, cut.faces, far


def _sliver(v, f, face):
    """A zero-area sliver beside ``face`` (a, b, c): a vertex m on the midpoint of (a, b),
    ``face`` becomes (a, m, c) in place, (m, b, c) and the sliver (a, b, m) are appended:
    a T-junction closed by a face of three collinear corners (manifold, oriented). Returns
    the vertices, faces and the sliver's id."""
    a, b, c = f[face]
    m = len(v)
    v = np.vstack([v, 0.5 * (v[a] + v[b])])
    f = f.copy()
    f[face] = (a, m, c)
    f = np.vstack([f, [[m, b, c], [a, b, m]]])
    return v, f, len(f) - 1


def _fill(v, f, **options):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = fill_holes(v, f, jobs=1, **options)
    return result, [str(w.message) for w in caught]


def _new_part(result):
    return (result.vertices[result.n_original_vertices:],
            result.faces[result.n_original_faces:])


def test_validate_mesh_reports_degenerate_faces_and_leaves_repeated_ones_out():
    v, f, far = _holed()
    base = validate_mesh(v, f)
    at = int(np.flatnonzero((f == far).any(axis=1))[0])
    a, b = f[at, :2]
    odd = np.insert(f, 7, [[a, a, b], [far, far, far]], axis=0)
    report = validate_mesh(v, odd)
    np.testing.assert_array_equal(report.repeated_vertex_faces, [7, 8])
    assert report.zero_area_faces.size == 0
    # the topology is that of the triangles: no slit hole along (a, b), the same counts
    assert report.boundary_loop_lengths == base.boundary_loop_lengths
    assert (report.n_edges, report.n_components, report.euler_characteristic) == (
        base.n_edges, base.n_components, base.euler_characteristic)
    assert report.n_faces == len(f) + 2
    assert any("2 faces use the same vertex twice" in n and f"7 ({a}, {a}, {b})" in n
               for n in report.notes)
    sv, sf, sliver = _sliver(v, f, at)
    report = validate_mesh(sv, sf)
    np.testing.assert_array_equal(report.zero_area_faces, [sliver])
    assert report.boundary_loop_lengths == base.boundary_loop_lengths
    assert any("1 face has zero area" in n and f"{sliver} (" in n for n in report.notes)
    # coincident corners are zero area too
    cv = np.vstack([v, [[3.0, 0, 0], [3.0, 0, 0], [3.0, 1, 0]]])
    cf = np.vstack([f, [[len(v), len(v) + 1, len(v) + 2]]])
    assert validate_mesh(cv, cf).zero_area_faces.tolist() == [len(f)]
    # check_topology returns them; it takes triangles only (the caller leaves the rest out)
    _, flat = check_topology(sv, sf)
    assert flat.tolist() == [sliver]
    with pytest.raises(MeshError, match="7 faces use the same vertex twice|same vertex twice"):
        check_topology(v, odd)


@pytest.mark.parametrize("method", ["fair", "conformal"])
@pytest.mark.parametrize("where", ["far", "on the loop"])
def test_a_face_that_repeats_a_vertex_is_kept_and_changes_no_fill(method, where):
    v, f, far = _holed()
    loop = find_holes(v, f)[0].loop
    a, b = (loop[0], loop[1]) if where == "on the loop" else \
        f[np.flatnonzero((f == far).any(axis=1))[0], :2]
    odd = np.insert(f, 11, [[a, b, a]], axis=0)
    # no hole invented: the same loops, in the same order
    assert [h.loop.tolist() for h in find_holes(v, odd)] == [h.loop.tolist()
                                                             for h in find_holes(v, f)]
    # per-vertex and per-face data: inpainted and copied across the loop as without it
    height = {"height": v[:, 2].copy()}
    label = np.arange(len(f))
    plain, _ = _fill(v, f, method=method, attributes=height,
                     face_attributes={"label": label})
    result, said = _fill(v, odd, method=method, attributes=height,
                         face_attributes={"label": np.insert(label, 11, -1)})
    assert [r.outcome for r in result.reports] == [r.outcome for r in plain.reports]
    assert not any(r.skipped for r in result.reports)
    # every original face kept, in order, the odd one in its place; the fill bit-identical
    np.testing.assert_array_equal(result.faces[:len(odd)], odd)
    np.testing.assert_array_equal(result.vertices[:len(v)], v)
    for got, expected in zip(_new_part(result), _new_part(plain), strict=True):
        np.testing.assert_array_equal(got, expected)
    np.testing.assert_array_equal(result.attributes["height"], plain.attributes["height"])
    np.testing.assert_array_equal(result.face_attributes["label"][len(odd):],
                                  plain.face_attributes["label"][len(f):])
    assert [s for s in said if "same vertex twice" in s] == [
        f"1 face uses the same vertex twice (no triangles: kept as they are, left out of "
        f"the holes and the fills): 11 ({a}, {b}, {a})"]


@pytest.mark.parametrize("method", ["fair", "conformal"])
def test_a_zero_area_sliver_away_from_the_hole_leaves_its_fill_bit_identical(method):
    v, f, far = _holed(4)  # the far side beyond the rings the λ-H fill looks at
    at = int(np.flatnonzero((f == far).any(axis=1))[0])
    sv, sf, sliver = _sliver(v, f, at)
    assert [h.loop.tolist() for h in find_holes(sv, sf)] == [h.loop.tolist()
                                                             for h in find_holes(v, f)]
    plain, _ = _fill(v, f, method=method)
    result, said = _fill(sv, sf, method=method)
    assert [r.outcome for r in result.reports] == [r.outcome for r in plain.reports] != [
        "skipped"]
    np.testing.assert_array_equal(result.faces[:len(sf)], sf)
    np.testing.assert_array_equal(result.vertices[:len(sv)], sv)
    new_v, new_f = _new_part(result)
    plain_v, plain_f = _new_part(plain)
    np.testing.assert_array_equal(new_v, plain_v)
    # the new vertices are numbered after the sliver's one more original vertex
    np.testing.assert_array_equal(new_f, np.where(plain_f >= len(v), plain_f + 1, plain_f))
    assert [s for s in said if "zero area" in s] == [
        f"1 face has zero area (collinear or coincident corners; kept as they are; a hole "
        f"whose fill would reach them is filled from fewer rings where it can, else left "
        f"open): {sliver} "
        f"{tuple(int(x) for x in sf[sliver])}"]


def test_a_hole_whose_neighbourhood_holds_a_zero_area_face_is_skipped_or_refused():
    v, f = sphere(3)
    h = mean_edge_length(v, f)
    far = int(np.argmin(v @ v[0]))
    cut = cut_holes(v, f, [0, far], [2.5 * h, 2.5 * h])
    v, f = cut.vertices, cut.faces
    holes = find_holes(v, f)
    near = holes[0].loop
    beside = int(np.flatnonzero(np.isin(f, near).sum(axis=1) == 2)[0])  # a face on the loop
    # the sliver on the face's inner edge: in the ring next to the hole
    inner = [k for k in range(3) if f[beside, k] not in near or f[beside, (k + 1) % 3]
             not in near][0]
    rolled = np.roll(f[beside], -inner)
    f = f.copy()
    f[beside] = rolled
    sv, sf, sliver = _sliver(v, f, beside)
    plain, _ = _fill(v, f, method="fair")
    with pytest.warns(HoleWarning, match=rf"hole 0: 1 face of zero area .* lies in the "
                                         rf"neighbourhood its fill uses: {sliver} "):
        result = fill_holes(sv, sf, method="fair", jobs=1)
    skipped, other = result.reports
    assert skipped.index == 0 and skipped.method == "none" and str(sliver) in skipped.skipped
    assert other.index == 1 and not other.skipped  # the other hole is filled as without it
    np.testing.assert_array_equal(result.faces[:len(sf)], sf)
    assert other.new_vertices == plain.reports[1].new_vertices > 0
    np.testing.assert_array_equal(result.vertices[len(sv):],
                                  plain.vertices[-other.new_vertices:])
    # named by the caller: an error naming the hole and the face
    with pytest.raises(MeshError, match=rf"hole 0: 1 face of zero area.*{sliver} ") as err:
        fill_holes(sv, sf, holes=[0], method="fair", jobs=1)
    assert err.value.faces == [sliver]


def _hops(v, f, sources):
    """Edge hops from ``sources`` to every vertex."""
    from scipy.sparse import coo_matrix

    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    graph = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(len(v), len(v))).tocsr()
    graph = graph + graph.T
    hops = np.full(len(v), np.inf)
    frontier, d = np.unique(sources), 0
    while len(frontier):
        hops[frontier] = d
        frontier = np.unique(graph[frontier].indices)
        frontier = frontier[np.isinf(hops[frontier])]
        d += 1
    return hops


def _sliver_rings_away(rings: int, n_holes: int = 1):
    """A sphere with ``n_holes`` holes and a zero-area sliver ``rings`` edge hops from the
    first hole's loop (in its neighbourhood of ``rings + 1`` vertex rings)."""
    v, f = sphere(4)
    h = mean_edge_length(v, f)
    centres = [np.array(c, float) for c in ([0, 0, 1], [1, 0, 0], [0, 1, 0])][:n_holes]
    cut = cut_holes(v, f, centres, [2.5 * h] * n_holes)
    v, f = cut.vertices, cut.faces
    hops = _hops(v, f, find_holes(v, f)[0].loop)
    # a face whose nearest corner is ``rings`` hops away, that corner first: the sliver on
    # its first edge is then in the neighbourhood of ``rings + 1`` rings, not of fewer
    at = int(np.flatnonzero(hops[f].min(axis=1) == rings)[0])
    f = f.copy()
    f[at] = np.roll(f[at], -int(np.argmin(hops[f[at]])))
    return (v, f, *_sliver(v, f, at))


@pytest.mark.parametrize("workers", ["none", "forked", "forkserver"])
def test_the_lambda_h_fill_works_around_a_zero_area_face_outside_the_faired_fills_rings(
        workers, monkeypatch):
    # the λ-H fill and its self-check look 16 rings around a 10-edge hole; a sliver 6 rings
    # away would leave the hole open; the faired fill's 3 rings hold none: it is written.
    # In workers too: forked ones cut the hole themselves, else it is cut here and sent
    from surfinpaint.fill import parallel

    monkeypatch.setattr(parallel, "MIN_PARALLEL_EDGES", {"fair": 0, "conformal": 0})
    v, f, sv, sf, sliver = _sliver_rings_away(6, n_holes=3)
    result, said = _fill(sv, sf, method="conformal") if workers == "none" else (None, [])
    if workers != "none":
        from surfinpaint.fill import pipeline

        monkeypatch.setattr(parallel.threading, "active_count",
                            lambda: 1 if workers == "forked" else 2)
        runs = []
        spread = pipeline.fill_in_parallel
        monkeypatch.setattr(pipeline, "fill_in_parallel",
                            lambda *a: (runs.append(parallel.forks()), spread(*a)))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = fill_holes(sv, sf, method="conformal", jobs=2)
        said = [str(w.message) for w in caught]
        assert runs == [workers == "forked"]
        serial, _ = _fill(sv, sf, method="conformal")
        np.testing.assert_array_equal(result.vertices, serial.vertices)
        np.testing.assert_array_equal(result.faces, serial.faces)
    first = result.reports[0]
    assert first.outcome == "faired" and first.fallback.startswith(
        f"not tried: 1 face of zero area (collinear or coincident corners) lies in the rings "
        f"it and its self-check use: {sliver} ")
    assert f"hole 0: conformal fill failed ({first.fallback}); used the faired fill (order 2) "\
        "instead" in said
    # the faired fill's, bit for bit
    fair = fill_holes(sv, sf, holes=[first.loop], method="fair", jobs=1)
    np.testing.assert_array_equal(
        result.vertices[len(sv):len(sv) + first.new_vertices], fair.vertices[len(sv):])
    assert all(not r.skipped for r in result.reports)


@pytest.mark.parametrize("method", ["fair", "conformal"])
def test_a_zero_area_face_within_the_faired_fills_rings_leaves_the_hole_open(method):
    v, f, sv, sf, sliver = _sliver_rings_away(2)
    with pytest.warns(HoleWarning, match=rf"hole 0: 1 face of zero area .*: {sliver} "):
        result = fill_holes(sv, sf, method=method, jobs=1)
    assert result.reports[0].skipped and len(result.faces) == len(sf)


def test_the_commands_take_a_mesh_with_degenerate_faces(tmp_path, capsys):
    v, f, far = _holed()
    at = int(np.flatnonzero((f == far).any(axis=1))[0])
    sv, sf, sliver = _sliver(v, f, at)
    odd = np.insert(sf, 3, [[0, 0, 1]], axis=0)
    source = tmp_path / "odd.ply"
    write_mesh(source, sv, odd)
    before = source.read_bytes()
    assert main(["holes", str(source)]) == 0
    out = capsys.readouterr()
    assert "1 face uses the same vertex twice" in out.err and "zero area" in out.err
    assert out.out.count("│ hole") == 1  # one hole, none invented
    target = tmp_path / "filled.ply"
    assert main(["fill", str(source), "-o", str(target), "--method", "fair"]) == 0
    err = capsys.readouterr().err
    assert err.count("same vertex twice") == 1 and err.count("zero area (collinear") == 1
    got_v, got_f = read_mesh(target)
    np.testing.assert_array_equal(got_v[:len(sv)], sv)
    np.testing.assert_array_equal(got_f[:len(odd)], odd)
    assert len(got_f) > len(odd)
    assert source.read_bytes() == before


@pytest.mark.skipif(not (ASSIMP / "regr01.obj").is_file(), reason="assimp-testmodels")
def test_assimps_regr01_with_four_zero_area_faces_is_filled(tmp_path, capsys):
    # refused whole before ("4 faces have zero area"); removing the faces left 4 slit holes
    source = ASSIMP / "regr01.obj"
    target = tmp_path / "regr01.obj"
    assert main(["fill", str(source), "-o", str(target), "--method", "fair", "-q"]) == 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        v, f = read_mesh(source)
        got_v, got_f = read_mesh(target)
    np.testing.assert_array_equal(got_v[:len(v)], v)
    np.testing.assert_array_equal(got_f[:len(f)], f)
    flat = validate_mesh(v, f).zero_area_faces
    assert flat.tolist() == [1287, 1313, 1415, 1441]
    result, said = _fill(v, f, method="fair")
    assert len(result.reports) == len(find_holes(v, f)) - sum(
        h.is_border for h in find_holes(v, f))
    assert sum("have zero area" in s for s in said) == 1


def test_report_skips_a_hole_beside_a_zero_area_face_unless_it_is_named(tmp_path, capsys):
    # `report` named every hole to its fills, so a hole the faired fill cannot reach without
    # a zero-area face stopped the whole report; now, as `fill`, it is skipped with a warning
    # unless the user named it with --holes
    v, f, sv, sf, sliver = _sliver_rings_away(2, n_holes=2)
    source = tmp_path / "sliver.ply"
    write_mesh(source, sv, sf)
    out_dir = tmp_path / "report"
    assert main(["report", str(source), "-o", str(out_dir)]) == 0
    out = capsys.readouterr()
    out = out.out + out.err
    said = f"hole 0: 1 face of zero area (collinear or coincident corners) lies in the " \
           f"neighbourhood its fill uses: {sliver} "
    # the hole's title says it, as `fill`'s hole line does; not again as a warning (session
    # 39: the warnings printed as `fill` prints them)
    assert "undefined; skipped" not in out
    assert f"hole 0, 12 boundary edges, diameter 0.313; nothing is written: {said[8:]}" in out
    assert "hole 1, 12 boundary edges, diameter 0.313; the λ-H fill (C) is written" in out
    page = (out_dir / "index.md").read_text()
    assert (out_dir / "hole1.png").is_file() and "| 1 | 12 | 0.313 | 4, " in page
    assert f"| 0 | 12 | 0.313 | 0, 0.00 | 0, 0.00 | skipped: {said[8:]}" in page
    assert f"- {said}" in page  # under "Warnings"
    # with -q, no titles: the warning, named
    assert main(["report", str(source), "-o", str(out_dir), "-q"]) == 0
    err = capsys.readouterr().err
    assert f"warning: {source}: {said}" in err and "undefined; skipped" in err
    # named: an error naming the hole and the face, nothing written
    named = tmp_path / "named"
    assert main(["report", str(source), "-o", str(named), "--holes", "0", "-q"]) == 1
    err = capsys.readouterr().err
    assert f"error: {source}: {said}" in err and "is skipped with a warning" in err
    assert not (named / "index.html").exists()
    # the other hole named alone is reported
    assert main(["report", str(source), "-o", str(named), "--holes", "1", "-q"]) == 0
    assert main(["report", str(source), "-o", str(named), "--holes", "1"]) == 0
    assert "index.html and 1 panel\n" in capsys.readouterr().err  # not '1 panels'


def _stray_triangle(corners):
    """The holed sphere with a stray component: one zero-area triangle at ``corners``."""
    v, f, _ = _holed(2)
    n = len(v)
    return np.vstack([v, corners]), np.vstack([f, [[n, n + 1, n + 2]]])


STRAY = {"collinear": [[3, 0, 0], [3.5, 0, 0], [4, 0, 0]],
         "coincident": [[3, 0, 0], [4, 0, 0], [3, 0, 0]]}


@pytest.mark.parametrize("zip_seams", [False, True])
@pytest.mark.parametrize("corners", sorted(STRAY))
def test_a_stray_zero_area_triangle_spans_no_area_and_is_left_open(corners, zip_seams):
    # it was a 3-edge "hole", skipped as a T-junction slit (collinear) or a seam that
    # --zip-seams "closes" (coincident corners), which zipping could not
    from surfinpaint.fill.seams import NO_AREA_FACES, SlitWarning

    v, f = _stray_triangle(STRAY[corners])
    holes = find_holes(v, f)
    assert [h.spans_no_area for h in holes] == [False, True]
    assert not holes[1].is_border
    with pytest.warns(SlitWarning, match=re.escape(f"hole 1: {NO_AREA_FACES}; skipped")):
        result = fill_holes(v, f, method="fair", jobs=1, zip_seams=zip_seams)
    stray = result.reports[1]
    assert stray.skipped == NO_AREA_FACES and stray.method == "none" and not stray.failed
    assert not result.reports[0].skipped and len(result.merged_vertices) == 0
    np.testing.assert_array_equal(result.vertices[:len(v)], v)
    np.testing.assert_array_equal(result.faces[:len(f)], f)
    # named, it is left open all the same (as a slit is): no fill attempt, no error
    with pytest.warns(SlitWarning):
        named = fill_holes(v, f, holes=[1], method="fair", jobs=1)
    assert named.reports[0].skipped == NO_AREA_FACES and len(named.faces) == len(f)


def test_the_commands_list_and_leave_open_a_stray_zero_area_triangle(tmp_path, capsys):
    v, f = _stray_triangle(STRAY["collinear"])
    source = tmp_path / "stray.ply"
    write_mesh(source, v, f)
    assert main(["holes", str(source)]) == 0
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("│")]
    assert rows[0].rstrip(" │").endswith("│ hole") and "spans no area" in rows[1]
    assert main(["fill", str(source), "-o", str(tmp_path / "out.ply"), "--method", "fair"]
                ) == 0
    out = capsys.readouterr()
    out = out.out + out.err
    assert "hole 1: 3 boundary edges" in out and "skipped: the loop spans no area: every " \
        "face of its piece of surface has zero area" in out
    assert "T-junction" not in out
    out_dir = tmp_path / "report"
    assert main(["report", str(source), "-o", str(out_dir)]) == 0  # -q: no hole lines
    out = capsys.readouterr()
    out = out.out + out.err
    assert "hole 1, 3 boundary edges, diameter 1; nothing is written: the loop spans no area" \
        in out


def test_a_thin_triangle_with_area_does_not_span_no_area():
    # the faces decide, not the loop's shape: a needle triangle of a small but real area
    # (its loop spans under 1 % of its perimeter squared: its faces are looked at) is a surface
    v, f = _stray_triangle([[3, 0, 0], [4, 0, 0], [3.5, 1e-4, 0]])
    found = find_holes(v, f)
    assert found[1].n_edges == 3 and found[1].is_border and not found[1].spans_no_area
    v, f = _stray_triangle(STRAY["collinear"])
    assert find_holes(v, f)[1].spans_no_area


@pytest.mark.skipif(not (ASSIMP / "spider.obj").is_file(), reason="assimp-testmodels")
@pytest.mark.parametrize("command", ["holes", "fill", "report"])
def test_assimps_spider_is_refused_for_its_orientation_saying_what_to_do(command, tmp_path,
                                                                           capsys):
    source = ASSIMP / "spider.obj"
    target = {"fill": ["-o", str(tmp_path / "out.obj")], "report": ["-o", str(tmp_path)]}
    args = [command, str(source), *target.get(command, []), *(["-q"] if command in target else [])]
    assert main(args) == 1
    err = capsys.readouterr().err
    assert f"error: {source}: inconsistent face orientation: 10 shared edges" in err
    assert "(568, 551) in faces 1096 and 1097" in err
    assert "trimesh.repair.fix_winding" in err
    assert "--repair (repair=True) reorients each piece consistently, flipping 4 faces" in err
