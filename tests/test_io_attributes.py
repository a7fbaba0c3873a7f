"""Per-vertex, per-face and per-corner data in and out of files (issue 16, the I/O half):
round trips bit-identical on the original vertices, nothing dropped without a MeshWarning."""

from __future__ import annotations

import json
import os
import struct
import warnings

import numpy as np
import pytest
from conftest import grid_mesh

from surfinpaint.errors import MeshError
from surfinpaint.io import (
    DataNotReturnedWarning,
    MeshData,
    MeshWarning,
    read_mesh,
    read_mesh_data,
    write_mesh,
    write_mesh_data,
)
from surfinpaint.io.formats import files_read

# PLY type name, numpy type, values that need the type's whole range
PLY_TYPES = [("char", "i1"), ("uchar", "u1"), ("short", "i2"), ("ushort", "u2"),
             ("int", "i4"), ("uint", "u4"), ("float", "f4"), ("double", "f8")]


def _extremes(t: str, n: int, rng) -> np.ndarray:
    dt = np.dtype(t)
    if dt.kind == "f":
        return (rng.standard_normal(n) * 10.0 ** rng.integers(-30, 30, n)).astype(dt)
    info = np.iinfo(dt)
    a = rng.integers(info.min, info.max, n, endpoint=True, dtype=np.int64).astype(dt)
    a[:2] = info.min, info.max
    return a


def _ply_with_every_type(endian: str | None):
    """A PLY built by hand: every scalar type on vertices and faces, colours rgba, normals,
    s t, quality, a per-corner texcoord list; binary (endian) or ascii (None)."""
    rng = np.random.default_rng(7)
    v, f = grid_mesh(4, 3)
    n, m = len(v), len(f)
    vprops = {"x": v[:, 0].astype("f4"), "y": v[:, 1].astype("f4"), "z": v[:, 2].astype("f4")}
    vprops.update({"red": rng.integers(0, 256, n).astype("u1"),
                   "green": rng.integers(0, 256, n).astype("u1"),
                   "blue": rng.integers(0, 256, n).astype("u1"),
                   "alpha": rng.integers(0, 256, n).astype("u1"),
                   "nx": rng.standard_normal(n).astype("f4"),
                   "ny": rng.standard_normal(n).astype("f4"),
                   "nz": rng.standard_normal(n).astype("f4"),
                   "s": rng.random(n).astype("f4"), "t": rng.random(n).astype("f4"),
                   "quality": rng.random(n).astype("f8")})
    vprops.update({f"v_{name}": _extremes(t, n, rng) for name, t in PLY_TYPES})
    fprops = {f"f_{name}": _extremes(t, m, rng) for name, t in PLY_TYPES}
    fprops.update({"red": rng.integers(0, 256, m).astype("u1"),
                   "green": rng.integers(0, 256, m).astype("u1"),
                   "blue": rng.integers(0, 256, m).astype("u1")})
    uv = rng.random((n, 2)).astype("f4")
    texcoord = uv[f].reshape(m, 6)  # per corner, one value per vertex
    names = dict(PLY_TYPES)
    tname = {"u1": "uchar", "f4": "float", "f8": "double", **{t: k for k, t in PLY_TYPES}}
    fmt = "ascii" if endian is None else f"binary_{endian}_endian"
    head = ["ply", f"format {fmt} 1.0", "comment every property type", f"element vertex {n}"]
    head += [f"property {tname[a.dtype.str[1:]]} {k}" for k, a in vprops.items()]
    head += [f"element face {m}", "property list uchar int vertex_indices"]
    head += [f"property {tname[a.dtype.str[1:]]} {k}" for k, a in fprops.items()]
    head += ["property list uchar float texcoord", "end_header"]
    blob = ("\n".join(head) + "\n").encode()
    if endian is None:
        def txt(a):
            return repr(float(a)) if a.dtype.kind == "f" else str(int(a))
        for i in range(n):
            blob += (" ".join(txt(a[i]) for a in vprops.values()) + "\n").encode()
        for j in range(m):
            row = ["3", *map(str, f[j])] + [txt(a[j]) for a in fprops.values()]
            row += ["6"] + [repr(float(x)) for x in texcoord[j]]
            blob += (" ".join(row) + "\n").encode()
    else:
        e = "<" if endian == "little" else ">"
        vrec = np.empty(n, [(k, e + a.dtype.str[1:]) for k, a in vprops.items()])
        for k, a in vprops.items():
            vrec[k] = a
        frec = np.empty(m, [("n", "u1"), ("i", e + "i4", (3,))]
                        + [(k, e + a.dtype.str[1:]) for k, a in fprops.items()]
                        + [("tn", "u1"), ("tc", e + "f4", (6,))])
        frec["n"], frec["i"], frec["tn"], frec["tc"] = 3, f, 6, texcoord
        for k, a in fprops.items():
            frec[k] = a
        blob += vrec.tobytes() + frec.tobytes()
    assert names  # the table drives both header and data
    return blob, v, f, vprops, fprops, uv


