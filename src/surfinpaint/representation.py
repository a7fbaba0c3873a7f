"""The λ-H representation of a disk-topology triangle mesh, and the surface rebuilt from it.

:func:`represent` maps the mesh conformally to the plane (method.md §6.4), samples its
positions φ on a regular grid over the parameter domain (§6.5) and computes the conformal
factor λ and the mean curvature H there (§3). :func:`rebuild` goes back: φ is reconstructed
from (λ, H) on the interior of the domain with a band of boundary nodes as known data (§4),
and every mesh vertex is placed at the reconstructed φ at its (u, v) (§6.8). The round trip
measures the whole chain map → sample → λ, H → reconstruct → interpolate on a surface whose
(λ, H) are right.
"""

from __future__ import annotations

import os
import tempfile
import warnings
from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np
from scipy import ndimage

from surfinpaint.errors import MeshError, preview
from surfinpaint.grid import Grid, grid_over, interpolate, resample
from surfinpaint.parameterization import flipped_faces, lscm, rectangular_conformal_map

__all__ = [
    "FoldedMapWarning",
    "LambdaH",
    "MAPS",
    "boundary_band",
    "disk_from_mesh",
    "parameterize",
    "plot_representation",
    "rebuild",
    "represent",
]

MAPS = ("rectangular", "lscm")

# the Gauss–Codazzi rebuild closes its stencils with 3 rings (8-neighbour) of known nodes
_BLOCK = ndimage.generate_binary_structure(2, 2)
_FORMAT = 1


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

    @property
    def unknown(self) -> np.ndarray:
        """(N, M) nodes that :func:`rebuild` reconstructs: the domain minus the band."""
        return self.domain & ~self.known

    def save(self, path: str | os.PathLike) -> None:
        """Write to ``path`` as ``.npz``, atomically (temporary file, then rename)."""
        path = Path(path)
        arrays = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "grid"}
        arrays["map"] = np.array(self.map)
        arrays["band"] = np.array(self.band)
        arrays["grid_origin"] = np.array(self.grid.origin, dtype=float)
        arrays["grid_h"] = np.array(self.grid.h, dtype=float)
        arrays["grid_shape"] = np.array(self.grid.shape, dtype=np.int64)
        arrays["format"] = np.array(_FORMAT)
        fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".tmp",
                                   dir=path.parent if str(path.parent) else ".")
        try:
            with os.fdopen(fd, "wb") as handle:
                np.savez_compressed(handle, **arrays)
            os.replace(tmp, path)
        except BaseException:
            if os.path.exists(tmp):
                os.unlink(tmp)
            raise

    @classmethod
    def load(cls, path: str | os.PathLike) -> LambdaH:
        """Read a representation written by :meth:`save`.

        Raises
        ------
        ValueError
            When the file is not a λ-H representation (names what is missing).
        """
        with np.load(path, allow_pickle=False) as data:
            needed = {"grid_origin", "grid_h", "grid_shape", "domain", "lam", "H", "phi",
                      "known", "uv", "vertices", "faces", "map"}
            missing = sorted(needed - set(data.files))
            if missing:
                raise ValueError(f"{path}: not a λ-H representation (missing {missing})")
            grid = Grid(tuple(float(x) for x in data["grid_origin"]), float(data["grid_h"]),
                        tuple(int(x) for x in data["grid_shape"]))
            return cls(
                grid=grid, domain=data["domain"].astype(bool), lam=data["lam"], H=data["H"],
                phi=data["phi"], known=data["known"].astype(bool), uv=data["uv"],
                vertices=data["vertices"], faces=data["faces"].astype(np.int64),
                map=str(data["map"]), band=int(data["band"]) if "band" in data.files else 4,
                corners=data["corners"] if "corners" in data.files else np.zeros(0, np.int64),
            )


