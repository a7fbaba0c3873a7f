"""Boundary loops that span no area: slits and seams.

A *slit* is a boundary loop that runs along a curve and back along the same curve, so that it
bounds no surface: a cut made by duplicating vertices, a zero-width crack, a T-junction (an
edge split on one side only). A *seam* is a slit whose two sides pair up vertex for vertex,
each vertex with a coincident partner: what an exporter writes along a texture (UV) seam when
it gives each side its own copy of the vertices (common in OBJ files converted from formats
with per-vertex texture coordinates).

No fill of such a loop is a surface: the triangles that close it are a sheet folded onto
itself (pairs of coincident faces) on a curved surface, zero-area triangles on a flat one
(where the faired fill's linear system is singular). So :func:`surfinpaint.fill_holes` never
fills one. By default it leaves the loop open and says so in a
:class:`~surfinpaint.MeshWarning` naming the hole. With ``zip_seams=True`` (``--zip-seams``)
it *zips* a seam instead: the faces that use a duplicate vertex use its coincident partner
(the smaller id: the one first in the file) instead, so the surface comes out closed along
the seam, which is what a mesh with a UV seam should be.

Zipping is the one change :func:`~surfinpaint.fill_holes` makes to the original faces, which
is why it is not the default: the vertex array stays as it was (every original vertex kept,
unmoved and in its place, so vertex ids and per-vertex data keep their meaning), but the
duplicates are no longer used by any face, and a per-vertex value that differed between the
two copies (a texture coordinate) is then the kept copy's on both sides. A slit whose sides
do not pair up (a T-junction) cannot be zipped without moving vertices, and is always left
open with a warning.

Both tests are scale-free: two points coincide when they are closer than ``SLIT_RTOL`` times
the length of the loop edges at them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from surfinpaint.errors import HoleWarning, how_many
from surfinpaint.io.base import MeshWarning
from surfinpaint.lazy import lazy_module

# imported at its first use (see fill/holes.py)
spatial = lazy_module("scipy.spatial")

__all__ = ["ALONG_OTHER_LOOPS", "ALONG_OTHER_LOOPS_NOT_ZIPPED", "NO_AREA_FACES", "SLIT_RTOL",
           "SEAM_LEFT_OPEN", "Slit", "SlitWarning", "find_seam_part", "find_slit", "spanless",
           "zip_faces", "zip_or_leave"]

# two loop points closer than this fraction of the neighbouring loop edges' length coincide
# (an exporter's duplicates are bit-identical; this leaves room for printed decimals)
SLIT_RTOL = 1e-3
# why a loop of a piece of surface whose faces all have zero area (Hole.spans_no_area: a
# stray collinear triangle) is left open: it spans no area, like a slit, whatever its shape
NO_AREA_FACES = ("the loop spans no area: every face of its piece of surface has zero area "
                 "(collinear or coincident corners), so it is no hole to fill")
# why a loop that runs along other boundary loops edge for edge (Hole.runs_along_other_loops:
# trimesh's split of a textured mesh along its UV seams) is left open: filling it would lay
# a second sheet of faces on the surface across the seam
ALONG_OTHER_LOOPS = ("every edge of the loop lies exactly on another boundary edge: a seam "
                     "between faces that do not join (their own copies of the vertices they "
                     "share), not a hole, so it is left open; merge coincident vertices first "
                     "(trimesh: mesh.merge_vertices(merge_tex=True, merge_norm=True)) to "
                     "join them")
# what zip_seams=True adds: zipping pairs the two sides of one loop; this loop's other side
# is other loops (each face or patch with its own vertices), which zipping never joins
ALONG_OTHER_LOOPS_NOT_ZIPPED = (
    "every edge of the loop lies exactly on another boundary edge: a seam between faces that "
    "do not join (their own copies of the vertices they share), not a hole, so it is left "
    "open; --zip-seams (zip_seams=True) does not join it: it zips a loop that runs back "
    "along itself, and this one runs along other loops (the faces across it are other "
    "pieces of surface); merge coincident vertices first (trimesh: "
    "mesh.merge_vertices(merge_tex=True, merge_norm=True)) to join them")
# what a seam not zipped (zip_seams False) is told
SEAM_LEFT_OPEN = "; left open (zip_seams=True, or --zip-seams, closes it)"
# where along each loop edge the slit test checks that it lies on another edge of the loop
_SAMPLES = np.array([0.25, 0.5, 0.75])


class SlitWarning(HoleWarning, MeshWarning):
    """A hole left open because its loop spans no area: a warning about the mesh
    (:class:`~surfinpaint.MeshWarning`) and about one hole (:class:`~surfinpaint.errors.
    HoleWarning`: ``surfinpaint fill`` says it in that hole's lines)."""


@dataclass(frozen=True)
class Slit:
    """A boundary loop that spans no area.

    Attributes
    ----------
    merges : (m, 2) int array
        ``(duplicate, kept)`` vertex-id pairs that zip it (the two coincident vertices of
        each pair; the kept one is the smaller id); empty when its sides do not pair up
        vertex for vertex (then it cannot be zipped).
    """

    merges: np.ndarray

    @property
    def is_seam(self) -> bool:
        """Whether its sides pair up, so that it can be zipped."""
        return len(self.merges) > 0

    def describe(self) -> str:
        """What the loop is, in words."""
        if self.is_seam:
            pairs = how_many(len(self.merges), "coincident vertex pair",
                             "coincident vertex pairs")
            return f"the loop spans no area: a seam of {pairs} (duplicated vertices)"
        return ("the loop spans no area: a slit whose two sides coincide but do not pair up "
                "vertex for vertex (a T-junction)")


def _segment_distances(points: np.ndarray, starts: np.ndarray, vectors: np.ndarray
                       ) -> np.ndarray:
    """Distance from each of ``points`` to the matching segment ``starts + t vectors``."""
    length2 = np.einsum("ij,ij->i", vectors, vectors)
    t = np.einsum("ij,ij->i", points - starts, vectors) / np.where(length2 > 0, length2, 1.0)
    nearest = starts + np.clip(t, 0.0, 1.0)[:, None] * vectors
    return np.linalg.norm(points - nearest, axis=1)


def _lies_on_itself(p: np.ndarray, e: np.ndarray, h: np.ndarray, rtol: float) -> bool:
    """Whether every loop edge lies on other edges of the loop (``p``: its points, ``e``:
    its edge vectors, ``h``: their lengths): checked at ``_SAMPLES`` along each edge."""
    n = len(p)
    samples = (p[:, None, :] + _SAMPLES[None, :, None] * e[:, None, :]).reshape(-1, 3)
    owner = np.repeat(np.arange(n), len(_SAMPLES))
    # an edge within rtol h of a sample has its midpoint within half the longest edge of it
    tree = spatial.cKDTree(p + 0.5 * e)
    near = tree.query_ball_point(samples, 0.5 * h.max() * (1 + 2 * rtol))
    counts = np.fromiter((len(c) for c in near), dtype=np.int64, count=len(samples))
    if (counts == 0).any():
        return False
    sample = np.repeat(np.arange(len(samples)), counts)
    edge = np.fromiter((k for c in near for k in c), dtype=np.int64, count=counts.sum())
    other = edge != owner[sample]
    sample, edge = sample[other], edge[other]
    d = np.full(len(samples), np.inf)
    np.minimum.at(d, sample, _segment_distances(samples[sample], p[edge], e[edge]))
    return bool((d <= rtol * h[owner]).all())


def _glued(p: np.ndarray, h: np.ndarray, rtol: float
           ) -> tuple[np.ndarray, np.ndarray] | None:
    """For each loop position the position of its coincident partner (-1: none, e.g. a tip
    of a seam), and which loop edges have their reversed copy in the loop (between the
    partners of their ends); None when the partners do not pair up (three coincident
    vertices, or a partner that pairs elsewhere)."""
    n = len(p)
    dist, nearest = spatial.cKDTree(p).query(p, k=2)
    # the nearest point is the vertex itself unless another lies on it exactly
    itself = nearest[:, 0] == np.arange(n)
    other = np.where(itself, nearest[:, 1], nearest[:, 0])
    other_dist = np.where(itself, dist[:, 1], dist[:, 0])
    local = np.minimum(h, np.roll(h, 1))
    partner = np.where(other_dist <= rtol * local, other, -1)
    has = partner >= 0
    if not (partner[partner[has]] == np.flatnonzero(has)).all():
        return None
    i = np.arange(n)
    ahead, after = (i + 1) % n, (i + 2) % n
    # edge (i, i+1) reversed: (i+1, i+2) folding back at a tip i+1, or (partner(i+1),
    # partner(i+1)+1) ending at i (the other side passes through i) or at partner(i)
    folds_back = partner == after
    back = np.where(partner[ahead] >= 0, (partner[ahead] + 1) % n, -2)
    along = (back == i) | ((back == partner) & has)
    return partner, folds_back | along


def _pairs(loop: np.ndarray, partner: np.ndarray, positions: np.ndarray) -> np.ndarray:
    """``(duplicate, kept)`` vertex-id pairs of the partnered ``positions``."""
    positions = positions[partner[positions] >= 0]
    pairs = np.column_stack([loop[positions], loop[partner[positions]]])
    return np.unique(np.column_stack([pairs.max(axis=1), pairs.min(axis=1)]), axis=0)


def find_seam_part(vertices: np.ndarray, loop: np.ndarray, rtol: float = SLIT_RTOL
                   ) -> np.ndarray | None:
    """The ``(duplicate, kept)`` pairs of a seam that makes up part of a loop (None: none).

    A loop that bounds a surface can still run back along itself over some of its edges: an
    open tube whose seam has duplicated vertices has one boundary loop, the two rims joined
    by the seam's two sides. Such a loop is no hole (no disk fills it); zipping its seam
    leaves the rest of it (the rims) open. At least two consecutive glued edges are asked
    for, so that a loop merely touching itself at one point is not taken for a seam.
    """
    loop = np.asarray(loop, dtype=np.int64)
    p = np.asarray(vertices, dtype=np.float64)[loop]
    p = p - p.mean(axis=0)
    scale = np.abs(p).max()
    if len(loop) < 4 or scale == 0:
        return None
    p = p / scale
    h = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)
    found = _glued(p, h, rtol)
    if found is None:
        return None
    partner, glued = found
    if glued.all() or not (glued & np.roll(glued, -1)).any():
        return None  # a whole slit (find_slit), or no run of two glued edges
    ends = np.flatnonzero(glued)
    return _pairs(loop, partner, np.unique(np.concatenate([ends, (ends + 1) % len(loop)])))