def _check_every_type(mesh: MeshData, v, f, vprops, fprops, uv) -> None:
    np.testing.assert_array_equal(mesh.vertices, v.astype("f4"))
    np.testing.assert_array_equal(mesh.faces, f)
    a = mesh.attributes
    expected = {
        "color": np.column_stack([vprops[k] for k in ("red", "green", "blue", "alpha")]),
        "normal": np.column_stack([vprops[k] for k in ("nx", "ny", "nz")]),
        "st": np.column_stack([vprops["s"], vprops["t"]]),
        "quality": vprops["quality"], "texcoord": uv,
        **{f"v_{name}": vprops[f"v_{name}"] for name, _ in PLY_TYPES},
    }
    assert set(a) == set(expected)
    for key, value in expected.items():
        assert a[key].dtype == value.dtype, key
        np.testing.assert_array_equal(a[key], value, err_msg=key)
    fa = mesh.face_attributes
    expected_f = {"color": np.column_stack([fprops[k] for k in ("red", "green", "blue")]),
                  **{f"f_{name}": fprops[f"f_{name}"] for name, _ in PLY_TYPES}}
    assert set(fa) == set(expected_f)
    for key, value in expected_f.items():
        assert fa[key].dtype == value.dtype, key
        np.testing.assert_array_equal(fa[key], value, err_msg=key)


@pytest.mark.parametrize("endian", ["little", "big", None], ids=["le", "be", "ascii"])
def test_ply_every_property_type_read_and_written_back_bit_identical(tmp_path, endian):
    blob, v, f, vprops, fprops, uv = _ply_with_every_type(endian)
    path = tmp_path / "every.ply"
    path.write_bytes(blob)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # everything is carried: no warning
        mesh = read_mesh_data(path)
    _check_every_type(mesh, v, f, vprops, fprops, uv)
    assert mesh.metadata["comments"] == "comment every property type"
    for ascii in (False, True):
        out = tmp_path / f"out_{ascii}.ply"
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            write_mesh_data(out, mesh, ascii=ascii)
            again = read_mesh_data(out)
        _check_every_type(again, v, f, vprops, fprops, uv)
        assert again.metadata == mesh.metadata
        # writing what was read gives the same file again
        write_mesh_data(tmp_path / "twice.ply", again, ascii=ascii)
        assert (tmp_path / "twice.ply").read_bytes() == out.read_bytes()


def test_read_mesh_keeps_its_pair_and_names_what_it_does_not_return(tmp_path):
    blob, v, f, *_ = _ply_with_every_type("little")
    path = tmp_path / "every.ply"
    path.write_bytes(blob)
    with pytest.warns(MeshWarning, match=r"every\.ply: per-vertex color, normal, st, .*; per-face "
                                         r"f_char.*, color not returned by read_mesh"):
        got_v, got_f = read_mesh(path)
    np.testing.assert_array_equal(got_f, f)
    mesh = read_mesh_data(path)
    vertices, faces = mesh  # unpacks like read_mesh
    np.testing.assert_array_equal(vertices, got_v)


def test_read_mesh_without_the_data_warning_keeps_the_others(tmp_path):
    blob, v, f, *_ = _ply_with_every_type("little")
    path = tmp_path / "every.ply"
    path.write_bytes(blob)
    # its own category, a MeshWarning, so that a caller that writes no mesh can leave it out
    with pytest.warns(DataNotReturnedWarning):
        loud_v, loud_f = read_mesh(path)
    assert issubclass(DataNotReturnedWarning, MeshWarning)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        quiet_v, quiet_f = read_mesh(path, data_warning=False)
    np.testing.assert_array_equal(quiet_v, loud_v)
    np.testing.assert_array_equal(quiet_f, f)
    # what no reader carries is still said: quads triangulated, with colours
    quads = tmp_path / "quads.ply"
    quads.write_text("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                     "property float y\nproperty float z\nproperty uchar red\n"
                     "property uchar green\nproperty uchar blue\nelement face 1\n"
                     "property list uchar int vertex_indices\nend_header\n"
                     "0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n0 1 0 9 9 9\n"
                     "4 0 1 2 3\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        _, two = read_mesh(quads, data_warning=False)
    assert len(two) == 2
    assert [type(w.message) for w in caught] == [MeshWarning]
    assert "1 polygon face with more than three corners was fan-triangulated" in str(
        caught[0].message)


def test_ply_seam_in_a_corner_list_is_kept_per_corner_with_a_warning(tmp_path):
    v, f = grid_mesh(2, 1)
    corner_uv = np.arange(len(f) * 6, dtype="f4").reshape(len(f), 6) / 10
    head = ("ply\nformat binary_little_endian 1.0\n"
            f"element vertex {len(v)}\nproperty double x\nproperty double y\nproperty double z\n"
            f"element face {len(f)}\nproperty list uchar int vertex_indices\n"
            "property list uchar float texcoord\nend_header\n").encode()
    rec = np.empty(len(f), [("n", "u1"), ("i", "<i4", (3,)), ("tn", "u1"), ("tc", "<f4", (6,))])
    rec["n"], rec["i"], rec["tn"], rec["tc"] = 3, f, 6, corner_uv
    path = tmp_path / "seam.ply"
    path.write_bytes(head + v.astype("<f8").tobytes() + rec.tobytes())
    with pytest.warns(MeshWarning, match=r"texcoord differs between the faces around \d+ "
                                         r"vertices.*kept per face corner"):
        mesh = read_mesh_data(path)
    np.testing.assert_array_equal(mesh.corner_attributes["texcoord"],
                                  corner_uv.reshape(-1, 3, 2))
    write_mesh_data(tmp_path / "seam2.ply", mesh)
    with pytest.warns(MeshWarning, match="seam"):
        again = read_mesh_data(tmp_path / "seam2.ply")
    np.testing.assert_array_equal(again.corner_attributes["texcoord"],
                                  mesh.corner_attributes["texcoord"])


def test_ply_other_elements_and_vertex_lists_are_named_when_dropped(tmp_path):
    path = tmp_path / "x.ply"
    path.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                    "property float y\nproperty float z\nproperty list uchar int friends\n"
                    "element face 1\nproperty list uchar int vertex_indices\n"
                    "element edge 2\nproperty int a\nproperty int b\nend_header\n"
                    "0 0 0 1 1\n1 0 0 0\n0 1 0 2 0 1\n3 0 1 2\n0 1\n1 2\n")
    with pytest.warns(MeshWarning) as record:
        read_mesh_data(path)
    text = " | ".join(str(w.message) for w in record)
    assert "vertex list property 'friends'" in text and "element 'edge' (2 records)" in text


