"""Maps of a disk to the plane that cannot fold: Floater's mean-value map onto a circle, and
the local untangling of a map's flipped triangles by mean-value weights. The fill uses them
where LSCM (:func:`surfinpaint.geometry.parameterization.lscm`) flips triangles."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from surfinpaint.geometry import parameterization
from surfinpaint.geometry.mesh import boundary_loops
from surfinpaint.geometry.parameterization import disk_boundary, scale_to_area, signed_areas

__all__ = ["bad_faces", "convex_combination", "mean_value_map", "mean_value_weights", "untangle"]


def mean_value_map(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Floater's mean-value map of a disk onto a circle: bijective by construction.

    Each interior vertex is the weighted mean of its neighbours, with the mean-value
    weights ``w_ij = (tan(α/2) + tan(β/2)) / |v_i − v_j|`` (α, β the corner angles at
    ``v_i`` beside the edge), which are positive on any triangle mesh; the boundary is laid
    on a circle by arc length. Positive weights and a convex boundary make the map an
    embedding (Tutte 1963, Floater 2003, *Mean value coordinates*): no triangle flips, where
    LSCM's cotangent weights turn negative on slivers and can flip some. It is not
    conformal, only close to it on well-shaped triangles.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        A topological disk (see :func:`check_disk`), consistently oriented.

    Returns
    -------
    uv : (n, 2) float array
        Counter-clockwise where ``faces`` are, placed and scaled as :func:`lscm`'s.
        Unreferenced vertices get NaN.

    Raises
    ------
    MeshError
        When the mesh is not a disk (from :func:`check_disk`).
    """
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    loop = disk_boundary(v, f)
    n = len(v)
    W = mean_value_weights(v, f)
    lengths = np.linalg.norm(v[np.roll(loop, -1)] - v[loop], axis=1)
    angle = 2.0 * np.pi * np.concatenate([[0.0], np.cumsum(lengths)[:-1]]) / lengths.sum()
    uv = np.full((n, 2), np.nan)
    uv[loop] = np.column_stack([np.cos(angle), np.sin(angle)])
    convex_combination(W, uv, np.setdiff1d(np.unique(f), loop))
    if np.nansum(signed_areas(f, uv)) < 0:  # the boundary loop ran clockwise
        uv[:, 1] = -uv[:, 1]
    uv = scale_to_area(v, f, uv)
    return uv - np.nanmin(uv, axis=0)


def untangle(vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray, *,
             rings: int = 6) -> np.ndarray:
    """A map with its flipped and collapsed triangles untangled locally.

    The vertices of flipped or collapsed triangles (:func:`bad_faces`) and ``k`` rings
    around them are placed again by the mean-value weights (:func:`mean_value_map`) with
    the rest of ``uv`` fixed, for k = 1, 2, ... ``rings`` until none is left: the map stays
    as it was away from them.

    Returns
    -------
    uv : (n, 2) float array
        The map, unchanged where nothing is flipped or collapsed, or None when ``rings``
        rings do not untangle it (or the bad triangles reach the border).
    """
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    flipped = bad_faces(v, f, uv)
    if len(flipped) == 0:
        return uv
    W = mean_value_weights(v, f)
    border = np.concatenate(boundary_loops(f))
    adjacency = (W + W.T).tocsr()
    seeds = np.zeros(len(v), dtype=bool)
    seeds[f[flipped].ravel()] = True
    for _ in range(rings):
        seeds = seeds | (adjacency @ seeds.astype(float) > 0)
        free = np.flatnonzero(seeds)
        free = free[~np.isin(free, border)]
        out = uv.copy()
        convex_combination(W, out, free)
        if len(bad_faces(v, f, out)) == 0:
            return out
    return None


def bad_faces(vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Parameter triangles a λ-H fill cannot use: flipped
    (:func:`~surfinpaint.geometry.parameterization.flipped_faces`) or squashed flat
    (:func:`~surfinpaint.geometry.parameterization.collapsed_faces`)."""
    return np.union1d(parameterization.flipped_faces(faces, uv),
                      parameterization.collapsed_faces(vertices, faces, uv))


def mean_value_weights(v: np.ndarray, f: np.ndarray) -> sp.csr_matrix:
    """Floater's mean-value weights ``W[i, j]`` (positive; not symmetric): the weights of
    :func:`mean_value_map` and :func:`convex_combination`."""
    rows, cols, weights = [], [], []
    for c in range(3):  # the corner at f[:, c], its edges to the two others
        i, j, k = f[:, c], f[:, (c + 1) % 3], f[:, (c + 2) % 3]
        a, b = v[j] - v[i], v[k] - v[i]
        la, lb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
        cos = np.clip(np.einsum("ij,ij->i", a, b) / (la * lb), -1.0, 1.0)
        half_tan = np.tan(np.arccos(cos) / 2.0)
        rows += [i, i]
        cols += [j, k]
        weights += [half_tan / la, half_tan / lb]
    return sp.csr_matrix((np.concatenate(weights), (np.concatenate(rows),
                                                    np.concatenate(cols))),
                         shape=(len(v), len(v)))


def convex_combination(W: sp.csr_matrix, uv: np.ndarray, free: np.ndarray) -> None:
    """Place ``uv[free]`` at the combination of their neighbours with the weights of ``W``
    (row ``i``: vertex ``i``'s positive weights on its neighbours), the other vertices
    fixed, in place: Floater's mean-value map with :func:`mean_value_map`'s weights, Tutte's
    embedding with a 0/1 adjacency. Inside a convex fixed border such a map folds no
    triangle (Floater 2003)."""
    if len(free) == 0:
        return
    fixed = np.setdiff1d(np.flatnonzero(np.asarray(W.sum(axis=1)).ravel() > 0), free)
    system = (sp.diags(np.asarray(W.sum(axis=1)).ravel()) - W).tocsr()[free]
    rhs = -(system[:, fixed] @ uv[fixed])
    uv[free] = spla.splu(system[:, free].tocsc()).solve(np.asarray(rhs))
