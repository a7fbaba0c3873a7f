"""``surfinpaint holes``' table: each boundary loop of a mesh, and what ``fill`` with the
same options does with it, by fill's own rules."""

from __future__ import annotations

from surfinpaint.app.fill_report import nothing_to_fill
from surfinpaint.app.hole_kinds import hole_kind, island_kinds
from surfinpaint.fill import hole_steps
from surfinpaint.fill.holes import (
    find_holes,
    hole_numbers,
    over_size,
    percent_below,
    select_holes,
)
from surfinpaint.fill.seams import spanless

__all__ = ["holes_table"]


def holes_table(vertices, faces, name: str, title: str, *, holes: list[int] | None = None,
                include_border: bool = False, keep_margins: bool = False,
                max_hole_edges: int | None = None, zip_seams: bool = False,
                islands: str = "bridge") -> list:
    """Print ``surfinpaint holes``' table: each loop, and what ``fill`` with these options
    does with it (fill's own rules: ``select_holes``, ``over_size``, ``left_open``, the
    islands: :func:`~surfinpaint.fill.islands.find_islands`), under
    ``title``; for a mesh without loops, why it has none, naming it ``name``."""
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    found = find_holes(vertices, faces, validate=False)  # validated by cmd_holes
    # in fill's order: the loops it chooses (those named; else not the outer border unless
    # include_border, the margins kept open with keep_margins), then the size limit, then
    # each loop's own check
    chosen = set(hole_numbers(vertices, faces, select_holes(
        vertices, faces, holes, include_border=include_border, keep_margins=keep_margins,
        validate=False, found=found), found=found))
    unchosen = [k for k, h in enumerate(found) if k not in chosen
                and (holes is not None or not h.is_border)]
    left_open = {k: over_size(found[k].n_edges, max_hole_edges) for k in sorted(chosen)}
    # what fill's own check of each hole says (a bow-tie it would leave pinched, ...): the
    # holes it would try; the others' kind says already why they stay open
    tried = [k for k, why in left_open.items() if why is None
             and not (found[k].spans_no_area or found[k].runs_along_other_loops)]
    left_open.update(zip(tried, hole_steps.left_open(vertices, faces,
                                                     [found[k].loop for k in tried],
                                                     zip_seams=zip_seams), strict=True))
    # a loop that spans no area and is not left open is a seam fill zips (--zip-seams)
    zipped = {k for k in tried if zip_seams and left_open[k] is None
              and spanless(vertices, found[k].loop) is not None}
    kinds = island_kinds(vertices, faces, found, [k for k in chosen if left_open[k] is None],
                         islands)
    # the title on a line of its own, never wrapped: as a table title it was broken at the
    # table's width, a long path across two lines (no longer found by grep or pasted back)
    Console().print(title, soft_wrap=True, markup=False, highlight=False)
    if not found:  # no table of nothing
        Console().print(f"{name}: {nothing_to_fill(faces)}", soft_wrap=True, markup=False,
                        highlight=False)
        return found
    table = Table()
    for name in ("hole", "edges", "perimeter", "diameter", "component", "kind"):
        table.add_column(name, justify="right" if name != "kind" else "left")
    for i, h in enumerate(found):
        why = left_open.get(i)
        kind = hole_kind(h) if why is None else "left open: see below"
        if i in zipped:
            kind = "seam of duplicated vertices: zipped (--zip-seams)"
        if i in chosen and h.is_border and why is None:
            kind = f"outer border: filled ({'--holes' if holes is not None else '--all'})"
        if i in unchosen:
            kind = "left open (not in --holes)" if holes is not None else (
                f"the margin? (spans {percent_below(h.span_fraction)} of its surface): "
                "left open (--keep-margins)")
        kind = kinds.get(i, kind)
        table.add_row(str(i), str(h.n_edges), f"{h.perimeter:.4g}", f"{h.diameter:.4g}",
                      str(h.component), escape(kind))
    Console().print(table)
    for i, why in left_open.items():
        if why is not None:
            Console().print(f"hole {i}: {why}; fill skips it", soft_wrap=True, markup=False,
                            highlight=False)
    return found