# ------------------------------------------------------------------------------ OBJ


def _obj_text(v, f, uv, normals) -> str:
    """vt and vn listed in reversed order, so per-corner indices differ from vertex ids."""
    n = len(v)
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in v.tolist()]
    lines += [f"vt {a!r} {b!r}" for a, b in uv[::-1].tolist()]
    lines += [f"vn {a!r} {b!r} {c!r}" for a, b, c in normals[::-1].tolist()]
    lines += ["f " + " ".join(f"{i + 1}/{n - i}/{n - i}" for i in face) for face in f]
    return "\n".join(lines) + "\n"


def test_obj_vt_vn_per_vertex_round_trip(tmp_path):
    rng = np.random.default_rng(3)
    v, f = grid_mesh(4, 3)
    uv, normals = rng.random((len(v), 2)), rng.standard_normal((len(v), 3))
    path = tmp_path / "uv.obj"
    path.write_text(_obj_text(v, f, uv, normals))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = read_mesh_data(path)
    np.testing.assert_array_equal(mesh.vertices, v)
    np.testing.assert_array_equal(mesh.attributes["uv"], uv)
    np.testing.assert_array_equal(mesh.attributes["normal"], normals)
    assert mesh.corner_attributes == {}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        write_mesh_data(tmp_path / "out.obj", mesh)
        again = read_mesh_data(tmp_path / "out.obj")
    for key in ("uv", "normal"):
        np.testing.assert_array_equal(again.attributes[key], mesh.attributes[key])
    np.testing.assert_array_equal(again.vertices, v)
    np.testing.assert_array_equal(again.faces, f)


def test_obj_unreferenced_vertex_writes_no_nan_and_its_vt_is_named(tmp_path):
    # a vertex no face uses (left over where faces were cut away): its vt and vn lines are
    # dropped with a warning, and the written file has no `vt nan nan` for it
    rng = np.random.default_rng(5)
    v, f = grid_mesh(4, 3)
    uv, normals = rng.random((len(v), 2)), rng.standard_normal((len(v), 3))
    lonely = int(f[0, 0])
    f = f[~(f == lonely).any(axis=1)]
    path = tmp_path / "cut.obj"
    path.write_text(_obj_text(v, f, uv, normals))
    with pytest.warns(MeshWarning, match=r"1 of 20 vt records is not referenced"):
        mesh = read_mesh_data(path)
    assert np.isnan(mesh.attributes["uv"][lonely]).all()
    write_mesh_data(tmp_path / "out.obj", mesh)
    text = (tmp_path / "out.obj").read_text()
    assert "nan" not in text
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        again = read_mesh_data(tmp_path / "out.obj")
    np.testing.assert_array_equal(again.vertices, v)
    np.testing.assert_array_equal(again.faces, f)
    for key in ("uv", "normal"):
        np.testing.assert_array_equal(again.attributes[key], mesh.attributes[key])


def test_obj_uv_seam_kept_per_corner_and_written_back(tmp_path):
    v, f = grid_mesh(2, 1)  # 6 vertices, 4 faces
    rng = np.random.default_rng(4)
    corner = rng.random((len(f), 3, 2))  # a different value at every corner: seams everywhere
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in v.tolist()]
    lines += [f"vt {a!r} {b!r}" for a, b in corner.reshape(-1, 2).tolist()]
    lines += ["f " + " ".join(f"{i + 1}/{3 * j + k + 1}" for k, i in enumerate(face))
              for j, face in enumerate(f)]
    path = tmp_path / "seam.obj"
    path.write_text("\n".join(lines) + "\n")
    with pytest.warns(MeshWarning, match=r"uv differs between the faces around 4 vertices"):
        mesh = read_mesh_data(path)
    np.testing.assert_array_equal(mesh.corner_attributes["uv"], corner)
    assert "uv" not in mesh.attributes
    write_mesh_data(tmp_path / "out.obj", mesh)
    with pytest.warns(MeshWarning, match="seam"):
        again = read_mesh_data(tmp_path / "out.obj")
    np.testing.assert_array_equal(again.corner_attributes["uv"], corner)


