"""Conformal surface inpainting of one hole (Lui, Wen, Gu; method.md §6).

Per hole: an initial fill S0 (the baseline's triangulation and refinement, faired with the
trilaplacian); a disk patch of S0 plus a few rings of the surface around it; its conformal map
(LSCM); λ and H of the known part; inpainting of λ and H over the hole; reconstruction of
the positions from the inpainted (λ, H) with the known surface as boundary condition. The
original vertices never move.

Two discretizations. ``"mesh"`` (default, :func:`inpaint_patch_on_mesh`): λ, H live on the
patch's own triangles, and inpainting and rebuild are solved together so that the
curvature at the hole's edge stays tied to the positions
(:mod:`surfinpaint.representation.on_mesh`). ``"grid"`` (:func:`inpaint_patch`): the paper's
regular grid over the conformal domain with robust λ, H fits, biharmonic inpainting on the
hole dilated past the crease, and a Gauss–Codazzi rebuild; measured less accurate
(docs/accuracy.md), kept as the paper's method and for comparison.

A sharp crease that crosses the hole (a cube's edge) is continued across it first and each
side is filled and inpainted on its own (:mod:`surfinpaint.fill.creases`): λ and H describe the
smooth sides, not the crease.

With ``select=True`` (default) the method checks itself without any ground truth of the
hole (:mod:`surfinpaint.fill.selfcheck`): it hides the rings of known surface around the hole
and cuts sibling holes of the same size out of the known surface nearby, fills them with
the λ-H method and by bilaplacian and trilaplacian fairing, keeps the λ-H fill when it
reproduces the removed surface better than the bilaplacian fill there, and otherwise
writes the faired fill the same tests prefer (method.md §8, "an honest safety net").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from surfinpaint.errors import FillError
from surfinpaint.fill.creases import CREASE_ANGLE, CREASE_EDGES, hole_crease, split_fill
from surfinpaint.fill.liepa.baseline import faired_fills
from surfinpaint.fill.selfcheck import hidden_ring_scores, sibling_scores
from surfinpaint.geometry.intersection import patch_intersects_surroundings, self_intersections
from surfinpaint.geometry.mesh import (
    boundary_loops,
    edge_faces,
    face_areas,
    face_normals,
    faces_near,
    unique_edges,
)

__all__ = ["PatchGrid", "conformal_fill", "hole_patch", "inpaint_patch",
           "inpaint_patch_on_mesh", "lambda_h_pictures", "patch_grid", "reconstruct_patch"]

# neighbouring triangles whose normals turn by more than this are a fold-over
FOLD_ANGLE = 120.0


def _is_disk(faces: np.ndarray) -> bool:
    _, _, count = unique_edges(faces)
    if (count > 2).any():
        return False
    n_vertices = len(np.unique(faces))
    if n_vertices - len(count) + len(faces) != 1:
        return False
    try:
        return len(boundary_loops(faces)) == 1
    except ValueError:
        return False


def hole_patch(
    faces: np.ndarray, loop: np.ndarray, fill_faces: np.ndarray, rings: int
) -> tuple[np.ndarray, int]:
    """The disk patch around a filled hole: ``fill_faces`` plus up to ``rings`` face rings of
    ``faces`` around ``loop``.

    The rings shrink until the patch is a topological disk (a ring that reaches another hole
    or the mesh border would break that).

    Returns
    -------
    patch_faces : (p, 3) int array
        The fill's faces first, then the ring faces.
    rings : int
        The number of rings actually used.

    Raises
    ------
    FillError
        When not even one ring gives a disk.
    """
    n = int(max(faces.max(), fill_faces.max(), np.max(loop))) + 1
    for k in range(rings, 0, -1):
        patch = np.concatenate([fill_faces, faces_near(faces, loop, k - 1, n)])
        if _is_disk(patch):
            return patch, k
    raise FillError("no disk-shaped patch around the hole: its neighbourhood is not a disk")


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
    grid: object
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
    from surfinpaint.geometry.parameterization import flipped_faces, lscm
    from surfinpaint.representation.grid import grid_over, resample

    ids, local = np.unique(patch_faces, return_inverse=True)
    local = local.reshape(-1, 3)
    points = vertices[ids]
    uv = lscm(points, local)
    flipped = flipped_faces(local, uv)
    if len(flipped):
        # a flipped sliver at the patch's outer edge only hides a little known data; a flip
        # in or next to the fill would corrupt the grid where it matters
        fill_vertices = np.unique(local[:n_fill_faces])
        if np.isin(local[flipped], fill_vertices).any():
            raise FillError(f"the conformal map of the patch folds ({len(flipped)} flipped "
                            "faces at the fill)")
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
    from surfinpaint.representation.reconstruction import reconstruct

    phi_known = np.where(domain[..., None], pg.phi, np.nan)
    try:
        return reconstruct(lam, H, phi_known, domain & ~region, pg.h, method=method,
                           domain=domain), method
    except ValueError as exc:
        if method != "gauss-codazzi" or "ring" not in str(exc):
            raise
    return (reconstruct(lam, H, phi_known, domain & ~region, pg.h, method="laplacian",
                        domain=domain), "laplacian (too few known rings for gauss-codazzi)")


def inpaint_patch(
    vertices: np.ndarray,
    patch_faces: np.ndarray,
    n_fill_faces: int,
    moving: np.ndarray,
    *,
    spacing: float = 0.5,
    fit_radius: int = 3,
    fit_sigma: float | None = None,
    dilate: int = 1,
    inpaint: str = "biharmonic",
    fidelity: float | None = None,
    reconstruct: str = "gauss-codazzi",
    max_nodes: int = 250_000,
) -> tuple[np.ndarray, dict]:
    """One λ-H inpainting pass over a disk patch.

    Parameters
    ----------
    vertices : (n, 3) float array
        Positions of all vertices the patch refers to.
    patch_faces : (p, 3) int array
        Disk patch; its first ``n_fill_faces`` faces are the fill (the hole).
    moving : (k,) int array
        Vertex ids to move (the fill's interior vertices).
    spacing : float
        Grid spacing as a fraction of the mean parameter-space edge length of the patch.
    fit_radius : int
        Window half-width (nodes) of the robust λ, H fits.
    fit_sigma : float, optional
        Gaussian weight width (nodes) of those fits; ``0.75 * fit_radius`` by default.
    dilate : int
        Nodes by which the hole region is grown before inpainting (the crease between the
        fill and the surface pollutes the nodes next to it).
    inpaint, fidelity :
        Inpainting model and optional soft data weight (see :func:`surfinpaint.inpaint`).
    reconstruct : {"laplacian", "gauss-codazzi"}
        Reconstruction from (λ, H) (see :func:`surfinpaint.reconstruct`).

    Returns
    -------
    positions : (k, 3) float array
        New positions of ``moving``.
    details : dict
        Grid shape, spacing and the (λ, H) grids for pictures and diagnostics.

    Raises
    ------
    FillError
        When the map folds, the grid is too large, or the result is not finite.
    """
    from surfinpaint.representation.estimation import robust_lambda_h
    from surfinpaint.representation.grid import interpolate
    from surfinpaint.representation.inpainting import inpaint as inpaint_grid
    from surfinpaint.representation.reconstruction import dilate as dilate_mask

    pg = patch_grid(vertices, patch_faces, n_fill_faces, spacing=spacing, max_nodes=max_nodes)
    grid, h, phi, inside, hole, known = pg.grid, pg.h, pg.phi, pg.inside, pg.hole, pg.known
    sigma = 0.75 * fit_radius if fit_sigma is None else fit_sigma
    lam0, H0 = robust_lambda_h(phi, h, valid=known, radius=fit_radius, sigma=sigma)
    region = dilate_mask(hole, dilate) & inside
    have = np.isfinite(lam0) & np.isfinite(H0)
    domain = inside & (have | region)
    # λ and H share the operator: one factorization for both
    lam, H = np.moveaxis(inpaint_grid(np.stack([lam0, H0], axis=-1), region, domain=domain,
                                      method=inpaint, h=h, fidelity=fidelity), -1, 0)
    lam = np.where(domain, lam, np.nan)
    H = np.where(domain, H, np.nan)
    rebuilt, used = reconstruct_patch(pg, lam, H, region, domain, method=reconstruct)
    positions = interpolate(rebuilt, grid, pg.uv_of(moving), order=3)
    if not np.isfinite(positions).all():
        raise FillError("the reconstruction is not finite at some fill vertices")
    return positions, {
        "grid_shape": grid.shape, "h": h, "reconstruct": used, "lam0": lam0, "H0": H0,
        "lam": lam, "H": H, "hole": hole, "region": region, "domain": domain,
    }


def inpaint_patch_on_mesh(
    vertices: np.ndarray,
    faces: np.ndarray,
    loop: np.ndarray,
    fill_faces: np.ndarray,
    moving: np.ndarray,
    *,
    rings: int = 4,
    iterations: int = 20,
    tol: float = 1e-3,
    cut_edges: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, dict]:
    """λ-H inpainting of a filled hole on its patch's own triangles
    (:func:`surfinpaint.representation.on_mesh.inpaint_on_mesh`): the default
    discretization.

    The patch is the fill plus ``rings`` face rings of the surface around the hole, mapped by
    LSCM; where that map flips a triangle the patch loses a ring, down to 3 rings. With
    ``cut_edges`` (a crease across the hole, :func:`surfinpaint.fill.creases.split_fill`) the
    mesh is cut open along them first and each side of the crease is a patch of its own,
    the crease its fixed border.

    Parameters
    ----------
    vertices : (n, 3) float array
        Positions of the mesh's vertices followed by the fill's new ones.
    faces : (f, 3) int array
        The mesh's faces (without the fill).
    loop : (k,) int array
        The hole's boundary loop.
    fill_faces : (p, 3) int array
        The fill's faces.
    moving : (m,) int array
        Vertex ids to move (the fill's interior vertices).
    rings : int
        Face rings of the surface in the patch.
    iterations, tol :
        Updates of the normals and λ in the coupled solve, and the step (in mean edge
        lengths) below which it stops.
    cut_edges : (c, 2) int array, optional
        Edges to cut along (see above).

    Returns
    -------
    positions : (m, 3) float array
        New positions of ``moving``.
    patch_faces : (p', 3) int array
        The patch used (fill faces first).
    details : dict
        Rings used, and under ``"mesh_lambda_h"`` the patch's map and its positions before
        and after, from which :func:`lambda_h_pictures` draws λ and H for the report (with
        a crease, of its side with the larger fill).

    Raises
    ------
    FillError
        When the map flips triangles even with 3 rings, or the coupled solve fails.
    """
    from surfinpaint.fill.creases import cut_along
    from surfinpaint.geometry.mesh import connected_components

    moving = np.asarray(moving, dtype=np.int64)
    if cut_edges is None:
        return _inpaint_piece(vertices, faces, loop, fill_faces, moving, rings=rings,
                              iterations=iterations, tol=tol)
    cut, parent = cut_along(np.vstack([fill_faces, faces]), cut_edges)
    cut_fill, cut_known = cut[:len(fill_faces)], cut[len(fill_faces):]
    points = vertices[parent]
    free = np.isin(parent, moving)
    natural = np.isin(parent, cut_edges)
    _, label = connected_components(cut_fill, len(parent))
    side = label[cut_fill[:, 0]]
    positions = vertices[moving].copy()
    order = np.argsort(moving)
    ring_faces, details = [], {}
    for piece in sorted(np.unique(side), key=lambda s: -(side == s).sum()):
        piece_fill = cut_fill[side == piece]
        piece_moving = np.unique(piece_fill[free[piece_fill]])
        seeds = np.unique(piece_fill[~free[piece_fill]])
        new, patch, info = _inpaint_piece(points, cut_known, seeds, piece_fill, piece_moving,
                                          rings=rings, iterations=iterations, tol=tol,
                                          natural=natural)
        positions[order[np.searchsorted(moving[order], parent[piece_moving])]] = new
        ring_faces.append(parent[patch[len(piece_fill):]])
        details = details or {**info, "crease": "λ-H inpainted on each side of the crease"}
        details["rings"] = min(details["rings"], info["rings"])
    rings_all = np.unique(np.sort(np.vstack(ring_faces), axis=1), axis=0, return_index=True)[1]
    ring_faces = np.vstack(ring_faces)[np.sort(rings_all)]
    return positions, np.vstack([fill_faces, ring_faces]), details


def _inpaint_piece(vertices, faces, seeds, fill_faces, moving, *, rings, iterations, tol,
                   natural=None):
    """:func:`inpaint_patch_on_mesh` of one patch, grown from ``seeds`` over ``faces``."""
    from surfinpaint.geometry.parameterization import flipped_faces, lscm
    from surfinpaint.representation.on_mesh import inpaint_on_mesh

    for k in range(rings, 2, -1):
        patch, used = hole_patch(faces, seeds, fill_faces, k)
        ids, local = np.unique(patch, return_inverse=True)
        local = local.reshape(-1, 3)
        uv = lscm(vertices[ids], local)
        flipped = flipped_faces(local, uv)
        if len(flipped) == 0:
            break
    else:
        raise FillError(f"the conformal map of the patch folds ({len(flipped)} flipped "
                        "faces, even with 3 rings)")
    free = np.isin(ids, moving)
    points = vertices[ids]
    new_points = inpaint_on_mesh(points, local, uv, free, iterations=iterations, tol=tol,
                                 natural=None if natural is None else natural[ids])
    details = {"rings": used, "discretization": "mesh",
               "mesh_lambda_h": {"uv": uv, "faces": local, "n_fill_faces": len(fill_faces),
                                 "free": free, "before": points, "after": new_points}}
    return new_points[np.searchsorted(ids, moving)], patch, details


def lambda_h_pictures(details: dict, resolution: int = 160) -> dict:
    """The λ, H grids the report draws (``lam0``, ``H0``, ``lam``, ``H``, ``hole``,
    ``region``, ``domain``) from a fill's details: as they are for the grid
    discretization, rasterized over the parameter domain from the per-vertex values of the
    mesh discretization (``details["mesh_lambda_h"]``); empty when there are none."""
    if "lam0" in details:
        return {k: details[k] for k in ("lam0", "H0", "lam", "H", "hole", "region",
                                        "domain") if k in details}
    from surfinpaint.representation.on_mesh import vertex_lambda_h

    data = details.get("mesh_lambda_h")
    if data is None:
        return {}
    uv, faces, free = data["uv"], data["faces"], data["free"]
    lam0, H0 = vertex_lambda_h(data["before"], faces, uv)
    lam, H = vertex_lambda_h(data["after"], faces, uv)
    # before: only what the known surface says (no vertex whose Laplacian sees the fill)
    touched = np.zeros(len(uv), bool)
    touched[faces[free[faces].any(axis=1)].ravel()] = True
    lam0[touched], H0[touched] = np.nan, np.nan
    return _raster(uv, faces, data["n_fill_faces"], touched,
                   {"lam0": lam0, "H0": H0, "lam": lam, "H": H}, resolution)


def _raster(uv, faces, n_fill_faces, touched, values: dict, resolution: int) -> dict:
    """Per-vertex values of a parameterized patch as grid images for the report."""
    from surfinpaint.representation.grid import grid_over, resample

    grid = grid_over(uv, resolution=resolution)
    stacked = np.column_stack(list(values.values()))
    # NaN (the border, where H has no two-sided Laplacian) stays NaN: drawn grey
    sampled, inside, face_index = resample(uv, faces, stacked, grid)
    # a node is unknown "before" when any corner of its triangle is
    corner_unknown = touched[faces].any(axis=1)
    out = {"h": grid.h, "grid_shape": grid.shape,
           "domain": inside, "hole": inside & (face_index < n_fill_faces),
           "region": inside & np.where(face_index >= 0, corner_unknown[face_index], False)}
    for k, name in enumerate(values):
        image = np.where(inside, sampled[..., k], np.nan)
        if name.endswith("0"):
            image = np.where(out["region"], np.nan, image)
        out[name] = image
    return out


def _check_patch(vertices: np.ndarray, patch_faces: np.ndarray, n_fill_faces: int, *,
                 self_crossing: bool = True, crease: np.ndarray | None = None) -> None:
    """Reject fills with non-finite positions, degenerate triangles, fold-overs (two
    neighbouring triangles, in the fill or a fill triangle and the surface next to it, whose
    normals turn by more than ``FOLD_ANGLE``, except across the ``crease`` edges), or
    intersections with the surrounding rings or (with ``self_crossing``) with itself."""
    fill = patch_faces[:n_fill_faces]
    if not np.isfinite(vertices[np.unique(fill)]).all():
        raise FillError("the filled patch has non-finite coordinates")
    area = face_areas(vertices, fill)
    if (area <= 1e-12 * max(float(np.median(area)), 1e-300)).any():
        raise FillError("the filled patch has degenerate triangles")
    edges, owner, count = edge_faces(patch_faces)
    normals = face_normals(vertices, patch_faces)
    two = count == 2
    checked = two & ((owner[:, 0] < n_fill_faces) | (owner[:, 1] < n_fill_faces))
    if crease is not None and len(crease):
        # a crease is meant to turn sharply
        base = int(max(edges.max(), np.max(crease))) + 1
        sharp = np.sort(np.asarray(crease, dtype=np.int64), axis=1)
        checked &= ~np.isin(edges[:, 0] * base + edges[:, 1], sharp[:, 0] * base + sharp[:, 1])
    pairs = owner[checked]
    cos = np.einsum("ij,ij->i", normals[pairs[:, 0]], normals[pairs[:, 1]])
    folds = int((cos < np.cos(np.radians(FOLD_ANGLE))).sum())
    if folds:
        raise FillError(f"the filled patch folds over at {folds} edges")
    crossing = patch_intersects_surroundings(vertices, fill, patch_faces[n_fill_faces:])
    if len(crossing):
        raise FillError(f"the filled patch cuts through the surrounding surface "
                        f"({len(crossing)} triangle pairs)")
    crossing = self_intersections(vertices, fill) if self_crossing else ()
    if len(crossing):
        raise FillError(f"the filled patch intersects itself ({len(crossing)} triangle pairs)")


def _fills(vertices, faces, loop, *, start, orders, s0_order, patch_rings, iterations,
           options, want_fair=True, want_conformal=True, s0=None, discretization="mesh",
           test=False, crease_angle=None, crease_edges=CREASE_EDGES):
    """The faired fills of fairing ``orders`` (``"fair2"``, ``"fair3"``; when ``want_fair``)
    and the conformal fill (when ``want_conformal``; S0 is the order-``s0_order`` faired fill
    with ``start="fair"``, or ``s0`` = (new_vertices, new_faces) when already made) of one
    hole: work is shared.

    Returns a dict name -> (new_vertices, new_faces, info); a failed conformal fill is
    returned as its exception under "conformal". ``test``: a self-check test hole's fill,
    scored by its distance to the removed surface, so the costly self-intersection check is
    left to the hole's own fill. With ``crease_angle``, a crease across the hole
    (:func:`surfinpaint.fill.creases.hole_crease`) is continued and the λ-H fill made on each
    side of it; when that fails, as for a smooth hole.
    """
    from surfinpaint.fill.liepa.baseline import conventional_fill

    needed = set(orders if want_fair else ())
    if want_conformal and start == "fair" and s0 is None:
        needed.add(s0_order)
    faired = faired_fills(vertices, faces, loop, sorted(needed)) if needed else {}
    out: dict = {}
    if want_fair:
        for k in orders:
            fv, ff, used = faired[k]
            out[f"fair{k}"] = (fv, ff, {"fair_order": used})
    if not want_conformal:
        return out
    if start == "fair":
        new_v, new_f = s0 if s0 is not None else faired[s0_order][:2]
    else:
        new_v, new_f = conventional_fill(vertices, faces, loop, refine=True, fair=False)
        new_v = np.asarray(new_v, dtype=float)
        new_f = np.asarray(new_f, dtype=np.int64)
    errors = (FillError, ValueError, RuntimeError, np.linalg.LinAlgError)
    crease_note = None
    crease = None
    if crease_angle is not None and discretization == "mesh":
        crease = hole_crease(vertices, faces, loop, angle=crease_angle,
                             min_edges=crease_edges)
    if crease is not None:
        try:
            cv, cf, cut_edges = split_fill(vertices, faces, loop, crease, order=s0_order,
                                           angle=crease_angle)
            fill = _lambda_h_fill(vertices, faces, loop, cv, cf, iterations=iterations,
                                  patch_rings=patch_rings, options=options,
                                  discretization=discretization, test=test,
                                  cut_edges=cut_edges)
            fill[2]["crease"] = (f"a crease ({crease.angle:.0f}°) crosses the hole: "
                                 "continued across it, each side inpainted on its own")
            out["conformal"] = fill
            return out
        except errors as exc:
            crease_note = f"the crease fill failed ({exc}), filled as a smooth hole"
    try:
        fill = _lambda_h_fill(vertices, faces, loop, new_v, new_f, iterations=iterations,
                              patch_rings=patch_rings, options=options,
                              discretization=discretization, test=test)
        if crease_note:
            fill[2]["crease_failed"] = crease_note
        out["conformal"] = fill
    except errors as exc:
        out["conformal"] = exc
    return out


def _lambda_h_fill(vertices, faces, loop, new_v, new_f, *, iterations, patch_rings, options,
                   discretization, test, cut_edges=None):
    """The λ-H fill from S0 = (new_v, new_f): ``iterations`` passes, then the checks."""
    n = len(vertices)
    moving = np.arange(n, n + len(new_v))
    if cut_edges is not None:  # the crease's points in the fill stay where they are put
        moving = np.setdiff1d(moving, cut_edges)
    if len(moving) == 0:
        return new_v, new_f, {"rings": 0, "note": "no interior vertices to move"}
    all_v = np.concatenate([vertices, new_v])
    info: dict = {}
    if discretization == "mesh":
        for _ in range(iterations):
            positions, patch, info_pass = inpaint_patch_on_mesh(
                all_v, faces, loop, new_f, moving, rings=patch_rings, cut_edges=cut_edges,
                **options)
            all_v[moving] = positions
            info.update(info_pass)
    else:
        patch, rings = hole_patch(faces, loop, new_f, patch_rings)
        info["rings"] = rings
        for _ in range(iterations):
            positions, info_pass = inpaint_patch(all_v, patch, len(new_f), moving, **options)
            all_v[moving] = positions
            info.update(info_pass)
    _check_patch(all_v, patch, len(new_f), self_crossing=not test, crease=cut_edges)
    return all_v[n:], new_f, info


# rings of surface in a hole's patch, per discretization (measured: docs/accuracy.md)
PATCH_RINGS = {"mesh": 4, "grid": 10}
# fairing order of the initial fill S0 (without ``fair_order``): measured, the λ-H fill
# from the trilaplacian S0 is closer (benchmarks/selfcheck_rules.py, README)
S0_ORDER = 3
# a λ-H fill this many times closer than the faired fill on the hidden rings is kept
# without the sibling test
DECISIVE = 0.5
# step (mean edge lengths) at which the coupled λ-H solve of a self-check test hole stops
TEST_TOL = 1e-2
# options of the grid discretization only (see inpaint_patch)
GRID_OPTIONS = ("spacing", "fit_radius", "fit_sigma", "dilate", "inpaint", "fidelity",
                "reconstruct", "max_nodes")


def _check_crease_angle(angle: float) -> None:
    if not 0.0 < angle < 180.0:
        raise ValueError(f"crease_angle must be between 0 and 180 degrees, got {angle}")


def check_options(discretization: str, options: dict) -> dict:
    """The options of the λ-H pass for ``discretization``, without the ``None`` ones.

    Raises
    ------
    ValueError
        For an unknown discretization, grid options with the mesh one, or a
        ``crease_angle`` outside (0, 180) degrees.
    """
    if discretization not in PATCH_RINGS:
        raise ValueError(f"discretization must be 'mesh' or 'grid', got {discretization!r}")
    options = {k: v for k, v in options.items() if v is not None}
    _check_crease_angle(options.get("crease_angle", CREASE_ANGLE))
    if discretization == "mesh":
        # the mesh discretization inpaints biharmonically, coupled with its rebuild
        if options.pop("inpaint", "biharmonic") != "biharmonic":
            raise ValueError("inpainting models other than 'biharmonic' need "
                             "discretization='grid'")
        grid_only = sorted(set(options) & set(GRID_OPTIONS))
        if grid_only:
            raise ValueError(f"option(s) {', '.join(grid_only)} apply to "
                             "discretization='grid' only")
    return options


def neighbourhood_rings(n_edges: int, *, patch_rings: int | None = None,
                        discretization: str = "mesh", select: bool = True,
                        siblings: int = 2, gap_rings: int = 3, **_) -> int:
    """Vertex rings around a hole of ``n_edges`` boundary edges that :func:`conformal_fill`
    looks at: its patch, and with ``select`` the sibling holes and their patches."""
    if patch_rings is None:
        patch_rings = PATCH_RINGS.get(discretization, max(PATCH_RINGS.values()))
    rings = patch_rings + 3
    if select and siblings > 0:
        hole_rings = int(np.ceil(n_edges / (2 * np.pi))) + 1
        rings = max(rings, gap_rings + 2 * hole_rings + patch_rings + 3)
    return rings


def conformal_fill(
    vertices: np.ndarray,
    faces: np.ndarray,
    loop: np.ndarray,
    *,
    start: str = "fair",
    fair_order: int | None = None,
    discretization: str = "mesh",
    patch_rings: int | None = None,
    iterations: int = 1,
    select: bool = True,
    hide_rings: int = 2,
    siblings: int = 2,
    gap_rings: int = 3,
    creases: bool = True,
    crease_angle: float = CREASE_ANGLE,
    **options,
) -> tuple[np.ndarray, np.ndarray, dict]:
    """Fill one hole by conformal λ-H inpainting, checked against fairing.

    Parameters
    ----------
    vertices, faces : arrays
        The mesh (often a local neighbourhood cut by :func:`surfinpaint.fill_holes`).
    loop : (k,) int array
        The hole's boundary loop, oriented as :func:`surfinpaint.geometry.mesh.boundary_loops`
        gives.
    start : {"fair", "initial"}
        Initial fill S0: faired (default) or only triangulated and refined.
    fair_order : int, optional
        Fairing order of S0 and of the faired fill the self-check compares with and falls
        back to. None (default): S0 is trilaplacian (``S0_ORDER``; the λ-H fill from it
        measured closer), the λ-H fill is compared with the bilaplacian fill (the
        baseline), and the faired fallback is chosen per hole by the same truth-free tests
        between the bilaplacian and the trilaplacian one (curvature-continuous across the
        hole's edge: measured better on smooth surfaces, much worse on noisy range scans;
        docs/accuracy.md).
    discretization : {"mesh", "grid"}
        Where λ and H live. ``"mesh"`` (default): on the patch's own triangles, inpainting
        and rebuild solved together (:func:`inpaint_patch_on_mesh`; measured better on
        every benchmark mesh, docs/accuracy.md). ``"grid"``: the paper's regular grid over
        the conformal domain (:func:`inpaint_patch`), with its own options.
    patch_rings : int, optional
        Rings of the known surface in the patch (shrunk where the patch would not be a disk
        or, on the mesh, where the map flips a triangle); 4 for the mesh discretization,
        10 for the grid by default.
    iterations : int
        Outer iterations: re-parameterize the new patch and inpaint again.
    select : bool
        Self-check, using no truth of the hole: predicting ``hide_rings`` hidden rings of
        the known surface around it (:func:`hidden_ring_scores`), and filling sibling holes
        as wide as this one cut from the known surface nearby (:func:`sibling_scores`).
        The conformal fill is kept when it beats the bilaplacian fill (the baseline, or
        the faired fill of ``fair_order``) on the hidden-ring test and does not lose the
        sibling test; a test whose hole the λ-H fill fails on says nothing (the other
        decides, and without the hidden-ring test the λ-H fill must win the sibling test);
        with less than half the faired fill's hidden-ring error the sibling test is
        skipped. Otherwise a faired fill
        is written: the trilaplacian one if it passes the same two tests against the
        bilaplacian one, else the bilaplacian one. The λ-H fill of the hole itself is
        computed only when it has won; when it then fails, the faired fill is returned and
        ``details["failed"]`` says why. ``select=False`` returns the raw conformal fill, or
        raises.
    hide_rings : int
        Rings hidden for the first test.
    siblings, gap_rings : int
        Number of sibling holes, and rings between them and the hole.
    creases : bool
        With the mesh discretization: a sharp crease (chains of edges whose faces turn by
        more than ``crease_angle`` degrees, :func:`surfinpaint.fill.creases.hole_crease`) that
        crosses the hole is continued across it, and each side is filled on its own
        (structure propagation, :mod:`surfinpaint.fill.creases`). False treats every hole as
        smooth.
    crease_angle : float
        See ``creases``.
    **options
        Passed to :func:`inpaint_patch` with the grid (``spacing``, ``fit_radius``,
        ``dilate``, ``inpaint``, ``fidelity``, ``reconstruct``); they are an error with the
        mesh discretization (except ``inpaint="biharmonic"``, which it is).

    Returns
    -------
    new_vertices : (m, 3) float array
    new_faces : (p, 3) int array
        Over the old ids and ``len(vertices) + j`` for the new ones.
    details : dict
        The self-check scores per candidate (``"conformal"``, ``"fair2"``, ``"fair3"``) and
        a ``selection`` note; with the conformal fill, the grids of its last pass
        (``lam0``, ``H0``, ``lam``, ``H``, ``hole``, ``region``, ``domain``, ``h``); with a
        faired fill, ``selected="fair"``, its ``fair_order`` and, if the conformal fill
        failed, ``failed``.

    Raises
    ------
    FillError
        With ``select=False``, when a step fails; otherwise only when not even the faired
        fill can be made (the caller falls back to the conventional fill).
    ValueError
        For an unknown ``start`` or ``fair_order``.
    """
    if start not in ("fair", "initial"):
        raise ValueError(f"start must be 'fair' or 'initial', got {start!r}")
    if fair_order is not None and fair_order not in (1, 2, 3):
        raise ValueError(f"fair_order must be 1, 2, 3 or None, got {fair_order!r}")
    _check_crease_angle(crease_angle)
    options = check_options(discretization, options)
    if patch_rings is None:
        patch_rings = PATCH_RINGS[discretization]
    orders = (2, 3) if fair_order is None else (fair_order,)
    s0_order = S0_ORDER if fair_order is None else fair_order

    # the test holes' λ-H fills stop at a coarser step: their scores differ by far more
    test_options = {"tol": TEST_TOL, **options} if discretization == "mesh" else options

    angle = crease_angle if creases and discretization == "mesh" else None
    # a hole crossed by a crease is filled along it; so are its test holes, where one sharp
    # edge left between them and a corner is enough (the crease is known from the hole
    # itself); a test hole that is not crossed (beside the crease) is filled as smooth and
    # says nothing about the crease fill
    crossed = angle is not None and hole_crease(vertices, faces, loop, angle=angle) is not None

    def fills_of(v, f, l, *, fair=True, conformal=True, s0=None, test=True):
        out = _fills(v, f, l, start=start, orders=orders, s0_order=s0_order,
                     patch_rings=patch_rings, iterations=iterations,
                     options=test_options if test else options, want_fair=fair,
                     want_conformal=conformal, s0=s0, discretization=discretization,
                     test=test, crease_angle=angle,
                     crease_edges=1 if test and crossed else CREASE_EDGES)
        made = out.get("conformal")
        if test and crossed and made is not None and not isinstance(made, Exception) \
                and "crease" not in made[2]:
            out["conformal"] = FillError("no crease crosses the test hole")
        return out

    if not select:
        fill = fills_of(vertices, faces, loop, fair=False, test=False)["conformal"]
        if isinstance(fill, Exception):
            raise fill
        return fill

    # The λ-H fill of the hole itself is made only once it has won the tests; the faired
    # fills are cheap.
    fills = fills_of(vertices, faces, loop, conformal=False, test=False)
    fair_names = [f"fair{k}" for k in orders]
    # the λ-H fill is measured against the bilaplacian fill (or the order asked for): the
    # trilaplacian one is the faired fallback on smooth surfaces where the λ-H fill fails
    reference = fair_names[0]

    def beats(scores, name, other):
        return name in scores and scores[name] < scores[other]

    def holds(scores, name, other):
        # a tie is not a loss: on sibling holes too small for inner vertices every fill is
        # the same triangulation
        return name in scores and scores[name] <= scores[other]

    def wins(hidden, sibling, name, other):
        """Wins the hidden-ring test and does not lose the sibling test; without the
        former, must win the latter."""
        if hidden:
            return beats(hidden, name, other) and (not sibling or holds(sibling, name, other))
        return bool(sibling) and beats(sibling, name, other)

    # the cheaper test first; the siblings only when they can still change the outcome
    hidden = hidden_ring_scores(vertices, faces, loop, fills_of, hide_rings=hide_rings,
                                patch_rings=patch_rings)
    # a λ-H fill that fails on the enlarged hole says nothing about how it fills this one
    # (it fails there on folded brain patches, measured): then the siblings decide
    hidden_lh = hidden if np.isfinite(hidden.get("conformal", 0.0)) else {}
    racing = not hidden_lh or beats(hidden_lh, "conformal", reference)
    fair3_racing = fair_order is None and (not hidden or beats(hidden, "fair3", "fair2"))
    # a decisive win needs no second opinion: on the benchmark the sibling test never
    # overturned one (docs/accuracy.md), and it is the costly test
    decisive = bool(hidden_lh) and (hidden_lh["conformal"]
                                    < DECISIVE * hidden_lh[reference])
    sibling = {}
    if (racing or fair3_racing) and not decisive:
        sibling = sibling_scores(
            vertices, faces, loop, lambda v, f, l: fills_of(v, f, l, conformal=racing),
            siblings=siblings, gap_rings=gap_rings, patch_rings=patch_rings)
    tests = {name: scores for name, scores in (("hidden rings", hidden),
                                               ("sibling holes", sibling)) if scores}
    scores_info = {f"score_{name.replace(' ', '_')}": scores for name, scores in tests.items()}
    if fair_order is not None:
        fair_name = reference
    elif hidden and wins(hidden, sibling, "fair3", "fair2"):
        fair_name = "fair3"
    else:
        fair_name = "fair2"
    verdicts = "; ".join(
        f"{name}: " + ", ".join(f"{k} {v:.3g}" for k, v in scores.items())
        for name, scores in tests.items()) or "no test could be run here"
    # likewise a λ-H fill that fails on a sibling hole: then the hidden rings decide
    sibling_lh = sibling if np.isfinite(sibling.get("conformal", 0.0)) else {}
    won = wins(hidden_lh, sibling_lh, "conformal", reference)
    if crossed and not hidden_lh and not sibling_lh:
        # no test hole is crossed by the crease (the hole spans it from corner to corner):
        # the two straight sharp chains that meet across the hole are the evidence
        won = True
        verdicts += "; no test hole is crossed by the crease, the crease fill is kept"
    lost = [name for name, scores in tests.items()
            if not (holds if name == "sibling holes" and hidden else beats)(
                scores, "conformal", reference)]
    failed = None
    # made when it won, or when it failed on a test hole: then whether it fails on this
    # hole too is what the report and the warning must say
    if won or any(np.isinf(scores.get("conformal", 0.0)) for scores in tests.values()):
        s0 = fills[f"fair{s0_order}"][:2] if start == "fair" else None  # S0, already made
        own = fills_of(vertices, faces, loop, fair=False, s0=s0, test=False)["conformal"]
        if isinstance(own, Exception):
            failed = own
        elif won:
            new_v, new_f, info = own
            info.update(scores_info)
            info["selection"] = f"self-check kept the conformal fill ({verdicts})"
            return new_v, new_f, info
    info = dict(scores_info)
    fv, ff, fair_info = fills[fair_name]
    info["selected"] = "fair"
    info["fair_order"] = fair_info["fair_order"]
    which = f"the faired fill (order {fair_info['fair_order']})"
    if failed is not None:
        info["failed"] = f"{type(failed).__name__}: {failed}"
        info["selection"] = f"the conformal fill failed, used {which} ({verdicts})"
    elif not tests:
        info["selection"] = f"self-check not possible here, kept {which}"
    else:
        info["selection"] = f"self-check ({', '.join(lost)}) preferred {which} ({verdicts})"
    return fv, ff, info
