"""The one atomic writer of the package, and the one file-mode helper.

Every file surfinpaint writes (meshes, overlays, reports, figures, ``.npz`` representations)
goes through :func:`atomic_path` or :func:`atomic_open`: the content is written to a hidden
temporary file next to the target (``.NAME.XXXXXX.tmp``) and moved into place with
:func:`os.replace` only when it is complete. A failure (an exception, Ctrl-C) removes the
temporary file, so there is never a partial output, and an existing target is either fully
replaced or left as it was.

That holds across a crash of the system too (power loss, kernel panic): the temporary file is
fsynced before the rename, so the rename can never reach the disk ahead of the content (on a
filesystem that does not order the two, e.g. XFS, or ext4 mounted ``noauto_da_alloc``, the
target would otherwise come back empty or truncated). The directory is not fsynced after the
rename: after a crash the target may still be the old file, which is one of the two outcomes
promised; what is not promised is that a completed write survives a crash. The fsync is
14-21 ms of wall for the 651k case's 32 MB output (docs/scale.md, session 39).
"""

from __future__ import annotations

import os
import secrets
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO

__all__ = ["atomic_open", "atomic_path", "new_file_mode", "remove_unfinished"]


def new_file_mode(path: str | os.PathLike | None = None) -> int:
    """The permission bits a new output file gets.

    An existing ``path`` keeps its permissions; otherwise ``0o666`` minus the process umask,
    what a plain :func:`open` would give (``mkstemp`` creates files ``0o600``).
    """
    if path is not None:
        try:
            return os.stat(path).st_mode & 0o7777
        except OSError:
            pass
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


@contextmanager
def atomic_path(path: str | os.PathLike, *, suffix: str = ".tmp") -> Iterator[str]:
    """Yield the name of a temporary file that replaces ``path`` when the block succeeds.

    For writers that want a file name (matplotlib, VTK, nibabel); :func:`atomic_open` for a
    handle. When the block succeeds the file (which the block must have closed) is fsynced,
    given its permissions and renamed onto ``path``.

    Parameters
    ----------
    path : str or path-like
        The target. Its directory must exist.
    suffix : str, default ".tmp"
        End of the temporary name (e.g. ``".png"`` for writers that choose the format by it).

    Raises
    ------
    OSError
        When the temporary file cannot be created or moved into place; whatever the block
        raises is re-raised after the temporary file is removed.
    """
    target = Path(path)
    directory = target.parent if str(target.parent) else Path(".")
    tmp = _create_temporary(directory, target.name, suffix)
    try:
        yield tmp
        _sync(tmp)  # before the chmod: a read-only target's mode would refuse the open
        os.chmod(tmp, new_file_mode(target))
        os.replace(tmp, target)
    except BaseException:
        _remove(tmp)
        raise
    finally:
        _UNFINISHED.discard(tmp)


# Temporary files created and not yet renamed into place or removed. A name is added BEFORE
# its file is created, so that an interrupt landing anywhere (even inside the creation, or
# between it and the ``try`` that removes the file on failure) leaves it findable by
# remove_unfinished().
_UNFINISHED: set[str] = set()


def _create_temporary(directory: Path, name: str, suffix: str) -> str:
    """Create an empty, private (0o600) file ``.NAME.XXXXXXXX<suffix>`` in ``directory``."""
    for _ in range(100):
        tmp = os.path.join(directory, f".{name}.{secrets.token_hex(4)}{suffix}")
        _UNFINISHED.add(tmp)
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
        except FileExistsError:
            _UNFINISHED.discard(tmp)
            continue
        except OSError:  # not created
            _UNFINISHED.discard(tmp)
            raise
        # an interrupt from here on (or one raised as os.open returned) leaves the name
        # registered: remove_unfinished() finds the file
        os.close(fd)
        return tmp
    raise FileExistsError(f"no free temporary name for {name!r} in {str(directory)!r}")


def _sync(tmp: str) -> None:
    """Write the content of the (closed) file ``tmp``, still private and writable by its
    owner, to the disk before it is renamed."""
    # read-write: fsync needs a writable descriptor on some systems (Windows' _commit)
    fd = os.open(tmp, os.O_RDWR | getattr(os, "O_BINARY", 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _remove(tmp: str) -> None:
    try:
        os.unlink(tmp)
    except FileNotFoundError:
        pass


def remove_unfinished() -> list[str]:
    """Remove the temporary files of writes still under way, and return their names.

    For a process being stopped (Ctrl-C, SIGTERM): every write removes its own temporary
    file when an exception passes through it, but an interrupt can land in the few
    instructions between creating the file and entering that protection; the command line
    calls this before exiting so that no temporary file survives either way.
    """
    removed = sorted(_UNFINISHED)
    for tmp in removed:
        _remove(tmp)
    _UNFINISHED.difference_update(removed)
    return removed


@contextmanager
def atomic_open(path: str | os.PathLike, mode: str = "wb", *,
                encoding: str | None = None) -> Iterator[IO]:
    """Open a temporary file for writing that replaces ``path`` when the block succeeds.

    The handle is closed (flushed) and the file fsynced before the rename, as
    :func:`atomic_path` does for every writer. ``mode`` is ``"wb"`` or ``"w"`` (then
    ``encoding`` defaults to UTF-8). Raises as :func:`atomic_path`.
    """
    if mode not in ("wb", "w"):
        raise ValueError(f"atomic_open writes only, mode 'wb' or 'w', got {mode!r}")
    if mode == "w" and encoding is None:
        encoding = "utf-8"
    with atomic_path(path) as tmp:
        with open(tmp, mode, encoding=encoding) as handle:
            yield handle
