"""The λ-H representation of a disk on a regular grid (the paper's images), and its rebuild.

:func:`represent_grid` maps the mesh conformally to the plane (method.md §6.4), samples its
positions φ on a regular grid over the parameter domain (§6.5) and computes the conformal
factor λ and the mean curvature H there (§3). φ is sampled from the C1 (Clough–Tocher)
surface through the vertices rather than the piecewise-linear mesh, and a coarse, strongly
curved mesh is first subdivided onto that surface and mapped again, so that the map is
conformal for the surface that is sampled (see :func:`represent_grid`). :func:`rebuild_grid`
goes back: φ is reconstructed from (λ, H) on the interior of the domain with a band of
boundary nodes as known data (§4), and every mesh vertex is placed at the reconstructed φ at
its (u, v) (§6.8). The round trip measures the whole chain map → sample → λ, H →
reconstruct → interpolate on a surface whose (λ, H) are right.

The default representation is on the mesh's own triangles
(:mod:`surfinpaint.representation.represent`); this grid is its resampled export.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from surfinpaint.geometry.mesh import face_normals, unique_edges
from surfinpaint.geometry.parameterization import flipped_faces, lscm
from surfinpaint.lazy import lazy_module
from surfinpaint.representation.clough_tocher import (
    clough_tocher,
    face_neighbours,
    vertex_gradients,
)
from surfinpaint.representation.fields import lambda_h
from surfinpaint.representation.grid import (
    GRADING,
    Grid,
    graded_grid_over,
    grid_over,
    interpolate,
    resample,
)
from surfinpaint.representation.grid_newton import GridLevel, rebuild_nested, triangle_levels
from surfinpaint.representation.mapping import MAPS, FoldedMapWarning, parameterize
from surfinpaint.representation.reconstruction import ReconstructionInfo, reconstruct
from surfinpaint.representation.roundtrip import RoundTrip, require_arrays, save_npz

ndimage = lazy_module("scipy.ndimage")  # the grid world only: no mesh fill imports it

__all__ = [
    "FoldedMapWarning",
    "LambdaH",
    "MAPS",
    "boundary_band",
    "mean_crease_angle",
    "parameterize",
    "rebuild_grid",
    "represent_grid",
    "sampled_vertices",
    "smooth_subdivision",
    "subdivided_map",
    "subdivision_levels",
]

SAMPLINGS = ("smooth", "pl")
# the interpolant of the mesh's positions that each sampling resamples at the grid's nodes
_INTERPOLANTS = {"smooth": "clough-tocher", "pl": "linear"}
SPACINGS = ("uniform", "graded")
# automatic subdivision: refine until the mean crease angle is at most this (degrees), with
# at most _MAX_LEVELS levels and _MAX_FACES faces (see subdivision_levels)
_CREASE_DEG = 4.0
_MAX_LEVELS = 4
_MAX_FACES = 500_000

# the Gauss–Codazzi rebuild closes its stencils with 3 rings (8-neighbour) of known nodes
# ndimage.generate_binary_structure(2, 2), spelled out: no import at start-up
_BLOCK = np.ones((3, 3), dtype=bool)
# 2: the levels of the nested rebuild on the grid's triangles (grid_newton) are stored
_FORMAT = 2
# rebuild methods: the mesh form on the grid's triangles (default), the paper's two
GRID_METHODS = ("newton", "laplacian", "gauss-codazzi")


@dataclass
class LambdaH:
    """The λ-H representation of a mesh on a regular grid over its conformal parameter domain.

    Attributes
    ----------
    grid : Grid
        The regular grid (``[i, j]`` ↔ ``(u0 + i h, v0 + j h)``).
    domain : (N, M) bool array
        Nodes inside the parameter domain (inside some parameter triangle).
    lam, H : (N, M) float arrays
        Conformal factor and mean curvature (method.md §1), NaN where a stencil leaves the
        domain.
    phi : (N, M, 3) float array
        The mesh's positions sampled at the nodes, NaN outside the domain.
    known : (N, M) bool array
        The boundary band of the domain whose φ is the boundary data of :func:`rebuild`.
    uv : (n, 2) float array
        Parameter coordinates of each mesh vertex.
    vertices : (n, 3) float array
    faces : (f, 3) int array
    map : str
        The conformal map used, ``"rectangular"`` or ``"lscm"``.
    band : int
        Width of ``known`` in nodes.
    corners : (4,) int array
        Corner vertices of the rectangular map (empty for LSCM).
    sampling : str
        How φ was sampled: ``"smooth"`` (C1 Clough–Tocher) or ``"pl"`` (piecewise linear).
    subdivide : int
        Levels of smooth subdivision applied before the (second) conformal map.
    check : RoundTrip or None
        The round trip measured by :func:`~surfinpaint.representation.represent.represent`
        (``check=True``): the mesh rebuilt from this grid against ``vertices``.
    levels : tuple of GridLevel
        λ, H and the conformality defect on the triangles of the grid and of its subgrids
        (:func:`~surfinpaint.representation.grid_newton.triangle_levels`), for the default
        ``"newton"`` rebuild; empty in files of format 1.
    """

    grid: Grid
    domain: np.ndarray
    lam: np.ndarray
    H: np.ndarray
    phi: np.ndarray
    known: np.ndarray
    uv: np.ndarray
    vertices: np.ndarray
    faces: np.ndarray
    map: str = "rectangular"
    band: int = 4
    corners: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    sampling: str = "pl"
    subdivide: int = 0
    check: RoundTrip | None = None
    levels: tuple[GridLevel, ...] = ()

    discretization = "grid"

    @property
    def unknown(self) -> np.ndarray:
        """(N, M) nodes that :func:`rebuild` reconstructs: the domain minus the band."""
        return self.domain & ~self.known

    def save(self, path: str | os.PathLike) -> None:
        """Write to ``path`` as ``.npz``, atomically (temporary file, then rename)."""
        path = Path(path)
        arrays = {f.name: getattr(self, f.name) for f in fields(self)
                  if f.name not in ("grid", "check", "levels")}
        arrays["level_steps"] = np.array([lv.step for lv in self.levels], dtype=np.int64)
        for k, lv in enumerate(self.levels):
            arrays.update({f"level{k}_lam": lv.lam, f"level{k}_H": lv.H,
                           f"level{k}_defect": lv.defect})
        arrays["discretization"] = np.array("grid")
        arrays["map"] = np.array(self.map)
        arrays["band"] = np.array(self.band)
        arrays["sampling"] = np.array(self.sampling)
        arrays["subdivide"] = np.array(self.subdivide)
        arrays["grid_origin"] = np.array(self.grid.origin, dtype=float)
        arrays["grid_h"] = np.array(self.grid.h, dtype=float)
        arrays["grid_shape"] = np.array(self.grid.shape, dtype=np.int64)
        if self.grid.graded:
            arrays["grid_u"], arrays["grid_v"] = self.grid.u, self.grid.v
        arrays["format"] = np.array(_FORMAT)
        save_npz(path, arrays, self.check)

    @classmethod
    def load(cls, path: str | os.PathLike) -> LambdaH:
        """Read a representation written by :meth:`save`.

        Raises
        ------
        ValueError
            When the file is not a λ-H representation (names what is missing).
        """
        with np.load(path, allow_pickle=False) as data:
            require_arrays(data, ("grid_origin", "grid_h", "grid_shape", "domain", "lam", "H",
                                  "phi", "known", "uv", "vertices", "faces", "map"), path,
                           "a λ-H representation")
            axes = None
            if "grid_u" in data.files:  # a graded grid
                axes = (tuple(data["grid_u"].tolist()), tuple(data["grid_v"].tolist()))
            grid = Grid(tuple(float(x) for x in data["grid_origin"]), float(data["grid_h"]),
                        tuple(int(x) for x in data["grid_shape"]), axes)
            steps = data["level_steps"] if "level_steps" in data.files else ()
            levels = tuple(GridLevel(int(step), data[f"level{k}_lam"], data[f"level{k}_H"],
                                     data[f"level{k}_defect"]) for k, step in enumerate(steps))
            return cls(
                grid=grid, domain=data["domain"].astype(bool), lam=data["lam"], H=data["H"],
                phi=data["phi"], known=data["known"].astype(bool), uv=data["uv"],
                vertices=data["vertices"], faces=data["faces"].astype(np.int64),
                map=str(data["map"]), band=int(data["band"]) if "band" in data.files else 4,
                corners=data["corners"] if "corners" in data.files else np.zeros(0, np.int64),
                sampling=str(data["sampling"]) if "sampling" in data.files else "pl",
                subdivide=int(data["subdivide"]) if "subdivide" in data.files else 0,
                check=RoundTrip.from_arrays(data), levels=levels,
            )


def mean_crease_angle(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Mean angle in degrees between the normals of faces sharing an interior edge."""
    f = np.asarray(faces, dtype=np.int64)
    n = face_normals(np.asarray(vertices, dtype=float), f)
    nb = face_neighbours(f)
    t, k = np.nonzero(nb > np.arange(len(nb))[:, None])  # every interior edge once
    if len(t) == 0:
        return 0.0
    cos = np.clip(np.einsum("ij,ij->i", n[t], n[nb[t, k]]), -1.0, 1.0)
    return float(np.degrees(np.nanmean(np.arccos(cos))))


