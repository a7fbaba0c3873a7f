"""The paper's experiment set, regenerated: ``surfinpaint experiments -o DIR``.

Lui, Wen and Gu show hole fills on a cube (a hole across an edge), a snowman (two holes), a
human face (nose and both cheeks), a brain (four regions) and a tooth, and λ-H rebuilds of a
face and a brain. Here the same set is made from data that ships inside installed packages or
that this project generates, with ground truth: every hole is a geodesic disk cut out of a
complete mesh (:func:`surfinpaint.geometry.cutting.cut_holes`), and every fill is measured against
the
removed patch.

- cube: :func:`surfinpaint.data.cube`, one hole centred on the edge y = z = 0.
- snowman: :func:`surfinpaint.data.snowman`, one hole on the lower ball, one across the
  lower neck.
- face: PyMeshLab's scanned range map ``tests/sample_meshes/rangemaps/face000.ply`` (a head
  statue; the largest connected component). Holes on the nose tip and both cheeks; the nose
  tip is the vertex nearest the scanner (largest z, the viewing axis) within the middle of
  the lower half of the face (10–35 % of the height, 35–65 % of the width, so the forehead
  and the crown do not count); the cheeks are offset by ±20 % of the width and +3 % of the
  height from it, at the nearest vertex in (x, y).
- brain: FreeSurfer fsaverage5 left pial surface from nilearn
  (:func:`surfinpaint.data.fsaverage5`), four holes at the vertices furthest in four
  directions (lateral, superior, anterior, posterior).
- tooth: :func:`surfinpaint.data.tooth`, a *synthetic* tooth-like surface (not a scan),
  holes on a cusp and on the crown's side.
- rebuilds: a geodesic disk of the face (around the bridge of the nose) and of the brain (lateral),
  represented by λ and H (:func:`surfinpaint.representation.represent`) and rebuilt from
  them (:func:`surfinpaint.representation.represent.rebuild`); the error is the distance between the
  rebuilt and the original disk.

``scale="quick"`` runs the same set on coarser meshes and smaller holes, in well under a
minute; the default (``"full"``) takes a few minutes.
"""

from __future__ import annotations

import argparse
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from surfinpaint import data
from surfinpaint.app.figures import (
    MeshView,
    before_after,
    grid_image,
    render_views,
    save_figure,
    view_direction,
)
from surfinpaint.app.progress import QuietConsole, add_quiet, hole_news, named, progress_bar
from surfinpaint.app.report import (
    LEGEND,
    PANEL_SIZE,
    HoleComparison,
    compare_holes,
    panels_for,
    write_page,
)
from surfinpaint.app.report_page import WRITTEN_ERROR, PageSection, TruthDistance
from surfinpaint.errors import MeshError, agreeing, how_many
from surfinpaint.geometry.cutting import compact, cut_geodesic_disk, cut_holes
from surfinpaint.geometry.mesh import boundary_loops, connected_components
from surfinpaint.geometry.metrics import surface_distance
from surfinpaint.representation.represent import rebuild, represent

__all__ = ["CASES", "REBUILDS", "Case", "Rebuild", "add_experiments_parser", "face_scan",
           "face_sites", "run_experiments", "run_set"]

SCALES = ("full", "quick")


# --------------------------------------------------------------------------- cases


@dataclass
class Case:
    """A hole-filling experiment: a complete mesh and where to cut.

    ``make(scale)`` returns ``(vertices, faces, centres, radii)``: centres as vertex ids or
    points, radii as geodesic radii in mesh units.
    """

    name: str
    title: str
    note: str
    make: Callable[[str], tuple]


@dataclass
class Rebuild:
    """A λ-H rebuild experiment: ``make(scale)`` returns ``(vertices, faces, centre, radius,
    resolution)``; the disk of that radius around the centre is represented and rebuilt."""

    name: str
    title: str
    note: str
    make: Callable[[str], tuple]


def face_scan() -> tuple[np.ndarray, np.ndarray]:
    """PyMeshLab's face range map (``rangemaps/face000.ply``), its largest connected
    component, unused vertices dropped."""
    v, f = data.pymeshlab_sample("rangemaps/face000.ply")
    _, label = connected_components(f, len(v))
    f = f[label[f[:, 0]] == np.argmax(np.bincount(label[f[:, 0]]))]
    return compact(v, f)[:2]


