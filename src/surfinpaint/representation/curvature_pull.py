"""The coupled λ-H solve's inpainting of λ and H pulled towards the initial fill's own λ and
H (an option, off by default; session 39 helper, docs/error_sources.md "Session 39").

Why: on the tuning-side holes where the λ-H fill loses to the trilaplacian fill S0 starts
from, the limit is the biharmonic prediction of H over the hole (its relative RMS error from
the true data 0.56 on the median such hole, against 0.21 for the H of the trilaplacian
surface itself); the rebuild from the true λ and H, and the start's shape, are not. The pull
adds ``w Σ_f M_f (x_f − x0_f)² / ē⁴`` to the biharmonic energy of x = H and x = λ (``M`` the
map's vertex areas, ``ē`` its mean edge length, ``x0`` the start's on the map): both, because
the rebuild uses λ²H, and H pulled alone moved fills away from a true start (measured on
analytic tori and spheres). w → ∞ gives the start back (its own λ and H rebuilt).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from surfinpaint.geometry.mesh import mean_edge_length
from surfinpaint.representation.vertex_lambda_h import vertex_lambda_h

__all__ = ["pulled_energy", "start_pull"]


def pulled_energy(block: sp.spmatrix, target: np.ndarray, area: np.ndarray, scale: float
                  ) -> tuple[sp.csc_matrix, np.ndarray]:
    """``block`` (a biharmonic block, the free vertices' rows and columns first) plus the
    pull ``p = area / scale`` on its first ``len(target)`` diagonal entries, and the pull's
    right-hand side ``p target`` (zero on the other rows)."""
    p = np.zeros(block.shape[0])
    p[:len(target)] = area / scale
    rhs = np.zeros(block.shape[0])
    rhs[:len(target)] = p[:len(target)] * target
    return (block + sp.diags(p)).tocsc(), rhs


def start_pull(Q_h: sp.spmatrix, Q_lam: sp.spmatrix, points: np.ndarray, faces: np.ndarray,
               uv: np.ndarray, free: np.ndarray, area: np.ndarray, weight: float):
    """The biharmonic blocks of H's and λ's unknowns with the pull towards the start's H and
    λ, and their right-hand sides.

    Parameters
    ----------
    Q_h, Q_lam : sparse matrices
        ``L M⁻¹ L`` over H's unknowns (the free vertices first) and over λ's (the free
        vertices).
    points, faces, uv :
        The patch's start positions (S0), triangles and map.
    free : (m,) int array
        The free vertices' ids.
    area : (n,) float array
        The map's vertex areas ``M``.
    weight : float
        ``w``; 0: no pull (the blocks returned as they are, right-hand sides 0).

    Returns
    -------
    Q_h, rhs_h, Q_lam, rhs_lam
    """
    if not weight:
        return Q_h, 0.0, Q_lam, 0.0
    lam0, H0 = vertex_lambda_h(points, faces, uv)
    edge = mean_edge_length(np.column_stack([uv, np.zeros(len(uv))]), faces)
    scale = edge**4 / weight
    Q_h, rhs_h = pulled_energy(Q_h, H0[free], area[free], scale)
    Q_lam, rhs_lam = pulled_energy(Q_lam, lam0[free], area[free], scale)
    return Q_h, rhs_h, Q_lam, rhs_lam
