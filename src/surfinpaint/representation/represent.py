"""The λ-H representation of a disk-topology mesh, the mesh rebuilt from it, and its check.

Two discretizations (method.md §3, §8):

- ``"mesh"`` (the default): λ, H (and the discrete conformality defect, see
  :mod:`~surfinpaint.representation.mesh_lambda_h`) at the vertices of the mesh's own
  parameter triangles; the rebuild solves ``L φ = M (2λ²H n + defect)`` on the same
  triangles with the border fixed, by Newton's method. Exact (to the solver's tolerance)
  when λ and H are the mesh's own, on any disk the map does not fold.
- ``"grid"``: the paper's images, φ resampled on a regular grid over the parameter domain
  (:mod:`~surfinpaint.representation.grid_represent`).
  :func:`~surfinpaint.representation.exports.grid_export` makes it from a mesh
  representation, with a resolution that follows λ's range.
- ``"quadtree"``: φ resampled at the nodes of balanced quadtrees over the parameter domain,
  refined where the map squeezes the surface, coarse to fine
  (:mod:`~surfinpaint.representation.quadtree_represent`);
  :func:`~surfinpaint.representation.exports.quadtree_export` makes it from a mesh
  representation. It holds disks whose λ varies by 10³–10⁴ (a tall finger,
  a limb's tip) with tens of thousands of nodes where a grid needs hundreds of thousands.

:func:`represent` checks itself by default: it rebuilds the mesh from the representation
and stores the round-trip error (:class:`~surfinpaint.representation.roundtrip.RoundTrip`).
"""

from __future__ import annotations

import os
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from surfinpaint.errors import NUMERICAL_ERRORS, MeshError
from surfinpaint.geometry.mesh import boundary_loops
from surfinpaint.representation.grid_represent import (
    LambdaH,
    rebuild_grid,
    represent_grid,
    sampled_vertices,
)
from surfinpaint.representation.mapping import MAPS, FoldedMapWarning, parameterize
from surfinpaint.representation.mesh_lambda_h import mesh_lambda_h, rebuild_on_mesh
from surfinpaint.representation.quadtree_represent import (
    QuadtreeLambdaH,
    rebuild_quadtree,
    represent_quadtree,
    sampled_tree_vertices,
)
from surfinpaint.representation.reconstruction import NotConvergedWarning
from surfinpaint.representation.roundtrip import (
    RoundTrip,
    measure_round_trip,
    require_arrays,
    save_npz,
)

__all__ = [
    "COARSE_FLOOR",
    "DISCRETIZATIONS",
    "CoarseGridWarning",
    "MeshLambdaH",
    "Rebuilt",
    "check_representation",
    "load_representation",
    "rebuild",
    "represent",
    "rebuild_stage",
    "round_trip",
    "sampled_floor",
    "warn_if_coarse",
]

DISCRETIZATIONS = ("auto", "mesh", "grid", "quadtree")
# a grid whose samples alone miss the mesh by more than this (% of the diagonal, Hausdorff)
# somewhere is reported (CoarseGridWarning): the grid export's target is 1 % at 512²
COARSE_FLOOR = 1.0


class CoarseGridWarning(UserWarning):
    """A grid or quadtree representation's sampling floor (its samples alone, no rebuild)
    misses the mesh by more than ``COARSE_FLOOR`` % of the diagonal (measured: the foot cap,
    the tall finger and the quadruped's leg cap at 512² and 1024², docs/representation.md,
    session 17)."""

# 3: the defect in the frame of w = P φ_u − n × φ_v (2: of P φ_u; its rebuild is not exact)
# 4: frame and normal softened where they vanish (mesh_lambda_h.soft_unit)
_FORMAT = 4
# sparse factorizations of the mesh rebuild (damped Newton, then pseudo-arclength
# continuation): the benchmark disks converge within 101 (the built foot cap; the others
# within 50, benchmarks/represent_speed.py, docs/representation.md session 13); the budget
# bounds a failure's time
MAX_STEPS = 150


