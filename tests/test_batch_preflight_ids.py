"""``batch``'s pre-flight of what names what (session 44): an OBJ's face ids past its
vertices (0, a negative id counting back past the first vertex, an id past the last), said
by the reader (the file, the face, its line and the id) and, in an OBJ the check reads whole
(up to 256 KiB), by the check in the same words (a larger one's by its fill); a FreeSurfer
``.annot``'s labels that its colour table does not hold (a warning naming the overlay,
the values and how many vertices; such vertices unlabelled), and a colour table announcing
more entries than label values can name (an error, read without allocating it)."""

from __future__ import annotations

import json
import struct
from pathlib import Path

import numpy as np
import pytest
from test_batch_preflight import _batch_events, _surface_and_overlay
from test_batch_preflight_bodies import _holed, _large_obj, _old_format_annot
from test_batch_preflight_ends import _annot, _said

from surfinpaint.app.cli import main
from surfinpaint.io.base import MeshWarning
from surfinpaint.io.brain import check_overlay
from surfinpaint.io.filetypes import check_file
from surfinpaint.io.formats import read_mesh, read_mesh_data, write_mesh
from surfinpaint.io.obj import obj_ids_plain

nib = pytest.importorskip("nibabel")

# ------------------------------------------------------------------------ OBJ face ids


def _with_face(data: bytes, face: int, line: bytes) -> tuple[bytes, int]:
    """``data`` (an OBJ) with its face ``face`` (from 0) replaced by ``line``, and the
    face's line number (from 1)."""
    lines = data.split(b"\n")
    at = [k for k, text in enumerate(lines) if text.startswith(b"f ")][face]
    lines[at] = line
    return b"\n".join(lines), at + 1


BAD_IDS = {  # the face's line -> what the message says of it (the OBJ has n vertices)
    "past the last": (lambda n: f"f 1 2 {n + 7}",
                      lambda n: f"uses vertex index {n + 7}, past the file's {n} vertices"),
    "past the last, with uv": (lambda n: f"f 1/1 {n + 1}/2 3/3",
                               lambda n: f"uses vertex index {n + 1}, past the file's {n} "
                               "vertices"),
    "0": (lambda n: "f 1 0 3", lambda n: "uses vertex index 0 (OBJ counts from 1)"),
    "negative past the first": (
        lambda n: f"f -1 -2 -{n + 5}",
        lambda n: f"uses vertex index -{n + 5}, a negative index past the first vertex (it "
                  f"counts back from the {n} vertices before the face)"),
}


@pytest.mark.parametrize("size", ["large", "small"])
@pytest.mark.parametrize("case", BAD_IDS)
def test_an_objs_face_id_past_its_vertices_is_said_by_the_check_and_the_reader(
        tmp_path, case, size):
    # the reader names the face, its line and the id (before session 44 it said neither);
    # the check says the same of an OBJ it reads whole and leaves a larger one's ids to the
    # reader (screening them cost 241x the pre-flight of an OBJ listing)
    whole = tmp_path / "whole.obj"
    if size == "large":
        data = _large_obj(whole)
    else:
        write_mesh(whole, *_holed(2))
        data = whole.read_bytes()
    n = data.count(b"\nv ")
    face = data.count(b"\nf ") // 2
    line, words = BAD_IDS[case]
    bad, number = _with_face(data, face, line(n).encode())
    path = tmp_path / "bad.obj"
    path.write_bytes(bad)
    said = _said(read_mesh, path)
    assert said == f"{path}: face {face} (line {number}) {words(n)}"
    if size == "small":
        assert _said(check_file, path) == said
    else:
        assert check_file(path) is None


def test_every_face_past_the_vertices_is_counted_and_named(tmp_path):
    data = _large_obj(tmp_path / "whole.obj")
    n = data.count(b"\nv ")
    for face in (7, 900, 901):
        data = _with_face(data, face, f"f {n + face} 1 2".encode())[0]
    path = tmp_path / "bad.obj"
    path.write_bytes(data)
    said = _said(read_mesh, path)
    assert said.endswith(f"uses vertex index {n + 7}, past the file's {n} vertices; 3 faces "
                         "do: 7, 900, 901"), said


