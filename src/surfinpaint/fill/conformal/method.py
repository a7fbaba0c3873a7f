"""Conformal surface inpainting of one hole (Lui, Wen, Gu; method.md §6), checked against
fairing without any truth of the hole.

Per hole: the candidates (:mod:`.candidates`: the faired fills, and the λ-H fill made only
when needed) → the plane test (a surface around the hole that is a plane within its noise,
:func:`known_plane`, or two planes meeting at an edge no crease search saw,
:func:`known_two_planes`: the faired fill laid on it) → the truth-free test scores
(:mod:`surfinpaint.fill.selfcheck`) → the verdict (:func:`.selection.choose`, pure; then
:func:`.selection.demoted` where its evidence is not significant) → the winner, made and
checked → a typed :class:`~surfinpaint.fill.results.Fill`. A failure of the λ-H fill is a
``FillError``, caught here and only here: the faired fill the verdict prefers is written
instead, and the ``Fill`` says why. The original vertices never move.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from surfinpaint.errors import FillError
from surfinpaint.fill.conformal.candidates import Candidates
from surfinpaint.fill.conformal.checks import blended_fill
from surfinpaint.fill.conformal.ear_cut import ear_cut_flat, ear_cut_won
from surfinpaint.fill.conformal.options import ConformalOptions, check_fair_order
from surfinpaint.fill.conformal.selection import (
    Verdict,
    choose,
    demoted,
    fair3_over_lambda_h,
    hidden_rings_shallower,
    sibling_test_plan,
)
from surfinpaint.fill.creases import CREASE_ANGLE, sharp_edge_rows
from surfinpaint.fill.liepa.baseline import (
    faired_fills,
    laid_on_plane,
    laid_on_two_planes,
    smoothing_decision,
)
from surfinpaint.fill.results import Fill
from surfinpaint.fill.selfcheck import (
    advantages_over,
    hidden_ring_scores,
    hidden_ring_test,
    sibling_scores,
)
from surfinpaint.fill.two_planes import split_on_two_planes
from surfinpaint.geometry.cutting import edge_graph
from surfinpaint.geometry.edges import edge_keys
from surfinpaint.geometry.flatness import (
    TRIM_KEEP_MOST,
    PlaneTest,
    TwoPlanes,
    part_plane_test,
    plane_test,
    trimmed_plane_test,
    two_plane_test,
)
from surfinpaint.geometry.mesh import edge_faces, k_ring, unique_edges, vertex_normals
from surfinpaint.geometry.rows import rows_all, rows_any
from surfinpaint.geometry.validation import face_ids

__all__ = ["STAGES", "conformal_fill", "stage_words"]

#: The stages of one hole's conformal fill, in their order, as its ``stage`` callback hears
#: of each as it starts (a hole skips those it does not need: a plane, a hole without a vertex
#: inside, a verdict without the λ-H fill): the faired candidates, the plane test, the
#: self-check's two tests and the hole's own λ-H fill (a 200-edge hole's can take minutes)
STAGES = ("faired fills", "plane test", "self-check: hidden-ring test",
          "self-check: sibling test", "λ-H fill")


def stage_words(name: str) -> str:
    """How progress says the stage ``name`` of :data:`STAGES`: ``λ-H fill (stage 5 of 5)``."""
    return f"{name} (stage {STAGES.index(name) + 1} of {len(STAGES)})"


# the plane test (ConformalOptions.plane_test) looks at the known vertices within
# PLANE_RINGS rings of the loop, at the significance level PLANE_ALPHA: the level fixed
# before any run, the rings chosen on tuning-side scans (2, 3, 4, 6 compared: 2 gave the
# most flat verdicts and none worse; docs/candidates.md, "Session 26")
PLANE_RINGS = 2
PLANE_ALPHA = 0.01
# the fillet step of the plane test (:func:`on_loop_plane`) takes a vertex to lie on the
# loop's plane within this fraction of the loop's diameter: a plane to rounding, as a clean
# part's face is (fixed before any run; docs/candidates.md, "Session 31")
ON_PLANE = 1e-9
#: the note of a hole whose triangulation has no inner vertex (every candidate is that fill)
NO_INNER_VERTEX = ("no vertex inside the hole: every candidate fill is its triangulation, "
                   "no self-check needed")


def conformal_fill(
    vertices: np.ndarray,
    faces: np.ndarray,
    loop: np.ndarray,
    options: ConformalOptions | None = None,
    *,
    fair_order: int | None = None,
    stage: Callable[[str], None] | None = None,
) -> Fill:
    """Fill one hole by conformal λ-H inpainting, checked against fairing.

    Parameters
    ----------
    vertices, faces : arrays
        The mesh (often a local neighbourhood cut by :func:`surfinpaint.fill_holes`).
    loop : (k,) int array
        The hole's boundary loop, oriented as :func:`surfinpaint.geometry.mesh.boundary_loops`
        gives.
    options : ConformalOptions, optional
        The method's options (the defaults when None).
    fair_order : int, optional
        Fairing order of S0 and of the faired fill the self-check compares with and falls
        back to. None (default): S0 is trilaplacian (measured: the λ-H fill from it is
        closer), the λ-H fill is measured against the bilaplacian fill (the baseline), and
        the faired fallback is chosen per hole by the same tests between the bilaplacian and
        the trilaplacian one (better on smooth surfaces, much worse on noisy range scans;
        docs/accuracy.md).
    stage : callable(name), optional
        Told of each of the :data:`STAGES` as it starts (progress only: the fill is the same).

    Returns
    -------
    Fill
        ``kind="conformal"`` with its verdict and diagnostics, or ``kind="fair"`` with its
        ``fair_order``, the verdict and, when the λ-H fill failed, ``failure``.

    Raises
    ------
    FillError
        Only when not even the faired fill can be made.
    ValueError
        For a bad ``fair_order``.
    MeshError
        Face ids that are not whole numbers (:func:`surfinpaint.geometry.validation.
        face_ids`).
    """
    options = ConformalOptions() if options is None else options
    check_fair_order(fair_order)
    faces = face_ids(faces)  # whole-number floats taken, never truncated
    # "auto": decided once, on the hole's own surroundings; the self-check's test holes
    # (hidden rings, siblings) follow it; recorded on the fill for its report
    smoothing = smoothing_decision(vertices, faces, loop, options.fair_smoothing)
    if smoothing is not None:
        options = replace(options, fair_smoothing=smoothing.length)
    return replace(_decided_fill(vertices, faces, loop, options, fair_order,
                                 stage or _no_stage), smoothing=smoothing)


def _no_stage(name: str) -> None:
    """The ``stage`` callback of a caller who does not listen."""


def _decided_fill(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                  options: ConformalOptions, fair_order: int | None,
                  stage: Callable[[str], None]) -> Fill:
    """:func:`conformal_fill` once its options' smoothing is a length (or None)."""
    candidates = Candidates.for_hole(vertices, faces, loop, options, fair_order)
    faired: dict[str, Fill] = {}
    verdict = None
    try:
        if not options.select:
            stage(STAGES[-1])
            s0 = candidates.initial(vertices, faces, loop)
            return candidates.lambda_h(vertices, faces, loop, s0, creases=candidates.creases)
        # the faired fills are cheap; the λ-H fill of the hole is made once it has won
        stage(STAGES[0])
        faired = candidates.faired(vertices, faces, loop)
        reference = faired[f"fair{candidates.orders[0]}"]
        if options.plane_test:
            stage(STAGES[1])
            ring = _ring(vertices, faces, loop, PLANE_RINGS)  # both tests' vertices
            plane = known_plane(vertices, faces, loop, angle=options.crease_angle, ring=ring)
            if plane.flat:
                return _on_plane(reference, plane)
            # a noisy scan's edge across the hole (a crease the search found is rebuilt
            # by the λ-H fill along it instead)
            planes = None if candidates.crossed else known_two_planes(vertices, faces, loop,
                                                                      ring=ring)
            if planes is not None and planes.flat:
                return _on_two_planes(vertices, faces, loop, reference, planes)
        won = ear_cut_flat(vertices, faces, loop, options.ear_cut_flat,
                           options.ear_cut_faired)
        if won is None and options.ear_cut_ratio is not None:
            won = ear_cut_won(vertices, faces, loop, candidates)
        if won is not None:
            return won
        if len(reference.vertices) == 0 and not candidates.crossed:
            # the candidates share the triangulation and none has a vertex to place: they
            # are the same fill, and a self-check could only choose among equals (57 of
            # the 64 holes of PyMeshFix's scanned bunny, 63 % of its time)
            return replace(reference, selection=NO_INNER_VERTEX)
        verdict = self_check(vertices, faces, loop, candidates, stage)
        if verdict.make:
            stage(STAGES[-1])
            s0 = candidates.initial(vertices, faces, loop, faired)
            own = candidates.lambda_h(vertices, faces, loop, s0, creases=candidates.creases)
            if verdict.keep:
                return replace(own, verdict=verdict,
                               selection=verdict.sentence(kept=True, failed=False))
    except FillError as exc:
        return _fall_back(vertices, faces, loop, faired, verdict, exc, fair_order,
                          options)
    return _faired_choice(faired, verdict)


