"""Fairing: move free vertices so that Δᵏx = 0 there, everything else fixed (Liepa 2003, §5).

With the cotangent Laplacian ``L`` and the Voronoi mass ``M`` (Meyer et al. 2003), the
discrete operator is ``L (M⁻¹ L)^(k-1)``: k = 1 gives a membrane (harmonic), k = 2 a thin
plate (biharmonic, the conventional choice), k = 3 also matches curvature variation. The
operator is assembled only on the free vertices plus the ``k`` rings its stencil reaches, so
the cost follows the hole, not the mesh.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from surfinpaint.errors import MeshError, preview
from surfinpaint.geometry.cutting import renumber
from surfinpaint.geometry.linalg import factorized_definite
from surfinpaint.geometry.mesh import laplacian_and_areas, unique_edges
from surfinpaint.geometry.rows import rows_all, rows_any

__all__ = ["OPERATORS", "fair", "fair_orders", "fair_smoothed", "laplacian_and_mass"]

OPERATORS = ("cotan", "clamped", "intrinsic")
# rings of faces beyond the operator's rows given to the intrinsic Delaunay triangulation:
# robust_laplacian triangulates the tufted cover of a mesh with a border, whose flips
# across the border change the rows next to it (measured on a plane: 1.6 % of an edge off
# with none, 3e-15 with two)
INTRINSIC_MARGIN = 2


def laplacian_and_mass(vertices: np.ndarray, faces: np.ndarray, operator: str = "cotan"
                       ) -> tuple[sp.csr_matrix, np.ndarray]:
    """The Laplacian ``L`` (negative semi-definite) and the lumped vertex masses of one of
    :data:`OPERATORS` (see :func:`fair`)."""
    if operator in ("cotan", "clamped"):
        return laplacian_and_areas(vertices, faces, nonnegative=operator == "clamped")
    try:  # the intrinsic Delaunay triangulation and its operators (an optional package)
        import robust_laplacian
    except ImportError as exc:
        raise ImportError("operator='intrinsic' needs the robust-laplacian package "
                          "(pip install robust-laplacian)") from exc

    lap, mass = robust_laplacian.mesh_laplacian(np.asarray(vertices, dtype=np.float64),
                                                np.asarray(faces, dtype=np.int64))
    # robust_laplacian's L is positive semi-definite: the opposite sign of ours
    return (-lap).tocsr(), np.asarray(mass.diagonal(), dtype=float)


def _grow(faces: np.ndarray, mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One ring: (faces touching ``mask``, mask grown by those faces' vertices)."""
    touching = rows_any(mask[faces])
    grown = mask.copy()
    grown[faces[touching].ravel()] = True
    return touching, grown


def _check_anchored(f: np.ndarray, is_free: np.ndarray, ids: np.ndarray) -> None:
    """Every connected group of free vertices must have an edge to a fixed vertex, or the
    system is singular (translations of the group are in its null space)."""
    e, _, _ = unique_edges(f)
    both = rows_all(is_free[e])
    m = len(is_free)
    graph = sp.coo_matrix((np.ones(both.sum()), (e[both, 0], e[both, 1])), shape=(m, m))
    _, label = connected_components(graph, directed=False)
    touching = e[is_free[e].sum(axis=1) == 1]
    anchored = np.zeros(label.max() + 1, dtype=bool)
    anchored[label[np.where(is_free[touching[:, 0]], touching[:, 0], touching[:, 1])]] = True
    loose = np.flatnonzero(is_free & ~anchored[label])
    if len(loose):
        raise MeshError(f"free vertices {preview(ids[loose].tolist())} are not connected to "
                        "any fixed vertex: the fairing system would be singular",
                        vertices=ids[loose][:10].tolist())


