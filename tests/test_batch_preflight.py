"""``batch``'s pre-flight (session 41): every input about to be filled is checked cheaply
first (:func:`surfinpaint.io.formats.check_file`: it exists, can be read, is not empty, has
a known format whose header parses), and a bad one is reported at once, named with why,
before any file is filled, not when the largest-first order reaches it."""

from __future__ import annotations

import gzip
import io
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import mark_fill_starts

from surfinpaint.app import batch, batch_listing
from surfinpaint.app.batch_inputs import UnknownFilesWarning
from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.errors import MeshError
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.io.base import RenumberedWarning
from surfinpaint.io.brain import check_overlay
from surfinpaint.io.formats import check_file, read_mesh, read_mesh_data, write_mesh


def _good_mesh():
    v, f = sphere(1)
    cut = cut_geodesic_disk(v, f, 0, 0.6)
    return cut.vertices, cut.faces


def _written(path: Path, ascii: bool = False) -> bytes:
    if path.suffix == ".stl":  # said, and expected: STL keeps no vertex order
        with pytest.warns(RenumberedWarning, match="renumbered by first use"):
            write_mesh(path, *_good_mesh(), ascii=ascii)
    else:
        write_mesh(path, *_good_mesh(), ascii=ascii)
    return path.read_bytes()


def _freesurfer_cut(path: Path) -> bytes:
    return _written(path)[:200]