def test_obj_corners_without_a_value_are_written_without_vt(tmp_path):
    # a fill across a UV seam gives its new corners no uv (NaN): those faces are written
    # as `f a b c` (or `f a//n`), never with `vt nan nan`, and read back as NaN again
    v, f = grid_mesh(2, 1)  # 6 vertices, 4 faces
    rng = np.random.default_rng(6)
    corner = rng.random((len(f), 3, 2))
    corner[1] = np.nan
    normals = rng.standard_normal((len(v), 3))
    mesh = MeshData(v, f, {"normal": normals}, {}, {"uv": corner})
    write_mesh_data(tmp_path / "out.obj", mesh)
    text = (tmp_path / "out.obj").read_text()
    assert "nan" not in text
    assert len([line for line in text.splitlines() if line.startswith("vt ")]) == 9
    faces = [line for line in text.splitlines() if line.startswith("f ")]
    assert [line.count("//") for line in faces] == [0, 3, 0, 0]
    with pytest.warns(MeshWarning, match="seam"):
        again = read_mesh_data(tmp_path / "out.obj")
    np.testing.assert_array_equal(again.faces, f)
    np.testing.assert_array_equal(again.corner_attributes["uv"], corner)
    np.testing.assert_array_equal(again.attributes["normal"], normals)


def test_obj_vertex_colours_and_dropped_records_are_named(tmp_path):
    path = tmp_path / "c.obj"
    path.write_text("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\ns 1\nl 1 2\nf 1 2 3\n")
    with pytest.warns(MeshWarning, match=r"OBJ records l, s \(smoothing .* not kept"):
        mesh = read_mesh_data(path)
    np.testing.assert_array_equal(mesh.attributes["color"], np.eye(3))