def fair(
    vertices: np.ndarray,
    faces: np.ndarray,
    free: np.ndarray,
    order: int = 2,
    *,
    iterations: int = 1,
    cut: np.ndarray | None = None,
    operator: str = "cotan",
) -> np.ndarray:
    """Solve ``Δ^order x = 0`` at the free vertices with all other vertices fixed.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
    free : (m,) int array or (n,) bool mask
        Vertices to move. Their ``order``-ring neighbourhood gives the boundary conditions
        (for order 2, the first ring fixes positions and the second the tangent plane).
    order : int
        1 (harmonic), 2 (biharmonic, default) or higher.
    iterations : int
        Number of solves; each recomputes the cotangent weights and masses from the previous
        result (the first uses the input positions, e.g. a flat initial patch).
    cut : (n,) bool array, optional
        Fixed vertices on a border the mesh was cut open along (a crease,
        :mod:`surfinpaint.fill.creases`): their one-sided Laplacians are left out of the
        operator (they are not zero even on a plane, and would pull the free vertices
        along the plane into slivers).
    operator : {"cotan", "clamped", "intrinsic"}
        ``"cotan"``: the cotangent Laplacian and the Voronoi mass of the mesh as it is.
        ``"clamped"``: its cotangents clamped to be non-negative first, as CGAL's fairing
        does (``cotangent_laplacian(nonnegative=True)``).
        ``"intrinsic"``: those of its intrinsic Delaunay triangulation (Sharp & Crane 2020,
        ``robust_laplacian.mesh_laplacian``), whose weights are never negative on slivers.

    Returns
    -------
    (n, 3) float array
        Positions, equal to ``vertices`` except at the free vertices.

    Raises
    ------
    MeshError
        If free ids are out of range, some free vertex is in no face, a connected group of
        free vertices touches no fixed vertex, or the system is singular.
    ValueError
        For order < 1 or iterations < 1.

    Examples
    --------
    >>> import trimesh
    >>> m = trimesh.creation.icosphere(2)
    >>> x = fair(m.vertices, m.faces, np.array([0]))
    >>> bool(np.abs(x[1:] - m.vertices[1:]).max() == 0)
    True
    """
    made = fair_orders(vertices, faces, free, (order,), iterations=iterations, cut=cut,
                       operator=operator)[order]
    if isinstance(made, MeshError):
        raise made
    return made


def fair_orders(
    vertices: np.ndarray,
    faces: np.ndarray,
    free: np.ndarray,
    orders=(2,),
    *,
    iterations: int = 1,
    cut: np.ndarray | None = None,
    operator: str = "cotan",
) -> dict[int, np.ndarray]:
    """:func:`fair` of each order in ``orders`` on the same mesh and free vertices, with
    the Laplacian and masses made once, on the submesh of the highest order.

    The same bits as one :func:`fair` call per order: the rows a fairing of order ``k``
    uses (the free vertices and ``k - 1`` rings around them) have their whole star in
    every larger submesh, and a row's entries are summed over the same faces in the same
    order there. With ``iterations > 1`` (the weights follow each order's own positions)
    or the intrinsic operator (its Delaunay flips see the whole submesh) each order makes
    its own.

    Returns
    -------
    dict
        order -> (n, 3) positions, as :func:`fair` returns them, or the ``MeshError``
        :func:`fair` raises for that order.

    Raises
    ------
    MeshError, ValueError
        As :func:`fair`, for bad arguments (free ids out of range, an unknown operator).
    """
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    n = len(v)
    orders = [int(k) for k in orders]
    if min(orders) < 1:
        raise ValueError(f"order must be at least 1, got {min(orders)}")
    if iterations < 1:
        raise ValueError(f"iterations must be at least 1, got {iterations}")
    if operator not in OPERATORS:
        raise ValueError(f"unknown operator {operator!r}: use one of {', '.join(OPERATORS)}")
    free = np.asarray(free)
    if free.dtype == bool:
        if free.shape != (n,):
            raise ValueError(f"free mask has shape {free.shape}, expected ({n},)")
        free_ids = np.flatnonzero(free)
    else:
        free_ids = np.unique(free.astype(np.int64).ravel())
        bad = free_ids[(free_ids < 0) | (free_ids >= n)]
        if len(bad):
            raise MeshError(f"free vertex ids {preview(bad.tolist())} are outside 0..{n - 1}",
                            vertices=bad[:10].tolist())
    if len(free_ids) == 0:
        return {k: v.copy() for k in orders}
    regions: dict[int, _Region | MeshError] = {}
    anchored = False  # the free vertices' anchoring is checked once (it is every order's)
    for order in orders:
        try:
            regions[order] = _Region(v, faces, free_ids, order, operator, cut,
                                     check=not anchored)
            anchored = True
        except MeshError as exc:
            regions[order] = exc
    top = regions[max(orders)]
    shared = None
    if (iterations == 1 and operator != "intrinsic" and len(set(orders)) > 1
            and isinstance(top, _Region)):
        shared = (top, *laplacian_and_mass(v[top.ids], top.f, operator))
    out: dict[int, np.ndarray | MeshError] = {}
    for order, region in regions.items():
        if isinstance(region, MeshError):
            out[order] = region
            continue
        try:
            out[order] = region.solve(v, iterations, operator,
                                      None if region is top else shared,
                                      shared[1:] if region is top and shared else None)
        except MeshError as exc:
            out[order] = exc
    return out


