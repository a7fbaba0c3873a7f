"""Typed results of filling one hole: the :class:`Fill` a method returns and the λ-H data a
conformal fill leaves for diagnostics and pictures (drawn in :mod:`surfinpaint.app`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from surfinpaint.fill.conformal.selection import Verdict

__all__ = ["Fill", "GridLambdaH", "LambdaHDiagnostics", "MeshLambdaH"]


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
    """

    uv: np.ndarray
    faces: np.ndarray
    n_fill_faces: int
    free: np.ndarray
    before: np.ndarray
    after: np.ndarray
    one_side: bool = False
    map: str = "lscm"


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
        checks (1: undamped; :func:`surfinpaint.fill.conformal.checks.damped_fill`).
    """

    discretization: str
    rings: int
    reconstruct: str | None = None
    grid: GridLambdaH | None = None
    mesh: MeshLambdaH | None = None
    note: str | None = None
    damping: float = 1.0


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

    @property
    def notes(self) -> str | None:
        """The selection and crease notes in one sentence (None without any)."""
        notes = [n for n in (self.selection, self.crease, self.crease_failure) if n]
        return "; ".join(notes) or None
