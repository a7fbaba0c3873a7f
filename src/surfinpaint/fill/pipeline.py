"""Hole filling, top to bottom: choose the holes; for each, cut a local neighbourhood around
it, check its loop, fill it with the requested method (the conformal method writes a faired
fill where its λ-H fill fails or loses its self-check), stitch the fill back after the
original vertices and faces, and report what happened.

Original vertices are never moved or reordered; original faces are kept in their order and
the new faces follow them.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from threadpoolctl import threadpool_limits

from surfinpaint.errors import HoleWarning, MeshError, preview
from surfinpaint.fill import parallel
from surfinpaint.fill.attributes import check_attributes, fill_result_attributes
from surfinpaint.fill.conformal import ConformalOptions
from surfinpaint.fill.conformal.options import check_fair_order
from surfinpaint.fill.face_attributes import fill_result_face_attributes
from surfinpaint.fill.holes import find_holes, hole_numbers, loop_diameter, select_holes
from surfinpaint.fill.neighbourhood import gather_positions, neighbourhood_faces
from surfinpaint.fill.objects import mesh_arrays
from surfinpaint.fill.results import Fill, FillResult, HoleReport
from surfinpaint.fill.seams import Slit, SlitWarning, find_seam_part, find_slit, zip_faces
from surfinpaint.fill.topology import topology_changes
from surfinpaint.fill.warmup import KernelWarmup
from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.geometry.mesh import vertex_faces
from surfinpaint.geometry.repair import remove_nonmanifold_faces, unjoined_bowties
from surfinpaint.geometry.validation import (
    check_arrays,
    check_loop,
    check_topology,
    face_ids,
    zero_area_faces,
)
from surfinpaint.io.base import MeshWarning

__all__ = ["FillResult", "HoleReport", "fill_holes", "METHODS"]

METHODS = ("conformal", "fair")
# vertex rings of the surface handed to the faired fill (its fairing needs up to 2)
FAIR_NEIGHBOURHOOD_RINGS = 3

ProgressCallback = Callable[[int, int, str], None]


@dataclass
class _Local:
    """The neighbourhood of one hole, cut out of the mesh filled so far."""

    loop: np.ndarray  # the hole's loop, global ids
    ids: np.ndarray  # global ids of the local vertices (sorted)
    faces_global: np.ndarray
    vertices: np.ndarray
    faces: np.ndarray  # over local ids
    local_loop: np.ndarray


class _FilledMesh:
    """The mesh as its holes are filled: the original arrays, unchanged, and the blocks of
    new vertices and faces appended hole by hole."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        self.vertices, self.faces = vertices, faces
        self.vertex_faces = vertex_faces(faces, len(vertices))
        self.vertex_blocks: list[np.ndarray] = []
        self.face_blocks: list[np.ndarray] = []
        self.n_new = 0

    def cut(self, loop: np.ndarray, rings: int) -> _Local:
        """The faces within ``rings`` vertex rings of ``loop``, the earlier fills included
        (the cost stays with the hole)."""
        added = (np.concatenate(self.face_blocks) if self.face_blocks
                 else np.empty((0, 3), dtype=np.int64))
        picked, picked_added = neighbourhood_faces(self.faces, self.vertex_faces, added, loop,
                                                   rings)
        faces_global = np.concatenate([self.faces[picked], added[picked_added]])
        ids, local_faces = np.unique(faces_global, return_inverse=True)
        return _Local(loop=loop, ids=ids, faces_global=faces_global,
                      vertices=gather_positions(self.vertices, self.vertex_blocks, ids),
                      faces=local_faces.reshape(-1, 3), local_loop=np.searchsorted(ids, loop))

    def stitch(self, local: _Local, fill: Fill) -> str | None:
        """Append ``fill`` (over ``local``'s ids); the reason when it cannot be."""
        new_v = np.asarray(fill.vertices, dtype=np.float64).reshape(-1, 3)
        new_f = np.asarray(fill.faces, dtype=np.int64)
        degenerate = len(zero_area_faces(np.concatenate([local.vertices, new_v]), new_f))
        if degenerate:
            return (f"the fill would add {degenerate} zero-area triangles (the loop spans no "
                    "area: a slit or a T-junction)")
        n_local = len(local.vertices)
        mapped = np.where(new_f < n_local, local.ids[np.minimum(new_f, n_local - 1)],
                          len(self.vertices) + self.n_new + (new_f - n_local))
        self.vertex_blocks.append(new_v)
        self.face_blocks.append(mapped)
        self.n_new += len(new_v)
        return None

    def result(self, reports: list[HoleReport], removed_faces: np.ndarray) -> FillResult:
        vertices = np.concatenate([self.vertices, *self.vertex_blocks])
        faces = np.concatenate([self.faces, *self.face_blocks])
        return FillResult(vertices, faces, reports, len(self.vertices), len(self.faces),
                          removed_faces)