def test_good_objs_with_negative_and_textured_ids_pass_the_check(tmp_path):
    # negative ids counting back from the vertices before the face, uv and normal ids: the
    # screen cannot clear negative ids, the reader then reads the file and passes it
    data = _large_obj(tmp_path / "whole.obj")
    n = data.count(b"\nv ")
    for k, line in enumerate([b"f -1 -2 -3", f"f 1/1/1 2//1 {n}/1".encode()]):
        path = tmp_path / f"good{k}.obj"
        good = _with_face(data, 3, line)[0]
        path.write_bytes(good.replace(b"\nf ", b"\nvt 0.5 0.5\nvn 0 0 1\nf ", 1) if k else good)
        read_mesh_data(path)
        assert check_file(path) is None


SCREENED = {  # OBJ text -> whether the screen clears its face ids (else the reader looks)
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n": True,
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3": True,  # no newline at the end
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\r\nf\t1/1/1 2//2 3/4\r\n": True,
    b"\xef\xbb\xbfv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n": True,
    b"v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n": True,  # a vertex after the face using it
    b"\xef\xbb\xbff 1 2 4\nv 0 0 0\nv 1 0 0\nv 0 1 0\n": False,  # the first line a face
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n": False,
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n": False,
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -1\n": False,
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\n  f 1 2 3\n": False,  # indented
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 # a note\n": False,
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1-2 3 1\n": False,
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf /1 2 3\n": False,
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3.5\n": False,
    b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n": False,
}


@pytest.mark.parametrize("text", SCREENED)
def test_the_screen_clears_plain_ids_in_range_read_in_any_chunks(text):
    assert obj_ids_plain([text]) is SCREENED[text]
    for cut in range(1, len(text)):  # a line split between two reads is read whole
        assert obj_ids_plain([text[:cut], text[cut:]]) is SCREENED[text], cut
    assert obj_ids_plain(text[k:k + 1] for k in range(len(text))) is SCREENED[text]


def test_a_batch_fails_a_large_obj_with_a_bad_face_id_in_the_readers_words(
        tmp_path, monkeypatch, capsys):
    # its pre-flight passes it (its ids are left to the reader): the file fails at its fill,
    # alone, in the reader's words, and the others are filled
    scans = tmp_path / "scans"
    scans.mkdir()
    data = _large_obj(scans / "whole.obj")
    (scans / "whole.obj").unlink()
    n = data.count(b"\nv ")
    (scans / "bad.obj").write_bytes(_with_face(data, 11, f"f 1 2 {n + 1}".encode())[0])
    said = _said(read_mesh, scans / "bad.obj")
    write_mesh(scans / "good.obj", *_holed())
    before = {p: p.read_bytes() for p in scans.iterdir()}
    events, failed = _batch_events(monkeypatch, scans, tmp_path / "out")
    assert sorted(events) == sorted([f"fill {scans / 'bad.obj'}", f"failed {scans / 'bad.obj'}",
                                     f"fill {scans / 'good.obj'}",
                                     f"filled {scans / 'good.obj'}"]), events
    assert failed == {str(scans / "bad.obj"): said}
    assert {p: p.read_bytes() for p in scans.iterdir()} == before  # inputs untouched
    code = main(["fill", str(scans / "bad.obj"), "-o", str(tmp_path / "f.obj"), "-q"])
    assert code == 1 and not (tmp_path / "f.obj").exists()
    assert "".join(said.split()) in "".join(capsys.readouterr().err.split())


# ------------------------------------------------------------- .annot labels and tables


def _annot_36(path: Path, n: int) -> None:
    """An ``.annot`` of 36 areas (aparc's count), some vertices unlabelled (value 0)."""
    ctab = np.array([[25 * k % 256, 40 * k % 256, 90 * k % 256, 0, 0] for k in range(36)])
    labels = (np.arange(n) * 7) % 36
    labels[::11] = -1  # written as value 0: no label
    nib.freesurfer.write_annot(str(path), labels, ctab, [f"area{k}".encode() for k in
                                                          range(36)], fill_ctab=True)


def _annot_with(path: Path, n: int, values: dict[int, int]) -> None:
    """:func:`_annot` of ``n`` vertices with the label values of some vertices replaced."""
    _annot(path, n)
    data = bytearray(path.read_bytes())
    for vertex, value in values.items():
        struct.pack_into(">i", data, 4 + 8 * vertex + 4, value)
    path.write_bytes(bytes(data))