@dataclass
class MeshLambdaH:
    """The λ-H representation of a mesh on its own conformally mapped triangles.

    Attributes
    ----------
    vertices : (n, 3) float array
        The original positions (the known ones are the boundary data of the rebuild; the
        rest are kept to measure the round trip).
    faces : (f, 3) int array
    uv : (n, 2) float array
        The conformal map.
    lam, H : (n,) float arrays
        Conformal factor and mean curvature at the vertices (method.md §1; H is NaN on the
        border).
    defect : (n, 2) float array
        The discrete conformality defect (a, b) (zero for a smooth conformal map; NaN on the
        border).
    known : (n,) bool array
        Vertices fixed in the rebuild: the border.
    map : str
        The conformal map, ``"lscm"`` or ``"rectangular"``.
    check : RoundTrip or None
        The self-check of :func:`represent`.
    """

    vertices: np.ndarray
    faces: np.ndarray
    uv: np.ndarray
    lam: np.ndarray
    H: np.ndarray
    defect: np.ndarray
    known: np.ndarray
    map: str = "lscm"
    check: RoundTrip | None = None

    discretization = "mesh"

    def save(self, path: str | os.PathLike) -> None:
        """Write to ``path`` as ``.npz``, atomically."""
        arrays = {name: np.asarray(getattr(self, name)) for name in
                  ("vertices", "faces", "uv", "lam", "H", "defect", "known")}
        arrays.update(discretization=np.array("mesh"), map=np.array(self.map),
                      format=np.array(_FORMAT))
        save_npz(path, arrays, self.check)

    @classmethod
    def load(cls, path: str | os.PathLike) -> MeshLambdaH:
        """Read a representation written by :meth:`save`.

        Raises
        ------
        ValueError
            When the file is not a mesh λ-H representation (names what is missing).
        """
        with np.load(path, allow_pickle=False) as data:
            require_arrays(data, ("vertices", "faces", "uv", "lam", "H", "defect", "known",
                                  "map"), path,
                           "a mesh λ-H representation")
            version = int(data["format"]) if "format" in data.files else 0
            if version < _FORMAT:
                raise ValueError(f"{path}: a mesh λ-H representation of format {version}, "
                                 f"whose defect this version ({_FORMAT}) reads differently: "
                                 "represent the mesh again")
            return cls(vertices=data["vertices"], faces=data["faces"].astype(np.int64),
                       uv=data["uv"], lam=data["lam"], H=data["H"], defect=data["defect"],
                       known=data["known"].astype(bool), map=str(data["map"]),
                       check=RoundTrip.from_arrays(data))


@dataclass(frozen=True)
class Rebuilt:
    """A mesh rebuilt from its λ-H representation.

    Unpacks as ``vertices, faces = rebuild(rep)``.

    Attributes
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        The representation's faces.
    converged : bool
        Whether the rebuild's iteration converged; when not, a
        :class:`~surfinpaint.representation.reconstruction.NotConvergedWarning` was issued.
    iterations : int
    message : str
    seconds : float
    """

    vertices: np.ndarray
    faces: np.ndarray
    converged: bool
    iterations: int
    message: str
    seconds: float

    def __iter__(self):
        return iter((self.vertices, self.faces))