def _stl_cut(path: Path) -> bytes:
    data = _written(path)
    return data[:len(data) // 2]


# name: how its bytes are made (from a scratch path of that name), the reader's reason
BAD_FILES = {
    "empty.ply": (lambda p: b"", "file is empty"),
    "truncated_header.ply": (lambda p: _written(p)[:40], "PLY header has no 'end_header'"),
    "points.ply": (lambda p: b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                   b"property float y\nproperty float z\nend_header\n0 0 0\n",
                   "PLY file has no face element"),
    "really_a_ply.stl": (lambda p: b"ply\nformat ascii 1.0\n" + b"0 " * 100,
                         "not an STL file"),
    "half.stl": (_stl_cut, "truncated binary STL"),
    "counts.off": (lambda p: b"OFF\nx y z\n", "bad count line"),
    "binary.off": (lambda p: b"OFF\n3 1 0\n\x00\x01", "not a text OFF file"),
    "lh.pial": (_freesurfer_cut, "FreeSurfer surface is truncated"),
    "rh.white": (lambda p: b"not a surface at all", "not a FreeSurfer surface"),
    # session 41 (second): a text file named .obj or .gii, an OBJ of points, an HTML page
    "readme.obj": (lambda p: b"# notes\nThis folder holds the scans of May.\n" * 20,
                   "OBJ file has no vertices (no 'v' line)"),
    "points.obj": (lambda p: b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "OBJ file has no faces"),
    "binary.obj": (lambda p: b"v 0 0 0\n\x00\x01\x02", "not a text OBJ file"),
    "readme.gii": (lambda p: b"Surfaces of subject 3, see below.\n", "not a GIFTI file (not XML"),
    "page.gii": (lambda p: b"<?xml version='1.0'?>\n<!-- saved -->\n<html><body/></html>",
                 "its XML root element is <html>, not <GIFTI>"),
    "readme.gii.gz": (lambda p: gzip.compress(b"Surfaces of subject 3.\n"),
                      "not a GIFTI file (not XML"),
    "empty_root.gii": (lambda p: b"<?xml version='1.0'?><GIFTI Version='1.0'></GIFTI>",
                       "GIFTI file has no DataArray"),
}


def _make(root: Path, name: str) -> Path:
    make, _ = BAD_FILES[name]
    path = root / name
    scratch = root / "scratch" / name
    scratch.parent.mkdir(exist_ok=True)
    path.write_bytes(make(scratch))
    return path


@pytest.mark.parametrize("name", list(BAD_FILES))
def test_check_file_says_what_the_reader_says_word_for_word(tmp_path, name):
    path = _make(tmp_path, name)
    with pytest.raises(MeshError) as checked:
        check_file(path)
    with pytest.raises(MeshError) as read:
        read_mesh(path)
    assert str(checked.value) == str(read.value)
    assert str(checked.value).startswith(f"{path}: ") and BAD_FILES[name][1] in str(read.value)


@pytest.mark.parametrize("case, said", [
    ("missing", "no such file"), ("folder", "is a directory"),
    ("unknown extension", "unknown mesh format '.xyz'"),
    ("unreadable", "permission denied")])
def test_check_file_says_a_file_it_cannot_open_as_the_reader_does(tmp_path, monkeypatch,
                                                                 case, said):
    path = {"missing": tmp_path / "gone.ply", "folder": tmp_path / "dir.ply",
            "unknown extension": tmp_path / "scan.xyz",
            "unreadable": tmp_path / "locked.ply"}[case]
    if case == "folder":
        path.mkdir()
    elif case != "missing":
        _written(tmp_path / "locked.ply")
        if case == "unknown extension":
            (tmp_path / "locked.ply").rename(path)
    if case == "unreadable":  # root reads any file: the denial is made
        def denied(self, *args, **kwargs):
            raise PermissionError(13, "Permission denied")

        monkeypatch.setattr(type(path), "open", denied)
    with pytest.raises(MeshError) as checked:
        check_file(path)
    with pytest.raises(MeshError) as read:
        read_mesh(path)
    assert str(checked.value) == str(read.value) and said in str(checked.value)


@pytest.mark.parametrize("name, ascii", [
    ("a.ply", False), ("a.ply", True), ("a.obj", False), ("a.stl", False), ("a.stl", True),
    ("a.off", False), ("a.gii", False), ("a.gii.gz", False), ("lh.pial", False)])
def test_check_file_passes_every_good_file(tmp_path, name, ascii):
    path = tmp_path / name
    _written(path, ascii=ascii)
    read_mesh(path)  # the reader takes it
    assert check_file(path) is None


def _count_reads(monkeypatch) -> list[int]:
    """The bytes each file opened by a ``Path`` gives its reader, from now on."""
    given: list[int] = []
    opened = Path.open

    def counting(self, *args, **kwargs):
        fh = opened(self, *args, **kwargs)
        real = fh.read

        def read(n=-1):
            data = real(n)
            given.append(len(data))
            return data

        fh.read = read
        return fh

    monkeypatch.setattr(Path, "open", counting)
    return given


def test_check_file_reads_only_the_head_of_a_large_file(tmp_path, monkeypatch):
    big = tmp_path / "big.ply"
    v, f = sphere(6)
    write_mesh(big, v, f)
    assert big.stat().st_size > 1 << 20  # larger than the most a check reads
    long_header = tmp_path / "comments.ply"  # a header past the first 8 KiB
    data = big.read_bytes()
    long_header.write_bytes(data.replace(b"\n", b"\n" + b"comment scanner notes\n" * 2000, 1))
    given = _count_reads(monkeypatch)
    check_file(big)
    assert sum(given) <= 1 << 13, given
    given.clear()
    check_file(long_header)
    assert 1 << 13 < sum(given) <= (1 << 13) + (1 << 20), given
    given.clear()
    read_mesh(long_header)  # the reader takes it whole
    assert sum(given) == long_header.stat().st_size


def test_check_file_reads_a_small_obj_whole_and_a_large_one_from_its_head(tmp_path,
                                                                          monkeypatch):
    small, large = tmp_path / "small.obj", tmp_path / "large.obj"
    write_mesh(small, *sphere(3))
    write_mesh(large, *sphere(6))
    assert (1 << 13) < small.stat().st_size < 1 << 18 < large.stat().st_size
    given = _count_reads(monkeypatch)
    check_file(small)  # its first 8 KiB (the format), then all of it for its v and f lines
    assert given == [1 << 13, small.stat().st_size], given
    given.clear()
    check_file(large)
    assert given == [1 << 13, 1 << 12], given  # its head, and its last line (session 43)
    # a text file with its only v and f lines past the first 8 KiB: no 'v' line in the head
    # is no failure, the lines are found in the whole
    late = tmp_path / "late.obj"
    late.write_bytes(b"# exported notes\n" * 1000 + small.read_bytes())
    assert late.stat().st_size > 1 << 13
    assert check_file(late) is None


def _surface_and_overlay(root: Path, make) -> tuple[Path, Path]:
    """A FreeSurfer surface ``surf/lh.pial`` and the overlay named by ``make``'s file in
    ``label/`` (``make(path, n)`` writes it for ``n`` vertices; None: it is missing)."""
    (root / "surf").mkdir(parents=True)
    (root / "label").mkdir()
    surface = root / "surf" / "lh.pial"
    _written(surface)
    name, write = make
    overlay = root / "label" / name
    if write is not None:
        write(overlay, len(read_mesh(surface)[0]))
    return surface, overlay


def _morph(path: Path, n: int) -> None:
    nib = pytest.importorskip("nibabel")
    nib.freesurfer.write_morph_data(str(path), np.linspace(1, 3, n).astype(np.float32))


def _shape_gii(path: Path, n: int) -> None:
    nib = pytest.importorskip("nibabel")
    image = nib.gifti.GiftiImage(darrays=[nib.gifti.GiftiDataArray(
        np.linspace(1, 3, n).astype(np.float32), intent="NIFTI_INTENT_SHAPE")])
    path.write_bytes(image.to_bytes())


# overlay: its file name, how it is written (None: missing), the reader's reason
BAD_OVERLAYS = {
    "missing": (("lh.thickness", None), "no such file"),
    "empty": (("lh.thickness", lambda p, n: p.write_bytes(b"")), "overlay file is empty"),
    "truncated": (("lh.thickness", lambda p, n: (_morph(p, n), p.write_bytes(
        p.read_bytes()[:100]))), "FreeSurfer overlay is truncated (its header announces"),
    "text as curv": (("lh.thickness", lambda p, n: p.write_text("thickness in mm\n")),
                     "not a FreeSurfer overlay (no FF FF FF magic bytes)"),
    "text as gifti": (("lh.thickness.shape.gii", lambda p, n: p.write_text("thickness\n")),
                      "not a GIFTI file (not XML"),
    "folder": (("lh.thickness", lambda p, n: p.mkdir()), "cannot read the overlay"),
}


@pytest.mark.parametrize("case", list(BAD_OVERLAYS))
def test_check_overlay_says_what_the_reader_says_word_for_word(tmp_path, case):
    make, said = BAD_OVERLAYS[case]
    surface, overlay = _surface_and_overlay(tmp_path, make)
    with pytest.raises(MeshError) as checked:
        check_overlay(overlay)
    with pytest.raises(MeshError) as read:
        read_mesh_data(surface, overlays=[overlay])
    assert str(checked.value) == str(read.value)
    assert str(read.value).startswith(f"{overlay}: ") and said in str(read.value)


@pytest.mark.parametrize("make", [("lh.thickness", _morph),
                                  ("lh.thickness.shape.gii", _shape_gii)])
def test_check_overlay_passes_a_good_overlay(tmp_path, make):
    surface, overlay = _surface_and_overlay(tmp_path, make)
    assert "thickness" in read_mesh_data(surface, overlays=[overlay]).attributes
    assert check_overlay(overlay) is None


def _batch_events(monkeypatch, folder: Path, out: Path, **options
                  ) -> tuple[list[str], dict[str, str]]:
    """``batch.fill_files([folder], out, **options)`` one file at a time, faired: what
    happened in order (``fill NAME`` as a fill starts, ``STATUS NAME`` as a row is said)
    and the failed rows' messages by path."""
    events: list[str] = []
    mark_fill_starts(monkeypatch, batch, lambda job: events.append(f"fill {job.name}"))
    rows = batch.fill_files([folder], out, jobs=1, method="fair", **options,
                            on_result=lambda row: events.append(f"{row.status} {row.path}"))
    return events, {r.path: r.message for r in rows if r.status == "failed"}


def test_a_batch_gives_a_bad_overlays_row_before_it_fills_any(tmp_path, monkeypatch):
    # batch --overlay: each surface's overlay checked in the pre-flight, its fill's words
    subjects = tmp_path / "subjects"
    for k, case in enumerate(["truncated", "text as curv"]):
        _surface_and_overlay(subjects / f"sub-bad{k}", BAD_OVERLAYS[case][0])
    for k in range(2):
        _surface_and_overlay(subjects / f"sub-good{k}", ("lh.thickness", _morph))
    inputs = sorted(subjects.glob("sub-*/surf/lh.pial"))

    def run(out: str) -> tuple[list[str], dict[str, str]]:
        # the text file named lh.thickness is no morphometry file: a stray, said
        with pytest.warns(UnknownFilesWarning, match="sub-bad1/label/lh.thickness"):
            return _batch_events(monkeypatch, subjects, tmp_path / out,
                                 overlays=["../label/{hemi}.thickness"])

    events, failed = run("out")
    bad = [str(p) for p in inputs if "sub-bad" in str(p)]
    assert events[:2] == [f"failed {name}" for name in bad], events
    assert all(e.startswith("fill ") or e.startswith("filled ") for e in events[2:]), events
    assert sorted(failed) == bad
    for name, (_, reason) in zip(bad, [BAD_OVERLAYS["truncated"],
                                          BAD_OVERLAYS["text as curv"]], strict=True):
        assert reason in failed[name], failed[name]
    # the same message as the fill gives without the pre-flight: one implementation
    monkeypatch.setattr(batch_listing, "checked_row", lambda job: None)
    unchecked_events, unchecked = run("out2")
    assert f"fill {bad[0]}" in unchecked_events  # now found when it is filled
    assert unchecked == failed


# a bad overlay the reader finds beside lh.pial: the subject's morphometry file, and one
# named after the surface (a text file named lh.thickness is no morphometry file: not read)
BESIDE = {"truncated lh.thickness": ("lh.thickness", "truncated"),
          "text lh.pial.thickness.shape.gii": ("lh.pial.thickness.shape.gii", "text as gifti")}


@pytest.mark.parametrize("case", BESIDE)
def test_a_batch_checks_the_overlays_beside_a_surface_without_overlay(tmp_path, monkeypatch,
                                                                      case):
    # no --overlay: the reader still reads the overlays beside lh.pial and fails the
    # surface on a bad one, so the pre-flight checks them too, in the reader's words
    name, kind = BESIDE[case]
    make = BAD_OVERLAYS[kind][0][1]
    subjects = tmp_path / "subjects"
    surface = _surface_and_overlay(subjects / "sub-good", ("lh.thickness", _morph))[0]
    bad = subjects / "sub-bad" / "surf" / "lh.pial"
    bad.parent.mkdir(parents=True)
    bad.write_bytes(surface.read_bytes())
    make(bad.parent / name, len(read_mesh(surface)[0]))

    events, failed = _batch_events(monkeypatch, subjects, tmp_path / "out")
    assert events[0] == f"failed {bad}", events
    assert list(failed) == [str(bad)] and BAD_OVERLAYS[kind][1] in failed[str(bad)]
    assert f"fill {bad}" not in events and f"fill {surface}" in events
    # the fill, unchecked, fails the surface with the same message
    monkeypatch.setattr(batch_listing, "checked_row", lambda job: None)
    unchecked_events, unchecked = _batch_events(monkeypatch, subjects, tmp_path / "out2")
    assert f"fill {bad}" in unchecked_events and unchecked == failed


def _batch_folder(root: Path) -> tuple[list[Path], list[Path]]:
    """Four good files and the bad ones (:data:`BAD_FILES`), the bad ones smaller (a good
    file is a sphere with a hole: larger than each bad one but the truncated STL, which is
    half of one): started last by the largest-first order; and a file of unknown type."""
    scans = root / "scans"
    scans.mkdir()
    good = [scans / f"good{k}.ply" for k in range(4)]
    for path in good:
        _written(path)
    bad = [_make(scans, name) for name in BAD_FILES]
    (scans / "scratch").rename(root / "scratch")  # not an input
    (scans / "notes.txt").write_text("a file of unknown type")
    return good, bad


@pytest.mark.parametrize("jobs", [1, 2])
def test_a_batch_gives_every_bad_files_row_before_it_fills_any(tmp_path, monkeypatch, jobs):
    good, bad = _batch_folder(tmp_path)
    events: list[str] = []
    if jobs == 1:  # filled in this process: each fill's start is seen
        mark_fill_starts(monkeypatch, batch,
                         lambda job: events.append(f"fill {Path(job.name).name}"))
    with pytest.warns(UnknownFilesWarning, match="notes.txt"):
        rows = batch.fill_files([tmp_path / "scans"], tmp_path / "out", jobs=jobs,
                                method="fair", on_result=lambda row: events.append(
                                    f"{row.status} {Path(row.path).name}"))
    n_bad = len(bad)
    # each bad file's row first, in the inputs' order, before any file is filled
    assert events[:n_bad] == [f"failed {p.name}" for p in sorted(bad)], events
    assert sorted(events[n_bad:]) == sorted(
        [f"filled {p.name}" for p in good] + ([f"fill {p.name}" for p in good] if jobs == 1
                                              else [])), events
    by_name = {Path(r.path).name: r for r in rows}
    for path in bad:  # the reader's own words: one implementation of each check
        with pytest.raises(MeshError) as read:
            read_mesh(path)
        assert by_name[path.name].message == str(read.value)
        assert not (tmp_path / "out" / path.name).exists()
    assert all((tmp_path / "out" / p.name).is_file() for p in good)


@pytest.mark.parametrize("quiet", [[], ["-q"]])
def test_the_command_says_each_bad_file_at_once_and_counts_it(tmp_path, capsys, monkeypatch,
                                                              quiet):
    monkeypatch.chdir(tmp_path)
    good, bad = _batch_folder(Path("."))
    mark_fill_starts(monkeypatch, batch,
                     lambda job: sys.stderr.write(f"\nstarting {job.name}\n"))
    monkeypatch.setattr(sys, "stdin", io.StringIO())
    capsys.readouterr()
    code = main(["batch", "scans", "-o", "out", "--jobs", "1", "--method", "fair", *quiet])
    lines = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert code == 1, lines
    first_fill = min(i for i, line in enumerate(lines) if line.startswith("starting "))
    errors = [f"error: {path}: {BAD_FILES[path.name][1]}" for path in sorted(bad)]
    said = [line for line in lines[:first_fill]]
    # the file of unknown type, then each bad file with why, all before the first fill
    assert said[0].startswith("warning: skipped 1 file of unknown type in scans: notes.txt")
    assert len(said) == 1 + len(bad), lines
    for line, start in zip(said[1:], errors, strict=True):
        assert line.startswith(start[:start.index(": ", 7) + 2]) and start.split(": ", 2)[2] \
            in line, (line, start)
    assert not any(line.startswith(("error: scans", "warning: ")) for line in lines[first_fill:])
    total = len(good) + len(bad)
    if quiet:
        assert lines[-1] == f"error: {len(bad)} of {total} files failed (each named above; " \
            "all in out/summary.csv)", lines
    else:
        assert lines[-1].startswith(f"{total} files: {len(good)} filled, 0 unfilled, 0 closed, "
                                    f"{len(bad)} failed, 0 skipped; 1 file of unknown type "), lines