@pytest.mark.parametrize("make", [_annot, _annot_36, _old_format_annot])
def test_an_annots_labels_and_table_are_nibabels(tmp_path, make):
    surface, overlay = _surface_and_overlay(tmp_path, ("lh.aparc.annot", make))
    mesh = read_mesh_data(surface, overlays=[overlay])
    labels, ctab, names = nib.freesurfer.read_annot(str(overlay))
    assert np.array_equal(mesh.attributes["aparc"], labels)
    table = json.loads(mesh.metadata["labels.aparc"])
    assert [row[:2] for row in table] == [[k, name.decode()] for k, name in enumerate(names)]
    assert np.allclose([row[2:] for row in table], np.column_stack(
        [ctab[:, :3] / 255, 1 - ctab[:, 3] / 255]))


def test_labels_not_in_the_colour_table_are_unlabelled_and_said(tmp_path):
    # 511 lies between the table's colours (nibabel gave its vertices a neighbour's
    # label, silently), 16777215 past them all (nibabel: an IndexError)
    odd = {5: 511, 6: 511, 9: 0xFFFFFF}
    surface, overlay = _surface_and_overlay(
        tmp_path, ("lh.aparc.annot", lambda path, n: _annot_with(path, n, odd)))
    expected = (f"{surface}: overlay lh.aparc.annot: 3 vertices have label values its colour "
                "table does not hold, read as no label (-1): 511 (RGB 255 1 0) on 2 "
                "vertices, 16777215 (RGB 255 255 255) on 1 vertex")
    with pytest.warns(MeshWarning) as said:
        labels = read_mesh_data(surface, overlays=[overlay]).attributes["aparc"]
    assert [str(w.message) for w in said] == [expected]
    want = np.arange(len(labels)) % 3
    want[list(odd)] = -1
    assert np.array_equal(labels, want)
    assert check_overlay(overlay) is None  # readable: a warning, not an error


def _huge_table(path: Path, n: int, announced: int = 2**31 - 1) -> None:
    """:func:`_annot` whose colour table announces ``announced`` entries (it holds 3)."""
    _annot(path, n)
    data = bytearray(path.read_bytes())
    struct.pack_into(">i", data, 4 + 8 * n + 8, announced)
    path.write_bytes(bytes(data))


def _huge_old_table(path: Path, n: int) -> None:
    """:func:`_old_format_annot` whose entry count says 2**31 - 1."""
    _old_format_annot(path, n)
    data = bytearray(path.read_bytes())
    struct.pack_into(">i", data, 4 + 8 * n + 4, 2**31 - 1)
    path.write_bytes(bytes(data))


@pytest.mark.parametrize("make", [_huge_table, _huge_old_table])
def test_a_colour_table_announcing_billions_of_entries_fails_without_allocating(
        tmp_path, monkeypatch, make):
    def allocating(*args, **kwargs):  # nibabel allocates the size a table announces
        raise AssertionError("nibabel's read_annot called")

    monkeypatch.setattr(nib.freesurfer, "read_annot", allocating)
    monkeypatch.setattr(nib.freesurfer.io, "read_annot", allocating)
    surface, overlay = _surface_and_overlay(tmp_path, ("lh.aparc.annot", make))
    said = _said(lambda p: read_mesh_data(surface, overlays=[p]), overlay)
    assert said == (f"{overlay}: FreeSurfer annotation's colour table announces 2147483647 "
                    "entries, more than the 16777216 colours a label value can name (a "
                    "corrupt table; not read)")
    assert _said(check_overlay, overlay) == said


def test_a_colour_table_of_as_many_entries_as_colours_is_read(tmp_path):
    # the limit itself: 2**24 announced, 3 held (nothing allocated for the 2**24)
    surface, overlay = _surface_and_overlay(
        tmp_path, ("lh.aparc.annot", lambda path, n: _huge_table(path, n, 1 << 24)))
    assert check_overlay(overlay) is None
    labels = read_mesh_data(surface, overlays=[overlay]).attributes["aparc"]
    assert np.array_equal(labels, np.arange(len(labels)) % 3)