def find_slit(vertices: np.ndarray, loop: np.ndarray, rtol: float = SLIT_RTOL
              ) -> Slit | None:
    """The loop as a :class:`Slit` when it spans no area (None: it bounds a surface).

    A loop spans no area when every one of its edges lies on another of its edges (within
    ``rtol`` times the edge's length); it is a seam when every edge's reversed copy is a
    loop edge between the coincident partners of its ends. Cost O(k log k) for a loop of
    ``k`` vertices; the loops that bound a surface are told apart in O(k) by their vector
    area (a loop that runs back along itself has none).

    Parameters
    ----------
    vertices : (n, 3) float array
    loop : (k,) int array
        Vertex ids of a boundary loop, in order.
    rtol : float
        Coincidence tolerance, relative to the length of the loop edges there.
    """
    loop = np.asarray(loop, dtype=np.int64)
    p = np.asarray(vertices, dtype=np.float64)[loop]
    p = p - p.mean(axis=0)
    scale = np.abs(p).max()
    if len(loop) < 3 or scale == 0:
        return None  # not a loop to fill (zero-length edges are refused by validation)
    p = p / scale  # scale-free: the same numbers at 1e-200 and 1e+200
    e = np.roll(p, -1, axis=0) - p
    h = np.linalg.norm(e, axis=1)
    vector_area = 0.5 * np.linalg.norm(np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0))
    # a loop whose sides lie within rtol h of each other spans at most that times its length
    if vector_area > rtol * h.max() * h.sum() or not _lies_on_itself(p, e, h, rtol):
        return None
    found = _glued(p, h, rtol)
    if found is None or not found[1].all():
        return Slit(np.empty((0, 2), dtype=np.int64))
    return Slit(_pairs(loop, found[0], np.arange(len(loop))))


