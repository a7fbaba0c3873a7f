"""Typed results of filling holes: the :class:`Fill` a method returns for one hole, the λ-H
data a conformal fill leaves for diagnostics and pictures (drawn in :mod:`surfinpaint.app`),
and what :func:`surfinpaint.fill_holes` returns: a :class:`FillResult` with one
:class:`HoleReport` per hole (its self-check's scores as :class:`TestScores`) and the
topology warnings (:class:`TopologyChange`, :mod:`surfinpaint.fill.topology`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

import numpy as np

from surfinpaint.errors import how_many
from surfinpaint.fill.objects import to_pyvista, to_trimesh

# which rule wrote an ear-cut fill (``Fill.ear_cut``, ``HoleReport.ear_cut``;
# :mod:`surfinpaint.fill.conformal.ear_cut`): here, where the report reads them without
# importing the fill
BY_HIDDEN_RINGS = "hidden rings"
BY_FLAT_PLANES = "flat planes"
BY_FAIRED_PLANES = "planes, faired between"  # ear_cut_faired: the vertices off them faired

if TYPE_CHECKING:
    from surfinpaint.fill.conformal.selection import Verdict
    from surfinpaint.geometry.flatness import PlaneTest, TwoPlanes
    from surfinpaint.geometry.surface_noise import NoiseEstimate

__all__ = ["Fill", "FillResult", "GridLambdaH", "HoleReport", "LambdaHDiagnostics",
           "LeastSquaresFill", "MeshLambdaH", "Outcome", "Smoothing", "TestScores",
           "TopologyChange"]


@dataclass(frozen=True)
class Smoothing:
    """Whether a hole's bilaplacian fill was the thin-plate smoothing fill, which follows
    the known surface around the hole within its noise instead of through every point
    (``ConformalOptions.fair_smoothing``; docs/candidates.md, sessions 44 and 45), and why.

    Attributes
    ----------
    length : float or None
        The smoothing length used, in mean edge lengths of the surface around the hole;
        None: the plain bilaplacian fill (the noise gate stayed shut, or smoothing off).
    asked : float or "auto"
        The option: "auto" decides per hole from ``noise``; a number is used as given.
    why : str
        Why, in words: the estimate and the sign of it that decided.
    noise : NoiseEstimate, optional
        For "auto": the estimate of the known surface's noise that decided
        (:func:`surfinpaint.geometry.surface_noise.surface_noise`; its ``wide_sigma`` is NaN
        where the 2-ring fits already shut the gate).
    """

    length: float | None
    asked: float | str
    why: str
    noise: NoiseEstimate | None = None

    def sentence(self) -> str:
        """Smoothed or not, and why, in words."""
        if self.length is None:
            return f"not smoothed: {self.why}"
        return f"smoothed (length {self.length:.2g} edges): {self.why}"


@dataclass(frozen=True)
class GridLambdaH:
    """λ and H of the grid discretization's last pass, on its grid (NaN where none).

    Attributes
    ----------
    h : float
        Grid spacing.
    lam0, H0 : (N, M) float arrays
        λ and H estimated from the known surface.
    lam, H : (N, M) float arrays
        After inpainting.
    hole, region, domain : (N, M) bool arrays
        The fill's nodes, the inpainted region (the hole dilated), the nodes with data.
    """

    h: float
    lam0: np.ndarray
    H0: np.ndarray
    lam: np.ndarray
    H: np.ndarray
    hole: np.ndarray
    region: np.ndarray
    domain: np.ndarray

    @property
    def grid_shape(self) -> tuple[int, int]:
        return tuple(self.domain.shape)


@dataclass(frozen=True)
class LeastSquaresFill:
    """The λ-H fill's last stage was used: the coupled solve found no fixed point, and the
    fill is the patch's positions nearest to one
    (:func:`surfinpaint.representation.least_squares_stage.least_squares_on_mesh`: continuation
    in the curvature weight, then least squares).

    Attributes
    ----------
    residual : float
        How far the λ-H update still moves them, in mean edge lengths (largest entry).
    weight : float
        The largest weight of the curvature term its continuation reached from the
        harmonic fill (1: it reached a fixed point, which Newton's method from the start
        did not).
    unsolved : str
        Why the coupled solve failed before (its lagged, halved and Newton attempts, on the
        patch and, where the continuation had not reached the full weight in its first
        solves, on the patch subdivided once).
    lattice : int
        Where the least-squares fill was not near enough either: the free vertices of the
        regular lattice of the patch's map on which the coupled solve found a fixed point
        (:func:`surfinpaint.fill.conformal.mesh_pass._on_lattice`); 0 when not used.
    folded : str
        Set when the lattice was used because the fill made on the patch's own triangles
        folded over or cut through the surface at every damping step (why), not because
        the solve failed; ``residual`` and ``weight`` are then NaN (the least-squares stage
        did not run).
    """

    residual: float
    weight: float
    unsolved: str
    lattice: int = 0
    folded: str = ""

    def sentence(self) -> str:
        """The stage in words, for the hole's report."""
        if self.folded:
            return (f"the fill on the patch's own triangles was rejected ({self.folded}); "
                    f"the coupled solve on a regular lattice of its map ({self.lattice} free "
                    f"vertices), read back at the fill's")
        if self.lattice:
            return (f"no fixed point on the patch (the least-squares fill's residual "
                    f"{self.residual:.2g} edge lengths); one found on a regular lattice of "
                    f"its map ({self.lattice} free vertices), read back at the fill's")
        if self.weight >= 1.0:
            return (f"no fixed point found from the start; one found by continuation in the "
                    f"curvature weight (a residual of {self.residual:.2g} edge lengths)")
        return (f"no fixed point of the coupled solve; the least-squares fill (from the "
                f"curvature weight {self.weight:.2g} its continuation reached), a residual "
                f"of {self.residual:.2g} edge lengths")


