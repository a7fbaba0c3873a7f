"""The hole's patch resampled on a regular triangular lattice of its map, for the coupled λ-H
solve where the patch's own triangles cannot carry it (issue 20, docs/convergence.md,
session 23).

Why: on a coarse CAD tessellation (the built quadruped: slivers with angles down to 0.01°
and up to 179°) the patch's parameter triangles give the cotangent Laplacian negative
weights on 10-20 % of its edges and Voronoi areas down to 4e-4 of the median, and the
coupled system there has no root near the start (cond(I + K Y) 1e4-5e8). Splitting the
triangles into four keeps their shapes (the subdivided retry fails the same way). Here the
map's domain around the hole is covered instead by equilateral triangles, their vertices
placed on the C1 (Clough–Tocher) interpolant of the known surface outside the hole (its
gradients fitted on the known triangles only, so S0 does not enter the data) and of S0
inside; the λ-H solve runs on that mesh, and the fill's vertices are read back from it at
their own map positions (barycentric in the lattice triangle that holds them).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy.spatial import cKDTree

from surfinpaint.errors import FillError, how_many
from surfinpaint.geometry.cutting import renumber
from surfinpaint.geometry.mean_value import convex_combination
from surfinpaint.geometry.mesh import (
    boundary_loops,
    connected_components,
    unique_edges,
    vertex_adjacency,
)
from surfinpaint.geometry.point_location import locate_points
from surfinpaint.representation.clough_tocher import clough_tocher, vertex_gradients

__all__ = ["LatticePatch", "LatticeScale", "lattice_patch", "tutte_positions"]

# lattice spacings of known surface kept around the hole (the coupled solve's stencil
# reaches three rings out from the free vertices), and the fewest spacings between the
# fill and the patch's border
BAND = 6
# the lattice is no finer than this many free vertices would make it
MAX_FREE = 600
# points are located in a triangle up to this barycentric coordinate outside it, and a
# lattice vertex is free when it lies this far inside a fill triangle
INSIDE = 1e-9


@dataclass(frozen=True)
class LatticePatch:
    """The lattice mesh of a patch and how the patch's free vertices are read back.

    Attributes
    ----------
    points : (n, 3) float array
        Positions of the lattice vertices (on the interpolant of the known surface outside
        the hole, of S0 inside).
    faces : (f, 3) int array
        Equilateral triangles of the map, counter-clockwise; a disk.
    uv : (n, 2) float array
    free : (n,) bool array
        The lattice vertices strictly inside the fill's triangles.
    spacing : float
        The lattice's edge length in the map.
    """

    points: np.ndarray
    faces: np.ndarray
    uv: np.ndarray
    free: np.ndarray
    spacing: float
    _read: tuple[np.ndarray, np.ndarray, np.ndarray]

    def read_back(self, positions: np.ndarray, points: np.ndarray) -> np.ndarray:
        """The patch's ``points`` with its free vertices moved to the lattice surface
        ``positions`` at their map positions."""
        ids, face, bary = self._read
        out = np.array(points, dtype=float, copy=True)
        out[ids] = np.einsum("ij,ijk->ik", bary, positions[self.faces[face]])
        return out

    def relocated(self, uv: np.ndarray) -> LatticePatch:
        """The same lattice, read back at the map positions ``uv`` of the free vertices
        instead of their own.

        Raises
        ------
        FillError
            When one of them lies outside the lattice.
        """
        where, bary = locate_points(self.uv, self.faces, uv, tolerance=INSIDE)
        if (where < 0).any():
            raise FillError("a vertex of the fill, placed again, lies outside the lattice")
        return replace(self, _read=(self._read[0], where, bary))


def tutte_positions(uv: np.ndarray, fill_faces: np.ndarray, free: np.ndarray) -> np.ndarray:
    """Map positions of the ``free`` vertices (ids) of the fill's triangles ``fill_faces``
    at the mean of their neighbours' (Tutte's embedding), the fill's other vertices where
    ``uv`` has them: a triangulation that flips no triangle in the map where the fill's loop
    is convex there, whatever the start's triangles did."""
    out = np.array(uv, dtype=float, copy=True)
    convex_combination(vertex_adjacency(fill_faces, len(uv)).astype(float).tocsr(), out,
                       np.asarray(free))
    return out[free]


