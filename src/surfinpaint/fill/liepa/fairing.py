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
from scipy.sparse.linalg import spsolve

from surfinpaint.errors import MeshError, preview
from surfinpaint.geometry.mesh import laplacian_and_areas, unique_edges

__all__ = ["OPERATORS", "fair", "laplacian_and_mass"]

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
    touching = mask[faces].any(axis=1)
    grown = mask.copy()
    grown[faces[touching].ravel()] = True
    return touching, grown


def _check_anchored(f: np.ndarray, is_free: np.ndarray, ids: np.ndarray) -> None:
    """Every connected group of free vertices must have an edge to a fixed vertex, or the
    system is singular (translations of the group are in its null space)."""
    e, _, _ = unique_edges(f)
    both = is_free[e].all(axis=1)
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
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    n = len(v)
    if order < 1:
        raise ValueError(f"order must be at least 1, got {order}")
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
    out = v.copy()
    if len(free_ids) == 0:
        return out

    # rings: free = ring 0; L rows are needed complete up to ring order-1, i.e. all faces
    # touching those vertices; the columns then reach ring `order`
    mask = np.zeros(n, dtype=bool)
    mask[free_ids] = True
    rows_mask = mask
    for _ in range(order - 1):
        _, rows_mask = _grow(faces, rows_mask)
    touching, reach = _grow(faces, rows_mask)
    for _ in range(INTRINSIC_MARGIN if operator == "intrinsic" else 0):
        touching, reach = _grow(faces, reach)
    sub = faces[touching]
    used = np.zeros(n, dtype=bool)
    used[sub.ravel()] = True
    lonely = free_ids[~used[free_ids]]
    if len(lonely):
        raise MeshError(f"free vertices {preview(lonely.tolist())} are in no face",
                        vertices=lonely[:10].tolist())
    ids = np.flatnonzero(used)
    local = np.full(n, -1, dtype=np.int64)
    local[ids] = np.arange(len(ids))
    f = local[sub]
    is_free = mask[ids]
    in_rows = rows_mask[ids]
    if cut is not None:
        in_rows = in_rows & ~np.asarray(cut, dtype=bool)[ids]
    _check_anchored(f, is_free, ids)

    for _ in range(iterations):
        x = out[ids]
        # rows of L are exact for vertices whose whole star is in the submesh (rows_mask);
        # outer vertices only appear as columns
        lap, mass = laplacian_and_mass(x, f, operator)
        inv_mass = 1.0 / np.maximum(mass, 1e-300)
        op = lap[is_free]
        for _ in range(order - 1):
            # (L M⁻¹)(…): only rows inside `rows_mask` are used, where L and M are exact
            op = (op[:, in_rows] @ sp.diags(inv_mass[in_rows]) @ lap[in_rows]).tocsr()
        op = op.tocsc()
        a = op[:, is_free]
        rhs = -(op[:, ~is_free] @ x[~is_free])
        sol = np.asarray(spsolve(a.tocsc(), rhs)).reshape(-1, 3)
        if not np.isfinite(sol).all():
            raise MeshError("fairing system is singular (degenerate triangles around the "
                            "free vertices?)", vertices=free_ids[:10].tolist())
        out[ids[is_free]] = sol
    return out
