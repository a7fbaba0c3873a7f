"""Per-vertex and per-face attributes of a filled hole: values for the new vertices and faces.

A fill adds vertices and faces; every attribute the mesh carries (colours, texture
coordinates, scalar overlays such as curvature or cortical thickness, normals, segmentation
labels) needs values there. The original vertices' and faces' values never change.

The rules, by kind (:func:`attribute_kind` decides the kind of an array):

``"values"`` (continuous data, colours included)
    Biharmonic inpainting over the hole's patch in its conformal domain, the machinery of λ
    and H: the patch is the fill's faces plus ``rings`` rings of original faces around the
    loop (:func:`hole_domain`), mapped to the plane by LSCM; with the parameter mesh's
    cotangent Laplacian ``L`` and Voronoi areas ``M``, the new vertices' values solve
    ``(L M⁻¹ L x)_new = 0`` with the known values of the patch as Dirichlet data (which fixes
    values and slopes at the hole's edge: two rings enter the stencil). One sparse direct
    solve a hole, all channels of all attributes at once. The result is clamped to each
    channel's range over the original vertices (the biharmonic overshoots a little; a hole
    that holds the attribute's extreme value is clipped at the largest original value);
    integer arrays (8-bit colours) are rounded and keep their dtype, so colours stay within
    0..255.
``"normal"``
    Not inpainted: recomputed from the filled surface (area-weighted face normals), pointing
    the way the given normals point at the loop.
``"label"`` (segmentations)
    Each new vertex takes the label whose *harmonic* indicator function is largest there: the
    random-walker rule (Grady 2006). The harmonic indicators obey the maximum principle, so
    every region a label gets among the new vertices is connected to known vertices of that
    label: regions are continued, never averaged, and no label appears that the loop's
    surroundings do not have. (Biharmonic indicators overshoot and lose that guarantee.)
``"id"`` (an integer array named like an id or index: ``vtkOriginalPointIds``, ``point_ids``)
    Each value names an element of another mesh, so a new vertex (face) names none: -1, or
    for an unsigned dtype its largest value (:func:`surfinpaint.fill.ids.none_id`); never an
    interpolated or copied id. The names: :func:`surfinpaint.fill.ids.is_id_name`.

Face attributes of new faces: ids (the same names) none; the others copied from the original
faces across the loop, never interpolated, by the same random-walker rule on the fill's dual graph
(:func:`surfinpaint.fill.face_attributes.fill_face_attributes`).

When the patch is not a disk even with one ring, or its conformal map folds, the same
operators are taken on the patch's 3D triangles (the surface metric) instead of its map.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from surfinpaint.errors import MeshError
from surfinpaint.fill.ids import is_id_name, none_ids
from surfinpaint.geometry.cutting import renumber
from surfinpaint.geometry.degenerate import triangle_incidence
from surfinpaint.geometry.linalg import factorized_definite
from surfinpaint.geometry.mesh import cotangent_laplacian, faces_near, mass_matrix, vertex_normals
from surfinpaint.geometry.parameterization import flipped_faces, lscm
from surfinpaint.io.base import MeshWarning
from surfinpaint.lazy import lazy_module

# imported at its first use (see fill/holes.py)
spatial = lazy_module("scipy.spatial")

__all__ = [
    "ATTRIBUTE_KINDS", "DirichletSolve", "HoleDomain", "MAX_LABELS", "attribute_kind",
    "attribute_rows", "channel_ranges", "check_attributes", "fill_hole_attributes",
    "fill_result_attributes", "hole_blocks", "hole_domain", "inpaint_labels", "inpaint_values",
    "inpaint_operators", "labels_by_indicators",
]

ATTRIBUTE_KINDS = ("values", "normal", "label", "id")

#: An integer (or boolean) per-vertex array with at most this many distinct values is a
#: segmentation (atlases have up to ~75 regions; a quality score with 200 levels is not one).
MAX_LABELS = 100

_COLOUR_NAMES = ("color", "colour", "rgb")
_CHANNEL_NAMES = ("red", "green", "blue", "alpha", "r", "g", "b", "a")
_NORMAL_NAMES = ("normal", "normals", "vertex_normal", "vertex_normals", "n")


def attribute_kind(name: str, values: np.ndarray) -> str:
    """The kind of a per-vertex attribute, hence the rule that fills it.

    Rule, in order: a non-numeric array (strings, objects) is ``"label"``; a float
    ``(n, 3)`` array named like a normal (``normal``, ``normals``, ``vertex_normals``,
    ``n``, any case) is ``"normal"``; an array named like a colour
    (containing ``color``/``colour``/``rgb``, or a channel name ``red``, ``green``, ``blue``,
    ``alpha``, ``r``, ``g``, ``b``, ``a``) is ``"values"``; a one-dimensional integer array
    named like an id or index (:func:`~surfinpaint.fill.ids.is_id_name`: ending in ``Ids``,
    ``_ids``, ``index``, ``indices``, ``_idx``; not a material's or region's) is ``"id"``;
    a one-dimensional integer or
    boolean array with at most :data:`MAX_LABELS` distinct values is ``"label"``; everything
    else is ``"values"``. Pass ``kinds=`` to the fill functions to override.

    Parameters
    ----------
    name : str
    values : (n,) or (n, c) array

    Returns
    -------
    str : one of :data:`ATTRIBUTE_KINDS`

    Examples
    --------
    >>> attribute_kind("normals", np.zeros((4, 3)))
    'normal'
    >>> attribute_kind("red", np.zeros(4, dtype=np.uint8)), attribute_kind("parcel", [0, 3])
    ('values', 'label')
    >>> attribute_kind("vtkOriginalPointIds", np.arange(4))
    'id'
    """
    a = np.asarray(values)
    key = name.lower()
    if a.dtype.kind not in "iubfc":
        return "label"
    if key in _NORMAL_NAMES and a.ndim == 2 and a.shape[1] == 3 and a.dtype.kind == "f":
        return "normal"
    if any(word in key for word in _COLOUR_NAMES) or key in _CHANNEL_NAMES:
        return "values"
    if a.ndim == 1 and a.dtype.kind in "iu" and is_id_name(name):
        return "id"
    if a.ndim == 1 and a.dtype.kind in "iub" and len(np.unique(a)) <= MAX_LABELS:
        return "label"
    return "values"


def inpaint_operators(domain: np.ndarray, faces: np.ndarray) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """The cotangent Laplacian (negative semi-definite) and the bilaplacian ``L M⁻¹ L``."""
    L = cotangent_laplacian(domain, faces)
    m = mass_matrix(domain, faces, "voronoi").diagonal()
    m = np.where(m > 0, m, 1.0)  # unreferenced vertices: no rows to speak of
    return L, (L @ sp.diags(1.0 / m) @ L).tocsr()


class DirichletSolve:
    """Solves ``(Q x)_free = 0`` with ``x_known = data`` for any number of right-hand sides,
    ``Q`` factorized once (definite on the free block)."""

    def __init__(self, Q: sp.csr_matrix, known: np.ndarray) -> None:
        self.free = np.flatnonzero(~known)
        Qf = Q[self.free]
        self.coupling = Qf[:, np.flatnonzero(known)]
        self.solve_free = factorized_definite(Qf[:, self.free])

    def __call__(self, data: np.ndarray) -> np.ndarray:
        rhs = -(self.coupling @ np.asarray(data, dtype=float))
        return self.solve_free(np.asarray(rhs, dtype=float))


def _check_known(known: np.ndarray, n: int) -> np.ndarray:
    known = np.asarray(known, dtype=bool)
    if known.shape != (n,):
        raise ValueError(f"known must be a boolean mask of {n} vertices, got {known.shape}")
    if not known.any():
        raise ValueError("no known vertex: inpainting needs Dirichlet data")
    return known


def inpaint_values(domain: np.ndarray, faces: np.ndarray, known: np.ndarray,
                   values: np.ndarray, order: int = 2) -> np.ndarray:
    """Harmonic or biharmonic inpainting of per-vertex values, all channels in one solve.

    The unknown vertices' values minimize the Dirichlet (``order=1``: ``L x = 0`` there) or
    Laplacian energy (``order=2``: ``L M⁻¹ L x = 0`` there) of the mesh ``(domain, faces)``,
    with the known values as Dirichlet data.

    Parameters
    ----------
    domain : (n, 2) or (n, 3) float array
        Vertex positions of the domain: a conformal map (the plane) or the surface itself.
    faces : (f, 3) int array
    known : (n,) bool array
        Vertices whose values are data. Every unknown vertex must be connected to one.
    values : (n,) or (n, c) array
        Rows of the unknown vertices are ignored; a known row's NaN or inf is no data.
    order : {1, 2}

    Returns
    -------
    (n,) or (n, c) float array
        ``values`` (as float) with the unknown rows filled.

    Raises
    ------
    ValueError
        On mismatched shapes, no known vertex or an order other than 1 or 2.
    RuntimeError
        When the system is singular (an unknown vertex cut off from every known one).

    Examples
    --------
    A path of three vertices on a flat strip: the middle value is the mean.

    >>> domain = np.array([[0.0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]])
    >>> faces = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])
    >>> x = np.array([0.0, 9.0, 2.0, 0.0, 1.0, 2.0])
    >>> known = np.array([True, False, True, True, True, True])
    >>> float(inpaint_values(domain, faces, known, x, order=1)[1])
    1.0
    """
    if order not in (1, 2):
        raise ValueError(f"order must be 1 (harmonic) or 2 (biharmonic), got {order!r}")
    domain = np.asarray(domain, dtype=float)
    faces = np.asarray(faces, dtype=np.int64)
    known = _check_known(known, len(domain))
    out = np.array(values, dtype=float)
    if out.shape[0] != len(domain):
        raise ValueError(f"values have {out.shape[0]} rows for {len(domain)} vertices")
    if known.all():
        return out
    L, Q = inpaint_operators(domain, faces)
    flat = out.reshape(len(out), -1)
    # a known vertex without a finite value has no data (a NaN overlay's gap): it is solved
    # for with the unknown ones in the channels it lacks, so that one gap by a hole does not
    # make every new value NaN (session 46); a channel with no data at all gets NaN
    gaps = known[:, None] & ~np.isfinite(flat)
    patterns, of_column = np.unique(gaps, axis=1, return_inverse=True)
    for k, gap in enumerate(patterns.T):
        data, columns = known & ~gap, of_column.reshape(-1) == k
        flat[np.ix_(~known, columns)] = (DirichletSolve(-L if order == 1 else Q, data)(
            flat[np.ix_(data, columns)])[(~known)[~data]] if data.any() else np.nan)
    return flat.reshape(out.shape)


def inpaint_labels(
    domain: np.ndarray, faces: np.ndarray, known: np.ndarray, labels: np.ndarray
) -> np.ndarray:
    """Labels for the unknown vertices by the largest harmonic indicator (random walker).

    For each label present among the known vertices, its indicator (1 on that label's known
    vertices, 0 on the other known ones) is extended harmonically over the unknown vertices
    (one solve, one column a label); each unknown vertex takes the label whose indicator is
    largest (the first on a tie). By the maximum principle every region a label gets is
    connected to known vertices of that label (Grady, *Random walks for image segmentation*,
    2006): labels are continued, never averaged, and none is invented.

    Parameters
    ----------
    domain, faces, known :
        As for :func:`inpaint_values`.
    labels : (n,) array of any dtype (integers, booleans, strings)
        Rows of the unknown vertices are ignored.

    Returns
    -------
    (n,) array of the dtype of ``labels``.

    Examples
    --------
    >>> domain = np.array([[0.0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]])
    >>> faces = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])
    >>> labels = np.array([7, -1, 7, 7, 7, 3])
    >>> known = labels >= 0
    >>> int(inpaint_labels(domain, faces, known, labels)[1])
    7
    """
    labels = np.asarray(labels)
    known = _check_known(known, len(labels))
    out = labels.copy()
    if known.all():
        return out
    L, _ = inpaint_operators(np.asarray(domain, dtype=float), np.asarray(faces, dtype=np.int64))
    out[~known] = labels_by_indicators(DirichletSolve(-L, known), [labels[known]])[0]
    return out


def labels_by_indicators(harmonic: DirichletSolve, known_labels: list[np.ndarray]
                          ) -> list[np.ndarray]:
    """The unknown rows of each label array (given its known rows) by the largest harmonic
    indicator: the indicator columns of all arrays in one solve."""
    columns, splits = [], []
    for labels in known_labels:
        # rows are the categories (a face colour is one value of three channels)
        present, which = np.unique(labels, return_inverse=True,
                                   axis=0 if labels.ndim > 1 else None)
        which = which.ravel()
        block = np.zeros((len(which), len(present)))
        block[np.arange(len(which)), which] = 1.0
        columns.append(block)
        splits.append(present)
    extended = harmonic(np.concatenate(columns, axis=1))
    out, start = [], 0
    for present in splits:
        out.append(present[np.argmax(extended[:, start:start + len(present)], axis=1)])
        start += len(present)
    return out


@dataclass(frozen=True)
class HoleDomain:
    """The patch of one filled hole and the domain its attributes are inpainted on.

    Attributes
    ----------
    ids : (k,) int array
        Global vertex ids of the patch (sorted); rows of ``domain`` follow them.
    faces : (p, 3) int array
        Local ids: the fill's faces first, then the ring faces.
    domain : (k, 2) or (k, 3) float array
        The patch's LSCM map, or its 3D positions when ``conformal`` is False.
    conformal : bool
        False when the patch was not a disk even with one ring, or its map folded.
    rings : int
        Rings of original faces around the loop in the patch.
    """

    ids: np.ndarray
    faces: np.ndarray
    domain: np.ndarray
    conformal: bool
    rings: int


def hole_domain(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                fill_faces: np.ndarray, rings: int = 3) -> HoleDomain:
    """The patch of a filled hole and its conformal map.

    The patch is ``fill_faces`` plus the faces of ``faces`` within ``rings`` rings of the
    loop (``rings=1``: the faces touching it), fewer rings when that is not a topological
    disk (a ring that reaches another hole or the border). Its LSCM map
    (:func:`surfinpaint.geometry.parameterization.lscm`) is the domain; when no ring count
    gives a disk, or the map flips a triangle, the patch's 3D positions are the domain.

    Parameters
    ----------
    vertices : (n, 3) float array
        Positions of the filled mesh (original and new vertices).
    faces : (f, 3) int array
        The faces around the hole, without the fill's faces: the original faces, so that
        other holes' fills stay out of the patch.
    loop : (k,) int array
        The hole's boundary loop.
    fill_faces : (m, 3) int array
        The faces the fill added to this hole.
    rings : int
        At least 1; the bilaplacian stencil at the new vertices needs only the loop's own
        faces (``rings=1``), more rings give the map room away from its free border.

    Returns
    -------
    HoleDomain
    """
    if not isinstance(rings, int | np.integer) or rings < 1:
        raise ValueError(f"rings must be a positive integer, got {rings!r}")
    vertices = np.asarray(vertices, dtype=float)
    fill_faces = np.asarray(fill_faces, dtype=np.int64).reshape(-1, 3)
    n = len(vertices)
    for k in range(rings, 0, -1):
        patch = np.concatenate([fill_faces, faces_near(faces, loop, k - 1, n)])
        if k == rings:
            widest = patch
        ids, local = renumber(patch)
        try:
            uv = lscm(vertices[ids], local)
        except (MeshError, RuntimeError):
            continue
        if np.isfinite(uv).all() and len(flipped_faces(local, uv)) == 0:
            return HoleDomain(ids, local, uv, True, k)
    ids, local = renumber(widest)
    return HoleDomain(ids, local, vertices[ids], False, rings)


def channel_ranges(values: np.ndarray) -> np.ndarray:
    """(2, c) per-channel minimum and maximum, NaNs ignored."""
    flat = np.asarray(values, dtype=float).reshape(len(values), -1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN channel stays NaN
        return np.stack([np.nanmin(flat, axis=0), np.nanmax(flat, axis=0)])


def _cast(inpainted: np.ndarray, like: np.ndarray, limits: np.ndarray) -> np.ndarray:
    """Clamp to ``limits`` (per channel), round integers, and take ``like``'s dtype/shape."""
    low, high = limits
    flat = np.clip(inpainted, low, high)
    if like.dtype.kind in "iub":
        flat = np.rint(flat)
    return flat.reshape((len(flat), *like.shape[1:])).astype(like.dtype)


