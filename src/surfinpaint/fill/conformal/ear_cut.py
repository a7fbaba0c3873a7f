"""The ear-cut triangulation as a candidate (``ConformalOptions.ear_cut_ratio``, default
off): where the hidden-ring test scores MeshFix's greedy ear cutting
(:func:`surfinpaint.fill.liepa.ear_cutting.ear_cut_triangulation`) well below every
candidate of the self-check, the loop's ear-cut triangulation is written (no new vertex).

Why: on machined parts PyMeshFix is closer than the default on some holes, and what makes
it closer is its triangulation, which continues the known faces' planes into the hole; its
refinement makes it worse (docs/candidates.md, "Session 49 (helper): CAD holes PyMeshFix
fills closer").
"""

from __future__ import annotations

import numpy as np

from surfinpaint.errors import FillError
from surfinpaint.fill.conformal.candidates import Candidates
from surfinpaint.fill.liepa.ear_cutting import ear_cut_triangulation
from surfinpaint.fill.results import Fill
from surfinpaint.fill.selfcheck import hidden_ring_scores
from surfinpaint.geometry.validation import zero_area_faces

__all__ = ["EAR_CUT", "ROUNDING", "ear_cut_fill", "ear_cut_won"]

EAR_CUT = "ear_cut"
# hidden-ring scores below this fraction of the loop's mean edge are rounding: on a hole
# every candidate rebuilds exactly, they do not decide (holdout 10's spanner #0: the λ-H
# fill's 3e-8 h against the ear cut's 2e-8 h, but the ear cut 1.9 % off the truth)
ROUNDING = 1e-6


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
    return Fill(fill.vertices, fill.faces, "fair",
                selection=f"ear cutting: its hidden-ring score {ratio:.3g}× the best "
                          f"candidate's (below {o.ear_cut_ratio:g}): the loop's "
                          "triangulation written, no new vertex")
