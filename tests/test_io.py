"""Mesh file I/O: exact round trips in file order, polygon handling, bad files, atomic writes."""

from __future__ import annotations

import gzip
import hashlib
import importlib.resources
import os
import struct
import warnings

import numpy as np
import pytest
from conftest import grid_mesh

from surfinpaint.errors import MeshError
from surfinpaint.geometry.validation import validate_mesh
from surfinpaint.io import formats as mio
from surfinpaint.io.formats import SUPPORTED_FORMATS, MeshWarning, read_mesh, write_mesh

# name -> (write kwargs, stores float64 exactly)
EXACT = {"m.ply": {}, "m_ascii.ply": {"ascii": True}, "m.obj": {}, "m.off": {}}
FLOAT32 = {"m.gii": {}, "m.gii.gz": {}, "lh.pial": {}, "rh.white": {}, "m.inflated": {},
           "m.sphere": {}, "m.orig": {}, "m.smoothwm": {}}


def _f32(v: np.ndarray) -> np.ndarray:
    return v.astype(np.float32).astype(np.float64)


def _sha(path) -> str:
    return hashlib.sha256(open(path, "rb").read()).hexdigest()


# --------------------------------------------------------------------------- round trips


@pytest.mark.parametrize("name", list(EXACT))
def test_round_trip_exact_keeps_order_values_and_unreferenced(tmp_path, shuffled, name):
    v, f = shuffled
    path = tmp_path / name
    write_mesh(path, v, f, **EXACT[name])
    v2, f2 = read_mesh(path)
    assert v2.dtype == np.float64 and f2.dtype == np.int64
    assert v2.flags.writeable and f2.flags.writeable  # not views of the read buffer
    np.testing.assert_array_equal(v2, v)  # bit-exact
    np.testing.assert_array_equal(f2, f)
    assert np.signbit(v).sum() > 0
    np.testing.assert_array_equal(np.signbit(v2), np.signbit(v))  # even -0.0 survives


@pytest.mark.parametrize("name", list(FLOAT32))
def test_round_trip_float32_formats(tmp_path, shuffled, name):
    v, f = shuffled
    path = tmp_path / name
    write_mesh(path, v, f)
    v2, f2 = read_mesh(path)
    assert v2.shape == v.shape and f2.dtype == np.int64
    np.testing.assert_array_equal(v2, _f32(v))  # exactly the float32 rounding, same order
    np.testing.assert_array_equal(f2, f)


def test_gii_gz_is_gzip_and_freesurfer_has_magic(tmp_path, shuffled):
    v, f = shuffled
    write_mesh(tmp_path / "s.gii.gz", v, f)
    write_mesh(tmp_path / "lh.pial", v, f)
    raw = (tmp_path / "s.gii.gz").read_bytes()
    assert raw[:2] == b"\x1f\x8b" and b"<GIFTI" in gzip.decompress(raw)
    assert (tmp_path / "lh.pial").read_bytes()[:3] == b"\xff\xff\xfe"


def test_freesurfer_detected_by_magic_whatever_the_name(tmp_path, shuffled):
    v, f = shuffled
    write_mesh(tmp_path / "lh.pial", v, f)
    os.replace(tmp_path / "lh.pial", tmp_path / "lh.sphere.reg")
    v2, f2 = read_mesh(tmp_path / "lh.sphere.reg")
    np.testing.assert_array_equal(v2, _f32(v))
    np.testing.assert_array_equal(f2, f)


def test_stl_round_trip_when_numbering_is_storable(tmp_path):
    v, f = grid_mesh(3, 2)  # vertices first used in id order, all referenced
    _, first = np.unique(f.ravel(), return_index=True)
    assert not np.array_equal(f.ravel()[np.sort(first)], np.arange(len(v)))
    # renumber by first use so an STL can carry the numbering
    order = f.ravel()[np.sort(first)]
    new = np.empty(len(v), dtype=np.int64)
    new[order] = np.arange(len(v))
    v, f = v[order], new[f]
    v = v + 1e-3 * np.arange(v.size).reshape(v.shape) / 7
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        write_mesh(tmp_path / "g.stl", v, f)
    v2, f2 = read_mesh(tmp_path / "g.stl")
    np.testing.assert_array_equal(v2, _f32(v))
    np.testing.assert_array_equal(f2, f)


