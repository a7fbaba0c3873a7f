"""Conformal maps of disk-topology triangle meshes to the plane, and their quality.

Two maps are offered, as in the paper's pipeline (method.md §6.4):

- :func:`lscm`, the least-squares conformal map of Lévy, Petitjean, Ray, Maillot 2002
  (free boundary, two pinned boundary vertices);
- :func:`rectangular_conformal_map`, a conformal map onto a rectangle whose aspect ratio is the
  conformal modulus of the disk with four marked boundary corners (the parameter domain of
  Meng, Choi, Lui 2016).

Both keep the faces' orientation: a counter-clockwise parameter triangle is a face whose 3D
normal is ``φu × φv``, the normal convention of method.md §1.

:func:`conformal_distortion` and :func:`angle_distortion` measure how conformal a map is
(the paper's Fig. 1(D) histogram is :func:`distortion_histogram`), :func:`flipped_faces` finds
folded parameter triangles and :func:`collapsed_faces` those squashed flat.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import scipy.sparse as sp
from scipy.sparse import csgraph

from surfinpaint.errors import MeshError, agreeing, how_many, preview
from surfinpaint.geometry.edges import EdgeTable
from surfinpaint.geometry.linalg import (
    factorized_definite,
    factorized_definite_ordered,
    nested_dissection,
)
from surfinpaint.geometry.mesh import (
    boundary_halfedges,
    boundary_loops,
    cotangent_laplacian,
    face_areas,
)
from surfinpaint.geometry.rows import row_norms, rows_any

__all__ = [
    "angle_distortion",
    "check_disk",
    "collapsed_faces",
    "conformal_distortion",
    "disk_boundary",
    "distortion_histogram",
    "flipped_faces",
    "lscm",
    "pinched_vertices",
    "rectangular_conformal_map",
    "scale_to_area",
    "signed_areas",
]


def check_disk(vertices: np.ndarray, faces: np.ndarray) -> None:
    """Raise unless the mesh is a topological disk without degenerate triangles.

    A disk is one connected component with exactly one boundary loop and Euler characteristic
    ``V − E + F = 1`` (genus 0). Unreferenced vertices are ignored.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array

    Raises
    ------
    MeshError
        Naming what the mesh is instead: empty, several components (how many), closed, several
        boundary loops (how many), genus g, non-manifold edges or pinched vertices, or
        zero-area faces (ids).
    """
    disk_boundary(vertices, faces)


def disk_boundary(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """:func:`check_disk`, returning the boundary loop (one edge table for both)."""
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    used = _check_triangles(v, f)
    table = EdgeTable.build(f)  # one edge table for the checks and the loop
    edges, face_edge, count = table.edges, table.face_edge, table.count
    nonmanifold = np.flatnonzero(count > 2)
    if len(nonmanifold):
        e = [tuple(map(int, edges[k])) for k in nonmanifold[:10]]
        raise MeshError(
            f"{how_many(len(nonmanifold), 'non-manifold edge', 'non-manifold edges')} (more "
            f"than two faces): {preview(e)}; a disk is a manifold surface with one boundary "
            "loop",
            edges=e,
        )
    half = np.stack([f[:, [1, 2]], f[:, [2, 0]], f[:, [0, 1]]], axis=1)[count[face_edge] == 1]
    tails, outgoing = np.unique(half[:, 0], return_counts=True)
    pinched = tails[outgoing > 1]
    if len(pinched):
        said = how_many(len(pinched), "non-manifold (pinched) boundary vertex",
                        "non-manifold (pinched) boundary vertices")
        raise MeshError(
            f"{said}, where two boundary loops touch: {preview(pinched)}; a disk's boundary "
            "is one loop through each of its vertices once",
            vertices=pinched,
        )
    graph = sp.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])),
                          shape=(len(v), len(v)))
    _, label = csgraph.connected_components(graph, directed=False)
    n_comp = len(np.unique(label[used]))
    if n_comp > 1:
        raise MeshError(f"mesh has {n_comp} connected components, a disk has one")
    loops = boundary_loops(f, table=table)
    chi = len(used) - len(edges) + len(f)
    n_loops = len(loops)
    if n_loops == 0:
        genus = (2 - chi) // 2
        what = "a closed sphere" if genus == 0 else f"a closed surface of genus {genus}"
        raise MeshError(f"mesh is {what} (no boundary), a disk has one boundary loop")
    genus = (2 - n_loops - chi) // 2
    if genus != 0:
        raise MeshError(
            f"mesh has genus {genus} (Euler characteristic {chi}, "
            f"{how_many(n_loops, 'boundary loop', 'boundary loops')}), a disk has genus 0"
        )
    if n_loops > 1:
        lengths = ", ".join(str(len(lp)) for lp in loops[:10])
        raise MeshError(
            f"mesh has {n_loops} boundary loops (an annulus or a disk with holes; loop sizes "
            f"{lengths}), a disk has one",
            vertices=np.concatenate(loops[1:])[:100],
        )
    return loops[0]


def _check_triangles(v: np.ndarray, f: np.ndarray) -> np.ndarray:
    """:func:`disk_boundary`'s checks before the topology; the vertices used."""
    if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0:
        raise MeshError(f"a disk needs at least one triangle; faces have shape {f.shape}")
    if f.min() < 0 or f.max() >= len(v):
        bad = np.flatnonzero((f < 0).any(axis=1) | (f >= len(v)).any(axis=1))
        raise MeshError(f"{agreeing(len(bad), 'face', 'faces')} {preview(bad)} "
                        f"{agreeing(len(bad), 'refers', 'refer')} to missing vertices", faces=bad)
    area = face_areas(v, f)
    used = np.unique(f)
    scale = max(float(np.ptp(v[used], axis=0).max()), 1e-300)
    degenerate = np.flatnonzero(area <= 1e-14 * scale**2)
    if len(degenerate):
        said = how_many(len(degenerate), "degenerate (zero-area) triangle",
                        "degenerate (zero-area) triangles")
        raise MeshError(
            f"{said}: {agreeing(len(degenerate), 'face', 'faces')} {preview(degenerate)}",
            faces=degenerate,
        )
    return used


