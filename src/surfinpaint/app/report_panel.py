"""One hole's panel of ``surfinpaint report``, in the layout of the paper's figures: the
surface with the hole and its fills from one camera (A, B, C and W), λ and H before and
after inpainting over the hole's parameter domain (D–G); what each panel shows is said in
:mod:`surfinpaint.app.report`, which decides what it draws (:func:`~surfinpaint.app.report.
panel_fills`).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from surfinpaint.app.figures import (
    add_legend,
    add_scale_bar,
    crop_to_ink,
    grid_image,
    render_hole,
    save_figure,
)
from surfinpaint.app.interrupts import imported_whole
from surfinpaint.app.lambda_h_images import lambda_h_images
from surfinpaint.fill.results import LambdaHDiagnostics

__all__ = ["PANEL_SIZE", "Patch", "hole_panel"]

PANEL_SIZE = (1600, 960)  # pixels of every hole panel
_DPI = 100

# one hole's fill: (vertices starting with the mesh's, the hole's new faces)
Patch = tuple[np.ndarray, np.ndarray]


def _range(arrays, masks, low=2.0, high=98.0):
    values = np.concatenate([a[m & np.isfinite(a)] for a, m in zip(arrays, masks, strict=True)])
    if len(values) == 0:
        return None, None
    lo, hi = np.percentile(values, [low, high])
    if hi - lo <= 1e-9 * max(abs(lo), abs(hi), 1.0):
        # constant up to round-off (λ = 1, H = 0 on a cube's faces): a readable range
        # around it, not one whose colour bar labels are round-off
        centre = 0.5 * (lo + hi)
        half = 0.05 * abs(centre) if centre != 0 else 1.0
        lo, hi = centre - half, centre + half
    return float(lo), float(hi)


def hole_panel(
    vertices: np.ndarray,
    faces: np.ndarray,
    loop: np.ndarray,
    fair: tuple[np.ndarray, np.ndarray],
    conformal: tuple[np.ndarray, np.ndarray],
    diagnostics: LambdaHDiagnostics | None,
    path: str | os.PathLike,
    *,
    written: Patch | None = None,
    titles: dict | None = None,
    suptitle: str = "",
) -> Path:
    """Write the paper-style panel of one hole (A–G, see :mod:`surfinpaint.app.report`) as a
    PNG of ``PANEL_SIZE`` pixels.

    Parameters
    ----------
    vertices, faces : arrays
        The mesh with the hole.
    loop : (k,) int array
        The hole's boundary loop.
    fair, conformal : (vertices, faces)
        The two fills of this hole: ``faces`` index ``vertices``, which must start with the
        mesh's vertices (a :class:`~surfinpaint.fill.pipeline.FillResult`'s ``vertices`` and the
        hole's new faces). ``conformal`` may be None (the method failed): (C) says so.
    diagnostics : LambdaHDiagnostics or None
        What the conformal fill's λ-H pass left (:attr:`surfinpaint.HoleReport.diagnostics`);
        panels D–G say "no data" without it.
    path : path
    written : (vertices, faces), optional
        The fill ``surfinpaint fill`` writes, as ``fair``, where neither ``fair`` nor
        ``conformal`` is it: drawn as a fourth 3D panel (W) beside (C).
    titles : dict, optional
        Replacement titles for panels ``"A"``–``"G"`` and ``"W"``.
    suptitle : str
    """
    Figure = imported_whole("matplotlib.figure", "matplotlib.backends.backend_agg").Figure


    vertices = np.asarray(vertices, float)
    loop = np.asarray(loop)
    names = {
        "A": "(A) surface with the hole", "B": "(B) conventional fill (faired)",
        "C": "(C) conformal fill", "W": "(W) written fill", "D": "(D) initial λ (known part)",
        "E": "(E) inpainted λ", "F": "(F) initial H (known part)", "G": "(G) inpainted H",
    }
    if diagnostics is not None and diagnostics.mesh is not None and diagnostics.mesh.one_side:
        # λ and H of one side of a crease (each side is inpainted on its own)
        for key in "DEFG":
            names[key] += ", one side"
    names.update(titles or {})
    drawn = (fair, conformal) if written is None else (fair, conformal, written)
    fills = [None if fill is None else (np.asarray(fill[0], float), np.asarray(fill[1]))
             for fill in drawn]
    # every 3D panel from one camera, so that the fills compare by eye
    images, units_per_pixel = render_hole(vertices, faces, loop, fills, size=(520, 440))
    images = crop_to_ink(images)
    fig = Figure(figsize=(PANEL_SIZE[0] / _DPI, PANEL_SIZE[1] / _DPI), dpi=_DPI,
                 layout="constrained")
    grid = fig.add_gridspec(2, 12, height_ratios=[1.0, 1.0])
    width = 12 // len(images)  # 3 or 4 panels share the top row
    for k, (key, image) in enumerate(zip("ABCW"[:len(images)], images, strict=True)):
        ax = fig.add_subplot(grid[0, width * k:width * (k + 1)])
        ax.imshow(image)
        ax.set_axis_off()
        ax.set_title(names[key], fontsize=11)
        if key == "A":
            add_scale_bar(ax, units_per_pixel)
        if key == "C" and conformal is None:
            ax.text(0.5, 0.5, "the conformal method failed on this hole\n(the faired fill "
                    "was used)", ha="center", va="center", transform=ax.transAxes)
    images = lambda_h_images(diagnostics)
    if images is not None:
        domain, hole, region = images.domain, images.hole, images.region
        lam_range = _range([images.lam0, images.lam], [domain, domain])
        h_range = _range([images.H0, images.H], [domain, domain])
        for k, (key, name, cmap, span, label) in enumerate((
                ("D", "lam0", "viridis", lam_range, "λ"),
                ("E", "lam", "viridis", lam_range, "λ"),
                ("F", "H0", "coolwarm", h_range, "H"),
                ("G", "H", "coolwarm", h_range, "H"))):
            ax = fig.add_subplot(grid[1, 3 * k:3 * k + 3])
            grid_image(ax, getattr(images, name), names[key], hole=hole, region=region,
                       domain=domain,
                       cmap=cmap, vmin=span[0], vmax=span[1], label=label)
    else:
        ax = fig.add_subplot(grid[1, :])
        ax.set_axis_off()
        ax.text(0.5, 0.5, "no λ, H data: the conformal method did not run on this hole",
                ha="center", va="center", fontsize=12)
    add_legend(fig)
    if suptitle:
        fig.suptitle(suptitle, fontsize=12)
    return save_figure(fig, path, dpi=_DPI)
