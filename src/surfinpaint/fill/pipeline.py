"""Hole filling, top to bottom: choose the holes, cut a local neighbourhood around each, fill
it with the requested method (falling back to the conventional fill when the conformal one
fails), and append the new vertices and faces after the original ones.

Original vertices are never moved or reordered; original faces are kept in their order and
the new faces follow them.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from surfinpaint.errors import FillError, MeshError
from surfinpaint.fill.holes import select_holes
from surfinpaint.geometry.repair import unjoined_bowties
from surfinpaint.geometry.validation import check_loop, zero_area_faces

__all__ = ["FillResult", "HoleReport", "fill_holes", "METHODS"]

METHODS = ("conformal", "fair", "triangulate", "initial")

ProgressCallback = Callable[[int, int, str], None]


@dataclass
class HoleReport:
    """What happened to one hole.

    ``method`` is the method whose fill was kept: "fair" when the conformal method fell back
    after a failure (``fallback`` says why, and a warning is issued) or when its self-check
    preferred the faired fill (``note`` says so); "none" when the hole was ``skipped``.
    """

    index: int
    loop: np.ndarray
    n_edges: int
    requested: str
    method: str
    new_vertices: int = 0
    new_faces: int = 0
    seconds: float = 0.0
    fallback: str | None = None
    note: str | None = None
    skipped: str | None = None
    details: dict = field(default_factory=dict)


@dataclass
class FillResult:
    """A filled mesh: the original vertices first, unchanged, then the new ones.

    ``faces`` holds the original faces in order (less ``removed_faces``, ids into the input
    faces, when ``repair=True``), then the new faces.
    """

    vertices: np.ndarray
    faces: np.ndarray
    reports: list[HoleReport]
    n_original_vertices: int
    n_original_faces: int
    removed_faces: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=np.int64))

    @property
    def new_faces(self) -> np.ndarray:
        """The faces added by the fill (all holes)."""
        return self.faces[self.n_original_faces :]


def _vertex_face_csr(faces: np.ndarray, n_vertices: int) -> sp.csr_matrix:
    rows = faces.ravel()
    cols = np.repeat(np.arange(len(faces)), 3)
    return sp.csr_matrix((np.ones(len(rows), dtype=np.int8), (rows, cols)),
                         shape=(n_vertices, len(faces)))


def _faces_of(vertex_faces: sp.csr_matrix, vertex_ids: np.ndarray) -> np.ndarray:
    starts = vertex_faces.indptr[vertex_ids]
    stops = vertex_faces.indptr[vertex_ids + 1]
    counts = stops - starts
    if counts.sum() == 0:
        return np.empty(0, dtype=np.int64)
    offsets = np.repeat(starts - np.cumsum(counts) + counts, counts) + np.arange(counts.sum())
    return np.unique(vertex_faces.indices[offsets])


def _neighbourhood(
    faces: np.ndarray, vertex_faces: sp.csr_matrix, added: np.ndarray, seeds: np.ndarray,
    rings: int,
) -> tuple[np.ndarray, np.ndarray]:
    """Faces within ``rings`` vertex rings of ``seeds``: ids into the original faces and into
    the faces added by earlier holes. Cost depends on the neighbourhood, not the mesh (the
    membership mask is allocated lazily, zero pages are never touched)."""
    n_original = vertex_faces.shape[0]
    n_all = max(n_original, int(added.max()) + 1 if len(added) else 0, int(np.max(seeds)) + 1)
    in_region = np.zeros(n_all, dtype=bool)
    frontier = np.unique(seeds)
    in_region[frontier] = True
    picked, picked_added = [], []
    # grow from the newest ring only: the faces of the older rings are already picked
    for _ in range(rings):
        new = _faces_of(vertex_faces, frontier[frontier < n_original])
        picked.append(new)
        grown = faces[new].ravel()
        if len(added):
            new_added = np.flatnonzero(in_region[added].any(axis=1))
            picked_added.append(new_added)
            grown = np.concatenate([grown, added[new_added].ravel()])
        frontier = np.unique(grown[~in_region[grown]])
        if len(frontier) == 0:
            break
        in_region[frontier] = True
    empty = np.empty(0, dtype=np.int64)
    return (np.unique(np.concatenate(picked)) if picked else empty,
            np.unique(np.concatenate(picked_added)) if picked_added else empty)


def _skip(report: HoleReport, reason: str) -> None:
    report.skipped = reason
    report.method = "none"
    warnings.warn(f"hole {report.index}: {reason}; skipped", stacklevel=3)


def _gather(vertices: np.ndarray, blocks: list[np.ndarray], ids: np.ndarray) -> np.ndarray:
    """Positions of ``ids`` among the original vertices followed by the added blocks."""
    n = len(vertices)
    out = np.empty((len(ids), 3))
    original = ids < n
    out[original] = vertices[ids[original]]
    if (~original).any():
        out[~original] = np.concatenate(blocks)[ids[~original] - n]
    return out


def _fill_one(vertices, faces, loop, method, options):
    from surfinpaint.fill.liepa.baseline import conventional_fill, faired_fill

    if method == "fair":
        new_v, new_f, used = faired_fill(vertices, faces, loop, options.get("fair_order") or 2)
        return new_v, new_f, {"fair_order": used}
    if method == "initial":
        new_v, new_f = conventional_fill(vertices, faces, loop, refine=True, fair=False)
        return new_v, new_f, {}
    if method == "triangulate":
        new_v, new_f = conventional_fill(vertices, faces, loop, refine=False, fair=False)
        return new_v, new_f, {}
    if method == "conformal":
        from surfinpaint.fill.conformal.core import conformal_fill

        return conformal_fill(vertices, faces, loop,
                              **{k: v for k, v in options.items() if v is not None})
    raise ValueError(f"unknown method {method!r}: choose one of {', '.join(METHODS)}")


def fill_holes(
    vertices: np.ndarray,
    faces: np.ndarray,
    holes: Sequence | None = None,
    method: str = "conformal",
    *,
    include_border: bool = False,
    max_hole_edges: int | None = None,
    rings: int | None = None,
    repair: bool = False,
    validate: bool = True,
    progress: ProgressCallback | None = None,
    fair_order: int | None = None,
    **options,
) -> FillResult:
    """Fill holes of a triangle mesh.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
    holes : None, list of int, or list of loops
        None fills every boundary loop except the outer border of an open surface
        (``include_border=True`` fills those too). Integers index :func:`find_holes`' list;
        sequences of vertex ids give boundary loops directly (any orientation, any start).
    method : {"conformal", "fair", "initial", "triangulate"}
        "conformal": λ-H inpainting (Lui, Wen, Gu), falling back to "fair" per hole on
        failure. "fair": the conventional fill (Liepa 2003: triangulate, refine, fair).
        "initial": triangulate and refine only. "triangulate": minimum-weight triangulation.
    max_hole_edges : int, optional
        Holes with more boundary edges are skipped (reported, not filled).
    repair : bool
        Remove the faces around non-manifold edges first (see
        :func:`surfinpaint.geometry.repair.remove_nonmanifold_faces`); the holes this opens are then
        filled with the others. The removed faces are listed in ``FillResult.removed_faces``.
    rings : int, optional
        Vertex rings of the surrounding surface handed to the filler (the conformal method's
        patch size); a default suited to the method when None.
    progress : callable(done, total, message), optional
        Called before and after each hole.
    fair_order : int, optional
        Fairing order (1 harmonic, 2 biharmonic, 3 triharmonic). "fair" uses 2 unless told
        (Liepa's and CGAL's default: the baseline). The conformal method, unless told,
        chooses its fallback per hole between 2 and 3 by its truth-free self-check (see
        :func:`surfinpaint.fill.conformal.core.conformal_fill`).
    **options
        Passed to the conformal method (see :func:`surfinpaint.fill.conformal.core.conformal_fill`).

    Returns
    -------
    FillResult
        ``.vertices`` (the originals, unchanged and in order, then the new ones), ``.faces``
        (the originals, then the new ones) and ``.reports`` (one :class:`HoleReport` a hole).

    Raises
    ------
    MeshError
        Invalid mesh or hole selection (the message names the offending ids).
    NotImplementedError
        ``method="conformal"`` before the conformal method is available.
    """
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}: choose one of {', '.join(METHODS)}")
    if fair_order is not None and (not isinstance(fair_order, int | np.integer)
                                   or fair_order not in (1, 2, 3)):
        raise ValueError(f"fair_order must be 1, 2 or 3, got {fair_order!r}")
    options = {**options, "fair_order": fair_order}
    for name, value in (("max_hole_edges", max_hole_edges), ("rings", rings)):
        if value is not None and (not isinstance(value, int | np.integer) or value < 1):
            raise ValueError(f"{name} must be a positive integer, got {value!r}")
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    removed_faces = np.empty(0, dtype=np.int64)
    if repair:
        from surfinpaint.geometry.repair import remove_nonmanifold_faces

        faces, removed_faces = remove_nonmanifold_faces(vertices, faces)
    if validate:
        from surfinpaint.geometry.validation import validate_mesh

        validate_mesh(vertices, faces)
    explicit = holes is not None
    loops = select_holes(vertices, faces, holes, include_border=include_border)
    if method == "conformal":
        try:
            import surfinpaint.fill.conformal.core  # noqa: F401
        except ImportError as exc:
            raise NotImplementedError(
                "method='conformal' is not implemented yet; use method='fair'"
            ) from exc
    if method == "conformal":
        from surfinpaint.fill.conformal.core import check_options, neighbourhood_rings

        # bad options are the caller's error, not a failed hole to fall back from
        check_options(options.get("discretization") or "mesh", options)
    n = len(vertices)
    vertex_faces = _vertex_face_csr(faces, n)
    new_vertex_blocks: list[np.ndarray] = []
    new_face_blocks: list[np.ndarray] = []
    n_new_vertices = 0
    reports: list[HoleReport] = []
    total = len(loops)
    for index, loop in enumerate(loops):
        report = HoleReport(index=index, loop=np.asarray(loop), n_edges=len(loop),
                            requested=method, method=method)
        reports.append(report)
        if max_hole_edges is not None and len(loop) > max_hole_edges:
            report.skipped = f"{len(loop)} boundary edges > max_hole_edges={max_hole_edges}"
            report.method = "none"
            continue
        if progress:
            progress(index, total, f"hole {index}: {len(loop)} edges, {method}")
        started = time.perf_counter()
        added = (np.concatenate(new_face_blocks) if new_face_blocks
                 else np.empty((0, 3), dtype=np.int64))
        hole_rings = rings
        if hole_rings is None:
            hole_rings = (neighbourhood_rings(len(loop), **options) if method == "conformal"
                          else 3)
        picked, picked_added = _neighbourhood(faces, vertex_faces, added, loop, hole_rings)
        local_faces_global = np.concatenate([faces[picked], added[picked_added]])
        local_ids, local_faces = np.unique(local_faces_global, return_inverse=True)
        local_faces = local_faces.reshape(-1, 3)
        local_vertices = _gather(vertices, new_vertex_blocks, local_ids)
        local_loop = np.searchsorted(local_ids, loop)
        try:
            # on the neighbourhood (global ids): the cost stays with the hole
            check_loop(local_faces_global, loop)
        except MeshError as exc:
            # a loop pinched at a bow-tie (split into pieces): filling each piece joins the
            # fans there, so the result is manifold once all pieces are filled
            if "bow-tie" not in exc.message or unjoined_bowties(local_faces_global, loop).size:
                if explicit:
                    raise MeshError(f"hole {index}: {exc.message}", vertices=exc.vertices,
                                    edges=exc.edges) from None
                _skip(report, exc.message)
                continue
        touching = local_faces_global[np.isin(local_faces_global, loop).any(axis=1)]
        if np.isin(touching, loop).all():
            # a lone triangle or a strip one face wide: the loop bounds nothing but the faces
            # along it, and a fill would lay a second sheet on them (duplicate faces)
            _skip(report, "the loop bounds only the faces along it (a lone sheet)")
            continue
        try:
            new_v, new_f, details = _fill_one(local_vertices, local_faces, local_loop,
                                               method, options)
        except (FillError, np.linalg.LinAlgError, RuntimeError, ValueError) as exc:
            if method != "conformal" or isinstance(exc, MeshError):
                raise
            report.fallback = f"{type(exc).__name__}: {exc}"
            report.method = "fair"
            warnings.warn(f"hole {index}: conformal fill failed ({exc}); used the "
                          "faired fill instead", stacklevel=2)
            new_v, new_f, details = _fill_one(
                local_vertices, local_faces, local_loop, "fair",
                {"fair_order": options.get("fair_order")})
        notes = [details.get(key) for key in ("selection", "crease", "crease_failed")]
        report.note = "; ".join(note for note in notes if note) or None
        if details.get("selected"):
            report.method = details["selected"]
        if details.get("failed"):
            # the conformal method already fell back to its (self-checked) faired fill
            report.fallback = details["failed"]
            warnings.warn(f"hole {index}: conformal fill failed ({details['failed']}); used "
                          f"the faired fill (order {details['fair_order']}) instead",
                          stacklevel=2)
        new_f = np.asarray(new_f, dtype=np.int64)
        degenerate = len(zero_area_faces(
            np.concatenate([local_vertices, np.reshape(new_v, (-1, 3))]), new_f))
        if degenerate:
            _skip(report, f"the fill would add {degenerate} zero-area triangles (the loop "
                  "spans no area: a slit or a T-junction)")
            continue
        n_local = len(local_vertices)
        mapped = np.where(new_f < n_local, local_ids[np.minimum(new_f, n_local - 1)],
                          n + n_new_vertices + (new_f - n_local))
        new_vertex_blocks.append(np.asarray(new_v, dtype=np.float64).reshape(-1, 3))
        new_face_blocks.append(mapped)
        n_new_vertices += len(new_v)
        report.new_vertices = len(new_v)
        report.new_faces = len(new_f)
        report.seconds = time.perf_counter() - started
        report.details = details
        if progress:
            progress(index + 1, total, f"hole {index}: done in {report.seconds:.2f} s")
    out_vertices = (np.concatenate([vertices, *new_vertex_blocks]) if new_vertex_blocks
                    else vertices.copy())
    out_faces = (np.concatenate([faces, *new_face_blocks]) if new_face_blocks
                 else faces.copy())
    return FillResult(out_vertices, out_faces, reports, n, len(faces), removed_faces)