def test_stl_merges_soup_by_first_occurrence_and_warns_on_lost_numbering(tmp_path, shuffled):
    v, f = shuffled
    with pytest.warns(MeshWarning, match=r"s\.stl.*2 unreferenced"):
        write_mesh(tmp_path / "s.stl", v, f)
    v2, f2 = read_mesh(tmp_path / "s.stl")
    used = np.unique(f)
    assert len(v2) == len(used)  # equal corners merged, nothing duplicated
    np.testing.assert_array_equal(v2[f2], _f32(v)[f])  # the same triangles, in order
    # numbered by first occurrence
    _, first = np.unique(f2.ravel(), return_index=True)
    np.testing.assert_array_equal(f2.ravel()[np.sort(first)], np.arange(len(v2)))


def test_ascii_stl(tmp_path):
    text = """solid t
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 1 0 0
  vertex 0 1 0
 endloop
endfacet
facet normal 0 0 1
 outer loop
  vertex 1 0 0
  vertex 1 1 0.5
  vertex 0 1 0
 endloop
endfacet
endsolid t
"""
    (tmp_path / "a.stl").write_text(text)
    v, f = read_mesh(tmp_path / "a.stl")
    np.testing.assert_array_equal(v, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.5]])
    np.testing.assert_array_equal(f, [[0, 1, 2], [1, 3, 2]])


def test_write_does_not_modify_arrays(tmp_path, shuffled):
    v, f = shuffled
    v0, f0 = v.copy(), f.copy()
    for name in ["a.ply", "a.obj", "a.off", "a.gii", "lh.white"]:
        write_mesh(tmp_path / name, v, f)
    np.testing.assert_array_equal(v, v0)
    np.testing.assert_array_equal(f, f0)


def test_reading_leaves_file_bytes_unchanged(tmp_path, shuffled):
    v, f = shuffled
    for name in [*EXACT, *FLOAT32]:
        path = tmp_path / name
        write_mesh(path, v, f, **EXACT.get(name, {}))
        before, mtime = _sha(path), path.stat().st_mtime_ns
        read_mesh(path)
        assert _sha(path) == before and path.stat().st_mtime_ns == mtime


# ------------------------------------------------------- hand-written files, unusual order

OBJ_UNUSUAL = """# vertices deliberately out of spatial order; v 3 is used by no face
v 3 0 0
v 0 0 0
v 9 9 9
vt 0 0
vt 1 0
vt 0 1
vt 0.5 0.5
vn 0 0 1
v 0 3 0
v 3 3 0
f 2/1/1 1/2/1 5/4/1 4/3/1
f 1/1 2/2 4/3
  f -4//1 -5//1 -2//1
f 5 1 2 # comment
"""


def test_obj_unusual_order_seams_negative_indices_and_quads(tmp_path):
    path = tmp_path / "u.obj"
    path.write_text(OBJ_UNUSUAL)
    with pytest.warns(MeshWarning, match=r"u\.obj: 1 polygon"):
        v, f = read_mesh(path)
    np.testing.assert_array_equal(v, [[3, 0, 0], [0, 0, 0], [9, 9, 9], [0, 3, 0], [3, 3, 0]])
    # the quad becomes a fan in place; uv seams never split vertices; -4 is vertex 1
    np.testing.assert_array_equal(f, [[1, 0, 4], [1, 4, 3], [0, 1, 3], [1, 0, 3], [4, 0, 1]])


def test_obj_negative_normal_ids_after_an_unused_uv_record(tmp_path):
    # the vt records' warning once shadowed the record list the vn ids are resolved with:
    # a negative vn id after an unused vt record was refused ("not enough values to unpack")
    path = tmp_path / "n.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                    "vt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n"
                    "vn 0 0 1\nvn 0 1 0\nvn 1 0 0\n"
                    "f 1/1/-3 2/2/-3 3/3/-3\nf 1/1/-2 3/3/-2 4/2/-1\n")
    # (the count and its verbs agree: "1 of 4 vt records is not referenced ... and is not kept")
    with pytest.warns(MeshWarning, match="1 of 4 vt records is not referenced by any face and "
                                         "is not kept"):
        mesh = mio.read_mesh_data(path)
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [0, 2, 3]])
    normals = mesh.corner_attributes.get("normal")
    if normals is None:  # one normal a vertex: kept per vertex
        normals = mesh.attributes["normal"][mesh.faces]
    np.testing.assert_array_equal(normals, [[[0, 0, 1]] * 3, [[0, 1, 0], [0, 1, 0], [1, 0, 0]]])