@dataclass(frozen=True)
class MeshLambdaH:
    """The mesh discretization's patch, from which λ and H before and after are drawn.

    Attributes
    ----------
    uv : (k, 2) float array
        The patch's conformal (LSCM) map.
    faces : (p, 3) int array
        The patch's faces over its own vertex ids, the fill's first.
    n_fill_faces : int
    free : (k,) bool array
        The vertices that moved (the fill's interior).
    before, after : (k, 3) float arrays
        Positions before (the initial fill) and after the λ-H pass.
    one_side : bool
        The patch is one side of a crease across the hole (the side with the larger fill).
    map : {"lscm", "lscm-untangled", "mean-value"}
        The patch's map: LSCM; where LSCM flips triangles at every patch size, LSCM with
        the flips untangled locally, or the mean-value map of the patch
        (:mod:`surfinpaint.geometry.mean_value`).
    least_squares : LeastSquaresFill, optional
        Set when the coupled solve found no fixed point (lagged, halved, Newton, on the
        subdivided patch) and the fill is the least-squares stage's.
    """

    uv: np.ndarray
    faces: np.ndarray
    n_fill_faces: int
    free: np.ndarray
    before: np.ndarray
    after: np.ndarray
    one_side: bool = False
    map: str = "lscm"
    least_squares: LeastSquaresFill | None = None


@dataclass(frozen=True)
class LambdaHDiagnostics:
    """What the λ-H pass of a conformal fill used.

    Attributes
    ----------
    discretization : {"mesh", "grid"}
    rings : int
        Face rings of known surface in the patch actually used (0: nothing moved).
    reconstruct : str, optional
        Grid discretization: the reconstruction actually used.
    grid : GridLambdaH, optional
        Grid discretization: λ and H on the grid.
    mesh : MeshLambdaH, optional
        Mesh discretization: the patch and its positions before and after.
    note : str, optional
        E.g. that the fill had no interior vertices to move.
    damping : float
        The fraction of the λ-H displacement from the initial fill that was kept to pass the
        checks (1: undamped; :func:`surfinpaint.fill.conformal.checks.damped_fill`); with
        ``blended_with``, the λ-H fill's share of the blend.
    blended_with : str, optional
        The λ-H fill failed its checks at every damping step, and what was written is its
        largest blend with this faired fill ("bilaplacian", "trilaplacian") that passes them
        (:func:`surfinpaint.fill.conformal.checks.blended_fill`).
    """

    discretization: str
    rings: int
    reconstruct: str | None = None
    grid: GridLambdaH | None = None
    mesh: MeshLambdaH | None = None
    note: str | None = None
    damping: float = 1.0
    blended_with: str | None = None


