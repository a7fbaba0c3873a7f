"""Pictures, rendered off-screen: meshes before and after a fill.

PyVista (VTK) renders without a display; it is imported lazily so the numerical core does not
need it.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

__all__ = ["render_meshes", "before_after", "view_direction"]

SURFACE = "#d9d4c7"
PATCH = "#e8833a"
BORDER = "#c0392b"


def _pv_mesh(vertices: np.ndarray, faces: np.ndarray):
    import pyvista as pv

    faces = np.asarray(faces, dtype=np.int64)
    cells = np.column_stack([np.full(len(faces), 3), faces]).ravel()
    return pv.PolyData(np.asarray(vertices, dtype=float), cells)


def view_direction(vertices: np.ndarray, faces: np.ndarray, loops) -> np.ndarray:
    """A unit direction from which the given loops are seen from outside the surface."""
    from surfinpaint.mesh import vertex_normals

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
        plotter.camera_position = [tuple(centre + 2.6 * extent * direction), tuple(centre),
                                   tuple(up)]
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(suffix=".png", dir=path.parent)
    os.close(fd)
    try:
        plotter.screenshot(tmp)
        os.replace(tmp, path)
    finally:
        plotter.close()
        if os.path.exists(tmp):
            os.remove(tmp)
    return path


def before_after(vertices: np.ndarray, faces: np.ndarray, result, path) -> Path:
    """Two panels: the mesh with its holes outlined, and the filled mesh with the patches
    coloured. ``result`` is a :class:`surfinpaint.pipeline.FillResult`."""
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