def test_off_with_comments_colours_and_polygons(tmp_path):
    path = tmp_path / "u.off"
    path.write_text("""COFF # header comment
# counts next
5 3 0
3 0 0 255 0 0 255
0 0 0 255 0 0 255
9 9 9 0 0 0 0
0 3 0 1 1 1 1

3 3 0 1 1 1 1
4 1 0 4 3  0.5 0.5 0.5
3 0 1 3
5 4 3 2 1 0
""")
    with pytest.warns(MeshWarning, match=r"u\.off: 2 polygon"):
        v, f = read_mesh(path)
    np.testing.assert_array_equal(v, [[3, 0, 0], [0, 0, 0], [9, 9, 9], [0, 3, 0], [3, 3, 0]])
    np.testing.assert_array_equal(f, [[1, 0, 4], [1, 4, 3], [0, 1, 3],
                                      [4, 3, 2], [4, 2, 1], [4, 1, 0]])


def _ply_binary_mixed(endian: str) -> bytes:
    e = "<" if endian == "little" else ">"
    header = (f"ply\nformat binary_{endian}_endian 1.0\ncomment mixed\n"
              "element vertex 5\nproperty double x\nproperty float y\nproperty double z\n"
              "property uchar red\nelement face 3\nproperty list uchar int vertex_indices\n"
              "property uchar flags\nelement edge 1\nproperty int a\nproperty int b\n"
              "end_header\n").encode()
    verts = [(3.1, 0, 0), (0, 0, 0), (9, 9, 9), (0, 3, 0), (3, 3, 0.25)]
    body = b"".join(struct.pack(e + "dfdB", x, y, z, 7) for x, y, z in verts)
    for face in ([1, 0, 4, 3], [0, 1, 3], [0, 1, 2, 3, 4]):
        body += struct.pack(f"{e}B{len(face)}iB", len(face), *face, 1)
    body += struct.pack(e + "ii", 0, 1)
    return header + body


@pytest.mark.parametrize("endian", ["little", "big"])
def test_binary_ply_mixed_polygons(tmp_path, endian):
    path = tmp_path / "mixed.ply"
    path.write_bytes(_ply_binary_mixed(endian))
    with pytest.warns(MeshWarning, match=r"mixed\.ply: 2 polygon"):
        v, f = read_mesh(path)
    np.testing.assert_array_equal(v, [[3.1, 0, 0], [0, 0, 0], [9, 9, 9], [0, 3, 0],
                                      [3, 3, 0.25]])
    np.testing.assert_array_equal(f, [[1, 0, 4], [1, 4, 3], [0, 1, 3],
                                      [0, 1, 2], [0, 2, 3], [0, 3, 4]])


def test_ascii_ply_extra_properties_and_mixed_polygons(tmp_path):
    path = tmp_path / "a.ply"
    path.write_text("""ply
format ascii 1.0
element vertex 5
property float x
property float y
property float z
property uchar red
element face 3
property list uchar int vertex_indices
end_header
3 0 0 1
0 0 0 1
9 9 9 1
0 3 0 1
3 3 0 1
4 1 0 4 3
3 0 1 3
3 4 3 2
""")
    with pytest.warns(MeshWarning, match="1 polygon"):
        v, f = read_mesh(path)
    np.testing.assert_array_equal(v[[0, 2, 4]], [[3, 0, 0], [9, 9, 9], [3, 3, 0]])
    np.testing.assert_array_equal(f, [[1, 0, 4], [1, 4, 3], [0, 1, 3], [4, 3, 2]])


def test_triangles_only_do_not_warn(tmp_path, shuffled):
    v, f = shuffled
    write_mesh(tmp_path / "t.obj", v, f)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        read_mesh(tmp_path / "t.obj")


# ------------------------------------------------------------------------- bad input