def _skip(report: HoleReport, reason: str, category: type[Warning] = HoleWarning,
          stacklevel: int = 5) -> None:
    report.skipped = reason
    report.method = "none"
    warnings.warn(f"hole {report.index}: {reason}; skipped", category, stacklevel=stacklevel)


def _open_seams(vertices: np.ndarray, faces: np.ndarray, todo: list[HoleReport],
                zip_seams: bool) -> tuple[np.ndarray, np.ndarray, list[HoleReport]]:
    """The holes of ``todo`` whose loop spans no area (:func:`find_slit`) or runs back along
    itself over a seam (:func:`find_seam_part`) taken out of it, before anything is filled:
    seams zipped with ``zip_seams`` (the faces returned use each kept vertex in place of its
    duplicate), the others skipped with a SlitWarning.

    Returns the faces, the merged ``(duplicate, kept)`` pairs and the holes left to fill
    (their loops in the zipped faces' ids).
    """
    left, merged = [], []
    for report in todo:
        slit = find_slit(vertices, report.loop)
        part = find_seam_part(vertices, report.loop) if slit is None else None
        if slit is None and part is None:
            left.append(report)
            continue
        if slit is None:  # a seam along part of a loop that bounds no disk (an open tube's)
            slit = Slit(part)
            reason = (f"the loop runs back along itself: a seam of {len(part)} coincident "
                      "vertex pairs joins two parts of it (duplicated vertices), so no disk "
                      "fills it")
            rest = "; the rest of the loop is left open"
        else:
            reason, rest = slit.describe(), ""
        if slit.is_seam and zip_seams:
            zipped, problem = zip_faces(faces, slit.merges)
            if problem is None:
                faces = zipped
                report.method, report.zipped = "zipped", slit.merges
                report.note = (f"seam zipped: {len(slit.merges)} duplicate vertices merged "
                               f"into their coincident partners{rest}")
                merged.append(slit.merges)
                warnings.warn(f"hole {report.index}: a seam of {len(slit.merges)} coincident "
                              "vertex pairs zipped: the faces use vertices "
                              f"{preview(slit.merges[:, 1])} in place of their duplicates "
                              f"{preview(slit.merges[:, 0])} (left unused){rest}",
                              MeshWarning, stacklevel=4)
                continue
            reason += f"; not zipped: {problem}"
        elif slit.is_seam:
            reason += "; left open (zip_seams=True, or --zip-seams, closes it)"
        _skip(report, reason, SlitWarning, stacklevel=5)
    pairs = np.concatenate(merged) if merged else np.empty((0, 2), dtype=np.int64)
    if len(pairs):  # a later loop through a duplicate (a bow-tie there) goes through its partner
        mapping = np.arange(len(vertices))
        mapping[pairs[:, 0]] = pairs[:, 1]
        for report in left:
            report.loop = mapping[report.loop]
    return faces, pairs, left


def _problem(local: _Local, index: int, explicit: bool) -> str | None:
    """Why the hole cannot be filled (None: it can); a hole the caller named is an error.

    The loop is checked on the faces at its vertices only: whether its edges are boundary
    edges and its vertices bow-ties is decided there (the same answer and message as on the
    whole neighbourhood, at the cost of the loop's faces, not of the many rings around)."""
    on_loop = np.isin(local.faces_global, local.loop)
    touching = local.faces_global[on_loop.any(axis=1)]
    try:
        check_loop(touching, local.loop)
    except MeshError as exc:
        # a loop pinched at a bow-tie (split into pieces): filling each piece joins the
        # fans there, so the result is manifold once all pieces are filled
        if "bow-tie" not in exc.message or unjoined_bowties(touching, local.loop).size:
            if explicit:
                raise MeshError(f"hole {index}: {exc.message}", vertices=exc.vertices,
                                edges=exc.edges) from None
            return exc.message
    if on_loop[on_loop.any(axis=1)].all():
        # a lone triangle or a strip one face wide: the loop bounds nothing but the faces
        # along it, and a fill would lay a second sheet on them (duplicate faces)
        return "the loop bounds only the faces along it (a lone sheet)"
    return None


