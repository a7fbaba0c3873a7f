"""Balanced quadtree triangulations of the unit square: cells as small as they must be
where they must be, every triangle a right isosceles one.

The triangulations of the quadtree form of the λ-H representation
(:mod:`~surfinpaint.representation.quadtree_represent`, ``represent --export-quadtree``;
issue 18): the graded grid of
:func:`~surfinpaint.representation.grid.graded_grid_over` crowds whole rows and columns, so
its cells away from the crowded spot are thin (aspect up to 128 on the benchmark's foot cap
at 128², where its rebuild fails), while a quadtree refines only where the map squeezes the
surface and keeps every cell square. Measured on the three tall disks of
``benchmarks/represent_speed.py`` (``benchmarks/quadtree_export.py``, LSCM map,
docs/representation.md, session 19): trees of 12–16 thousand nodes sample their smooth
interpolant to 0.0009–0.005 % mean / 0.1–0.67 % Hausdorff of the diagonal, where the graded
512² grid takes about 200 thousand nodes for 0.0009–0.005 % / 0.08–0.77 %; sampled from the
mesh itself, all three are rebuilt exactly by the mesh form's Newton method, coarse to fine
over such trees (0.013–0.016 % / 0.15–0.99 %; the graded grid's rebuild does not converge on
them; session 21).

The tree is *2:1 balanced* (cells sharing an edge differ by at most one level), so a
cell's side carries at most one hanging node, its midpoint; each leaf is triangulated as a
fan from its centre to its corners and hanging midpoints (4 to 8 triangles, all with
angles of 45°, 45° and 90°). Trees built with the same ``max_depth`` place their nodes on
the same lattice, so a tree refined further keeps every node of the coarser one
(:attr:`QuadtreeTriangulation.keys`), as a coarse-to-fine solve needs.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["QuadtreeTriangulation", "balanced_splits", "quadtree_triangulation"]

# the points of a cell (in its own unit coordinates) where a refinement test looks: the
# centre, the corners and the side midpoints
CELL_PROBES = np.array([[0.5, 0.5], [0, 0], [1, 0], [0, 1], [1, 1],
                        [0.5, 0], [0, 0.5], [1, 0.5], [0.5, 1]])


@dataclass(frozen=True)
class QuadtreeTriangulation:
    """A conforming triangulation of the unit square by a balanced quadtree's leaves.

    Attributes
    ----------
    lattice : (n, 2) int array
        Node coordinates in units of ``1 / 2**(max_depth + 1)`` (leaf centres included).
    faces : (f, 3) int array
        Counter-clockwise.
    max_depth : int
    leaf_depth : (f,) int array
        The depth of the leaf each triangle belongs to.
    """

    lattice: np.ndarray
    faces: np.ndarray
    max_depth: int
    leaf_depth: np.ndarray

    @property
    def scale(self) -> int:
        """Lattice units per side of the square."""
        return 2 ** (self.max_depth + 1)

    @property
    def keys(self) -> np.ndarray:
        """(n,) increasing int array: each node's id on the lattice, the same in every tree
        of this ``max_depth``."""
        return self.lattice[:, 0] * (self.scale + 1) + self.lattice[:, 1]

    @property
    def points(self) -> np.ndarray:
        """(n, 2) float array: the nodes in the unit square."""
        return self.lattice / self.scale

    def border(self) -> np.ndarray:
        """(n,) bool array: nodes on the square's sides."""
        return ((self.lattice == 0) | (self.lattice == self.scale)).any(axis=1)


def _codes(i: np.ndarray, j: np.ndarray, n: int) -> np.ndarray:
    return np.unique(i * n + j)


