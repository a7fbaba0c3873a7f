"""Odd files met in the wild (issue 19): trailing data, BOMs, Latin-1 names, comments that look
like keywords, STL padding, bad counts, extreme scales, malformed ascii STL. Each file is built
here, in code, from a small mesh written by :func:`write_mesh`."""

from __future__ import annotations

import logging
import re
import warnings

import numpy as np
import pytest
from conftest import grid_mesh

from surfinpaint import data
from surfinpaint.errors import MeshError
from surfinpaint.geometry.validation import validate_mesh, zero_area_faces
from surfinpaint.io import MeshWarning, read_mesh, read_mesh_data, write_mesh


def _written(tmp_path, name: str, **kwargs) -> tuple[bytes, np.ndarray, np.ndarray]:
    v, f = grid_mesh(4, 3)
    path = tmp_path / name
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MeshWarning)
        write_mesh(path, v, f, **kwargs)
    return path.read_bytes(), v, f


def _refused(path, *fragments) -> MeshError:
    with pytest.raises(MeshError) as info:
        read_mesh(path)
    text = str(info.value)
    assert str(path) in text, text
    for fragment in fragments:
        assert re.search(fragment, text), text
    return info.value


def _same(path, v, f) -> None:
    got_v, got_f = read_mesh(path)
    np.testing.assert_array_equal(got_v, v)
    np.testing.assert_array_equal(got_f, f)


# ------------------------------------------------------------- counts and trailing data


def _ply_recount(blob: bytes, element: str, delta: int) -> bytes:
    head, sep, body = blob.partition(b"end_header\n")
    n = int(re.search(rf"element {element} (\d+)".encode(), head).group(1))
    head = head.replace(f"element {element} {n}\n".encode(),
                        f"element {element} {n + delta}\n".encode())
    return head + sep + body


@pytest.mark.parametrize("ascii", [False, True], ids=["binary", "ascii"])
def test_ply_with_more_faces_than_announced_is_refused_as_trailing_data(tmp_path, ascii):
    blob, _, _ = _written(tmp_path, "m.ply", ascii=ascii)
    path = tmp_path / "more.ply"
    path.write_bytes(_ply_recount(blob, "face", -1))
    _refused(path, "trailing data", "face")


@pytest.mark.parametrize("ascii", [False, True], ids=["binary", "ascii"])
def test_ply_with_more_vertices_than_announced_is_refused(tmp_path, ascii):
    blob, _, _ = _written(tmp_path, "m.ply", ascii=ascii)
    path = tmp_path / "morev.ply"
    path.write_bytes(_ply_recount(blob, "vertex", -1))
    _refused(path)


@pytest.mark.parametrize("ascii", [False, True], ids=["binary", "ascii"])
def test_ply_with_fewer_faces_than_announced_is_truncated(tmp_path, ascii):
    blob, _, _ = _written(tmp_path, "m.ply", ascii=ascii)
    path = tmp_path / "fewer.ply"
    path.write_bytes(_ply_recount(blob, "face", +1))
    _refused(path, "truncated")


def test_ply_trailing_newline_is_not_data(tmp_path):
    blob, v, f = _written(tmp_path, "m.ply")
    path = tmp_path / "nl.ply"
    path.write_bytes(blob + b"\n")
    _same(path, v, f)


@pytest.mark.parametrize("ascii", [False, True], ids=["binary", "ascii"])
def test_ply_with_zero_faces_is_no_mesh_not_truncated(tmp_path, ascii):
    # `element face 0` (a point cloud exported as a mesh, or an empty export) is a whole
    # file: refused for having no faces, not as truncated
    blob, v, _ = _written(tmp_path, "m.ply", ascii=ascii)
    head, sep, body = blob.partition(b"end_header\n")
    nf = int(re.search(rb"element face (\d+)", head).group(1))
    head = head.replace(f"element face {nf}".encode(), b"element face 0")
    cut = b" ".join(body.split()[:3 * len(v)]) + b"\n" if ascii else body[:v.size * 8]
    path = tmp_path / "nofaces.ply"
    path.write_bytes(head + sep + cut)
    err = _refused(path, "no faces")
    assert "truncated" not in str(err)


def _off_recount(blob: bytes, dv: int, df: int) -> bytes:
    lines = blob.split(b"\n")
    nv, nf, ne = map(int, lines[1].split())
    lines[1] = f"{nv + dv} {nf + df} {ne}".encode()
    return b"\n".join(lines)


@pytest.mark.parametrize(("dv", "df"), [(0, -1), (-1, 0), (-2, -3)])
def test_off_with_more_records_than_announced_is_refused_as_trailing_data(tmp_path, dv, df):
    blob, _, _ = _written(tmp_path, "m.off")
    path = tmp_path / "more.off"
    path.write_bytes(_off_recount(blob, dv, df))
    _refused(path, "trailing data")