@dataclass(frozen=True)
class Fill:
    """The fill of one hole.

    Attributes
    ----------
    vertices : (m, 3) float array
        The new vertices.
    faces : (p, 3) int array
        The new faces, over the mesh's vertex ids and ``n + j`` for new vertex ``j``
        (``n`` the mesh's vertex count).
    kind : {"conformal", "fair"}
        Whose fill it is: the λ-H fill, or a faired fill (the conventional one).
    fair_order : int, optional
        Of a faired fill: the fairing order actually used.
    verdict : Verdict, optional
        The conformal method's self-check (:func:`surfinpaint.fill.conformal.choose`).
    selection : str, optional
        The self-check's verdict in words.
    failure : str, optional
        Why the λ-H fill failed on this hole (``kind`` is then "fair").
    crease : str, optional
        A crease crosses the hole and was continued across it (the λ-H fill).
    crease_failure : str, optional
        The crease fill failed and the hole was filled as smooth.
    diagnostics : LambdaHDiagnostics, optional
        What the λ-H pass used (the λ-H fill).
    crossing_triangles : (c,) int array
        The fill's triangles (rows of ``faces``, sorted) that pierce or overlap the surface
        around the hole (:func:`surfinpaint.fill.parallel.crossing_triangles`; empty for a
        clean fill); :attr:`crossings` counts them.
    plane : PlaneTest or TwoPlanes, optional
        The known surface around the hole was a plane within its noise (the conformal
        method's ``plane_test``), or two planes meeting at an edge (``two_plane_test``),
        and this faired fill was laid on it.
    smoothing : Smoothing, optional
        How the hole's bilaplacian fill was made where smoothing was asked for
        (``fair_smoothing`` "auto", the default, or a length): smoothed or not, and why.
        It is the written fill where ``kind`` is "fair" with ``fair_order`` 2 and no
        ``plane``; else a candidate the self-check compared. None: not asked for.
    ear_cut : str, optional
        The fill is the loop's ear-cut triangulation (:mod:`surfinpaint.fill.conformal.
        ear_cut`), written by the rule named here: "flat planes" (``ear_cut_flat``, refined
        within its planes), "planes, faired between" (``ear_cut_faired``) or "hidden rings"
        (``ear_cut_ratio``, bare).
    """

    vertices: np.ndarray
    faces: np.ndarray
    kind: str
    fair_order: int | None = None
    verdict: Verdict | None = None
    selection: str | None = None
    failure: str | None = None
    crease: str | None = None
    crease_failure: str | None = None
    diagnostics: LambdaHDiagnostics | None = None
    crossing_triangles: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=np.int64))
    plane: PlaneTest | TwoPlanes | None = None
    smoothing: Smoothing | None = None
    ear_cut: str | None = None

    @property
    def crossings(self) -> int:
        """How many of the fill's triangles cross the surface around the hole."""
        return len(self.crossing_triangles)

    @property
    def notes(self) -> str | None:
        """The selection and crease notes in one sentence (None without any)."""
        notes = [n for n in (self.selection, self.crease, self.crease_failure) if n]
        return "; ".join(notes) or None


#: What was written for a hole: the λ-H fill, a faired fill, nothing because the hole was
#: skipped (by ``max_hole_edges``, or a loop that cannot be filled), nothing because its
#: fill failed, or its seam zipped (``zip_seams=True``: :mod:`surfinpaint.fill.seams`).
Outcome = Literal["lambda-h", "faired", "skipped", "failed", "zipped"]

# the self-check's candidate names (:mod:`surfinpaint.fill.conformal.selection`)
_CANDIDATES = {"conformal": "lambda_h", "fair2": "bilaplacian", "fair3": "trilaplacian"}


@dataclass(frozen=True)
class TestScores:
    """One test of the conformal method's self-check, scored.

    Each score is the mean distance, in mesh units, from a candidate's fill of the test's
    hole(s) to the known surface hidden there (:mod:`surfinpaint.fill.selfcheck`): lower is
    better, ``inf`` where that candidate failed, None where it was not scored.

    Attributes
    ----------
    test : {"hidden rings", "sibling holes"}
        The rings of known surface around the hole, hidden and predicted again; or holes as
        wide as this one cut from the known surface nearby.
    lambda_h, bilaplacian, trilaplacian : float or None
        The λ-H fill's, the bilaplacian (order 2) and the trilaplacian (order 3) faired
        fill's scores.
    """

    __test__ = False  # not a pytest test class

    test: str
    lambda_h: float | None = None
    bilaplacian: float | None = None
    trilaplacian: float | None = None

    @classmethod
    def of(cls, test: str, scores: dict[str, float]) -> TestScores:
        """From a test's scores by candidate name (as :class:`~surfinpaint.fill.conformal.
        selection.Verdict` holds them)."""
        return cls(test, **{_CANDIDATES[name]: float(value) for name, value in scores.items()
                            if name in _CANDIDATES})


