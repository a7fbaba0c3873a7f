"""How noisy is a piece of surface? A truth-free estimate of the normal noise of the known
vertices around a hole, in mesh units and in edges, with a sign of whether it is noise at all.

Each vertex's position is predicted from its neighbours within 2 rings (a quadric height field
fitted in the frame of its normal, the vertex itself left out) and the prediction's residual
scaled by its standard error; the noise level is the residuals' robust spread (1.4826 × their
median absolute value). Two signs tell noise from shape that no quadric of 2 rings fits (a
cortex folded at the mesh's scale, a tooth's fissures, a coarse tessellation): independent
noise leaves residuals that are, if anything, opposed between neighbouring vertices (a vertex
raised by its noise lowers its neighbours' predictions), where shape leaves them alike; and
noise gives the same spread from fits over 3 rings, where shape gives more. Why: the
smoothing fill (:func:`surfinpaint.fill.liepa.fairing.fair_smoothed`) gains on range scans and
costs on clean meshes; this tells them apart (docs/candidates.md, "Session 45 (helper)").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from surfinpaint.geometry.mesh import (
    faces_near,
    k_ring,
    mean_edge_length,
    vertex_adjacency,
    vertex_normals,
)
from surfinpaint.geometry.rows import row_cross, row_norms

__all__ = ["NoiseEstimate", "surface_noise"]

# fewest neighbours a vertex's quadric (6 unknowns) is fitted to: fewer leave it nearly
# interpolating, with nothing to estimate the noise from (a vertex at the cut mesh's border)
MIN_NEIGHBOURS = 9
# 1 / (the standard normal's median absolute value): the MAD's scale to a standard deviation
MAD_TO_SD = 1.4826


@dataclass(frozen=True)
class NoiseEstimate:
    """The verdict of :func:`surface_noise`.

    Attributes
    ----------
    sigma : float
        Robust standard deviation of the vertices' noise along the normal (mesh units).
    edge : float
        Mean edge length of the faces around the vertices measured.
    correlation : float
        Correlation of the residuals across the edges between measured vertices: at most
        about 0 for independent noise, positive for shape the fits do not follow
        (NaN with fewer than 4 such edges).
    vertices : int
        How many vertices were measured.
    wide_sigma : float
        ``sigma`` from quadrics fitted over 3 rings instead of 2: about ``sigma`` for noise,
        larger for shape the quadrics do not follow.
    """

    sigma: float
    edge: float
    correlation: float
    vertices: int
    wide_sigma: float = float("nan")

    @property
    def relative(self) -> float:
        """``sigma`` in mean edge lengths."""
        return self.sigma / self.edge if self.edge > 0 else float("nan")

    @property
    def scale_ratio(self) -> float:
        """``wide_sigma / sigma``: about 1 for noise (NaN for a noise-free surface)."""
        return self.wide_sigma / self.sigma if self.sigma > 0 else float("nan")


def surface_noise(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, *,
                  rings: int = 3, wide: bool = True) -> NoiseEstimate:
    """Estimate the normal noise of the known vertices within ``rings`` rings of ``loop``
    (the loop itself left out: its vertices lack the neighbours on the hole's side).

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
    loop : (k,) int array
        The hole's boundary loop (or any seed vertices).
    rings : int
        How many rings around the loop are measured.
    wide : bool
        Also fit over 3 rings (``wide_sigma``; NaN without): a third of the cost more, which
        a caller that has already decided from ``sigma`` and ``correlation`` saves.

    Returns
    -------
    NoiseEstimate
        NaN ``sigma`` where no vertex has :data:`MIN_NEIGHBOURS` neighbours within 2 rings.
    """
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    loop = np.asarray(loop, dtype=np.int64).ravel()
    n = len(v)
    measured = k_ring(faces, loop, rings, n)
    measured[loop] = False
    ids = np.flatnonzero(measured)
    edge = mean_edge_length(v, faces_near(faces, loop, rings, n))
    # every face a measured vertex's normal, its edges and its neighbours within 3 rings
    # touch (the paths to those start within rings + 2 of the loop), in the mesh's order: the
    # whole mesh's numbers to the bit, at the region's cost (a whole mesh's normals and
    # adjacency cost a default fill 7-12 % on clean meshes, session 45)
    region = faces_near(faces, loop, rings + 2, n)
    residual = _left_out_residuals(v, region, ids, 2)
    kept = np.isfinite(residual)
    if not kept.any():
        return NoiseEstimate(float("nan"), edge, float("nan"), 0)
    sigma = MAD_TO_SD * float(np.median(np.abs(residual[kept])))
    wide_sigma = float("nan")
    if wide:
        wide_residual = _left_out_residuals(v, region, ids, 3)
        wide_sigma = MAD_TO_SD * float(np.median(np.abs(
            wide_residual[np.isfinite(wide_residual)])))
    return NoiseEstimate(sigma, edge, _edge_correlation(region, ids[kept], residual[kept], n),
                         int(kept.sum()), wide_sigma)


def _rings_of(faces: np.ndarray, n: int, ids: np.ndarray, rings: int) -> sp.csr_matrix:
    """Rows ``ids`` of the ``rings``-ring incidence (a vertex not its own neighbour)."""
    adjacency = vertex_adjacency(faces, n).tocsr()
    reach = adjacency[ids]
    for _ in range(rings - 1):
        reach = reach + reach @ adjacency
    reach = (reach > 0).tocoo()
    keep = reach.col != ids[reach.row]
    return sp.csr_matrix((np.ones(int(keep.sum()), dtype=np.int8),
                          (reach.row[keep], reach.col[keep])), shape=(len(ids), n))


def _left_out_residuals(v: np.ndarray, faces: np.ndarray, ids: np.ndarray,
                        rings: int) -> np.ndarray:
    """Each vertex of ``ids``: its height over the quadric fitted to its neighbours within
    ``rings`` rings in its normal's frame, divided by the prediction's standard error in
    units of the noise (``sqrt(1 + leverage)``); NaN with fewer than
    :data:`MIN_NEIGHBOURS` neighbours."""
    if len(ids) == 0:
        return np.zeros(0)
    rows = _rings_of(faces, len(v), ids, rings)
    count = np.diff(rows.indptr)
    valid = (np.arange(count.max(initial=0))[None, :] < count[:, None])
    neighbour = np.zeros(valid.shape, dtype=np.int64)
    neighbour[valid] = rows.indices
    normal = vertex_normals(v, faces)[ids]
    helper = np.where(np.abs(normal[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    first = row_cross(normal, helper)
    first /= row_norms(first)[:, None]
    second = row_cross(normal, first)
    offset = v[neighbour] - v[ids][:, None, :]
    scale = np.sqrt(np.mean(np.einsum("mkj,mkj->mk", offset, offset)[valid]))  # conditioning
    x = np.einsum("mkj,mj->mk", offset, first) / scale
    y = np.einsum("mkj,mj->mk", offset, second) / scale
    z = np.einsum("mkj,mj->mk", offset, normal) * valid
    design = np.stack([np.ones_like(x), x, y, x * x, x * y, y * y], axis=2) * valid[..., None]
    normal_matrix = np.einsum("mki,mkj->mij", design, design) + 1e-12 * np.eye(6)
    inverse = np.linalg.pinv(normal_matrix, hermitian=True)
    height = np.einsum("mj,mkj,mk->m", inverse[:, 0, :], design, z)  # the fit at the vertex
    residual = -height / np.sqrt(1.0 + inverse[:, 0, 0])
    return np.where(count >= MIN_NEIGHBOURS, residual, np.nan)


def _edge_correlation(faces: np.ndarray, ids: np.ndarray, residual: np.ndarray,
                      n: int) -> float:
    """Pearson correlation of ``residual`` across the mesh edges between vertices ``ids``
    (each edge once per face side: interior edges weigh twice, as in both directions)."""
    at = np.full(n, np.nan)
    at[ids] = residual
    ends = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    ends = ends[np.isfinite(at[ends]).all(axis=1)]
    if len(ends) < 4:
        return float("nan")
    a, b = at[ends[:, 0]], at[ends[:, 1]]
    # both directions: the correlation of a symmetric relation
    first, second = np.concatenate([a, b]), np.concatenate([b, a])
    spread = first.std()
    if spread == 0.0:
        return float("nan")
    return float(np.mean((first - first.mean()) * (second - second.mean())) / spread**2)
