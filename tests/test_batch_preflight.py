"""``batch``'s pre-flight (session 41): every input about to be filled is checked cheaply
first (:func:`surfinpaint.io.formats.check_file`: it exists, can be read, is not empty, has
a known format whose header parses), and a bad one is reported at once, named with why,
before any file is filled, not when the largest-first order reaches it."""

from __future__ import annotations

import io
import sys
from pathlib import Path

import pytest

from surfinpaint.app import batch
from surfinpaint.app.cli import main
from surfinpaint.data import sphere
from surfinpaint.errors import MeshError
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.io.formats import check_file, read_mesh, write_mesh


def _good_mesh():
    v, f = sphere(1)
    cut = cut_geodesic_disk(v, f, 0, 0.6)
    return cut.vertices, cut.faces


def _written(path: Path, ascii: bool = False) -> bytes:
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
        filled = batch.fill_file

        def marked(job, options, hole_progress=None):
            events.append(f"fill {Path(job.name).name}")
            return filled(job, options, hole_progress)

        monkeypatch.setattr(batch, "fill_file", marked)
    rows = batch.fill_files([tmp_path / "scans"], tmp_path / "out", jobs=jobs, method="fair",
                            on_result=lambda row: events.append(
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
    filled = batch.fill_file

    def marked(job, options, hole_progress=None):
        sys.stderr.write(f"\nstarting {job.name}\n")
        return filled(job, options, hole_progress)

    monkeypatch.setattr(batch, "fill_file", marked)
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
