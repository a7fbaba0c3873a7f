"""The candidate fills of one hole: the faired fills (bilaplacian, trilaplacian) from one
triangulation, and the λ-H fill, made only when asked (it is the costly one).

The λ-H fill starts from an initial fill S0 (the trilaplacian faired fill unless a fairing
order is asked for, or only triangulated and refined), runs ``passes`` λ-H passes of the
chosen discretization over the hole's patch, and is checked (:mod:`.checks`). A crease that
crosses the hole is continued across it first and each side is filled and inpainted on its
own (:mod:`surfinpaint.fill.creases`): λ and H describe the smooth sides, not the crease.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from surfinpaint.errors import NUMERICAL_ERRORS, FillError
from surfinpaint.fill.conformal.checks import damped_fill
from surfinpaint.fill.conformal.grid_pass import inpaint_patch
from surfinpaint.fill.conformal.mesh_pass import inpaint_patch_on_mesh
from surfinpaint.fill.conformal.options import (
    S0_ORDER,
    SOLVER_TOL,
    TEST_SOLVER_TOL,
    ConformalOptions,
)
from surfinpaint.fill.conformal.patch import hole_patch
from surfinpaint.fill.creases import CREASE_EDGES, hole_creases, split_fill
from surfinpaint.fill.liepa.baseline import conventional_fill, faired_fills
from surfinpaint.fill.results import Fill, LambdaHDiagnostics

__all__ = ["Candidates"]

# candidate name -> fill, or the FillError of a λ-H fill that failed on that hole
Candidate = Fill | FillError


@dataclass(frozen=True)
class Candidates:
    """How the candidate fills of one hole (and of its self-check's test holes) are made.

    Attributes
    ----------
    options : ConformalOptions
    orders : tuple of int
        Fairing orders of the faired candidates (``fair2``, ``fair3``; or the one asked for).
    s0_order : int
        Fairing order of S0 (with ``options.start == "fair"``).
    crease_angle : float, optional
        Creases are looked for (mesh discretization with ``options.creases``); None: every
        hole is filled as smooth.
    crossed : bool
        A crease crosses the hole itself: its test holes are filled along it too, where one
        sharp edge left between them and a corner is enough (the crease is known from the
        hole), and a test hole that is not crossed says nothing about the crease fill.
    creases : tuple of Crease
        The creases that cross the hole (:func:`~surfinpaint.fill.creases.hole_creases`),
        found once for ``crossed`` and for the hole's own λ-H fill (:meth:`lambda_h`'s
        ``creases``).
    """

    options: ConformalOptions
    orders: tuple[int, ...]
    s0_order: int
    crease_angle: float | None
    crossed: bool
    creases: tuple = ()

    @classmethod
    def for_hole(cls, vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                 options: ConformalOptions, fair_order: int | None = None) -> Candidates:
        """The candidates of the hole ``loop`` with ``options`` and the fairing order asked
        for (None: S0 trilaplacian, faired candidates of orders 2 and 3)."""
        angle = options.crease_angle if options.creases and \
            options.discretization == "mesh" else None
        creases = () if angle is None else tuple(hole_creases(vertices, faces, loop,
                                                              angle=angle))
        return cls(options=options, orders=(2, 3) if fair_order is None else (fair_order,),
                   s0_order=S0_ORDER if fair_order is None else fair_order,
                   crease_angle=angle, crossed=len(creases) > 0, creases=creases)

    def faired(self, vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray
               ) -> dict[str, Fill]:
        """The faired candidates ``"fair<k>"`` (one triangulation and refinement shared)."""
        made = faired_fills(vertices, faces, loop, sorted(self.orders),
                            search=self.options.s0_search,
                            refinement=self.options.s0_refinement,
                            smoothing=self.options.fair_smoothing)
        return {f"fair{k}": Fill(made[k][0], made[k][1], "fair", fair_order=made[k][2])
                for k in self.orders}

    def initial(self, vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                faired: dict[str, Fill] | None = None) -> tuple[np.ndarray, np.ndarray]:
        """S0 = (new_vertices, new_faces): the order-``s0_order`` faired fill (taken from
        ``faired`` when given), or only triangulated and refined."""
        if self.options.start == "fair":
            if faired is not None:
                s0 = faired[f"fair{self.s0_order}"]
                return s0.vertices, s0.faces
            new_v, new_f, _ = faired_fills(vertices, faces, loop, [self.s0_order],
                                           search=self.options.s0_search,
                                           refinement=self.options.s0_refinement,
                                           smoothing=self.options.fair_smoothing
                                           )[self.s0_order]
            return new_v, new_f
        new_v, new_f = conventional_fill(vertices, faces, loop, refine=True, fair=False,
                                         search=self.options.s0_search,
                                         refinement=self.options.s0_refinement)
        return np.asarray(new_v, dtype=float), np.asarray(new_f, dtype=np.int64)

    def lambda_h(self, vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                 s0: tuple[np.ndarray, np.ndarray], *, test: bool = False,
                 crease_only: bool = False, creases: tuple | None = None) -> Fill:
        """The λ-H fill from S0; along a crease that crosses the hole when one does (as a
        smooth hole when that fails).

        ``test``: a self-check test hole's fill, scored by its distance to the removed
        surface: its coupled solve stops at a coarser step and is not retried on the
        subdivided patch where it fails, and the costly self-intersection check is left to
        the hole's own fill.

        ``crease_only``: where no crease fill is made (no crease found, or its fill failed),
        raise instead of filling the hole as a smooth one: a test hole of a hole a crease
        crosses scores only a crease fill (:meth:`for_tests`), so the smooth fill would be
        made and thrown away.

        ``creases``: the hole's creases where the caller has them (:attr:`creases`, found
        by :meth:`for_hole` on the same hole with the same arguments); searched here when
        None.

        Raises
        ------
        FillError
            When the λ-H fill fails: a numerical failure of any step (``NUMERICAL_ERRORS``)
            is turned into one here.
        """
        if self.crease_angle is None:
            creases = []
        elif creases is None:
            creases = hole_creases(vertices, faces, loop, angle=self.crease_angle,
                                   min_edges=1 if test and self.crossed else CREASE_EDGES)
        else:
            creases = list(creases)
        crease_failure = None
        if creases:
            try:
                cv, cf, cut_edges = split_fill(vertices, faces, loop, creases,
                                               order=self.s0_order, angle=self.crease_angle)
                fill = self._passes(vertices, faces, loop, cv, cf, test=test,
                                    cut_edges=cut_edges)
                return replace(fill, crease=_crease_words(creases))
            except NUMERICAL_ERRORS as exc:
                if crease_only:
                    raise FillError(f"the crease fill failed ({exc})") from exc
                crease_failure = f"the crease fill failed ({exc}), filled as a smooth hole"
        if crease_only:
            raise FillError("no crease crosses the test hole")
        try:
            fill = self._passes(vertices, faces, loop, *s0, test=test)
        except FillError as exc:
            fill = self._on_lattice_after_fold(exc, vertices, faces, loop, s0, test)
        except NUMERICAL_ERRORS as exc:
            raise FillError(f"{type(exc).__name__}: {exc}") from exc
        return replace(fill, crease_failure=crease_failure)

    def for_tests(self, *, with_lambda_h: bool = True
                  ) -> Callable[[np.ndarray, np.ndarray, np.ndarray], dict[str, Candidate]]:
        """The candidates of a self-check test hole, as :mod:`surfinpaint.fill.selfcheck`
        takes them: function(vertices, faces, loop) -> name -> Fill (or the FillError of a
        λ-H fill that failed there)."""
        def fills(vertices, faces, loop) -> dict[str, Candidate]:
            out: dict[str, Candidate] = dict(self.faired(vertices, faces, loop))
            if not with_lambda_h:
                return out
            s0 = self.initial(vertices, faces, loop, out)
            try:
                # a test hole of a hole a crease crosses scores only a crease fill
                out["conformal"] = self.lambda_h(vertices, faces, loop, s0, test=True,
                                                 crease_only=self.crossed)
            except FillError as exc:
                out["conformal"] = exc
            return out
        return fills

    def _on_lattice_after_fold(self, exc: FillError, vertices, faces, loop, s0, test) -> Fill:
        """The λ-H fill made again on a regular lattice of the patch's map, where the one on
        the patch's own triangles folded over or cut through the surface at every damping
        step (``exc``, which carries it as its ``rejected``) and was not made on the lattice
        already; else, or when that fails too, ``exc`` is raised again (its blend stands).

        Why: on a coarse or irregular thin part the fill's own triangles fold (S0's do, in
        3D); the lattice's do not, and the fill read back from it often passes the checks.
        On the built animals (decimated to 5000 faces, Loop-subdivided once) two of the
        five holes that fell back: 13.44 → 8.30 % and 21.60 → 18.16 % of the hole's
        diameter (the better faired fill 12.31 and 20.08 %; docs/convergence.md, session
        23). Not for a self-check test hole (its failure only makes it say nothing), the
        grid discretization or a crease's sides (no lattice there).
        """
        rejected = getattr(exc, "rejected", None)
        mesh = rejected is not None and rejected.diagnostics and rejected.diagnostics.mesh
        if (test or not mesh or self.options.discretization != "mesh"
                or (mesh.least_squares and mesh.least_squares.lattice)):
            raise exc
        try:
            return self._passes(vertices, faces, loop, *s0, test=test, lattice_after=str(exc))
        except NUMERICAL_ERRORS:
            raise exc from None

    def _passes(self, vertices, faces, loop, new_v, new_f, *, test, cut_edges=None,
                lattice_after: str = "") -> Fill:
        """``options.passes`` λ-H passes over S0 = (new_v, new_f), then the checks."""
        o = self.options
        n = len(vertices)
        moving = np.arange(n, n + len(new_v))
        if cut_edges is not None:  # the crease's points in the fill stay where they are put
            moving = np.setdiff1d(moving, cut_edges)
        if len(moving) == 0:
            return Fill(new_v, new_f, "conformal", diagnostics=LambdaHDiagnostics(
                o.discretization, rings=0, note="no interior vertices to move"))
        all_v = np.concatenate([vertices, new_v])
        start = all_v[moving].copy()
        rings = o.rings_in_patch
        if o.discretization == "mesh":
            tol = o.solver_tol if o.solver_tol is not None else (
                TEST_SOLVER_TOL if test else SOLVER_TOL)
            for _ in range(o.passes):
                positions, patch, used, mesh = inpaint_patch_on_mesh(
                    all_v, faces, loop, new_f, moving, rings=rings,
                    iterations=o.solver_iterations, tol=tol, cut_edges=cut_edges,
                    subdivide=not test, lattice_after=lattice_after,
                    skip_stalled_subdivision=o.skip_stalled_subdivision,
                    continuation_smallest=o.continuation_smallest)
                all_v[moving] = positions
            diagnostics = LambdaHDiagnostics("mesh", used, mesh=mesh)
        else:
            patch, used = hole_patch(faces, loop, new_f, rings)
            for _ in range(o.passes):
                positions, grid, reconstruct = inpaint_patch(all_v, patch, len(new_f), moving,
                                                             o.grid)
                all_v[moving] = positions
            diagnostics = LambdaHDiagnostics("grid", used, reconstruct=reconstruct, grid=grid)
        try:
            all_v, damping = damped_fill(all_v, start, moving, patch, len(new_f),
                                         self_crossing=not test, crease=cut_edges)
        except FillError as exc:
            if getattr(exc, "rejected", None) is not None:  # for a blended fallback
                exc.rejected = replace(exc.rejected, diagnostics=diagnostics)
            least_squares = diagnostics.mesh and diagnostics.mesh.least_squares
            if not least_squares:
                raise
            # the fallback's reason says that the coupled solve failed first
            said = type(exc)(f"{least_squares.unsolved}; {least_squares.sentence()}, "
                             f"fails: {exc}")
            said.rejected = getattr(exc, "rejected", None)  # for a blended fallback
            raise said from None
        return Fill(all_v[n:], new_f, "conformal", diagnostics=replace(diagnostics,
                                                                        damping=damping))


def _crease_words(creases) -> str:
    """The crease note of a fill along ``creases``."""
    angles = ", ".join(f"{c.angle:.0f}°" for c in creases)
    if creases[0].corner is not None:
        return (f"a corner of {len(creases[0].ends)} creases ({angles}) in the hole: each "
                "continued to it, each face inpainted on its own")
    if len(creases) == 1:
        return (f"a crease ({angles}) crosses the hole: continued across it, each side "
                "inpainted on its own")
    return (f"{len(creases)} creases ({angles}) cross the hole: continued across it, each "
            "region between them inpainted on its own")