def test_off_with_fewer_faces_than_announced_is_truncated(tmp_path):
    blob, _, _ = _written(tmp_path, "m.off")
    path = tmp_path / "fewer.off"
    path.write_bytes(_off_recount(blob, 0, 2))
    _refused(path, "truncated")


@pytest.mark.parametrize("count", ["-1", "-7", "1.5", "12abc", "0x10"])
@pytest.mark.parametrize("element", ["vertex", "face"])
@pytest.mark.parametrize("ascii", [False, True], ids=["binary", "ascii"])
def test_ply_bad_element_counts_are_named(tmp_path, ascii, element, count):
    blob, _, _ = _written(tmp_path, "m.ply", ascii=ascii)
    head, sep, body = blob.partition(b"end_header\n")
    head = re.sub(rf"element {element} \d+".encode(), f"element {element} {count}".encode(), head)
    path = tmp_path / "count.ply"
    path.write_bytes(head + sep + body)
    err = _refused(path, f"element {element} {re.escape(count)}")
    if count.startswith("-"):
        assert "negative" in str(err)


def test_ply_count_beyond_the_file_is_truncated(tmp_path):
    blob, _, _ = _written(tmp_path, "m.ply")
    path = tmp_path / "huge.ply"
    path.write_bytes(_ply_recount(blob, "vertex", 10**15))
    _refused(path, "truncated")


# ------------------------------------------------------------------------ text encodings


def test_obj_starting_with_a_utf8_bom(tmp_path):
    blob, v, f = _written(tmp_path, "m.obj")
    assert blob.startswith(b"# ")
    path = tmp_path / "bom.obj"
    path.write_bytes(b"\xef\xbb\xbf" + b"v" + blob[blob.index(b"\nv ") + 2:])
    # the first record is a vertex line right after the BOM
    assert path.read_bytes()[:5] == b"\xef\xbb\xbfv "
    _same(path, v, f)


def test_latin1_bytes_in_obj_comments_and_group_names(tmp_path):
    blob, v, f = _written(tmp_path, "m.obj")
    path = tmp_path / "latin1.obj"
    first_face = blob.index(b"\nf ") + 1
    path.write_bytes(b"# mod\xe8le cr\xe9\xe9 \xe0 la main\no pi\xe8ce\n" + blob[:first_face]
                     + b"g gr\xfcn\nusemtl m\xe9tal\n" + blob[first_face:])
    _same(path, v, f)
    labels = read_mesh_data(path).face_attributes
    assert set(labels["material"]) == {"m\xe9tal"} and set(labels["object"]) == {"pi\xe8ce"}


def test_latin1_bytes_in_off_comments(tmp_path):
    blob, v, f = _written(tmp_path, "m.off")
    path = tmp_path / "latin1.off"
    head, _, rest = blob.partition(b"\n")
    path.write_bytes(head + b"\n# mod\xe8le \xa9 soci\xe9t\xe9\n" + rest)
    _same(path, v, f)


def test_binary_garbage_in_a_text_format_is_still_refused(tmp_path):
    path = tmp_path / "nul.obj"
    path.write_bytes(b"v 0 0 0\nv 1 0 0\x00\x00\nv 0 1 0\nf 1 2 3\n")
    _refused(path, "not a text OBJ file")


def _header_edited(tmp_path, name: str, lines: bytes, ascii: bool = False):
    """A small mesh written as PLY with ``lines`` in place of its header's comment."""
    blob, v, f = _written(tmp_path, "m.ply", ascii=ascii)
    path = tmp_path / name
    path.write_bytes(blob.replace(b"comment written by surfinpaint\n", lines))
    return path, v, f


@pytest.mark.parametrize("ascii", [False, True], ids=["binary", "ascii"])
def test_ply_comment_containing_end_header(tmp_path, ascii):
    path, v, f = _header_edited(tmp_path, "comment.ply", b"comment the end_header line "
                                b"follows\nobj_info end_header\n", ascii)
    _same(path, v, f)


@pytest.mark.parametrize("ascii", [False, True], ids=["binary", "ascii"])
def test_ply_header_line_without_a_keyword_is_read_as_a_comment(tmp_path, ascii):
    # Blender 2.4's exporter writes its name without "comment" (assimp's Wuson.ply);
    # other readers take such files: the line is kept with the comments, and said
    path, v, f = _header_edited(tmp_path, "blender.ply", b"Created by Blender3D 247 - "
                                b"www.blender.org, source file: \n", ascii)
    with pytest.warns(MeshWarning, match=r"blender\.ply: PLY header line 'Created by "
                                         r"Blender3D.*read as a comment"):
        mesh = read_mesh_data(path)
    np.testing.assert_array_equal(mesh.vertices, v)
    np.testing.assert_array_equal(mesh.faces, f)
    assert "Created by Blender3D 247" in mesh.metadata["comments"]


