"""Pictures, rendered off-screen: meshes before and after a fill.

PyVista (VTK) renders without a display; it is imported lazily so the numerical core does not
need it.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from surfinpaint.io.atomic import atomic_path

__all__ = ["before_after", "crop_around", "grid_image", "render_meshes", "render_views",
           "save_figure", "view_direction"]

SURFACE = "#d9d4c7"
PATCH = "#e8833a"
BORDER = "#c0392b"


def _quiet_vtk() -> None:
    """Silence VTK's note that there is no X display: off-screen rendering needs none."""
    try:
        from vtkmodules.vtkCommonCore import vtkLogger

        vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
    except ImportError:  # pragma: no cover - older VTK
        pass


def _pv_mesh(vertices: np.ndarray, faces: np.ndarray):
    import pyvista as pv

    faces = np.asarray(faces, dtype=np.int64)
    cells = np.column_stack([np.full(len(faces), 3), faces]).ravel()
    return pv.PolyData(np.asarray(vertices, dtype=float), cells)


def view_direction(vertices: np.ndarray, faces: np.ndarray, loops) -> np.ndarray:
    """A unit direction from which the given loops are seen from outside the surface."""
    from surfinpaint.geometry.mesh import vertex_normals

    if not loops:
        return np.array([1.0, 0.6, 0.8]) / np.linalg.norm([1.0, 0.6, 0.8])
    normals = vertex_normals(vertices, faces)
    d = sum(normals[np.asarray(loop)].sum(axis=0) for loop in loops)
    norm = np.linalg.norm(d)
    return d / norm if norm > 1e-9 else np.array([0.0, 0.0, 1.0])