def disk_from_mesh(vertices: np.ndarray, faces: np.ndarray, *, fill_holes: bool = True,
                   max_rounds: int = 20) -> tuple[np.ndarray, np.ndarray]:
    """Make a topological disk out of an open mesh such as a range scan.

    Keeps the largest connected component, removes the faces around pinched boundary
    vertices and slivers of zero area (repeating while that creates new ones), then closes
    every boundary loop but the longest with the conventional fill (Liepa's triangulate /
    refine / fair, :func:`surfinpaint.baseline.conventional_fill`). Unused vertices are
    dropped.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        Consistently oriented, edge-manifold.
    fill_holes : bool
        Close the inner loops; otherwise a mesh with several loops raises.
    max_rounds : int
        Limit on the cleaning rounds.

    Returns
    -------
    vertices, faces
        A mesh that passes :func:`~surfinpaint.parameterization.check_disk`.

    Raises
    ------
    MeshError
        When no disk comes out (e.g. a closed mesh, or a handle), saying why.
    """
    from surfinpaint.mesh import boundary_loops, connected_components, face_areas
    from surfinpaint.parameterization import check_disk, pinched_vertices

    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    for _ in range(max_rounds):
        _, label = connected_components(f, len(v))
        biggest = np.argmax(np.bincount(label[f[:, 0]]))
        f = f[label[f[:, 0]] == biggest]
        area = face_areas(v, f)
        scale = float(np.ptp(v[np.unique(f)], axis=0).max())
        bad = area <= 1e-14 * scale**2
        pinched = pinched_vertices(f)
        if len(pinched):
            bad |= np.isin(f, pinched).any(axis=1)
        if not bad.any():
            break
        f = f[~bad]
    if fill_holes:
        from surfinpaint.baseline import conventional_fill

        for loop in boundary_loops(f)[1:]:
            new_v, new_f = conventional_fill(v, f, loop)
            v = np.vstack([v, new_v])
            f = np.vstack([f, new_f])
    used = np.unique(f)
    remap = np.full(len(v), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    v, f = v[used], remap[f]
    check_disk(v, f)
    return v, f


class FoldedMapWarning(UserWarning):
    """The conformal map folds some triangles over (see
    :func:`~surfinpaint.parameterization.flipped_faces`)."""


def parameterize(vertices: np.ndarray, faces: np.ndarray, map: str = "rectangular", *,
                 strict: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """``(uv, corners)`` of the named conformal map (``corners`` empty for LSCM).

    Folded (flipped) parameter triangles make the grid sampling ambiguous there; a few of
    them (they come from obtuse triangles on ragged boundaries) only disturb the sampling
    locally, so by default they give a :class:`FoldedMapWarning`.

    Raises
    ------
    ValueError
        For an unknown map name.
    MeshError
        When the mesh is not a disk, or, with ``strict``, when the map folds (names the
        flipped faces).
    """
    if map == "rectangular":
        uv, corners = rectangular_conformal_map(vertices, faces)
    elif map == "lscm":
        uv, corners = lscm(vertices, faces), np.zeros(0, dtype=np.int64)
    else:
        raise ValueError(f"unknown conformal map {map!r}; choose from {MAPS}")
    flipped = flipped_faces(faces, uv)
    if len(flipped):
        message = (f"the {map} map folds {len(flipped)} of {len(faces)} triangles over "
                   f"(faces {preview(flipped)}); the mesh probably has badly shaped "
                   "triangles there")
        if strict:
            raise MeshError(message, faces=flipped[:100])
        warnings.warn(message, FoldedMapWarning, stacklevel=3)
    return uv, corners


def boundary_band(domain: np.ndarray, band: int = 4) -> np.ndarray:
    """Nodes of ``domain`` within ``band`` 8-neighbour steps of a node outside it (or of the
    grid border): the known data around the rebuilt interior."""
    interior = ndimage.binary_erosion(domain, structure=_BLOCK, iterations=band,
                                      border_value=0)
    return domain & ~interior


def represent(vertices: np.ndarray, faces: np.ndarray, resolution: int = 256, *,
              map: str = "lscm", band: int = 4, h: float | None = None,
              strict: bool = False) -> LambdaH:
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
        The conformal map (:func:`~surfinpaint.parameterization.lscm`, the default, measured
        2–4× more accurate in round trips and folding fewer triangles on ragged borders, or
        the paper's :func:`~surfinpaint.parameterization.rectangular_conformal_map`); both
        scale the domain so that its area is the surface area.
    band : int
        Width in nodes of the boundary band kept as known data for :func:`rebuild`. The
        Gauss–Codazzi rebuild needs λ and H on 3 known rings, and λ, H need one more ring
        of φ, hence 4; the Laplacian rebuild needs 1.
    h : float, optional
        Grid spacing, instead of ``resolution``.
    strict : bool
        Raise instead of warning when the map folds triangles over.

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
    >>> from surfinpaint.data import bumpy_disk
    >>> rep = represent(*bumpy_disk(8), resolution=32)
    >>> rep.lam.shape == rep.grid.shape
    True
    """
    from surfinpaint.lambda_h import lambda_h

    if band < 1:
        raise ValueError(f"band must be at least 1 node, got {band}")
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    uv, corners = parameterize(v, f, map, strict=strict)
    grid = grid_over(uv, h=h) if h is not None else grid_over(uv, resolution=resolution)
    phi, domain, _ = resample(uv, f, v, grid)
    lam, H = lambda_h(phi, grid.h)
    known = boundary_band(domain, band)
    return LambdaH(grid=grid, domain=domain, lam=lam, H=H, phi=phi, known=known, uv=uv,
                   vertices=v.copy(), faces=f.copy(), map=map, band=band,
                   corners=np.asarray(corners, dtype=np.int64))


def rebuild(rep: LambdaH, method: str = "laplacian", *, order: int = 3,
            lam: np.ndarray | None = None, H: np.ndarray | None = None,
            **options) -> tuple[np.ndarray, np.ndarray]:
    """The mesh rebuilt from its λ-H representation.

    φ is reconstructed on the unknown nodes (the domain minus its boundary band) from
    (λ, H) with the band's φ as boundary data; each vertex whose interpolation cell touches
    a reconstructed node is moved to the interpolated φ at its (u, v). The other vertices
    lie in the band, where φ is the original surface itself, so they keep their positions
    (interpolating the resampled surface there would only add interpolation error).

    Parameters
    ----------
    rep : LambdaH
    method : {"laplacian", "gauss-codazzi"}
        The reconstruction (:func:`surfinpaint.reconstruction.reconstruct`). The Laplacian
        form measured 2–10x lower round-trip error and 4–10x faster here (bumpy disk,
        ``benchmarks/represent_speed.py``).
    order : {1, 3}
        Bilinear or bicubic interpolation of the reconstructed φ at the vertices (bicubic
        falls back to bilinear where its 4×4 stencil leaves the domain).
    lam, H : (N, M) arrays, optional
        Replace the representation's λ and H (e.g. inpainted or edited ones).
    **options
        Passed on to ``reconstruct``.

    Returns
    -------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        The representation's faces, unchanged.
    """
    from surfinpaint.reconstruction import reconstruct

    lam = rep.lam if lam is None else np.asarray(lam, dtype=float)
    H = rep.H if H is None else np.asarray(H, dtype=float)
    phi = reconstruct(lam, H, rep.phi, rep.known, rep.grid.h, method=method,
                      domain=rep.domain, **options)
    out = np.array(rep.vertices, dtype=float, copy=True)
    used = np.zeros(len(out), dtype=bool)
    used[rep.faces.ravel()] = True
    touches = interpolate(rep.unknown.astype(float), rep.grid, rep.uv, order=1)
    moved = used & np.isfinite(touches) & (touches > 0)
    values = interpolate(phi, rep.grid, rep.uv[moved], order=order)
    ok = np.isfinite(values).all(axis=1)
    idx = np.flatnonzero(moved)[ok]
    out[idx] = values[ok]
    return out, rep.faces.copy()


def plot_representation(rep: LambdaH, path: str | os.PathLike, *, clip: float = 1.0,
                        title: str | None = None) -> None:
    """Write a PNG of λ and H over the parameter domain with colour bars (paper Figs. 2–4)
    and the histogram of the map's angle distortion (paper Fig. 1(D)). Written atomically.

    Parameters
    ----------
    rep : LambdaH
    path : str or PathLike
    clip : float
        The colour ranges are clipped to the ``clip``/``100 − clip`` percentiles, since H of
        a resampled piecewise-linear surface has spikes on the edges (and λ near a
        rectangle's corners).
    title : str, optional
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    g = rep.grid
    extent = (g.origin[0] - g.h / 2, g.origin[0] + (g.shape[0] - 0.5) * g.h,
              g.origin[1] - g.h / 2, g.origin[1] + (g.shape[1] - 0.5) * g.h)
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8), constrained_layout=True,
                             gridspec_kw={"width_ratios": [1, 1, 0.8]})
    finite_h = rep.H[np.isfinite(rep.H)]
    if len(finite_h):
        lo, hi = np.percentile(finite_h, [clip, 100 - clip])
        m = max(abs(lo), abs(hi), 1e-12)
    else:
        m = 1.0
    finite_lam = rep.lam[np.isfinite(rep.lam)]
    lam_range = (dict(zip(("vmin", "vmax"), np.percentile(finite_lam, [clip, 100 - clip]),
                          strict=True)) if len(finite_lam) else {})
    for ax, data, name, kw in (
        (axes[0], rep.lam, "conformal factor λ", {"cmap": "viridis", **lam_range}),
        (axes[1], rep.H, "mean curvature H", {"cmap": "RdBu_r", "vmin": -m, "vmax": m}),
    ):
        # arrays are [i, j] = (u, v): transpose so u runs along x and v along y
        im = ax.imshow(data.T, origin="lower", extent=extent, interpolation="nearest", **kw)
        ax.set_title(name)
        ax.set_xlabel("u")
        ax.set_ylabel("v")
        ax.set_aspect("equal")
        fig.colorbar(im, ax=ax, shrink=0.85)
    from surfinpaint.figures import save_figure
    from surfinpaint.parameterization import angle_distortion, plot_conformality

    distortion = np.abs(angle_distortion(rep.vertices, rep.faces, rep.uv))
    plot_conformality(axes[2], rep.vertices, rep.faces, rep.uv)
    axes[2].set_title(f"conformality: angle distortion (median {np.median(distortion):.2f}°)")
    fig.suptitle(title or f"λ-H representation ({rep.map} map, {g.shape[0]}×{g.shape[1]})")
    try:
        save_figure(fig, path, dpi=120)
    finally:
        plt.close(fig)