def subdivision_levels(vertices: np.ndarray, faces: np.ndarray) -> int:
    """Levels of :func:`smooth_subdivision` that :func:`represent` applies by default.

    Each level halves the angles between neighbouring faces; the mesh is refined until
    their mean is at most 4° (at most 4 levels and 500,000 faces). Measured
    (``benchmarks/represent_speed.py``): the 250-vertex pial disk (mean crease 17°) needs 3
    levels to reach the round-trip targets, while the face scan (3.6°, its creases are scan
    noise that subdivision keeps) and the synthetic disks (≤ 2.2°) do not gain from it.
    """
    crease = mean_crease_angle(vertices, faces)
    if not np.isfinite(crease) or crease <= _CREASE_DEG:
        return 0
    levels = int(np.ceil(np.log2(crease / _CREASE_DEG)))
    by_size = int(np.floor(np.log(_MAX_FACES / max(len(faces), 1)) / np.log(4)))
    return int(max(0, min(levels, _MAX_LEVELS, by_size)))


def smooth_subdivision(vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray,
                       levels: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Refine a mesh onto the C1 surface through its vertices.

    The parameter triangles are split ``levels`` times into four (edge midpoints), and every
    new vertex is placed on the Clough–Tocher interpolant
    (:func:`~surfinpaint.representation.clough_tocher.clough_tocher`) of the positions
    over ``uv``, so the refined mesh approximates one smooth surface through the original
    vertices, with creases
    2^levels times flatter.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
    uv : (n, 2) float array
        A parameterization of the mesh (no folded triangles, ideally).
    levels : int

    Returns
    -------
    vertices : (n + m, 3) float array
        The original vertices first (same ids), then the new ones.
    faces : (4^levels f, 3) int array
        Same orientation as ``faces``.
    """
    v = np.asarray(vertices, dtype=float)
    q = np.asarray(uv, dtype=float)
    f0 = np.asarray(faces, dtype=np.int64)
    if levels <= 0:
        return v.copy(), f0.copy()
    grads = vertex_gradients(q, f0, v)
    f = f0
    origin = np.arange(len(f0))  # the original face each fine face lies in
    points = [q]
    at = [np.full(len(q), -1, dtype=np.int64)]
    n = len(q)
    for _ in range(levels):
        allq = np.vstack(points)
        e, fe, _ = unique_edges(f)
        eorigin = np.empty(len(e), dtype=np.int64)
        eorigin[fe.ravel()] = np.repeat(origin, 3)  # any face on the edge: C0 there
        points.append((allq[e[:, 0]] + allq[e[:, 1]]) / 2)
        at.append(eorigin)
        m = n + fe  # m[:, k]: midpoint of the edge opposite corner k
        a, b, c = f[:, 0], f[:, 1], f[:, 2]
        f = np.vstack([np.column_stack([a, m[:, 2], m[:, 1]]),
                       np.column_stack([m[:, 2], b, m[:, 0]]),
                       np.column_stack([m[:, 1], m[:, 0], c]),
                       np.column_stack([m[:, 0], m[:, 1], m[:, 2]])])
        origin = np.tile(origin, 4)
        n += len(e)
    new_q = np.vstack(points[1:])
    new_at = np.concatenate(at[1:])
    with np.errstate(invalid="ignore", divide="ignore"):
        new_v = clough_tocher(q, f0, v, grads, new_at, new_q)
    # folded or degenerate parameter triangles have no well-defined smooth patch: their new
    # vertices stay on the flat triangle (barycentric coordinates of the point in it)
    bad = np.zeros(len(f0), dtype=bool)
    bad[flipped_faces(f0, q)] = True
    bad = bad[new_at] | ~np.isfinite(new_v).all(axis=1)
    if bad.any():
        tri = q[f0[new_at[bad]]]
        r = new_q[bad] - tri[:, 2]
        t1, t2 = tri[:, 0] - tri[:, 2], tri[:, 1] - tri[:, 2]
        det = t1[:, 0] * t2[:, 1] - t2[:, 0] * t1[:, 1]
        with np.errstate(invalid="ignore", divide="ignore"):
            b1 = (r[:, 0] * t2[:, 1] - r[:, 1] * t2[:, 0]) / det
            b2 = (t1[:, 0] * r[:, 1] - t1[:, 1] * r[:, 0]) / det
        b = np.column_stack([b1, b2, 1 - b1 - b2])
        b = np.where(np.isfinite(b).all(axis=1, keepdims=True), b, 1.0 / 3)
        new_v[bad] = np.einsum("pk,pkd->pd", b, v[f0[new_at[bad]]])
    return np.vstack([v, new_v]), f


def boundary_band(domain: np.ndarray, band: int = 4) -> np.ndarray:
    """Nodes of ``domain`` within ``band`` 8-neighbour steps of a node outside it (or of the
    grid border): the known data around the rebuilt interior."""
    interior = ndimage.binary_erosion(domain, structure=_BLOCK, iterations=band,
                                      border_value=0)
    return domain & ~interior


def represent_grid(vertices: np.ndarray, faces: np.ndarray, resolution: int = 256, *,
                   map: str = "lscm", band: int = 4, h: float | None = None,
                   strict: bool = False, sampling: str = "smooth",
                   subdivide: int | None = None, spacing: str = "uniform",
                   grading: float | None = None) -> LambdaH:
    """The λ-H representation of a disk-topology mesh.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        A topological disk, consistently oriented; H's sign follows its orientation
        (``n = φu × φv`` is the faces' normal).
    resolution : int
        Grid nodes along the longer side of the parameter domain.
    map : {"lscm", "rectangular"}
        The conformal map (:func:`~surfinpaint.geometry.parameterization.lscm`, the default,
        measured as or more accurate in round trips at 128–512 nodes on the four benchmark
        meshes (1.0–25×; only the face disk at 64 was 1.3× better rectangular) and folding
        fewer triangles on ragged borders, or the paper's
        :func:`~surfinpaint.geometry.parameterization.rectangular_conformal_map`); both scale
        the domain so that its area is the surface area.
    band : int
        Width in nodes of the boundary band kept as known data for :func:`rebuild`. The
        Gauss–Codazzi rebuild needs λ and H on 3 known rings, and λ, H need one more ring
        of φ, hence 4; the Laplacian rebuild needs 1.
    h : float, optional
        Grid spacing, instead of ``resolution``.
    strict : bool
        Raise instead of warning when the map folds triangles over.
    sampling : {"smooth", "pl"}
        How φ is sampled at the nodes: the C1 Clough–Tocher interpolant of the vertex
        positions over the mesh's own parameter triangles (``"smooth"``, the default), or
        the piecewise-linear mesh itself (``"pl"``). Sampled finer than its triangles, a
        piecewise-linear surface has Δφ = 0 inside them and spikes on the edges, with a large
        tangential part that (λ, H) do not carry; the smooth surface through the same
        vertices has neither. Measured round-trip mean error on the bumpy disk 1.3–10×
        lower than ``"pl"``, on the face scans equal at 64 and 1.1–1.4× lower at 128–512
        (README, ``benchmarks/represent_speed.py --compare``).
    subdivide : int, optional
        Levels of :func:`smooth_subdivision` before the conformal map is computed again on
        the refined mesh; ``None`` (default) chooses them with
        :func:`subdivision_levels` (0 for meshes with mean crease angle ≤ 4°). On a coarse,
        strongly curved mesh a piecewise-linear conformal map is far from conformal for the
        smooth surface through its vertices: a smooth φ over it has a non-conformal metric,
        and the derivatives of that metric are the tangential part of Δφ
        (<Δφ, φu> = ½(E − G)u + Fv), which (λ, H) do not carry. Mapping the subdivided mesh
        makes it conformal to O(refined edge). On the 250-vertex pial disk the tangential
        part fell from 21–24 % of |Δφ| (PL sampling; 40–54 % smooth) to 5–6 % with 3
        levels, and the round-trip mean error from 0.13–0.24 % to 0.004–0.015 % of the
        diagonal (64–512 nodes).
    spacing : {"uniform", "graded"}
        The paper's square grid (default), or a rectilinear grid of the same size whose
        nodes are densest where the map squeezes the surface
        (:func:`~surfinpaint.representation.grid.graded_grid_over`; not with ``h``). A
        graded grid's λ and H are those of its triangles (its first level), and it is
        rebuilt by the ``"newton"`` method only.
    grading : float, optional
        A graded grid's share of nodes placed by the density (``graded_grid_over``'s
        ``grading``, default 0.8: the weakest that holds the benchmark's three tall disks
        under 1 % of the diagonal at 512²). Weaker grading gives squarer cells, which its
        rebuild handles better (docs/representation.md, session 18).

    Returns
    -------
    LambdaH

    Raises
    ------
    MeshError
        When the mesh is not a topological disk, has degenerate faces, or (``strict``) the
        map folds.
    ValueError
        For bad parameters.

    Examples
    --------
    >>> from surfinpaint import represent
    >>> from surfinpaint.data import bumpy_disk
    >>> rep = represent(*bumpy_disk(8), discretization="grid", resolution=32)
    >>> rep.lam.shape == rep.grid.shape
    True
    """
    _check_grid_options(band, sampling, spacing, grading, h, subdivide)
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    uv, corners, levels, (sample_uv, sample_f, sample_v) = _mapped(v, f, map, strict,
                                                                   subdivide)
    grid = _sampling_grid(uv, sample_uv, sample_f, levels, resolution=resolution, h=h,
                          spacing=spacing, grading=grading)
    phi, domain, _ = resample(sample_uv, sample_f, sample_v, grid,
                              interpolant=_INTERPOLANTS[sampling])
    known = boundary_band(domain, band)
    on_triangles = triangle_levels(phi, domain, known, grid)
    lam, H = _nodes_lambda_h(phi, grid, on_triangles)
    return LambdaH(grid=grid, domain=domain, lam=lam, H=H, phi=phi, known=known, uv=uv,
                   vertices=v.copy(), faces=f.copy(), map=map, band=band,
                   corners=np.asarray(corners, dtype=np.int64), sampling=sampling,
                   subdivide=levels, levels=on_triangles)


def _mapped(v: np.ndarray, f: np.ndarray, map: str, strict: bool, subdivide: int | None):
    """The conformal map of :func:`represent_grid`'s mesh and the mesh it samples: the map
    ``uv`` of the mesh's vertices, the rectangular map's ``corners``, the ``levels`` of
    smooth subdivision (``subdivide``, or :func:`subdivision_levels` when None) and the
    sampled mesh's (uv, faces, vertices). With ``levels`` the sampled mesh is the subdivided
    one mapped again (:func:`subdivided_map`) and ``uv`` its map's first ``len(v)`` rows;
    without, the mesh itself over its own map."""
    uv, corners = parameterize(v, f, map, strict=strict)
    levels = subdivision_levels(v, f) if subdivide is None else int(subdivide)
    if not levels:
        return uv, corners, levels, (uv, f, v)
    sample_uv, sample_f, sample_v = subdivided_map(v, f, uv, corners, map, levels, strict)
    return sample_uv[:len(v)], corners, levels, (sample_uv, sample_f, sample_v)


def _sampling_grid(uv: np.ndarray, sample_uv: np.ndarray, sample_f: np.ndarray, levels: int, *,
                   resolution: int, h: float | None, spacing: str, grading: float | None
                   ) -> Grid:
    """The grid :func:`represent_grid` samples φ on, over the map ``uv`` of the mesh's
    vertices and ``sample_uv`` of the mesh sampled (``sample_f``, subdivided ``levels``
    times): graded by where the map squeezes the sampled mesh, or square."""
    if spacing == "graded":
        return graded_grid_over(sample_uv, sample_f, resolution,
                                grading=GRADING if grading is None else grading)
    # with subdivision the refined border may bulge out of the original vertices' box
    over = sample_uv[np.unique(sample_f)] if levels else uv
    return grid_over(over, h=h) if h is not None else grid_over(over, resolution=resolution)


def _nodes_lambda_h(phi: np.ndarray, grid: Grid, on_triangles: tuple[GridLevel, ...]
                    ) -> tuple[np.ndarray, np.ndarray]:
    """λ and H at the grid's nodes: by finite differences of φ on a square grid, those of
    the first level's triangles (:func:`triangle_levels`) on a graded one."""
    if grid.graded:  # no finite differences on unequal spacing: the triangles' λ, H
        return on_triangles[0].lam, on_triangles[0].H
    return lambda_h(phi, grid.h)


def _check_grid_options(band: int, sampling: str, spacing: str, grading: float | None,
                        h: float | None, subdivide: int | None) -> None:
    """:func:`represent_grid`'s options, or a ValueError naming the one that is wrong."""
    if band < 1:
        raise ValueError(f"band must be at least 1 node, got {band}")
    if sampling not in SAMPLINGS:
        raise ValueError(f"unknown sampling {sampling!r}; choose from {SAMPLINGS}")
    if spacing not in SPACINGS:
        raise ValueError(f"unknown spacing {spacing!r}; choose from {SPACINGS}")
    if spacing == "graded" and h is not None:
        raise ValueError("a graded grid takes a resolution, not a spacing h")
    if grading is not None and spacing != "graded":
        raise ValueError("grading is for spacing='graded'")
    if subdivide is not None and subdivide < 0:
        raise ValueError(f"subdivide must be at least 0, got {subdivide}")


def subdivided_map(v: np.ndarray, f: np.ndarray, uv: np.ndarray, corners, map: str,
                    levels: int, strict: bool, *, untangle: bool = False):
    """The mesh subdivided ``levels`` times onto its smooth interpolant and mapped again:
    (uv, faces, vertices) of the refined mesh, whose first ``len(v)`` vertices are the
    original ones. The smooth surface is built over the LSCM map, which folds fewer
    triangles; the rectangular map keeps the coarse map's corners. ``untangle``: the
    refined map's folds untangled where they can be
    (:func:`~surfinpaint.representation.mapping.parameterize`)."""
    base_uv = uv if map == "lscm" else lscm(v, f)
    sample_v, sample_f = smooth_subdivision(v, f, base_uv, levels)
    sample_uv, _ = parameterize(sample_v, sample_f, map, strict=strict, untangle=untangle,
                                corners=corners if len(corners) else None)
    return sample_uv, sample_f, sample_v


def rebuild_grid(rep: LambdaH, method: str = "newton", *, order: int = 3,
                 lam: np.ndarray | None = None, H: np.ndarray | None = None,
                 **options) -> tuple[np.ndarray, np.ndarray, ReconstructionInfo]:
    """The mesh rebuilt from its λ-H representation on the grid.

    φ is reconstructed on the unknown nodes (the domain minus its boundary band) from
    (λ, H) with the band's φ as boundary data; each vertex whose interpolation cell touches
    a reconstructed node is moved to the interpolated φ at its (u, v). The other vertices
    lie in the band, where φ is the original surface itself, so they keep their positions
    (interpolating the resampled surface there would only add interpolation error).

    Parameters
    ----------
    rep : LambdaH
    method : {"newton", "laplacian", "gauss-codazzi"}
        ``"newton"`` (the default): the mesh form's equations on the grid's own triangles,
        solved coarse to fine from the stored levels
        (:func:`~surfinpaint.representation.grid_newton.rebuild_nested`), exact (to the
        solver's tolerance) where it converges; measured within the grid export's targets
        on the distorted benchmark disks where the paper's Laplacian iteration is not
        (docs/representation.md, session 11). Or the paper's reconstructions
        (:func:`surfinpaint.representation.reconstruction.reconstruct`): the Laplacian
        form measured 2–10x lower round-trip error and 4–10x faster than Gauss–Codazzi
        (bumpy disk, ``benchmarks/represent_speed.py``).
    order : {1, 3}
        Bilinear or bicubic interpolation of the reconstructed φ at the vertices (bicubic
        falls back to bilinear where its 4×4 stencil leaves the domain).
    lam, H : (N, M) arrays, optional
        Replace the representation's λ and H (e.g. inpainted or edited ones).
    **options
        Passed on to ``reconstruct`` (``tol``, ``max_iter`` also to ``rebuild_nested``).

    Returns
    -------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        The representation's faces, unchanged.
    info : ReconstructionInfo
        Whether the reconstruction converged.
    """

    if method not in GRID_METHODS:
        raise ValueError(f"unknown method {method!r}; choose from {GRID_METHODS}")
    known = rep.known
    if method == "newton":
        if not rep.levels:
            raise ValueError("this grid representation (format 1) has no levels for the "
                             "'newton' rebuild: represent the mesh again, or rebuild with "
                             "method='laplacian'")
        solve = rebuild_nested(rep.levels, rep.phi, rep.domain, rep.known, rep.grid,
                               lam=lam, H=H, **options)
        phi = solve.phi
        info = ReconstructionInfo(solve.converged, solve.iterations, 0.0, solve.message)
        known = _newton_known(rep)
    else:
        if rep.grid.graded:
            raise ValueError(f"a graded grid is rebuilt by the 'newton' method only, not "
                             f"{method!r}")
        lam = rep.lam if lam is None else np.asarray(lam, dtype=float)
        H = rep.H if H is None else np.asarray(H, dtype=float)
        phi, info = reconstruct(lam, H, rep.phi, rep.known, rep.grid.h, method=method,
                                domain=rep.domain, return_info=True, **options)
    return _vertices_from(rep, phi, known, order), rep.faces.copy(), info


def sampled_vertices(rep: LambdaH, *, order: int = 3) -> np.ndarray:
    """The mesh's vertices as an exact ``"newton"`` rebuild gives them back: each vertex
    that :func:`rebuild_grid` moves, moved to the *sampled* φ interpolated at its (u, v).

    A converged rebuild returns the sampled φ at the grid's nodes (it solves equations the
    sampled φ satisfies exactly), so these vertices are the closest that any rebuild of this
    grid can come to the mesh: the grid's *sampling floor*. Where the map squeezes part of
    the surface into a few cells (λ, the stretch, large: a finger's tip, a leg's hoof), the
    grid misses it whatever the solver does (docs/representation.md, session 17).
    """
    return _vertices_from(rep, rep.phi, _newton_known(rep), order)


def _newton_known(rep: LambdaH) -> np.ndarray:
    """The nodes the ``"newton"`` rebuild keeps: the band, and the nodes on no triangle of
    the finest level (or without its H) that keep their data (the band without levels)."""
    if not rep.levels:
        return rep.known
    on = np.isfinite(rep.levels[0].lam)
    return rep.known | (rep.domain & ~on) | (on & ~np.isfinite(rep.levels[0].H))


def _vertices_from(rep: LambdaH, phi: np.ndarray, known: np.ndarray, order: int
                   ) -> np.ndarray:
    """``rep``'s vertices, those whose interpolation cell touches a node off ``known``
    moved to ``phi`` interpolated at their (u, v) (``order`` 1 or 3)."""
    out = np.array(rep.vertices, dtype=float, copy=True)
    used = np.zeros(len(out), dtype=bool)
    used[rep.faces.ravel()] = True
    touches = interpolate((rep.domain & ~known).astype(float), rep.grid, rep.uv, order=1)
    moved = used & np.isfinite(touches) & (touches > 0)
    values = interpolate(phi, rep.grid, rep.uv[moved], order=order)
    ok = np.isfinite(values).all(axis=1)
    idx = np.flatnonzero(moved)[ok]
    out[idx] = values[ok]
    return out