def self_check(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
               candidates: Candidates, stage: Callable[[str], None] = _no_stage) -> Verdict:
    """Run the truth-free tests of the hole's candidates and :func:`choose` by their scores:
    the cheaper hidden-ring test first, the sibling test only when it can still change the
    outcome (:func:`sibling_test_plan`). Where the hidden-ring test's λ-H fill was a crease
    fill and no crease crosses the hole, the test is run again one ring shallower
    (:func:`~surfinpaint.fill.conformal.selection.hidden_rings_shallower`); where that
    scores, the deeper test's fills are not scored (:func:`hidden_ring_test`: its scores
    would not be used). ``stage`` is told as each test starts (:data:`STAGES`)."""
    o = candidates.options
    reference = f"fair{candidates.orders[0]}"
    choose_faired = len(candidates.orders) > 1
    graph = edge_graph(faces, len(vertices))  # one adjacency for both tests' searches
    weigh = o.significance is not None  # the weighed verdict needs per-sample records
    hidden_detail: dict | None = {} if weigh else None
    sibling_detail: list | None = [] if weigh else None
    creased: list[bool] = []
    stage(STAGES[2])
    # the test hole filled; its fills scored only where their scores are used (below)
    deeper = hidden_ring_test(vertices, faces, loop,
                              _noting_creases(candidates.for_tests(), creased),
                              hide_rings=o.hide_rings, patch_rings=o.rings_in_patch,
                              graph=graph, detail=hidden_detail)
    shallower = False
    if hidden_rings_shallower(any(creased), crossed=candidates.crossed,
                              hide_rings=o.hide_rings):
        shallow_detail: dict | None = {} if weigh else None
        shallow = hidden_ring_scores(vertices, faces, loop, candidates.for_tests(),
                                     hide_rings=o.hide_rings - 1,
                                     patch_rings=o.rings_in_patch, graph=graph,
                                     detail=shallow_detail)
        if shallow:  # else the deeper test's scores stand
            hidden, hidden_detail, shallower = shallow, shallow_detail, True
    if not shallower:
        hidden = deeper()
    run, with_lambda_h = sibling_test_plan(hidden, reference=reference,
                                           choose_faired=choose_faired, shallower=shallower)
    sibling = {}
    if run:
        stage(STAGES[3])
        sibling = sibling_scores(vertices, faces, loop,
                                 _lambda_h_until_it_fails(candidates, with_lambda_h),
                                 siblings=o.siblings, gap_rings=o.gap_rings,
                                 patch_rings=o.rings_in_patch, graph=graph,
                                 detail=sibling_detail)
    verdict = choose(hidden, sibling, reference=reference, choose_faired=choose_faired,
                     crossed=candidates.crossed, shallower=shallower)
    if weigh:
        verdict = demoted(verdict, advantages_over(hidden_detail, sibling_detail, reference),
                          o.significance, crossed=candidates.crossed)
    if o.lambda_h_over_fair3 is not None and choose_faired:
        verdict = fair3_over_lambda_h(verdict, o.lambda_h_over_fair3, shallower=shallower,
                                      crossed=candidates.crossed)
    return verdict


