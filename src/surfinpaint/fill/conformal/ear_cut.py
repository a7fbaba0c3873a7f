"""The ear-cut triangulation as a candidate (both tests default off): where the
hidden-ring test scores MeshFix's greedy ear cutting
(:func:`surfinpaint.fill.liepa.ear_cutting.ear_cut_triangulation`) well below every
candidate of the self-check (``ConformalOptions.ear_cut_ratio``), or where the ear-cut
patch is (nearly) all pieces of the known faces' planes and two of them meet at a crease
inside the hole (``ConformalOptions.ear_cut_flat``, :func:`ear_cut_flat`), the loop's
ear-cut triangulation is written: bare (no new vertex) by the first rule; by the second
refined within its planes to the surroundings' density (:func:`refined_in_planes`).

Why: on machined parts PyMeshFix is closer than the default on some holes, and what makes
it closer is its triangulation, which continues the known faces' planes into the hole; its
refinement makes it worse (docs/candidates.md, "Session 49 (helper): CAD holes PyMeshFix
fills closer"). The flatness rule separates the holes it rebuilds better than the
hidden-ring test (docs/candidates.md, "Session 50 (helper): ear-cut triangulation where a
crease crosses the hole").
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from surfinpaint.errors import FillError
from surfinpaint.fill.conformal.candidates import Candidates
from surfinpaint.fill.creases import sharp_edges
from surfinpaint.fill.liepa.ear_cutting import ear_cut_triangulation
from surfinpaint.fill.liepa.fairing import fair
from surfinpaint.fill.liepa.refinement import boundary_scales, refine_patch
from surfinpaint.fill.results import BY_FAIRED_PLANES, BY_FLAT_PLANES, BY_HIDDEN_RINGS, Fill
from surfinpaint.fill.selfcheck import hidden_ring_scores
from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.geometry.mesh import face_areas, face_normals, halfedge_faces, orient_loop
from surfinpaint.geometry.rows import rows_any
from surfinpaint.geometry.validation import zero_area_faces

__all__ = ["BY_FAIRED_PLANES", "BY_FLAT_PLANES", "BY_HIDDEN_RINGS", "EAR_CUT", "FLIP_ANGLE",
           "PIECE_ANGLE", "PIECE_CREASE", "ROUNDING", "PlanePieces", "ear_cut_fill",
           "ear_cut_flat", "ear_cut_won", "faired_off_planes", "plane_pieces",
           "refined_in_planes"]

EAR_CUT = "ear_cut"
# hidden-ring scores below this fraction of the loop's mean edge are rounding: on a hole
# every candidate rebuilds exactly, they do not decide (holdout 10's spanner #0: the λ-H
# fill's 3e-8 h against the ear cut's 2e-8 h, but the ear cut 1.9 % off the truth)
ROUNDING = 1e-6
# the flatness rule (ear_cut_flat): a patch triangle continues a known face's plane where
# their normals differ by less than this (degrees; chosen on the 413 tuning-side CAD holes:
# 1 fires on 2 fewer, one better and one worse, 5 on 7 more, 6 of them worse), and a crease
# crosses the hole where two such planes meet at more than this (any of 0 to 45 the same
# there: every patch that is 90 % planes and more than one plane has a crease of 60 or more)
PIECE_ANGLE = 2.0
PIECE_CREASE = 20.0
# the refinement of the written patch (refined_in_planes) flips an edge only between
# triangles within this angle (degrees): coplanar but for rounding, so the refined patch is
# the bare one's surface. At PIECE_ANGLE, flips between triangles 0.3-1 degree apart moved
# it: 5 of the 73 tuning-side CAD holes the rule fires on 10-190 % farther from the truth
# than the bare patch (by at most 0.006 % of the diameter); docs/candidates.md, session 51
FLIP_ANGLE = 0.01


def ear_cut_fill(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray) -> Fill:
    """The loop's ear-cut triangulation as a fill (no new vertex).

    Raises
    ------
    FillError
        Where it has a zero-area triangle (greedy cutting can leave the last ears on a
        straight run of the loop): the fill could not be written (the pipeline skips such
        a fill), so it is no candidate.
    """
    triangles = ear_cut_triangulation(vertices, faces, loop)
    if len(zero_area_faces(vertices, triangles)):
        raise FillError("ear cutting left a zero-area triangle")
    return Fill(np.zeros((0, 3)), triangles, "fair")


def ear_cut_won(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                candidates: Candidates, graph=None) -> Fill | None:
    """The ear-cut fill with the test's verdict in words where its hidden-ring score is
    below ``ear_cut_ratio`` × the best of the self-check's candidates' (the faired fills and
    the λ-H fill, scored on the same test hole); None elsewhere, where the test does not
    score, or where the best score is rounding (:data:`ROUNDING`)."""
    o = candidates.options
    tests = candidates.for_tests()

    def with_ear_cut(v, f, lp):
        out = dict(tests(v, f, lp))
        try:
            out[EAR_CUT] = ear_cut_fill(v, f, lp)
        except FillError as exc:  # scores as a failure
            out[EAR_CUT] = exc
        return out

    scores = hidden_ring_scores(vertices, faces, loop, with_ear_cut, hide_rings=o.hide_rings,
                                patch_rings=o.rings_in_patch, graph=graph)
    best = min((s for name, s in scores.items() if name != EAR_CUT), default=np.inf)
    mine = scores.get(EAR_CUT, np.inf)
    edge = np.linalg.norm(vertices[loop] - vertices[np.roll(loop, -1)], axis=1).mean()
    if not (np.isfinite(best) and best > ROUNDING * edge and mine < o.ear_cut_ratio * best):
        return None
    try:
        fill = ear_cut_fill(vertices, faces, loop)
    except FillError:
        return None
    ratio = mine / best if best > 0 else 0.0
    return Fill(fill.vertices, fill.faces, "fair", ear_cut=BY_HIDDEN_RINGS,
                selection=f"ear cutting: its hidden-ring score {ratio:.3g}× the best "
                          f"candidate's (below {o.ear_cut_ratio:g}): the loop's "
                          "triangulation written, no new vertex")


def ear_cut_flat(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                 flat: float | None, faired: float | None = None) -> Fill | None:
    """The ear-cut fill refined within its planes (:func:`refined_in_planes`), with the
    rule's verdict in words, where at least ``flat`` of its area continues known faces'
    planes (:func:`plane_pieces` at :data:`PIECE_ANGLE`) and two of those planes meet at
    more than :data:`PIECE_CREASE`; where the share is below ``flat`` but at least
    ``faired``, the same with its vertices off the planes faired (:func:`faired_off_planes`);
    None elsewhere (``flat`` None: never the first, ``faired`` None: never the second), and
    where the ear cut cannot be written (:func:`ear_cut_fill`). The rule is decided on the
    bare ear cut."""
    least = min(x for x in (flat, faired, np.inf) if x is not None)
    if not np.isfinite(least):
        return None
    try:
        if not _loop_faces_turn(vertices, faces, loop, PIECE_CREASE):
            return None  # no crease possible: the rule's answer, without the ear cut
        fill = ear_cut_fill(vertices, faces, loop)
    except FillError:
        return None
    pieces = plane_pieces(vertices, faces, fill.faces, np.radians(PIECE_ANGLE))
    share, crease = pieces.flat_fraction(), np.degrees(pieces.crease())
    if share < least or not crease > PIECE_CREASE:
        return None
    new_vertices, patch = refined_in_planes(vertices, faces, loop, fill.faces)
    flat_enough = flat is not None and share >= flat

    def said(bound: float, how: str) -> str:
        return (f"ear cutting: {100 * share:.0f} % of its area continues the known faces' "
                f"planes (at least {bound:g}), two of them meet at {crease:.0f}°: the loop's "
                f"triangulation written, refined within its planes, {how}")

    if flat_enough:
        return Fill(new_vertices, patch, "fair", ear_cut=BY_FLAT_PLANES,
                    selection=said(flat, "not faired"))
    try:
        new_vertices = faired_off_planes(vertices, faces, new_vertices, patch)
    except FillError:
        return None
    return Fill(new_vertices, patch, "fair", ear_cut=BY_FAIRED_PLANES,
                selection=said(faired, "its vertices off them faired"))


def _loop_faces_turn(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                     degrees: float) -> bool:
    """Whether two of the known faces on the loop's edges meet at more than ``degrees``
    (less a rounding margin). A plane piece's normal is the known face's on the loop edge
    it grows from (:func:`plane_pieces`), so where no two of them meet at more, no two
    pieces do: the flatness rule cannot fire, and most holes (a scan's, a smooth
    surface's) are told so before their ear cut is made (a twelfth of their fill's time
    on a torus's holes, session 51)."""
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    owner, _ = halfedge_faces(faces, orient_loop(faces, loop))
    normals = face_normals(v, faces[owner])
    widest = np.degrees(np.arccos(np.clip((normals @ normals.T).min(), -1.0, 1.0)))
    return bool(widest > degrees - 1e-6)


def refined_in_planes(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                      triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """An ear-cut patch refined to the surrounding edge length without leaving its planes.

    Every edge whose two triangles are not coplanar (they turn by more than
    :data:`FLIP_ANGLE`, :func:`~surfinpaint.fill.creases.sharp_edges`: the creases the ear
    cut put inside the hole, and the folds of its few non-plane triangles) is first cut
    into pieces of about the surrounding edge length (:func:`_creases_split`: new vertices
    on the edge, on both its triangles' planes); then Liepa's refinement as the faired
    fills use it (:func:`~surfinpaint.fill.liepa.refinement.refine_patch`): each new vertex
    is the centroid of the triangle it splits, on that triangle's plane, and nothing is
    faired. Those pieces never flip, so the Delaunay flips only swap diagonals between
    coplanar triangles: the refined patch is the bare one's surface, its creases where the
    ear cut put them.

    Returns
    -------
    new_vertices : (m, 3) float array
    patch : (p, 3) int array
        Over the mesh's ids and ``n + j`` for new vertex ``j``.
    """
    v = np.asarray(vertices, dtype=float)
    loop = np.asarray(loop, np.int64)
    creases, _ = sharp_edges(v, triangles, FLIP_ANGLE)
    sigma = np.zeros(len(v))
    sigma[loop] = boundary_scales(v, faces, loop)
    points, scales, patch, pieces = _creases_split(v, np.asarray(triangles, np.int64),
                                                   creases, sigma)
    ids = len(v) + np.arange(len(points))
    # the crease points join the loop for their scales only (``loops``: the one closed
    # loop whose edges never flip)
    new, patch = refine_patch(np.vstack([v, points]), patch, np.concatenate([loop, ids]),
                              faces=faces, loops=[loop], fixed_edges=pieces,
                              scales=np.concatenate([sigma[loop], scales]))
    return np.vstack([points, new]), patch


def faired_off_planes(vertices: np.ndarray, faces: np.ndarray, new_vertices: np.ndarray,
                      patch: np.ndarray) -> np.ndarray:
    """The new vertices of a refined ear-cut patch (:func:`refined_in_planes`) with those off
    its planes faired: the vertices no plane-continuing triangle touches
    (:func:`plane_pieces` at :data:`PIECE_ANGLE` on the refined patch) placed by the
    bilaplacian fairing (:func:`~surfinpaint.fill.liepa.fairing.fair`, order 2) with every
    other vertex fixed, so the plane pieces stay exactly where they were and the rest of
    the patch bends smoothly between them instead of keeping the ear cut's flat folds.

    Returns
    -------
    (m, 3) float array
        ``new_vertices`` with the free ones moved.

    Raises
    ------
    FillError
        Where the fairing's solve gives non-finite positions.
    """
    v = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, np.int64)
    patch = np.asarray(patch, np.int64)
    everything = np.vstack([v, new_vertices])
    pieces = plane_pieces(everything, faces, patch, np.radians(PIECE_ANGLE))
    on_plane = np.zeros(len(everything), bool)
    on_plane[patch[pieces.plane >= 0].ravel()] = True
    free = len(v) + np.flatnonzero(~on_plane[len(v):])
    if not len(free):
        return np.asarray(new_vertices, dtype=float)
    placed = fair(everything, np.vstack([faces, patch]), free, order=2)[len(v):]
    if not np.isfinite(placed).all():
        raise FillError("fairing off the planes gave non-finite positions")
    return placed


def _creases_split(v: np.ndarray, triangles: np.ndarray, creases: np.ndarray,
                   sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Each crease edge (a, b) cut into round(|ab| / σ) equal pieces, σ the mean of its
    ends' scales ``sigma`` (its ends are loop vertices: the ear cut adds none), its two
    triangles into fans over the pieces (oriented as they were).

    Returns
    -------
    points : (c, 3) float array
        The new vertices, ids ``len(v) + j``, crease by crease from a to b.
    scales : (c,) float array
        Their σ, interpolated between the crease's ends'.
    triangles : (t, 3) int array
    pieces : (e, 2) int array
        The crease's pieces (the uncut creases whole).
    """
    points, scales, pieces = [np.zeros((0, 3))], [np.zeros(0)], [np.zeros((0, 2), np.int64)]
    for a, b in creases:  # a few creases per hole
        k = max(1, int(round(np.linalg.norm(v[b] - v[a]) / (0.5 * (sigma[a] + sigma[b])))))
        ids = len(v) + sum(map(len, points)) + np.arange(k - 1)
        w = np.arange(1, k) / k
        points.append(v[a] + np.outer(w, v[b] - v[a]))
        scales.append((1 - w) * sigma[a] + w * sigma[b])
        chain = np.concatenate([[a], ids, [b]])
        pieces.append(np.column_stack([chain[:-1], chain[1:]]))
        triangles = np.vstack([_fanned(t, chain) for t in triangles])
    return np.vstack(points), np.concatenate(scales), triangles, np.vstack(pieces)


def _fanned(t: np.ndarray, chain: np.ndarray) -> np.ndarray:
    """Triangle ``t`` as rows: itself, or where it has the edge from ``chain[0]`` to
    ``chain[-1]`` (either way round) the fan from its third corner over the chain's pieces,
    oriented as ``t``."""
    for r in range(3):
        s, e, o = np.roll(t, -r)
        if {s, e} == {chain[0], chain[-1]}:
            q = chain if s == chain[0] else chain[::-1]
            return np.column_stack([q[:-1], q[1:], np.full(len(q) - 1, o)])
    return t[None]


class PlanePieces(NamedTuple):
    """The ear-cut patch's triangles that continue a known face's plane
    (:func:`plane_pieces`).

    Attributes
    ----------
    plane : (m,) int array
        For each patch triangle, the known face whose plane it continues (an index into the
        mesh's faces), -1 where it continues none.
    area : (m,) float array
        The patch triangles' areas.
    normal : (m, 3) float array
        The unit normal of the plane each triangle continues (its known face's; zero where
        it continues none).
    """

    plane: np.ndarray
    area: np.ndarray
    normal: np.ndarray

    def flat_fraction(self) -> float:
        """The fraction of the patch's area in plane-continuing triangles."""
        return float(self.area[self.plane >= 0].sum() / max(self.area.sum(), 1e-300))

    def crease(self) -> float:
        """The largest angle (radians) between two planes the patch continues: 0 where it
        continues one plane or none, a crease inside the patch where it is large."""
        n = self.normal[self.plane >= 0]
        if len(n) < 2:
            return 0.0
        return float(np.arccos(np.clip((n @ n.T).min(), -1.0, 1.0)))


def plane_pieces(vertices: np.ndarray, faces: np.ndarray, triangles: np.ndarray,
                 angle: float) -> PlanePieces:
    """Which triangles of a hole's patch continue a known face's plane.

    A patch triangle on a loop edge continues the plane of the known face across that edge
    where their normals differ by less than ``angle``; the plane grows from there across
    the patch's inner edges to every triangle connected to it through triangles all within
    ``angle`` of that known face's normal (measured against the known face, not from
    triangle to triangle, so a curved patch of small steps does not count as flat).

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        The mesh with the hole (the known faces).
    triangles : (m, 3) int array
        The patch's faces over the same vertices (e.g. :func:`ear_cut_triangulation`).
    angle : float
        Radians.
    """
    v = np.asarray(vertices, dtype=float)
    patch = np.asarray(triangles, np.int64)
    faces = np.asarray(faces, np.int64)
    ids = np.flatnonzero(rows_any(np.isin(faces, patch)))  # the known faces at the loop
    known, m = faces[ids], len(patch)
    normals = face_normals(v, np.concatenate([patch, known]))
    table = EdgeTable.build(np.concatenate([patch, known]))
    pair = table.owners[table.count == 2]
    inner = pair[(pair < m).all(axis=1)]  # patch-patch edges
    across = pair[(pair < m).sum(axis=1) == 1]  # loop edges: a patch and a known face
    seed, face = across.min(axis=1), across.max(axis=1)
    cos = np.cos(angle)
    plane = np.full(m, -1, np.int64)
    # try the known faces in turn (at most the loop's length); each grows its piece
    for t, f in zip(seed, face, strict=True):
        if plane[t] >= 0 or normals[t] @ normals[f] <= cos:
            continue
        close = normals[:m] @ normals[f] > cos
        keep = inner[close[inner].all(axis=1)]
        graph = sp.coo_matrix((np.ones(len(keep)), (keep[:, 0], keep[:, 1])), shape=(m, m))
        _, label = connected_components(graph, directed=False)
        grown = (label == label[t]) & (plane < 0)
        plane[grown] = f - m
    normal = np.where((plane >= 0)[:, None], normals[m + np.maximum(plane, 0)], 0.0)
    return PlanePieces(np.where(plane >= 0, ids[plane], -1), face_areas(v, patch), normal)