@pytest.mark.parametrize("line", [b"property float\n", b"format\n", b"element vertex\n"])
def test_ply_header_keyword_lines_that_do_not_parse_are_refused(tmp_path, line):
    path, _, _ = _header_edited(tmp_path, "bad.ply", b"comment written by surfinpaint\n" + line)
    _refused(path, "PLY header")


# ------------------------------------------------------------------------------- STL


@pytest.mark.parametrize("pad", [1, 2, 49])
def test_binary_stl_with_padding_bytes(tmp_path, pad):
    blob, _, _ = _written(tmp_path, "m.stl")
    v, f = read_mesh(tmp_path / "m.stl")
    path = tmp_path / "pad.stl"
    path.write_bytes(blob + b"\x00" * pad)
    _same(path, v, f)


def test_binary_stl_with_a_solid_header_and_padding(tmp_path):
    blob, _, _ = _written(tmp_path, "m.stl")
    v, f = read_mesh(tmp_path / "m.stl")
    path = tmp_path / "solid.stl"
    path.write_bytes(b"solid exported by a CAD tool".ljust(80, b" ") + blob[80:] + b"\x00\x00")
    _same(path, v, f)


def test_binary_stl_with_a_whole_extra_record_is_refused(tmp_path):
    blob, _, _ = _written(tmp_path, "m.stl")
    path = tmp_path / "extra.stl"
    path.write_bytes(blob + blob[-50:])
    _refused(path, "trailing data|truncated")


_FACET = ("facet normal 0 0 1\n outer loop\n  vertex {0}\n  vertex {1}\n  vertex {2}\n"
          " endloop\nendfacet\n")


def _ascii_stl(normal_line: str | None = None) -> str:
    one = _FACET.format("0 0 0", "1 0 0", "0 1 0")
    two = _FACET.format("1 0 0", "1 1 0", "0 1 0")
    if normal_line is not None:
        two = two.replace("facet normal 0 0 1", normal_line)
    return "solid test\n" + one + two + "endsolid test\n"


def test_ascii_stl_parsed_exactly(tmp_path):
    path = tmp_path / "ok.stl"
    path.write_text(_ascii_stl())
    v, f = read_mesh(path)
    np.testing.assert_array_equal(v, [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    np.testing.assert_array_equal(f, [[0, 1, 2], [1, 3, 2]])
    path.write_text(_ascii_stl("facet normal nan nan nan").upper())  # some exporters do both
    np.testing.assert_array_equal(read_mesh(path)[1], f)


@pytest.mark.parametrize("line", ["facet normal a b c", "facet normal 0,0,1", "facet normal 0 0",
                                  "facet normal 0 0 1e", "facet 0 0 1"])
def test_ascii_stl_malformed_facet_normal_is_one_clean_error(tmp_path, capfd, caplog, line):
    path = tmp_path / "bad.stl"
    path.write_text(_ascii_stl(line))
    caplog.set_level(logging.DEBUG)
    err = _refused(path, "line 9", "facet")
    assert err.__cause__ is None and (err.__context__ is None or err.__suppress_context__)
    captured = capfd.readouterr()
    assert captured.err == "" and captured.out == ""
    assert caplog.records == []


def test_ascii_stl_without_endsolid_is_truncated(tmp_path):
    path = tmp_path / "cut.stl"
    path.write_text(_ascii_stl().replace("endsolid test\n", ""))
    _refused(path, "truncated")


# ---------------------------------------------------------------------- extreme scales


@pytest.mark.parametrize("scale", [1e200, 1e-200, 1e300, 1e-300])
def test_extreme_coordinates_are_not_zero_area(tmp_path, scale):
    v, f = data.sphere()
    path = tmp_path / "scaled.ply"
    write_mesh(path, v * scale, f)
    got_v, got_f = read_mesh(path)
    np.testing.assert_array_equal(got_v, v * scale)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow or underflow on the way
        report = validate_mesh(got_v, got_f, path=str(path))
        assert zero_area_faces(got_v, got_f).size == 0
    assert report.is_closed and report.euler_characteristic == 2


@pytest.mark.parametrize("scale", [1.0, 1e200, 1e-200])
def test_zero_area_is_still_found_at_every_scale(scale):
    v = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1e-13, 0], [0, 0, 0]]) * scale
    f = np.array([[0, 1, 3], [0, 1, 2], [0, 2, 4], [0, 5, 3], [0, 3, 4]])
    np.testing.assert_array_equal(zero_area_faces(v, f), [1, 2, 3])