def render_meshes(
    panels: list[dict],
    path: str | os.PathLike,
    *,
    direction: np.ndarray | None = None,
    window_size: tuple[int, int] = (1200, 600),
) -> Path:
    """Render side-by-side panels to a PNG, all seen from the same camera.

    Each panel is a dict with ``vertices``, ``faces``, optional ``highlight`` (face ids drawn
    in the patch colour), optional ``loops`` (boundary loops drawn as red lines) and ``title``.
    The PNG is written atomically.
    """
    import pyvista as pv

    pv.OFF_SCREEN = True
    _quiet_vtk()
    path = Path(path)
    plotter = pv.Plotter(off_screen=True, shape=(1, len(panels)), window_size=window_size,
                         border=False)
    plotter.set_background("white")
    centre = np.mean([np.asarray(p["vertices"]).mean(axis=0) for p in panels], axis=0)
    extent = max(np.ptp(np.asarray(p["vertices"]), axis=0).max() for p in panels)
    direction = np.array([1.0, 0.6, 0.8]) if direction is None else np.asarray(direction)
    direction = direction / np.linalg.norm(direction)
    up = np.array([0.0, 0.0, 1.0]) if abs(direction[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    for k, panel in enumerate(panels):
        plotter.subplot(0, k)
        mesh = _pv_mesh(panel["vertices"], panel["faces"])
        colours = np.tile(np.array([0.85, 0.83, 0.78]), (len(panel["faces"]), 1))
        highlight = panel.get("highlight")
        if highlight is not None and len(highlight):
            colours[np.asarray(highlight)] = (0.91, 0.51, 0.23)
        mesh.cell_data["colour"] = (colours * 255).astype(np.uint8)
        plotter.add_mesh(mesh, scalars="colour", rgb=True, smooth_shading=False,
                         specular=0.2, show_edges=len(panel["faces"]) < 20000,
                         edge_color="#8a8578", line_width=0.3)
        for loop in panel.get("loops") or []:
            pts = np.asarray(panel["vertices"])[np.append(loop, loop[0])]
            plotter.add_lines(np.repeat(pts, 2, axis=0)[1:-1], color=BORDER, width=3)
        if panel.get("title"):
            plotter.add_text(panel["title"], font_size=11, color="black")
        plotter.camera_position = [tuple(centre + 2.0 * extent * direction), tuple(centre),
                                   tuple(up)]
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        with atomic_path(path, suffix=".png") as tmp:
            plotter.screenshot(tmp)
    finally:
        plotter.close()
    return path


def before_after(vertices: np.ndarray, faces: np.ndarray, result, path) -> Path:
    """Two panels: the mesh with its holes outlined, and the filled mesh with the patches
    coloured. ``result`` is a :class:`surfinpaint.fill.pipeline.FillResult`."""
    loops = [r.loop for r in result.reports if not r.skipped]
    direction = view_direction(vertices, faces, loops)
    patch = np.arange(result.n_original_faces, len(result.faces))
    methods = sorted({r.method for r in result.reports if not r.skipped})
    return render_meshes(
        [
            {"vertices": vertices, "faces": faces, "loops": loops,
             "title": f"with holes ({len(loops)})"},
            {"vertices": result.vertices, "faces": result.faces, "highlight": patch,
             "title": "filled: " + ", ".join(methods) if methods else "filled"},
        ],
        path,
        direction=direction,
    )


# --------------------------------------------------------------------------- hole panels


def crop_around(vertices: np.ndarray, faces: np.ndarray, centre: np.ndarray,
                radius: float) -> np.ndarray:
    """Ids of the faces whose three corners lie within ``radius`` of ``centre``: a close-up
    renders only these, so nothing further away hides the hole."""
    inside = np.linalg.norm(np.asarray(vertices) - np.asarray(centre), axis=1) <= radius
    return np.flatnonzero(inside[np.asarray(faces)].all(axis=1))


def _up_vector(direction: np.ndarray) -> np.ndarray:
    # the world axis least aligned with the view: z when possible, then y, then x
    for axis in (np.array([0.0, 0, 1]), np.array([0.0, 1, 0]), np.array([1.0, 0, 0])):
        if abs(float(axis @ direction)) < 0.9:
            return axis
    return np.array([1.0, 0, 0])  # pragma: no cover - one of the three always qualifies


def _quiet_vtk() -> None:
    """Keep VTK's log to errors: off-screen rendering without a display logs a harmless
    "bad X server connection" warning on every render window."""
    try:
        from vtkmodules.vtkCommonCore import vtkLogger
    except ImportError:  # pragma: no cover - VTK without its logger
        return
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_ERROR)


def render_views(
    views: list[dict],
    *,
    centre: np.ndarray,
    direction: np.ndarray,
    distance: float,
    size: tuple[int, int] = (520, 440),
) -> list[np.ndarray]:
    """Render several meshes from one camera into RGB arrays (off-screen).

    Parameters
    ----------
    views : list of dict
        As the panels of :func:`render_meshes`: ``vertices``, ``faces``, optional
        ``highlight`` (face ids in the patch colour) and ``loops`` (drawn in red).
    centre, direction, distance :
        The camera looks at ``centre`` from ``centre + distance · direction``.
    size : (width, height)
        Pixels of each view.

    Returns
    -------
    list of (height, width, 3) uint8 arrays, one per view.
    """
    import pyvista as pv

    _quiet_vtk()
    pv.OFF_SCREEN = True
    direction = np.asarray(direction, float)
    direction = direction / np.linalg.norm(direction)
    centre = np.asarray(centre, float)
    width, height = size
    plotter = pv.Plotter(off_screen=True, shape=(1, len(views)),
                         window_size=(width * len(views), height), border=False)
    try:
        plotter.set_background("white")
        for k, view in enumerate(views):
            plotter.subplot(0, k)
            faces = np.asarray(view["faces"])
            if len(faces):
                mesh = _pv_mesh(view["vertices"], faces)
                colours = np.tile(np.array([0.85, 0.83, 0.78]), (len(faces), 1))
                highlight = view.get("highlight")
                if highlight is not None and len(highlight):
                    colours[np.asarray(highlight)] = (0.91, 0.51, 0.23)
                mesh.cell_data["colour"] = (colours * 255).astype(np.uint8)
                plotter.add_mesh(mesh, scalars="colour", rgb=True, smooth_shading=False,
                                 specular=0.25, show_edges=len(faces) < 30000,
                                 edge_color="#8a8578", line_width=0.4)
            for loop in view.get("loops") or []:
                pts = np.asarray(view["vertices"])[np.append(loop, loop[0])]
                plotter.add_lines(np.repeat(pts, 2, axis=0)[1:-1], color=BORDER, width=3)
            plotter.camera_position = [tuple(centre + distance * direction), tuple(centre),
                                       tuple(_up_vector(direction))]
            plotter.camera.view_angle = 30.0
        image = np.asarray(plotter.screenshot(return_img=True))
    finally:
        plotter.close()
    image = image[..., :3]
    step = image.shape[1] // len(views)
    return [image[:, k * step:(k + 1) * step].copy() for k in range(len(views))]


def grid_image(ax, values: np.ndarray, title: str, *, hole: np.ndarray | None = None,
               region: np.ndarray | None = None, domain: np.ndarray | None = None,
               cmap: str = "viridis", vmin: float | None = None, vmax: float | None = None,
               label: str = ""):
    """Show a grid function (λ or H over the parameter domain) with a colour bar and the
    hole outlined.

    Parameters
    ----------
    ax : matplotlib Axes
    values : (N, M) float array
        ``[i, j]`` ↔ ``(u_i, v_j)``; NaN nodes inside ``domain`` are drawn grey (no value:
        e.g. the hole before inpainting), nodes outside ``domain`` white.
    title : str
    hole : (N, M) bool array, optional
        Drawn as a solid black outline.
    region : (N, M) bool array, optional
        The inpainted region (the hole dilated), drawn as a dashed outline.
    domain : (N, M) bool array, optional
        Nodes inside the parameter domain (default: the finite ones).
    cmap, vmin, vmax :
        Colour map and range (shared between the panels to be compared).
    label : str
        Colour-bar label.

    Returns
    -------
    The image artist.
    """
    import matplotlib

    values = np.asarray(values, float)
    domain = np.isfinite(values) if domain is None else np.asarray(domain, bool)
    # NaN transparent: the grey underneath shows
    colour_map = matplotlib.colormaps[cmap].with_extremes(bad=(1.0, 1.0, 1.0, 0.0))
    # unknown nodes inside the domain: grey underneath the (transparent) NaN pixels
    background = np.where(domain & ~np.isfinite(values), 0.75, np.nan)
    ax.imshow(background.T, origin="lower", cmap="gray", vmin=0, vmax=1,
              interpolation="nearest")
    shown = np.where(domain, values, np.nan)
    image = ax.imshow(np.ma.masked_invalid(shown).T, origin="lower", cmap=colour_map,
                      vmin=vmin, vmax=vmax, interpolation="nearest")
    for mask, style in ((region, "--"), (hole, "-")):
        if mask is not None and np.asarray(mask).any():
            ax.contour(np.asarray(mask, float).T, levels=[0.5], colors="black",
                       linestyles=style, linewidths=1.2 if style == "-" else 0.9)
    ax.set_title(title, fontsize=10)
    ax.set_xticks([])
    ax.set_yticks([])
    bar = ax.figure.colorbar(image, ax=ax, shrink=0.8, pad=0.02)
    if label:
        bar.set_label(label)
    return image


def save_figure(fig, path: str | os.PathLike, dpi: int = 100) -> Path:
    """Save a matplotlib figure to a PNG atomically (temporary file, then rename)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_path(path, suffix=".png") as tmp:
        fig.savefig(tmp, dpi=dpi, format="png")
    return path