def _children(codes: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """(i, j) at the next level of the cells ``codes`` of a level with ``n`` cells a side."""
    i, j = np.divmod(codes, n)
    di, dj = np.array([0, 1, 0, 1]), np.array([0, 0, 1, 1])
    return (2 * i[:, None] + di).ravel(), (2 * j[:, None] + dj).ravel()


def _edge_neighbours(codes: np.ndarray, n: int) -> np.ndarray:
    """The codes of the cells sharing an edge with ``codes`` (inside the level)."""
    i, j = np.divmod(codes, n)
    ni = np.concatenate([i - 1, i + 1, i, i])
    nj = np.concatenate([j, j, j - 1, j + 1])
    ok = (ni >= 0) & (ni < n) & (nj >= 0) & (nj < n)
    return _codes(ni[ok], nj[ok], n)


def balanced_splits(wants_split: Callable[[int, np.ndarray, np.ndarray], np.ndarray],
                    max_depth: int) -> list[np.ndarray]:
    """The split cells of a 2:1-balanced quadtree over the unit square.

    Parameters
    ----------
    wants_split : callable(depth, i, j) -> bool array
        Whether cells ``(i, j)`` of level ``depth`` (``2**depth`` cells a side, cell
        ``(i, j)`` covering ``[i, i+1] × [j, j+1] / 2**depth``) should be split; asked only
        for cells whose parent is split, level by level from the root (level 0, always
        split) to ``max_depth − 1``.
    max_depth : int
        Leaves are at most this deep (≥ 1).

    Returns
    -------
    list of int arrays
        Entry ``d``: the sorted codes ``i * 2**d + j`` of the split cells of level ``d``
        (``d = 0 … max_depth``; the last is empty). Balancing splits more cells than
        asked for: a cell is split whenever a cell sharing an edge with it has split
        children.
    """
    if max_depth < 1:
        raise ValueError(f"max_depth must be at least 1, got {max_depth}")
    split = [np.zeros(1, dtype=np.int64)]
    for d in range(1, max_depth):
        i, j = _children(split[-1], 2 ** (d - 1))
        want = np.asarray(wants_split(d, i, j), dtype=bool) if len(i) else np.zeros(0, bool)
        split.append(_codes(i[want], j[want], 2 ** d))
    split.append(np.zeros(0, dtype=np.int64))
    # fine to coarse: the parents of split cells are split, and so are the edge neighbours
    # of a cell whose children are split (else a leaf would meet leaves two levels finer)
    for d in range(max_depth - 1, -1, -1):
        n = 2 ** d
        ci, cj = np.divmod(split[d + 1], 2 * n)
        parents = _codes(ci // 2, cj // 2, n)
        split[d] = np.union1d(split[d], np.union1d(parents, _edge_neighbours(parents, n)))
    return split


def quadtree_triangulation(wants_split: Callable[[int, np.ndarray, np.ndarray], np.ndarray],
                           max_depth: int) -> QuadtreeTriangulation:
    """The fan triangulation of the leaves of :func:`balanced_splits`' tree.

    Each leaf is split from its centre to its corners and to the midpoint of each side
    whose neighbour across is split (a hanging node of the finer side), so the triangles
    meet edge to edge: every interior edge has two triangles, every edge with one lies on
    the square's sides.

    Examples
    --------
    >>> t = quadtree_triangulation(lambda d, i, j: (i == 0) & (j == 0), 3)
    >>> len(t.faces), len(t.lattice), int(t.leaf_depth.max())
    (68, 43, 3)
    """
    split = balanced_splits(wants_split, max_depth)
    K = 2 ** (max_depth + 1)
    corners, depths = [], []
    for d in range(1, max_depth + 1):
        n = 2 ** d
        i, j = _children(split[d - 1], n // 2)
        leaf = ~np.isin(i * n + j, split[d])
        i, j = i[leaf], j[leaf]
        k = K // n
        x0, y0 = i * k, j * k
        cx, cy = x0 + k // 2, y0 + k // 2
        # the sides counter-clockwise: (from, to, neighbour across)
        sides = (((x0, y0), (x0 + k, y0), (i, j - 1)),
                 ((x0 + k, y0), (x0 + k, y0 + k), (i + 1, j)),
                 ((x0 + k, y0 + k), (x0, y0 + k), (i, j + 1)),
                 ((x0, y0 + k), (x0, y0), (i - 1, j)))
        for (ax, ay), (bx, by), (ni, nj) in sides:
            inside = (ni >= 0) & (ni < n) & (nj >= 0) & (nj < n)
            hanging = inside & np.isin(ni * n + nj, split[d])
            mx, my = (ax + bx) // 2, (ay + by) // 2
            whole = ~hanging
            for keep, p, q in ((whole, (ax, ay), (bx, by)), (hanging, (ax, ay), (mx, my)),
                               (hanging, (mx, my), (bx, by))):
                corners.append(np.stack([cx[keep], cy[keep], p[0][keep], p[1][keep],
                                         q[0][keep], q[1][keep]], axis=1))
                depths.append(np.full(int(keep.sum()), d))
    tri = np.vstack(corners).reshape(-1, 3, 2)
    keys, faces = np.unique(tri[..., 0] * (K + 1) + tri[..., 1], return_inverse=True)
    lattice = np.column_stack(np.divmod(keys, K + 1))
    return QuadtreeTriangulation(lattice=lattice, faces=faces.reshape(-1, 3).astype(np.int64),
                                 max_depth=int(max_depth), leaf_depth=np.concatenate(depths))
