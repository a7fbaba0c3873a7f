"""The λ-H representation on adaptive (quadtree) triangulations of the parameter domain, and
its coarse-to-fine rebuild.

The grid export samples the surface on a regular (or graded) grid over its conformal map; a
map that squeezes part of the surface into a small spot (a finger's tip, a leg's hoof: λ
varies by 10³–10⁴) needs a grid of ~200 thousand nodes to resolve it, whose rebuild did not
converge in 30–50 minutes (docs/representation.md, sessions 17–18). Here the parameter domain
is covered by 2:1-balanced quadtrees (:mod:`~surfinpaint.representation.quadtree`) refined
where the map squeezes the surface: a cell is split while its side on the surface,
(side in the plane) × σ, exceeds ``target`` × the mesh's bounding-box diagonal, where
σ = √(surface area / parameter area) is taken per vertex as the median over its triangles
and, at a cell, as the largest at its 9 probe points (``CELL_PROBES``; the 3 nearest
vertices of each). One tree per target, coarse to fine; trees of one ``max_depth`` share a
lattice, so a finer tree keeps the coarser one's nodes.

φ is sampled at a tree's nodes from the mesh (piecewise linear over its parameter
triangles, ``"pl"``, the default; or its Clough–Tocher interpolant, ``"smooth"``, which folds
on the tall finger: docs/representation.md, session 19); λ, H and the conformality defect
are those of the tree's own triangles
(:func:`~surfinpaint.representation.mesh_lambda_h.mesh_lambda_h`), so the sampled φ solves
the mesh form's equations on them exactly. Triangles with a corner outside the map (LSCM's
free border, or where a rectangular map folds at its border) are dropped; the tree's border
nodes are the boundary data. A map that folds is untangled first, and where LSCM's image
overlaps itself the rectangle is used instead.

The rebuild (:func:`rebuild_quadtree`) solves the coarsest tree from the harmonic surface
(Newton, then the continuation,
:func:`~surfinpaint.representation.mesh_lambda_h.rebuild_on_mesh`) and each finer one from
the coarser solution interpolated at its nodes, the nodes the two share held, then released
(:func:`~surfinpaint.representation.grid_newton.solve_finer_level`); a finer tree that does
not converge so is solved alone from the harmonic surface. The mesh's vertices are
the finest solution interpolated at their (u, v) (Clough–Tocher over the tree's triangles).

Measured (``benchmarks/quadtree_export.py``, docs/representation.md, session 21; the
default trees 0.4, 0.2, 0.1, 0.05, 0.02): 9 of the 11 disks of
``benchmarks/represent_speed.py`` come back exactly to their sampling floors, under 0.1 %
mean / 1 % Hausdorff of the diagonal, from finest trees of 5–16 thousand nodes, the tall
finger, foot and leg cap that no 512² grid holds among them; the 70 mm pial disk (a finer
tree does not converge) and the whole face scan (its trees' samples miss it by 6.7 % over
the rectangle) do not.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.spatial import cKDTree

from surfinpaint.errors import MeshError
from surfinpaint.geometry.cutting import renumber
from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.geometry.overlap import border_crossings
from surfinpaint.geometry.point_location import locate_points
from surfinpaint.representation.clough_tocher import clough_tocher, vertex_gradients
from surfinpaint.representation.grid_newton import harmonic_fill, solve_finer_level
from surfinpaint.representation.grid_represent import (
    SAMPLINGS,
    subdivided_map,
    subdivision_levels,
)
from surfinpaint.representation.mapping import MAPS, FoldedMapWarning, parameterize
from surfinpaint.representation.mesh_lambda_h import (
    AREA_MATCH,
    area_mismatch,
    mesh_lambda_h,
    rebuild_on_mesh,
)
from surfinpaint.representation.quadtree import CELL_PROBES, quadtree_triangulation
from surfinpaint.representation.reconstruction import ReconstructionInfo
from surfinpaint.representation.roundtrip import RoundTrip, require_arrays, save_npz

__all__ = ["DEFAULT_TARGETS", "LevelSolve", "QuadtreeLambdaH", "TreeLevel", "level_solves",
           "rebuild_quadtree", "represent_quadtree", "sampled_tree_vertices",
           "tree_vertices"]

# cell sides on the surface, × the diagonal, of the trees, coarse to fine: each at most
# twice finer than the one before, from a coarse start (chosen on the three tuning disks of
# benchmarks/quadtree_export.py, session 21: from 0.1 or 0.2 the tall finger's coarsest tree
# does not converge, from 0.4 the chain converges exactly on all three)
DEFAULT_TARGETS = (0.4, 0.2, 0.1, 0.05, 0.02)
# the deepest leaves: cells of 2⁻¹⁴ of the domain's long side (the finger's tip needs 13)
DEFAULT_DEPTH = 14
_FORMAT = 1
# the level arrays of a file, per level k: level{k}_{name}
_LEVEL_ARRAYS = ("keys", "uv", "faces", "phi", "known", "lam", "H", "defect")


@dataclass(frozen=True)
class TreeLevel:
    """One quadtree triangulation of the parameter domain with the λ-H data of its triangles.

    Attributes
    ----------
    target : float
        Its cells' largest side on the surface, × the mesh's bounding-box diagonal.
    keys : (k,) int array
        Each node's id on the lattice shared by all the representation's trees
        (:attr:`~surfinpaint.representation.quadtree.QuadtreeTriangulation.keys`),
        increasing.
    uv : (k, 2) float array
        The nodes in the parameter plane.
    faces : (t, 3) int array
        Counter-clockwise in ``uv``.
    phi : (k, 3) float array
        The surface sampled at the nodes (only the ``known`` ones are read by the rebuild).
    known : (k,) bool array
        The border nodes: the rebuild's boundary data.
    lam, H : (k,) float arrays
        Conformal factor and mean curvature of the sampled φ on these triangles (H NaN on
        the border).
    defect : (k, 2) float array
        The conformality defect of the sampled φ on these triangles.
    """

    target: float
    keys: np.ndarray
    uv: np.ndarray
    faces: np.ndarray
    phi: np.ndarray
    known: np.ndarray
    lam: np.ndarray
    H: np.ndarray
    defect: np.ndarray


@dataclass
class QuadtreeLambdaH:
    """The λ-H representation of a mesh on quadtree triangulations of its parameter domain.

    Attributes
    ----------
    vertices : (n, 3) float array
        The original positions (kept to place the rebuilt vertices and measure the round
        trip).
    faces : (f, 3) int array
    uv : (n, 2) float array
        Each vertex's place in the trees' parameter plane.
    levels : tuple of TreeLevel
        Coarse to fine; the last is the representation (``lam``, ``H`` are its).
    map : str
        The conformal map, ``"lscm"`` or ``"rectangular"``.
    sampling : str
        How φ was sampled at the nodes, ``"pl"`` or ``"smooth"``.
    max_depth : int
        The trees' deepest possible level.
    check : RoundTrip or None
        The self-check (the mesh rebuilt from the trees against ``vertices``, with the
        sampling floor).
    """

    vertices: np.ndarray
    faces: np.ndarray
    uv: np.ndarray
    levels: tuple[TreeLevel, ...]
    map: str = "lscm"
    sampling: str = "pl"
    max_depth: int = DEFAULT_DEPTH
    check: RoundTrip | None = None

    discretization = "quadtree"

    @property
    def finest(self) -> TreeLevel:
        return self.levels[-1]

    @property
    def lam(self) -> np.ndarray:
        """λ at the finest tree's nodes."""
        return self.finest.lam

    @property
    def H(self) -> np.ndarray:
        """H at the finest tree's nodes."""
        return self.finest.H

    def save(self, path: str | os.PathLike) -> None:
        """Write to ``path`` as ``.npz``, atomically."""
        arrays = {"vertices": self.vertices, "faces": self.faces, "uv": self.uv,
                  "discretization": np.array("quadtree"), "map": np.array(self.map),
                  "sampling": np.array(self.sampling), "max_depth": np.array(self.max_depth),
                  "targets": np.array([lv.target for lv in self.levels], dtype=float),
                  "format": np.array(_FORMAT)}
        for k, level in enumerate(self.levels):
            arrays.update({f"level{k}_{name}": getattr(level, name) for name in _LEVEL_ARRAYS})
        save_npz(path, arrays, self.check)

    @classmethod
    def load(cls, path: str | os.PathLike) -> QuadtreeLambdaH:
        """Read a representation written by :meth:`save`.

        Raises
        ------
        ValueError
            When the file is not a quadtree λ-H representation (names what is missing).
        """
        with np.load(path, allow_pickle=False) as data:
            require_arrays(data, ("vertices", "faces", "uv", "targets", "map", "sampling",
                                  "max_depth"), path,
                           "a quadtree λ-H representation")
            require_arrays(data, [f"level{k}_{name}" for k in range(len(data["targets"]))
                                  for name in _LEVEL_ARRAYS], path,
                           "a quadtree λ-H representation")
            levels = tuple(TreeLevel(float(target), *(
                data[f"level{k}_{name}"] for name in _LEVEL_ARRAYS)) for k, target in
                enumerate(data["targets"]))
            levels = tuple(_typed_level(level) for level in levels)
            return cls(vertices=data["vertices"], faces=data["faces"].astype(np.int64),
                       uv=data["uv"], levels=levels, map=str(data["map"]),
                       sampling=str(data["sampling"]), max_depth=int(data["max_depth"]),
                       check=RoundTrip.from_arrays(data))