def _lambda_h_until_it_fails(candidates: Candidates, with_lambda_h: bool = True):
    """The sibling test's fills (:meth:`Candidates.for_tests`), without the λ-H fill once it
    has failed on a sibling hole: that failure is given again for the later holes.

    Why it changes nothing: the sibling test's λ-H score is the mean over its holes
    (:func:`~surfinpaint.fill.selfcheck.sibling_scores`), infinite once one of them is, and
    a test whose λ-H score is infinite says nothing for it (:func:`choose`, :func:`demoted`):
    the later holes' λ-H fills could change no score, note or choice. Their faired fills,
    which score, are made as before (and the λ-H fill is the last candidate scored, so the
    faired fills' distances are searched as before)."""
    with_it = candidates.for_tests(with_lambda_h=with_lambda_h)
    faired_only = candidates.for_tests(with_lambda_h=False)
    failed: list[FillError] = []

    def fills(vertices, faces, loop):
        if failed:
            return {**faired_only(vertices, faces, loop), "conformal": failed[0]}
        out = with_it(vertices, faces, loop)
        if isinstance(out.get("conformal"), FillError):
            failed.append(out["conformal"])
        return out
    return fills


def _noting_creases(fills, creased: list):
    """``fills`` (:meth:`Candidates.for_tests`'s), appending to ``creased`` whether each test
    hole's λ-H fill was a crease fill."""
    def noting(vertices, faces, loop):
        out = fills(vertices, faces, loop)
        creased.append(getattr(out.get("conformal"), "crease", None) is not None)
        return out
    return noting


