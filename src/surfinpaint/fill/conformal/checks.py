"""Checks of a λ-H fill before it is accepted: finite, no degenerate triangles, no fold-over,
no intersection with the surface around it or with itself."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from surfinpaint.errors import FillError, how_many
from surfinpaint.geometry.intersection import patch_intersects_surroundings, self_intersections
from surfinpaint.geometry.mesh import edge_faces, face_areas, face_normals

__all__ = ["BLEND_HALVINGS", "DAMPING_STEPS", "FOLD_ANGLE", "CrossingError", "Crossings",
           "RejectedFill", "blended_fill", "check_crossings", "check_patch", "crossings",
           "damped_fill", "fold_count"]

# neighbouring triangles whose normals turn by more than this are a fold-over
FOLD_ANGLE = 120.0


# the λ-H fill is damped toward its start S0 by these fractions of its displacement, largest
# first, until it passes the checks (a line search: 1 is the undamped fill, 0 would be S0)
DAMPING_STEPS = (1.0, 0.8, 0.6, 0.45, 0.3, 0.15)

# below the last damping step, the largest blend that passes is found by this many halvings
# of (0, min(DAMPING_STEPS)] (:func:`blended_fill`)
BLEND_HALVINGS = 8


def fold_count(vertices: np.ndarray, patch_faces: np.ndarray, n_fill_faces: int, *,
               crease: np.ndarray | None = None, edges: tuple | None = None) -> int:
    """Fold-overs of a filled patch: pairs of neighbouring triangles, in the fill or a fill
    triangle and the surface next to it, whose normals turn by more than ``FOLD_ANGLE``,
    except across the ``crease`` edges (``edges``: ``edge_faces(patch_faces)``, when made)."""
    edges, owner, count = edge_faces(patch_faces) if edges is None else edges
    normals = face_normals(vertices, patch_faces)
    two = count == 2
    checked = two & ((owner[:, 0] < n_fill_faces) | (owner[:, 1] < n_fill_faces))
    if crease is not None and len(crease):
        # a crease is meant to turn sharply
        base = int(max(edges.max(), np.max(crease))) + 1
        sharp = np.sort(np.asarray(crease, dtype=np.int64), axis=1)
        checked &= ~np.isin(edges[:, 0] * base + edges[:, 1], sharp[:, 0] * base + sharp[:, 1])
    pairs = owner[checked]
    cos = np.einsum("ij,ij->i", normals[pairs[:, 0]], normals[pairs[:, 1]])
    return int((cos < np.cos(np.radians(FOLD_ANGLE))).sum())


def check_patch(vertices: np.ndarray, patch_faces: np.ndarray, n_fill_faces: int, *,
                self_crossing: bool = True, crease: np.ndarray | None = None,
                allowed_folds: int = 0, allowed_crossings: Crossings | None = None,
                edges: tuple | None = None) -> None:
    """Reject a filled patch (its first ``n_fill_faces`` faces are the fill; ``edges``:
    ``edge_faces(patch_faces)``, when made).

    Raises
    ------
    FillError
        For non-finite positions, degenerate triangles, more than ``allowed_folds``
        fold-overs (:func:`fold_count`), or intersections with the surrounding rings or
        (with ``self_crossing``) with itself other than the ``allowed_crossings``.
    """
    fill = patch_faces[:n_fill_faces]
    if not np.isfinite(vertices[np.unique(fill)]).all():
        raise FillError("the filled patch has non-finite coordinates")
    area = face_areas(vertices, fill)
    if (area <= 1e-12 * max(float(np.median(area)), 1e-300)).any():
        raise FillError("the filled patch has degenerate triangles")
    folds = fold_count(vertices, patch_faces, n_fill_faces, crease=crease, edges=edges)
    if folds > allowed_folds:
        more = f" (its start has {allowed_folds})" if allowed_folds else ""
        raise FillError(f"the filled patch folds over at {how_many(folds, 'edge', 'edges')}{more}")
    check_crossings(crossings(vertices, patch_faces, n_fill_faces, self_crossing=self_crossing),
                    allowed_crossings)


def check_crossings(found: Crossings, allowed: Crossings | None = None) -> None:
    """:func:`check_patch`'s last test: reject a patch whose crossings ``found`` are more
    than the ``allowed`` ones.

    Raises
    ------
    CrossingError
        With ``found`` as its attribute (a check of the same patch against other allowed
        crossings needs no new search: :func:`damped_fill`).
    """
    allowed = allowed or Crossings.none()
    around = _new_pairs(found.around, allowed.around)
    if len(around):
        raise CrossingError(f"the filled patch cuts through the surrounding surface "
                            f"({how_many(len(around), 'triangle pair', 'triangle pairs')})", found)
    itself = _new_pairs(found.itself, allowed.itself)
    if len(itself):
        raise CrossingError("the filled patch intersects itself "
                            f"({how_many(len(itself), 'triangle pair', 'triangle pairs')})", found)


class CrossingError(FillError):
    """A filled patch crosses the surface around it or itself; ``found``: its
    :class:`Crossings` (None where not given)."""

    def __init__(self, message: str, found: Crossings | None = None):
        super().__init__(message)
        self.found = found


@dataclass(frozen=True)
class Crossings:
    """Intersecting triangle pairs of a filled patch: ``around`` (fill face, ring face) and
    ``itself`` (two fill faces), as index rows into the fill and the rings."""

    around: np.ndarray
    itself: np.ndarray

    @staticmethod
    def none() -> Crossings:
        return Crossings(np.zeros((0, 2), np.int64), np.zeros((0, 2), np.int64))


def crossings(vertices: np.ndarray, patch_faces: np.ndarray, n_fill_faces: int, *,
              self_crossing: bool = True) -> Crossings:
    """The :class:`Crossings` of a filled patch (``itself`` empty without
    ``self_crossing``)."""
    fill = patch_faces[:n_fill_faces]
    around = patch_intersects_surroundings(vertices, fill, patch_faces[n_fill_faces:])
    itself = (self_intersections(vertices, fill) if self_crossing
              else np.zeros((0, 2), np.int64))
    return Crossings(np.asarray(around, np.int64).reshape(-1, 2),
                     np.asarray(itself, np.int64).reshape(-1, 2))


def _new_pairs(found: np.ndarray, allowed: np.ndarray) -> np.ndarray:
    """The rows of ``found`` that are not rows of ``allowed``."""
    if len(found) == 0 or len(allowed) == 0:
        return found
    base = int(max(found.max(), allowed.max())) + 1
    return found[~np.isin(found[:, 0] * base + found[:, 1], allowed[:, 0] * base + allowed[:, 1])]


@dataclass(frozen=True)
class RejectedFill:
    """A λ-H fill that no damping step let pass (:func:`damped_fill`), kept on the
    ``FillError`` it raised (as its ``rejected`` attribute) for :func:`blended_fill`.

    Attributes
    ----------
    positions : (n, 3) float array
        All positions, the λ-H fill at ``moving``.
    moving : (m,) int array
    patch_faces : (p, 3) int array
        The patch, its first ``n_fill_faces`` faces the fill.
    n_fill_faces : int
    self_crossing : bool
    crease : (c, 2) int array, optional
    diagnostics : LambdaHDiagnostics, optional
        What the λ-H pass used (set by the candidates, which made it).
    """

    positions: np.ndarray
    moving: np.ndarray
    patch_faces: np.ndarray
    n_fill_faces: int
    self_crossing: bool = True
    crease: np.ndarray | None = None
    diagnostics: object | None = None


def blended_fill(rejected: RejectedFill, end: np.ndarray) -> tuple[np.ndarray, float] | None:
    """The largest blend ``end + t (λH − end)`` of a rejected λ-H fill with another fill
    of the same triangles (``end``: its positions of ``rejected.moving``, e.g. the faired
    fill written instead) that passes :func:`check_patch`, the folds and crossings ``end``
    has itself allowed; ``t`` from ``DAMPING_STEPS``, then ``BLEND_HALVINGS`` halvings of
    (0, min(DAMPING_STEPS)].

    Why: where the λ-H fill folds over or cuts through the surface at every damping step,
    a blend with a share of it can still pass; measured on 30 such holes of the tuning-side
    families, the blend with the faired fill the default would have written is 0.66-1.05×
    that fill's error (better by more than 5 % on 5 of 25, worse on none;
    docs/convergence.md, session 13).

    Returns
    -------
    (positions, t) or None
        All positions with the blend at ``moving``, and ``t`` (0 < t ≤ 1); None when no
        ``t`` tried passes.
    """
    r = rejected
    at_end = r.positions.copy()
    at_end[r.moving] = end
    edges = edge_faces(r.patch_faces)
    allowed = fold_count(at_end, r.patch_faces, r.n_fill_faces, crease=r.crease, edges=edges)
    crossed = crossings(at_end, r.patch_faces, r.n_fill_faces, self_crossing=r.self_crossing)
    displacement = r.positions[r.moving] - end

    def trial(t):
        out = at_end.copy()
        out[r.moving] = end + t * displacement
        try:
            check_patch(out, r.patch_faces, r.n_fill_faces, self_crossing=r.self_crossing,
                        crease=r.crease, allowed_folds=allowed, allowed_crossings=crossed,
                        edges=edges)
        except FillError:
            return None
        return out

    for t in DAMPING_STEPS:
        passed = trial(t)
        if passed is not None:
            return passed, t
    low, high, best = 0.0, min(DAMPING_STEPS), None
    for _ in range(BLEND_HALVINGS):
        middle = 0.5 * (low + high)
        passed = trial(middle)
        if passed is None:
            high = middle
        else:
            low, best = middle, passed
    return None if best is None else (best, low)


def damped_fill(vertices: np.ndarray, start: np.ndarray, moving: np.ndarray,
                patch_faces: np.ndarray, n_fill_faces: int, *, self_crossing: bool = True,
                crease: np.ndarray | None = None) -> tuple[np.ndarray, float]:
    """The λ-H fill, damped toward its start until it passes :func:`check_patch`.

    A fold-over of the λ-H fill is local and is rarely the whole displacement's fault: the
    fill ``S0 + t (λH − S0)`` is tried for ``t`` in ``DAMPING_STEPS`` (a line search toward
    the start, which the checks accepted as the faired fill), and the first that passes is
    kept. Fold-overs that the start has too (a brain sulcus's loop can make every smooth
    fill turn by more than ``FOLD_ANGLE`` against its rim) are not counted against it, nor
    are the triangle pairs that cross in the start too (at a cube's corner the
    triangulation of the loop itself can cut the surface, measured: 4 pairs whatever the
    interior vertices do).

    Parameters
    ----------
    vertices : (n, 3) float array
        Positions with the λ-H fill at ``moving``.
    start : (m, 3) float array
        The start S0's positions of ``moving``.
    moving : (m,) int array
        The vertices the λ-H fill moved.
    patch_faces, n_fill_faces, self_crossing, crease :
        As :func:`check_patch`.

    Returns
    -------
    positions : (n, 3) float array
        ``vertices`` with the damped fill at ``moving``.
    t : float
        The fraction of the λ-H displacement kept (1: undamped).

    Raises
    ------
    FillError
        The undamped fill's failure, when no step passes; its ``rejected`` attribute is the
        :class:`RejectedFill` (for :func:`blended_fill`).
    """
    at_start = vertices.copy()
    at_start[moving] = start
    edges = edge_faces(patch_faces)  # one topology for the start and every trial
    allowed = fold_count(at_start, patch_faces, n_fill_faces, crease=crease, edges=edges)
    crossed = None  # the start's crossings, found only once a trial crosses something
    displacement = vertices[moving] - start
    first_failure = None
    for t in DAMPING_STEPS:
        trial = at_start.copy()
        trial[moving] = start + t * displacement
        try:
            try:
                check_patch(trial, patch_faces, n_fill_faces, self_crossing=self_crossing,
                            crease=crease, allowed_folds=allowed, allowed_crossings=crossed,
                            edges=edges)
            except CrossingError as crossing:
                if crossed is not None:
                    raise
                crossed = crossings(at_start, patch_faces, n_fill_faces,
                                    self_crossing=self_crossing)
                # the trial passed the other checks and its crossings are found: only they
                # are checked again, against the start's (the same outcome as a whole
                # check_patch, without the second search)
                check_crossings(crossing.found, crossed)
        except FillError as exc:
            first_failure = first_failure or exc
            continue
        return trial, t
    first_failure.rejected = RejectedFill(vertices.copy(), np.asarray(moving), patch_faces,
                                          n_fill_faces, self_crossing, crease)
    raise first_failure