def _record(report: HoleReport, fill: Fill) -> None:
    """What the method did with the hole, in its report (a fallback also as a warning)."""
    report.method = fill.kind
    report.note = fill.notes
    report.fair_order = fill.fair_order
    report.verdict, report.crease, report.diagnostics = (fill.verdict, fill.crease,
                                                          fill.diagnostics)
    report.crease_failure = fill.crease_failure
    report.crossings = fill.crossings
    if fill.crossings:
        many = fill.crossings > 1
        warnings.warn(f"hole {report.index}: {fill.crossings} triangle{'s' * many} of the "
                      f"fill cross{'es' * (not many)} the surface around the hole (its "
                      "boundary loop folds over itself there): check the result",
                      HoleWarning, stacklevel=5)
    if fill.failure:
        report.fallback = fill.failure
        warnings.warn(f"hole {report.index}: conformal fill failed ({fill.failure}); used "
                      f"the faired fill (order {fill.fair_order}) instead", HoleWarning,
                      stacklevel=5)


def _checked(method, options, fair_order, max_hole_edges, neighbourhood_rings
             ) -> ConformalOptions:
    """The conformal options to use; bad arguments are the caller's error."""
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}: choose one of {', '.join(METHODS)}")
    check_fair_order(fair_order)
    if options is not None and not isinstance(options, ConformalOptions):
        raise ValueError(f"options must be a ConformalOptions, got {type(options).__name__}")
    if options is not None and method != "conformal":
        raise ValueError(f"options apply to method='conformal', not {method!r}")
    for name, value in (("max_hole_edges", max_hole_edges),
                        ("neighbourhood_rings", neighbourhood_rings)):
        if value is not None and (isinstance(value, bool)
                                  or not isinstance(value, int | np.integer) or value < 1):
            raise ValueError(f"{name} must be a positive integer, got {value!r}")
    return ConformalOptions() if options is None else options