def _ring(vertices, faces, loop, rings):
    """The known vertices within ``rings`` rings of the loop (a mask), their local ids, and
    the mesh edges between them in local ids."""
    near = k_ring(faces, loop, rings, len(vertices))
    return (near, *_local(faces, near))


def known_plane(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, *,
                rings: int = PLANE_RINGS, angle: float = CREASE_ANGLE,
                ring: tuple | None = None) -> PlaneTest:
    """:func:`~surfinpaint.geometry.flatness.plane_test` (at ``PLANE_ALPHA``) of the known
    vertices within ``rings`` rings of the loop (the loop's included), with the mesh edges
    between them (``ring``: :func:`_ring`'s of those rings, where the caller has it); where
    it says curved:

    - the same test of the vertices a trimmed plane fit keeps
      (:func:`~surfinpaint.geometry.flatness.trimmed_plane_test`: a few vertices off the
      plane on one side, at most a tenth of the loop's), whose verdict stands where it is
      flat;
    - else, where sharp edges (turning by more than ``angle`` degrees) cut the rings, the
      same test of the hole's own face (:func:`own_face`: the vertices reached from the
      loop without crossing one), whose verdict stands where it is flat;
    - else, where the loop is a plane to rounding, the same test of the vertices of that face
      on the loop's plane (:func:`on_loop_plane`), where the others lie on one side of the
      loop (:func:`~surfinpaint.geometry.flatness.part_plane_test`), whose verdict stands
      where it is flat.

    Why the own face: a hole on a narrow face of a part, whose rings reach past the part's edges
    on both sides, is a plane that neither the test nor the trimmed fit sees, and the
    self-check's hidden rings, which cross those edges too, can favour a curved fill there.
    On 109 tuning-side holes cut on flat faces within 0.2-0.7 edge lengths of a part's
    edge (docs/candidates.md, "Session 30"), 9 clean-CAD holes were called curved and this
    found 6 of them flat (laid on the plane: exact, where the self-check had written fills
    at 0.28-1.61 % of the hole's diameter); of 896 other tuning-side holes, one changed
    (a coarse egg crate's, 0.91× the error).

    Why the loop's plane: a clean part's face that runs into a fillet or a bore has no sharp
    edge there, so its own face holds vertices on the fillet, off the plane on that side (and
    the vertices past a sharp edge lie on another side, so the trimmed fit does not apply).
    Of the 109 near-edge holes, this found the last 3 clean holes called curved flat (tee #3,
    bracket #1, #2: 0.267, 0.502, 0.740 % → exact, where the bilaplacian fill was 0.04-0.07
    %); no other tuning-side hole changed (docs/candidates.md, "Session 31"). On a smooth
    surface the loop is seldom a plane to rounding, and where it is (a cap of a sphere cut
    along a circle), the surface leaves its plane all around the loop: not on one side.
    """
    near, local, edges = _ring(vertices, faces, loop, rings) if ring is None else ring
    test = plane_test(vertices[near], edges, alpha=PLANE_ALPHA)
    if test.flat:
        return test
    trimmed = trimmed_plane_test(vertices[near], edges, keep=local[loop], alpha=PLANE_ALPHA)
    if trimmed is not None and trimmed.flat:
        return trimmed
    face = own_face(vertices, faces, loop, rings=rings, angle=angle, near=near)
    past = int(near.sum() - face.sum())
    on_face, face_edges = _local(faces, face)
    if past:
        own = plane_test(vertices[face], face_edges, alpha=PLANE_ALPHA)
        if own.flat:
            return replace(own, past_edges=past)
    on_plane = on_loop_plane(vertices, faces, loop, face)
    if on_plane is None:
        return test
    beside = part_plane_test(vertices[face], face_edges, on_plane[face], keep=on_face[loop],
                             alpha=PLANE_ALPHA)
    return replace(beside, past_edges=past) if beside is not None and beside.flat else test