@dataclass(frozen=True)
class LatticeScale:
    """What a patch's lattice spacing is made of, whatever the lattice's ``per_edge``
    (:meth:`of`), and :meth:`spacing`, the one :func:`lattice_patch` takes.

    Why apart: where the spacing is bounded (by the patch's border or ``MAX_FREE``) several
    of the caller's ``per_edge`` give the same lattice; the caller sees that before making
    it again (midthickness #6: two of its three lattices, 36 ms, thrown away; session 47
    helper).

    Attributes
    ----------
    fill_ids : (k,) int array
        The fill's vertices.
    h : float
        The fill's mean map edge length.
    to_border : float
        The least map distance from a fill vertex to the patch's border.
    area : float
        The fill's map area.
    """

    fill_ids: np.ndarray
    h: float
    to_border: float
    area: float

    @classmethod
    def of(cls, faces: np.ndarray, uv: np.ndarray, n_fill: int) -> LatticeScale:
        """The scale of the patch ``faces`` (the fill's ``n_fill`` first) mapped to ``uv``."""
        fill_ids = np.unique(faces[:n_fill])
        edges = unique_edges(faces[:n_fill])[0]
        h = float(np.linalg.norm(uv[edges[:, 0]] - uv[edges[:, 1]], axis=1).mean())
        border = np.concatenate(boundary_loops(faces))
        to_border = float(cKDTree(uv[border]).query(uv[fill_ids])[0].min())
        corner = uv[faces[:n_fill]]
        d1, d2 = corner[:, 1] - corner[:, 0], corner[:, 2] - corner[:, 0]
        area = 0.5 * float(np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]).sum())
        return cls(fill_ids, h, to_border, area)

    def spacing(self, per_edge: float) -> float:
        """The lattice's spacing: ``1/per_edge`` of :attr:`h`, finer where the fill comes
        within ``BAND + 2`` spacings of the border, coarser where it would make more than
        ``MAX_FREE`` free vertices."""
        return max(min(self.h / per_edge, self.to_border / (BAND + 2)),
                   np.sqrt(self.area / MAX_FREE / (np.sqrt(3) / 2)))


