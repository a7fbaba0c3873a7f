"""Pictures of λ-H representations: λ and H over the parameter domain (the paper's Figs.
2–4) and the map's angle distortion (Fig. 1(D)), for each discretization."""

from __future__ import annotations

import os

import numpy as np

from surfinpaint.app.figures import save_figure
from surfinpaint.geometry.parameterization import angle_distortion, distortion_histogram

__all__ = ["plot_conformality", "plot_representation"]


def plot_conformality(ax, vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray,
                      bins: int = 60, range_deg: tuple[float, float] = (-30.0, 30.0),
                      label: str | None = None):
    """Draw the angle-distortion histogram on a matplotlib ``ax``; returns ``ax``."""
    counts, edges = distortion_histogram(vertices, faces, uv, bins, range_deg)
    ax.stairs(counts, edges, fill=True, alpha=0.6, label=label)
    ax.set_xlabel("angle difference (degrees)")
    ax.set_ylabel("number of angles")
    return ax


def _range(values: np.ndarray, clip: float, symmetric: bool) -> dict:
    finite = values[np.isfinite(values)]
    if not len(finite):
        return {}
    lo, hi = np.percentile(finite, [clip, 100 - clip])
    if symmetric:
        m = max(abs(lo), abs(hi), 1e-12)
        return {"vmin": -m, "vmax": m}
    return {"vmin": lo, "vmax": hi}


# λ drawn on a log scale when its largest value is this many times its smallest
_LOG_RANGE = 100.0


def lambda_panel(lam: np.ndarray) -> tuple[np.ndarray, str]:
    """λ as drawn, and its panel's title: log₁₀ λ where λ varies more than ``_LOG_RANGE``-
    fold (a map that squeezes a limb's tip 1000-fold: on a linear scale all but the tip is
    one colour), else λ itself."""
    lam = np.asarray(lam, dtype=float)
    finite = lam[np.isfinite(lam) & (lam > 0)]
    if len(finite) and finite.max() > _LOG_RANGE * finite.min():
        return np.log10(np.where(lam > 0, lam, np.nan)), "conformal factor log₁₀ λ"
    return lam, "conformal factor λ"


def plot_representation(rep, path: str | os.PathLike, *, clip: float = 1.0,
                        title: str | None = None) -> None:
    """Write a PNG of λ and H over the parameter domain with colour bars and the histogram
    of the map's angle distortion. Written atomically.

    Parameters
    ----------
    rep : MeshLambdaH, LambdaH or QuadtreeLambdaH
        On the mesh, λ and H are drawn on the parameter triangles (Gouraud shading of the
        vertex values); on the grid, as images; on quadtrees, on the finest tree's
        triangles, with their edges.
    path : str or PathLike
    clip : float
        The colour ranges are clipped to the ``clip``/``100 − clip`` percentiles (H of a
        mesh has outliers on slivers, λ near a rectangle's corners). λ is drawn as
        log₁₀ λ where it varies more than 100-fold.
    title : str, optional
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8), constrained_layout=True,
                             gridspec_kw={"width_ratios": [1, 1, 0.8]})
    lam, lam_name = lambda_panel(rep.lam)
    panels = ((axes[0], lam, lam_name, "viridis", False),
              (axes[1], rep.H, "mean curvature H", "RdBu_r", True))
    if rep.discretization in ("mesh", "quadtree"):
        import matplotlib.tri as mtri

        if rep.discretization == "mesh":
            uv, faces = rep.uv, rep.faces
            size = f"{len(rep.vertices)} vertices"
        else:  # the finest tree, its cells drawn: where the map squeezes, they are small
            uv, faces = rep.finest.uv, rep.finest.faces
            size = f"finest tree of {len(uv)} nodes"
        triangulation = mtri.Triangulation(uv[:, 0], uv[:, 1], faces)
        for ax, data, name, cmap, symmetric in panels:
            values = np.where(np.isfinite(data), data, np.nanmedian(data))  # border: no H
            im = ax.tripcolor(triangulation, values, shading="gouraud", cmap=cmap,
                              **_range(data, clip, symmetric))
            if rep.discretization == "quadtree":
                ax.triplot(triangulation, color="k", linewidth=0.1, alpha=0.3)
            _decorate(fig, ax, im, name)
    else:
        g = rep.grid
        extent = (g.origin[0] - g.h / 2, g.origin[0] + (g.shape[0] - 0.5) * g.h,
                  g.origin[1] - g.h / 2, g.origin[1] + (g.shape[1] - 0.5) * g.h)
        size = f"{g.shape[0]}×{g.shape[1]}{' graded' if g.graded else ''}"
        for ax, data, name, cmap, symmetric in panels:
            # arrays are [i, j] = (u, v): transpose so u runs along x and v along y
            if g.graded:  # cells of unequal size, drawn where they are
                im = ax.pcolormesh(g.u, g.v, data.T, shading="nearest", cmap=cmap,
                                   **_range(data, clip, symmetric))
            else:
                im = ax.imshow(data.T, origin="lower", extent=extent, interpolation="nearest",
                               cmap=cmap, **_range(data, clip, symmetric))
            _decorate(fig, ax, im, name)
    distortion = np.abs(angle_distortion(rep.vertices, rep.faces, rep.uv))
    plot_conformality(axes[2], rep.vertices, rep.faces, rep.uv)
    axes[2].set_title(f"angle distortion, median {np.median(distortion):.2f}°")
    fig.suptitle(title or f"λ-H representation ({rep.discretization}, {rep.map} map, {size})")
    try:
        save_figure(fig, path, dpi=120)
    finally:
        plt.close(fig)


def _decorate(fig, ax, image, name: str) -> None:
    ax.set_title(name)
    ax.set_xlabel("u")
    ax.set_ylabel("v")
    ax.set_aspect("equal")
    fig.colorbar(image, ax=ax, shrink=0.85)
