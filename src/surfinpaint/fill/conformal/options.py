"""The conformal method's options: validated once here, documented once in the docstrings.

:class:`ConformalOptions` holds what the conformal fill of one hole does (its initial fill,
where λ and H live, its patch, its self-check, creases); :class:`GridOptions` the options of
the paper's grid discretization only. Both are frozen: a value that is accepted here is one
the method can run with.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from surfinpaint.fill.creases import CREASE_ANGLE
from surfinpaint.fill.liepa.refinement import REFINEMENTS
from surfinpaint.fill.liepa.triangulation import SEARCHES
from surfinpaint.representation.inpainting import INPAINT_METHODS
from surfinpaint.representation.reconstruction import METHODS as RECONSTRUCT_METHODS
from surfinpaint.representation.weight_steps import CONTINUATION_SMALLEST, CONTINUATION_STEP

__all__ = ["EAR_CUT_FLAT", "ConformalOptions", "GridOptions", "PATCH_RINGS", "S0_ORDER",
           "SIGNIFICANCE", "TEST_SOLVER_TOL", "check_fair_order"]

# rings of surface in a hole's patch, per discretization (measured: docs/accuracy.md)
PATCH_RINGS = {"mesh": 4, "grid": 10}
# the self-check's choice of a fill other than fair2 stands only where its advantage in the
# test that decided exceeds this many standard errors: one-sided 1 %, the plane test's
# level, fixed before any run (docs/selfcheck.md, "Session 26: a noise-aware self-check")
SIGNIFICANCE = 2.326
# fairing order of the initial fill S0 (without ``fair_order``): measured, the λ-H fill
# from the trilaplacian S0 is closer (benchmarks/selfcheck_rules.py, README)
S0_ORDER = 3
# step (mean edge lengths) at which the coupled λ-H solve of the hole's own fill stops
SOLVER_TOL = 1e-3
# the same for a self-check test hole: their scores differ by far more
TEST_SOLVER_TOL = 1e-2
# the ear-cut fill where at least this fraction of the ear cut continues the known faces'
# planes and a crease crosses the hole (ear_cut_flat; chosen on the 413 tuning-side CAD
# holes, it fires on none of 409 others: docs/candidates.md, sessions 50 and 51)
EAR_CUT_FLAT = 0.9


def _positive_int(name: str, value, minimum: int = 1) -> None:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}, got {value!r}")


def _positive_number(name: str, value) -> None:
    if isinstance(value, bool) or not isinstance(value, int | float | np.number) \
            or not np.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a positive number, got {value!r}")


def _one_of(name: str, value, choices) -> None:
    if value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, choices))}, "
                         f"got {value!r}")


def check_fair_order(fair_order, *, allow_none: bool = True) -> None:
    """Raise ValueError unless ``fair_order`` is 1, 2, 3 (or None when ``allow_none``)."""
    if fair_order is None and allow_none:
        return
    if isinstance(fair_order, bool) or not isinstance(fair_order, int | np.integer) \
            or fair_order not in (1, 2, 3):
        raise ValueError(f"fair_order must be 1, 2 or 3, got {fair_order!r}")


@dataclass(frozen=True)
class GridOptions:
    """Options of the paper's grid discretization (``discretization="grid"``,
    :func:`surfinpaint.fill.conformal.grid_pass.inpaint_patch`).

    Attributes
    ----------
    spacing : float
        Grid spacing as a fraction of the mean parameter-space edge length of the patch.
    fit_radius : int
        Window half-width (nodes) of the robust λ, H fits.
    fit_sigma : float, optional
        Gaussian weight width (nodes) of those fits; ``0.75 * fit_radius`` when None.
    dilate : int
        Nodes by which the hole region is grown before inpainting (the crease between the
        initial fill and the surface pollutes the nodes next to it).
    inpaint : {"biharmonic", "harmonic"}
        Inpainting model of λ and H (:func:`surfinpaint.inpaint`).
    fidelity : float, optional
        Soft data weight of the inpainting (:func:`surfinpaint.inpaint`); None: hard data.
    reconstruct : {"gauss-codazzi", "laplacian"}
        Reconstruction of the positions from (λ, H) (:func:`surfinpaint.reconstruct`); the
        Laplacian form is used where too few known rings surround the region.
    max_nodes : int
        Largest grid; a larger one is a failure of the hole (the faired fill is used).
    """

    spacing: float = 0.5
    fit_radius: int = 3
    fit_sigma: float | None = None
    dilate: int = 1
    inpaint: str = "biharmonic"
    fidelity: float | None = None
    reconstruct: str = "gauss-codazzi"
    max_nodes: int = 250_000

    def __post_init__(self) -> None:
        _positive_number("spacing", self.spacing)
        _positive_int("fit_radius", self.fit_radius)
        if self.fit_sigma is not None:
            _positive_number("fit_sigma", self.fit_sigma)
        _positive_int("dilate", self.dilate, minimum=0)
        _one_of("inpaint", self.inpaint, INPAINT_METHODS)
        if self.fidelity is not None:
            _positive_number("fidelity", self.fidelity)
        _one_of("reconstruct", self.reconstruct, RECONSTRUCT_METHODS)
        _positive_int("max_nodes", self.max_nodes)


@dataclass(frozen=True)
class ConformalOptions:
    """Options of the conformal fill (:func:`surfinpaint.fill.conformal.conformal_fill`).

    The fairing order of the initial fill and of the faired fallback is ``fill_holes``'
    ``fair_order`` (it applies to the faired method too).

    Attributes
    ----------
    start : {"fair", "initial"}
        Initial fill S0: faired (default; trilaplacian unless ``fair_order`` says) or only
        triangulated and refined.
    discretization : {"mesh", "grid"}
        Where λ and H live. ``"mesh"`` (default): on the patch's own triangles, inpainting
        and rebuild solved together (measured better on every benchmark mesh,
        docs/accuracy.md). ``"grid"``: the paper's regular grid over the conformal domain,
        with the options ``grid``.
    patch_rings : int, optional
        Face rings of the known surface in a hole's patch (fewer where the patch would not
        be a disk or, on the mesh, where the conformal map flips a triangle); None: 4 for
        the mesh discretization, 10 for the grid.
    passes : int
        Outer passes: re-parameterize the new patch and inpaint again.
    solver_iterations : int
        Mesh discretization: updates of the normals and λ in the coupled λ-H solve.
    solver_tol : float, optional
        Mesh discretization: step (mean edge lengths) below which the coupled solve stops;
        None: 1e-3 for the hole, 1e-2 for the self-check's test holes.
    select : bool
        Self-check without any truth of the hole (method.md §8): predict ``hide_rings``
        hidden rings of the known surface around it, and fill ``siblings`` holes as wide
        as it cut from the known surface ``gap_rings`` rings away; the λ-H fill is kept
        when it wins (:func:`surfinpaint.fill.conformal.selection.choose`), else a faired
        fill is written. False: the raw λ-H fill (the faired fill when it fails).
    hide_rings : int
        Rings hidden for the first test.
    siblings : int
        Number of sibling holes (0: no sibling test).
    gap_rings : int
        Rings between the hole and its sibling holes.
    creases : bool
        Mesh discretization: sharp creases (edges whose faces turn by more than
        ``crease_angle`` degrees, :func:`surfinpaint.fill.creases.hole_creases`) that cross
        the hole, one or several side by side, are continued across it and each region
        between them is filled on its own. False fills every hole as smooth.
    crease_angle : float
        Degrees, in (0, 180); see ``creases``. Also where the plane test's own-face step
        stops (``plane_test``).
    grid : GridOptions, optional
        Options of the grid discretization; ``GridOptions()`` when ``discretization`` is
        "grid" and None. Given with the mesh discretization, an error.
    s0_search : {"delaunay", "all", "cdt"}
        The triangulation of the hole's loop under S0 and the faired candidates
        (:func:`surfinpaint.fill.liepa.triangulation.minimum_weight_triangulation`'s
        ``search``; docs/candidates.md).
    s0_refinement : {"liepa", "cgal"}
        The refinement under S0 and the faired candidates
        (:func:`surfinpaint.fill.liepa.refinement.refine_patch`'s ``style``: Liepa's
        relaxation to convergence, or CGAL's single flip passes; docs/candidates.md).
    fair_smoothing : float or "auto", optional
        The bilaplacian candidate fair2 (and its fallback) as a thin-plate smoothing fill
        of this smoothing length, in mean edge lengths: the known vertices within 2 rings
        of the loop are followed within their noise, not fixed
        (:func:`surfinpaint.fill.liepa.baseline.faired_fills`' ``smoothing``; for range
        scans, docs/candidates.md, "Session 44 (helper)"). "auto": decided once per hole
        from a truth-free estimate of the noise of the known surface around it, 0.35 where
        it is a noisy scan's and none elsewhere
        (:func:`surfinpaint.fill.liepa.baseline.smoothing_for_hole`; docs/candidates.md,
        "Session 45 (helper)"; the default since session 45). None: the bilaplacian fill
        everywhere. Also the faired fill
        :func:`surfinpaint.fill_holes` writes instead where zero-area faces lie in the
        self-check's rings (a fallback of this method); ``method="fair"``, the conventional
        baseline, never smooths.
    plane_test : bool
        With ``select``: where the known surface within 2 rings of the loop is a plane
        within its noise (neither a quadric's curvature nor a pattern in the plane's
        residuals significant at 1 %: :func:`surfinpaint.geometry.flatness.plane_test`;
        or those a trimmed fit keeps; or those of the hole's own face, up to a part's sharp
        edges: :func:`surfinpaint.fill.conformal.method.known_plane`), the faired fill's
        new vertices are laid on that plane
        (:func:`surfinpaint.fill.liepa.baseline.laid_on_plane`) and no self-check
        runs: on a range scan's flat face the faired fills carry the rim's noise into the
        hole (docs/candidates.md, "Session 26"). Where it is two planes meeting at an edge
        that no crease crosses the hole along (a scanned part's edge:
        :func:`surfinpaint.geometry.flatness.two_plane_test`), the hole is split along the
        line where they meet and each side laid on its plane
        (:func:`surfinpaint.fill.two_planes.split_on_two_planes`; sessions 29-30). False:
        never.
    significance : float, optional
        With ``select``: a λ-H fill or fair3 that the self-check prefers is written only
        when its advantage over fair2 in the test that decided (the hidden rings; the
        sibling holes where no hidden-ring test speaks for the λ-H fill) exceeds this many
        standard errors of the paired per-sample differences
        (:func:`surfinpaint.fill.conformal.selection.demoted`); else the next choice down.
        Default ``SIGNIFICANCE`` = 2.326 (one-sided 1 %; docs/selfcheck.md, "Session 26: a
        noise-aware self-check on scans"). None: the scores alone decide.
    skip_stalled_subdivision : bool
        Where the λ-H solve fails on a patch of at least
        ``mesh_pass.SUBDIVIDED_SKIP_FREE`` (90) free vertices and the least-squares stage's
        continuation, made first, raised the curvature weight and then stalled, the
        subdivided patch's solve is not tried: least squares starts from the stall, as it
        does where that solve fails (:func:`surfinpaint.fill.conformal.mesh_pass.
        subdivision_skipped`). Faster on the failing path's slowest holes (holdout 23's
        tenderizer #6: 0.27 s of its 0.62); on the tuning side the solve it leaves out
        never converged, so no tuning-side fill changes (docs/convergence.md, session 48
        helper). Default False: the solve is tried as before.
    ear_cut_ratio : float, optional
        With ``select``, after the plane tests: the hidden-ring test is run with MeshFix's
        greedy ear-cut triangulation of the loop as one more candidate
        (:mod:`surfinpaint.fill.conformal.ear_cut`), and where its score is below this
        many times the best of the other candidates' the triangulation is written (no new
        vertex) and no self-check runs. On machined parts it continues the known faces'
        planes into the hole where the faired and λ-H fills round them off (docs/candidates.md,
        "Session 49 (helper): CAD holes PyMeshFix fills closer"). None (default): never.
    ear_cut_flat : float, optional
        With ``select``, after the plane tests: where at least this fraction (0 to 1) of
        the area of the loop's ear-cut triangulation continues the known faces' planes and
        two of those planes meet at a crease inside the hole
        (:func:`surfinpaint.fill.conformal.ear_cut.ear_cut_flat`), the triangulation is
        written, refined within its planes to the surrounding edge length (its creases
        kept, nothing faired), and no self-check runs: a machined part's faces and the
        edges between them rebuilt where the faired and λ-H fills round them off
        (docs/candidates.md, "Session 50 (helper): ear-cut triangulation where a crease
        crosses the hole", 0.9 there; "Session 51 (helper): the ear-cut fill refined
        within its planes"). Default 0.9 (session 51); None: never.
    lambda_h_over_fair3 : float, optional
        With ``select``: a λ-H fill the self-check keeps is written only where its
        hidden-ring score is below this many times the trilaplacian fill's (fair3's); else
        fair3 is written (:func:`surfinpaint.fill.conformal.selection.fair3_over_lambda_h`:
        not where the hidden rings ran one ring shallower, a crease crosses the hole or a
        fairing order is asked for). The self-check otherwise measures the λ-H fill against
        fair2 only; on folded cortices fair3 is closer on most holes where the hidden rings
        do not rank the λ-H fill ahead of it (docs/candidates.md, "Session 52 (helper):
        cortex holes", 1.05 there: not the default, it moved some cortex and off-cortex
        holes farther). None (default): never.
    ear_cut_faired : float, optional
        With ``select``, after the plane tests: where the ear-cut triangulation's share of
        area in the known faces' planes is at least this but below ``ear_cut_flat`` (or at
        most 1 where that is None), and a crease crosses the hole, the triangulation is
        written refined within its planes with its vertices off them faired (bilaplacian,
        the plane pieces fixed: :func:`surfinpaint.fill.conformal.ear_cut.
        faired_off_planes`), and no self-check runs (docs/candidates.md, "Session 52
        (helper): CAD holes PyMeshFix still wins after the ear-cut default": not adopted, worse
        by 10 % on as many held-back CAD holes as it improved, and on every smooth or
        scanned hole it fired on at 0.4). Must be below ``ear_cut_flat``. None (default):
        never.
    continuation_smallest : float
        The least-squares stage's continuation in the curvature weight (where the λ-H solve
        fails) halves its weight step after each solve that fails and ends where the step
        falls below this, at most ``CONTINUATION_STEP`` (0.125, its first step): larger
        gives a stalled continuation up sooner, on the same path (:func:`surfinpaint.
        representation.least_squares_stage.curvature_continuation`). Default
        ``CONTINUATION_SMALLEST`` (1e-3); docs/convergence.md, session 49 helper.
    """

    start: str = "fair"
    discretization: str = "mesh"
    patch_rings: int | None = None
    passes: int = 1
    solver_iterations: int = 20
    solver_tol: float | None = None
    select: bool = True
    hide_rings: int = 2
    siblings: int = 2
    gap_rings: int = 3
    creases: bool = True
    crease_angle: float = CREASE_ANGLE
    grid: GridOptions | None = None
    s0_search: str = "delaunay"
    s0_refinement: str = "liepa"
    fair_smoothing: float | str | None = "auto"
    plane_test: bool = True
    significance: float | None = SIGNIFICANCE
    skip_stalled_subdivision: bool = False
    ear_cut_ratio: float | None = None
    ear_cut_flat: float | None = EAR_CUT_FLAT
    lambda_h_over_fair3: float | None = None
    ear_cut_faired: float | None = None
    continuation_smallest: float = CONTINUATION_SMALLEST

    def __post_init__(self) -> None:
        _one_of("start", self.start, ("fair", "initial"))
        _one_of("s0_search", self.s0_search, SEARCHES)
        _one_of("s0_refinement", self.s0_refinement, REFINEMENTS)
        _one_of("discretization", self.discretization, tuple(PATCH_RINGS))
        if self.patch_rings is not None:
            # the mesh discretization drops rings where the map flips, down to 3
            _positive_int("patch_rings", self.patch_rings,
                          minimum=3 if self.discretization == "mesh" else 1)
        _positive_int("passes", self.passes)
        _positive_int("solver_iterations", self.solver_iterations)
        if self.solver_tol is not None:
            _positive_number("solver_tol", self.solver_tol)
        if self.significance is not None:
            _positive_number("significance", self.significance)
        if self.ear_cut_ratio is not None:
            _positive_number("ear_cut_ratio", self.ear_cut_ratio)
        if self.lambda_h_over_fair3 is not None:
            _positive_number("lambda_h_over_fair3", self.lambda_h_over_fair3)
        if self.ear_cut_flat is not None:
            _positive_number("ear_cut_flat", self.ear_cut_flat)
            if self.ear_cut_flat > 1:
                raise ValueError(f"ear_cut_flat must be at most 1, got {self.ear_cut_flat!r}")
        if self.ear_cut_faired is not None:
            _positive_number("ear_cut_faired", self.ear_cut_faired)
            below = 1.0 if self.ear_cut_flat is None else self.ear_cut_flat
            if self.ear_cut_faired > 1 or (self.ear_cut_flat is not None
                                           and self.ear_cut_faired >= below):
                raise ValueError(f"ear_cut_faired must be below ear_cut_flat ({below!r}) and "
                                 f"at most 1, got {self.ear_cut_faired!r}")
        if isinstance(self.fair_smoothing, str) and self.fair_smoothing != "auto":
            raise ValueError("fair_smoothing must be a positive number, 'auto' or None, got "
                             f"{self.fair_smoothing!r}")
        if self.fair_smoothing is not None and not isinstance(self.fair_smoothing, str):
            _positive_number("fair_smoothing", self.fair_smoothing)
        _positive_int("hide_rings", self.hide_rings)
        _positive_number("continuation_smallest", self.continuation_smallest)
        if self.continuation_smallest > CONTINUATION_STEP:
            raise ValueError(f"continuation_smallest must be at most {CONTINUATION_STEP} (the "
                             f"continuation's first step), got {self.continuation_smallest!r}")
        _positive_int("siblings", self.siblings, minimum=0)
        _positive_int("gap_rings", self.gap_rings, minimum=0)
        for name in ("select", "creases", "plane_test", "skip_stalled_subdivision"):
            if not isinstance(getattr(self, name), bool | np.bool_):
                raise ValueError(f"{name} must be True or False, got {getattr(self, name)!r}")
        if isinstance(self.crease_angle, bool) or not isinstance(
                self.crease_angle, int | float | np.number) \
                or not 0.0 < self.crease_angle < 180.0:
            raise ValueError("crease_angle must be between 0 and 180 degrees, got "
                             f"{self.crease_angle!r}")
        if self.grid is not None and not isinstance(self.grid, GridOptions):
            raise ValueError(f"grid must be a GridOptions, got {type(self.grid).__name__}")
        if self.discretization == "grid" and self.grid is None:
            object.__setattr__(self, "grid", GridOptions())
        if self.discretization == "mesh" and self.grid is not None:
            raise ValueError("grid options apply to discretization='grid' only")

    @property
    def rings_in_patch(self) -> int:
        """``patch_rings``, or the default of the discretization."""
        return PATCH_RINGS[self.discretization] if self.patch_rings is None \
            else int(self.patch_rings)

    def neighbourhood_rings(self, n_edges: int) -> int:
        """Vertex rings around a hole of ``n_edges`` boundary edges that the fill looks at:
        its patch, and with ``select`` the sibling holes and their patches (the size of the
        neighbourhood :func:`surfinpaint.fill_holes` cuts for it)."""
        rings = self.rings_in_patch + 3
        if self.select and self.siblings > 0:
            hole_rings = int(np.ceil(n_edges / (2 * np.pi))) + 1
            rings = max(rings, self.gap_rings + 2 * hole_rings + self.rings_in_patch + 3)
        return rings