def _local(faces, mask):
    """Local ids of the vertices of ``mask`` (-1 elsewhere) and the mesh edges between them
    in local ids."""
    local = np.full(len(mask), -1)
    local[mask] = np.arange(int(mask.sum()))
    return local, local[unique_edges(faces[rows_all(mask[faces])])[0]]


def on_loop_plane(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                  among: np.ndarray) -> np.ndarray | None:
    """The vertices of ``among`` (a mask) on the plane of the loop to rounding (within
    ``ON_PLANE`` of its diameter) and reached from the loop along mesh edges between such
    vertices, as a mask; None where more than ``TRIM_KEEP_MOST`` of the loop is off it (the
    loop is no plane to rounding).

    Examples
    --------
    >>> from surfinpaint.data import cube
    >>> from surfinpaint.geometry.mesh import boundary_loops
    >>> v, f = cube(6)
    >>> top = np.flatnonzero(np.isclose(v[:, 2], v[:, 2].max()))
    >>> centre = top[np.argmin(np.linalg.norm(v[top, :2] - v[top, :2].mean(0), axis=1))]
    >>> keep = ~(f == centre).any(axis=1)
    >>> loop = boundary_loops(f[keep])[0]
    >>> on = on_loop_plane(v, f[keep], loop, np.ones(len(v), dtype=bool))
    >>> # the top face's vertices, but for the hole's centre (no face holds it now)
    >>> bool(np.isclose(v[on, 2], v[:, 2].max()).all()), int(on.sum()) == len(top) - 1
    (True, True)
    """
    centre = vertices[loop].mean(axis=0)
    normal = np.linalg.svd(vertices[loop] - centre, full_matrices=False)[2][2]
    tolerance = ON_PLANE * float(np.ptp(vertices[loop], axis=0).max())
    if (np.abs((vertices[loop] - centre) @ normal) > tolerance).sum() > \
            TRIM_KEEP_MOST * len(loop):
        return None
    ids = np.flatnonzero(among)
    on = np.zeros(len(vertices), dtype=bool)
    on[ids] = np.abs((vertices[ids] - centre) @ normal) <= tolerance
    edges = unique_edges(faces[rows_all(among[faces])])[0]
    local = np.cumsum(on) - 1
    edges = local[edges[rows_all(on[edges])]]
    m = int(on.sum())
    graph = sp.coo_matrix((np.ones(len(edges)), tuple(edges.T)), shape=(m, m))
    labels = np.full(len(vertices), -1)
    labels[on] = connected_components(graph, directed=False)[1]
    return on & np.isin(labels, labels[loop[on[loop]]])


