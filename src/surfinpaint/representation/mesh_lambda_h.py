"""λ-H on a mesh's own parameter triangles, and the Newton rebuild of the mesh from them.

The discretization is the one of :mod:`surfinpaint.representation.on_mesh`: the parameter
mesh's cotangent Laplacian ``L`` and Voronoi areas ``M`` give ``Δφ ≈ M⁻¹ L φ``, λ² is the
ratio of a vertex's 3D to its parameter Voronoi area, and ``H = n · Δφ / (2λ²)`` with the
area-weighted vertex normal ``n``. For a smooth conformal φ, Δφ is normal (method.md §1);
on a mesh it is not quite: the discrete map is conformal only up to the triangles' shapes,
and ``M⁻¹ L φ`` has a tangential part (measured: a median 2-26 % of its length on the
benchmark disks, up to 100 % on slivers). That part is the *conformality defect*
``a e1 + b e2`` in the orthonormal tangent frame ``e1 = w / |w|``, ``e2 = n × e1`` with
``w = P φ_u − n × φ_v`` (``P`` the tangent projection, ``φ_u``, ``φ_v`` the area-weighted
vertex gradients over the parameter triangles). For a conformal φ, ``n × φ_v = −φ_u`` and
``w = 2 φ_u``; unlike ``P φ_u`` alone, w vanishes only where the map is locally
anti-conformal, so the frame stays smooth where a rebuild's intermediate surface turns
φ_u along the normal (measured on the 70 mm pial disk: |P φ_u| fell to 4e-4 |φ_u| and the
continuation stalled there with the frame ``P φ_u / |P φ_u|``). The defect vanishes in
the continuum (``<Δφ, φ_u> = ½(E − G)_u + F_v = 0`` for a conformal φ), so (λ, H) are
the paper's representation and (a, b) what the discretization adds to make the rebuild
exact:

    L φ = M (2λ²H n(φ) + a e1(φ) + b e2(φ))     at the unknown vertices,

with the known vertices (at least the border) fixed. The original mesh solves it to rounding
error. :func:`rebuild_on_mesh` solves it by damped Newton with the exact Jacobian from the
harmonic surface, and when that does not converge (on caps: a tall finger, a bunny's ear),
by pseudo-arclength continuation of the equations with their data scaled by t from 0 (the
harmonic surface) to 1 (:mod:`~surfinpaint.representation.continuation`), which goes round
the folds where stepping t stalls. It reports whether it converged; it never stops
silently at a limit.

The equations need not have one solution only: they use λ only through 2λ²H, and on large,
strongly folded disks (a 70 mm pial disk) another surface solves them on the same triangles
(residual 1e-12, 0.18 % of the diagonal away). The vertex areas that λ prescribes tell the
solutions apart (:func:`area_mismatch`, zero to rounding for the original): the
continuation takes the first crossing of t = 1 whose areas match.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from surfinpaint.errors import how_many
from surfinpaint.geometry.linalg import factorized_ordered
from surfinpaint.geometry.linalg import nested_dissection as dissection_order
from surfinpaint.geometry.mesh import (
    boundary_loops,
    cotangent_laplacian,
    face_cross,
    mass_matrix,
    vertex_normals,
)
from surfinpaint.representation.continuation import arclength_continuation
from surfinpaint.representation.damped_newton import damped_newton

# damped Newton steps tried from the start before the continuation
NEWTON_STEPS = 12
# the softened unit vectors (see soft_unit): the frame's w is cut off below this fraction
# of its conformal length 2λ, the vertex normal's N below this fraction of 6 λ² A_uv (its
# length on the original, twice the one-ring's area)
SOFTENING = 0.01
# vertex areas within this relative difference of λ²'s: the original, not another solution
AREA_MATCH = 1e-6
# with nested_dissection=True, Newton's Jacobians of more unknown vertices than this are
# factored in nested-dissection order (smaller ones keep their bit-identical solves)
ORDERED_ABOVE = 20000

__all__ = [
    "MeshSolve",
    "RebuildSystem",
    "area_mismatch",
    "area_vectors",
    "cross_matrices",
    "gradient_operators",
    "mesh_lambda_h",
    "normals_with_jacobian",
    "rebuild_on_mesh",
    "relative_residual",
]


def gradient_operators(uv: np.ndarray, faces: np.ndarray) -> tuple[sp.csr_matrix, sp.csr_matrix]:
    """Sparse ``(G_u, G_v)``: the parameter-area-weighted mean over a vertex's triangles of
    the gradient of a piecewise-linear function, so ``G_u φ`` is ``φ_u`` at the vertices.

    Parameters
    ----------
    uv : (n, 2) float array
    faces : (f, 3) int array

    Returns
    -------
    G_u, G_v : (n, n) sparse matrices
    """
    q = np.asarray(uv, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    n = len(q)
    e1, e2 = q[f[:, 1]] - q[f[:, 0]], q[f[:, 2]] - q[f[:, 0]]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    area = np.abs(det) / 2
    safe = np.where(det != 0, det, 1.0)
    weight = np.zeros(n)
    for k in range(3):
        np.add.at(weight, f[:, k], area)
    weight = np.where(weight > 0, weight, 1.0)
    rows = np.repeat(f[:, :, None], 3, axis=2).ravel()  # [face, corner i, corner k]
    cols = np.repeat(f[:, None, :], 3, axis=1).ravel()
    ops = []
    # φ_u = c1 (φ1 − φ0) + c2 (φ2 − φ0): the rows of [e1; e2]⁻¹ per derivative
    for c1, c2 in ((e2[:, 1], -e1[:, 1]), (-e2[:, 0], e1[:, 0])):
        c1, c2 = c1 / safe, c2 / safe
        coef = np.column_stack([-c1 - c2, c1, c2]) * area[:, None]  # (f, 3) per corner k
        vals = np.repeat(coef[:, None, :], 3, axis=1).ravel()
        G = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
        ops.append((sp.diags(1.0 / weight) @ G).tocsr())
    return ops[0], ops[1]


def cross_matrices(a: np.ndarray) -> np.ndarray:
    """(k, 3, 3) matrices ``[a]×`` with ``[a]× b = a × b``."""
    X = np.zeros((len(a), 3, 3))
    X[:, 0, 1], X[:, 0, 2] = -a[:, 2], a[:, 1]
    X[:, 1, 0], X[:, 1, 2] = a[:, 2], -a[:, 0]
    X[:, 2, 0], X[:, 2, 1] = -a[:, 1], a[:, 0]
    return X


def _blocks(rows: np.ndarray, cols: np.ndarray, blocks: np.ndarray, n: int) -> sp.csr_matrix:
    """The (3n, 3n) sparse matrix with 3×3 ``blocks`` at vertex pairs (rows, cols), summed."""
    r = (3 * rows[:, None, None] + np.arange(3)[None, :, None]).repeat(3, axis=2)
    c = (3 * cols[:, None, None] + np.arange(3)[None, None, :]).repeat(3, axis=1)
    return sp.csr_matrix((blocks.ravel(), (r.ravel(), c.ravel())), shape=(3 * n, 3 * n))


def normals_with_jacobian(points: np.ndarray, faces: np.ndarray,
                          eps: np.ndarray | None = None) -> tuple[np.ndarray, sp.csr_matrix]:
    """Area-weighted unit vertex normals and their derivative with respect to the positions.

    ``N_i = Σ_f (p1 − p0) × (p2 − p0)`` over the faces of i and ``n_i = N_i / |N_i|``;
    ``∂N_i/∂p_k = [p_{k+2} − p_{k+1}]×`` for corner k of a face of i, and
    ``dn = (I − n nᵀ) dN / |N|``. With ``eps``, ``n_i = soft_unit(N_i, eps_i)`` instead
    (unit where ``|N_i| ≥ eps_i``; :func:`soft_unit`).

    Returns
    -------
    normals : (n, 3) float array
    D : (3n, 3n) sparse matrix
        ``d(normals).ravel() = D @ d(points).ravel()``.
    """
    p = np.asarray(points, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    n = len(p)
    N = area_vectors(p, f)
    if eps is None:
        length = np.linalg.norm(N, axis=1)
        length = np.where(length > 0, length, 1.0)
        unit = N / length[:, None]
        P = (np.eye(3)[None] - unit[:, :, None] * unit[:, None, :]) / length[:, None, None]
    else:
        unit, k, k1 = soft_unit(N, eps)
        P = _soft_jacobian(N, k, k1)
    rows, cols, blocks = [], [], []
    for k in range(3):
        X = cross_matrices(p[f[:, (k + 2) % 3]] - p[f[:, (k + 1) % 3]])
        for i in range(3):
            rows.append(f[:, i])
            cols.append(f[:, k])
            blocks.append(np.einsum("fab,fbc->fac", P[f[:, i]], X))
    return unit, _blocks(np.concatenate(rows), np.concatenate(cols),
                         np.concatenate(blocks), n)


def mesh_lambda_h(points: np.ndarray, faces: np.ndarray, uv: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """λ, H and the conformality defect (α, β) at the vertices of a conformally mapped mesh.

    Parameters
    ----------
    points : (n, 3) float array
    faces : (f, 3) int array
        Counter-clockwise in ``uv``.
    uv : (n, 2) float array
        A conformal map without folded triangles.

    Returns
    -------
    lam : (n,) float array
        ``sqrt(A_3D / A_uv)`` (Voronoi areas), as
        :func:`~surfinpaint.representation.on_mesh.vertex_lambda_h`.
    H : (n,) float array
        ``n · M⁻¹ L φ / (2λ²)``, as ``vertex_lambda_h``; NaN on the border.
    defect : (n, 2) float array
        (α, β): the tangential part of ``M⁻¹ L φ`` is ``P(α φ_u + β φ_v)``; NaN on the
        border.
    """
    p = np.asarray(points, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    L = cotangent_laplacian(uv, f)
    area_uv = mass_matrix(uv, f).diagonal()
    lam2 = _per_uv_area(mass_matrix(p, f).diagonal(), area_uv)
    normal = vertex_normals(p, f)
    lap = _per_uv_area(L @ p, area_uv)
    along = np.einsum("ij,ij->i", lap, normal)
    H = along / (2.0 * lam2)
    G_u, G_v = gradient_operators(uv, f)
    lam = np.sqrt(lam2)
    eps_w, eps_n = softening(lam, area_uv)
    # the rebuild's (softened) normal; on the original it is the unit one wherever the
    # one-ring's area vector is longer than eps_n (all vertices but a folded one-ring's)
    soft = soft_unit(area_vectors(p, f), eps_n)[0]
    e1, e2, _, _ = _frame(G_u @ p, G_v @ p, soft, eps_w)
    tangential = lap - along[:, None] * normal
    length2 = np.einsum("ij,ij->i", e1, e1)  # e1 ⊥ e2, both of this squared length
    length2 = np.where(length2 > 0, length2, 1.0)
    defect = np.column_stack([np.einsum("ij,ij->i", tangential, e1) / length2,
                              np.einsum("ij,ij->i", tangential, e2) / length2])
    border = np.concatenate(boundary_loops(f)) if len(f) else np.zeros(0, np.int64)
    H[border] = np.nan
    defect[border] = np.nan
    return lam, H, defect


def _per_uv_area(values: np.ndarray, area_uv: np.ndarray) -> np.ndarray:
    """``values / area_uv`` per vertex (rows), NaN at a vertex of no area: one on no face
    (unreferenced; its uv is NaN too), where the division would be 0/0 and numpy would
    warn of it (``represent`` of a mesh with unused vertices printed "invalid value
    encountered in divide (×14)")."""
    values = np.asarray(values, dtype=float)
    out = np.full(values.shape, np.nan)
    has_area = area_uv != 0  # as before wherever the division is defined
    out[has_area] = values[has_area] / (area_uv[has_area] if values.ndim == 1
                                        else area_uv[has_area, None])
    return out


def area_vectors(points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """``N_i = Σ_f (p1 − p0) × (p2 − p0)`` over the faces of each vertex."""
    c = face_cross(points, faces)
    N = np.zeros((len(points), 3))
    for k in range(3):
        np.add.at(N, faces[:, k], c)
    return N


def soft_unit(x: np.ndarray, eps: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``x / |x|`` softened below ``|x| = ε``: ``x k(|x|)`` with ``k(ρ) = 1 / ρ`` for
    ρ ≥ ε and ``k(ρ) = (2 − ρ/ε) / ε`` below, so the vector is unit where ``|x| ≥ ε`` and
    goes smoothly (C¹) to zero with x instead of jumping.

    Why: a rebuild's intermediate surfaces can fold a vertex's one-ring (its area vector N
    vanishes) or make its map anti-conformal there (the frame's w vanishes); the unit
    vectors are not continuous there, and the continuation's curve ended at such points
    (measured: the cow's hoof cap at t = 0.584, |w| = 1e-5 |φ_u|; the 70 mm pial disk at
    t = 0.188, |N| = 6e-6 of the one-ring's area, docs/representation.md). Softened, the
    equations are smooth everywhere and unchanged wherever ``|x| ≥ ε``, the original
    mesh among those points.

    Parameters
    ----------
    x : (n, 3) float array
    eps : (n,) float array
        Positive.

    Returns
    -------
    y : (n, 3) float array
        The softened unit vectors.
    k, k1 : (n,) float arrays
        ``k(|x|)`` and ``k'(|x|) |x|``: ``dy = (k I + k1 x̂ x̂ᵀ) dx``.
    """
    rho = np.sqrt(np.einsum("ij,ij->i", x, x))
    inside = rho < eps
    safe = np.where(rho > 0, rho, 1.0)
    k = np.where(inside, (2.0 - rho / eps) / eps, 1.0 / safe)
    # -ρ/ε² is -0 at ρ = 0 whatever ε, not 0/0 where ε² underflows (a vertex on no face has
    # no area and the least ε: represent warned "invalid value encountered in divide")
    k1 = np.where(inside, np.divide(-rho, eps**2, out=np.full(rho.shape, -0.0),
                                    where=inside & (rho > 0)), -1.0 / safe)
    return x * k[:, None], k, k1


def _soft_jacobian(x: np.ndarray, k: np.ndarray, k1: np.ndarray) -> np.ndarray:
    """(n, 3, 3) ``k I + k1 x̂ x̂ᵀ`` of :func:`soft_unit`."""
    rho = np.linalg.norm(x, axis=1)
    unit = x / np.where(rho > 0, rho, 1.0)[:, None]
    return (k[:, None, None] * np.eye(3)[None]
            + k1[:, None, None] * unit[:, :, None] * unit[:, None, :])


def softening(lam: np.ndarray, area_uv: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """ε of :func:`soft_unit` for the frame's w and for the vertex normal's N at each
    vertex: ``SOFTENING`` times their lengths on a conformal mesh with this λ, 2λ and
    ``6 λ² A_uv``."""
    lam = np.where(np.isfinite(lam) & (lam > 0), lam, 1.0)
    tiny = np.finfo(float).tiny
    return (np.maximum(SOFTENING * 2.0 * lam, tiny),
            np.maximum(SOFTENING * 6.0 * lam**2 * area_uv, tiny))


def _frame(g_u: np.ndarray, g_v: np.ndarray, normal: np.ndarray, eps: np.ndarray
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """The tangent frame ``e1 = soft_unit(w)``, ``e2 = n × e1`` with
    ``w = g_u − (g_u·n) n − n × g_v``; and w with :func:`soft_unit`'s (k, k1)."""
    w = (g_u - np.einsum("ij,ij->i", g_u, normal)[:, None] * normal
         - np.cross(normal, g_v))
    e1, k, k1 = soft_unit(w, eps)
    return e1, np.cross(normal, e1), w, (k, k1)


@dataclass(frozen=True)
class MeshSolve:
    """The outcome of :func:`rebuild_on_mesh`.

    Attributes
    ----------
    points : (n, 3) float array
        The rebuilt positions (the known ones unchanged).
    converged : bool
        The last Newton step was a full step shorter than ``tol`` times the border's size.
    iterations : int
        Sparse factorizations: Newton steps, continuation steps and the Newton steps at
        the continuation's crossings of t = 1.
    step : float
        Length of the last step relative to the border's bounding-box diagonal.
    residual : float
        ``|R| / |L φ|`` at the end, R the residual of the equations at the unknowns.
    method : str
        ``"newton"`` (damped Newton from the start converged) or ``"continuation"`` (it
        did not, or its solution's areas did not match λ; pseudo-arclength continuation
        from the harmonic surface was used).
    area_mismatch : float
        :func:`area_mismatch` of the result: ~1e-13 for the original, large for another
        solution of the same equations (or for data that are not a mesh's own).
    message : str
        What happened, in words.
    seconds : float
    """

    points: np.ndarray
    converged: bool
    iterations: int
    step: float
    residual: float
    method: str
    area_mismatch: float
    message: str
    seconds: float


class RebuildSystem:
    """The rebuild equations (data scaled by t), restricted to the unknown vertices:
    ``R(φ) = L φ − t M (s n + a e1 + b e2)`` with s = 2λ²H and (a, b) the defect."""

    def __init__(self, faces, uv, lam, H, defect, unknown, nested_dissection=False):
        self.faces = faces
        self.uv = uv
        self.nested_dissection = nested_dissection
        self._order = None
        self.L = cotangent_laplacian(uv, faces).tocsr()
        self.area = mass_matrix(uv, faces).diagonal()
        self.G_u, self.G_v = gradient_operators(uv, faces)
        self.s = np.where(unknown, 2.0 * lam**2 * H, 0.0)
        self.a = np.where(unknown, defect[:, 0], 0.0)
        self.b = np.where(unknown, defect[:, 1], 0.0)
        self.eps_w, self.eps_n = softening(lam, self.area)
        self.L3 = sp.kron(self.L, sp.eye(3), format="csr")
        self.G3 = sp.kron(self.G_u, sp.eye(3), format="csr")
        self.G3v = sp.kron(self.G_v, sp.eye(3), format="csr")
        self.idx = np.flatnonzero(np.repeat(unknown, 3))
        self.n = len(uv)

    def factorized(self, J):
        """A solver for the Jacobian ``J`` (restricted to the unknowns): SuperLU's minimum
        degree order; with ``nested_dissection`` and above ``ORDERED_ABOVE`` unknown
        vertices, :func:`~surfinpaint.geometry.linalg.nested_dissection` over the vertices
        (a vertex's three coordinates together), its separators taken from J's own pattern.

        Why per discretization: on an irregular mesh's disk the order costs ~1.6x less CPU
        a factorization (104,635 vertices: 11.9-16.6 -> 7.2-10.0 s); on the grid export's
        levels minimum degree is the faster one (docs/representation.md, sessions 14, 16)."""
        if not self.nested_dissection or len(self.idx) <= 3 * ORDERED_ABOVE:
            return spla.splu(J, permc_spec="MMD_AT_PLUS_A").solve
        if self._order is None:
            # J's pattern collapsed to its vertices (sums of |J|: nothing cancels), so the
            # separators separate J itself (L's pattern misses the edges whose cotangent
            # weight vanishes)
            m = len(self.idx) // 3
            collapse = sp.kron(sp.eye(m, format="csr"), np.ones((1, 3)), format="csr")
            adjacency = collapse @ abs(sp.csr_matrix(J)) @ collapse.T
            vertex_order = dissection_order(adjacency, self.uv[self.idx[::3] // 3])
            self._order = (3 * vertex_order[:, None] + np.arange(3)).ravel()
        return factorized_ordered(J, self._order)

    def normals(self, phi):
        return soft_unit(area_vectors(phi, self.faces), self.eps_n)[0]

    def force(self, phi, normal):
        e1, e2, _, _ = _frame(self.G_u @ phi, self.G_v @ phi, normal, self.eps_w)
        return self.s[:, None] * normal + self.a[:, None] * e1 + self.b[:, None] * e2

    def residual(self, phi, t):
        force = self.force(phi, self.normals(phi))
        return (self.L @ phi - t * self.area[:, None] * force).ravel()[self.idx]

    def rounding(self, phi, t):
        """The residual's norm that rounding alone leaves: eps times the norm of the
        terms' magnitudes."""
        force = np.abs(self.force(phi, self.normals(phi)))
        terms = abs(self.L) @ np.abs(phi) + t * self.area[:, None] * force
        return np.finfo(float).eps * float(np.linalg.norm(terms.ravel()[self.idx]))

    def jacobian(self, phi, t):
        # dF = (B − K C') dn + K P dg_u − K [n]× dg_v with w = P g_u − n × g_v,
        # de1 = Q dw (Q = soft_unit's derivative), dw = P dg_u − [n]× dg_v − C' dn,
        # P = I − n nᵀ, C' = (g_u·n) I + n g_uᵀ − [g_v]× (n the softened normal)
        normal, D = normals_with_jacobian(phi, self.faces, self.eps_n)
        g, g_v = self.G_u @ phi, self.G_v @ phi
        ng = np.einsum("ij,ij->i", g, normal)
        e1, _, w, (k, k1) = _frame(g, g_v, normal, self.eps_w)
        eye = np.eye(3)[None]
        P = eye - normal[:, :, None] * normal[:, None, :]
        Q = _soft_jacobian(w, k, k1)
        C = (ng[:, None, None] * eye + normal[:, :, None] * g[:, None, :]
             - cross_matrices(g_v))
        N = cross_matrices(normal)
        K = (self.a[:, None, None] * eye + self.b[:, None, None] * N) @ Q
        B = self.s[:, None, None] * eye - self.b[:, None, None] * cross_matrices(e1)
        scale = t * self.area[:, None, None]
        ids = np.arange(self.n)
        on_D = _blocks(ids, ids, scale * (B - K @ C), self.n)
        on_G = _blocks(ids, ids, scale * (K @ P), self.n)
        on_Gv = _blocks(ids, ids, scale * (K @ N), self.n)
        J = self.L3 - on_D @ D - on_G @ self.G3 + on_Gv @ self.G3v
        return J[self.idx][:, self.idx].tocsc(), normal


def area_mismatch(points: np.ndarray, faces: np.ndarray, uv: np.ndarray,
                  lam: np.ndarray) -> float:
    """Largest relative difference between a surface's vertex areas and the ones λ
    prescribes, ``max |A_3D / (λ² A_uv) − 1|`` (Voronoi areas, as in :func:`mesh_lambda_h`).

    The rebuild equations use λ only through 2λ²H; this is what tells their solutions apart
    (zero to rounding for the original).
    """
    target = lam**2 * mass_matrix(uv, faces).diagonal()
    used = target > 0
    area = mass_matrix(points, faces).diagonal()
    return float(np.abs(area[used] / target[used] - 1.0).max()) if used.any() else 0.0


def relative_residual(points: np.ndarray, faces: np.ndarray, uv: np.ndarray, lam: np.ndarray,
                      H: np.ndarray, defect: np.ndarray | None, known: np.ndarray) -> float:
    """``|R| / |L φ|`` of the rebuild equations at the unknown vertices (as
    :attr:`MeshSolve.residual`): ~1e-13 for a solution."""
    known, lam, H, defect = _rebuild_inputs(len(points), known, lam, H, defect)
    system = RebuildSystem(np.asarray(faces, dtype=np.int64), np.asarray(uv, dtype=float),
                           lam, H, defect, ~known)
    x = np.asarray(points, dtype=float)
    size = np.linalg.norm((system.L @ x).ravel()[system.idx]) or 1.0
    return float(np.linalg.norm(system.residual(x, 1.0)) / size)


def rebuild_on_mesh(points: np.ndarray, faces: np.ndarray, uv: np.ndarray, lam: np.ndarray,
                    H: np.ndarray, defect: np.ndarray | None, known: np.ndarray, *,
                    tol: float = 1e-10, max_iter: int = 200,
                    start: np.ndarray | None = None, select_by_area: bool = True,
                    nested_dissection: bool = False) -> MeshSolve:
    """Solve ``L φ = M (2λ²H n(φ) + P(φ)(α G_u + β G_v) φ)`` for the unknown vertices.

    Parameters
    ----------
    points : (n, 3) float array
        Positions; only the ``known`` ones are read (unless ``start`` is not given and they
        are used for nothing else either: the start is the harmonic surface).
    faces : (f, 3) int array
        Counter-clockwise in ``uv``.
    uv : (n, 2) float array
    lam, H : (n,) float arrays
        Needed (finite) at the unknown vertices.
    defect : (n, 2) float array or None
        The conformality defect (α, β) of :func:`mesh_lambda_h`; ``None`` or zeros give the
        paper's equation ``Δφ = 2λ²H n`` (exact only for an exactly conformal mesh).
    known : (n,) bool array
        Fixed vertices; must contain the border (H has no two-sided Laplacian there).
    tol : float
        Converged when a full Newton step is shorter than ``tol`` times the diagonal of the
        known vertices' bounding box.
    max_iter : int
        Sparse factorizations allowed in all: Newton steps, continuation steps and the
        Newton steps at its crossings of t = 1.
    start : (n, 3) float array, optional
        Initial positions of the unknown vertices for Newton's method; default the
        harmonic surface (``L φ = 0``) with the known ones as boundary data. The
        continuation always starts from the harmonic surface.
    select_by_area : bool
        λ, H and the defect are a mesh's own: a Newton solution whose vertex areas do not
        match λ's (:func:`area_mismatch` above ``AREA_MATCH``) is another solution of the
        equations, so the continuation looks for the one that matches. With inpainted or
        edited data no solution matches exactly: pass False to take Newton's.
    nested_dissection : bool
        Factor Newton's Jacobians of more than ``ORDERED_ABOVE`` unknown vertices in
        nested-dissection order (:meth:`RebuildSystem.factorized`): faster on an irregular
        mesh's disk, slower on a grid's right triangles (the grid export leaves it off).
        The solutions agree to rounding.

    Returns
    -------
    MeshSolve
        With ``converged`` False (and why in ``message``) when the budget ran out; never
        silently.

    Raises
    ------
    ValueError
        On bad shapes, or λ, H not finite at an unknown vertex, or no known vertex.
    """
    started = time.perf_counter()
    p = np.asarray(points, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    known, lam, H, defect = _rebuild_inputs(len(p), known, lam, H, defect)
    unknown = ~known
    phi = p.copy()
    if not unknown.any():
        return MeshSolve(phi, True, 0, 0.0, 0.0, "newton", 0.0, "nothing to rebuild",
                         time.perf_counter() - started)
    uv = np.asarray(uv, dtype=float)
    system = RebuildSystem(f, uv, lam, H, defect, unknown, nested_dissection)
    scale = float(np.linalg.norm(np.ptp(p[known], axis=0))) or 1.0
    L = system.L
    lu = spla.splu(L[unknown][:, unknown].tocsc(), permc_spec="MMD_AT_PLUS_A")
    phi[unknown] = lu.solve(-(L[unknown][:, known] @ p[known]))  # harmonic: t = 0
    first = phi if start is None else np.where(unknown[:, None], start, p)
    x, ok, used, step = damped_newton(system, first, 1.0, tol, min(NEWTON_STEPS, max_iter),
                                      scale)
    mismatch = area_mismatch(x, f, uv, lam) if ok else np.inf
    method, note = "newton", ""
    if (not ok or (select_by_area and mismatch > AREA_MATCH)) and max_iter > used:
        arc = _continuation(system, phi, scale, tol, max_iter - used,
                            (f, uv, lam) if select_by_area else None)
        used += arc.steps
        if arc.score < mismatch or not ok:
            x, ok, method = arc.points, np.isfinite(arc.score), "continuation"
            step = tol if ok else np.nan
        note = arc.message
    mismatch = area_mismatch(x, f, uv, lam)
    r = system.residual(x, 1.0)
    size = np.linalg.norm((system.L @ x).ravel()[system.idx]) or 1.0
    if ok:
        message = f"{method} converged in {how_many(used, 'step', 'steps')}"
    else:
        message = f"did not converge: {how_many(used, 'step', 'steps')} ({method})"
    message += (f", vertex areas within {mismatch:.1e} of λ's"
                + (f" ({note})" if note else ""))
    return MeshSolve(x, ok, used, float(step), float(np.linalg.norm(r) / size), method,
                     mismatch, message, time.perf_counter() - started)


def _rebuild_inputs(n: int, known, lam, H, defect):
    """:func:`rebuild_on_mesh`'s data as arrays, checked: ``known`` an (n,) mask with a
    vertex, λ, H and the defect (zeros when None) finite at every unknown vertex."""
    known = np.asarray(known, dtype=bool)
    if known.shape != (n,) or not known.any():
        raise ValueError("known must be an (n,) boolean mask with at least one vertex")
    lam = np.asarray(lam, dtype=float)
    H = np.asarray(H, dtype=float)
    defect = np.zeros((n, 2)) if defect is None else np.asarray(defect, dtype=float)
    for name, a in (("lam", lam), ("H", H), ("defect", defect)):
        bad = np.flatnonzero(~known & ~np.isfinite(a.reshape(n, -1)).all(axis=1))
        if len(bad):
            raise ValueError(f"{name} is not finite at {len(bad)} unknown vertices, e.g. "
                             f"{bad[:5].tolist()}")
    return known, lam, H, defect


def _continuation(system, harmonic: np.ndarray, scale: float, tol: float, budget: int,
                  area_data: tuple | None):
    """The arclength continuation from the harmonic surface to t = 1, Newton's method at
    its crossings; scored by the vertex areas' mismatch with λ's when ``area_data`` (faces,
    uv, λ) is given, else it stops at the first crossing."""
    def newton(y):
        y, converged, k, _ = damped_newton(system, y, 1.0, tol, NEWTON_STEPS, scale)
        return y, converged, k

    def score(y):
        return 0.0 if area_data is None else area_mismatch(y, *area_data)

    return arclength_continuation(system, harmonic, scale, newton, score,
                                  np.inf if area_data is None else AREA_MATCH, budget)