def fill_holes(
    vertices,
    faces: np.ndarray | None = None,
    holes: Sequence | None = None,
    method: str = "conformal",
    *,
    options: ConformalOptions | None = None,
    fair_order: int | None = None,
    attributes: dict[str, np.ndarray] | None = None,
    face_attributes: dict[str, np.ndarray] | None = None,
    attribute_kinds: dict[str, str] | None = None,
    include_border: bool = False,
    max_hole_edges: int | None = None,
    neighbourhood_rings: int | None = None,
    repair: bool = False,
    validate: bool = True,
    zip_seams: bool = False,
    progress: ProgressCallback | None = None,
    jobs: int | None = None,
) -> FillResult:
    """Fill holes of a triangle mesh.

    Parameters
    ----------
    vertices : (n, 3) float array, ``trimesh.Trimesh`` or ``pyvista.PolyData``
        A mesh object brings its own attributes (a Trimesh's vertex colours and
        ``vertex_attributes``, a PolyData's ``point_data``; see
        :mod:`surfinpaint.fill.objects`); ``faces`` is then left out.
    faces : (f, 3) int array
        Vertex ids (a float array is taken when every id is a whole number).
    holes : None, list of int, or list of loops
        None fills every boundary loop except the outer border of an open surface
        (``include_border=True`` fills those too). Integers index :func:`find_holes`' list;
        sequences of vertex ids give boundary loops directly (any orientation, any start).
    method : {"conformal", "fair"}
        "conformal": λ-H inpainting (Lui, Wen, Gu) checked against fairing, writing a
        faired fill per hole where it fails or loses (:func:`surfinpaint.fill.conformal.
        conformal_fill`). "fair": the conventional fill (Liepa 2003: triangulate, refine,
        fair).
    options : ConformalOptions, optional
        The conformal method's options (its defaults when None); an error with "fair".
    fair_order : int, optional
        Fairing order (1 harmonic, 2 biharmonic, 3 triharmonic). "fair" uses 2 unless told
        (Liepa's and CGAL's default: the baseline). The conformal method, unless told,
        starts from the trilaplacian fill and chooses its fallback per hole between 2 and 3
        by its truth-free self-check.
    include_border : bool
        Also fill the loops that look like the outer border of an open surface.
    max_hole_edges : int, optional
        Holes with more boundary edges are skipped (reported, not filled).
    neighbourhood_rings : int, optional
        Vertex rings of the surrounding surface cut out and handed to the filler; None: what
        the method looks at (for the conformal method, its patch and its test holes).
    repair : bool
        Remove the faces around non-manifold edges first (see
        :func:`surfinpaint.geometry.repair.remove_nonmanifold_faces`); the holes this opens
        are then filled with the others. The removed faces are listed in
        ``FillResult.removed_faces``.
    validate : bool
        Check the mesh first (:func:`surfinpaint.validate_mesh`).
    zip_seams : bool
        A loop that spans no area (a slit, or a seam of duplicated coincident vertices as
        exporters write along a UV seam) is never filled: no fill of it is a surface. By
        default it is left open with a :class:`~surfinpaint.MeshWarning`; with
        ``zip_seams=True`` a seam is zipped instead: the faces use each duplicate's
        coincident partner (the smaller id) in its place, so the surface comes out closed
        along the seam. The vertices stay as they are (the duplicates unused); the pairs
        are in ``FillResult.merged_vertices``. See :mod:`surfinpaint.fill.seams`.
    progress : callable(done, total, message), optional
        Called before and after each hole (in hole order).
    jobs : int, optional
        Worker processes filling holes at once (None: all the cores this process may use;
        1: one hole after another in this process). The result is bit-identical to the
        serial run: holes whose neighbourhoods reach an earlier hole's loop are filled
        after it (:mod:`surfinpaint.fill.parallel`); a few small holes are always filled
        in this process.
    attributes, face_attributes : dict of name to array, optional
        Per-vertex (per-face) data; the new vertices' values are inpainted and the new faces'
        copied from across the loop (rules: :mod:`surfinpaint.fill.attributes`), the
        originals' kept as they are, in ``FillResult.attributes`` (``.face_attributes``).
    attribute_kinds : dict of name to {"values", "normal", "label"}, optional
        Overrides :func:`surfinpaint.fill.attributes.attribute_kind`.

    Returns
    -------
    FillResult
        ``.vertices`` (the originals, unchanged and in order, then the new ones), ``.faces``
        (the originals, then the new ones) and ``.reports`` (one :class:`HoleReport` a hole).

    Raises
    ------
    MeshError
        Invalid mesh or hole selection (the message names the offending ids; a problem
        found at one hole, by the hole's :func:`find_holes` number), including face ids
        that are not whole numbers (whole-number floats are taken:
        :func:`surfinpaint.geometry.validation.face_ids`).
    ValueError
        An unknown method or a bad argument value (``MeshError`` is a ``ValueError`` too).
    TypeError
        An unknown option name, or a mesh of a kind not taken
        (:func:`surfinpaint.fill.objects.mesh_arrays`).
    RuntimeError
        A worker process died (``concurrent.futures.process.BrokenProcessPool``, e.g.
        killed for memory) while ``jobs`` > 1 filled holes.

    A hole that cannot be filled never stops the others, and is never an exception: its
    fill's failure (``FillError`` or a singular system, the faired fallback's included) is
    reported (``HoleReport.failed``, the reason in ``.skipped``) and warned, and the hole is
    left open; so is a loop
    that spans no area (see ``zip_seams``).
    """
    vertices, faces, attributes, face_attributes = mesh_arrays(vertices, faces, attributes,
                                                               face_attributes)
    # bad arguments are the caller's error, found before any hole is filled
    attributes, attribute_kinds = _checked_attributes(len(vertices), len(faces), attributes,
                                                      face_attributes, attribute_kinds)
    options = _checked(method, options, fair_order, max_hole_edges, neighbourhood_rings)
    for name, flag in (("include_border", include_border), ("repair", repair),
                       ("validate", validate), ("zip_seams", zip_seams)):
        if not isinstance(flag, bool | np.bool_):
            raise ValueError(f"{name} must be True or False, got {flag!r}")
    jobs = parallel.resolve_jobs(jobs)
    # the kernels load on the idle core while the whole-mesh passes run (fill/warmup.py)
    warmup = KernelWarmup.for_mesh(len(faces), method)
    try:
        vertices, faces, removed_faces, table = _prepared(vertices, faces, repair, validate)
        # checked by _prepared, as validate says
        found = find_holes(vertices, faces, table, validate=False)
        loops = select_holes(vertices, faces, holes, include_border=include_border,
                             table=table, validate=False, found=found)
        del table  # the holes are found: its memory is free for the fills
        # numbered as find_holes numbers them (the outer border counts), whatever was selected
        numbers = hole_numbers(vertices, faces, loops, found=found)
    finally:  # before any hole is filled or worker forked
        warmup.join()
    reports = [HoleReport(index=k, loop=np.asarray(loop), n_edges=len(loop), requested=method,
                          method=method, diameter=loop_diameter(vertices[loop]))
               for k, loop in zip(numbers, loops, strict=True)]
    todo = []
    for report in reports:
        if max_hole_edges is not None and report.n_edges > max_hole_edges:
            report.skipped = f"{report.n_edges} boundary edges > max_hole_edges={max_hole_edges}"
            report.method = "none"
        else:
            todo.append(report)
    # before anything is filled: a zipped seam changes the faces the other holes are cut from
    faces, merged, todo = _open_seams(vertices, faces, todo, zip_seams)
    mesh = _FilledMesh(vertices, faces)
    run = _Run(method, options, fair_order, explicit=holes is not None, n_holes=len(loops),
               progress=progress, rings=neighbourhood_rings,
               position={id(r): k for k, r in enumerate(reports)})
    workers = min(jobs, len(todo))
    if parallel.worth_parallel([r.n_edges for r in todo], workers, method):
        _fill_in_parallel(mesh, todo, run, workers)
    else:
        for report in todo:
            run.starting(report)
            _fill_hole(mesh, report, run.rings_of(report), explicit=run.explicit,
                       fill=run.fill)
            run.finished(report)
    result = mesh.result(reports, removed_faces)
    result.merged_vertices = merged
    result = _with_attributes(result, attributes, face_attributes, attribute_kinds)
    result.topology = topology_changes(result)
    for change in result.topology:
        warnings.warn(change.message, stacklevel=2)
    return result