def _typed_level(level: TreeLevel) -> TreeLevel:
    return TreeLevel(level.target, level.keys.astype(np.int64), level.uv,
                     level.faces.astype(np.int64), level.phi, level.known.astype(bool),
                     level.lam, level.H, level.defect)


def _vertex_stretch(points: np.ndarray, faces: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """σ at each vertex: √(surface area / parameter area) of its triangles, the median of
    them (the largest gave 25–50 % more nodes for the same floors on the tuning disks: its
    slivers)."""
    p, q = points[faces], uv[faces]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    e1, e2 = q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]
    plane = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    per_corner = np.repeat(np.sqrt(area / np.maximum(plane, np.finfo(float).tiny)), 3)
    order = np.lexsort((per_corner, faces.ravel()))
    vid, val = faces.ravel()[order], per_corner[order]
    start = np.r_[0, np.flatnonzero(np.diff(vid)) + 1]
    count = np.diff(np.r_[start, len(vid)])
    sigma = np.zeros(len(points))
    sigma[vid[start]] = val[start + count // 2]
    return sigma


class _MappedDisk:
    """A disk's (subdivided) mesh over its conformal map, the scale σ of its triangles at
    the vertices, and its surface sampled at points of the plane."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, map: str, strict: bool):
        # a map that folds is untangled first, as the mesh form's: PL sampling of a folded
        # map samples one sheet where the mesh has two, and the smooth surface built over it
        # folds (a 72-vertex cow cap: 18 flipped triangles, 236 of the subdivided map's;
        # 10 with the coarse map untangled)
        uv, corners = parameterize(vertices, faces, map, strict=strict, untangle=True)
        crossing = border_crossings(faces, uv) if map == "lscm" else ()
        if len(crossing):
            # LSCM's free border curls over itself (large folded disks: a 50 mm pial disk,
            # a whole face scan): a point of the plane lies on two sheets there, and the
            # trees would sample one of them; the rectangle's border cannot cross
            message = (f"the LSCM map overlaps itself ({len(crossing)} crossings of its "
                       "border)")
            if strict:
                raise MeshError(message)
            warnings.warn(message + ": the quadtrees are built over the rectangular map",
                          FoldedMapWarning, stacklevel=4)
            map = "rectangular"
            uv, corners = parameterize(vertices, faces, map, strict=strict, untangle=True)
        self.map = map
        levels = subdivision_levels(vertices, faces)
        # the fine mesh (the smooth surface through the vertices, as the grid export's)
        self.uv, self.faces, self.points = (uv, faces, vertices) if levels == 0 else \
            subdivided_map(vertices, faces, uv, corners, map, levels, strict, untangle=True)
        self.lo, self.hi = np.nanmin(self.uv, axis=0), np.nanmax(self.uv, axis=0)
        self.sigma = _vertex_stretch(self.points, self.faces, self.uv)
        # the nodes on faces (a vertex on no face has a NaN uv, which a k-d tree refuses)
        self._on_faces = np.flatnonzero(np.isfinite(self.uv).all(axis=1))
        self._near = cKDTree(self.uv[self._on_faces])

    def sigma_at(self, points: np.ndarray) -> np.ndarray:
        return self.sigma[self._on_faces[self._near.query(points, k=3)[1]]].max(axis=1)

    def locate(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(triangle, weights, the points moved 1e-9 of the box inside it) of each point:
        the tree's border nodes lie on the box, where a rectangular map's border is."""
        points = np.clip(points, self.lo + 1e-9 * (self.hi - self.lo),
                         self.hi - 1e-9 * (self.hi - self.lo))
        return *locate_points(self.uv, self.faces, points), points

    @cached_property
    def gradients(self) -> np.ndarray:
        """The surface's gradients at the vertices, for its Clough–Tocher interpolant."""
        return vertex_gradients(self.uv, self.faces, self.points)

    def sample(self, located: tuple[np.ndarray, np.ndarray, np.ndarray],
               sampling: str) -> np.ndarray:
        """The surface at points of the plane, each in a triangle of the map (``located``:
        :meth:`locate`'s answer for them)."""
        where, weights, points = located
        if sampling == "pl":
            return np.einsum("pk,pkd->pd", weights, self.points[self.faces[where]])
        return clough_tocher(self.uv, self.faces, self.points, self.gradients, where, points)


def _tree_level(disk: _MappedDisk, target: float, diagonal: float, max_depth: int,
                sampling: str) -> TreeLevel:
    side = float(np.max(disk.hi - disk.lo))

    def wants_split(d, i, j):
        unit = (np.column_stack([i, j])[:, None, :] + CELL_PROBES) / 2 ** d
        plane = disk.lo + unit.reshape(-1, 2) * (disk.hi - disk.lo)
        sigma = disk.sigma_at(plane).reshape(len(i), -1).max(axis=1)
        return sigma * side / 2 ** d > target * diagonal

    tree = quadtree_triangulation(wants_split, max_depth)
    faces, uv = tree.faces, disk.lo + tree.points * (disk.hi - disk.lo)
    # only the triangles inside the map: LSCM's free border, or a rectangular map whose
    # border leaves the rectangle where it folds (the whole face scan's: 248 flipped
    # triangles, 735 of its 2,476 border vertices off the rectangle's sides)
    located = disk.locate(uv)
    inside = located[0] >= 0
    faces = faces[inside[faces].all(axis=1)]
    used, faces = renumber(faces)
    uv, keys = uv[used], tree.keys[used]
    phi = disk.sample(tuple(a[used] for a in located), sampling)
    table = EdgeTable.build(faces, len(uv))
    known = np.zeros(len(uv), dtype=bool)
    known[table.edges[table.count == 1].ravel()] = True
    lam, H, defect = mesh_lambda_h(phi, faces, uv)
    return TreeLevel(float(target), keys, uv, faces, phi, known, lam, H, defect)


def represent_quadtree(vertices: np.ndarray, faces: np.ndarray, *,
                       targets: tuple[float, ...] = DEFAULT_TARGETS, map: str = "lscm",
                       max_depth: int = DEFAULT_DEPTH, sampling: str = "pl",
                       strict: bool = False) -> QuadtreeLambdaH:
    """The λ-H representation of a disk on quadtree triangulations of its conformal map.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        A topological disk, consistently oriented.
    targets : tuple of float
        The trees' cell sides on the surface, × the bounding-box diagonal, decreasing
        (coarse to fine; the rebuild goes through them in this order). A tree with no node
        inside the map to solve for (too coarse for the disk) is left out.
    map : {"lscm", "rectangular"}
        The conformal map. LSCM by default: the rectangle's corners squeeze the surface
        too, and no rectangular-map tree of the tuning disks was rebuilt (session 19). Where
        LSCM's image overlaps itself (its border crosses itself,
        :func:`~surfinpaint.geometry.overlap.border_crossings`), the rectangle
        instead, with a :class:`~surfinpaint.representation.mapping.FoldedMapWarning`; the
        map used is the representation's ``map``.
    max_depth : int
        The deepest leaves: cells of ``2**-max_depth`` of the map's long side.
    sampling : {"pl", "smooth"}
        φ at the nodes from the (subdivided) mesh, piecewise linear, or from its
        Clough–Tocher interpolant.
    strict : bool
        Raise when the map folds triangles over.

    Returns
    -------
    QuadtreeLambdaH
        Not checked: :func:`~surfinpaint.representation.represent.quadtree_export` adds the
        round trip.

    Raises
    ------
    MeshError
        When the mesh is not a topological disk, or (``strict``) the map folds or LSCM's
        image overlaps itself.
    ValueError
        For bad parameters.
    """
    targets = tuple(float(t) for t in np.atleast_1d(targets))
    if not targets or any(not t > 0 for t in targets) or \
            any(b >= a for a, b in zip(targets, targets[1:], strict=False)):
        raise ValueError(f"targets must be positive and decreasing (coarse to fine), got "
                         f"{targets}")
    if map not in MAPS:
        raise ValueError(f"unknown conformal map {map!r}; choose from {MAPS}")
    if sampling not in SAMPLINGS:
        raise ValueError(f"unknown sampling {sampling!r}; choose from {SAMPLINGS}")
    if not 1 <= int(max_depth) <= 20:
        raise ValueError(f"max_depth must be in 1..20, got {max_depth}")
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    disk = _MappedDisk(v, f, map, strict)
    diagonal = float(np.linalg.norm(np.ptp(v, axis=0)))
    levels = tuple(_tree_level(disk, t, diagonal, int(max_depth), sampling)
                   for t in targets)
    # a tree too coarse to have a node to solve for inside the map (a flat disk's 0.4 tree:
    # a few cells, all cut by LSCM's free border) is left out of the chain
    levels = tuple(level for level in levels if not level.known.all())
    if not levels:
        raise ValueError(f"no tree of targets {targets} has a node inside the map to solve "
                         "for: give smaller targets")
    return QuadtreeLambdaH(vertices=v.copy(), faces=f.copy(), uv=disk.uv[:len(v)].copy(),
                           levels=levels, map=disk.map, sampling=sampling,
                           max_depth=int(max_depth))


@dataclass(frozen=True)
class LevelSolve:
    """One tree's rebuild: its node positions, whether Newton converged (to the surface:
    with the tree's own data, a root whose vertex areas miss λ's is not), its sparse
    factorizations and how it went."""

    level: TreeLevel
    points: np.ndarray
    converged: bool
    iterations: int
    message: str


def level_solves(rep: QuadtreeLambdaH, *, lam: np.ndarray | None = None,
                 H: np.ndarray | None = None, tol: float = 1e-10, max_iter: int = 150,
                 direct: bool = False) -> Iterator[LevelSolve]:
    """The trees rebuilt coarse to fine, one :class:`LevelSolve` each.

    Parameters
    ----------
    rep : QuadtreeLambdaH
    lam, H : arrays at the finest tree's nodes, optional
        Replace its λ and H (e.g. edited ones); the coarser trees take them at the nodes
        they share with it (an approximate start only).
    tol, max_iter : float, int
        Newton's tolerance (relative to the border's diagonal) and the coarsest tree's
        budget of factorizations.
    direct : bool
        Solve each tree alone from the harmonic surface (as the coarsest), not from the
        coarser solution (measured: only the foot cap converges so, session 19). Without
        it, a finer tree that does not converge from the coarser solution is solved alone
        too (with ``max_iter`` more factorizations).
    """
    edited = lam is not None or H is not None
    previous = None
    for level in rep.levels:
        lv_lam, lv_H = _edited(level, rep.finest, lam, H)
        data = (level.faces, level.uv, lv_lam, lv_H, level.defect)
        if previous is None or direct:
            x, ok, steps, how = _alone(level, data, edited, tol, max_iter)
        else:
            start, shared = _interpolated_start(previous, level)
            harmonic_fill(start, ~np.isfinite(start).all(axis=1), level.uv, level.faces)
            x, ok, steps = solve_finer_level(start, data, level.known, shared, tol,
                                             not edited)
            x, ok, steps, how = _checked(x, ok, steps, f"{int(shared.sum())} nodes held, "
                                         "then released", level, lv_lam, edited)
            if not ok:
                # the coarser solution is no start for this tree (the 50 mm pial disk's
                # 0.05 tree, session 21): the tree alone, from the harmonic surface
                y, y_ok, more, y_how = _alone(level, data, edited, tol, max_iter)
                steps += more
                if y_ok:
                    x, ok = y, True
                how += f"; not converged, then alone: {y_how}"
        previous = (level, x)
        yield LevelSolve(level, x, bool(ok), int(steps), how)


def _alone(level: TreeLevel, data: tuple, edited: bool, tol: float, max_iter: int
           ) -> tuple[np.ndarray, bool, int, str]:
    """A tree solved alone, from the harmonic surface (Newton, then the continuation)."""
    solve = rebuild_on_mesh(level.phi, *data, level.known, tol=tol, max_iter=max_iter,
                            select_by_area=not edited)
    return _checked(solve.points, solve.converged, solve.iterations, solve.message, level,
                    data[2], edited)


def _checked(x: np.ndarray, ok: bool, steps: int, how: str, level: TreeLevel,
             lam: np.ndarray, edited: bool) -> tuple[np.ndarray, bool, int, str]:
    """A tree's solve, not converged when (the tree's own data) its vertex areas miss λ's:
    that root is another solution of the equations (as rebuild_nested reports it)."""
    if ok and not edited and area_mismatch(x, level.faces, level.uv, lam) > AREA_MATCH:
        ok, how = False, how + "; another root: vertex areas off λ's"
    return x, bool(ok), int(steps), how


def _edited(level: TreeLevel, finest: TreeLevel, lam, H) -> tuple[np.ndarray, np.ndarray]:
    """The level's λ and H, with the finest tree's replacements where it has its nodes."""
    out = []
    for own, new, name in ((level.lam, lam, "lam"), (level.H, H, "H")):
        if new is None:
            out.append(own)
            continue
        new = np.asarray(new, dtype=float)
        if new.shape != finest.lam.shape:
            raise ValueError(f"{name} must have the finest tree's {len(finest.lam)} nodes, "
                             f"got shape {new.shape}")
        pos = np.minimum(np.searchsorted(finest.keys, level.keys), len(finest.keys) - 1)
        shared = finest.keys[pos] == level.keys
        value = own.copy()
        value[shared] = new[pos[shared]]
        if name == "H":
            value[~np.isfinite(own)] = np.nan  # no H on the border
        out.append(value)
    return out[0], out[1]


def _interpolated_start(previous: tuple[TreeLevel, np.ndarray], level: TreeLevel
                        ) -> tuple[np.ndarray, np.ndarray]:
    """The coarser tree's solution at the finer tree's nodes (Clough–Tocher; NaN where it
    does not cover them), exact at the nodes the two share, and those."""
    coarse, x = previous
    where = locate_points(coarse.uv, coarse.faces, level.uv)[0]
    inside = where >= 0
    start = np.full_like(level.phi, np.nan)
    start[inside] = clough_tocher(coarse.uv, coarse.faces, x,
                                  vertex_gradients(coarse.uv, coarse.faces, x),
                                  where[inside], level.uv[inside])
    pos = np.minimum(np.searchsorted(coarse.keys, level.keys), len(coarse.keys) - 1)
    shared = coarse.keys[pos] == level.keys
    start[shared] = x[pos[shared]]
    start[level.known] = level.phi[level.known]
    return start, shared


def tree_vertices(rep: QuadtreeLambdaH, level: TreeLevel, nodes: np.ndarray) -> np.ndarray:
    """The mesh's vertices from a tree's node positions: Clough–Tocher over its triangles
    at each vertex's (u, v); the vertices outside them, or on a triangle of border nodes
    only (the known surface), keep their positions."""
    where = locate_points(level.uv, level.faces, rep.uv)[0]
    inside = where >= 0
    out = np.array(rep.vertices, dtype=float, copy=True)
    out[inside] = clough_tocher(level.uv, level.faces, nodes,
                                vertex_gradients(level.uv, level.faces, nodes),
                                where[inside], rep.uv[inside])
    keep = ~inside
    keep[inside] = level.known[level.faces[where[inside]]].all(axis=1)
    out[keep] = rep.vertices[keep]
    return out


def sampled_tree_vertices(rep: QuadtreeLambdaH) -> np.ndarray:
    """The mesh's vertices as an exact rebuild of the finest tree gives them back: its
    sampling floor."""
    return tree_vertices(rep, rep.finest, rep.finest.phi)


def rebuild_quadtree(rep: QuadtreeLambdaH, *,
                     progress: Callable[[str], None] | None = None, **options
                     ) -> tuple[np.ndarray, np.ndarray, ReconstructionInfo]:
    """The mesh rebuilt from its quadtree representation, coarse to fine
    (:func:`level_solves`, which takes ``options``); ``progress`` is called with a sentence
    as each tree's solve starts.

    Returns
    -------
    vertices : (n, 3) float array
        The finest tree's solution interpolated at the vertices' (u, v), or that of the
        first tree that did not converge (the finer ones are not tried from it).
    faces : (f, 3) int array
        The representation's faces.
    info : ReconstructionInfo
        Whether every tree converged, the sparse factorizations in all, and per tree its
        nodes and factorizations.
    """
    say = progress or (lambda message: None)
    solves, trees = [], level_solves(rep, **options)
    for k, level in enumerate(rep.levels):
        say(f"rebuilding tree {k + 1} of {len(rep.levels)} ({len(level.uv)} nodes, cells of "
            f"{level.target:g} × the diagonal)")
        solves.append(next(trees))
        if not solves[-1].converged:
            break  # a finer tree from an unconverged start only repeats the failure
    converged = all(s.converged for s in solves) and len(solves) == len(rep.levels)
    parts = ", ".join(f"{len(s.level.uv)} nodes: {s.iterations}"
                      + ("" if s.converged else " (not converged)") for s in solves)
    verdict = "converged" if converged else "did not converge"
    message = f"coarse-to-fine Newton on the quadtrees {verdict} ({parts} factorizations)"
    last = solves[-1]
    vertices = tree_vertices(rep, last.level, last.points)
    info = ReconstructionInfo(converged, sum(s.iterations for s in solves), 0.0, message)
    return vertices, rep.faces.copy(), info