def _raises(path, *fragments):
    with pytest.raises(MeshError) as info:
        read_mesh(path)
    text = str(info.value)
    assert str(path) in text
    for fragment in fragments:
        assert fragment in text, text
    assert "Traceback" not in text
    # chained exceptions are hidden so users see one clear message
    err = info.value
    assert err.__cause__ is None and (err.__context__ is None or err.__suppress_context__)
    return info.value


def test_missing_file(tmp_path):
    err = _raises(tmp_path / "nope.ply", "no such file")
    # a MeshError (the CLI's message and exit code) that FileNotFoundError catches too
    assert isinstance(err, FileNotFoundError) and err.filename == str(tmp_path / "nope.ply")
    with pytest.raises(FileNotFoundError, match="nope.gii: no such file"):
        mio.read_mesh_data(tmp_path / "nope.gii")
    assert isinstance(err.with_path("other.ply"), FileNotFoundError)


def test_directory(tmp_path):
    (tmp_path / "d.obj").mkdir()
    _raises(tmp_path / "d.obj", "directory")


@pytest.mark.skipif(hasattr(os, "geteuid") and os.geteuid() == 0, reason="root reads anything")
def test_unreadable_file(tmp_path, shuffled):
    path = tmp_path / "locked.obj"
    write_mesh(path, *shuffled)
    path.chmod(0)
    try:
        _raises(path, "permission denied")
    finally:
        path.chmod(0o644)


def test_permission_error_is_reported(tmp_path, shuffled, monkeypatch):
    path = tmp_path / "locked.ply"
    write_mesh(path, *shuffled)

    def denied(self, *args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(type(path), "open", denied)  # Path.read_bytes opens it so too
    _raises(path, "permission denied")


@pytest.mark.parametrize("name", ["e.ply", "e.obj", "e.stl", "e.off", "e.gii", "lh.pial"])
def test_empty_file(tmp_path, name):
    (tmp_path / name).write_bytes(b"")
    _raises(tmp_path / name, "empty")


def test_unknown_extension_lists_supported(tmp_path):
    (tmp_path / "m.xyz").write_text("1 2 3\n")
    err = _raises(tmp_path / "m.xyz", "unknown mesh format", "'.xyz'")
    for ext in SUPPORTED_FORMATS:
        assert ext in str(err)


ALL_NAMES = ["m.ply", "m_ascii.ply", "m.obj", "m.off", "m.stl", "m.gii", "m.gii.gz", "lh.pial"]


@pytest.mark.parametrize("name", ALL_NAMES)
def test_truncated_files(tmp_path, name):
    v, f = grid_mesh(6, 5)
    path = tmp_path / name
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MeshWarning)  # STL renumbering
        write_mesh(path, v, f, ascii=name == "m_ascii.ply")
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    _raises(path)


@pytest.mark.parametrize("name", ALL_NAMES)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_bytes(tmp_path, name, seed):
    path = tmp_path / name
    path.write_bytes(np.random.default_rng(seed).bytes(2000))
    _raises(path)


def test_random_bytes_with_plausible_headers(tmp_path):
    noise = np.random.default_rng(3).bytes(500)
    cases = {"h.ply": b"ply\nformat binary_little_endian 1.0\nelement vertex 100\n"
                      b"property float x\nproperty float y\nproperty float z\nelement face 50\n"
                      b"property list uchar int vertex_indices\nend_header\n" + noise,
             "h.stl": b"solid x\n" + noise, "h.off": b"OFF\n" + noise,
             "h.gii": b"<?xml version='1.0'?><GIFTI>" + noise,
             "h.pial": b"\xff\xff\xfecreated\n\n" + noise}
    for name, data in cases.items():
        (tmp_path / name).write_bytes(data)
        _raises(tmp_path / name)