def represent(vertices: np.ndarray, faces: np.ndarray, *, discretization: str = "auto",
              map: str = "lscm", check: bool = True, strict: bool = False,
              progress: Callable[[str], None] | None = None,
              **resampling_options) -> MeshLambdaH | LambdaH | QuadtreeLambdaH:
    """The λ-H representation of a disk-topology mesh, checked by its round trip.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        A topological disk, consistently oriented; H's sign follows its orientation.
    discretization : {"auto", "mesh", "grid", "quadtree"}
        ``"auto"`` (default): the mesh form, or, where its rebuild does not converge (a
        coarse cap over a limb's tip), the quadtrees when theirs does and gives the mesh
        back closer (without ``check`` there is nothing to choose by: the mesh form).
        ``"mesh"``: λ and H at the vertices of the mesh's parameter triangles; on a
        regular grid (:func:`~surfinpaint.representation.grid_represent.represent_grid`,
        which takes ``resolution``, ``h``, ``band``, ``sampling``, ``subdivide``,
        ``spacing``, ``grading``), or on quadtrees refined where the map squeezes the
        surface (:func:`~surfinpaint.representation.quadtree_represent.represent_quadtree`,
        which takes ``targets``, ``max_depth``, ``sampling``). Measured
        (``benchmarks/represent_speed.py``, ``benchmarks/quadtree_export.py``,
        docs/representation.md): the mesh form gives each benchmark disk back to ~1e-8 %
        of the diagonal; a resampled form at best to its sampling floor, and
        :func:`~surfinpaint.representation.exports.resampled_export` picks the one (trees
        or grid) that gives the disk back within 0.1 % mean / 1 % Hausdorff.
    map : {"lscm", "rectangular"}
        The conformal map (:func:`~surfinpaint.representation.mapping.parameterize`).
    check : bool
        Rebuild the mesh from the representation and store the round-trip error in
        ``check`` (:class:`~surfinpaint.representation.roundtrip.RoundTrip`).
    strict : bool
        Raise instead of warning when the map folds triangles over (without it the mesh
        form untangles them first: ``parameterize(..., untangle=True)``).
    progress : callable, optional
        Called with a sentence as each stage starts (the map and λ, H; the self-check's
        rebuild, which takes most of the time on large or strongly distorted disks).
    **resampling_options
        For ``discretization="grid"`` or ``"quadtree"`` only (``spacing="graded"`` among
        the grid's: a grid denser where the map squeezes the surface).

    Returns
    -------
    MeshLambdaH, LambdaH or QuadtreeLambdaH

    Raises
    ------
    MeshError
        When the mesh is not a topological disk, or (``strict``) the map folds.
    ValueError
        For bad parameters.

    Examples
    --------
    >>> from surfinpaint.data import bumpy_disk
    >>> rep = represent(*bumpy_disk(8))
    >>> rep.check.converged and rep.check.mean_percent < 1e-6
    True
    """
    if discretization not in DISCRETIZATIONS:
        raise ValueError(f"unknown discretization {discretization!r}; choose from "
                         f"{DISCRETIZATIONS}")
    if map not in MAPS:
        raise ValueError(f"unknown conformal map {map!r}; choose from {MAPS}")
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    if discretization == "auto":
        if resampling_options:
            raise ValueError(f"options {sorted(resampling_options)} are for "
                             "discretization='grid' or 'quadtree'")
        return _mesh_form_or_quadtrees(v, f, map, check, strict, progress)
    say = progress or (lambda message: None)
    say(f"mapping {len(v)} vertices and computing λ, H"
        + {"mesh": "", "grid": " on the grid", "quadtree": " on the quadtrees"}[discretization])
    if discretization == "grid":
        rep = represent_grid(v, f, map=map, strict=strict, **resampling_options)
    elif discretization == "quadtree":
        rep = represent_quadtree(v, f, map=map, strict=strict, **resampling_options)
    else:
        if resampling_options:
            raise ValueError(f"options {sorted(resampling_options)} are for discretization='grid' "
                             "or 'quadtree'")
        rep = _represent_on_mesh(v, f, map, strict)
    if check:
        say(rebuild_stage(rep))
        rep.check = check_representation(rep, progress=progress)
        warn_if_coarse(rep)
    return rep


def _mesh_form_or_quadtrees(v: np.ndarray, f: np.ndarray, map: str, check: bool, strict: bool,
                            progress: Callable[[str], None] | None
                            ) -> MeshLambdaH | QuadtreeLambdaH:
    """``discretization="auto"``: the mesh form, or the quadtrees where the mesh form's
    rebuild does not converge and theirs does, closer to the mesh.

    Measured (docs/representation.md, session 22): on a coarse cap over a cow's hoof (86
    vertices, λ varying 670-fold, 10 border vertices) the mesh form's continuation stalls at
    t ≈ 0.25 whatever its budget (150-1500 factorizations) or one or two midpoint
    subdivisions, and the quadtrees, refined where the map squeezes the hoof, converge
    coarse to fine to their floor.
    """
    rep = represent(v, f, discretization="mesh", map=map, check=check, strict=strict,
                    progress=progress)
    if not check or rep.check.converged:
        return rep
    if progress is not None:
        progress("the mesh form's rebuild did not converge; trying the quadtrees")
    try:
        with warnings.catch_warnings():
            # a tree that does not hold this surface is not kept: nothing to warn about
            warnings.simplefilter("ignore", CoarseGridWarning)
            warnings.simplefilter("ignore", FoldedMapWarning)
            trees = represent(v, f, discretization="quadtree", map=map, strict=strict,
                              progress=progress)
    except (MeshError, *NUMERICAL_ERRORS):
        return rep
    if trees.check.converged and trees.check.hausdorff < rep.check.hausdorff:
        return trees
    return rep