def test_obj_objects_groups_materials_are_face_labels_and_written_back(tmp_path):
    v, f = grid_mesh(2, 1)  # 4 faces
    lines = ["mtllib skin.mtl", *(f"v {x!r} {y!r} {z!r}" for x, y, z in v.tolist()),
             "o body", "g left", "usemtl skin"]
    lines += ["f " + " ".join(str(i + 1) for i in f[0])]
    lines += ["usemtl bone # a comment", "f " + " ".join(str(i + 1) for i in f[1])]
    lines += ["g right", "f " + " ".join(str(i + 1) for i in f[2]),
              "f " + " ".join(str(i + 1) for i in f[3])]
    path = tmp_path / "m.obj"
    path.write_text("\n".join(lines) + "\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = read_mesh_data(path)
    assert mesh.face_attributes["object"].tolist() == ["body"] * 4
    assert mesh.face_attributes["group"].tolist() == ["left", "left", "right", "right"]
    assert mesh.face_attributes["material"].tolist() == ["skin", "bone", "bone", "bone"]
    assert mesh.metadata == {"mtllib": "skin.mtl"}
    (tmp_path / "skin.mtl").write_text("newmtl skin\nnewmtl bone\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        write_mesh_data(tmp_path / "out.obj", mesh)
        again = read_mesh_data(tmp_path / "out.obj")
    for key in ("object", "group", "material"):
        assert again.face_attributes[key].tolist() == mesh.face_attributes[key].tolist()
    assert again.metadata == mesh.metadata
    np.testing.assert_array_equal(again.faces, f)
    # written into a folder without the library: the materials would not show; say so
    (tmp_path / "elsewhere").mkdir()
    with pytest.warns(MeshWarning, match="material library 'skin.mtl' is not beside the "
                                         "output"):
        write_mesh_data(tmp_path / "elsewhere" / "out.obj", mesh)


# ------------------------------------------------------------------------------ OFF


def test_coff_vertex_and_face_colours_round_trip(tmp_path):
    v, f = grid_mesh(3, 2)
    rng = np.random.default_rng(5)
    vc = rng.integers(0, 256, (len(v), 4)).astype(np.uint8)
    fc = rng.integers(0, 256, (len(f), 3)).astype(np.uint8)
    vc[0, 0] = 255  # some value above 1: 8-bit colours
    rows = [f"{x!r} {y!r} {z!r} " + " ".join(map(str, c))
            for (x, y, z), c in zip(v.tolist(), vc.tolist(), strict=True)]
    rows += ["3 " + " ".join(map(str, face)) + " " + " ".join(map(str, c))
             for face, c in zip(f.tolist(), fc.tolist(), strict=True)]
    path = tmp_path / "c.off"
    path.write_text(f"COFF\n{len(v)} {len(f)} 0\n" + "\n".join(rows) + "\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = read_mesh_data(path)
        assert mesh.attributes["color"].dtype == np.uint8
        np.testing.assert_array_equal(mesh.attributes["color"], vc)
        np.testing.assert_array_equal(mesh.face_attributes["color"], fc)
        write_mesh_data(tmp_path / "out.off", mesh)
        again = read_mesh_data(tmp_path / "out.off")
    assert (tmp_path / "out.off").read_text().startswith("COFF\n")
    np.testing.assert_array_equal(again.attributes["color"], vc)
    np.testing.assert_array_equal(again.face_attributes["color"], fc)
    np.testing.assert_array_equal(again.vertices, v)


def test_noff_float_normals_and_colours(tmp_path):
    path = tmp_path / "n.off"
    path.write_text("CNOFF\n3 1 0\n0 0 0 0 0 1 0.5 0.25 1\n1 0 0 0 0 1 0 0 0\n"
                    "0 1 0 0 0 1 1 1 1\n3 0 1 2\n")
    mesh = read_mesh_data(path)
    np.testing.assert_array_equal(mesh.attributes["normal"], [[0, 0, 1]] * 3)
    np.testing.assert_array_equal(mesh.attributes["color"][0], [0.5, 0.25, 1])
    write_mesh_data(tmp_path / "out.off", mesh)
    again = read_mesh_data(tmp_path / "out.off")
    for key in ("normal", "color"):
        np.testing.assert_array_equal(again.attributes[key], mesh.attributes[key])


def test_obj_says_it_drops_the_uv_and_normal_of_a_vertex_on_no_face(tmp_path):
    # session 46's fuzz campaign: `fill --repair` of an OBJ removed the faces of a fin's
    # vertex; OBJ stores uv and normals per face corner, so that vertex's uv was lost, and
    # nothing said so
    v, f = grid_mesh(2, 2)
    v = np.vstack([v, [[5.0, 5, 5], [6.0, 6, 6]]])
    uv = np.vstack([v[:-2, :2], [[0.5, 0.5], [np.nan, np.nan]]])  # the last has none
    normal = np.tile([0.0, 0, 1], (len(v), 1))
    with pytest.warns(MeshWarning) as record:
        write_mesh(tmp_path / "a.obj", v, f, attributes={"uv": uv, "normal": normal})
    said = [str(w.message) for w in record if "no face" in str(w.message)]
    assert said == [f"{tmp_path / 'a.obj'}: OBJ stores uv and normal per face corner: the "
                    "uv of 1 vertex on no face (9) not written, the normal of 2 vertices on "
                    "no face (9, 10) not written"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # every vertex on a face: nothing to say
        write_mesh(tmp_path / "b.obj", v[:-2], f, attributes={"uv": uv[:-2]})


# ------------------------------------------------------------------------------ STL


def test_stl_says_it_stores_no_attributes_and_keeps_facet_attributes(tmp_path):
    v, f = grid_mesh(2, 2)
    colour = np.zeros((len(v), 3), np.uint8)
    with pytest.warns(MeshWarning, match=r"STL stores triangles only: per-vertex color, "
                                         r"per-face quality not written"):
        write_mesh(tmp_path / "a.stl", v, f, attributes={"color": colour},
                   face_attributes={"quality": np.ones(len(f))})
    assert read_mesh_data(tmp_path / "a.stl").face_attributes == {}
    tags = np.arange(len(f), dtype=np.uint16) * 1000 + 1
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        write_mesh(tmp_path / "b.stl", v, f, face_attributes={"stl_attribute": tags})
        mesh = read_mesh_data(tmp_path / "b.stl")
    assert [str(w.message) for w in record if "not written" in str(w.message)] == []
    np.testing.assert_array_equal(mesh.face_attributes["stl_attribute"], tags)
    assert struct.unpack_from("<H", (tmp_path / "b.stl").read_bytes(), 84 + 48)[0] == 1


# ---------------------------------------------------------------------- GIFTI / FreeSurfer


def _brain_surface(tmp_path):
    v, f = grid_mesh(5, 4)
    rng = np.random.default_rng(6)
    thickness = rng.random(len(v)).astype(np.float32) * 4
    curv = rng.standard_normal(len(v)).astype(np.float32)
    return v.astype(np.float32).astype(np.float64), f, thickness, curv


def test_gifti_with_overlays_beside_round_trip(tmp_path):
    nib = pytest.importorskip("nibabel")
    v, f, thickness, curv = _brain_surface(tmp_path)
    meta = {"AnatomicalStructurePrimary": "CortexLeft"}
    write_mesh_data(tmp_path / "lh.pial.gii",
                    MeshData(v, f, {"thickness": thickness, "curv": curv}, metadata=meta))
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["lh.pial.curv.shape.gii", "lh.pial.gii", "lh.pial.thickness.shape.gii"]
    image = nib.load(tmp_path / "lh.pial.thickness.shape.gii")
    np.testing.assert_array_equal(image.darrays[0].data, thickness)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = read_mesh_data(tmp_path / "lh.pial.gii")
    assert set(mesh.attributes) == {"thickness", "curv"}
    np.testing.assert_array_equal(mesh.attributes["thickness"], thickness)
    np.testing.assert_array_equal(mesh.attributes["curv"], curv)
    assert mesh.attributes["thickness"].dtype == np.float32
    assert mesh.metadata == meta
    np.testing.assert_array_equal(mesh.vertices, v)
    # read_mesh reads the surface only, overlays are files of their own
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_array_equal(read_mesh(tmp_path / "lh.pial.gii")[0], v)
    # written beside the output, under the output's name; gzip-compressed surface too
    write_mesh_data(tmp_path / "out.gii.gz", mesh)
    again = read_mesh_data(tmp_path / "out.gii.gz")
    np.testing.assert_array_equal(again.attributes["thickness"], thickness)
    assert (tmp_path / "out.thickness.shape.gii").is_file()


@pytest.mark.parametrize("output", ["lh.pial.filled.gii", "lh.pial.filled.surf.gii"])
def test_a_surface_written_beside_another_keeps_its_overlays_to_itself(tmp_path, output):
    # lh.pial.gii filled into lh.pial.filled.gii beside it: the output's
    # lh.pial.filled.thickness.shape.gii matched lh.pial.gii's pattern too, so the input
    # could not be read again ("overlay has n + k values, the surface n vertices")
    pytest.importorskip("nibabel")
    v, f, thickness, _ = _brain_surface(tmp_path)
    write_mesh_data(tmp_path / "lh.pial.gii", MeshData(v, f, {"thickness": thickness}))
    longer = MeshData(np.vstack([v, v[:2]]), f, {"thickness": np.r_[thickness, 1.0, 2.0]})
    write_mesh_data(tmp_path / output, longer)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mesh = read_mesh_data(tmp_path / "lh.pial.gii")
        again = read_mesh_data(tmp_path / output)
    assert set(mesh.attributes) == {"thickness"} == set(again.attributes)
    np.testing.assert_array_equal(mesh.attributes["thickness"], thickness)
    np.testing.assert_array_equal(again.attributes["thickness"], longer.attributes["thickness"])


def test_freesurfer_overlays_beside_lh_surface_and_written_beside_output(tmp_path):
    pytest.importorskip("nibabel")
    from nibabel.freesurfer import write_morph_data

    v, f, thickness, curv = _brain_surface(tmp_path)
    write_mesh(tmp_path / "lh.white", v, f)
    write_morph_data(tmp_path / "lh.thickness", thickness)
    write_morph_data(tmp_path / "lh.curv", curv)
    mesh = read_mesh_data(tmp_path / "lh.white")
    np.testing.assert_array_equal(mesh.attributes["thickness"], thickness)
    np.testing.assert_array_equal(mesh.attributes["curv"], curv)
    assert "create_stamp" in mesh.metadata
    out = tmp_path / "out"
    out.mkdir()
    write_mesh_data(out / "lh.filled.white", mesh)
    assert sorted(p.name for p in out.iterdir()) == [
        "lh.filled.white", "lh.filled.white.curv", "lh.filled.white.thickness"]
    again = read_mesh_data(out / "lh.filled.white")
    np.testing.assert_array_equal(again.attributes["thickness"], thickness)
    assert again.metadata["create_stamp"] == mesh.metadata["create_stamp"]
    assert read_mesh_data(out / "lh.filled.white", overlays=False).attributes == {}


def test_the_subjects_overlays_go_with_freesurfer_surfaces_only(tmp_path):
    # a GIFTI surface named lh.* (converted, resampled: its vertices need not be the
    # subject's) took FreeSurfer's lh.sulc beside it, though the rule is documented for
    # FreeSurfer surfaces only; its own overlays, named after it, are still read
    nib = pytest.importorskip("nibabel")
    from nibabel.freesurfer import write_morph_data

    v, f, thickness, curv = _brain_surface(tmp_path)
    gifti = tmp_path / "lh.test.gii"
    nib.save(nib.gifti.GiftiImage(darrays=[
        nib.gifti.GiftiDataArray(v.astype(np.float32), intent="NIFTI_INTENT_POINTSET"),
        nib.gifti.GiftiDataArray(f.astype(np.int32), intent="NIFTI_INTENT_TRIANGLE")]), gifti)
    write_morph_data(tmp_path / "lh.sulc", curv)  # as many values as the GIFTI's vertices
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # not read, and nothing to warn about
        mesh = read_mesh_data(gifti)
    assert mesh.attributes == {}
    assert files_read(gifti) == [gifti]  # batch's up-to-date test does not look at it
    np.testing.assert_array_equal(mesh.vertices, v)
    nib.save(nib.gifti.GiftiImage(darrays=[nib.gifti.GiftiDataArray(
        thickness, intent="NIFTI_INTENT_SHAPE")]), tmp_path / "lh.test.thickness.shape.gii")
    assert set(read_mesh_data(gifti).attributes) == {"thickness"}
    # given explicitly, lh.sulc is read with the GIFTI surface
    given = read_mesh_data(gifti, overlays=[tmp_path / "lh.sulc"])
    np.testing.assert_array_equal(given.attributes["sulc"], curv)
    # a FreeSurfer surface beside it takes the subject's lh.sulc, named lh.* by the
    # convention or recognised by its magic bytes
    for name in ("lh.white", "lh.smoothed"):
        write_mesh(tmp_path / "lh.white", v, f)
        if name != "lh.white":
            os.replace(tmp_path / "lh.white", tmp_path / name)
        surface = read_mesh_data(tmp_path / name)
        assert set(surface.attributes) == {"sulc"}, name
        np.testing.assert_array_equal(surface.attributes["sulc"], curv)
        assert tmp_path / "lh.sulc" in files_read(tmp_path / name)


def test_filled_surface_beside_the_subjects_overlays_reads_back(tmp_path):
    # subj/surf/lh.white filled into subj/surf/lh.filled.white: the subject's lh.thickness
    # (one value per vertex of lh.white) is found beside the filled surface too; it was an
    # error ("overlay has n values, the surface n + k vertices"), so the output could not be
    # read again. It is skipped with a warning; the output's own overlay is read.
    pytest.importorskip("nibabel")
    from nibabel.freesurfer import write_morph_data

    v, f, thickness, _ = _brain_surface(tmp_path)
    write_mesh(tmp_path / "lh.white", v, f)
    write_morph_data(tmp_path / "lh.thickness", thickness)
    mesh = read_mesh_data(tmp_path / "lh.white")
    longer = MeshData(np.vstack([v, v[:2]]), f,
                      {"thickness": np.r_[thickness, thickness[:2]]})
    write_mesh_data(tmp_path / "lh.filled.white", longer)
    with pytest.warns(MeshWarning, match=r"overlay lh.thickness has \d+ values, the surface "
                                         r"\d+ vertices: another surface's, not read"):
        again = read_mesh_data(tmp_path / "lh.filled.white")
    np.testing.assert_array_equal(again.attributes["thickness"], longer.attributes["thickness"])
    assert set(again.attributes) == {"thickness"}
    np.testing.assert_array_equal(mesh.attributes["thickness"], thickness)


def test_two_overlays_of_one_name_are_both_kept_and_named(tmp_path):
    # lh.pial.gii picks up lh.pial.thickness.shape.gii and FreeSurfer's lh.thickness: both
    # would be called "thickness"; the second must not silently replace the first
    pytest.importorskip("nibabel")
    from nibabel.freesurfer import write_morph_data

    v, f, thickness, curv = _brain_surface(tmp_path)
    write_mesh(tmp_path / "s.gii", v, f)
    write_morph_data(tmp_path / "thickness", curv)
    write_morph_data(tmp_path / "lh.thickness", thickness)
    with pytest.warns(MeshWarning, match=r"overlay lh.thickness would be named 'thickness' "
                                         r"like an earlier overlay; it is kept as 'lh.thickness'"):
        mesh = read_mesh_data(tmp_path / "s.gii",
                              overlays=[tmp_path / "thickness", tmp_path / "lh.thickness"])
    np.testing.assert_array_equal(mesh.attributes["thickness"], curv)
    np.testing.assert_array_equal(mesh.attributes["lh.thickness"], thickness)


def test_explicit_overlay_with_wrong_length_names_the_overlay(tmp_path):
    pytest.importorskip("nibabel")
    from nibabel.freesurfer import write_morph_data

    v, f, thickness, _ = _brain_surface(tmp_path)
    write_mesh(tmp_path / "s.gii", v, f)
    write_morph_data(tmp_path / "other.thickness", thickness[:-1])
    with pytest.raises(MeshError, match=rf"other\.thickness: overlay has {len(v) - 1} values, "
                                        rf"the surface {len(v)} vertices"):
        read_mesh_data(tmp_path / "s.gii", overlays=[tmp_path / "other.thickness"])
    write_morph_data(tmp_path / "sulc", thickness)
    mesh = read_mesh_data(tmp_path / "s.gii", overlays=[tmp_path / "sulc"])
    np.testing.assert_array_equal(mesh.attributes["sulc"], thickness)


def test_unstorable_attributes_are_named_and_not_written(tmp_path):
    v, f = grid_mesh(2, 2)
    labels = np.array(["a"] * len(v))
    with pytest.warns(MeshWarning, match=r"per-vertex name .* cannot be stored in PLY"):
        write_mesh(tmp_path / "a.ply", v, f, attributes={"name": labels,
                                                          "q": np.ones(len(v))})
    assert set(read_mesh_data(tmp_path / "a.ply").attributes) == {"q"}
    with pytest.warns(MeshWarning, match=r"per-face tag not written"):
        write_mesh(tmp_path / "a.gii", v, f, face_attributes={"tag": np.ones(len(f))})


# ------------------------------------------------------------------------ the container


def test_appended_rows_keep_the_originals_and_refuse_missing_attributes(tmp_path):
    v, f = grid_mesh(2, 1)
    colour = np.arange(len(v) * 3, dtype=np.uint8).reshape(-1, 3)
    mesh = MeshData(v, f, {"color": colour}, {"quality": np.arange(len(f), dtype=float)})
    new_v = np.array([[0.5, 0.5, 1.0]])
    new_f = np.array([[0, 1, len(v)]])
    grown = mesh.appended(new_v, new_f, attributes={"color": [[9, 9, 9]]},
                          face_attributes={"quality": [7.0]})
    np.testing.assert_array_equal(grown.vertices[:len(v)], v)
    np.testing.assert_array_equal(grown.attributes["color"][:len(v)], colour)
    assert grown.attributes["color"].dtype == np.uint8
    np.testing.assert_array_equal(grown.attributes["color"][-1], [9, 9, 9])
    np.testing.assert_array_equal(grown.face_attributes["quality"][-1], 7.0)
    write_mesh_data(tmp_path / "g.ply", grown)
    back = read_mesh_data(tmp_path / "g.ply")
    np.testing.assert_array_equal(back.attributes["color"], grown.attributes["color"])
    np.testing.assert_array_equal(back.vertices[:len(v)], v)
    with pytest.raises(ValueError, match=r"missing \['color'\]"):
        mesh.appended(new_v, new_f, face_attributes={"quality": [1.0]})
    with pytest.raises(ValueError, match="shape"):
        mesh.appended(new_v, new_f, attributes={"color": [[1, 2]]},
                      face_attributes={"quality": [1.0]})
    with pytest.raises(ValueError, match=r"attribute 'color' has 2 rows, expected 6"):
        MeshData(v, f, {"color": colour[:2]})


def test_label_overlay_keeps_numbers_and_its_label_table(tmp_path):
    nib = pytest.importorskip("nibabel")
    v, f, _, _ = _brain_surface(tmp_path)
    write_mesh(tmp_path / "s.gii", v, f)
    labels = (np.arange(len(v)) % 3).astype(np.int32)
    table = nib.gifti.GiftiLabelTable()
    for key, name in enumerate(["unknown", "V1", "V2"]):
        label = nib.gifti.GiftiLabel(key=key, red=1.0, green=0.0, blue=0.0, alpha=1.0)
        label.label = name
        table.labels.append(label)
    image = nib.gifti.GiftiImage(labeltable=table, darrays=[nib.gifti.GiftiDataArray(
        labels, intent="NIFTI_INTENT_LABEL", datatype="NIFTI_TYPE_INT32")])
    (tmp_path / "s.areas.label.gii").write_bytes(image.to_bytes())
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshWarning)  # kept (session 35): nothing lost to name
        mesh = read_mesh_data(tmp_path / "s.gii", overlays=[tmp_path / "s.areas.label.gii"])
    np.testing.assert_array_equal(mesh.attributes["areas"], labels)
    assert mesh.attributes["areas"].dtype == np.int32
    assert json.loads(mesh.metadata["labels.areas"]) == [
        [k, name, 1.0, 0.0, 0.0, 1.0] for k, name in enumerate(["unknown", "V1", "V2"])]


def test_read_fill_write_keeps_the_original_vertices_and_their_attributes(tmp_path):
    from surfinpaint import data, fill_holes

    v, f = data.default_demo_mesh()
    colour = np.clip((v - v.min(0)) / np.ptp(v, 0) * 255, 0, 255).astype(np.uint8)
    quality = v[:, 2].astype(np.float32)
    write_mesh_data(tmp_path / "in.ply", MeshData(v, f, {"color": colour, "q": quality}))
    mesh = read_mesh_data(tmp_path / "in.ply")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the fill's own notes
        result = fill_holes(mesh.vertices, mesh.faces, attributes=mesh.attributes,
                            face_attributes=mesh.face_attributes)
    write_mesh(tmp_path / "out.ply", result.vertices, result.faces,
               attributes=result.attributes, face_attributes=result.face_attributes)
    out = read_mesh_data(tmp_path / "out.ply")
    n = len(v)
    assert len(out.vertices) > n
    np.testing.assert_array_equal(out.vertices[:n], v)
    np.testing.assert_array_equal(out.attributes["color"][:n], colour)
    np.testing.assert_array_equal(out.attributes["q"][:n], quality)
    assert out.attributes["color"].dtype == np.uint8 and out.attributes["q"].dtype == np.float32


def test_the_attribute_api_is_at_the_top_level(tmp_path):
    # what a user with colours or overlays needs, reachable as surfinpaint.<name>: a colour
    # read, filled and written back through the top-level names
    import trimesh

    import surfinpaint
    from surfinpaint.geometry.cutting import cut_geodesic_disk

    sphere = trimesh.creation.icosphere(subdivisions=3)
    cut = cut_geodesic_disk(np.asarray(sphere.vertices), np.asarray(sphere.faces), 0, 0.4)
    v, f = cut.vertices, cut.faces
    colour = np.tile(np.array([[10, 200, 30]], np.uint8), (len(v), 1))
    mesh = surfinpaint.MeshData(v, f, {"colour": colour})
    surfinpaint.write_mesh_data(tmp_path / "in.ply", mesh)
    again = surfinpaint.read_mesh_data(tmp_path / "in.ply")
    result, filled = surfinpaint.fill_mesh_data(again, method="fair")
    assert len(filled.vertices) > len(v)
    np.testing.assert_array_equal(filled.vertices[: len(v)], v)
    assert (np.asarray(filled.attributes["colour"]) == [10, 200, 30]).all()
    assert issubclass(surfinpaint.SlitWarning, surfinpaint.MeshWarning)


def test_obj_writes_opaque_rgba_colours_as_rgb_and_says_why_others_are_not(tmp_path):
    # a PLY's RGBA colours (alpha 255 everywhere, as most writers store them) were not
    # written to OBJ at all; OBJ's v x y z r g b has no alpha (session 34)
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    f = np.array([[0, 1, 2]])
    rgba = np.array([[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255]], np.uint8)
    with pytest.warns(MeshWarning, match="8-bit color is written as OBJ's float") as caught:
        write_mesh_data(tmp_path / "o.obj", MeshData(v, f, attributes={"color": rgba}))
    assert not [w for w in caught if "not written" in str(w.message)]
    back = read_mesh_data(tmp_path / "o.obj")
    np.testing.assert_array_equal(back.attributes["color"] * 255, rgba[:, :3])
    see_through = rgba.copy()
    see_through[1, 3] = 254
    with pytest.warns(MeshWarning, match=r"per-vertex color \(RGBA, not opaque\)"):
        write_mesh_data(tmp_path / "t.obj", MeshData(v, f, attributes={"color": see_through}))
    assert "color" not in read_mesh_data(tmp_path / "t.obj").attributes
