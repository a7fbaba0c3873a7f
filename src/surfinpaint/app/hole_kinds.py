"""The ``kind`` column of ``surfinpaint holes``: what ``fill`` does with each loop, before
its own check of the loop (:func:`~surfinpaint.fill.hole_steps.left_open`)."""

from __future__ import annotations

import numpy as np

from surfinpaint.errors import agreeing
from surfinpaint.fill.holes import Hole, percent_below
from surfinpaint.fill.islands import find_islands

__all__ = ["hole_kind", "island_kinds"]


def hole_kind(hole: Hole) -> str:
    """The ``kind`` column of ``surfinpaint holes`` (before fill's check of the hole's
    loop, :func:`~surfinpaint.fill.hole_steps.left_open`)."""
    if hole.is_border:
        return "outer border"
    if hole.spans_no_area:  # never filled: fill leaves it open with a warning
        return "spans no area (zero-area faces): left open"
    if hole.runs_along_other_loops:  # never filled either: a seam of unjoined faces
        return "runs along other loops (faces that do not join): left open"
    if hole.may_be_border:  # filled by default, with a warning
        where = ", inside its border: an inner margin?" if hole.inside_border else \
            ": the margin?"
        return f"hole (spans {percent_below(hole.span_fraction)} of its surface{where})"
    return "hole"


def island_kinds(vertices: np.ndarray, faces: np.ndarray, found: list[Hole],
                 holes: list[int], mode: str) -> dict[int, str]:
    """What ``fill`` with ``--islands mode`` does with the holes it fills (``holes``, by
    number) that hold islands (:func:`~surfinpaint.fill.islands.find_islands`) and with
    the islands' loops, by loop number: the ``kind`` column of ``surfinpaint holes``."""
    islands = find_islands(vertices, faces, found, holes)
    kinds: dict[int, str] = {}
    for hole in sorted({i.hole for i in islands}):
        held = [i for i in islands if i.hole == hole]
        joined = [i.loop for i in held if mode == "bridge" and not i.opposite]
        loops = ", ".join(str(i.loop) for i in held)
        them = agreeing(len(held), "it", "them")
        kinds[hole] = (f"hole with island {agreeing(len(held), 'loop', 'loops')} {loops}: "
                       + (f"filled with {them}" if len(joined) == len(held) else
                          "filled as a disk through or by "
                          + (f"{them} (--islands ignore)" if mode == "ignore" else
                             "those wound opposite")))
        for i in held:
            kinds[i.loop] = (f"island of hole {hole} (piece {i.piece}): "
                             + ("joined to it" if i.loop in joined else
                                "left as it is" + (" (wound opposite)" if i.opposite
                                                   else "")))
    return kinds