def face_sites(vertices: np.ndarray) -> np.ndarray:
    """Vertex ids of the nose tip, the left and the right cheek of the face scan (see the
    module docstring for how they are found)."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    extent = hi - lo
    fx, fy = ((vertices[:, :2] - lo[:2]) / extent[:2]).T
    band = np.flatnonzero((fy > 0.10) & (fy < 0.35) & (fx > 0.35) & (fx < 0.65))
    tip = int(band[np.argmax(vertices[band, 2])])
    sites = [tip]
    for side in (-1.0, 1.0):
        target = vertices[tip, :2] + np.array([side * 0.2 * extent[0], 0.03 * extent[1]])
        sites.append(int(np.argmin(((vertices[:, :2] - target) ** 2).sum(axis=1))))
    return np.array(sites)


def _extreme(vertices: np.ndarray, directions) -> np.ndarray:
    d = np.asarray(directions, float)
    return np.argmax((vertices - vertices.mean(axis=0)) @ d.T, axis=0)


def _cube(scale):
    v, f = data.cube(12 if scale == "quick" else 24)
    return v, f, [np.array([0.5, 0.0, 0.0])], [0.25 if scale == "quick" else 0.2]


def _snowman(scale):
    v, f = data.snowman(edge_length=0.1 if scale == "quick" else 0.05)
    centres = [np.array([1.0, 0.0, -0.1]), np.array([0.0, -0.565, 0.94])]
    return v, f, centres, [0.55, 0.4]


def _face(scale):
    v, f = face_scan()
    return v, f, face_sites(v), [6.0 if scale == "quick" else 10.0] * 3


def _brain(scale):
    v, f = data.fsaverage5("pial", "left")
    sites = _extreme(v, [[-1, 0, 0.2], [0, 0, 1], [0, 1, 0], [0, -1, 0]])
    return v, f, sites, [10.0 if scale == "quick" else 14.0] * 4


def _tooth(scale):
    v, f = data.tooth(edge_length=0.08 if scale == "quick" else 0.04)
    centres = [np.array([0.42, 0.42, 1.3]), np.array([0.8, 0.0, 0.5])]
    return v, f, centres, [0.3, 0.3]


def _face_disk(scale):
    v, f = face_scan()
    # the bridge of the nose, 12 % of the height above the tip: nose, eyes and brows, and
    # clear of the scanner's own holes (around the tip they are 20 mm away)
    tip = face_sites(v)[0]
    target = v[tip, :2] + np.array([0.0, 0.12 * np.ptp(v[:, 1])])
    centre = int(np.argmin(((v[:, :2] - target) ** 2).sum(axis=1)))
    if scale == "quick":
        return v, f, centre, 15.0, 64
    return v, f, centre, 35.0, 160


def _brain_disk(scale):
    v, f = data.fsaverage5("pial", "left")
    site = _extreme(v, [[-1, 0, 0.2]])[0]
    if scale == "quick":
        return v, f, site, 20.0, 64
    return v, f, site, 30.0, 160


CASES = (
    Case("cube", "Cube: a hole across an edge", "data.cube: the unit cube, sharp edges.",
         _cube),
    Case("snowman", "Snowman: two holes", "data.snowman: three blended balls; one hole on "
         "the lower ball, one across the lower neck.", _snowman),
    Case("face", "Face: nose and both cheeks", "PyMeshLab's scanned range map "
         "rangemaps/face000.ply (a statue's head), largest component; nose tip = the point "
         "nearest the scanner in the lower middle of the face, cheeks beside it.", _face),
    Case("brain", "Brain: four regions", "fsaverage5 left pial surface (nilearn); holes at "
         "the lateral, superior, anterior and posterior extremes.", _brain),
    Case("tooth", "Tooth: two holes", "data.tooth: a SYNTHETIC tooth-like surface this "
         "project generates (not a scan): a cusp and the crown's side.", _tooth),
)

REBUILDS = (
    Rebuild("face-rebuild", "λ-H rebuild of the face", "A geodesic disk around the bridge "
            "of the nose of the face scan, represented by (λ, H) on a grid and rebuilt from "
            "them.",
            _face_disk),
    Rebuild("brain-rebuild", "λ-H rebuild of the brain", "A geodesic disk of the fsaverage5 "
            "left pial surface (lateral), represented by (λ, H) and rebuilt from them.",
            _brain_disk),
)


# --------------------------------------------------------------------------- running


@dataclass(frozen=True)
class RebuildError:
    """How far a λ-H rebuild is from the disk it was represented from, in % of the disk's
    diameter.

    Attributes
    ----------
    vertices : int
        The disk's vertices.
    grid : str
        The representation's grid, ``"rows×columns"``.
    diameter : float
        The disk's diameter (mesh units).
    mean, hausdorff : float
        The two-sided mean and the Hausdorff surface distance.
    vertex_rms, vertex_max : float
        How far the vertices moved: root mean square and largest.
    """

    vertices: int
    grid: str
    diameter: float
    mean: float
    hausdorff: float
    vertex_rms: float
    vertex_max: float


@dataclass
class CaseResult:
    """What one experiment measured (``rebuild``: a rebuild experiment's, else None)."""

    name: str
    title: str
    note: str
    comparisons: list[HoleComparison] = field(default_factory=list)
    rebuild: RebuildError | None = None
    pictures: list[str] = field(default_factory=list)
    seconds: float = 0.0
    error: str | None = None


class _CaseSteps:
    """The step hook ``step`` for the case ``name``: each message said after its name
    (``brain: hole 2: measured``), ``advance`` in place of each step's own where given, and
    the hole news of its fills too where ``step`` takes them (:func:`hole_news`: the bar's
    clock runs while they fill)."""

    def __init__(self, step, name: str, advance: int | None = None) -> None:
        self.step, self.name, self.advance = step, name, advance

    def __call__(self, message: str, advance: int = 1) -> None:
        self.step(f"{self.name}: {message}", advance if self.advance is None else self.advance)

    def holes(self, label: str):
        return hole_news(self.step, f"{self.name}: {label}")


def _run_case(case: Case, scale: str, out_dir: Path, step) -> CaseResult:
    started = time.perf_counter()
    result = CaseResult(case.name, case.title, case.note)
    v, f, centres, radii = case.make(scale)
    cut = cut_holes(v, f, centres, radii)
    loops = [h.loop for h in cut.holes]
    truth = [(h.truth_vertices, h.truth_faces) for h in cut.holes]
    # the fills' steps do not move the bar: a case's steps are its holes' panels
    comparisons, fills = compare_holes(cut.vertices, cut.faces, loops, truth=truth,
                                       step=_CaseSteps(step, case.name, advance=0))
    folder = out_dir / case.name
    panels_for(cut.vertices, cut.faces, comparisons, fills, folder, name=case.name,
               step=_CaseSteps(step, case.name))
    for c in comparisons:
        c.picture = f"{case.name}/{c.picture}"
    before_after(cut.vertices, cut.faces, fills.conformal, folder / "overview.png")
    result.pictures = [f"{case.name}/overview.png"]
    result.comparisons = comparisons
    result.seconds = time.perf_counter() - started
    return result


def rebuild_panel(rep, rebuilt: np.ndarray, path: Path, suptitle: str) -> Path:
    """Original and rebuilt disk from one camera, and λ, H over the parameter domain."""
    from matplotlib.figure import Figure

    v, f = rep.vertices, rep.faces
    loop = boundary_loops(f)[0]
    centre = v.mean(axis=0)
    radius = float(np.linalg.norm(v - centre, axis=1).max())
    direction = view_direction(v, f, [np.unique(f)])
    images = render_views(
        [MeshView(v, f, loops=[loop]), MeshView(rebuilt, f, loops=[loop])],
        centre=centre, direction=direction, distance=1.05 * radius / np.tan(np.radians(15)),
        size=(700, 520))
    fig = Figure(figsize=(PANEL_SIZE[0] / 100, PANEL_SIZE[1] / 100), dpi=100,
                 layout="constrained")
    grid = fig.add_gridspec(2, 4, height_ratios=[1.2, 1.0])
    for k, (image, name) in enumerate(zip(images, ("original", "rebuilt from (λ, H)"),
                                          strict=True)):
        ax = fig.add_subplot(grid[0, 2 * k:2 * k + 2])
        ax.imshow(image)
        ax.set_axis_off()
        ax.set_title(name, fontsize=11)
    for k, (values, name, cmap) in enumerate(((rep.lam, "conformal factor λ", "viridis"),
                                              (rep.H, "mean curvature H", "coolwarm"))):
        ax = fig.add_subplot(grid[1, 2 * k:2 * k + 2])
        finite = values[rep.domain & np.isfinite(values)]
        lo, hi = np.percentile(finite, [2, 98]) if len(finite) else (None, None)
        grid_image(ax, values, name, domain=rep.domain, cmap=cmap, vmin=lo, vmax=hi,
                   label="λ" if k == 0 else "H")
    fig.suptitle(suptitle, fontsize=12)
    return save_figure(fig, path)


def _run_rebuild(item: Rebuild, scale: str, out_dir: Path, step) -> CaseResult:
    started = time.perf_counter()
    result = CaseResult(item.name, item.title, item.note)
    v, f, centre, radius, resolution = item.make(scale)
    disk = cut_geodesic_disk(v, f, centre, radius)
    dv, df = disk.truth_vertices, disk.truth_faces
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a few folded triangles on ragged borders
        rep = represent(dv, df, discretization="grid", check=False,
                        resolution=resolution)
        rebuilt, _ = rebuild(rep)
    diameter = disk.diameter
    d = surface_distance(rebuilt, df, dv, df, n_samples=10000)
    moved = np.linalg.norm(rebuilt - dv, axis=1)
    result.rebuild = RebuildError(
        vertices=len(dv), grid=f"{rep.grid.shape[0]}×{rep.grid.shape[1]}",
        diameter=diameter, mean=100 * d.mean / diameter,
        hausdorff=100 * d.hausdorff / diameter,
        vertex_rms=100 * float(np.sqrt((moved**2).mean())) / diameter,
        vertex_max=100 * float(moved.max()) / diameter)
    picture = f"{item.name}.png"
    r = result.rebuild
    rebuild_panel(rep, rebuilt, out_dir / picture,
                  f"{item.title}: {how_many(r.vertices, 'vertex', 'vertices')}, grid "
                  f"{r.grid}; distance to the "
                  f"original {r.mean:.3g} % mean, {r.hausdorff:.3g} % Hausdorff "
                  "(of the disk diameter)")
    result.pictures = [picture]
    result.seconds = time.perf_counter() - started
    step(f"{item.name}: rebuilt", 1)
    return result


def _pair(error: TruthDistance) -> str:
    if not error.measured:
        return "failed"
    return f"{error.mean:.3g} / {error.hausdorff:.3g}"


def _summary(results: list[CaseResult]) -> tuple[list[str], list[list[str]]]:
    header = ["case", "hole", "edges", "fair mean / Hd %", WRITTEN_ERROR,
              "conformal raw mean / Hd %", "conformal kept", "s (fair, conformal)"]
    rows = []
    for r in results:
        if r.error:
            rows.append([r.name, "–", "–", "–", "–", "–", f"failed: {r.error}", "–"])
        for c in r.comparisons:
            e = c.errors
            rows.append([r.name, str(c.index), str(c.n_edges)]
                        + [_pair(e[m]) for m in ("fair", "conformal", "conformal raw")]
                        + ["yes" if c.kept else "no",
                           f"{c.seconds['fair']:.2f}, {c.seconds['conformal']:.2f}"])
    return header, rows


def _rebuild_table(results: list[CaseResult]) -> tuple[list[str], list[list[str]]]:
    header = ["case", "vertices", "grid", "mean %", "Hausdorff %", "vertex RMS %",
              "vertex max %"]
    rows = [[r.name, str(r.rebuild.vertices), r.rebuild.grid]
            + [f"{x:.3g}" for x in (r.rebuild.mean, r.rebuild.hausdorff, r.rebuild.vertex_rms,
                                    r.rebuild.vertex_max)]
            if r.rebuild is not None else [r.name, "–", "–", f"failed: {r.error}", "–", "–", "–"]
            for r in results]
    return header, rows


def run_set(out_dir: str | Path, scale: str = "full", *, cases: list[str] | None = None,
            step=None) -> list[CaseResult]:
    """Run the experiment set and write its pictures and page into ``out_dir``.

    Parameters
    ----------
    out_dir : path
    scale : {"full", "quick"}
        "quick": coarser meshes and smaller holes (for tests, well under a minute).
    cases : list of str, optional
        Names to run (of :data:`CASES` and :data:`REBUILDS`); all by default.
    step : callable(message, advance=1), optional
        Progress hook: advanced once per hole and once per rebuild.

    Returns
    -------
    list of CaseResult, hole cases first.

    Warns
    -----
    The warnings of each experiment (its fills': :func:`~surfinpaint.app.report.compare_holes`),
    each starting with the experiment's name (``"brain: hole 2: ..."``).

    Raises
    ------
    ValueError
        For an unknown scale or case name.
    """
    if scale not in SCALES:
        raise ValueError(f"scale must be one of {SCALES}, got {scale!r}")
    known = [c.name for c in CASES] + [r.name for r in REBUILDS]
    cases = known if cases is None else list(cases)
    unknown = sorted(set(cases) - set(known))
    if unknown:
        raise ValueError(f"{agreeing(len(unknown), 'unknown experiment', 'unknown experiments')} "
                         f"{unknown}; choose from {known}")
    step = step or (lambda message, advance=1: None)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    started = time.perf_counter()
    results = []
    for item, run in [(c, _run_case) for c in CASES] + [(r, _run_rebuild) for r in REBUILDS]:
        if item.name not in cases:
            continue
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                results.append(run(item, scale, out_dir, step))
            except (ValueError, RuntimeError, OSError, MeshError, np.linalg.LinAlgError) as exc:
                # one failed experiment is reported on the page; the others still run
                results.append(CaseResult(item.name, item.title, item.note,
                                          error=f"{type(exc).__name__}: {exc}"))
                step(f"{item.name}: failed", 0)
        # the experiments have no input file: each warning names its case, as a command's
        # warnings name their input ("brain: hole 2: ...")
        for w in caught:
            warnings.warn(named(str(w.message), item.name), w.category, stacklevel=2)
    holes = [r for r in results if r.name in {c.name for c in CASES}]
    sections = []
    if holes:
        sections.append(PageSection(
            "Summary: distance to the truth", table=_summary(holes),
            text="Two-sided mean / Hausdorff distance between each fill and the removed "
            "patch, in % of the hole diameter."))
    rebuilds = [r for r in results if r.name in {c.name for c in REBUILDS}]
    if rebuilds:
        sections.append(PageSection(
            "Summary: λ-H rebuilds", table=_rebuild_table(rebuilds),
            text="Distance between the rebuilt and the original disk (mean, Hausdorff; "
            "vertex displacement RMS and maximum), in % of the disk diameter."))
    for r in results:
        note = f"FAILED: {r.error}" if r.error else f"{r.note} ({r.seconds:.1f} s)"
        sections.append(PageSection(r.title, text=note, comparisons=r.comparisons,
                                    pictures=r.pictures))
    write_page(out_dir, sections, f"surfinpaint experiments ({scale})",
               f"Scale {scale!r}, {time.perf_counter() - started:.0f} s in all. " + LEGEND)
    return results


# --------------------------------------------------------------------------- command line


def add_experiments_parser(subparsers) -> argparse.ArgumentParser:
    """Add ``surfinpaint experiments`` to an argparse subparsers object."""
    names = [c.name for c in CASES] + [r.name for r in REBUILDS]
    p = subparsers.add_parser(
        "experiments", help="regenerate the paper's experiment set with error tables",
        description="Cut holes with known ground truth out of a cube, a snowman, a face "
        "scan, a brain surface and a synthetic tooth, fill them with both methods, rebuild "
        "a face and a brain disk from (λ, H), and write panels and a page (index.md, "
        "index.html) with each method's distance to the truth.")
    p.add_argument("-o", "--output", required=True, help="output folder")
    p.add_argument("--quick", action="store_true",
                   help="coarser meshes and smaller holes (well under a minute)")
    p.add_argument("--cases", help=f"comma-separated subset of: {', '.join(names)}")
    add_quiet(p)
    p.set_defaults(func=run_experiments)
    return p


def _expected_steps(cases: list[str]) -> int:
    holes = {"cube": 1, "snowman": 2, "face": 3, "brain": 4, "tooth": 2}
    return sum(holes.get(name, 1) for name in cases)


def run_experiments(args: argparse.Namespace) -> int:
    """``surfinpaint experiments``: returns the exit code (0 on success)."""
    from rich.console import Console
    from rich.table import Table

    cases = ([c.strip() for c in args.cases.split(",") if c.strip()] if args.cases
             else [c.name for c in CASES] + [r.name for r in REBUILDS])
    scale = "quick" if args.quick else "full"
    says = QuietConsole(args.quiet)
    with progress_bar(says.progress, _expected_steps(cases), "experiments",
                      ticking=True) as step:
        results = run_set(args.output, scale, cases=cases, step=step)
    hole_names = {c.name for c in CASES}
    for title, (header, rows) in (
            ("hole fills", _summary([r for r in results if r.name in hole_names])),
            ("λ-H rebuilds", _rebuild_table([r for r in results if r.name not in hole_names]))):
        if not rows:
            continue
        table = Table(title=f"{title}: % of the diameter")
        for name in header:
            table.add_column(name)
        for row in rows:
            table.add_row(*row)
        Console().print(table)
    says.say(f"wrote {Path(args.output) / 'index.html'}")
    failed = [r.name for r in results if r.error]
    if failed:
        says.error(f"[red]failed:[/red] {', '.join(failed)} (see the page)")
        return 1
    return 0
