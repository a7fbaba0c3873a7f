"""Hole filling, top to bottom: choose the holes; for each, cut a local neighbourhood around
it, check its loop, fill it with the requested method (the conformal method writes a faired
fill where its λ-H fill fails or loses its self-check), stitch the fill back after the
original vertices and faces, and report what happened.

Original vertices are never moved or reordered; original faces are kept in their order and
the new faces follow them.
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Callable, Sequence

import numpy as np

from surfinpaint.errors import HoleWarning, MeshError, agreeing, how_many
from surfinpaint.fill import parallel
from surfinpaint.fill.attributes import ATTRIBUTE_KINDS, check_attributes, fill_result_attributes
from surfinpaint.fill.conformal import ConformalOptions
from surfinpaint.fill.conformal.options import check_fair_order
from surfinpaint.fill.face_attributes import fill_result_face_attributes
from surfinpaint.fill.far_crossings import crossing_fill_pairs, far_crossing_triangles
from surfinpaint.fill.hole_steps import Run, fill_hole, open_seams
from surfinpaint.fill.holes import (
    BORDER_SPAN_FRACTION,
    Hole,
    find_holes,
    hole_numbers,
    loop_diameter,
    over_size,
    percent_below,
    select_holes,
)
from surfinpaint.fill.island_steps import fill_with_islands, joined_islands
from surfinpaint.fill.islands import Island, check_islands_mode, find_islands
from surfinpaint.fill.neighbourhood import FilledMesh
from surfinpaint.fill.objects import display_of, mesh_arrays
from surfinpaint.fill.results import FillResult, HoleReport
from surfinpaint.fill.scheduler import fill_in_parallel
from surfinpaint.fill.topology import topology_changes
from surfinpaint.fill.unjoined import unjoined_borders_note
from surfinpaint.fill.warmup import Beside, load_for_workers, loading_beside
from surfinpaint.geometry.degenerate import triangle_incidence, triangle_rows
from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.geometry.repair import repair_faces
from surfinpaint.geometry.validation import (
    check_arrays,
    check_topology,
    degenerate_notes,
    face_ids,
    zero_area_faces,
)
from surfinpaint.io.base import MeshWarning

__all__ = ["FillResult", "HoleReport", "fill_holes", "METHODS"]

METHODS = ("conformal", "fair")
ProgressCallback = Callable[[int, int, str], None]


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
    if method == "fair":  # the conventional baseline: never the smoothing fill, whatever
        # the conformal method's default (its faired fallbacks take the conformal options')
        return dataclasses.replace(ConformalOptions(), fair_smoothing=None)
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
    keep_margins: bool = False,
    max_hole_edges: int | None = None,
    neighbourhood_rings: int | None = None,
    repair: bool = False,
    validate: bool = True,
    zip_seams: bool = False,
    islands: str = "bridge",
    progress: ProgressCallback | None = None,
    jobs: int | None = None,
) -> FillResult:
    """Fill holes of a triangle mesh.

    Parameters
    ----------
    vertices : (n, 3) float array, ``trimesh.Trimesh`` or ``pyvista.PolyData``
        A mesh object brings its own attributes (a Trimesh's vertex colours and
        ``vertex_attributes``, a PolyData's ``point_data``; see
        :mod:`surfinpaint.fill.objects`); ``faces`` is then left out. Filled and
        returned as float64 (a float32 PolyData's too; its originals are equal), with a
        :class:`~surfinpaint.MeshWarning` if that rounds any (longdouble, int64 past 2**53).
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
    keep_margins : bool
        With ``holes=None``, also leave open the loops that may be a margin of the surface
        (:attr:`~surfinpaint.fill.holes.Hole.may_be_border`): a piece's largest loop that
        spans 10–40 % of its area (a tooth crown scanned down to the gum), or a loop inside
        a piece's outer border that spans at least 20 % of it (the inner edge of a scanned
        ring or bore). Filled by default, with a warning. For a batch of such scans, where
        ``holes`` differs from file to file.
    max_hole_edges : int, optional
        Holes with more boundary edges are skipped (reported, not filled).
    neighbourhood_rings : int, optional
        Vertex rings of the surrounding surface cut out and handed to the filler; None: what
        the method looks at (for the conformal method, its patch and its test holes).
    repair : bool
        Remove the faces around non-manifold edges first (see
        :func:`surfinpaint.geometry.repair.remove_nonmanifold_faces`); the holes this opens
        are then filled with the others. The removed faces are listed in
        ``FillResult.removed_faces``. Then the faces of each piece are oriented
        consistently, the fewest flipped (their last two vertex ids swapped:
        :func:`surfinpaint.geometry.orientation.orient_faces`), with a
        :class:`~surfinpaint.MeshWarning` naming them, and each closed piece wound inward
        (negative signed volume) is turned outward, all its faces flipped, with a warning
        too (:func:`surfinpaint.geometry.orientation.turn_outward`); the faces flipped in
        the end are listed (ids into the input faces) in ``FillResult.flipped_faces``. A
        piece that cannot be oriented (a Möbius strip) is left as it is, and refused as
        without ``repair``.
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
    islands : {"bridge", "ignore"}
        A small piece of surface with one loop that lies inside a hole (a scan's floating
        fragment: an *island*, :func:`surfinpaint.fill.islands.find_islands`). "bridge"
        (default): the hole is filled with it, a faired fill of the region between the
        hole's loop and the island's (:mod:`surfinpaint.fill.annulus`; the λ-H method
        needs a disk), reported ``faired`` with the note "with its island, piece N (loop
        m)". "ignore": the hole is filled as a disk through or by the island, which is
        left as it is, with a warning (as is an island that cannot be joined, e.g. wound
        opposite to the surface around the hole). The island is never deleted.
    progress : callable(done, total, message), optional
        Called before and after each hole (in hole order), and as each stage of a conformal
        fill starts (``hole 3: 212 edges, λ-H fill (stage 5 of 5)``; on forked workers as
        the stages' news comes, the last said again each second), always in this thread.
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
    attribute_kinds : dict of name to {"values", "normal", "label", "id"}, optional
        Overrides :func:`surfinpaint.fill.attributes.attribute_kind` (of a face attribute
        too: ``"id"`` gives the new faces the none id, any other kind copies).

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
    left open; so is a loop that spans no area (see ``zip_seams``).
    """
    display = display_of(vertices)  # an object's material, active arrays: given back
    vertices, faces, attributes, face_attributes = mesh_arrays(vertices, faces, attributes,
                                                               face_attributes)
    # bad arguments are the caller's error, found before any hole is filled
    attributes = _checked_attributes(len(vertices), len(faces), attributes, face_attributes,
                                     attribute_kinds)
    options = _checked(method, options, fair_order, max_hole_edges, neighbourhood_rings)
    _check_flags(include_border=include_border, keep_margins=keep_margins, repair=repair,
                 validate=validate, zip_seams=zip_seams)
    check_islands_mode(islands)
    jobs = parallel.resolve_jobs(jobs)
    # the mesh checked (and repaired) and its holes found, the kernels loading meanwhile
    found = _found_holes(vertices, faces, holes, method, include_border=include_border,
                         keep_margins=keep_margins, repair=repair, validate=validate,
                         zip_seams=zip_seams)
    del vertices, faces  # the found mesh's from here: a converted copy of the input is freed
    # the plan: a report a hole; those over the size limit skipped, those with islands apart
    reports = _hole_reports(found.vertices, found.loops, found.numbers, method)
    todo, joined = joined_islands(found.islands, reports,
                                  _within_size(reports, max_hole_edges), islands)
    # before anything is filled: a zipped seam changes the faces the other holes are cut from
    zipped, merged, todo = open_seams(found.vertices, found.faces, todo, zip_seams,
                                      found.unfillable)
    mesh = _mesh_to_fill(found, zipped)
    run = Run(method, options, fair_order, explicit=holes is not None, n_holes=len(found.loops),
              progress=progress, rings=neighbourhood_rings,
              position={id(r): k for k, r in enumerate(reports)})
    _fill_all(mesh, todo, run, jobs, joined)
    # after the fills: a hole skipped or failed for any reason was not filled, and its
    # warning says so; this one is for the margin that was filled
    _warn_may_be_border(_filled_margins(found.margins, reports), stacklevel=3)
    # the result: what the per-hole checks could not see warned, the attributes carried
    result = _result(mesh, reports, found, merged)
    _warn_crossings(result, mesh, reports)
    result = _with_attributes(result, attributes)
    _warn_topology(result)
    result.display = display
    return result


def _check_flags(**flags) -> None:
    """The flag arguments are True or False."""
    for name, flag in flags.items():
        if not isinstance(flag, bool | np.bool_):
            raise ValueError(f"{name} must be True or False, got {flag!r}")


@dataclasses.dataclass
class _FoundHoles:
    """The mesh :func:`_found_holes` made ready and what it found in it."""

    vertices: np.ndarray  # float64
    faces: np.ndarray  # what ``repair`` kept (the input's otherwise)
    removed_faces: np.ndarray  # by ``repair``: ids into the input faces
    flipped_faces: np.ndarray  # by ``repair``: ids into the input faces
    loops: list[np.ndarray]  # the loops to fill
    numbers: list[int]  # their find_holes numbers (-1: none of its loops)
    incidence: object  # the faces' triangle_incidence
    zero_area: np.ndarray  # the faces of zero area, which no neighbourhood may hold
    unfillable: dict[int, Hole]  # never filled: they span no area or run along other loops
    margins: dict[int, Hole]  # may be the surface's margin (holes=None only)
    islands: list[Island]  # the islands in the holes chosen


def _found_holes(vertices, faces, holes, method: str, *, include_border: bool,
                 keep_margins: bool, repair: bool, validate: bool,
                 zip_seams: bool = False) -> _FoundHoles:
    """The mesh prepared (:func:`_prepared`: ``repair``'s removed and flipped faces), the
    loops to fill, their :func:`find_holes`
    numbers (the outer border counts, whatever was selected), the faces'
    ``triangle_incidence``, their zero-area faces (a warning names the degenerate faces),
    the holes never filled, by number (those that span no area for that,
    :attr:`Hole.spans_no_area`, and those that run along other loops,
    :attr:`Hole.runs_along_other_loops`), those that may be the margin, and the islands
    in the holes chosen (:func:`find_islands`);
    a large mesh's kernels load on the idle core meanwhile, and the passes that
    need only the edge table run there while the mesh is checked
    (:func:`~surfinpaint.fill.warmup.loading_beside`)."""
    with loading_beside(len(faces), method) as beside:
        prepared = _prepared(vertices, faces, repair, validate, beside)
        vertices, triangles = prepared.vertices, prepared.triangles
        found = prepared.found()  # after the checks: their errors come first
        loops = select_holes(vertices, triangles, holes, include_border=include_border,
                             keep_margins=keep_margins, table=prepared.table, validate=False,
                             found=found)
        prepared.table = None  # the holes are found: its memory is free for the fills
        numbers = hole_numbers(vertices, triangles, loops, found=found)
        incidence = prepared.incidence()  # before the thread is joined
    for note in degenerate_notes(prepared.faces, prepared.repeated, prepared.zero_area):
        warnings.warn(note, MeshWarning, stacklevel=3)
    unjoined = unjoined_borders_note(vertices, found, zip_seams=zip_seams)
    if unjoined is not None:  # else nothing says why a soup of faces has nothing filled
        warnings.warn(unjoined, MeshWarning, stacklevel=3)
    # chosen by the rule, not by the caller: warned about once filled
    margins = {} if holes is not None else {
        k: found[k] for k in numbers if k >= 0 and found[k].may_be_border}
    unfillable = {k: found[k] for k in numbers
                  if k >= 0 and (found[k].spans_no_area or found[k].runs_along_other_loops)}
    return _FoundHoles(
        vertices, prepared.faces, prepared.removed_faces, prepared.flipped_faces, loops,
        numbers, incidence, prepared.zero_area, unfillable, margins,
        find_islands(vertices, triangles, found, [k for k in numbers if k >= 0]))


def _warn_may_be_border(chosen: dict[int, Hole], *, stacklevel: int) -> None:
    """A warning for each hole filled (``chosen``: its :func:`find_holes` number -> hole)
    that may be the open surface's margin (:attr:`Hole.may_be_border`), saying how to
    keep it open."""
    for number, hole in chosen.items():
        if hole.may_be_border:
            if hole.inside_border:
                why = ("inside the surface's outer border, so it was filled; if it is an "
                       "inner margin of the surface (the inner edge of a scanned ring or bore)")
            else:
                why = (f"below the {BORDER_SPAN_FRACTION:.0%} that makes it the outer border, "
                       "so it was filled; if it is the open margin of the surface (a tooth "
                       "crown scanned to the gum)")
            warnings.warn(
                f"hole {number}: its loop ({hole.n_edges} edges) "
                f"spans {percent_below(hole.span_fraction)} of its surface's area, {why}, "
                "keep it open with --keep-margins, --holes or --max-hole-edges "
                "(keep_margins=, holes=, max_hole_edges=)",
                MeshWarning, stacklevel=stacklevel)


def _filled_margins(margins: dict[int, Hole], reports: list[HoleReport]) -> dict[int, Hole]:
    """The holes of ``margins`` (by number) that were filled (λ-H or faired)."""
    return {r.index: margins[r.index] for r in reports
            if r.index in margins and r.outcome in ("lambda-h", "faired")}


def _mesh_to_fill(found: _FoundHoles, faces: np.ndarray) -> FilledMesh:
    """The mesh the holes are cut from and stitched into: ``faces`` are the found mesh's
    with any seam zipped (:func:`~surfinpaint.fill.hole_steps.open_seams`)."""
    # the incidence made beside the checks is of the prepared faces, not of zipped ones
    return FilledMesh(found.vertices, faces,
                      found.incidence if faces is found.faces else None, found.zero_area)


def _hole_reports(vertices: np.ndarray, loops: Sequence[np.ndarray], numbers: list[int],
                  method: str) -> list[HoleReport]:
    """One report a hole to fill, in the order of ``loops``: its :func:`find_holes` number
    (of ``numbers``), loop, size and diameter, ``method`` requested."""
    return [HoleReport(index=k, loop=np.asarray(loop), n_edges=len(loop), requested=method,
                       method=method, diameter=loop_diameter(vertices[loop]))
            for k, loop in zip(numbers, loops, strict=True)]


def _within_size(reports: list[HoleReport], max_hole_edges: int | None) -> list[HoleReport]:
    """The holes to fill: those over ``max_hole_edges`` reported skipped."""
    todo = []
    for report in reports:
        too_large = over_size(report.n_edges, max_hole_edges)
        if too_large is not None:
            report.skipped = too_large
            report.method = "none"
        else:
            todo.append(report)
    return todo


def _fill_all(mesh: FilledMesh, todo: list[HoleReport], run: Run, jobs: int,
              joined: dict[int, list[Island]]) -> None:
    """The holes of ``todo`` filled and stitched into ``mesh`` in their order: in worker
    processes when worth it (:mod:`surfinpaint.fill.scheduler`), else one after another;
    a hole with islands (``joined``: hole number -> its islands) here, in its turn, the
    holes between such holes as one run each."""
    start = 0
    for at in [k for k, r in enumerate(todo) if r.index in joined] + [len(todo)]:
        _fill_run(mesh, todo[start:at], run, jobs)
        if at < len(todo):
            run.starting(todo[at])
            fill_with_islands(mesh, todo[at], run, joined[todo[at].index])
            run.finished(todo[at])
        start = at + 1


def _fill_run(mesh: FilledMesh, todo: list[HoleReport], run: Run, jobs: int) -> None:
    """:func:`_fill_all` for holes without islands."""
    workers = min(jobs, len(todo))
    if parallel.worth_parallel([r.n_edges for r in todo], workers, run.method):
        load_for_workers(run.method)  # once here, not in each worker (fill/warmup.py)
        fill_in_parallel(mesh, todo, run, workers)
        return
    for report in todo:
        run.starting(report)
        fill_hole(mesh, report, run)
        run.finished(report)


def _result(mesh: FilledMesh, reports: list[HoleReport], found: _FoundHoles,
            merged: np.ndarray) -> FillResult:
    """The filled mesh with its reports, the faces ``repair`` removed and flipped and the
    merged seam vertices."""
    result = mesh.result(reports, found.removed_faces)
    result.flipped_faces = found.flipped_faces
    result.merged_vertices = merged
    return result


def _warn_crossings(result: FillResult, mesh: FilledMesh, reports: list[HoleReport]) -> None:
    """Add the fills' triangles that cross the surface away from their hole, or another
    hole's fill, to the holes' reports (a triangle already counted is not counted again),
    each check's finding also a warning (at the caller of ``fill_holes``): each hole was
    checked only against the rings around it, as it was filled."""
    hole_faces = result.hole_faces()
    for report, far in zip(reports, far_crossing_triangles(
            result.vertices, mesh.faces, mesh.vertex_faces, hole_faces,
            [r.loop for r in reports]), strict=True):
        if len(far):
            triangles = how_many(len(far), "triangle", "triangles")
            warnings.warn(f"hole {report.index}: {triangles} of the fill "
                          f"cross{agreeing(len(far), 'es', '')} the surface farther out than the "
                          "rings around the hole checked as it was filled (a fold or a thin "
                          "part, near in space): check the result", HoleWarning, stacklevel=3)
            report.add_crossings(far)
    for pair in crossing_fill_pairs(result.vertices, hole_faces):
        one, other = reports[pair.first], reports[pair.second]
        first, second = len(pair.first_triangles), len(pair.second_triangles)
        # not a HoleWarning: the hole lines count these triangles, only this names both
        warnings.warn(f"holes {one.index} and {other.index}: "
                      f"{how_many(first, 'triangle', 'triangles')} of hole "
                      f"{one.index}'s fill cross{agreeing(first, 'es', '')} "
                      f"{second} of hole {other.index}'s (two holes near in "
                      "space, each filled without the other's fill): check the result",
                      MeshWarning, stacklevel=3)
        one.add_crossings(pair.first_triangles)
        other.add_crossings(pair.second_triangles)


def _warn_topology(result: FillResult) -> None:
    """The fills that may have changed the surface's topology (:func:`topology_changes`:
    two fills that close a tube's two ends) into ``result.topology``, each also a warning
    (at the caller of ``fill_holes``)."""
    result.topology = topology_changes(result)
    for change in result.topology:
        warnings.warn(change.message, MeshWarning, stacklevel=3)


@dataclasses.dataclass
class _Attributes:
    """The attributes the fill carries to the new vertices and faces, with their kinds."""

    vertex: dict[str, np.ndarray]
    face: dict[str, np.ndarray]
    vertex_kinds: dict[str, str]
    face_kinds: dict[str, str]  # those given: the others are found from the values


def _checked_attributes(n_vertices, n_faces, attributes, face_attributes,
                        kinds) -> _Attributes:
    """The vertex attributes and their kinds, checked (:func:`check_attributes`), the
    face attributes' row counts, and the kinds given for face attributes."""
    kinds = dict(kinds or {})
    face_kinds = {name: kinds[name] for name in face_attributes if name in kinds}
    attributes, kinds = check_attributes(n_vertices, attributes, {
        name: kind for name, kind in kinds.items()
        if name in attributes or name not in face_attributes})
    for name, a in face_attributes.items():
        if np.ndim(a) == 0 or len(a) != n_faces:
            raise ValueError(f"face attribute {name!r} has {len(a) if np.ndim(a) else 0} "
                             f"rows, the mesh has {n_faces} faces")
    if any(kind not in ATTRIBUTE_KINDS for kind in face_kinds.values()):
        raise ValueError(f"unknown attribute kinds {face_kinds}: use one of {ATTRIBUTE_KINDS}")
    return _Attributes(attributes, face_attributes, kinds, face_kinds)


@dataclasses.dataclass
class _Prepared:
    """The mesh as :func:`_prepared` makes it ready for the hole search."""

    vertices: np.ndarray  # float64
    faces: np.ndarray  # what ``repair`` kept (the input's otherwise)
    triangles: np.ndarray  # the faces that repeat no vertex
    removed_faces: np.ndarray  # by ``repair``: ids into the input faces
    flipped_faces: np.ndarray  # by ``repair``: ids into the input faces
    table: EdgeTable | None  # of ``triangles``, when validated
    found: Callable[[], list[Hole]]  # find_holes' list, when the thread has it
    incidence: Callable[[], object]  # the faces' triangle_incidence, likewise
    repeated: np.ndarray  # the faces that repeat a vertex
    zero_area: np.ndarray  # the faces of zero area


def _prepared(vertices, faces, repair: bool, validate: bool, beside: Beside) -> _Prepared:
    """The mesh as arrays and its triangles (:func:`triangle_rows`), with ``repair`` the
    faces around non-manifold edges removed and the rest oriented (which faces were removed
    and flipped, the flips warned), with ``validate`` checked; the
    edge table of its triangles when validated (built once: the holes are found from it
    too); the collectors of its :func:`find_holes` list and its ``triangle_incidence``; and
    its degenerate faces (those that repeat a vertex, left out of the table, the holes and
    the neighbourhoods; those of zero area, which no fill's neighbourhood may hold,
    validated or not).

    ``find_holes`` and the incidence are handed to ``beside`` once the table is built: its
    thread makes them while this one checks the mesh (651k case: docs/scale.md, session
    24; started before the table, beside the kernels' loading, they waited for the GIL and
    the peak memory grew by their temporaries and the table's together). The holes found
    are collected after the checks, so that a mesh the checks refuse raises their error,
    not one of ``find_holes``."""
    faces = face_ids(faces)  # whole-number floats taken, never truncated
    if validate:  # shapes, dtypes and ids first: the repair and the edge table index by them
        check_arrays(vertices, faces)
    vertices = _float64_vertices(vertices)
    removed, flipped = np.empty(0, dtype=np.int64), np.empty(0, dtype=np.int64)
    if repair:
        repair = repair_faces(vertices, faces)
        faces, removed, flipped = repair.faces, repair.removed, repair.flipped
        for note in repair.notes():
            warnings.warn(f"repair {note}", MeshWarning, stacklevel=4)
        if len(faces) == 0 and len(removed):  # else an empty result, said by nothing
            raise MeshError(f"repair removed every face ({how_many(len(removed), 'face', 'faces')}"
                            " on non-manifold edges or at bow-tie vertices): nothing is left "
                            "to fill", faces=removed[:10].tolist())
    triangles, repeated, rows = triangle_rows(faces)  # a face that repeats a vertex joins none
    table = EdgeTable.build(triangles, len(vertices)) if validate else None
    found = beside.submit(find_holes, vertices, triangles, table, validate=False)
    incidence = beside.submit(triangle_incidence, faces, len(vertices), rows, known=True)
    if validate:  # validate_mesh's errors, not its report
        _, flat = check_topology(vertices, triangles, table)
    else:  # checked by the caller, but the fills must know where they cannot go
        flat = zero_area_faces(vertices, triangles)
    flat = flat if rows is None else rows[flat]
    return _Prepared(vertices, faces, triangles, removed, flipped, table, found, incidence,
                     repeated, flat)


def _float64_vertices(vertices) -> np.ndarray:
    """The vertices as float64, what the fills compute in and return, with a warning naming
    how many vertices that rounds: float16/32 and integers below 2**53 are float64 numbers
    (their originals come back equal), a longdouble's or a big int64's may not be (session
    47: a longdouble array's originals came back rounded, without a word)."""
    given = np.asarray(vertices)
    as_float = np.asarray(given, dtype=np.float64)
    if given.dtype.kind in "fiu" and given.dtype != np.float64 and given.ndim == 2:
        with np.errstate(invalid="ignore", over="ignore"):  # a rounding past int64's range
            rounded = int(np.count_nonzero((as_float.astype(given.dtype) != given).any(axis=1)))
        if rounded:
            warnings.warn(f"{how_many(rounded, 'vertex', 'vertices')} of the {given.dtype} "
                          "input cannot be stored as float64, the fill's and its result's "
                          "number type: rounded to the nearest float64 (the original "
                          "vertices of the result are these rounded values)", MeshWarning,
                          stacklevel=5)
    return as_float


def _with_attributes(result: FillResult, attributes: _Attributes) -> FillResult:
    """The attributes of the filled mesh, new rows by the rules of fill/attributes.py."""
    if attributes.vertex:
        result.attributes = fill_result_attributes(result, attributes.vertex,
                                                   kinds=attributes.vertex_kinds)
    if attributes.face:
        result.face_attributes = fill_result_face_attributes(result, attributes.face,
                                                             attributes.face_kinds)
    return result
