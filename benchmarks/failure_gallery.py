"""The holes where the default fill loses most, in pictures (issue 14): every hole of one half
of the validation benchmark where the fill the self-check writes is more than 1.5× the better
faired fill's error, as the removed truth and the three candidates (bilaplacian,
trilaplacian, λ-H), seen along the hole's normal and from the side.

The holes are read from a score table of ``selfcheck_table.py`` (the library's rule replayed
by ``selfcheck_replay.py``); the candidates are made again as the table makes them. Meant
for the tuning half: looking at the validation half's failures to design a rule would be
tuning on it.

    python benchmarks/failure_gallery.py --cache /tmp/scores.jsonl --split tuning \\
        --out docs/images/selfcheck_failures_tuning.png
"""

from __future__ import annotations

import argparse
import functools
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import holes_manifest  # noqa: E402
import selfcheck_replay as replay  # noqa: E402
import selfcheck_table  # noqa: E402
import validation  # noqa: E402
import validation_meshes as vm  # noqa: E402

from surfinpaint.app.figures import (  # noqa: E402
    HoleFrame,
    MeshView,
    add_scale_bar,
    crop_to_ink,
    frame_hole,
    render_hole,
    render_views,
    save_figure,
)
from surfinpaint.fill.conformal import ConformalOptions  # noqa: E402
from surfinpaint.fill.neighbourhood import FilledMesh  # noqa: E402

PANELS = (("truth", "truth"), ("fair2", "bilaplacian"), ("fair3", "trilaplacian"),
          ("conformal", "λ-H"))
SIZE = (260, 200)
_load = functools.lru_cache(maxsize=None)(vm.load)  # a mesh with several losing holes: once


def losing_holes(rows, limit: float = 1.5) -> list[dict]:
    """The rows where the library's rule writes more than ``limit`` × the better faired
    fill's error, worst first."""
    out = []
    for r, written in zip(rows, replay.chosen_errors(rows, replay.rule_library), strict=True):
        better = min(r["true"]["fair2"], r["true"]["fair3"])
        if better > 1e-6 and written / better > limit:
            out.append({**r, "written": written, "ratio": written / better})
    return sorted(out, key=lambda r: -r["ratio"])


def side_views(vertices, faces, frame: HoleFrame, fills) -> list[np.ndarray]:
    """The hole's surroundings and each fill from the side: the camera looks along the
    surface (``frame.up``) with the hole's normal up, so a fill that bulges shows."""
    radius = 2.5 * frame.half_height
    near = (np.linalg.norm(vertices - frame.centre, axis=1) <= radius)[faces].all(axis=1)
    views = []
    for fill in fills:
        if fill is None:
            views.append(MeshView(np.zeros((0, 3)), np.zeros((0, 3), int)))
            continue
        all_vertices, patch = fill
        kept = np.concatenate([faces[near], patch])
        views.append(MeshView(all_vertices, kept, highlight=np.arange(near.sum(), len(kept))))
    return render_views(views, centre=frame.centre, direction=frame.up,
                        distance=20.0 * frame.half_height, size=SIZE, up=frame.direction,
                        half_height=0.6 * frame.half_height)


def hole_fills(entry, k: int, options: ConformalOptions):
    """The hole's neighbourhood and its panels' fills: (vertices, faces, loop, {name:
    (all vertices, new faces) or None})."""
    cut = validation._cut(_load(entry["mesh"]), entry["holes"][k])
    local = FilledMesh(cut.vertices, cut.faces).cut(
        cut.loop, options.neighbourhood_rings(len(cut.loop)))
    v, f, loop = local.vertices, local.faces, local.local_loop
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, made, _, _ = selfcheck_table.made_candidates(v, f, loop, options)
    fills = {"truth": (np.vstack([v, cut.truth_vertices]), cut.truth_faces + len(v))}
    for name in ("fair2", "fair3", "conformal"):
        fill = made[name]
        fills[name] = (None if isinstance(fill, Exception) else
                       (np.vstack([v, fill.vertices]), np.asarray(fill.faces)))
    return v, f, loop, fills


def gallery(rows, out: Path) -> Path:
    import matplotlib.pyplot as plt

    holes = losing_holes(rows)
    if not holes:
        raise SystemExit("no hole above 1.5× the better faired fill: nothing to draw")
    entries = {e["mesh"]: e for e in holes_manifest.read()["meshes"]}
    options = ConformalOptions()
    fig, axes = plt.subplots(2 * len(holes), len(PANELS),
                             figsize=(2.6 * len(PANELS), 3.6 * len(holes)), squeeze=False)
    for i, r in enumerate(holes):
        v, f, loop, fills = hole_fills(entries[r["mesh"]], r["hole"], options)
        panels = [fills[name] for name, _ in PANELS]
        images, units = render_hole(v, f, loop, panels, size=SIZE)
        images = crop_to_ink(images[1:])
        sides = crop_to_ink(side_views(v, f, frame_hole(v, f, loop), panels))
        for j, (name, words) in enumerate(PANELS):
            error = (f"{r['mesh']} #{r['hole']}: " if name == "truth" else
                     f": {r['true'][name]:.3g} %")
            top, bottom = axes[2 * i, j], axes[2 * i + 1, j]
            top.imshow(images[j])
            bottom.imshow(sides[j])
            top.set_title(error + words if name == "truth" else words + error, fontsize=9)
            for ax in (top, bottom):
                ax.set_axis_off()
        axes[2 * i + 1, 0].set_title(f"written: {r['written']:.3g} % = {r['ratio']:.2f}× the "
                                     "better faired fill; from the side", fontsize=8,
                                     loc="left")
        add_scale_bar(axes[2 * i, 0], units)
    fig.tight_layout()
    path = save_figure(fig, out, dpi=80)
    plt.close(fig)
    return path


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cache", required=True, help="a selfcheck_table.py score table")
    parser.add_argument("--split", choices=("tuning", "validation"), default="tuning")
    parser.add_argument("--out", required=True, help="PNG file")
    args = parser.parse_args(argv)
    rows = [r for r in selfcheck_table.read_cache(Path(args.cache)) if r["split"] == args.split]
    print(gallery(rows, Path(args.out)))


if __name__ == "__main__":
    main()
