"""Per-face and per-corner attributes of filled holes: values for the faces a fill added.

Face data are copied from the original faces across the loop, never interpolated (a
material id or a face colour continues into the hole), by the random-walker rule of
:func:`surfinpaint.fill.attributes.inpaint_labels` on the fill's dual graph; an id array
(``vtkOriginalCellIds``: the ``"id"`` kind of :func:`~surfinpaint.fill.attributes.
attribute_kind`) gives the new faces the none id instead.

Corner data (``(f, 3, k)``: values that may differ between the faces around a vertex, such as
texture coordinates at a UV seam) are continued in the chart the hole's loop lies in: the
patch's faces joined to the faces along the loop across edges without a seam; each vertex
with one value on all its corners in that chart is known, and the new vertices' values are
inpainted from them like a per-vertex attribute (a seam elsewhere in the patch is no
obstacle). Where seams cut the loop into runs of different charts, the seam is continued
across the hole instead (:mod:`surfinpaint.fill.seam_charts`): the new faces are split among
the runs and each part takes its own run's chart, continued only over its share of the
hole, so each part draws texels from its own chart, not from across the seam. Where that is
not possible (a seam that meets the loop once) or mirrors more new faces, the chart along
most of the loop is continued across the hole (its values extrapolated to the other loop
vertices), with a warning. Only where no face along the loop has a value (NaN) do the new
corners get none. Texture coordinates (two channels) that fold (a new face mirrored against
the chart) are placed again by the mean-value map (:func:`_unfolded_uv`). Normals per corner
(hard edges) are the filled surface's, as per vertex: a loop vertex with one normal keeps it
on the new corners (smooth shading continues), the others take the surface's unit normal.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping

import numpy as np

from surfinpaint.fill.attributes import (
    HoleDomain,
    attribute_kind,
    attribute_rows,
    channel_ranges,
    hole_blocks,
    hole_domain,
    inpaint_values,
)
from surfinpaint.fill.ids import none_ids
from surfinpaint.fill.seam_charts import (
    chart_labels,
    labels_across_loop,
    single_values,
    split_at_seams,
)
from surfinpaint.geometry.mean_value import convex_combination, mean_value_weights
from surfinpaint.geometry.mesh import vertex_normals
from surfinpaint.geometry.parameterization import signed_areas
from surfinpaint.io.base import MeshWarning

__all__ = ["fill_corner_attributes", "fill_face_attributes", "fill_result_corner_attributes",
           "fill_result_face_attributes"]


def fill_face_attributes(
    vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, fill_faces: np.ndarray,
    face_attributes: Mapping[str, np.ndarray], kinds: Mapping[str, str] | None = None,
) -> dict[str, np.ndarray]:
    """Values of every per-face attribute at the faces a fill added to one hole.

    Rule: face data are copied, never interpolated (a material id or a face colour continues
    from across the loop). Each new face takes the value, among those of the original faces
    across the loop, whose harmonic indicator on the fill's dual graph is largest: the
    random-walker rule of :func:`~surfinpaint.fill.attributes.inpaint_labels` on faces
    (nodes the fill's faces and the original faces touching the loop, joined across shared
    edges with weight edge length over centroid distance), so every value's region among
    the new faces is connected to the faces across the loop that carry it. An id array
    (kind ``"id"`` by :func:`~surfinpaint.fill.attributes.attribute_kind` or ``kinds``)
    gives every new face the none id (:func:`surfinpaint.fill.ids.none_id`).

    Parameters
    ----------
    vertices : (n, 3) float array
        The filled mesh's positions.
    faces : (f, 3) int array
        The original faces; ``face_attributes`` rows follow them.
    loop : (k,) int array
    fill_faces : (m, 3) int array
    face_attributes : mapping of name to (f,) or (f, c) array
    kinds : mapping of name to kind, optional
        ``"id"`` makes an array an id array; any other kind copies (the default by name).

    Returns
    -------
    dict of name to (m,) or (m, c) array
    """
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    fill_faces = np.asarray(fill_faces, dtype=np.int64).reshape(-1, 3)
    arrays = {name: attribute_rows(name, a, (len(faces),), "faces")
              for name, a in face_attributes.items()}
    kinds = dict(kinds or {})
    ids = {name for name, a in arrays.items()
           if kinds.get(name, attribute_kind(name, a)) == "id"}
    if len(fill_faces) == 0 or not arrays:
        return {name: a[:0] for name, a in arrays.items()}
    out = {name: none_ids(arrays[name], len(fill_faces)) for name in ids}
    copied = {name: a for name, a in arrays.items() if name not in ids}
    if not copied:
        return out
    on_loop = np.zeros(len(vertices), dtype=bool)
    on_loop[np.asarray(loop, dtype=np.int64)] = True
    touching = np.flatnonzero(on_loop[faces].any(axis=1))
    found = labels_across_loop(vertices, faces[touching], fill_faces,
                               [values[touching] for values in copied.values()])
    out.update(zip(copied, found, strict=True))
    return {name: out[name] for name in arrays}


def fill_result_face_attributes(
    result, face_attributes: Mapping[str, np.ndarray], kinds: Mapping[str, str] | None = None,
) -> dict[str, np.ndarray]:
    """Every per-face attribute over a whole filled mesh: the original faces' values, then
    the new faces' by :func:`fill_face_attributes`.

    Parameters
    ----------
    result : FillResult
    face_attributes : mapping of name to (f, ...) array
        One row per input face; with ``repair=True`` the rows of ``result.removed_faces``
        are dropped, as the faces were.
    kinds : mapping of name to kind, optional
        See :func:`fill_face_attributes`.

    Returns
    -------
    dict of name to (len(result.faces), ...) array.
    """
    n_input = result.n_original_faces + len(result.removed_faces)
    keep = np.ones(n_input, dtype=bool)
    keep[result.removed_faces] = False
    originals = {name: attribute_rows(name, a, (n_input,), "faces")[keep]
                 for name, a in face_attributes.items()}
    faces = result.faces[: result.n_original_faces]
    parts: dict[str, list[np.ndarray]] = {name: [a] for name, a in originals.items()}
    for report, _, face_ids, near in hole_blocks(result, 1 if originals else 0):
        if len(face_ids) == 0 or not originals:
            continue
        filled = fill_face_attributes(result.vertices, faces[near], report.loop,
                                      result.faces[face_ids],
                                      {name: a[near] for name, a in originals.items()},
                                      kinds)
        for name, values in filled.items():
            parts[name].append(values)
    return {name: np.concatenate(blocks) for name, blocks in parts.items()}


def _chart_faces(faces: np.ndarray, values: np.ndarray, loop: np.ndarray
                 ) -> tuple[np.ndarray, int, int] | None:
    """The faces of the chart the hole's loop lies in: those joined to the faces along the
    loop across edges whose two ends have the same value in both faces (a UV seam cuts the
    patch into charts). Where a seam reaches the loop, the chart along most of the loop's
    edges. None when no face along the loop has all its values (NaN: none given).

    Parameters
    ----------
    faces : (p, 3) int array
    values : (p, 3, k) float array
        Each face's corner values.
    loop : (q,) int array

    Returns
    -------
    chart : (c,) int array
        Ids of the chart's faces.
    edges, loop_edges : int
        The loop's edges along the chart's faces, and all the loop's edges.
    """
    chart = chart_labels(faces, values)
    corner_edges = np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2)
    owner = np.repeat(np.arange(len(faces)), 3)
    key = np.sort(corner_edges, axis=1)
    loop = np.asarray(loop, dtype=np.int64)
    size = int(max(faces.max(), loop.max())) + 1
    loop_keys = np.sort(np.stack([loop, np.roll(loop, -1)], axis=1), axis=1) @ [size, 1]
    along = chart[owner[np.isin(key @ [size, 1], loop_keys)]]  # one a loop edge
    along = along[along >= 0]
    if len(along) == 0:
        return None
    charts, counts = np.unique(along, return_counts=True)
    return (np.flatnonzero(chart == charts[np.argmax(counts)]), int(counts.max()),
            len(loop))


def _corner_normals(vertices: np.ndarray, dom: HoleDomain, known: np.ndarray,
                    ring_faces: np.ndarray, values: np.ndarray,
                    fill_faces: np.ndarray) -> np.ndarray:
    """Normals for the new faces' corners, the per-vertex rule's: at a loop vertex with one
    normal on all its corners in the patch, that normal (smooth shading continues); elsewhere
    (new vertices, a hard edge through the loop vertex) the filled surface's area-weighted
    unit normal, pointing the way the given normals point."""
    normals = vertex_normals(vertices[dom.ids], dom.faces)
    corner_vertex = ring_faces.ravel()
    given = values.reshape(-1, 3)
    finite = np.isfinite(given).all(axis=1)
    if np.einsum("ij,ij->", normals[corner_vertex[finite]], given[finite]) < 0:
        normals = -normals
    low = np.full((len(dom.ids), 3), np.inf)
    high = np.full((len(dom.ids), 3), -np.inf)
    np.minimum.at(low, corner_vertex, given)
    np.maximum.at(high, corner_vertex, given)
    single = known & np.all(low == high, axis=1)
    out = np.where(single[:, None], low, normals)
    return out[fill_faces]


def _unfolded_uv(dom: HoleDomain, new: np.ndarray, uv: np.ndarray, chart_uv: np.ndarray,
                 fill_faces: np.ndarray) -> tuple[np.ndarray, int]:
    """The inpainted UVs ``uv`` of a patch, or, where they fold (a new face's UV triangle
    oriented against the majority of the chart's faces: texels drawn mirrored), the new
    values placed again by Floater's mean-value map from the same data: each a
    combination of its neighbours with positive weights (on the patch's domain), which folds
    nothing inside a convex loop (Floater 2003) and seldom inside another. The biharmonic
    UVs are kept unless that folds fewer new faces.

    Parameters
    ----------
    dom : HoleDomain
    new : (k,) bool array
        The patch's vertices without data (the new ones; loop vertices on a seam).
    uv : (k, 2) float array
        Inpainted values of the patch's vertices.
    chart_uv : (c, 3, 2) float array
        The corners of the chart's faces.
    fill_faces : (m, 3) int array
        The new faces, in patch ids.

    Returns
    -------
    uv : (k, 2) float array
    mirrored : int
        The new faces ``uv`` mirrors.
    """
    corners = np.arange(3 * len(chart_uv)).reshape(-1, 3)
    sign = np.sign(np.sign(signed_areas(corners, chart_uv.reshape(-1, 2))).sum())
    folded = int((signed_areas(fill_faces, uv) * sign < 0).sum())
    if sign == 0 or folded == 0:
        return uv, folded
    placed = uv.copy()
    convex_combination(mean_value_weights(dom.domain, dom.faces), placed, np.flatnonzero(new))
    again = int((signed_areas(fill_faces, placed) * sign < 0).sum())
    return (placed, again) if again < folded else (uv, folded)


def fill_corner_attributes(
    vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, fill_faces: np.ndarray,
    new_ids: np.ndarray, corner_attributes: Mapping[str, np.ndarray], *, rings: int = 3,
    hole: int | None = None,
) -> dict[str, np.ndarray]:
    """Values of every per-corner attribute at the corners of the faces a fill added.

    Rule (see the module docstring): normals (a float ``(f, 3, 3)`` array named like one,
    :func:`~surfinpaint.fill.attributes.attribute_kind`) are the surface's, as per vertex
    (:func:`_corner_normals`); other values are inpainted biharmonically over the new
    vertices from the corners of the chart the loop lies in (:func:`_chart_faces`: a seam
    elsewhere in the patch is no obstacle) and clamped to the attribute's range; where
    seams cut the loop into runs of different charts, the new faces are split among them
    (:func:`~surfinpaint.fill.seam_charts.split_at_seams`) unless that mirrors more new
    faces than the one chart along most of the loop, which is then continued with a
    warning; NaN with a warning where no face along the loop has a value.

    Parameters
    ----------
    vertices, faces, loop, fill_faces, new_ids :
        As for :func:`surfinpaint.fill.attributes.fill_hole_attributes`.
    corner_attributes : mapping of name to (f, 3, k) float array
        One row per original face.
    rings : int
    hole : int, optional
        The hole's number, for the warning.

    Returns
    -------
    dict of name to (m, 3, k) float array
    """
    vertices = np.asarray(vertices, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    fill_faces = np.asarray(fill_faces, dtype=np.int64).reshape(-1, 3)
    arrays = {name: attribute_rows(name, a, (len(faces),), "faces")
              for name, a in corner_attributes.items()}
    if not arrays or len(fill_faces) == 0:
        return {name: np.empty((len(fill_faces), 3, a.shape[2])) for name, a in arrays.items()}
    dom = hole_domain(vertices, faces, loop, fill_faces, rings)
    in_patch = np.zeros(len(vertices), dtype=bool)
    in_patch[dom.ids] = True
    ring = in_patch[faces].all(axis=1)
    ring_faces = np.searchsorted(dom.ids, faces[ring])
    known = ~np.isin(dom.ids, new_ids)
    local_fill = np.searchsorted(dom.ids, fill_faces)
    loop_local = np.searchsorted(dom.ids, loop)
    out = {name: np.full((len(fill_faces), 3, a.shape[2]), np.nan) for name, a in arrays.items()}
    for name, a in arrays.items():
        k = a.shape[2]
        values = np.asarray(a, dtype=float)[ring]
        if k == 3 and attribute_kind(name, values[:, 0]) == "normal":
            out[name] = _corner_normals(vertices, dom, known, ring_faces, values,
                                        local_fill).astype(a.dtype)
            continue
        found = _chart_faces(ring_faces, values, loop_local)
        if found is not None:
            chart, edges, loop_edges = found
            single, low = single_values(len(dom.ids), ring_faces[chart], values[chart])
        if found is None or not single.any():
            warnings.warn(f"hole {'' if hole is None else hole}: corner attribute {name!r} "
                          "has no value along the hole's loop: its new faces' corners get "
                          "none (NaN)", MeshWarning, stacklevel=3)
            continue
        seamed = edges < loop_edges or not single[loop_local].all()
        split = (split_at_seams(vertices[dom.ids], dom.domain, dom.faces, ring_faces, values,
                                loop_local, local_fill) if seamed else None)
        if split is not None and split[1] == 0:
            out[name] = split[0].astype(a.dtype)  # the seam continued across the hole
            continue
        filled = inpaint_values(dom.domain, dom.faces, single, low)
        limits = channel_ranges(values.reshape(-1, k))
        filled = np.clip(filled, limits[0], limits[1])
        mirrored = 0
        if k == 2:  # texture coordinates: a new face drawn mirrored is a visible flaw
            filled, mirrored = _unfolded_uv(dom, ~single, filled, values[chart], local_fill)
        if split is not None and split[1] <= mirrored:
            out[name] = split[0].astype(a.dtype)
            continue
        if seamed:
            warnings.warn(f"hole {'' if hole is None else hole}: a seam of corner attribute "
                          f"{name!r} reaches the hole's loop: the new faces' values continue "
                          f"the chart along {edges} of its {loop_edges} edges across the hole "
                          "(the seam runs on along the others)", MeshWarning, stacklevel=3)
        out[name] = filled[local_fill].astype(a.dtype)
    return out


def fill_result_corner_attributes(
    result, corner_attributes: Mapping[str, np.ndarray], *, rings: int = 3,
) -> dict[str, np.ndarray]:
    """Every per-corner attribute over a whole filled mesh: the original faces' corners,
    then the new faces' by :func:`fill_corner_attributes`.

    Parameters
    ----------
    result : FillResult
    corner_attributes : mapping of name to (f, 3, k) float array
        One row per input face (rows of ``result.removed_faces`` dropped; the corners of
        ``result.flipped_faces`` swapped as their last two vertices were).

    Returns
    -------
    dict of name to (len(result.faces), 3, k) array.
    """
    n_input = result.n_original_faces + len(result.removed_faces)
    keep = np.ones(n_input, dtype=bool)
    keep[result.removed_faces] = False
    flipped = np.cumsum(keep)[result.flipped_faces] - 1  # ids among the faces kept
    originals = {}
    for name, a in corner_attributes.items():
        a = attribute_rows(name, a, (n_input,), "faces")
        if a.ndim != 3 or a.shape[1] != 3 or a.dtype.kind != "f":
            raise ValueError(f"corner attribute {name!r} must be a float (f, 3, k) array, "
                             f"got {a.dtype} {a.shape}")
        a = a[keep]
        a[flipped] = a[flipped][:, [0, 2, 1]]  # a flipped face's corners follow its vertices
        originals[name] = a
    faces = result.faces[: result.n_original_faces]
    parts: dict[str, list[np.ndarray]] = {name: [a] for name, a in originals.items()}
    for report, new_ids, face_ids, near in hole_blocks(result, rings if originals else 0):
        if len(face_ids) == 0 or not originals:
            continue
        filled = fill_corner_attributes(result.vertices, faces[near], report.loop,
                                        result.faces[face_ids], new_ids,
                                        {name: a[near] for name, a in originals.items()},
                                        rings=rings, hole=report.index)
        for name, values in filled.items():
            parts[name].append(values)
    return {name: np.concatenate(blocks) for name, blocks in parts.items()}
