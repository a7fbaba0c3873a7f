"""The one atomic writer of the package, and the one file-mode helper.

Every file surfinpaint writes (meshes, overlays, reports, figures, ``.npz`` representations)
goes through :func:`atomic_path` or :func:`atomic_open`: the content is written to a hidden
temporary file next to the target (``.NAME.XXXXXX.tmp``) and moved into place with
:func:`os.replace` only when it is complete. A failure (an exception, Ctrl-C) removes the
temporary file, so there is never a partial output, and an existing target is either fully
replaced or left as it was.
"""

from __future__ import annotations

import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import IO

__all__ = ["atomic_open", "atomic_path", "new_file_mode"]


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
    handle.

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
    fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=suffix, dir=directory)
    os.close(fd)
    try:
        yield tmp
        os.chmod(tmp, new_file_mode(target))
        os.replace(tmp, target)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise


@contextmanager
def atomic_open(path: str | os.PathLike, mode: str = "wb", *,
                encoding: str | None = None) -> Iterator[IO]:
    """Open a temporary file for writing that replaces ``path`` when the block succeeds.

    The handle is flushed and fsynced before the rename. ``mode`` is ``"wb"`` or ``"w"``
    (then ``encoding`` defaults to UTF-8). Raises as :func:`atomic_path`.
    """
    if mode not in ("wb", "w"):
        raise ValueError(f"atomic_open writes only, mode 'wb' or 'w', got {mode!r}")
    if mode == "w" and encoding is None:
        encoding = "utf-8"
    with atomic_path(path) as tmp:
        with open(tmp, mode, encoding=encoding) as handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
