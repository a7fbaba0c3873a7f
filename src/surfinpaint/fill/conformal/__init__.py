"""The conformal fill: λ and H inpainted over the hole on the patch's conformal domain, the
surface rebuilt from them, measured against the faired fills by a truth-free self-check.

| module | what |
|---|---|
| ``options`` | ``ConformalOptions``, ``GridOptions``: validated once, documented once |
| ``method`` | ``conformal_fill``: candidates → scores → verdict → the written ``Fill`` |
| ``candidates`` | the faired fills and the (lazy) λ-H fill of a hole and its test holes |
| ``selection`` | ``choose``: the pure keep-or-fall-back rule, and its ``Verdict`` |
| ``patch`` | the disk patch around a filled hole |
| ``mesh_pass`` | one λ-H pass on the patch's triangles (the default) |
| ``grid_pass`` | one λ-H pass on the paper's grid |
| ``checks`` | finite, degenerate, fold-over and intersection checks of a fill |
"""

import importlib

from surfinpaint.fill.conformal.options import ConformalOptions, GridOptions
from surfinpaint.fill.conformal.selection import Verdict, choose, sibling_test_plan

__all__ = ["ConformalOptions", "GridOptions", "Verdict", "choose", "conformal_fill",
           "sibling_test_plan"]


def __getattr__(name: str):
    # ``conformal_fill`` at its first use: the faired fill's pipeline needs the options, not
    # the λ-H fill and the representation under it (docs/scale.md, session 14)
    if name != "conformal_fill":
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = importlib.import_module("surfinpaint.fill.conformal.method").conformal_fill
    globals()[name] = value
    return value