def _resolve_kinds(attributes: Mapping[str, np.ndarray],
                   kinds: Mapping[str, str] | None) -> dict[str, str]:
    kinds = dict(kinds or {})
    unknown = set(kinds) - set(attributes)
    if unknown:
        raise ValueError(f"kinds given for attributes that are not there: {sorted(unknown)}")
    bad = {k: v for k, v in kinds.items() if v not in ATTRIBUTE_KINDS}
    if bad:
        raise ValueError(f"unknown attribute kinds {bad}: use one of {ATTRIBUTE_KINDS}")
    return {name: kinds.get(name) or attribute_kind(name, values)
            for name, values in attributes.items()}


def attribute_rows(name: str, values, counts: tuple[int, ...], what: str = "vertices"
                   ) -> np.ndarray:
    """``values`` as an array, checked to have one of ``counts`` rows."""
    a = np.asarray(values)
    if a.ndim == 0 or a.shape[0] not in counts:
        raise ValueError(f"attribute {name!r} has {a.shape[0] if a.ndim else 0} rows, the "
                         f"mesh has {counts[0]} {what}")
    return a


def fill_hole_attributes(
    vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, fill_faces: np.ndarray,
    new_ids: np.ndarray, attributes: Mapping[str, np.ndarray], *,
    kinds: Mapping[str, str] | None = None, ranges: Mapping[str, np.ndarray] | None = None,
    rings: int = 3, order: int = 2) -> dict[str, np.ndarray]:
    """Values of every per-vertex attribute at the new vertices of one filled hole.

    The rules by kind are the module's (:mod:`surfinpaint.fill.attributes`): continuous
    values (colours too) inpainted biharmonically on the patch's conformal domain
    (:func:`hole_domain`, :func:`inpaint_values`) and clamped to ``ranges``, integers rounded;
    normals recomputed from the filled surface; labels by the largest harmonic indicator
    (:func:`inpaint_labels`); ids the none id. All continuous channels share one
    factorization and one solve, all labels' indicators another.

    Parameters
    ----------
    vertices : (n, 3) float array
        The filled mesh's positions.
    faces : (f, 3) int array
        The original faces (without any fill's faces).
    loop : (k,) int array
        The hole's boundary loop.
    fill_faces : (m, 3) int array
        The faces the fill added to this hole.
    new_ids : (q,) int array
        The fill's new vertices (all used by ``fill_faces``).
    attributes : mapping of name to (n,) or (n, c) array
        One row per vertex of ``vertices``; the rows of ``new_ids`` are ignored.
    kinds : mapping of name to kind, optional
        Overrides :func:`attribute_kind`.
    ranges : mapping of name to (2, c) array, optional
        Per-channel lower and upper limits of the continuous attributes; by default their
        range over the vertices other than ``new_ids``.
    rings, order :
        Rings of the patch (:func:`hole_domain`) and 2 (biharmonic) or 1 (harmonic).

    Returns
    -------
    dict of name to (q,) or (q, c) array, in each attribute's dtype

    Raises
    ------
    ValueError
        On attributes with the wrong number of rows, unknown kinds, or new vertices that no
        fill face uses.
    """
    vertices = np.asarray(vertices, dtype=float)
    new_ids = np.asarray(new_ids, dtype=np.int64)
    arrays = {name: attribute_rows(name, a, (len(vertices),)) for name, a in attributes.items()}
    kinds = _resolve_kinds(arrays, kinds)
    if len(new_ids) == 0 or not arrays:
        return {name: a[new_ids] for name, a in arrays.items()}
    dom = hole_domain(vertices, faces, loop, fill_faces, rings)
    local_new = np.minimum(np.searchsorted(dom.ids, new_ids), len(dom.ids) - 1)
    if not np.array_equal(dom.ids[local_new], new_ids):
        raise ValueError("new vertices not used by the fill's faces: "
                         f"{new_ids[dom.ids[local_new] != new_ids][:10].tolist()}")
    known = np.ones(len(dom.ids), dtype=bool)
    known[local_new] = False
    out: dict[str, np.ndarray] = {}
    values = [name for name, kind in kinds.items() if kind == "values"]
    if values:
        if ranges is None:
            other = np.setdiff1d(np.arange(len(vertices)), new_ids)
            ranges = {name: channel_ranges(arrays[name][other]) for name in values}
        blocks = [np.asarray(arrays[name][dom.ids], dtype=float).reshape(len(dom.ids), -1)
                  for name in values]
        filled = inpaint_values(dom.domain, dom.faces, known, np.concatenate(blocks, axis=1),
                                order)[local_new]
        start = 0
        for name, block in zip(values, blocks, strict=True):
            width = block.shape[1]
            out[name] = _cast(filled[:, start:start + width], arrays[name],
                              np.asarray(ranges[name], dtype=float).reshape(2, width))
            start += width
    labels = [name for name, kind in kinds.items() if kind == "label"]
    if labels:
        L, _ = inpaint_operators(dom.domain, dom.faces)
        found = labels_by_indicators(DirichletSolve(-L, known),
                                      [arrays[name][dom.ids][known] for name in labels])
        out.update(zip(labels, found, strict=True))
    for name in (name for name, kind in kinds.items() if kind == "id"):  # new: no element
        out[name] = none_ids(arrays[name], len(new_ids))
    normals = (vertex_normals(vertices[dom.ids], dom.faces) if "normal" in kinds.values()
               else None)
    loop_ids = np.asarray(loop, dtype=np.int64)
    for name in (name for name, kind in kinds.items() if kind == "normal"):
        # point the way the given normals point at the loop (an inward convention too)
        agree = np.einsum("ij,ij->", normals[np.searchsorted(dom.ids, loop_ids)],
                          np.asarray(arrays[name][loop_ids], dtype=float)) >= 0
        out[name] = (normals if agree else -normals)[local_new].astype(arrays[name].dtype)
    return {name: out[name] for name in arrays}


