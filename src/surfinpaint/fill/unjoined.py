"""Outer borders that run along other boundary edges: faces that do not join.

A file that gives each face (or each flat-shaded or textured patch) its own copies of the
vertices it shares with its neighbours, as exporters write per-face normals and texture
coordinates (assimp's ``Wuson.ply``: 3,732 faces, 11,184 vertices), is a surface only to
the eye: no two faces share an edge, every face is a piece of its own, and each piece's
loop is its outer border. trimesh does the same along a textured mesh's UV seams
(PyMeshLab's ``bunny10k_textured.obj``: 134 outer borders). Nothing is filled there, and without
a word the user read "5 holes found" and a written file (session 34).
:func:`unjoined_borders_note` says what happened and what to do.
The loops that run along other loops edge for edge are never filled
(:attr:`Hole.runs_along_other_loops`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from surfinpaint.errors import agreeing, how_many
from surfinpaint.fill.holes import Hole

__all__ = ["unjoined_borders_note"]


def unjoined_borders_note(vertices: np.ndarray, found: Sequence[Hole], *,
                          zip_seams: bool = False) -> str | None:
    """A warning's text when some outer borders run along other boundary edges.

    Parameters
    ----------
    vertices : (n, 3) float array
    found : sequence of Hole
        Every boundary loop, as :func:`~surfinpaint.fill.holes.find_holes` numbers them.
    zip_seams : bool
        Whether the fill zips seams (``--zip-seams``): the text then says that zipping does
        not join these (it pairs the two sides of one loop that runs back along itself; a
        loop along other loops has its other side in other pieces of surface).

    Returns
    -------
    str or None
        None unless an outer border (:attr:`Hole.is_border`, left open) has an edge on an
        edge of another loop (:attr:`Hole.seam_edges`): faces that meet there do not join.
        Else how many such borders and vertices there are, examples of the coincident vertex
        pairs, and how to join them (merge coincident vertices before filling).
    """
    borders = [k for k, h in enumerate(found) if h.is_border]
    unjoined = _with_seam_edges(found, borders)
    if not unjoined:
        return None
    ids = np.unique(np.concatenate([np.asarray(h.loop) for h in found]))
    _, group, counts = np.unique(vertices[ids], axis=0, return_inverse=True,
                                 return_counts=True)
    group = group.ravel()
    copied = np.zeros(len(vertices), dtype=bool)
    copied[ids[counts[group] > 1]] = True  # another boundary vertex at the same point
    # examples: the two lowest ids at each of the first points held more than once
    order = np.argsort(group, kind="stable")
    first = np.r_[True, group[order[1:]] != group[order[:-1]]]
    heads = np.flatnonzero(first[:-1] & ~first[1:])
    pairs = ", ".join(f"{int(ids[order[i]])} = {int(ids[order[i + 1]])}" for i in heads[:5])
    if len(heads) > 5:
        pairs += f" and {len(heads) - 5} more points"
    if len(unjoined) == len(borders):
        which = ("the one outer border runs" if len(borders) == 1
                 else f"all {len(borders)} outer borders run")
    else:
        which = (f"{len(unjoined)} of the {len(borders)} outer borders "
                 f"{agreeing(len(unjoined), 'runs', 'run')}")
    copies = how_many(int(copied.sum()), "boundary vertex lies", "boundary vertices lie")
    return (f"{which} along other boundary edges: {copies} exactly on another vertex (the "
            f"mesh gives faces their own "
            f"copies of the vertices they share, as exporters do with per-face normals or "
            f"texture coordinates, trimesh along texture seams and PyVista's OBJ reader at "
            f"every face; e.g. vertices {pairs}), "
            "so the faces there do not join, and those loops are taken as the surface's "
            "outer borders and left open, not filled; "
            + ("--zip-seams does not join them (it zips a loop that runs back along itself; "
               "these run along other loops, other pieces of surface); " if zip_seams else "")
            + "merge coincident vertices first "
            "(trimesh: "
            "mesh.merge_vertices(merge_tex=True, merge_norm=True); PyVista: mesh.clean(); "
            "MeshLab: Merge Close Vertices), then fill; filled from its file (surfinpaint "
            "fill, read_mesh_data), a textured OBJ keeps its seams per face corner")


def _with_seam_edges(found, chosen: list[int]) -> list[int]:
    """The holes of ``chosen`` (positions in ``found``) with an edge on another loop's
    (:attr:`Hole.seam_edges`), with one reduction over all their flags, not a call per
    hole (a triangle soup: a border a face)."""
    flagged = [k for k in chosen if found[k].seam_edges is not None]
    sizes = np.array([len(found[k].seam_edges) for k in flagged], dtype=np.int64)
    if not sizes.any():
        return []
    flags = np.concatenate([found[k].seam_edges for k in flagged])
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    seamed = np.logical_or.reduceat(flags, np.minimum(starts, len(flags) - 1)) & (sizes > 0)
    return [flagged[i] for i in np.flatnonzero(seamed).tolist()]
