"""``batch``'s pre-flight past the headers (session 43): a FreeSurfer ``.annot``'s colour
table, a GIFTI file's data (its DataArrays' payloads and dimensions), a ``.gii.gz`` cut
short, a ``.gii`` cut just after a tag, and a large OBJ whose last line is cut short. Each
is said by the reader and by the check in the same words, naming the file and the
DataArray, colour table entry or line; a batch fails them before any fill, and ``fill``
exits 1 with the same words, writing nothing."""

from __future__ import annotations

import builtins
import gzip
import re
import struct
from pathlib import Path

import numpy as np
import pytest
from test_batch_preflight import _batch_events, _count_reads, _surface_and_overlay
from test_batch_preflight_ends import _annot, _said

from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.io import brain_checks
from surfinpaint.io.brain import check_overlay
from surfinpaint.io.formats import check_file, read_mesh, read_mesh_data, write_mesh

nib = pytest.importorskip("nibabel")


def _holed(level: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """A sphere with a hole: a good file of it is filled."""
    v, f = sphere(level)
    cut = cut_geodesic_disk(v, f, 0, 0.6)
    return cut.vertices, cut.faces


# ------------------------------------------------------------------------ a GIFTI's data


def _gifti_bytes(encoding: str = "GZipBase64Binary") -> bytes:
    """A GIFTI surface of :func:`_holed` with its arrays in ``encoding``."""
    v, f = _holed()
    arrays = [nib.gifti.GiftiDataArray(v.astype(np.float32), intent="NIFTI_INTENT_POINTSET",
                                       datatype="NIFTI_TYPE_FLOAT32", encoding=encoding),
              nib.gifti.GiftiDataArray(f.astype(np.int32), intent="NIFTI_INTENT_TRIANGLE",
                                       datatype="NIFTI_TYPE_INT32", encoding=encoding)]
    return nib.gifti.GiftiImage(darrays=arrays).to_bytes()


def _payload(data: bytes, k: int) -> tuple[int, int]:
    """Where the payload of DataArray ``k`` starts and ends."""
    start = [m.end() for m in re.finditer(rb"<Data>", data)][k]
    return start, data.index(b"</Data>", start)


def _cut_payload(data: bytes, k: int = 0, count: int = 16) -> bytes:
    """DataArray ``k``'s payload with its last ``count`` characters cut."""
    end = _payload(data, k)[1]
    return data[:end - count] + data[end:]


def _dims(data: bytes, k: int, dim: int, change: int) -> bytes:
    """DataArray ``k``'s ``Dim{dim}`` changed by ``change`` (0: the attribute dropped)."""
    tag = list(re.finditer(rb"<DataArray\b[^>]*>", data))[k]
    old = re.search(rb' Dim%d="(\d+)"' % dim, tag[0])
    new = b"" if not change else b' Dim%d="%d"' % (dim, int(old[1]) + change)
    return data[:tag.start()] + tag[0].replace(old[0], new) + data[tag.end():]


def _drop_last_value(data: bytes) -> bytes:
    """DataArray 0's last value (ASCII) dropped."""
    start, end = _payload(data, 0)
    values = data[start:end].split()
    return data[:start] + b" ".join(values[:-1]) + data[end:]


N, F = len(_holed()[0]), len(_holed()[1])
POINTS, TRIANGLES = "GIFTI DataArray 0 (NIFTI_INTENT_POINTSET) is corrupt: ", \
    "GIFTI DataArray 1 (NIFTI_INTENT_TRIANGLE) is corrupt: "
# each: the encoding written, the corruption, what the reader and the check say
BAD_GIFTIS = {
    "gzip payload cut": ("GZipBase64Binary", _cut_payload, POINTS + "its GZipBase64Binary "
                         "data do not decode (Error -5 while decompressing data: incomplete "
                         "or truncated stream)"),
    "base64 payload cut": ("Base64Binary", _cut_payload, POINTS + f"Dim0 × Dim1 = {N} × 3 = "
                           f"{3 * N} values of NIFTI_TYPE_FLOAT32 = {12 * N} bytes, its data "
                           f"hold {12 * N - 12} bytes"),
    "base64 padding cut": ("Base64Binary", lambda d: _cut_payload(d, 1, 1),
                           TRIANGLES + "its Base64Binary data do not decode (Incorrect "
                           "padding)"),
    "ascii value missing": ("ASCII", _drop_last_value, POINTS + f"Dim0 × Dim1 = {N} × 3 = "
                            f"{3 * N} values, its data hold {3 * N - 1}"),
    "Dim0 one more": ("GZipBase64Binary", lambda d: _dims(d, 0, 0, 1),
                      POINTS + f"Dim0 × Dim1 = {N + 1} × 3 = {3 * N + 3} values of "
                      f"NIFTI_TYPE_FLOAT32 = {12 * N + 12} bytes, its data hold {12 * N} "
                      "bytes"),
    "triangles' Dim0 one fewer": ("GZipBase64Binary", lambda d: _dims(d, 1, 0, -1),
                                  TRIANGLES + f"Dim0 × Dim1 = {F - 1} × 3 = {3 * F - 3} "
                                  f"values of NIFTI_TYPE_INT32 = {12 * F - 12} bytes, its "
                                  f"data hold {12 * F} bytes"),
    "Dim1 missing": ("GZipBase64Binary", lambda d: _dims(d, 1, 1, 0),
                     TRIANGLES + "its Dimensionality is 2, but it has no Dim1"),
}


@pytest.mark.parametrize("case", BAD_GIFTIS)
def test_a_gifti_with_corrupt_data_is_said_by_the_check_in_the_readers_words(tmp_path, case):
    encoding, corrupt, expected = BAD_GIFTIS[case]
    good = _gifti_bytes(encoding)
    bad = tmp_path / "bad.gii"
    bad.write_bytes(corrupt(good))
    said = _said(read_mesh, bad)
    assert said == f"{bad}: {expected}"
    assert _said(check_file, bad) == said
    # gzip-compressed, the same words
    bad_gz = tmp_path / "bad.gii.gz"
    bad_gz.write_bytes(gzip.compress(corrupt(good)))
    assert _said(check_file, bad_gz) == _said(read_mesh, bad_gz) == f"{bad_gz}: {expected}"


@pytest.mark.parametrize("encoding", ["GZipBase64Binary", "Base64Binary", "ASCII"])
def test_a_good_gifti_of_each_encoding_passes(tmp_path, encoding):
    good = tmp_path / "good.gii"
    # line breaks in the payload, as some writers wrap base64, and a '>' in a quoted
    # attribute value: the reader takes them
    data = _gifti_bytes(encoding).replace(b"<Data>", b"<Data>\n", 1)
    good.write_bytes(data.replace(b'ExternalFileName=""', b'ExternalFileName="a>b"', 1))
    assert len(read_mesh(good)[0]) == N
    assert check_file(good) is None


def test_a_gifti_overlay_with_wrong_dimensions_is_said_by_check_overlay(tmp_path):
    def wrong_dims(path: Path, n: int) -> None:
        values = nib.gifti.GiftiDataArray(np.linspace(1, 3, n).astype(np.float32),
                                          intent="NIFTI_INTENT_SHAPE")
        path.write_bytes(_dims(nib.gifti.GiftiImage(darrays=[values]).to_bytes(), 0, 0, 2))

    surface, overlay = _surface_and_overlay(tmp_path, ("lh.pial.thickness.shape.gii",
                                                       wrong_dims))
    said = _said(lambda p: read_mesh_data(surface, overlays=[p]), overlay)
    n = len(read_mesh(surface)[0])
    assert said == (f"{overlay}: GIFTI DataArray 0 (NIFTI_INTENT_SHAPE) is corrupt: Dim0 = "
                    f"{n + 2} = {n + 2} values of NIFTI_TYPE_FLOAT32 = {4 * n + 8} bytes, its "
                    f"data hold {4 * n} bytes")
    assert _said(check_overlay, overlay) == said


# ------------------------------------------------- a .gii.gz cut short, a .gii cut at a tag


@pytest.mark.parametrize("cut", [8, 1, "half"])
def test_a_gzip_gifti_cut_short_is_said_by_the_check(tmp_path, monkeypatch, cut):
    whole = tmp_path / "whole.gii.gz"
    write_mesh(whole, *sphere(4))
    data = whole.read_bytes()
    assert len(data) > 1 << 13  # past the head the check reads first
    cut_short = tmp_path / "cut.gii.gz"
    cut_short.write_bytes(data[:len(data) // 2] if cut == "half" else data[:-cut])
    said = _said(read_mesh, cut_short)
    assert said == f"{cut_short}: corrupt gzip data (EOFError: Compressed file ended before " \
        "the end-of-stream marker was reached)"
    given = _count_reads(monkeypatch)
    assert _said(check_file, cut_short) == said
    assert given == [1 << 13, cut_short.stat().st_size], given  # its head, then all of it


@pytest.mark.parametrize("tag", [b"</DataArray>", b"</Data>", b"</MatrixData>",
                                 b"</CoordinateSystemTransformMatrix>"])
def test_a_gifti_cut_just_after_a_tag_is_said_by_the_check(tmp_path, tag):
    # session 42's check looked for the closing tag in the last 4 KiB and let a file whose
    # last bytes end with '>' pass (a long comment may follow the root there)
    whole = tmp_path / "whole.gii"
    write_mesh(whole, *sphere(4))
    data = whole.read_bytes()
    for at in (data.index(tag) + len(tag), data.rindex(tag) + len(tag)):
        cut_short = tmp_path / "cut.gii"
        cut_short.write_bytes(data[:at])
        said = _said(read_mesh, cut_short)
        assert said == f"{cut_short}: GIFTI file is truncated (it does not end with its " \
            "closing tag </GIFTI>)"
        assert _said(check_file, cut_short) == said


# ------------------------------------------------------------ an .annot's colour table


def _table_at(n: int) -> int:
    """Where an ``.annot`` of ``n`` vertices' colour table starts: its flag."""
    return 4 + 8 * n


def _entry_at(data: bytes, n: int, k: int) -> int:
    """Where entry ``k`` of a version-2 colour table starts (its index)."""
    at = _table_at(n) + 12  # flag, -2, the table's size
    at += 4 + struct.unpack_from(">i", data, at)[0] + 4  # the table's file name, the count
    for _ in range(k):
        at += 8 + struct.unpack_from(">i", data, at + 4)[0] + 16
    return at


def _put(data: bytes, at: int, value: int) -> bytes:
    return data[:at] + struct.pack(">i", value) + data[at + 4:]


TABLE = "FreeSurfer annotation's colour table"
# each: the corruption of a good .annot's bytes (n vertices), what the reader and check say
BAD_TABLES = {
    "cut in its last entry": (lambda d, n: d[:-1], f"{TABLE} is truncated (entry 2 of 3 runs "
                              "past the end of the file)"),
    "cut in its header": (lambda d, n: d[:_table_at(n) + 14], f"{TABLE} is truncated (its "
                          "header runs past the end of the file)"),
    "no table": (lambda d, n: _put(d, _table_at(n), 0), "FreeSurfer annotation has no colour "
                 "table (its flag after the labels is 0)"),
    "version 3": (lambda d, n: _put(d, _table_at(n) + 4, -3), f"{TABLE} is of version 3 "
                  "(versions 2 and the old format are read)"),
    "an index past the table": (lambda d, n: _put(d, _entry_at(d, n, 1), 7),
                                f"{TABLE} entry 1 has index 7, outside 0 to 2 (the table "
                                "announces 3 entries)"),
    "a negative index": (lambda d, n: _put(d, _entry_at(d, n, 2), -1),
                         f"{TABLE} entry 2 has index -1, outside 0 to 2 (the table announces "
                         "3 entries)"),
    "a negative name length": (lambda d, n: _put(d, _entry_at(d, n, 1) + 4, -5),
                               f"{TABLE} is corrupt (entry 1 of 3 has a name of -5 bytes)"),
    "a name past the end": (lambda d, n: _put(d, _entry_at(d, n, 0) + 4, 1 << 20),
                            f"{TABLE} is truncated (entry 0 of 3 runs past the end of the "
                            "file)"),
}


@pytest.mark.parametrize("case", BAD_TABLES)
def test_an_annot_with_a_bad_colour_table_is_said_by_check_overlay(tmp_path, case):
    corrupt, expected = BAD_TABLES[case]

    def bad_annot(path: Path, n: int) -> None:
        _annot(path, n)
        path.write_bytes(corrupt(path.read_bytes(), n))

    surface, overlay = _surface_and_overlay(tmp_path, ("lh.aparc.annot", bad_annot))
    said = _said(lambda p: read_mesh_data(surface, overlays=[p]), overlay)
    assert said == f"{overlay}: {expected}"
    assert _said(check_overlay, overlay) == said


def _old_format_annot(path: Path, n: int) -> None:
    """An ``.annot`` with an old-format colour table (its entry count, then each entry's
    name and colour), as nibabel reads it."""
    ints = lambda *values: struct.pack(f">{len(values)}i", *values)  # noqa: E731
    labels = np.column_stack([np.arange(n), np.full(n, 255)]).astype(">i4").tobytes()
    table = ints(1, 2) + ints(5) + b"none\0"
    table += ints(4) + b"red\0" + ints(255, 0, 0, 0) + ints(5) + b"blue\0" + ints(0, 0, 255, 0)
    path.write_bytes(ints(n) + labels + table)


def test_good_annots_pass_and_the_check_reads_the_head_and_the_table_only(tmp_path,
                                                                          monkeypatch):
    for name, make in (("lh.new.annot", _annot), ("lh.old.annot", _old_format_annot)):
        surface, overlay = _surface_and_overlay(tmp_path / name, (name, make))
        labels = read_mesh_data(surface, overlays=[overlay]).attributes[name[3:-6]]
        assert len(labels) == len(read_mesh(surface)[0])
        assert check_overlay(overlay) is None
    # the old format cut in its last entry: said too
    overlay.write_bytes(overlay.read_bytes()[:-3])
    assert _said(check_overlay, overlay) == f"{overlay}: {TABLE} is truncated (entry 1 of 2 " \
        "runs past the end of the file)"
    # an .annot larger than the head read: its labels are not read, its table is
    large = tmp_path / "lh.large.annot"
    _annot(large, 5000)
    given: list[int] = []
    opened = builtins.open

    def counting(*args, **kwargs):
        fh = opened(*args, **kwargs)
        real = fh.read
        fh.read = lambda n=-1: given.append(len(data := real(n))) or data
        return fh

    monkeypatch.setattr(brain_checks, "open", counting, raising=False)
    check_overlay(large)
    assert given == [1 << 13, large.stat().st_size - _table_at(5000)], given


# ----------------------------------------------------- a large OBJ whose last line is cut


def _large_obj(path: Path) -> bytes:
    """An OBJ of a holed sphere larger than the 256 KiB the check reads whole."""
    write_mesh(path, *_holed(5))
    data = path.read_bytes()
    assert len(data) > 1 << 18 and data.endswith(b"\n")
    return data


def _cut_face(data: bytes) -> bytes:
    """The last face line left with two corners, and no newline after it."""
    return data.rstrip(b"\n").rsplit(b" ", 1)[0]


def _cut_vertex(data: bytes) -> bytes:
    """Cut in the last vertex line, after its second coordinate."""
    at = data.rindex(b"\nv ", 0, data.index(b"\nf ")) + 1
    return data[:data.index(b" ", data.index(b" ", at) + 1)]


CUT_OBJS = {
    "a face of two corners": (_cut_face, "a face with fewer than three corners"),
    "a vertex of two coordinates": (_cut_vertex, "a vertex with fewer than three coordinates"),
    "a coordinate cut after its e": (lambda d: d + b"v 0.5 0.25 1.5e",
                                     "a vertex with a coordinate that is not a number"),
}


@pytest.mark.parametrize("case", CUT_OBJS)
def test_a_large_obj_ending_in_a_line_cut_short_is_said_by_the_check(tmp_path, monkeypatch,
                                                                     case):
    corrupt, problem = CUT_OBJS[case]
    data = corrupt(_large_obj(tmp_path / "whole.obj"))
    cut = tmp_path / "cut.obj"
    cut.write_bytes(data)
    last, line = data[data.rindex(b"\n") + 1:].decode(), data.count(b"\n") + 1
    said = _said(read_mesh, cut)
    assert said == (f"{cut}: OBJ file ends in a line cut short (line {line}, with no newline "
                    f"after it, is {problem}: {last!r})")
    given = _count_reads(monkeypatch)
    assert _said(check_file, cut) == said
    # its head and its last 4 KiB, then (the last line cut) all of it for the line's number
    assert given == [1 << 13, 1 << 12, len(data)], given


def test_a_large_obj_ending_without_a_newline_passes(tmp_path, monkeypatch):
    data = _large_obj(tmp_path / "whole.obj")
    for ending in (b"", b" # the last face", b"\n# notes, no newline", b"\nf"):
        path = tmp_path / "open_end.obj"
        path.write_bytes(data.rstrip(b"\n") + ending)
        read_mesh(path)
        given = _count_reads(monkeypatch)
        assert check_file(path) is None
        assert given == [1 << 13, 1 << 12], given
        monkeypatch.undo()


# ------------------------------------------------ a batch fails them first; fill says them


def _bad_inputs(folder: Path) -> dict[str, str]:
    """A bad file of each kind above in ``folder``: name -> what the reader says."""
    folder.mkdir(parents=True, exist_ok=True)
    gifti = _gifti_bytes()
    write_mesh(folder / "ok.gii.gz", *sphere(4))
    files = {"corrupt.gii": _dims(gifti, 0, 0, 1),
             "cut_at_a_tag.gii": gifti[:gifti.rindex(b"</DataArray>") + 12],
             "cut.gii.gz": (folder / "ok.gii.gz").read_bytes()[:-8],
             "cut.obj": _cut_face(_large_obj(folder / "whole.obj"))}
    (folder / "ok.gii.gz").unlink()
    (folder / "whole.obj").unlink()
    for name, data in files.items():
        (folder / name).write_bytes(data)
    return {name: _said(read_mesh, folder / name) for name in files}


def test_a_batch_fails_each_before_any_fill_with_the_readers_words(tmp_path, monkeypatch):
    scans = tmp_path / "scans"
    expected = _bad_inputs(scans)
    write_mesh(scans / "good.gii", *_holed())
    before = {p: p.read_bytes() for p in scans.iterdir()}
    events, failed = _batch_events(monkeypatch, scans, tmp_path / "out")
    bad = sorted(str(scans / name) for name in expected)
    assert sorted(events[:len(bad)]) == [f"failed {name}" for name in bad], events
    assert events[len(bad):] == [f"fill {scans / 'good.gii'}", f"filled {scans / 'good.gii'}"]
    assert failed == {str(scans / name): said for name, said in expected.items()}
    assert {p: p.read_bytes() for p in scans.iterdir()} == before  # inputs untouched
    written = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert written == ["good.gii", "summary.csv", "summary.json"], written


def test_a_batch_fails_an_annot_with_a_cut_colour_table_before_any_fill(tmp_path,
                                                                        monkeypatch):
    subjects = tmp_path / "subjects"

    def cut_table(path: Path, n: int) -> None:
        _annot(path, n)
        path.write_bytes(path.read_bytes()[:-1])

    _, bad = _surface_and_overlay(subjects / "sub-bad", ("lh.aparc.annot", cut_table))
    _surface_and_overlay(subjects / "sub-good", ("lh.aparc.annot", _annot))
    events, failed = _batch_events(monkeypatch, subjects, tmp_path / "out",
                                   overlays=["../label/{hemi}.aparc.annot"])
    surface = str(subjects / "sub-bad" / "surf" / "lh.pial")
    assert events[0] == f"failed {surface}", events
    assert failed == {surface: f"{surface}: {bad}: {TABLE} is truncated (entry 2 of 3 runs "
                      "past the end of the file)"}


def test_fill_says_each_in_the_readers_words_exits_1_and_writes_nothing(tmp_path, capsys):
    scans = tmp_path / "scans"
    expected = _bad_inputs(scans)
    for name, words in {"corrupt.gii": POINTS, "cut_at_a_tag.gii": "GIFTI file is truncated",
                        "cut.gii.gz": "corrupt gzip data", "cut.obj": "a line cut short"}.items():
        assert words in expected[name]
    before = sorted(p.name for p in tmp_path.rglob("*"))
    for name, said in expected.items():
        out = tmp_path / f"filled-{name}"
        code = main(["fill", str(scans / name), "-o", str(out), "--method", "fair", "-q"])
        err = capsys.readouterr().err
        assert code == 1, err
        assert "".join(said.split()) in "".join(err.split()), err
        assert "Traceback" not in err
    assert sorted(p.name for p in tmp_path.rglob("*")) == before  # nothing written


def test_fill_says_an_annot_overlays_cut_colour_table_and_exits_1(tmp_path, capsys):
    def cut_table(path: Path, n: int) -> None:
        _annot(path, n)
        path.write_bytes(path.read_bytes()[:_table_at(n) + 14])

    surface, overlay = _surface_and_overlay(tmp_path, ("lh.aparc.annot", cut_table))
    out = tmp_path / "lh.filled.pial"
    code = main(["fill", str(surface), "--overlay", str(overlay), "-o", str(out), "--method",
                 "fair", "-q"])
    err = "".join(capsys.readouterr().err.split())
    assert code == 1, err
    assert "".join(f"{overlay}: {TABLE} is truncated (its header runs past the end of the "
                   "file)".split()) in err, err
    assert not out.exists()
