"""Fills that may have changed the surface's topology, found after the fill.

A disk glued along a hole's loop never changes the genus or the number of pieces of the
surface with its holes capped. What it can do is close a surface whose missing part was not
a disk: cut a torus's tube across and the two loops left are filled with two disks, giving a
sphere where the surface had genus 1. Nothing in the mesh with holes tells the two apart (a
torus with its tube cut across and a sphere with two holes are both cylinders); the geometry
does: the two loops face each other across a gap narrower than they are wide, each fill's
outward normal pointing at the other, and the surface around each loop is the tube's wall,
running along the fill's normal. Two holes cut into the two banks of a brain's sulcus face
each other too, but the surface around each lies across the fill, as a sheet around a hole
does. :func:`topology_changes` finds the pairs of tube ends; the pipeline warns about each.
"""

from __future__ import annotations

import numpy as np

from surfinpaint.fill.results import FillResult, TopologyChange
from surfinpaint.geometry.degenerate import triangle_rows
from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.geometry.mesh import boundary_loops
from surfinpaint.lazy import lazy_module

# imported at its first use (see fill/holes.py)
spatial = lazy_module("scipy.spatial")

__all__ = ["FACING_COSINE", "SIZE_RATIO", "TUBE_WALL_COSINE", "surface_genus",
           "topology_changes", "wall_alignment"]

# each fill's outward normal within 45 degrees of the direction to the other fill
FACING_COSINE = float(np.cos(np.radians(45.0)))
# and the smaller of the two holes at least this fraction of the larger's diameter
SIZE_RATIO = 0.5
# and the known faces next to each loop, on (area-weighted) average, more than 60 degrees from
# its fill's normal: a tube's wall, not a sheet around a hole. Measured (session 37,
# docs/robustness.md): 0.04-0.31 at the ends of a torus's tube cut across, where the two
# tests above warn; 0.68-0.99 at holes cut on both banks of a sulcus of fsaverage5's left
# pial and white surfaces (8 pairs that the two tests above took for tube ends)
TUBE_WALL_COSINE = 0.5


def surface_genus(faces: np.ndarray) -> tuple[int, int]:
    """``(genus, boundary loops)`` of one connected, orientable triangulated surface, from its
    Euler characteristic: ``V - E + F = 2 - 2 genus - loops``."""
    table = EdgeTable.build(faces)
    loops = len(boundary_loops(faces, table))
    chi = len(np.unique(faces)) - table.n_edges + len(faces)
    return (2 - chi - loops) // 2, loops


def _facing_pairs(result: FillResult, filled: np.ndarray
                  ) -> list[tuple[int, int, float, float, np.ndarray, np.ndarray]]:
    """Pairs ``(a, b, gap, sign, normal_a, normal_b)`` of reports (positions in
    ``result.reports``, among ``filled``) whose fills face each other: along the line between
    their centres, closer than the wider one is wide, of like size. ``sign`` is +1 when the
    fills' normals (as the faces are oriented) point at each other, -1 when they point away
    from each other along that line (an inward-oriented surface's tube ends); ``normal_a``,
    ``normal_b`` are the fills' area vectors. Vectorized: the fills are contiguous runs of the
    new faces, the candidate pairs come from a k-d tree."""
    counts = np.array([r.new_faces for r in result.reports], dtype=np.int64)
    corners = np.asarray(result.vertices, float)[result.faces[result.n_original_faces:]]
    area = 0.5 * np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    weight = np.linalg.norm(area, axis=1)
    starts = (np.cumsum(counts) - counts)[filled]
    normal = np.add.reduceat(area, starts, axis=0)
    total = np.maximum(np.add.reduceat(weight, starts), 1e-300)
    centre = np.add.reduceat(weight[:, None] * corners.mean(1), starts, axis=0) / total[:, None]
    diameter = np.array([result.reports[k].diameter for k in filled])
    length = np.linalg.norm(normal, axis=1)
    pairs = spatial.cKDTree(centre).query_pairs(float(np.nanmax(diameter)), output_type="ndarray")
    if len(pairs) == 0:
        return []
    a, b = pairs[:, 0], pairs[:, 1]
    offset = centre[b] - centre[a]
    gap = np.linalg.norm(offset, axis=1)
    wide = np.maximum(diameter[a], diameter[b])
    with np.errstate(invalid="ignore", divide="ignore"):
        u = offset / gap[:, None]
        ca = np.einsum("ij,ij->i", normal[a], u) / length[a]
        cb = -np.einsum("ij,ij->i", normal[b], u) / length[b]
    facing = (np.minimum(ca, cb) > FACING_COSINE) | (np.maximum(ca, cb) < -FACING_COSINE)
    keep = ((gap > 0) & (gap < wide) & (np.minimum(diameter[a], diameter[b]) >= SIZE_RATIO * wide)
            & (length[a] > 0) & (length[b] > 0) & facing)
    order = np.lexsort((b[keep], a[keep]))
    return [(int(filled[i]), int(filled[j]), float(g), 1.0 if c > 0 else -1.0, normal[i],
             normal[j])
            for i, j, g, c in zip(a[keep][order], b[keep][order], gap[keep][order],
                                  ca[keep][order], strict=True)]