@dataclass(frozen=True)
class _Run:
    """How the holes of one call are filled, and whom to tell."""

    method: str
    options: ConformalOptions
    fair_order: int | None
    explicit: bool
    n_holes: int
    progress: ProgressCallback | None
    rings: int | None
    # a report's place among the selected holes, for the progress count
    position: dict[int, int] = field(default_factory=dict)

    def rings_of(self, report: HoleReport) -> int:
        """The vertex rings cut out around the hole: what its method looks at."""
        return self.rings or (self.options.neighbourhood_rings(report.n_edges)
                              if self.method == "conformal" else FAIR_NEIGHBOURHOOD_RINGS)

    def fill(self, local: _Local) -> tuple[Fill | None, str | None]:
        return parallel.fill_or_failure(local.vertices, local.faces, local.local_loop,
                                        self.method, self.options, self.fair_order)

    def starting(self, report: HoleReport) -> None:
        if self.progress:
            self.progress(self.position.get(id(report), 0), self.n_holes,
                          f"hole {report.index}: {report.n_edges} edges, {self.method}")

    def finished(self, report: HoleReport) -> None:
        if self.progress and not report.skipped:
            self.progress(self.position.get(id(report), 0) + 1, self.n_holes,
                          f"hole {report.index}: done in {report.seconds:.2f} s")


def _fill_hole(mesh: _FilledMesh, report: HoleReport, rings: int, *,
               explicit: bool, fill: Callable[[_Local], tuple[Fill | None, str | None]]
               ) -> None:
    """One hole: cut its neighbourhood, check its loop, fill it, stitch the fill in, and
    say what happened in ``report`` (skipped, with a warning, when it cannot be filled)."""
    started = time.perf_counter()
    local = mesh.cut(report.loop, rings)
    problem = _problem(local, report.index, explicit)
    made, failure = (None, None) if problem else _at_hole(report.index, fill, local)
    _stitched(mesh, report, local, made, problem, started, failure)


def _at_hole(index: int, call: Callable, *args):
    """``call(*args)`` for hole ``index``: a MeshError raised names the hole."""
    try:
        return call(*args)
    except MeshError as exc:
        raise MeshError(f"hole {index}: {exc.message}", path=exc.path, vertices=exc.vertices,
                        edges=exc.edges, faces=exc.faces) from exc