def hole_blocks(result, rings: int):
    """(report, new vertex ids, new face ids, near) of each hole of a ``FillResult``, in the
    order the fill appended them; ``near`` are the ids of the original faces touching the
    vertices within ``rings - 1`` rings of the loop (all a patch of ``rings`` rings can use),
    found through a vertex-face incidence built once, so a hole costs what its neighbourhood
    costs, not the mesh."""
    faces = result.faces[: result.n_original_faces]
    n = len(result.vertices)
    if rings > 0:  # a face that repeats a vertex is near no hole (left out as by the fill)
        incidence = triangle_incidence(faces, n)
    vertex_start, face_start = result.n_original_vertices, result.n_original_faces
    for report in result.reports:
        nv, nf = report.new_vertices, report.new_faces
        seen = np.zeros(n, dtype=bool)
        frontier = np.unique(np.asarray(report.loop, dtype=np.int64))
        seen[frontier] = True
        near = []
        for _ in range(rings if nf else 0):
            near.append(incidence[frontier].indices)
            grown = np.unique(faces[near[-1]])
            frontier = grown[~seen[grown]]
            seen[grown] = True
        yield (report, np.arange(vertex_start, vertex_start + nv),
               np.arange(face_start, face_start + nf),
               np.unique(np.concatenate(near)) if near else np.zeros(0, dtype=np.int64))
        vertex_start += nv
        face_start += nf