def lattice_patch(points: np.ndarray, faces: np.ndarray, uv: np.ndarray, free: np.ndarray,
                  n_fill: int, per_edge: float, scale: LatticeScale | None = None
                  ) -> LatticePatch:
    """The patch (``faces`` over ``points``, its map ``uv``, the fill's faces first)
    resampled on an equilateral lattice of spacing ``1/per_edge`` of the fill's mean map
    edge length (finer where the fill comes within ``BAND + 2`` spacings of the patch's
    border, coarser where it would make more than ``MAX_FREE`` free vertices), kept within
    ``BAND`` spacings of the fill.

    ``scale``: :meth:`LatticeScale.of` of these ``faces``, ``uv`` and ``n_fill``, where the
    caller has it (made here when None).

    Raises
    ------
    FillError
        When the kept lattice is not a disk, or a free vertex lies outside it.
    """
    scale = LatticeScale.of(faces, uv, n_fill) if scale is None else scale
    fill_ids, spacing = scale.fill_ids, scale.spacing(per_edge)
    reach = scale.h + BAND * spacing
    lattice_uv, lattice_faces = _lattice(uv[fill_ids].min(0) - reach,
                                         uv[fill_ids].max(0) + reach, spacing)
    near = cKDTree(uv[fill_ids]).query(lattice_uv, distance_upper_bound=reach)[0] <= reach
    # the patch's triangles that can hold a point near the fill
    centre = uv[faces].mean(axis=1)
    radius = np.linalg.norm(uv[faces] - centre[:, None], axis=2).max(axis=1)
    candidates = np.flatnonzero(cKDTree(uv[fill_ids]).query(centre)[0] <= reach + radius)
    holder = np.full(len(lattice_uv), -1)
    depth = np.full(len(lattice_uv), -np.inf)
    found, weights = locate_points(uv, faces[candidates], lattice_uv[near], tolerance=INSIDE)
    holder[near] = np.where(found >= 0, candidates[found], -1)
    depth[near] = np.where(found >= 0, np.nan_to_num(weights, nan=-np.inf).min(axis=1),
                           -np.inf)
    kept = lattice_faces[(holder >= 0)[lattice_faces].all(axis=1)]
    ids, kept = renumber(kept)
    lat_free = (holder[ids] < n_fill) & (depth[ids] > INSIDE)
    count, label = connected_components(kept, len(ids))
    if count > 1 and lat_free.any():  # the piece around the hole
        piece = kept[label[kept[:, 0]] == np.bincount(label[lat_free]).argmax()]
        sub, kept = renumber(piece)
        ids, lat_free = ids[sub], lat_free[sub]
    n_edges = len(unique_edges(kept)[0])
    loops = boundary_loops(kept)
    if len(loops) != 1 or len(ids) - n_edges + len(kept) != 1 or not lat_free.any():
        borders = how_many(len(loops), "border", "borders")
        raise FillError(f"the lattice around the hole is not a disk ({borders})")
    # the known surface's interpolant takes its gradients from the known triangles only
    known = faces[n_fill:]
    gradients = vertex_gradients(uv, faces, points).reshape(len(points), 2, 3)
    on_known = np.zeros(len(points), dtype=bool)
    on_known[known.ravel()] = True
    gradients[on_known] = vertex_gradients(uv, known, points).reshape(len(points), 2, 3)[
        on_known]
    lat_points = clough_tocher(uv, faces, points, gradients, holder[ids], lattice_uv[ids])
    moving = np.flatnonzero(free)
    where, bary = locate_points(lattice_uv[ids], kept, uv[moving], tolerance=INSIDE)
    if (where < 0).any():
        raise FillError("a vertex of the fill lies outside the lattice around the hole")
    return LatticePatch(lat_points, kept, lattice_uv[ids], lat_free, spacing,
                        (moving, where, bary))


def _lattice(low: np.ndarray, high: np.ndarray, spacing: float
             ) -> tuple[np.ndarray, np.ndarray]:
    """An equilateral triangular lattice over the box [low, high]: points, faces
    (counter-clockwise)."""
    dy = spacing * np.sqrt(3.0) / 2.0
    nx = int(np.ceil((high[0] - low[0]) / spacing)) + 2
    ny = int(np.ceil((high[1] - low[1]) / dy)) + 2
    j, i = np.mgrid[0:ny, 0:nx]
    points = np.column_stack([(low[0] + spacing * (i + 0.5 * (j % 2))).ravel(),
                              (low[1] + dy * j).ravel()])
    idx = np.arange(nx * ny).reshape(ny, nx)
    a, b = idx[:-1, :-1], idx[:-1, 1:]  # row r, corners i and i + 1
    c, d = idx[1:, :-1], idx[1:, 1:]  # row r + 1
    even = (np.arange(ny - 1) % 2 == 0)[:, None] & np.ones(nx - 1, dtype=bool)
    # even rows: row r + 1 is shifted right by half a spacing
    first = np.where(even[..., None], np.stack([a, b, c], -1), np.stack([a, b, d], -1))
    second = np.where(even[..., None], np.stack([b, d, c], -1), np.stack([a, d, c], -1))
    return points, np.vstack([first.reshape(-1, 3), second.reshape(-1, 3)])