def own_face(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, *,
             rings: int = PLANE_RINGS, angle: float = CREASE_ANGLE,
             near: np.ndarray | None = None) -> np.ndarray:
    """The hole's own face: the vertices of the faces within ``rings`` rings of the loop
    that are reached from the faces on the loop's edges without crossing a sharp edge (one
    whose faces' normals turn by more than ``angle`` degrees, :func:`~surfinpaint.fill.
    creases.sharp_edges`), as a boolean mask over ``vertices``. ``near``: the mask of the
    vertices within ``rings`` rings of the loop, where the caller has it.

    Examples
    --------
    >>> from surfinpaint.data import cube
    >>> from surfinpaint.geometry.mesh import boundary_loops
    >>> v, f = cube(6)
    >>> top = np.flatnonzero(np.isclose(v[:, 2], v[:, 2].max()))
    >>> centre = top[np.argmin(np.linalg.norm(v[top, :2] - v[top, :2].mean(0), axis=1))]
    >>> keep = ~(f == centre).any(axis=1)
    >>> loop = boundary_loops(f[keep])[0]
    >>> face = own_face(v, f[keep], loop, rings=4)
    >>> bool(np.isclose(v[face, 2], v[:, 2].max()).all())  # the top face only
    True
    """
    if near is None:
        near = k_ring(faces, loop, rings, len(vertices))
    inside = faces[rows_all(near[faces])]
    table = edge_faces(inside)
    edges, owners, count = table
    n = len(vertices)
    keys = edge_keys(edges[:, 0], edges[:, 1], n)
    crossing = count == 2
    crossing[sharp_edge_rows(vertices, inside, table, angle)[0]] = False
    # one direction per shared edge: the components of an undirected search are the same
    step = sp.coo_matrix((np.ones(int(crossing.sum())), tuple(owners[crossing].T)),
                         shape=(len(inside), len(inside))).tocsr()
    loop_keys = edge_keys(loop, np.roll(loop, -1), n)
    reached = np.unique(owners[np.isin(keys, loop_keys), 0])
    labels = connected_components(step, directed=False)[1]
    face = np.zeros(n, dtype=bool)
    face[inside[np.isin(labels, labels[reached])]] = True
    return face


def known_two_planes(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, *,
                     rings: int = PLANE_RINGS, ring: tuple | None = None) -> TwoPlanes | None:
    """:func:`~surfinpaint.geometry.flatness.two_plane_test` (at ``PLANE_ALPHA``) of the
    known vertices within ``rings`` rings of the loop, where the edge between the two planes
    crosses the hole (the loop has vertices on both planes); else None. ``ring``:
    :func:`_ring`'s of those rings, where the caller has it. The vertex normals are summed
    over the faces at those vertices only (in the faces' order: the same bits)."""
    near, local, edges = _ring(vertices, faces, loop, rings) if ring is None else ring
    at_near = faces[rows_any(near[faces])]
    planes = two_plane_test(vertices[near], vertex_normals(vertices, at_near)[near], edges,
                            alpha=PLANE_ALPHA)
    if planes is None or planes.second_side[local[loop]].all() or \
            not planes.second_side[local[loop]].any():
        return None
    return planes


def _on_two_planes(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                   faired: Fill, planes: TwoPlanes) -> Fill:
    """The hole split along the line where the two planes of the known surface meet, each
    side faired and laid on its plane
    (:func:`~surfinpaint.fill.two_planes.split_on_two_planes`); where the split cannot
    be made, the faired fill laid on them
    (:func:`~surfinpaint.fill.liepa.baseline.laid_on_two_planes`); the verdict in words."""
    first = (planes.first.centre, planes.first.normal)
    second = (planes.second.centre, planes.second.normal)
    try:
        new, new_faces = split_on_two_planes(vertices, faces, loop, first, second,
                                             order=faired.fair_order)
        how = "split along the line where they meet, each side faired (order " \
              f"{faired.fair_order}) and laid on its plane"
    except FillError as exc:
        new, new_faces = laid_on_two_planes(faired.vertices, first, second), faired.faces
        how = f"the faired fill (order {faired.fair_order}) laid on them (not split: {exc})"
    return replace(faired, vertices=new, faces=new_faces, plane=planes,
                   selection=f"{planes.sentence()}: {how}, no self-check")


