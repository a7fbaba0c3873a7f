"""The one atomic writer: complete files or nothing, normal permissions, used by every writer."""

import os
import re
from pathlib import Path

import pytest

import surfinpaint
from surfinpaint.io.atomic import atomic_open, atomic_path, new_file_mode


def _umask_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


@pytest.mark.parametrize("exc", [RuntimeError("injected"), KeyboardInterrupt()])
def test_failure_keeps_the_old_file_and_leaves_no_temporary(tmp_path, exc):
    target = tmp_path / "out.txt"
    target.write_text("old")
    with pytest.raises(type(exc)):
        with atomic_open(target, "w") as handle:
            handle.write("new, half written")
            raise exc
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]


def test_failure_on_a_new_file_leaves_nothing(tmp_path):
    with pytest.raises(RuntimeError):
        with atomic_path(tmp_path / "fig.png", suffix=".png") as tmp:
            Path(tmp).write_bytes(b"partial")
            raise RuntimeError("injected")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("writer", ["atomic_open", "atomic_path"])
def test_the_content_reaches_the_disk_before_the_rename(tmp_path, monkeypatch, writer):
    # a crash must find the old file or the whole new one: the temporary file's data is
    # fsynced (the inode renamed, at its full size) before os.replace moves it into place
    events = []
    fsync, replace = os.fsync, os.replace

    def recording_fsync(fd):
        events.append(("fsync", os.fstat(fd).st_ino, os.fstat(fd).st_size))
        fsync(fd)

    def recording_replace(src, dst):
        events.append(("replace", os.stat(src).st_ino, os.stat(src).st_size))
        replace(src, dst)

    monkeypatch.setattr(os, "fsync", recording_fsync)
    monkeypatch.setattr(os, "replace", recording_replace)
    target = tmp_path / "out.bin"
    if writer == "atomic_open":
        with atomic_open(target) as handle:
            handle.write(b"12345")
    else:
        with atomic_path(target) as tmp:
            Path(tmp).write_bytes(b"12345")
    inode = target.stat().st_ino
    assert events == [("fsync", inode, 5), ("replace", inode, 5)]
    assert target.read_bytes() == b"12345"


def test_a_read_only_target_is_replaced(tmp_path, monkeypatch):
    # the temporary file is synced while it is still the writer's own (0o600): given the
    # target's read-only mode first, a user who is not root could not open it to fsync it
    # (simulated here, as root may open anything)
    real_open = os.open

    def permission_checked_open(path, flags, *args, **kwargs):
        writes = flags & (os.O_WRONLY | os.O_RDWR)
        if writes and os.path.exists(path) and not os.stat(path).st_mode & 0o200:
            raise PermissionError(13, "Permission denied", path)
        return real_open(path, flags, *args, **kwargs)

    monkeypatch.setattr(os, "open", permission_checked_open)
    target = tmp_path / "frozen.txt"
    target.write_text("old")
    target.chmod(0o444)
    with atomic_open(target, "w") as handle:
        handle.write("new")
    assert target.read_text() == "new"
    assert target.stat().st_mode & 0o777 == 0o444


def test_success_replaces_with_normal_mode_and_keeps_an_existing_mode(tmp_path):
    new = tmp_path / "new.bin"
    with atomic_open(new) as handle:
        handle.write(b"\x00\x01")
    assert new.read_bytes() == b"\x00\x01"
    assert new.stat().st_mode & 0o777 == _umask_mode() == new_file_mode()
    old = tmp_path / "old.txt"
    old.write_text("a")
    old.chmod(0o640)
    with atomic_open(old, "w") as handle:
        handle.write("b")
    assert old.read_text() == "b" and old.stat().st_mode & 0o777 == 0o640
    assert [p.name for p in sorted(tmp_path.iterdir())] == ["new.bin", "old.txt"]


def test_only_the_atomic_module_creates_temporary_files_or_reads_the_umask():
    root = Path(surfinpaint.__file__).parent
    pattern = re.compile(r"mkstemp|NamedTemporaryFile|os\.replace|os\.rename|os\.umask")
    users = sorted(str(p.relative_to(root)) for p in root.rglob("*.py")
                   if pattern.search(p.read_text(encoding="utf-8")))
    assert users == [os.path.join("io", "atomic.py")]