def wall_alignment(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                   normal: np.ndarray) -> float:
    """How much the faces next to a hole's loop lie across the hole: the area-weighted mean
    of |cos| of the angle between their normals and ``normal`` (the hole's fill's).

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        The surface around the hole (without the fill's faces).
    loop : (k,) int array
        The hole's loop (vertex ids).
    normal : (3,) float array
        The fill's normal (any length but zero).

    Returns
    -------
    float
        In [0, 1]: near 0 where the surface around the loop runs along ``normal`` (a tube's
        wall at its cut end), near 1 where it lies across it (a sheet around a hole); 0 when
        no face of positive area touches the loop.
    """
    corners = np.asarray(vertices, float)[faces[np.isin(faces, loop).any(axis=1)]]
    area = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    weight = np.linalg.norm(area, axis=1)
    if weight.sum() <= 0:
        return 0.0
    unit = np.asarray(normal, float) / np.linalg.norm(normal)
    return float(np.abs(area @ unit).sum() / weight.sum())


def _outward(vertices: np.ndarray, faces: np.ndarray) -> bool:
    """Whether the faces of a (nearly) closed piece face outward: positive signed volume."""
    c = vertices[faces]
    return float(np.einsum("ij,ij->i", c[:, 0], np.cross(c[:, 1], c[:, 2])).sum()) >= 0


def topology_changes(result: FillResult) -> tuple[TopologyChange, ...]:
    """Pairs of filled holes that look like the two ends of a tube cut across.

    Two holes qualify when their fills face each other (each outward normal, as the
    surface's own orientation says, within 45 degrees of the direction to the other fill),
    are closer than the wider one's diameter, of like size (within a factor
    ``1 / SIZE_RATIO``), and each sits at the end of a tube: the known faces next to its
    loop run along its fill's normal (:func:`wall_alignment` below ``TUBE_WALL_COSINE``), as
    a tube's wall does and the two banks of a sulcus do not. Cost: a few operations per new
    face, and a pass over the known faces and an edge table of the pieces concerned when a
    pair qualifies.

    Returns
    -------
    tuple of TopologyChange
        Of kind "tube ends": on one piece the genus it has now and the genus it would have
        with the two ends joined; on two pieces, the count of pieces (two now, one joined).
    """
    filled = np.flatnonzero([r.outcome in ("lambda-h", "faired") and r.new_faces > 0
                             for r in result.reports])
    if len(filled) < 2:
        return ()
    vertices = np.asarray(result.vertices, float)
    pairs = _facing_pairs(result, filled)
    if not pairs:
        return ()
    triangles = triangle_rows(result.faces)[0]  # a face that repeats a vertex joins nothing
    _, label = EdgeTable.build(triangles, len(vertices)).vertex_components
    face_label = label[triangles[:, 0]]
    changes = []
    known = np.asarray(result.faces[:result.n_original_faces])
    for a, b, gap, sign, normal_a, normal_b in pairs:
        ra, rb = result.reports[a], result.reports[b]
        if max(wall_alignment(vertices, known, ra.loop, normal_a),
               wall_alignment(vertices, known, rb.loop, normal_b)) >= TUBE_WALL_COSINE:
            continue  # a sheet around either hole: two holes facing across a gap
        pieces = {int(label[ra.loop[0]]), int(label[rb.loop[0]])}
        faces = triangles[np.isin(face_label, list(pieces))]
        outward = _outward(vertices, faces)
        if (sign > 0) != outward:  # the normals point away from each other, outside
            continue
        holes = (ra.index, rb.index)
        what = (f"holes {holes[0]} and {holes[1]} face each other {gap:.3g} mesh units apart,"
                f" closer than they are wide ({max(ra.diameter, rb.diameter):.3g}): if they "
                "are the two ends of a tube cut across, filling each with a disk")
        if len(pieces) == 1:
            genus, _ = surface_genus(faces)
            change = TopologyChange(holes, "tube ends", "genus", genus + 1, genus, gap,
                                    f"{what} changed the surface's genus from {genus + 1} to "
                                    f"{genus} (the tube is closed at both ends, not rejoined)")
        else:
            change = TopologyChange(holes, "tube ends", "pieces", 1, 2, gap,
                                    f"{what} left two pieces where the tube made one (it "
                                    "is closed at both ends, not rejoined)")
        changes.append(change)
    return tuple(changes)