def fill_result_attributes(
    result, attributes: Mapping[str, np.ndarray], *,
    kinds: Mapping[str, str] | None = None, rings: int = 3, order: int = 2,
) -> dict[str, np.ndarray]:
    """Every per-vertex attribute over a whole filled mesh: the originals' values, unchanged,
    then the new vertices' values, hole by hole (:func:`fill_hole_attributes`).

    Parameters
    ----------
    result : FillResult
        From :func:`surfinpaint.fill.pipeline.fill_holes`.
    attributes : mapping of name to (n, ...) array
        One row per original vertex (``result.n_original_vertices``); an array with a row
        per vertex of the result has its new rows ignored.
    kinds, rings, order :
        See :func:`fill_hole_attributes`; the clamping ranges are the original vertices'.

    Returns
    -------
    dict of name to (len(result.vertices), ...) array, in each attribute's dtype.
    """
    n, total = result.n_original_vertices, len(result.vertices)
    originals, kinds = check_attributes(n, attributes, kinds, total)
    ranges = {name: channel_ranges(a) for name, a in originals.items()
              if kinds[name] == "values"}
    out = {name: np.concatenate([a, np.zeros((total - n, *a.shape[1:]), dtype=a.dtype)])
           for name, a in originals.items()}
    faces = result.faces[: result.n_original_faces]
    for report, new_ids, face_ids, near in hole_blocks(result, rings if out else 0):
        if len(new_ids) == 0 or not out:
            continue
        try:
            filled = fill_hole_attributes(result.vertices, faces[near], report.loop,
                                          result.faces[face_ids], new_ids, out, kinds=kinds,
                                          ranges=ranges, rings=rings, order=order)
        except (RuntimeError, np.linalg.LinAlgError) as exc:
            # a singular patch system: the geometry is filled, its attributes must not be lost
            warnings.warn(f"hole {report.index}: attributes not inpainted ({exc}); the new "
                          "vertices copy the nearest original vertex's values", MeshWarning,
                          stacklevel=2)
            _, nearest = spatial.cKDTree(result.vertices[:n]).query(result.vertices[new_ids])
            filled = {name: none_ids(a, len(new_ids)) if kinds[name] == "id" else a[nearest]
                      for name, a in originals.items()}
        for name, values in filled.items():
            out[name][new_ids] = values
    return out


def check_attributes(
    n_vertices: int, attributes: Mapping[str, np.ndarray] | None,
    kinds: Mapping[str, str] | None = None, n_filled: int | None = None,
) -> tuple[dict[str, np.ndarray], dict[str, str]]:
    """The per-vertex attributes as arrays of ``n_vertices`` rows, and their kinds.

    Parameters
    ----------
    n_vertices : int
    attributes : mapping of name to array, or None
    kinds : mapping of name to kind, optional
    n_filled : int, optional
        Also accepted as a row count (an array over a filled mesh: its first
        ``n_vertices`` rows are kept).

    Raises
    ------
    ValueError
        Naming the attribute with the wrong number of rows, or an unknown kind.
    """
    counts = (n_vertices,) if n_filled is None else (n_vertices, n_filled)
    arrays = {name: attribute_rows(name, a, counts)[:n_vertices]
              for name, a in dict(attributes or {}).items()}
    return arrays, _resolve_kinds(arrays, kinds)
