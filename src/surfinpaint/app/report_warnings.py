"""The warnings of ``surfinpaint report``'s two fills of its holes, the conventional
(comparison) fill and the conformal fill ``surfinpaint fill`` writes: each said once, saying
which fill it came from (:func:`fills_warnings`)."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence

from surfinpaint.errors import HoleWarning
from surfinpaint.fill.results import HoleReport

__all__ = ["CONFORMAL_FILL", "CONVENTIONAL_FILL", "fills_warnings", "said_once"]

#: What follows a warning of one fill only, saying which (the panels' names for them).
CONFORMAL_FILL, CONVENTIONAL_FILL = " (conformal fill)", " (conventional fill)"


def said_once(caught: Iterable, reports: Sequence[HoleReport]) -> dict[str, type[Warning]]:
    """The warnings ``caught`` during one fill, each text once in the order the fill said
    them, with its category; and a :class:`~surfinpaint.errors.HoleWarning` for each hole
    of ``reports`` skipped without a warning of its own."""
    said: dict[str, type[Warning]] = {}
    for w in caught:
        said.setdefault(str(w.message), w.category)
    for r in reports:
        if r.skipped:
            said.setdefault(f"hole {r.index}: {r.skipped}; skipped", HoleWarning)
    return said


def fills_warnings(conformal: Mapping[str, type[Warning]],
                   conventional: Mapping[str, type[Warning]]) -> dict[str, type[Warning]]:
    """Each warning of the two fills (:func:`said_once` of each) once, with its category,
    saying which fill it came from.

    A warning both fills gave is said as it is: most are of the mesh (a degenerate face,
    what ``--repair`` did), said by each fill alike, or of a hole both fill alike (an
    island ``--islands ignore`` leaves). One of the conformal fill only is followed by
    :data:`CONFORMAL_FILL`, one of the conventional fill only by :data:`CONVENTIONAL_FILL`;
    the conformal fill's first, in the order said, then the conventional fill's. A
    conventional fill's :class:`~surfinpaint.errors.HoleWarning` is said as a
    ``UserWarning``: ``report`` leaves a ``HoleWarning`` to the hole's title where the
    titles are printed, and a title says what the conformal fill wrote only."""
    said = {text if text in conventional else text + CONFORMAL_FILL: category
            for text, category in conformal.items()}
    for text, category in conventional.items():
        if text not in conformal:
            said[text + CONVENTIONAL_FILL] = (UserWarning if issubclass(category, HoleWarning)
                                              else category)
    return said