def fair_smoothed(vertices: np.ndarray, faces: np.ndarray, free: np.ndarray,
                  soft: np.ndarray, stiffness: float) -> np.ndarray:
    """A thin-plate smoothing fill: the free vertices of the positions that minimise
    ``stiffness · xᵀ L M⁻¹ L x + Σ_{i in soft} m_i |x_i − p_i|²`` over the free and the
    ``soft`` vertices, every other vertex of ``faces`` fixed (``L``, ``M``: the cotangent
    Laplacian and the Voronoi masses of ``faces``, ``p`` the input positions).

    Why: the bilaplacian fill (:func:`fair`, order 2) takes its boundary data, positions and
    slopes, from the loop and the ring beyond it as they are; on a range scan their noise
    is carried into the hole (docs/candidates.md, "Session 44 (helper)"). Here the known
    vertices near the loop are data to be followed within their noise, not fixed values:
    the fill continues a smoothed surface (a smoothing spline of smoothing length
    ``stiffness ** 0.25``). ``stiffness`` → 0 gives :func:`fair` of order 2 with the soft
    vertices fixed.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        The faces the energy is summed over: the fill and a few rings of the known surface
        around it (a vertex of theirs that is neither free nor soft is fixed).
    free : (m,) int array
        The vertices to place (the fill's new vertices).
    soft : (k,) int array
        Known vertices whose positions are data: followed, not kept (their positions are
        not changed in the result).
    stiffness : float
        Weight of the bending energy, in length⁴ (``(c h)⁴`` for a smoothing length of
        ``c`` edges of length ``h``).

    Returns
    -------
    (n, 3) float array
        ``vertices`` with the free vertices' new positions.

    Raises
    ------
    MeshError
        If the system is singular.
    """
    v = np.asarray(vertices, dtype=float)
    ids, f = renumber(np.asarray(faces, dtype=np.int64))
    x = v[ids]
    lap, mass = laplacian_and_mass(x, f)
    is_free = np.isin(ids, free)
    data = np.where(np.isin(ids, soft) & ~is_free, mass, 0.0)
    moving = is_free | (data > 0)
    bending = (lap @ sp.diags(1.0 / np.maximum(mass, 1e-300)) @ lap).tocsc()
    a = stiffness * bending[moving][:, moving] + sp.diags(data[moving])
    rhs = data[moving, None] * x[moving] - stiffness * (bending[moving][:, ~moving]
                                                        @ x[~moving])
    try:  # definite: the bending energy is semi-definite, the data terms and the fixed
        # vertices anchor every free vertex
        sol = factorized_definite(a.tocsc())(np.asarray(rhs))
    except RuntimeError:  # SuperLU: exactly singular
        sol = np.full((int(moving.sum()), 3), np.nan)
    if not np.isfinite(sol).all():
        raise MeshError("smoothing fairing system is singular (degenerate triangles around "
                        "the free vertices?)")
    out = v.copy()
    out[ids[is_free]] = sol[is_free[moving]]
    return out