def warn_if_coarse(rep: MeshLambdaH | LambdaH | QuadtreeLambdaH) -> None:
    """A :class:`CoarseGridWarning` when a grid's or quadtree's samples alone miss the mesh
    by more than ``COARSE_FLOOR`` % of the diagonal somewhere: then no rebuild can give it
    back."""
    c = rep.check
    if c.floor_hausdorff is None or c.floor_hausdorff <= COARSE_FLOOR / 100 * c.diagonal:
        return
    if rep.discretization == "quadtree":
        what = (f"the finest quadtree ({len(rep.finest.uv)} nodes, cells of "
                f"{rep.finest.target:g} × the diagonal)")
        finer = "a smaller last target or a larger max_depth"
    else:
        shape = "×".join(str(n) for n in rep.grid.shape)
        what = f"the {shape} {'graded ' if rep.grid.graded else ''}grid"
        finer = ("a finer grid" if rep.grid.graded else
                 "a finer or graded grid (spacing='graded')") + \
            ", the quadtree export (quadtree_export, --export-quadtree), whose cells follow " \
            "the squeeze"
    warnings.warn(
        f"{what} under-resolves this surface "
        f"where the map squeezes it: its samples alone miss the mesh by "
        f"{100 * c.floor_hausdorff / c.diagonal:.3g} % of the diagonal at worst "
        f"({100 * c.floor_mean / c.diagonal:.3g} % mean), and no rebuild of it can be "
        f"closer; {finer}, or the mesh form (the default), which stores the mesh's own "
        f"triangles", CoarseGridWarning, stacklevel=3)


def _represent_on_mesh(v: np.ndarray, f: np.ndarray, map: str, strict: bool) -> MeshLambdaH:
    uv, _ = parameterize(v, f, map, strict=strict, untangle=True)
    lam, H, defect = mesh_lambda_h(v, f, uv)
    known = np.zeros(len(v), dtype=bool)
    known[np.concatenate(boundary_loops(f))] = True
    unused = np.ones(len(v), dtype=bool)
    unused[f.ravel()] = False
    known |= unused  # vertices on no face: nothing to rebuild them from
    return MeshLambdaH(vertices=v.copy(), faces=f.copy(), uv=uv, lam=lam, H=H,
                       defect=defect, known=known, map=map)


def rebuild(rep: MeshLambdaH | LambdaH | QuadtreeLambdaH, method: str | None = None, *,
            lam: np.ndarray | None = None, H: np.ndarray | None = None,
            defect: np.ndarray | None = None, tol: float | None = None,
            max_iter: int | None = None, progress: Callable[[str], None] | None = None,
            **options) -> Rebuilt:
    """The mesh rebuilt from its λ-H representation.

    Parameters
    ----------
    rep : MeshLambdaH, LambdaH or QuadtreeLambdaH
    method : {"newton", "laplacian", "gauss-codazzi"}, optional
        The grid reconstruction (grid representations only;
        :func:`~surfinpaint.representation.grid_represent.rebuild_grid`): default
        ``"newton"`` (the mesh form on the grid's own triangles, coarse to fine), or
        ``"laplacian"`` for grid files of format 1, which lack its data.
    lam, H : arrays, optional
        Replace the representation's λ and H (e.g. inpainted ones), shaped like them (a
        quadtree's: at its finest tree's nodes).
    defect : (n, 2) array, optional
        Mesh only: replace the conformality defect (zeros: the paper's ``Δφ = 2λ²H n``).
    tol, max_iter : float, int, optional
        Tolerance and iteration budget: on the mesh and the quadtrees, Newton's (relative
        to the border's diagonal; default 1e-10 and MAX_STEPS = 150 factorizations,
        :func:`~surfinpaint.representation.mesh_lambda_h.rebuild_on_mesh`; the quadtrees'
        budget is the coarsest tree's); on the grid, the Laplacian iteration's
        (``reconstruct``'s defaults).
    progress : callable, optional
        Quadtrees: called with a sentence as each tree's solve starts (the others are one
        solve).
    **options
        Grid: passed on to ``rebuild_grid``; quadtree: ``direct`` (each tree alone, not
        coarse to fine) for
        :func:`~surfinpaint.representation.quadtree_represent.level_solves`.

    Returns
    -------
    Rebuilt

    Warns
    -----
    NotConvergedWarning
        When the rebuild did not converge (``Rebuilt.converged`` is then False).
    """
    if isinstance(rep, LambdaH):
        started = time.perf_counter()
        options.update({k: x for k, x in (("tol", tol), ("max_iter", max_iter))
                        if x is not None})
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NotConvergedWarning)  # re-issued below, once
            if method is None:
                method = "newton" if rep.levels else "laplacian"
            v, f, info = rebuild_grid(rep, method, lam=lam, H=H, **options)
        out = Rebuilt(v, f, info.converged, info.iterations, info.message,
                      time.perf_counter() - started)
    elif isinstance(rep, QuadtreeLambdaH):
        if method is not None or defect is not None:
            raise ValueError("method and defect are not for quadtree representations (the "
                             "mesh form's Newton method on each tree's own triangles)")
        started = time.perf_counter()
        v, f, info = rebuild_quadtree(rep, lam=lam, H=H, tol=1e-10 if tol is None else tol,
                                      max_iter=MAX_STEPS if max_iter is None else max_iter,
                                      progress=progress, **options)
        out = Rebuilt(v, f, info.converged, info.iterations, info.message,
                      time.perf_counter() - started)
    else:
        if options or method is not None:
            raise ValueError("method and reconstruction options are for grid representations")
        solve = rebuild_on_mesh(rep.vertices, rep.faces, rep.uv,
                                rep.lam if lam is None else lam, rep.H if H is None else H,
                                rep.defect if defect is None else defect, rep.known,
                                tol=1e-10 if tol is None else tol,
                                max_iter=MAX_STEPS if max_iter is None else max_iter,
                                select_by_area=lam is None and H is None and defect is None,
                                nested_dissection=True)
        out = Rebuilt(solve.points, rep.faces.copy(), solve.converged, solve.iterations,
                      solve.message, solve.seconds)
    if not out.converged:
        warnings.warn(f"the λ-H rebuild did not converge: {out.message}", NotConvergedWarning,
                      stacklevel=2)
    return out