def pinched_vertices(faces: np.ndarray) -> np.ndarray:
    """Boundary vertices with more than one outgoing boundary edge (two boundary loops, or
    two parts of one loop, touch there): the mesh is not a manifold at them."""
    half = boundary_halfedges(faces)
    if len(half) == 0:
        return np.zeros(0, dtype=np.int64)
    ids, count = np.unique(half[:, 0], return_counts=True)
    return ids[count > 1]


def _far_pair(vertices: np.ndarray, loop: np.ndarray) -> tuple[int, int]:
    """Two boundary vertices roughly farthest apart (two sweeps of farthest point)."""
    p = vertices[loop]
    a = int(np.argmax(row_norms(p - p[0])))
    b = int(np.argmax(row_norms(p - p[a])))
    return int(loop[a]), int(loop[b])


def scale_to_area(vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Scale ``uv`` so the parameter area equals the surface area (mean λ² = 1)."""
    a3 = face_areas(vertices, faces).sum()
    a2 = face_areas(uv, faces).sum()
    return uv * np.sqrt(a3 / a2)


# free vertices above which lscm solves the real form of its Hermitian system (see lscm)
_REAL_FORM_ABOVE = 20000


def lscm(vertices: np.ndarray, faces: np.ndarray, *, boundary: np.ndarray | None = None
         ) -> np.ndarray:
    """Least-squares conformal map (Lévy et al. 2002) with a free boundary.

    Minimizes the conformal energy ``E_C = ½∫|∇u|² + ½∫|∇v|² − Area(u, v)``, which is zero
    exactly for an orientation-preserving conformal map (the cotangent formulation of
    Desbrun, Meyer, Alliez 2002, equal to LSCM). Two boundary vertices far apart are pinned
    to ``(0, 0)`` and ``(d, 0)``; one sparse direct solve.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        A topological disk (see :func:`check_disk`), consistently oriented.
    boundary : (k,) int array, optional
        Its boundary loop as :func:`disk_boundary` gives it, from a caller that knows the
        faces form a disk: their topology is then not checked again (degenerate ones are).

    Returns
    -------
    uv : (n, 2) float array
        Translated so the lower-left corner of its bounding box is the origin and scaled so
        the parameter area equals the surface area, i.e. the mean of λ² over the surface is 1.
        Unreferenced vertices get NaN.

    Raises
    ------
    MeshError
        When the mesh is not a disk (from :func:`check_disk`).
    """
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    if boundary is None:
        loop = disk_boundary(v, f)
    else:
        _check_triangles(v, f)
        loop = np.asarray(boundary, dtype=np.int64)
    n = len(v)
    L = cotangent_laplacian(v, f)
    # In z = u + iv the energy is (up to a factor 2) the Hermitian form z^H (−L + i A) z:
    # with the antisymmetric A (+½ at (i, j), −½ at (j, i) for each boundary edge i→j),
    # z^H (i A) z = −Σ (u_i v_j − u_j v_i) = −2 × the signed parameter area. One complex
    # solve of n unknowns: the minimizer of the real form in 2n unknowns, ~1.5x faster.
    i, j = loop, np.roll(loop, -1)
    half = np.full(len(i), 0.5)
    A = sp.coo_matrix((np.concatenate([half, -half]),
                       (np.concatenate([i, j]), np.concatenate([j, i]))), shape=(n, n))
    Q = ((-L).astype(complex) + 1j * A).tocsr()
    a, b = _far_pair(v, loop)
    d = float(np.linalg.norm(v[a] - v[b]))
    free = np.zeros(n, dtype=bool)
    free[f.ravel()] = True
    free[[a, b]] = False
    z = np.full(n, complex(np.nan, np.nan))
    z[a], z[b] = 0.0, d  # pinned: (0, 0) and (d, 0)
    Qf = Q[free]
    rhs = -(Qf[:, [b]] @ np.array([complex(d)]))
    if free.sum() > _REAL_FORM_ABOVE:
        # SuperLU's complex factorization is slow on large meshes (measured, 20k vertices:
        # 19.7 s complex, 2.9 s for the equivalent real symmetric form in 2n unknowns;
        # 5k: 2.2 s / 0.36 s; 1.3k: 0.03 / 0.06 s): below the threshold, where every fill
        # patch lies, the complex solve stays (bit-identical results). Nested dissection
        # over the vertices, u and v of a vertex together, halves the factorization's time
        # against minimum degree (105k vertices: 2.4 s / 5.0 s of CPU)
        Qr = Qf[:, free]
        real = sp.bmat([[Qr.real, -Qr.imag], [Qr.imag, Qr.real]]).tocsc()
        m = Qr.shape[0]
        order = np.repeat(nested_dissection(Qr, v[free]), 2)
        order[1::2] += m
        x = factorized_definite_ordered(real, order)(np.concatenate([rhs.real, rhs.imag]))
        z[free] = x[:len(rhs)] + 1j * x[len(rhs):]
    else:
        z[free] = factorized_definite(Qf[:, free])(rhs)
    uv = np.column_stack([z.real, z.imag])
    uv = scale_to_area(v, f, uv)
    return uv - np.nanmin(uv, axis=0)


def _boundary_corners(vertices: np.ndarray, loop: np.ndarray) -> np.ndarray:
    """Positions in ``loop`` of four corners, in loop order.

    When the boundary has four clear corners (angles below 150° between the boundary points
    a 32nd of its length away on either side, corners at least an eighth of the length
    apart) those are used, since a rectangle corner placed where the boundary is straight
    forces a 180° → 90° angle change there. Otherwise the boundary is
    split into quarters of its length starting at its sharpest turn.
    """
    p = vertices[loop]
    seg = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)[:-1]])
    total = seg.sum()
    # turning measured between the boundary points a 32nd of the length away on either
    # side, so that a ragged (scanned) boundary does not look like all corners
    reach = total / 32
    size = len(loop)
    ahead = np.searchsorted(np.concatenate([s, s + total]), s + reach) % size
    behind = (np.searchsorted(np.concatenate([s - total, s]), s - reach, side="right")
              - 1) % size
    prev, nxt = p[behind] - p, p[ahead] - p
    cos = np.einsum("ij,ij->i", prev, nxt) / np.maximum(
        np.linalg.norm(prev, axis=1) * np.linalg.norm(nxt, axis=1), 1e-300)
    angle = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    chosen: list[int] = []
    for k in np.argsort(angle, kind="stable"):
        if angle[k] >= 150.0 or len(chosen) == 4:
            break
        gap = np.abs(s[chosen] - s[k])
        if np.all(np.minimum(gap, total - gap) >= total / 8):
            chosen.append(int(k))
    if len(chosen) == 4:
        return np.sort(np.array(chosen))
    start = int(np.argmin(angle))
    targets = (s[start] + total * np.array([0.0, 0.25, 0.5, 0.75])) % total
    gap = np.abs(s[None, :] - targets[:, None])
    idx = np.minimum(gap, total - gap).argmin(axis=1)
    return np.unique(idx) if len(np.unique(idx)) < 4 else idx[np.argsort(idx)]


def _dirichlet_solve(L: sp.csr_matrix, fixed: np.ndarray, values: np.ndarray,
                     free: np.ndarray) -> np.ndarray:
    x = np.full(L.shape[0], np.nan)
    x[fixed] = values
    rhs = -L[free][:, fixed] @ values
    x[free] = factorized_definite(L[free][:, free])(np.asarray(rhs, dtype=float))
    return x


def rectangular_conformal_map(
    vertices: np.ndarray, faces: np.ndarray, corners: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Conformal map of a disk onto a rectangle with four boundary vertices at its corners.

    With corners ``c0, c1, c2, c3`` in boundary order, ``u`` is harmonic with ``u = 0`` on the
    arc c3→c0, ``u = 1`` on c1→c2 and natural (Neumann) conditions on the other two arcs;
    ``v`` likewise with ``v = 0`` on c0→c1 and ``v = b`` on c2→c3. For a conformal map the
    height is the conformal modulus, ``b = ∫|∇u|²`` (the Dirichlet energy of ``u``), and
    ``u + iv`` is then holomorphic: this is the rectangular conformal map that Meng, Choi, Lui
    (2016) use as the parameter domain, computed as two cotangent-Laplacian solves instead of
    their disk map + Schwarz–Christoffel-type step. The two arcs with natural conditions come
    out as the straight sides ``v = 0`` and ``v = b`` only in the limit; here they are exactly
    straight because each is a Dirichlet arc of the other coordinate.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
        A topological disk, consistently oriented.
    corners : (4,) int array, optional
        Vertex ids of the corners, in the boundary's order. By default the boundary is split
        into quarters of its length starting at its sharpest turn.

    Returns
    -------
    uv : (n, 2) float array
        In the rectangle ``[0, s] × [0, s·b]``, ``s`` chosen so the parameter area equals the
        surface area. NaN for unreferenced vertices.
    corners : (4,) int array
        The corner vertex ids, at ``(0, 0), (s, 0), (s, s·b), (0, s·b)``.

    Raises
    ------
    MeshError
        When the mesh is not a disk, or a given corner is not on its boundary.
    ValueError
        When ``corners`` does not hold four distinct vertices.
    """
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    loop = disk_boundary(v, f)
    n = len(v)
    if len(loop) < 4:
        raise MeshError(f"boundary has only {how_many(len(loop), 'vertex', 'vertices')}, a "
                        "rectangle needs 4",
                        vertices=loop)
    if corners is None:
        pos = _boundary_corners(v, loop)
        if len(pos) < 4:
            raise MeshError("could not place four distinct corners on the boundary",
                            vertices=loop)
        corners = loop[pos]
    corners = np.asarray(corners, dtype=np.int64)
    if corners.shape != (4,) or len(np.unique(corners)) != 4:
        raise ValueError(f"corners must be 4 distinct vertex ids, got {corners.tolist()}")
    where = {int(x): k for k, x in enumerate(loop)}
    missing = [int(c) for c in corners if int(c) not in where]
    if missing:
        raise MeshError(f"corner vertices {missing} are not on the boundary", vertices=missing)
    pos = np.array([where[int(c)] for c in corners])
    # corners must follow the loop order (cyclically)
    shifted = (pos - pos[0]) % len(loop)
    if not np.all(np.diff(shifted) > 0):
        raise ValueError(f"corners {corners.tolist()} are not in boundary order")

    def arc(a: int, b: int) -> np.ndarray:
        pa, pb = where[int(a)], where[int(b)]
        k = (pb - pa) % len(loop)
        return loop[(pa + np.arange(k + 1)) % len(loop)]

    c0, c1, c2, c3 = corners
    left, right = arc(c3, c0), arc(c1, c2)
    bottom, top = arc(c0, c1), arc(c2, c3)
    L = -cotangent_laplacian(v, f)  # positive semi-definite
    used = np.zeros(n, dtype=bool)
    used[f.ravel()] = True

    def solve(zero: np.ndarray, one: np.ndarray) -> np.ndarray:
        fixed = np.concatenate([zero, one])
        values = np.concatenate([np.zeros(len(zero)), np.ones(len(one))])
        free = used.copy()
        free[fixed] = False
        return _dirichlet_solve(L, fixed, values, np.flatnonzero(free))

    # two independent factorizations; SuperLU releases the GIL, so use both cores
    with ThreadPoolExecutor(max_workers=2) as pool:
        u, w = pool.map(lambda arcs: solve(*arcs), [(left, right), (bottom, top)])
    ok = used
    b = float(u[ok] @ (L[ok][:, ok] @ u[ok]))  # conformal modulus = Dirichlet energy of u
    uv = np.column_stack([u, b * w])
    return scale_to_area(v, f, uv), corners


def _conformal_parts(vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """(f, 2) conformal and anticonformal parts ``(Q, R)`` of the affine map from each
    parameter triangle to its 3D triangle (in the triangle's own orthonormal frame).

    The singular values are ``Q + R`` and ``|Q − R|``; ``R > Q`` where the map reverses
    orientation."""
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    q = np.asarray(uv, dtype=float)
    e1, e2 = v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]
    # orthonormal frame in each 3D triangle, so the map is 2×2
    x = e1 / np.maximum(np.linalg.norm(e1, axis=1, keepdims=True), 1e-300)
    nrm = np.cross(e1, e2)
    y = np.cross(nrm, x)
    y /= np.maximum(np.linalg.norm(y, axis=1, keepdims=True), 1e-300)
    P = np.stack([np.stack([np.einsum("ij,ij->i", e1, x), np.einsum("ij,ij->i", e2, x)], -1),
                  np.stack([np.zeros(len(f)), np.einsum("ij,ij->i", e2, y)], -1)], axis=1)
    d1, d2 = q[f[:, 1]] - q[f[:, 0]], q[f[:, 2]] - q[f[:, 0]]
    D = np.stack([d1, d2], axis=-1)  # columns are parameter edges
    det = D[:, 0, 0] * D[:, 1, 1] - D[:, 0, 1] * D[:, 1, 0]
    safe = np.where(np.abs(det) > 0, det, np.nan)
    Dinv = np.stack([np.stack([D[:, 1, 1], -D[:, 0, 1]], -1),
                     np.stack([-D[:, 1, 0], D[:, 0, 0]], -1)], axis=1) / safe[:, None, None]
    J = P @ Dinv
    # closed form for 2×2: J = Q·rotation + R·reflection, σ = Q ± R, |μ| = R / Q
    a, b, c, d = J[:, 0, 0], J[:, 0, 1], J[:, 1, 0], J[:, 1, 1]
    q = 0.5 * np.hypot(a + d, c - b)
    r = 0.5 * np.hypot(a - d, c + b)
    return np.column_stack([q, r])


def conformal_distortion(vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray,
                         kind: str = "beltrami") -> np.ndarray:
    """Per-face distortion of the map between the mesh and its parameterization.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
    uv : (n, 2) float array
    kind : {"beltrami", "angle", "stretch"}
        ``"beltrami"``: the modulus ``|μ| = (σ1 − σ2)/(σ1 + σ2)`` of the Beltrami coefficient
        of the affine map on each face (0 for a similarity, → 1 as it degenerates, > 1
        on flipped triangles).
        ``"angle"``: the largest absolute difference, in degrees, between a corner angle in
        3D and in the parameter domain.
        ``"stretch"``: the conformal factor estimate ``sqrt(σ1 σ2)`` (λ per face).

    Returns
    -------
    (f,) float array; NaN on faces degenerate in the parameter domain.
    """
    if kind == "beltrami":
        qr = _conformal_parts(vertices, faces, uv)
        return qr[:, 1] / qr[:, 0]
    if kind == "stretch":
        qr = _conformal_parts(vertices, faces, uv)
        return np.sqrt(np.abs(qr[:, 0] ** 2 - qr[:, 1] ** 2))
    if kind == "angle":
        return np.abs(angle_distortion(vertices, faces, uv)).max(axis=1)
    raise ValueError(f"unknown distortion kind {kind!r}: use 'beltrami', 'angle' or 'stretch'")


def _corner_angles(points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    p = np.asarray(points, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    out = np.empty(f.shape)
    for k in range(3):
        a = p[f[:, (k + 1) % 3]] - p[f[:, k]]
        b = p[f[:, (k + 2) % 3]] - p[f[:, k]]
        cos = np.einsum("ij,ij->i", a, b) / np.maximum(row_norms(a) * row_norms(b), 1e-300)
        out[:, k] = np.arccos(np.clip(cos, -1.0, 1.0))
    return out


def angle_distortion(vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """(f, 3) signed corner-angle differences, parameter minus 3D, in degrees.

    This is the quantity histogrammed in the paper's Fig. 1(D). Flipped parameter
    triangles count their unsigned angles (use :func:`flipped_faces` to find them).
    """
    return np.degrees(_corner_angles(uv, faces) - _corner_angles(vertices, faces))


# a parameter corner below this fraction of its 3D angle is squashed flat: a conformal map
# keeps angles, and the cotangent of a vanishing angle makes the Laplacian's weights explode
# (measured: a cube corner's LSCM laid one triangle flat, 1e15 weights, the λ-H fill's
# first step 1e48 edge lengths)
COLLAPSED = 0.05


def collapsed_faces(vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray, *,
                    ratio: float = COLLAPSED) -> np.ndarray:
    """Ids of parameter triangles squashed flat: some corner angle in the plane is below
    ``ratio`` times its angle in 3D (nearly zero area, yet not flipped).

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (f, 3) int array
    uv : (n, 2) float array
    ratio : float
        See above.

    Returns
    -------
    (k,) int array of face ids.
    """
    squashed = _corner_angles(uv, faces) < ratio * _corner_angles(vertices, faces)
    return np.flatnonzero(rows_any(squashed))


def distortion_histogram(vertices: np.ndarray, faces: np.ndarray, uv: np.ndarray,
                         bins: int | np.ndarray = 60,
                         range_deg: tuple[float, float] = (-30.0, 30.0)
                         ) -> tuple[np.ndarray, np.ndarray]:
    """Histogram of corner-angle differences in degrees (the paper's Fig. 1(D)).

    Returns
    -------
    counts : (bins,) int array
    edges : (bins + 1,) float array, degrees
    """
    d = angle_distortion(vertices, faces, uv).ravel()
    return np.histogram(d[np.isfinite(d)], bins=bins, range=range_deg)


def signed_areas(faces: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Twice the signed area of each parameter triangle (positive: counter-clockwise)."""
    f = np.asarray(faces, dtype=np.int64)
    q = np.asarray(uv, dtype=float)
    d1, d2 = q[f[:, 1]] - q[f[:, 0]], q[f[:, 2]] - q[f[:, 0]]
    return d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]


def flipped_faces(faces: np.ndarray, uv: np.ndarray) -> np.ndarray:
    """Ids of parameter triangles that are folded over or degenerate.

    A triangle is flipped when its signed area in the parameter domain has the opposite
    sign of the total signed area (so a map that reverses orientation everywhere has no
    flipped faces), or is zero.

    Parameters
    ----------
    faces : (f, 3) int array
    uv : (n, 2) float array

    Returns
    -------
    (k,) int array of face ids.
    """
    signed = signed_areas(faces, uv)
    total = np.nansum(signed)
    sign = 1.0 if total >= 0 else -1.0
    return np.flatnonzero(~(signed * sign > 0))