class _Region:
    """The submesh one fairing of ``order`` works on: the free vertices (ring 0), the rows
    of ``L`` it needs complete (up to ring ``order - 1``: all faces touching them) and the
    columns they reach (ring ``order``).

    ``check``: whether every group of free vertices has an edge to a fixed one
    (:func:`_check_anchored`). Its answer is the same for every order: the faces around the
    free vertices, which hold all their edges, are in every region."""

    def __init__(self, v, faces, free_ids, order, operator, cut, check=True):
        n = len(v)
        mask = np.zeros(n, dtype=bool)
        mask[free_ids] = True
        rows_mask = mask
        for _ in range(order - 1):
            _, rows_mask = _grow(faces, rows_mask)
        touching, reach = _grow(faces, rows_mask)
        for _ in range(INTRINSIC_MARGIN if operator == "intrinsic" else 0):
            touching, reach = _grow(faces, reach)
        self.ids, self.f = renumber(faces[touching])
        lonely = free_ids[~np.isin(free_ids, self.ids)]
        if len(lonely):
            raise MeshError(f"free vertices {preview(lonely.tolist())} are in no face",
                            vertices=lonely[:10].tolist())
        self.order, self.free_ids = order, free_ids
        self.is_free = mask[self.ids]
        self.in_rows = rows_mask[self.ids]
        if cut is not None:
            self.in_rows = self.in_rows & ~np.asarray(cut, dtype=bool)[self.ids]
        if check:
            _check_anchored(self.f, self.is_free, self.ids)

    def solve(self, v, iterations, operator, shared=None, own=None):
        """The faired positions (n, 3). For the first solve: ``shared`` = (a larger region,
        its L, its masses), whose rows this region's rows equal, or ``own`` = (L, masses)
        already made on this region."""
        out = v.copy()
        ids, is_free, in_rows = self.ids, self.is_free, self.in_rows
        for step in range(iterations):
            x = out[ids]
            if step == 0 and own is not None:
                lap, mass = own
            elif step == 0 and shared is not None:
                top, top_lap, top_mass = shared
                pos = np.searchsorted(top.ids, ids)
                # rows outside `in_rows` differ from this submesh's own (their stars are
                # cut off here) but are never used
                lap, mass = top_lap[pos][:, pos], top_mass[pos]
            else:
                # rows of L are exact for vertices whose whole star is in the submesh
                # (rows_mask); outer vertices only appear as columns
                lap, mass = laplacian_and_mass(x, self.f, operator)
            inv_mass = 1.0 / np.maximum(mass, 1e-300)
            op = lap[is_free]
            for _ in range(self.order - 1):
                # (L M⁻¹)(…): only rows inside `rows_mask` are used, where L and M are exact
                op = (op[:, in_rows] @ sp.diags(inv_mass[in_rows]) @ lap[in_rows]).tocsr()
            op = op.tocsc()
            a = op[:, is_free]
            rhs = -(op[:, ~is_free] @ x[~is_free])
            try:  # L M⁻¹ L (and L M⁻¹ L M⁻¹ L), the fixed vertices out, is definite as L
                # is: factored without pivoting (definite_lu)
                sol = factorized_definite(a)(np.asarray(rhs)).reshape(-1, 3)
            except RuntimeError:  # SuperLU: exactly singular
                sol = np.full((int(is_free.sum()), 3), np.nan)
            if not np.isfinite(sol).all():
                raise MeshError("fairing system is singular (degenerate triangles around "
                                "the free vertices?)", vertices=self.free_ids[:10].tolist())
            out[ids[is_free]] = sol
        return out
