"""The paper's grid discretization of one λ-H pass (Lui, Wen, Gu; method.md §6): the patch
resampled on a regular grid over its conformal map, robust λ, H fits, biharmonic
inpainting on the hole dilated past the crease, and a Gauss–Codazzi rebuild. Measured less
accurate than the mesh discretization (docs/accuracy.md); kept as the paper's method."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from surfinpaint.errors import FillError, how_many
from surfinpaint.fill.conformal.options import GridOptions
from surfinpaint.fill.results import GridLambdaH
from surfinpaint.geometry import parameterization
from surfinpaint.geometry.cutting import renumber
from surfinpaint.geometry.mesh import unique_edges
from surfinpaint.representation import reconstruction
from surfinpaint.representation.estimation import robust_lambda_h
from surfinpaint.representation.grid import Grid, grid_over, interpolate, resample
from surfinpaint.representation.inpainting import inpaint as inpaint_grid

__all__ = ["PatchGrid", "inpaint_patch", "patch_grid", "reconstruct_patch"]


@dataclass
class PatchGrid:
    """A disk patch resampled on a regular grid over its conformal map.

    Attributes
    ----------
    ids : (k,) int array
        Global vertex ids of the patch's vertices (sorted); ``uv`` rows follow them.
    uv : (k, 2) float array
        The patch's conformal (LSCM) map.
    grid : Grid
    h : float
        Grid spacing.
    phi : (N, M, 3) float array
        Positions resampled on the grid (NaN outside the patch).
    inside, hole, known : (N, M) bool arrays
        Nodes in the patch, in the fill, and in the known surface around it.
    """

    ids: np.ndarray
    uv: np.ndarray
    grid: Grid
    h: float
    phi: np.ndarray
    inside: np.ndarray
    hole: np.ndarray
    known: np.ndarray

    def uv_of(self, vertex_ids: np.ndarray) -> np.ndarray:
        """Parameter positions of the given global vertex ids (all in the patch)."""
        return self.uv[np.searchsorted(self.ids, vertex_ids)]


def patch_grid(vertices: np.ndarray, patch_faces: np.ndarray, n_fill_faces: int, *,
               spacing: float = 0.5, max_nodes: int = 250_000) -> PatchGrid:
    """Map a disk patch conformally (LSCM) and resample it on a regular grid.

    The grid spacing is ``spacing`` times the mean parameter-space edge length. Faces that
    the map flips are dropped when they are away from the fill (they only hide a little
    known data).

    Raises
    ------
    FillError
        When the map flips faces at the fill, or the grid would exceed ``max_nodes``.
    """
    ids, local = renumber(patch_faces)
    points = vertices[ids]
    uv = parameterization.lscm(points, local)
    flipped = parameterization.flipped_faces(local, uv)
    if len(flipped):
        # a flipped sliver at the patch's outer edge only hides a little known data; a flip
        # in or next to the fill would corrupt the grid where it matters
        fill_vertices = np.unique(local[:n_fill_faces])
        if np.isin(local[flipped], fill_vertices).any():
            raise FillError("the conformal map of the patch folds "
                            f"({how_many(len(flipped), 'flipped face', 'flipped faces')} at the "
                            "fill)")
        keep = np.ones(len(local), dtype=bool)
        keep[flipped] = False
        n_fill_faces = int(keep[:n_fill_faces].sum())
        local = local[keep]
    edges, _, _ = unique_edges(local)
    mean_uv_edge = float(np.linalg.norm(uv[edges[:, 0]] - uv[edges[:, 1]], axis=1).mean())
    h = spacing * mean_uv_edge
    grid = grid_over(uv, h=h, margin=2 * h)
    if grid.shape[0] * grid.shape[1] > max_nodes:
        raise FillError(f"grid of {grid.shape} nodes is larger than max_nodes={max_nodes}")
    phi, inside, face_index = resample(uv, local, points, grid)
    hole = inside & (face_index < n_fill_faces)
    return PatchGrid(ids=ids, uv=uv, grid=grid, h=h, phi=phi, inside=inside, hole=hole,
                     known=inside & ~hole)


def reconstruct_patch(pg: PatchGrid, lam: np.ndarray, H: np.ndarray, region: np.ndarray,
                      domain: np.ndarray, *, method: str = "gauss-codazzi"
                      ) -> tuple[np.ndarray, str]:
    """Positions on the patch's grid rebuilt from (λ, H) over ``region``, with the resampled
    surface on ``domain & ~region`` as boundary data.

    Gauss–Codazzi needs 3 known rings around the region, the Laplacian form 1: a patch
    squeezed between holes or against the border may have only the latter, and then the
    Laplacian form is used.

    Returns
    -------
    phi : (N, M, 3) float array
    used : str
        The reconstruction actually used.
    """
    # called through its module so that tests can stand in for the reconstruction
    phi_known = np.where(domain[..., None], pg.phi, np.nan)
    try:
        return reconstruction.reconstruct(lam, H, phi_known, domain & ~region, pg.h,
                                          method=method, domain=domain), method
    except ValueError as exc:
        if method != "gauss-codazzi" or "ring" not in str(exc):
            raise
    return (reconstruction.reconstruct(lam, H, phi_known, domain & ~region, pg.h,
                                       method="laplacian", domain=domain),
            "laplacian (too few known rings for gauss-codazzi)")


def inpaint_patch(
    vertices: np.ndarray,
    patch_faces: np.ndarray,
    n_fill_faces: int,
    moving: np.ndarray,
    options: GridOptions | None = None,
) -> tuple[np.ndarray, GridLambdaH, str]:
    """One λ-H pass of the grid discretization over a disk patch.

    Parameters
    ----------
    vertices : (n, 3) float array
        Positions of all vertices the patch refers to.
    patch_faces : (p, 3) int array
        Disk patch; its first ``n_fill_faces`` faces are the fill (the hole).
    moving : (k,) int array
        Vertex ids to move (the fill's interior vertices).
    options : GridOptions, optional
        The grid's options (defaults when None).

    Returns
    -------
    positions : (k, 3) float array
        New positions of ``moving``.
    lambda_h : GridLambdaH
        λ and H on the grid before and after inpainting.
    reconstruct : str
        The reconstruction actually used.

    Raises
    ------
    FillError
        When the map folds, the grid is too large, or the result is not finite.
    """
    o = GridOptions() if options is None else options
    pg = patch_grid(vertices, patch_faces, n_fill_faces, spacing=o.spacing,
                    max_nodes=o.max_nodes)
    grid, h, inside, hole, known = pg.grid, pg.h, pg.inside, pg.hole, pg.known
    sigma = 0.75 * o.fit_radius if o.fit_sigma is None else o.fit_sigma
    lam0, H0 = robust_lambda_h(pg.phi, h, valid=known, radius=o.fit_radius, sigma=sigma)
    region = reconstruction.dilate(hole, o.dilate) & inside
    have = np.isfinite(lam0) & np.isfinite(H0)
    domain = inside & (have | region)
    # λ and H share the operator: one factorization for both
    lam, H = np.moveaxis(inpaint_grid(np.stack([lam0, H0], axis=-1), region, domain=domain,
                                      method=o.inpaint, h=h, fidelity=o.fidelity), -1, 0)
    lam = np.where(domain, lam, np.nan)
    H = np.where(domain, H, np.nan)
    rebuilt, used = reconstruct_patch(pg, lam, H, region, domain, method=o.reconstruct)
    positions = interpolate(rebuilt, grid, pg.uv_of(moving), order=3)
    if not np.isfinite(positions).all():
        raise FillError("the reconstruction is not finite at some fill vertices")
    return positions, GridLambdaH(h=h, lam0=lam0, H0=H0, lam=lam, H=H, hole=hole,
                                  region=region, domain=domain), used
