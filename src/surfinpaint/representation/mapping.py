"""The conformal map of a disk that both λ-H discretizations start from."""

from __future__ import annotations

import warnings

import numpy as np

from surfinpaint.errors import MeshError, agreeing, how_many, preview
from surfinpaint.geometry import mean_value
from surfinpaint.geometry.parameterization import flipped_faces, lscm, rectangular_conformal_map

__all__ = ["FoldedMapWarning", "MAPS", "parameterize"]

MAPS = ("rectangular", "lscm")


class FoldedMapWarning(UserWarning):
    """The conformal map folds some triangles over (see
    :func:`~surfinpaint.geometry.parameterization.flipped_faces`)."""


def parameterize(vertices: np.ndarray, faces: np.ndarray, map: str = "rectangular", *,
                 strict: bool = False, untangle: bool = False,
                 corners: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(uv, corners)`` of the named conformal map (``corners`` empty for LSCM).

    Folded (flipped) parameter triangles make the grid sampling ambiguous there; a few of
    them (they come from obtuse triangles on ragged boundaries) only disturb the sampling
    locally, so by default they give a :class:`FoldedMapWarning`.

    With ``untangle``, a map that folds is untangled locally
    (:func:`~surfinpaint.geometry.mean_value.untangle`: the vertices of the flipped triangles
    and a few rings around them placed again by mean-value weights, the rest unchanged) and
    the warning says so; where that cannot untangle it (a fold at the border), the map is
    kept as it is. The mesh λ-H form needs no conformal map, only one without folds (its
    conformality defect absorbs the rest), so
    :func:`~surfinpaint.representation.represent.represent` asks for this. (The mean-value
    map of the whole disk onto a circle is no fallback: it moved the λ of a whole 85k-vertex
    face scan for one folded border triangle, and its rebuild, 80 s of CPU by Newton's
    method before, was stopped after 11 minutes; session 14.)

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
        message = (f"the {map} map folds {len(flipped)} of "
                   f"{how_many(len(faces), 'triangle', 'triangles')} over "
                   f"({agreeing(len(flipped), 'face', 'faces')} {preview(flipped)}); the mesh "
                   "probably has badly shaped triangles there")
        if strict:
            raise MeshError(message, faces=flipped[:100])
        if untangle:
            uv, how = _untangled(vertices, faces, uv)
            message += f"; {how}" if how else ""
        warnings.warn(message, FoldedMapWarning, stacklevel=3)
    return uv, corners


def _untangled(vertices, faces, uv):
    """``(uv, what was done in words)``: ``uv`` untangled, or as it was (and no words)
    when it cannot be."""
    local = mean_value.untangle(vertices, faces, uv)
    if local is not None and len(flipped_faces(faces, local)) == 0:
        return local, "they were untangled locally by mean-value weights"
    return uv, ""