def check_representation(rep: MeshLambdaH | LambdaH | QuadtreeLambdaH, *,
                         progress: Callable[[str], None] | None = None) -> RoundTrip:
    """Rebuild the mesh from ``rep`` and measure it against the original it stores
    (``progress``: as :func:`rebuild`'s)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NotConvergedWarning)  # it is in the result
        out = rebuild(rep, progress=progress)
    return round_trip(rep, out)


def round_trip(rep: MeshLambdaH | LambdaH | QuadtreeLambdaH, out: Rebuilt) -> RoundTrip:
    """The round-trip error of ``out`` (:func:`rebuild`'s result) against the original that
    ``rep`` stores; for a grid or quadtree, with its sampling floor (the error of an exact
    rebuild of it, :func:`~surfinpaint.representation.grid_represent.sampled_vertices`,
    :func:`~surfinpaint.representation.quadtree_represent.sampled_tree_vertices`)."""
    return measure_round_trip(rep.vertices, out.vertices, rep.faces, converged=out.converged,
                              iterations=out.iterations, message=out.message,
                              seconds=out.seconds, floor=sampled_floor(rep))


def sampled_floor(rep: MeshLambdaH | LambdaH | QuadtreeLambdaH) -> np.ndarray | None:
    """The original's vertices as an exact rebuild of a grid or quadtree gives them back
    (its sampling floor's vertices); None for the mesh form, whose floor is 0."""
    return {"grid": sampled_vertices, "quadtree": sampled_tree_vertices,
            "mesh": lambda rep: None}[rep.discretization](rep)


def load_representation(path: str | os.PathLike
                        ) -> MeshLambdaH | LambdaH | QuadtreeLambdaH:
    """Read any kind of representation file (:meth:`MeshLambdaH.save`,
    :meth:`LambdaH.save`, :meth:`QuadtreeLambdaH.save`).

    Raises
    ------
    ValueError
        When the file is not a λ-H representation (not an ``.npz`` archive, or one without
        a representation's arrays).
    """
    with open(path, "rb") as fh:  # np.load of any other file talks of pickles
        if fh.read(4) != b"PK\x03\x04":
            raise ValueError("not an .npz archive, as represent and its exports write")
    with np.load(path, allow_pickle=False) as data:
        kind = str(data["discretization"]) if "discretization" in data.files else "grid"
    if kind == "mesh":
        return MeshLambdaH.load(path)
    if kind == "quadtree":
        return QuadtreeLambdaH.load(path)
    return LambdaH.load(path)


def rebuild_stage(rep: MeshLambdaH | LambdaH | QuadtreeLambdaH) -> str:
    """The self-check's stage, for a ``progress`` callback."""
    if rep.discretization == "quadtree":
        nodes = ", ".join(str(len(level.uv)) for level in rep.levels)
        return f"self-check: rebuilding the quadtrees ({nodes} nodes) coarse to fine"
    if rep.discretization == "grid":
        shape = "×".join(str(n) for n in rep.grid.shape)
        return f"self-check: rebuilding the {shape} grid from its λ and H"
    return f"self-check: rebuilding the {len(rep.vertices)} vertices from λ and H"