def _on_plane(faired: Fill, plane: PlaneTest) -> Fill:
    """The faired fill laid on the known surface's plane
    (:func:`~surfinpaint.fill.liepa.baseline.laid_on_plane`), with the verdict in words."""
    new = laid_on_plane(faired.vertices, plane.centre, plane.normal)
    return replace(faired, vertices=new, plane=plane,
                   selection=f"{plane.sentence()}: the faired fill (order "
                             f"{faired.fair_order}) laid on it, no self-check")


def _faired_choice(faired: dict[str, Fill], verdict: Verdict,
                   failure: str | None = None) -> Fill:
    """The faired fill the verdict prefers, with the verdict in words."""
    fill = faired[verdict.faired]
    return replace(fill, verdict=verdict, failure=failure, selection=verdict.sentence(
        kept=False, failed=failure is not None, fair_order=fill.fair_order))


def _fall_back(vertices, faces, loop, faired, verdict, exc: FillError,
               fair_order: int | None, options: ConformalOptions) -> Fill:
    """The faired fill written when the λ-H fill (or a step before the verdict) failed: the
    one the verdict prefers, or without a verdict the order asked for (2 by default), on
    the triangulation and refinement the options ask for (those of the faired candidates);
    where the λ-H fill was made and only its checks rejected it, its largest blend with that
    faired fill that passes them (:func:`_blended`)."""
    failure = f"{type(exc).__name__}: {exc}"
    if verdict is not None:
        fallback = _faired_choice(faired, verdict, failure)
    else:
        order = fair_order or 2
        new_v, new_f, used = faired_fills(vertices, faces, loop, (order,),
                                          search=options.s0_search,
                                          refinement=options.s0_refinement,
                                          smoothing=options.fair_smoothing)[order]
        fallback = Fill(new_v, new_f, "fair", fair_order=used, failure=failure)
    return _blended(len(vertices), fallback, getattr(exc, "rejected", None)) or fallback


def _blended(n: int, fallback: Fill, rejected) -> Fill | None:
    """The largest blend of the rejected λ-H fill with the faired ``fallback`` that passes
    the λ-H fill's checks (:func:`~surfinpaint.fill.conformal.checks.blended_fill`), as a
    conformal fill whose ``damping`` is the blend's share of the λ-H fill and whose notes
    say that it is a blend and why; None without a rejected fill of the same triangles
    (``n``: the mesh's vertex count) or without a blend that passes.

    Measured on the tuning-side families (docs/convergence.md, session 13): on the 25
    holes where the default made the λ-H fill and its checks rejected it, the blend (a
    share of the λ-H fill of 0.002-0.45) is 0.66-1.05× the faired fill's error, median
    0.999, better by more than 5 % on 5 and worse by more on none; a blend is reported as
    one (``LambdaHDiagnostics.blended_with``, the notes)."""
    if rejected is None or rejected.diagnostics is None:
        return None
    fill_faces = rejected.patch_faces[:rejected.n_fill_faces]
    new = np.arange(n, n + len(fallback.vertices))
    if not (np.array_equal(fill_faces, fallback.faces)
            and np.array_equal(np.sort(rejected.moving), new)):
        return None
    made = blended_fill(rejected, fallback.vertices[rejected.moving - n])
    if made is None:
        return None
    positions, t = made
    name = {2: "bilaplacian", 3: "trilaplacian"}.get(fallback.fair_order,
                                                     f"order-{fallback.fair_order}")
    blend = (f"{fallback.failure}; written instead: the largest blend of the λ-H fill with "
             f"the {name} fill that passes the checks, {t:.2g} of the λ-H fill")
    if fallback.verdict is not None:  # it chose the λ-H fill; its scores are the evidence
        blend += f" (self-check: {fallback.verdict.scores})"
    return Fill(positions[n:], fallback.faces, "conformal", verdict=fallback.verdict,
                selection=blend, diagnostics=replace(rejected.diagnostics, damping=t,
                                                     blended_with=name))
