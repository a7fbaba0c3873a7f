"""Errors raised on bad input. Every message names what is wrong and where."""

from __future__ import annotations

from collections.abc import Sequence


class MeshError(ValueError):
    """A mesh that cannot be processed as given.

    Attributes name the offending elements so callers (and the CLI) can report them:
    ``path`` (the file, if any), ``vertices``, ``edges`` and ``faces`` (ids, possibly
    truncated lists).
    """

    def __init__(
        self,
        message: str,
        *,
        path: str | None = None,
        vertices: Sequence[int] = (),
        edges: Sequence[tuple[int, int]] = (),
        faces: Sequence[int] = (),
    ) -> None:
        self.path = path
        self.vertices = list(vertices)
        self.edges = list(edges)
        self.faces = list(faces)
        self.message = message
        super().__init__(self._text())

    def _text(self) -> str:
        return f"{self.path}: {self.message}" if self.path else self.message

    def with_path(self, path: str) -> MeshError:
        """The same error, naming the file it came from."""
        err = type(self)(self.message, path=str(path), vertices=self.vertices,
                         edges=self.edges, faces=self.faces)
        return err


class MissingFileError(MeshError, FileNotFoundError):
    """A mesh, overlay or representation file that does not exist: a :class:`MeshError`
    (the CLI's message and exit code) that ``except FileNotFoundError`` catches too."""

    def __init__(self, path: str) -> None:
        super().__init__("no such file", path=path)
        self.filename = path

    def __str__(self) -> str:  # MeshError's text, not OSError's "[Errno ...]"
        return self._text()

    def with_path(self, path: str) -> MissingFileError:
        return MissingFileError(str(path))


class InputError(ValueError):
    """A command's inputs that cannot be run as given, found before any file is read: a
    folder with no mesh file, two inputs whose outputs would be one file, an output that
    would overwrite its input, a bad ``--overlay`` pattern. The message says which."""


class FillError(RuntimeError):
    """A hole could not be filled by the requested method (the caller may fall back)."""


class HoleWarning(UserWarning):
    """One hole's fill is not what was asked: the hole was skipped, its fill failed, or the
    λ-H fill fell back to a faired fill. Its :class:`~surfinpaint.fill.results.HoleReport`
    says the same, so ``surfinpaint fill`` prints it in that hole's lines, not again at the
    end."""


# what a numerical step raises when it fails: FillError is a RuntimeError, MeshError and
# numpy's LinAlgError are ValueErrors (scipy's singular factorizations raise RuntimeError)
NUMERICAL_ERRORS = (ValueError, RuntimeError)


def agreeing(n: int, one: str, many: str) -> str:
    """The words of ``one`` and ``many`` that agree with the count ``n``: ``one`` for 1,
    ``many`` for any other count (0 too: "0 faces"). The one rule every count and noun
    of a message follows (:func:`how_many`); alone where the count is a list after the
    words, as in ``f"vertices {preview(ids)}"``: ``agreeing(len(ids), "vertex",
    "vertices")``."""
    return one if n == 1 else many


def how_many(n: int, one: str, many: str) -> str:
    """``n`` and the words that agree with it (:func:`agreeing`): ``how_many(1, "face has",
    "faces have")`` is ``"1 face has"``, with 3 ``"3 faces have"``."""
    return f"{n} {agreeing(n, one, many)}"


def mesh_size(n_vertices: int, n_faces: int) -> str:
    """A mesh's size in words, each count agreeing with its noun (:func:`how_many`):
    ``"1 vertex, 0 faces"``, ``"3 vertices, 1 face"``."""
    return f"{how_many(n_vertices, 'vertex', 'vertices')}, {how_many(n_faces, 'face', 'faces')}"


def preview(ids: Sequence, limit: int = 10) -> str:
    """Short text for a list of ids: the first ``limit`` and how many more."""
    ids = list(ids)
    head = ", ".join(str(i) for i in ids[:limit])
    more = f" and {len(ids) - limit} more" if len(ids) > limit else ""
    return f"{head}{more}"
