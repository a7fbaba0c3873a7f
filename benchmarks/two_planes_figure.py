"""The two-plane fill in a picture (docs/candidates.md, "Session 30: the two-plane fill split
along the meeting line"): a hole across a step's edge on a simulated range scan of a
tuning-side CAD part (scan_stair #2 of ``benchmarks/cad_tuning_manifest.json``), cut by a
plane across the edge through the hole's middle. The noise-free truth, the bilaplacian fill
(rounds the edge), the same fill projected onto the two planes (session 29: bevels it) and
the hole split along the planes' meeting line, each side laid on its plane (the default).

    python benchmarks/two_planes_figure.py --out docs/images/two_planes_scan.png
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
import validation_meshes as vm  # noqa: E402

from surfinpaint.fill.conformal import conformal_fill  # noqa: E402
from surfinpaint.fill.conformal.method import known_two_planes  # noqa: E402
from surfinpaint.fill.liepa.baseline import faired_fill, laid_on_two_planes  # noqa: E402
from surfinpaint.geometry.flatness import meeting_line  # noqa: E402

MESH, HOLE = "scan_stair", 2  # tuning side: the CAD parts' scans


def _section(vertices, faces, origin, normal):
    """The segments where a plane cuts the triangles, (s, 2, 3)."""
    import trimesh
    from trimesh.intersections import mesh_plane

    mesh = trimesh.Trimesh(vertices, faces, process=False)
    return mesh_plane(mesh, normal, origin)


def curves():
    """(label, segments (s, 2, 3), error % of the hole's diameter or None) per curve, the
    section's origin, its in-plane axes (across the edge, up) and the hole's diameter."""
    entry = next(e for e in holes_manifest.read(holes_manifest.CAD_TUNING_MANIFEST)["meshes"]
                 if e["mesh"] == MESH)
    cut = validation._cut(vm.load(MESH), entry["holes"][HOLE])
    v, f, loop = cut.vertices, cut.faces, cut.loop
    planes = known_two_planes(v, f, loop)
    assert planes is not None and planes.flat, "the default lays this hole on two planes"
    first = (planes.first.centre, planes.first.normal)
    second = (planes.second.centre, planes.second.normal)
    on_line, direction, _ = meeting_line(*first, *second)
    middle = v[loop].mean(axis=0)
    origin = on_line + ((middle - on_line) @ direction) * direction
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fair_v, fair_f, _ = faired_fill(v, f, loop, 2)
        default = conformal_fill(v, f, loop)
    projected = laid_on_two_planes(fair_v, first, second)
    items = [("removed truth (noise-free)", cut.truth_vertices, cut.truth_faces, None)]
    for label, nv, nf in (("bilaplacian fill", fair_v, fair_f),
                          ("projected onto the two planes (session 29)", projected, fair_f),
                          ("split along their line (the default)", default.vertices,
                           default.faces)):
        items.append((label, np.vstack([v, nv]), nf, study._error(cut, nv, nf, 10000)))
    up = planes.first.normal + planes.second.normal
    up -= (up @ direction) * direction
    up /= np.linalg.norm(up)
    across = np.cross(direction, up)
    known = ("the scan around the hole (noisy)", v, f, None)
    out = [(label, _section(p, t, origin, direction), err)
           for label, p, t, err in [known] + items]
    return out, origin, (across, up), cut.diameter


def draw(out_path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    items, origin, (across, up), diameter = curves()
    scale = 100.0 / diameter  # in % of the hole's diameter
    styles = [dict(color="0.75", lw=1.0), dict(color="black", lw=2.2, ls="--"),
              dict(color="tab:green", lw=1.6), dict(color="tab:orange", lw=1.6),
              dict(color="tab:blue", lw=1.8)]
    fig, ax = plt.subplots(figsize=(7.2, 4.6))
    shown = []
    for (label, segments, err), style in zip(items, styles, strict=True):
        xy = np.stack([(segments - origin) @ across, (segments - origin) @ up], axis=-1)
        xy *= scale
        text = label if err is None else f"{label}: {err:.2f} %"
        ax.add_collection(LineCollection(xy, label=text, **style))
        if err is not None:  # frame the fills, with some of the scan around them
            shown.append(xy.reshape(-1, 2))
    lo, hi = np.vstack(shown).min(axis=0), np.vstack(shown).max(axis=0)
    pad = 0.35 * (hi - lo).max()
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("across the edge, % of the hole's diameter")
    ax.set_ylabel("% of the hole's diameter")
    ax.set_title(f"{MESH} #{HOLE}: a section across the scanned edge through the hole")
    ax.legend(loc="best", fontsize=8, frameon=False)
    fig.tight_layout()
    out_path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out_path, dpi=130)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs/images/two_planes_scan.png"))
    args = parser.parse_args(argv)
    draw(args.out)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
