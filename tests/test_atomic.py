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
