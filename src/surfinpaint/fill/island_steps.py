"""Holes with islands in :func:`surfinpaint.fill_holes`: which holes are filled with their
islands (``islands="bridge"``, the default) and the warnings for the others, and the one
step that fills such a hole (:func:`fill_with_islands`), in the serial order of the holes.

An island is never deleted and never left out silently: with ``islands="ignore"``, or when
it cannot be joined (wound opposite to the surface around the hole, its loop refused, the
fill failing), the hole is filled as a disk, as without islands, with a warning naming the
hole and the island's piece.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from surfinpaint.errors import NUMERICAL_ERRORS, agreeing
from surfinpaint.fill.annulus import annulus_fill
from surfinpaint.fill.hole_steps import (
    FAIR_NEIGHBOURHOOD_RINGS,
    Run,
    fill_hole,
    loop_problem,
    stitched,
    warn_at_caller,
)
from surfinpaint.fill.islands import Island
from surfinpaint.fill.neighbourhood import FilledMesh, Local, zero_area_reason
from surfinpaint.fill.parallel import crossing_triangles
from surfinpaint.fill.results import Fill, HoleReport
from surfinpaint.geometry.intersection import self_intersections
from surfinpaint.io.base import MeshWarning

__all__ = ["ISLAND_FAIR_ORDER", "fill_with_islands", "island_note", "joined_islands"]

# fairing order of a hole with islands when the caller sets none, by the method asked for:
# "fair" keeps its baseline's order 2; for "conformal", order 3 measured closer to the truth
# on 3 of 4 tuning-side cases (0.78-0.88x order 2's distance; 1.13x on a noisy scan:
# docs/robustness.md, "Session 37 (helper): holes with islands")
ISLAND_FAIR_ORDER = {"conformal": 3, "fair": 2}


def island_note(islands: list[Island]) -> str:
    """``with its island, piece 1 (loop 3)``: the note of a hole filled with its islands."""
    named = ", ".join(f"piece {i.piece} (loop {i.loop})" for i in islands)
    return f"with its {agreeing(len(islands), 'island', 'islands')}, {named}"


def _not_joined(island: Island, why: str) -> str:
    return (f"hole {island.hole}: piece {island.piece} (loop {island.loop}) lies inside it, "
            f"an island; {why}: the hole is filled as a disk through or by it, the island "
            "left as it is")


def joined_islands(islands: list[Island], reports: list[HoleReport], todo: list[HoleReport],
                   mode: str) -> tuple[list[HoleReport], dict[int, list[Island]]]:
    """The holes of ``todo`` to fill with their islands, and the holes left to fill.

    With ``mode`` "ignore", or for an island wound opposite to the surface around its
    hole, a warning says the hole is filled as a disk through or by the island. An island
    whose own loop was chosen too (``include_border``, ``holes=``) is reported as joined
    to its hole and not filled on its own (its report says so).

    Returns
    -------
    todo : list of HoleReport
        ``todo`` less the islands' own loops joined to their holes.
    joined : dict
        Hole number -> the islands joined to it.
    """
    filled = {r.index for r in todo}
    joined: dict[int, list[Island]] = {}
    for island in islands:
        if island.hole not in filled:
            continue
        if mode == "ignore":
            warn_at_caller(_not_joined(island, "islands='ignore' (--islands ignore)"),
                           MeshWarning)
        elif island.opposite:
            warn_at_caller(_not_joined(island, "its faces are wound opposite to the surface "
                                       "around the hole (flip them to join it)"), MeshWarning)
        else:
            joined.setdefault(island.hole, []).append(island)
    loops = {i.loop: i.hole for held in joined.values() for i in held}
    for report in reports:
        if report.index in loops:
            report.method = "none"
            report.skipped = (f"the island of hole {loops[report.index]}: filled with it "
                              "(its loop joined to the hole's)")
    return [r for r in todo if r.index not in loops], joined


def _crossing(local: Local, loops: np.ndarray, fill: Fill) -> int:
    """How many triangles of ``fill`` cross the surface around its loops
    (:func:`~surfinpaint.fill.parallel.crossing_triangles`) or one another (each once)."""
    positions = np.concatenate([local.vertices, fill.vertices])
    pairs = self_intersections(positions, fill.faces)
    return len(np.union1d(crossing_triangles(local.vertices, local.faces, loops, fill),
                          pairs))


def _annulus(local: Local, loops: list[np.ndarray], order: int) -> tuple[Fill | None, str]:
    """The fill of the hole with its islands (``loops``: the hole's, then the islands', in
    ``local``'s ids) at ``order``, else at order 2 where that one crosses the surface or
    itself (:func:`_crossing`); None and why when every order does or the fill fails."""
    tried = []
    for attempt in dict.fromkeys((order, 2)):
        try:
            new_v, new_f, used = annulus_fill(local.vertices, local.faces, loops[0], loops[1:],
                                              attempt)
        except NUMERICAL_ERRORS as exc:
            return None, str(exc)
        made = Fill(new_v, new_f, "fair", fair_order=used)
        crossing = _crossing(local, np.concatenate(loops), made)
        if not crossing:
            return made, ""
        tried.append(f"{crossing} at order {used}")
    return None, ("its fill's triangles cross the surface around the loops or one another: "
                  + ", ".join(tried))


def fill_with_islands(mesh: FilledMesh, report: HoleReport, run: Run,
                      islands: list[Island]) -> None:
    """Fill the hole of ``report`` with its ``islands`` (:func:`~surfinpaint.fill.annulus.
    annulus_fill`: a faired fill, reported with the note :func:`island_note`); where that
    cannot be done, or every fill made crosses the surface (the loops of a folded surface,
    a brain's), a warning and the hole filled as a disk (:func:`fill_hole`)."""
    started = time.perf_counter()
    inners = [i.loop_vertices for i in islands]
    local = mesh.cut(np.concatenate([report.loop, *inners]), FAIR_NEIGHBOURHOOD_RINGS)
    problem = loop_problem(dataclasses.replace(local, loop=report.loop), report.index,
                           run.explicit)
    made = None
    if problem is None:
        made, problem = _annulus(local, [np.searchsorted(local.ids, loop)
                                         for loop in (report.loop, *inners)],
                                 run.fair_order or ISLAND_FAIR_ORDER[run.method])
        problem = problem or zero_area_reason(local.vertices, made)
    if problem:
        for island in islands:
            warn_at_caller(_not_joined(island, f"it could not be joined ({problem})"),
                           MeshWarning)
        fill_hole(mesh, report, run)
        return
    stitched(mesh, report, local.ids, made, None, started)
    report.islands = tuple(i.loop for i in islands)
    report.note = "; ".join(n for n in (island_note(islands), report.note) if n)
