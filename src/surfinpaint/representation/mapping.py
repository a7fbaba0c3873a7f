"""The conformal map of a disk that both λ-H discretizations start from."""

from __future__ import annotations

import warnings

import numpy as np

from surfinpaint.errors import MeshError, preview
from surfinpaint.geometry.parameterization import flipped_faces, lscm, rectangular_conformal_map

__all__ = ["FoldedMapWarning", "MAPS", "parameterize"]

MAPS = ("rectangular", "lscm")


class FoldedMapWarning(UserWarning):
    """The conformal map folds some triangles over (see
    :func:`~surfinpaint.geometry.parameterization.flipped_faces`)."""


def parameterize(vertices: np.ndarray, faces: np.ndarray, map: str = "rectangular", *,
                 strict: bool = False,
                 corners: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(uv, corners)`` of the named conformal map (``corners`` empty for LSCM).

    Folded (flipped) parameter triangles make the grid sampling ambiguous there; a few of
    them (they come from obtuse triangles on ragged boundaries) only disturb the sampling
    locally, so by default they give a :class:`FoldedMapWarning`.

    ``corners`` (rectangular map only) fixes the four corner vertices.

    Raises
    ------
    ValueError
        For an unknown map name.
    MeshError
        When the mesh is not a disk, or, with ``strict``, when the map folds (names the
        flipped faces).
    """
    if map == "rectangular":
        uv, corners = rectangular_conformal_map(vertices, faces, corners)
    elif map == "lscm":
        uv, corners = lscm(vertices, faces), np.zeros(0, dtype=np.int64)
    else:
        raise ValueError(f"unknown conformal map {map!r}; choose from {MAPS}")
    flipped = flipped_faces(faces, uv)
    if len(flipped):
        message = (f"the {map} map folds {len(flipped)} of {len(faces)} triangles over "
                   f"(faces {preview(flipped)}); the mesh probably has badly shaped "
                   "triangles there")
        if strict:
            raise MeshError(message, faces=flipped[:100])
        warnings.warn(message, FoldedMapWarning, stacklevel=3)
    return uv, corners
