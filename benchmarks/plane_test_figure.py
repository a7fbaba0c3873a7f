"""The plane test in a picture (docs/candidates.md, "Session 26"): a hole on a flat face of
one of the study's simulated range scans of a tuning-half source, seen from above, coloured
by each surface's height above the fitted plane: the scan's noisy rings around the hole,
the bilaplacian fill (which takes its slopes from them), the same fill laid on the known
surface's plane (what the default writes there), and the removed truth.

    python benchmarks/plane_test_figure.py --out docs/images/plane_test_scan.png
"""

from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import holes_manifest  # noqa: E402
import scan_flatness_study as study  # noqa: E402
import validation  # noqa: E402

from surfinpaint.fill.conformal import conformal_fill  # noqa: E402
from surfinpaint.fill.conformal.method import known_plane  # noqa: E402
from surfinpaint.fill.liepa.baseline import faired_fill  # noqa: E402
from surfinpaint.geometry.mesh import k_ring  # noqa: E402

MESH, HOLE = "xscan_bracket_under", 6  # an extra scan of a tuning source: a 10 h hole
RINGS = 3  # known rings drawn around the hole


def _hole(mesh_id: str, hole: int):
    """The cut of hole ``hole`` of ``scan_flatness_study``'s extra scan ``mesh_id`` (a
    tuning-half source), planned as the study plans it."""
    mesh = study.extra_mesh(mesh_id)
    planned = holes_manifest.plan_holes(mesh.vertices, mesh.faces, "range_scan",
                                        2000 + list(study.EXTRA).index(mesh_id), mesh_id)
    return validation._cut(mesh, planned[hole])


def panels(mesh_id: str = MESH, hole: int = HOLE):
    """(title, points (n, 3), triangles, error % of the hole's diameter or None) per panel,
    the plane test's verdict, the hole's diameter and the new vertices' largest height."""
    cut = _hole(mesh_id, hole)
    plane = known_plane(cut.vertices, cut.faces, cut.loop)
    around = k_ring(cut.faces, cut.loop, RINGS, len(cut.vertices))
    rings = cut.faces[around[cut.faces].all(axis=1)]
    out = [("the scan around the hole (noisy)", cut.vertices, rings, None)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        new, patch, _ = faired_fill(cut.vertices, cut.faces, cut.loop, 2)
        fill = conformal_fill(cut.vertices, cut.faces, cut.loop)  # the default
        assert fill.plane is not None, "the default laid this hole on its plane"
        for title, (v, f) in (("the bilaplacian fill", (new, patch)),
                              ("laid on the plane (the default)", (fill.vertices, fill.faces))):
            out.append((title, np.vstack([cut.vertices, v]), np.vstack([rings, f]),
                        study._error(cut, v, f, 10000)))
    out.append(("the removed truth (noise-free)", cut.truth_vertices, cut.truth_faces, None))
    top = float(np.abs((new - plane.centre) @ plane.normal).max())
    return out, plane, cut.diameter, top


def draw(out_path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation

    items, plane, diameter, top = panels()
    normal = np.asarray(plane.normal)
    a = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
    a /= np.linalg.norm(a)
    b = np.cross(normal, a)
    scale = 100.0 / diameter  # heights in % of the hole's diameter
    heights = [((p - plane.centre) @ normal) * scale for _, p, _, _ in items]
    used = [np.unique(f) for _, _, f, _ in items]
    top *= scale  # the colour scale: the bilaplacian fill's largest height
    fig, axes = plt.subplots(1, len(items), figsize=(4.0 * len(items), 4.2))
    rings = items[0][1][used[0]] - plane.centre
    lo = np.column_stack([rings @ a, rings @ b]).min(axis=0)
    hi = np.column_stack([rings @ a, rings @ b]).max(axis=0)
    for ax, (title, p, f, error), h in zip(axes, items, heights, strict=True):
        xy = np.column_stack([(p - plane.centre) @ a, (p - plane.centre) @ b])
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        art = ax.tripcolor(Triangulation(xy[:, 0], xy[:, 1], f), h, shading="gouraud",
                           cmap="RdBu_r", vmin=-top, vmax=top)
        ax.set_title(title if error is None else f"{title}\n{error:.3f} %", fontsize=10)
        ax.set_aspect("equal")
        ax.set_autoscale_on(False)
        ax.axis("off")
    fig.colorbar(art, ax=axes, shrink=0.8,
                 label="height above the fitted plane, % of the hole's diameter")
    fig.suptitle(f"{MESH} #{HOLE}, a simulated scan of a tuning-half part: a hole on its flat "
                 "face; under each fill its mean distance to the removed truth, % of the "
                 "hole's diameter", fontsize=11, y=1.04)
    fig.savefig(out_path, dpi=110, bbox_inches="tight")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("docs/images/plane_test_scan.png"))
    draw(parser.parse_args(argv).out)


if __name__ == "__main__":
    main()