def test_no_faces(tmp_path):
    (tmp_path / "p.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n")
    _raises(tmp_path / "p.obj", "no faces")
    (tmp_path / "p.off").write_text("OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n")
    _raises(tmp_path / "p.off", "no faces")
    (tmp_path / "p.ply").write_text("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                    "property float y\nproperty float z\nend_header\n0 0 0\n")
    _raises(tmp_path / "p.ply", "no face element")


def test_no_vertices(tmp_path):
    (tmp_path / "c.obj").write_text("# only a comment\n")
    _raises(tmp_path / "c.obj", "no vertices")
    (tmp_path / "c.off").write_text("OFF\n0 0 0\n")
    _raises(tmp_path / "c.off", "no vertices")


def test_out_of_range_and_negative_indices_name_faces(tmp_path):
    (tmp_path / "r.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\nf 1 9 3\n")
    err = _raises(tmp_path / "r.obj", "face 1 (line 5) uses vertex index 7, past the file's 3 "
                  "vertices; 2 faces do: 1, 2")
    assert err.faces == [1, 2]
    (tmp_path / "r.off").write_text("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 -1 2\n")
    err = _raises(tmp_path / "r.off", "negative", "1")
    assert err.faces == [1]
    (tmp_path / "n.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n")
    _raises(tmp_path / "n.obj", "face 0 (line 4) uses vertex index -4, a negative index past "
            "the first vertex (it counts back from the 3 vertices before the face)")


def test_nan_and_inf_name_vertices(tmp_path):
    (tmp_path / "nan.obj").write_text(
        "v 0 0 0\nv 1 nan 0\nv 0 1 0\nv 0 0 inf\nf 1 2 3\nf 1 3 4\n")
    err = _raises(tmp_path / "nan.obj", "NaN or infinite", "1, 3")
    assert err.vertices == [1, 3]


def test_non_numeric_obj_coordinate(tmp_path):
    (tmp_path / "x.obj").write_text("v 0 0 zero\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    _raises(tmp_path / "x.obj", "non-numeric")


def test_short_vertex_line_is_not_misaligned(tmp_path):
    # 2 + 4 coordinates add up to 2 x 3: must not be read as two good vertices
    (tmp_path / "s.obj").write_text("v 1 2\nv 1 2 3 1\nv 0 0 1\nf 1 2 3\n")
    _raises(tmp_path / "s.obj", "vertex 0 has fewer than three coordinates")


def test_obj_w_column_and_trailing_comments(tmp_path):
    (tmp_path / "w.obj").write_text("v 1 2 3 1.0\nv 4 5 6 # c\nv 7 8 9.5\nf 1 2 3\n")
    v, f = read_mesh(tmp_path / "w.obj")
    np.testing.assert_array_equal(v, [[1, 2, 3], [4, 5, 6], [7, 8, 9.5]])


def test_degenerate_polygon_is_rejected(tmp_path):
    (tmp_path / "d.off").write_text("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n2 0 1\n")
    _raises(tmp_path / "d.off", "fewer than three corners", "1")


# ------------------------------------------------------------------------ atomic writes


def test_unknown_extension_on_write_creates_nothing(tmp_path, shuffled):
    with pytest.raises(MeshError, match=r"m\.xyz.*unknown mesh format.*\.ply"):
        write_mesh(tmp_path / "m.xyz", *shuffled)
    assert list(tmp_path.iterdir()) == []


def test_missing_directory_on_write(tmp_path, shuffled):
    target = tmp_path / "no" / "such" / "m.ply"
    with pytest.raises(MeshError, match="does not exist"):
        write_mesh(target, *shuffled)
    assert list(tmp_path.iterdir()) == []


def test_bad_arrays_on_write_create_nothing(tmp_path, shuffled):
    v, f = shuffled
    bad = v.copy()
    bad[4, 1] = np.nan
    with pytest.raises(MeshError, match=r"m\.ply.*NaN.*: 4"):
        write_mesh(tmp_path / "m.ply", bad, f)
    with pytest.raises(MeshError, match="faces use vertex ids"):
        write_mesh(tmp_path / "m.ply", v, f + len(v))
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("exc", [OSError("disk full"), KeyboardInterrupt()])
def test_failure_mid_write_leaves_old_file_and_no_temp(tmp_path, shuffled, monkeypatch, exc):
    v, f = shuffled
    target = tmp_path / "m.ply"
    write_mesh(target, v, f)
    before = _sha(target)

    def half_then_fail(fh, tmp, mesh, ascii):
        fh.write(b"ply\nformat ascii 1.0\n")
        fh.flush()
        raise exc

    monkeypatch.setitem(mio._WRITERS, "ply", half_then_fail)
    with pytest.raises(type(exc) if isinstance(exc, KeyboardInterrupt) else MeshError):
        write_mesh(target, 2 * v, f)
    assert [p.name for p in tmp_path.iterdir()] == ["m.ply"]
    assert _sha(target) == before


def test_failure_mid_write_of_new_file_leaves_nothing(tmp_path, shuffled, monkeypatch):
    def fail(fh, tmp, mesh, ascii):
        fh.write(b"OFF\n12 ")
        raise RuntimeError("injected")

    monkeypatch.setitem(mio._WRITERS, "off", fail)
    with pytest.raises(MeshError, match=r"n\.off: writing failed: RuntimeError: injected"):
        write_mesh(tmp_path / "n.off", *shuffled)
    assert list(tmp_path.iterdir()) == []


def test_written_file_has_normal_permissions(tmp_path, shuffled):
    write_mesh(tmp_path / "m.obj", *shuffled)
    umask = os.umask(0)
    os.umask(umask)
    assert (tmp_path / "m.obj").stat().st_mode & 0o777 == 0o666 & ~umask


def test_overwrite_replaces_content(tmp_path, shuffled):
    v, f = shuffled
    write_mesh(tmp_path / "m.off", v, f)
    write_mesh(tmp_path / "m.off", v + 1, f)
    np.testing.assert_array_equal(read_mesh(tmp_path / "m.off")[0], v + 1)
    assert [p.name for p in tmp_path.iterdir()] == ["m.off"]


# ------------------------------------------------------------- real data from packages


def _packaged(package: str, relative: str):
    pytest.importorskip(package)
    path = importlib.resources.files(package) / relative
    if not path.is_file():
        pytest.skip(f"{package} does not ship {relative}")
    return path


def test_pymeshlab_bunny_obj():
    path = _packaged("pymeshlab", "tests/sample_meshes/bunny.obj")
    v, f = read_mesh(path)
    # the header comment announces the counts
    assert (len(v), len(f)) == (28088, 56172)
    report = validate_mesh(v, f, path=str(path))
    assert report.n_components == 1 and report.is_closed
    assert report.euler_characteristic == 2 and report.unreferenced_vertices.size == 0


def test_pymeshfix_bunny_ply_is_read_and_its_defects_named():
    path = _packaged("pymeshfix", "examples/StanfordBunny.ply")
    v, f = read_mesh(path)
    assert (len(v), len(f)) == (50000, 99785)  # the header's element counts
    # an all-triangle binary PLY, which trimesh also reads in file order
    trimesh = pytest.importorskip("trimesh")
    other = trimesh.load(path, process=False)
    np.testing.assert_array_equal(v, other.vertices)
    np.testing.assert_array_equal(f, other.faces)
    # this example is pymeshfix's broken input: it has non-manifold edges, named by id
    with pytest.raises(MeshError, match=r"StanfordBunny\.ply: 132 non-manifold edges") as info:
        validate_mesh(v, f, path=str(path))
    assert len(info.value.edges) == 100


def test_nilearn_fsaverage5_gifti_gz():
    path = _packaged("nilearn", "datasets/data/fsaverage5/pial_left.gii.gz")
    v, f = read_mesh(path)
    assert (len(v), len(f)) == (10242, 20480)  # icosahedron order 5
    report = validate_mesh(v, f, path=str(path))
    assert report.is_closed and report.euler_characteristic == 2
    assert report.n_components == 1
    # a pial surface spans roughly 70 x 110 x 80 mm
    assert np.all((np.ptp(v, axis=0) > 50) & (np.ptp(v, axis=0) < 250))


@pytest.mark.parametrize("suffix", [".ply", ".obj", ".off", ".stl"])
def test_triangle_faces_read_are_our_own_writable_int64_array(tmp_path, suffix):
    # all-triangle files take the faces straight from the parsed list (no gathered copy):
    # they must still be a fresh, writable (f, 3) int64 array, equal to what was written
    v, f = grid_mesh(4, 3)
    path = tmp_path / f"grid{suffix}"
    write_mesh(path, v, f)
    _, g = read_mesh(path)
    assert g.dtype == np.int64 and g.shape == f.shape and g.flags.writeable
    if suffix != ".stl":  # STL stores corners, not shared vertex ids
        np.testing.assert_array_equal(g, f)
    g[0] = g[1]
    assert not np.array_equal(read_mesh(path)[1][0], g[0])