def zip_faces(faces: np.ndarray, merges: np.ndarray) -> tuple[np.ndarray, str | None]:
    """``faces`` with each ``merges`` duplicate replaced by its kept partner (a new array;
    ``faces`` is not modified), and why that is not a manifold surface around the merged
    vertices (None: it is).

    Parameters
    ----------
    faces : (f, 3) int array
    merges : (m, 2) int array
        ``(duplicate, kept)`` pairs (:attr:`Slit.merges`).
    """
    faces = np.asarray(faces, dtype=np.int64)
    mapping = np.arange(max(int(faces.max()), int(merges.max())) + 1)
    mapping[merges[:, 0]] = merges[:, 1]
    zipped = mapping[faces]
    touched = zipped[np.isin(zipped, merges[:, 1]).any(axis=1)]
    if ((touched[:, 0] == touched[:, 1]) | (touched[:, 1] == touched[:, 2])
            | (touched[:, 2] == touched[:, 0])).any():
        return zipped, "a face would use one vertex twice"
    directed = np.concatenate([touched[:, [0, 1]], touched[:, [1, 2]], touched[:, [2, 0]]])
    _, counts = np.unique(directed, axis=0, return_counts=True)
    if (counts > 1).any():
        return zipped, ("its two sides face opposite ways or meet other faces there (the "
                        "zipped edges would be non-manifold or inconsistently oriented)")
    return zipped, None