@dataclass
class HoleReport:
    """What happened to one hole.

    ``index`` numbers the hole as :func:`surfinpaint.find_holes` does (the outer border
    counts), whatever was selected. ``method`` is the method whose fill was kept: "fair" when
    the conformal method fell back after a failure (``fallback`` says why, and a warning is
    issued) or when its self-check preferred the faired fill (``note`` says so); "none" when
    nothing was written (``skipped`` says why; ``failed`` when it is because the hole's fill
    failed rather than a choice or a loop that cannot be filled; a loop that spans no area
    is skipped with a warning); "zipped" when the loop was a seam of duplicated vertices
    zipped with ``zip_seams=True`` (``zipped`` holds the merged ``(duplicate, kept)`` vertex
    pairs; see :mod:`surfinpaint.fill.seams`). ``diameter`` is the largest
    distance between two of the loop's vertices, in mesh units. ``fair_order`` is the fairing
    order of a faired fill, ``verdict`` the conformal method's self-check, ``crease`` says
    that a crease crossing the hole was continued across it (``crease_failure``: that its crease
    fill failed and it was filled as smooth), ``diagnostics`` what the λ-H pass used, and
    ``crossings`` how many of the written fill's triangles cross the surface around the hole
    (0 where no fill was written, also one made and not stitched in; see :class:`Fill`),
    farther out, or another hole's fill
    (:mod:`surfinpaint.fill.far_crossings`; a warning says so for each, naming both holes
    for the last), each triangle counted once, ``crossing_triangles`` which (their rows in
    the hole's new faces, :meth:`FillResult.hole_faces`; sorted), ``plane`` the plane test's
    verdict where the faired fill was laid on the plane (or two planes) of the surface
    around the hole (``note`` says so). ``islands``: the
    loops (by number) of the islands the hole was filled with
    (:mod:`surfinpaint.fill.islands`: a faired fill of the annulus between the loops;
    ``note`` names their pieces). ``smoothing``: whether the hole's bilaplacian fill was
    the smoothing fill, and why (see :class:`Fill`; :attr:`smoothed` says whether the
    written fill is it). ``ear_cut``: the rule that wrote the loop's ear-cut triangulation,
    if one did (see :class:`Fill`).
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
    fair_order: int | None = None
    verdict: Verdict | None = None
    crease: str | None = None
    diagnostics: LambdaHDiagnostics | None = None
    diameter: float = float("nan")
    failed: bool = False
    crease_failure: str | None = None
    zipped: np.ndarray | None = None
    crossings: int = 0
    plane: PlaneTest | TwoPlanes | None = None
    islands: tuple[int, ...] = ()
    smoothing: Smoothing | None = None
    crossing_triangles: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=np.int64))
    ear_cut: str | None = None

    def add_crossings(self, triangles: np.ndarray) -> None:
        """Take ``triangles`` (rows of the hole's new faces) among those that cross the
        surface or another fill; ``crossings`` counts each triangle once, whichever checks
        found it."""
        self.crossing_triangles = np.union1d(self.crossing_triangles,
                                             np.asarray(triangles, dtype=np.int64))
        self.crossings = len(self.crossing_triangles)

    @property
    def smoothed(self) -> bool:
        """The written fill is the smoothing fill: the bilaplacian one where its smoothing
        was used, with vertices inside the hole, not laid on a plane (which replaces its
        heights)."""
        return (self.outcome == "faired" and self.fair_order == 2 and self.plane is None
                and self.new_vertices > 0  # a bare triangulation: nothing to smooth
                and self.smoothing is not None and self.smoothing.length is not None)

    @property
    def outcome(self) -> Outcome:
        """What was written for the hole (see :data:`Outcome`)."""
        if self.method == "conformal":
            return "lambda-h"
        if self.method == "fair":
            return "faired"
        if self.method == "zipped":
            return "zipped"
        return "failed" if self.failed else "skipped"

    @property
    def self_check(self) -> tuple[TestScores, ...]:
        """The self-check's tests that ran, in the order they ran (empty without one)."""
        if self.verdict is None:
            return ()
        return tuple(TestScores.of(name, scores) for name, scores in self.verdict.tests.items())


@dataclass(frozen=True)
class TopologyChange:
    """Two filled holes that may have changed the surface's topology.

    A disk glued along each loop never changes the genus or the number of pieces of the
    surface with its holes capped; what it can do is close off a part that was not a disk.
    Two holes facing each other across a gap narrower than they are wide look like the two
    ends of a tube cut across (:func:`surfinpaint.fill.topology.topology_changes`): each
    was closed by a disk where the removed surface may have joined them.

    Attributes
    ----------
    holes : tuple of int
        The two holes (numbered as :func:`surfinpaint.find_holes` numbers them).
    kind : {"tube ends"}
    quantity : {"genus", "pieces"}
        On one piece: its genus; on two pieces: the count of pieces.
    before, after : int
        The quantity had the two ends been joined, and now.
    gap : float
        The distance between the two fills' centres, in mesh units.
    message : str
        The warning in words.
    """

    holes: tuple[int, ...]
    kind: str
    quantity: str
    before: int
    after: int
    gap: float
    message: str


@dataclass
class FillResult:
    """A filled mesh: the original vertices first, unchanged, then the new ones.

    ``faces`` holds the original faces in order (less ``removed_faces``, ids into the input
    faces, when ``repair=True``; ``flipped_faces``, ids into the input faces too, have their
    last two vertex ids swapped), then the new faces. Seams zipped with ``zip_seams=True``
    are the one change to the original faces: ``merged_vertices`` lists the ``(duplicate,
    kept)`` vertex pairs, and the faces use each kept vertex in place of its duplicate (left
    in ``vertices``, unused).
    """

    vertices: np.ndarray
    faces: np.ndarray
    reports: list[HoleReport]
    n_original_vertices: int
    n_original_faces: int
    removed_faces: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=np.int64))
    flipped_faces: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=np.int64))
    merged_vertices: np.ndarray = field(
        default_factory=lambda: np.empty((0, 2), dtype=np.int64))
    #: per-vertex arrays over ``vertices`` (the new rows inpainted: fill/attributes.py)
    attributes: dict[str, np.ndarray] = field(default_factory=dict)
    #: per-face arrays over ``faces`` (the new rows from across the loop)
    face_attributes: dict[str, np.ndarray] = field(default_factory=dict)
    #: fills that changed, or may have changed, the surface's topology (each also a warning)
    topology: tuple[TopologyChange, ...] = ()
    #: how the input object was shown (a textured trimesh's material, a PolyData's active
    #: arrays: :func:`surfinpaint.fill.objects.display_of`), given back by ``to_trimesh`` and
    #: ``to_pyvista``
    display: dict[str, object] = field(default_factory=dict)

    def __repr__(self) -> str:
        # a notebook shows this for `result`: the counts, not pages of arrays
        outcomes: dict[str, int] = {}
        for report in self.reports:
            outcomes[report.outcome] = outcomes.get(report.outcome, 0) + 1
        smoothed = sum(report.smoothed for report in self.reports)
        said = ", ".join(f"{n} {outcome}" + (f" ({smoothed} smoothed)" if smoothed
                                               and outcome == "faired" else "")
                         for outcome, n in outcomes.items()) or "none"
        extra = {"attributes": list(self.attributes),
                 "face_attributes": list(self.face_attributes)}
        return (f"FillResult({len(self.vertices)} vertices "
                f"({len(self.vertices) - self.n_original_vertices} new), {len(self.faces)} "
                f"faces ({len(self.faces) - self.n_original_faces} new), "
                f"{how_many(len(self.reports), 'hole', 'holes')}: {said}"
                + "".join(f", {k}={v}" for k, v in extra.items() if v) + ")")

    @property
    def new_faces(self) -> np.ndarray:
        """The faces added by the fill (all holes)."""
        return self.faces[self.n_original_faces :]

    def hole_faces(self) -> list[np.ndarray]:
        """Each hole's new faces (ids into ``vertices``), in the order of ``reports`` (empty
        for a hole not filled): the new faces come hole after hole."""
        counts = [r.new_faces for r in self.reports]
        starts = self.n_original_faces + np.concatenate([[0], np.cumsum(counts)]).astype(int)
        return [self.faces[starts[k]:starts[k + 1]] for k in range(len(counts))]

    def to_trimesh(self):
        """A ``trimesh.Trimesh``: colours in ``visual``, the other attributes in
        ``vertex_attributes`` and ``face_attributes``, a textured trimesh's material with
        the ``"uv"`` (see :mod:`surfinpaint.fill.objects`)."""
        return to_trimesh(self.vertices, self.faces, self.attributes, self.face_attributes,
                          self.display)

    def to_pyvista(self):
        """A ``pyvista.PolyData``: the attributes in ``point_data``, the face attributes in
        ``cell_data``; an input PolyData's active texture coordinates, normals and scalars
        made active again."""
        return to_pyvista(self.vertices, self.faces, self.attributes, self.face_attributes,
                          self.display)