def _stitched(mesh: _FilledMesh, report: HoleReport, local: _Local, made: Fill | None,
              problem: str | None, started: float, failure: str | None = None) -> None:
    """Stitch ``made`` (None: ``problem`` says why there is no fill, or ``failure`` why the
    fill raised) in, and report it."""
    if failure is not None:  # the fill raised: the hole is left open, the others go on
        report.failed = True
        problem = f"the fill failed: {failure}"
    if made is not None:
        _record(report, made)
        problem = mesh.stitch(local, made)
        report.failed = problem is not None  # a fill was made: it is its failure
    if problem is not None:
        _skip(report, problem)
        return
    report.new_vertices, report.new_faces = len(made.vertices), len(made.faces)
    report.seconds = time.perf_counter() - started


def _fill_in_parallel(mesh: _FilledMesh, todo: list[HoleReport], run: _Run,
                      workers: int) -> None:
    """The holes of ``todo``, the independent ones in ``workers`` processes, stitched in hole
    order; the dependent ones filled here when their turn comes (see
    :mod:`surfinpaint.fill.parallel`)."""
    first_loop = parallel.first_loops({r.index: r.loop for r in todo}, len(mesh.vertices))
    cuts: dict[int, _Local] = {}
    problems: dict[int, str | MeshError | None] = {}
    futures = {}
    executor = parallel.pool(workers)
    # one BLAS thread here too: a dependent hole filled here shares the cores with workers
    blas = threadpool_limits(limits=1)
    try:
        for report in todo:  # nothing is stitched yet: these are cuts of the original mesh
            k = report.index
            cut = mesh.cut(report.loop, run.rings_of(report))
            if not parallel.reaches_no_earlier_loop(k, cut.ids, first_loop):
                continue
            cuts[k] = cut
            try:
                problems[k] = _problem(cut, k, run.explicit)
            except MeshError as exc:  # raised when its turn comes, as the serial loop would
                problems[k] = exc
            if problems[k] is None:  # sent at once: the workers start while we cut on
                futures[k] = executor.submit(parallel.fill_in_worker, cut.vertices, cut.faces,
                                             cut.local_loop, run.method, run.options,
                                             run.fair_order)
        for report in todo:
            k = report.index
            run.starting(report)
            if k not in cuts:  # its neighbourhood takes in earlier fills: cut it now
                _fill_hole(mesh, report, run.rings_of(report), explicit=run.explicit,
                           fill=run.fill)
            elif k in futures:
                made, failure, records, seconds = _at_hole(k, futures.pop(k).result)
                parallel.reissue(records)
                _stitched(mesh, report, cuts[k], made, None, time.perf_counter() - seconds,
                          failure)
            elif isinstance(problems[k], MeshError):
                raise problems[k]
            else:
                _stitched(mesh, report, cuts[k], None, problems[k], time.perf_counter())
            cuts.pop(k, None)
            run.finished(report)
    finally:
        executor.shutdown(wait=True, cancel_futures=True)
        blas.restore_original_limits()


def _checked_attributes(n_vertices, n_faces, attributes, face_attributes, kinds):
    """The vertex attributes and their kinds, checked (:func:`check_attributes`), and the
    face attributes' row counts."""
    attributes, kinds = check_attributes(n_vertices, attributes, kinds)
    for name, a in face_attributes.items():
        if np.ndim(a) == 0 or len(a) != n_faces:
            raise ValueError(f"face attribute {name!r} has {len(a) if np.ndim(a) else 0} "
                             f"rows, the mesh has {n_faces} faces")
    return attributes, kinds


def _prepared(vertices, faces, repair: bool, validate: bool):
    """The mesh as arrays, with ``repair`` the faces around non-manifold edges removed
    (and which), with ``validate`` checked; and its edge table when validated (built once:
    the holes are found from it too)."""
    faces = face_ids(faces)  # whole-number floats taken, never truncated
    if validate:  # shapes, dtypes and ids first: the repair and the edge table index by them
        check_arrays(vertices, faces)
    vertices = np.asarray(vertices, dtype=np.float64)
    removed_faces = np.empty(0, dtype=np.int64)
    if repair:
        faces, removed_faces = remove_nonmanifold_faces(vertices, faces)
    table = None
    if validate:
        table = EdgeTable.build(faces, len(vertices))
        check_topology(vertices, faces, table)  # validate_mesh's errors, not its report
    return vertices, faces, removed_faces, table


def _with_attributes(result: FillResult, attributes, face_attributes, kinds) -> FillResult:
    """The attributes of the filled mesh, new rows by the rules of fill/attributes.py."""
    if attributes:
        result.attributes = fill_result_attributes(result, attributes, kinds=kinds)
    if face_attributes:
        result.face_attributes = fill_result_face_attributes(result, face_attributes)
    return result