def spanless(vertices: np.ndarray, loop: np.ndarray) -> tuple[Slit, str, str] | None:
    """The loop as a slit (:func:`find_slit`), or the seam that makes up part of it
    (:func:`find_seam_part`), with why no disk fills it and what zipping that seam leaves
    open ("" or "; the rest of the loop is left open"); None when it bounds a surface.
    What :func:`surfinpaint.fill_holes` leaves open (or zips, with ``zip_seams``) before
    anything is filled, and what ``surfinpaint holes`` says of it."""
    slit = find_slit(vertices, loop)
    if slit is not None:
        return slit, slit.describe(), ""
    part = find_seam_part(vertices, loop)
    if part is None:
        return None
    # a seam along part of a loop that bounds no disk (an open tube's)
    pairs = how_many(len(part), "coincident vertex pair joins", "coincident vertex pairs join")
    return (Slit(part), f"the loop runs back along itself: a seam of {pairs} two parts of it "
            "(duplicated vertices), so no disk fills it",
            "; the rest of the loop is left open")


def zip_or_leave(faces: np.ndarray, slit: Slit, reason: str, zip_seams: bool
                 ) -> tuple[np.ndarray | None, str | None]:
    """What :func:`surfinpaint.fill_holes` does with a loop that spans no area
    (:func:`spanless`'s ``slit`` and ``reason``): ``(zipped faces, None)`` where it zips the
    seam (``zip_seams``, and the zipped faces are a manifold surface there), else
    ``(None, why it is left open)``. The one rule ``fill`` and ``surfinpaint holes`` use."""
    if slit.is_seam and zip_seams:
        zipped, problem = zip_faces(faces, slit.merges)
        if problem is None:
            return zipped, None
        return None, f"{reason}; not zipped: {problem}"
    return None, reason + (SEAM_LEFT_OPEN if slit.is_seam else "")
