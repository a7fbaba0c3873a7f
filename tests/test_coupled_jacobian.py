"""The lagged update's exact derivative on large patches (docs/convergence.md, session 14):
its matrix-free products against central differences and against the dense Jacobian, the
Newton–Krylov steps that use them, and the Jacobian taken without a second lagged solve."""

import sys
from pathlib import Path

import numpy as np
import pytest

from surfinpaint.fill.liepa.baseline import faired_fill
from surfinpaint.geometry.mesh import vertex_adjacency
from surfinpaint.representation import on_mesh
from surfinpaint.representation.coupled_jacobian import (
    UpdateDerivative,
    lagged_update_jacobian,
)

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
from eggcrate import egg_crate  # noqa: E402


def _system(n, radius, rings=3, perturb=0.1, subdivided=False, period=7, amplitude=2.5):
    """A coupled system on an egg-crate patch (``subdivided``: split once into four, as
    the retry of mesh_pass does) and a point near its start."""
    from surfinpaint.fill.conformal.mesh_pass import _mapped_patch, _subdivided

    cut = egg_crate(n, 3, period, amplitude, 0.4, radius)
    new_v, new_f, _ = faired_fill(cut.vertices, cut.faces, cut.loop, 2)
    vertices = np.vstack([cut.vertices, new_v])
    _, ids, local, uv, _, _ = _mapped_patch(vertices, cut.faces, cut.loop, new_f, rings)
    points = vertices[ids]
    free = ids >= len(cut.vertices)
    if subdivided:
        points, local, uv, free, _ = _subdivided(points, local, uv, free, len(new_f),
                                                 np.zeros(len(points), dtype=bool))
    system = on_mesh._CoupledSystem(points, local, uv, free)
    phi = points.copy()
    phi[system.f] += perturb * system.scale * np.random.default_rng(0).standard_normal(
        (len(system.f), 3))
    return system, points, phi, (local, uv, free)


@pytest.fixture(scope="module")
def large():
    # 213 free vertices: above on_mesh.NEWTON_ANALYTIC_MAX, where Newton's steps took GMRES
    # on finite-difference products (1e-3 relative) before
    system, points, phi, _ = _system(40, 11, subdivided=True)
    assert len(system.f) > on_mesh.NEWTON_ANALYTIC_MAX
    return system, points, phi


def test_the_update_s_exact_products_match_central_differences_on_a_large_patch(large):
    system, _, phi = large
    f = system.f
    V = np.random.default_rng(1).standard_normal((3 * len(f), 4))
    JV = UpdateDerivative(system, phi).apply(V)
    e = 1e-5 * system.scale
    for k in range(V.shape[1]):
        plus, minus = phi.copy(), phi.copy()
        plus[f] += e * V[:, k].reshape(-1, 3)
        minus[f] -= e * V[:, k].reshape(-1, 3)
        central = ((system.update(plus) - system.update(minus)) / (2 * e)).ravel()
        # measured: 1e-9 relative (central differences' own error)
        assert np.linalg.norm(JV[:, k] - central) < 1e-7 * np.linalg.norm(central)


def test_the_products_are_the_dense_jacobian_s():
    # the same chain rule with other right-hand sides; and J itself unchanged by the refactor
    system, _, phi, _ = _system(30, 6)
    J = lagged_update_jacobian(system, phi)
    V = np.random.default_rng(2).standard_normal((J.shape[1], 3))
    derivative = UpdateDerivative(system, phi)
    np.testing.assert_allclose(derivative.apply(V), J @ V, rtol=0, atol=1e-10 * np.abs(J).max())
    v = V[:, 0]
    # Newton–Krylov's product (on_mesh.newton_solve): the residual's Jacobian J − I
    np.testing.assert_allclose(derivative.residual_product(v), J @ v - v, rtol=0,
                               atol=1e-10 * np.abs(J).max())


def test_the_jacobian_takes_no_second_lagged_solve_where_the_residual_was_evaluated(monkeypatch):
    # Newton's steps and the least-squares stage evaluate the residual, then take the
    # Jacobian at the same point: the lagged solve there was made twice before
    system, points, phi, patch = _system(30, 6)
    solves = []
    measures = on_mesh.vertex_normals_and_areas  # once a lagged solve
    monkeypatch.setattr(on_mesh, "vertex_normals_and_areas",
                        lambda *a: (solves.append(1), measures(*a))[1])
    new = system.update(phi)
    J = system.jacobian(phi)
    assert len(solves) == 1
    system.update(points)  # another point: solved again
    assert len(solves) == 2
    # and the cached state is the one a fresh system gives
    fresh = on_mesh._CoupledSystem(points, *patch)
    np.testing.assert_array_equal(fresh.update(phi), new)
    np.testing.assert_array_equal(fresh.jacobian(phi), J)


def test_newton_krylov_on_exact_products_converges_on_a_large_patch():
    # the Newton stage on a patch above NEWTON_ANALYTIC_MAX free vertices: GMRES on the
    # exact products reaches the fixed point to 1e-10 edge lengths
    system, points, _, _ = _system(40, 8, subdivided=True, period=14, amplitude=2.0)
    assert len(system.f) > on_mesh.NEWTON_ANALYTIC_MAX
    sizes = []
    line_search = on_mesh._line_search

    def recorded(*args):
        x, r = line_search(*args)
        sizes.append(float(np.abs(r).max()))
        return x, r

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(on_mesh, "_line_search", recorded)
        out = on_mesh.newton_solve(system, points, 1e-10, 12)
    residual = np.abs(system.update(out) - out[system.f]).max() / system.scale
    assert residual < 1e-10 and len(sizes) <= 6


@pytest.mark.parametrize("natural", [False, True])
def test_the_dense_jacobian_s_fast_path_is_the_reference_one(natural):
    # lagged_update_jacobian takes products with matrices made once a system (session 28);
    # UpdateDerivative.apply(None) is the chain rule as written (solves with every
    # right-hand side): the same Jacobian to rounding, also with the free vertices next to a
    # natural border (H unknown on the crease; the stencil's H data on it do not move on
    # this patch, so the Q_fs term is zero here as in the reference)
    from surfinpaint.representation.coupled_jacobian import _DenseJacobian

    system, points, phi, (local, uv, free) = _system(30, 6)
    if natural:  # the free vertices moved next to the patch's border on one side
        system = on_mesh._CoupledSystem(points, local, uv, _near_border(points, local),
                                        np.ones(len(points), dtype=bool))
        assert len(system.natural_data) and system.n_crease
        phi = points.copy()
        phi[system.f] += 0.1 * system.scale * np.random.default_rng(3).standard_normal(
            (len(system.f), 3))
    reference = UpdateDerivative(system, phi)
    fast = lagged_update_jacobian(system, phi)
    J = reference.apply(None)
    assert np.abs(fast - J).max() < 1e-12 * np.abs(J).max()
    # the dense derivatives are the sparse ones (the normals' rows: free, tied, the rest)
    d_unit, d_area = _DenseJacobian.of(system).derivatives(phi)
    where = _DenseJacobian.of(system).where[system.moving]
    rows = (3 * where[:, None] + np.arange(3)).ravel()  # in the moving vertices' order
    np.testing.assert_allclose(d_unit[rows], reference.d_unit.toarray(), rtol=0, atol=1e-13)
    np.testing.assert_allclose(d_area, reference.d_area.toarray(), rtol=0, atol=1e-13)
    # made once a system, and what it keeps does not depend on where it is taken
    assert _DenseJacobian.of(system) is _DenseJacobian.of(system)
    again = lagged_update_jacobian(system, points)
    assert np.abs(again - UpdateDerivative(system, points).apply(None)).max() < (
        1e-12 * np.abs(again).max())


@pytest.mark.parametrize("natural", [False, True])
def test_newton_s_dense_step_is_the_jacobian_s_without_its_product_with_the_inverse(natural):
    # newton_step solves (R − L̃) dx = −L̃ r with J = L̃⁻¹ R (session 33 helper): the step
    # −(J − I)⁻¹ r to rounding, also next to a natural border; the Jacobian is L_ff⁻¹ R bit
    # for bit, and L̃ is L_ff ⊗ I₃
    from surfinpaint.representation import coupled_jacobian
    from surfinpaint.representation.coupled_jacobian import _DenseJacobian
    from surfinpaint.representation.sparse_newton import newton_step

    system, points, phi, (local, uv, free) = _system(30, 6)
    if natural:
        system = on_mesh._CoupledSystem(points, local, uv, _near_border(points, local),
                                        np.ones(len(points), dtype=bool))
        phi = points.copy()
        phi[system.f] += 0.1 * system.scale * np.random.default_rng(3).standard_normal(
            (len(system.f), 3))
    dense = _DenseJacobian.of(system)
    r = np.random.default_rng(4).standard_normal(3 * len(system.f))
    J = lagged_update_jacobian(system, phi)
    want = np.linalg.solve(J - np.eye(len(J)), -r)
    got = newton_step(system, points, phi[system.f], r)
    assert np.abs(got - want).max() < 1e-11 * np.abs(want).max()
    R = dense.right_hand_side(phi)
    assert np.array_equal(J, (dense.L_inv @ R.reshape(len(system.f), -1)).reshape(J.shape))
    L_ff = system.L.tocsr()[system.f][:, system.f].toarray()
    stiffness = np.zeros(J.size)
    np.add.at(stiffness, *dense.stiffness_entries())
    assert np.array_equal(stiffness.reshape(J.shape), np.kron(L_ff, np.eye(3)))
    # where R − L̃ is exactly singular, the step is J − I's as before
    calls = []

    def singular(a, overwrite_a=False):
        calls.append(a.shape)
        return a, np.arange(1, len(a) + 1, dtype=np.int32), 1

    original = coupled_jacobian._GETRF
    try:
        coupled_jacobian._GETRF = singular
        again = newton_step(system, points, phi[system.f], r)
    finally:
        coupled_jacobian._GETRF = original
    assert calls and np.array_equal(again, want)


def central_differences(system, phi: np.ndarray) -> np.ndarray:
    """The lagged update's Jacobian in the free positions at ``phi`` by central differences
    (steps of 1e-5 edge lengths; rows and columns ``3 i + c``)."""
    f = system.f

    def update(x):
        trial = phi.copy()
        trial[f] = x.reshape(-1, 3)
        return system.update(trial).ravel()

    x, e = phi[f].ravel(), 1e-5 * system.scale
    return np.column_stack([(update(x + e * d) - update(x - e * d)) / (2 * e)
                            for d in np.eye(x.size)])


def _near_border(points, local):
    """Free vertices two edges from the patch's border but on one side (four there)."""
    import scipy.sparse as sp

    from surfinpaint.geometry.mesh import boundary_loops

    nv = len(points)
    edges = np.vstack([local[:, [0, 1]], local[:, [1, 2]], local[:, [2, 0]]])
    A = sp.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(nv, nv))
    A = A + A.T
    near = np.zeros(nv, dtype=bool)
    near[np.concatenate(boundary_loops(local))] = True
    near |= (A @ near) > 0
    far = near.copy()
    for _ in range(3):
        far |= (A @ far) > 0
    return ~near & ~(far & (points[:, 0] < np.median(points[:, 0])))


def test_the_dense_jacobian_s_natural_border_term_where_it_is_not_zero():
    # The natural-border term W = Q_ff⁻¹ Q_fs dH_s of the fast path (the derivative of
    # _CoupledSystem.stencil_H) is structurally zero on a real patch: a natural stencil
    # vertex next to an inner moving one is two Laplacian steps from a free vertex, so Q_f
    # reaches it (barring exact cancellation) and it is on the crease, an unknown, not data
    # (checked on the patches of this file and tests/test_convergence.py, 0 such vertices;
    # not where cotangent weights are exactly zero: _right_angled_patch, |W| 2.8 there).
    # So the system here is the natural one of the fast-path test with each natural datum's
    # mean widened to the inner moving vertex nearest it: stencil_H (the update) and
    # _d_stencil_H (both Jacobians) read the same adjacency, so it is a consistent system
    # on which W is not zero. Measured: fast against reference 2e-15 of J's largest entry,
    # both against central differences 1.3e-9 relative; dropping W moves J by 1e-3 of its
    # largest entry (2.5e-4 relative to central differences).
    import scipy.sparse as sp

    from surfinpaint.representation.coupled_jacobian import _d_stencil_H, _DenseJacobian

    _, points, _, (local, uv, _) = _system(30, 6)
    system = on_mesh._CoupledSystem(points, local, uv, _near_border(points, local),
                                    np.ones(len(points), dtype=bool))
    m = system.moving
    inner = m[system.inner[m] > 0]
    distance = np.linalg.norm(points[system.natural_data][:, None] - points[inner][None], axis=2)
    nearest = inner[distance.argmin(axis=1)]
    system.adjacency = (system.adjacency + sp.csr_matrix(
        (np.ones(len(nearest)), (np.arange(len(nearest)), nearest)),
        shape=system.adjacency.shape)).tocsr()
    system.weight = np.maximum(system.adjacency @ system.inner, 1.0)
    f = system.f
    phi = points.copy()
    phi[f] += 0.1 * system.scale * np.random.default_rng(3).standard_normal((len(f), 3))
    fast = lagged_update_jacobian(system, phi)
    J = UpdateDerivative(system, phi).apply(None)
    # W is not zero here (measured: |W| 18, its largest entry 12; |J|'s 0.4)
    dense = _DenseJacobian.of(system)
    d_unit, d_area = dense.derivatives(phi)
    d_unit = d_unit.reshape(len(m), 3, -1)
    normals = system._lagged(phi)[1][0]
    W = dense.stencil_map @ _d_stencil_H(system, phi, normals,
                                         lambda ids: d_unit[dense.where[ids]], d_area, None)
    assert np.abs(W).max() > 1.0
    assert np.abs(fast - J).max() < 1e-12 * np.abs(J).max()

    central = central_differences(system, phi)
    assert np.linalg.norm(fast - central) < 1e-7 * np.linalg.norm(fast)
    assert np.linalg.norm(J - central) < 1e-7 * np.linalg.norm(J)


def _right_angled_patch(near_border):
    """A curved patch whose map is a square grid split by diagonals: the angles opposite
    the diagonals are right angles, so their cotangent weights are exactly zero and the
    Laplacian does not join the vertices they join. The free vertices: a disk at the
    centre, or every vertex two edges from the border but on one side (a natural border)."""
    from test_parameterization import grid_mesh

    uv, faces = grid_mesh(11, extent=(-1.0, 1.0, -1.0, 1.0))
    u, v = uv.T
    points = np.column_stack([u, v, 0.3 * u**2 + 0.2 * v**2 + 0.1 * u * v
                              + 0.05 * np.sin(3 * u) * np.cos(2 * v)])
    if near_border:
        return points, faces, uv, _near_border(points, faces), np.ones(len(uv), dtype=bool)
    return points, faces, uv, np.linalg.norm(uv, axis=1) < 0.35, None


@pytest.mark.parametrize("near_border", [False, True])
def test_the_vertices_sharing_a_face_with_a_free_one_move_where_cotangent_weights_are_zero(
        near_border):
    # λ and the normals change at every vertex whose faces touch a free one, and H there
    # depends on the fill, whether or not the Laplacian joins it to a free vertex. With the
    # sets read off L's (Q's) nonzeros (before), a vertex joined to the free ones only by a
    # zero-weight diagonal kept its λ and H of the start (the update moved by 5e-4 edge
    # lengths with the start), on a natural border the Jacobians missed its H's change in
    # the crease's mean (2.6e-2 relative to central differences) and the update jumped by
    # 1e-3 edge lengths when the map moved by 1e-12 (measured)
    points, faces, uv, free, natural = _right_angled_patch(near_border)
    system = on_mesh._CoupledSystem(points, faces, uv, free, natural)
    f = system.f
    ring = np.unique(faces[np.isin(faces, f).any(axis=1)])
    joined = np.flatnonzero(np.diff(system.L[:, f].tocsr().indptr))
    assert len(np.setdiff1d(ring, joined))  # vertices the Laplacian does not join: the case
    np.testing.assert_array_equal(system.moving, ring)
    if near_border:  # H at a natural datum: the mean of its mesh neighbours' off the border
        assert len(system.natural_data) and system.n_crease
        neighbours = vertex_adjacency(faces, len(points))[system.natural_data]
        assert ((system.adjacency != 0) != (neighbours != 0)).nnz == 0
    else:  # H tied to φ there too
        np.testing.assert_array_equal(system.tied, np.setdiff1d(ring, f))

    phi = points.copy()
    phi[f] += 0.1 * system.scale * np.random.default_rng(0).standard_normal((len(f), 3))
    # the update at φ does not depend on where the fill started (H and λ next to it
    # follow φ; before, they were the start's there)
    start = points.copy()
    start[f] += 0.2 * system.scale * np.random.default_rng(1).standard_normal((len(f), 3))
    other = on_mesh._CoupledSystem(start, faces, uv, free, natural)
    np.testing.assert_array_equal(other.update(phi), system.update(phi))
    # and it is continuous in the map: moved off the right angles (no weight zero), the
    # same sets (measured: 1e-11 edge lengths)
    moved = uv + 1e-12 * np.random.default_rng(3).standard_normal(uv.shape)
    other = on_mesh._CoupledSystem(points, faces, moved, free, natural)
    assert np.abs(other.update(phi) - system.update(phi)).max() < 1e-9 * system.scale

    # the dense fast path, the reference chain rule and its products: central differences'
    central = central_differences(system, phi)
    derivative = UpdateDerivative(system, phi)
    V = np.random.default_rng(2).standard_normal((3 * len(f), 3))
    for J in (lagged_update_jacobian(system, phi), derivative.apply(None)):
        assert np.linalg.norm(J - central) < 1e-7 * np.linalg.norm(central)
    assert np.linalg.norm(derivative.apply(V) - central @ V) < 1e-7 * np.linalg.norm(central @ V)


def test_the_stencil_s_h_from_the_faces_it_reads_is_the_whole_patch_s():
    # stencil_H makes H from the faces around the vertices it reads only (session 30): the
    # same bits as from the whole patch's normals, areas and L φ, also after the adjacency
    # of the natural data is replaced (the read set is made again)
    import scipy.sparse as sp

    from surfinpaint.geometry.mesh import vertex_areas, vertex_normals

    _, points, _, (local, uv, _) = _system(30, 6)
    system = on_mesh._CoupledSystem(points, local, uv, _near_border(points, local),
                                    np.ones(len(points), dtype=bool))
    assert len(system.natural_data)

    def whole_patch(phi):  # stencil_H as it was: H at every vertex of the patch
        lam2 = vertex_areas(phi, system.faces) / system.area
        H = (np.einsum("ij,ij->i", system.L @ phi, vertex_normals(phi, system.faces))
             / (2.0 * lam2 * system.area))
        out = H[system.stencil]
        out[system.on_natural_stencil] = ((system.adjacency @ np.where(system.inner > 0, H, 0.0))
                                          / system.weight)
        return out

    phi = points.copy()
    phi[system.f] += 0.1 * system.scale * np.random.default_rng(4).standard_normal(
        (len(system.f), 3))
    for _ in range(2):
        for at in (points, phi):
            assert np.array_equal(system.stencil_H(at), whole_patch(at))
        inner = system.moving[system.inner[system.moving] > 0][:len(system.natural_data)]
        system.adjacency = (system.adjacency + sp.csr_matrix(
            (np.ones(len(inner)), (np.arange(len(inner)), inner)),
            shape=system.adjacency.shape)).tocsr()
        system.weight = np.maximum(system.adjacency @ system.inner, 1.0)


def test_the_face_blocks_are_the_sliced_whole_patch_derivatives_and_the_terms_made_once():
    # UpdateDerivative assembles its derivatives from FaceBlocks' index arrays (session 30)
    # where it sliced the whole patch's (3n, 3n) ones: the same to rounding, the sparse and
    # the dense assembly the same bits; the natural border's terms made once at φ give the
    # products made with them fresh, bit for bit
    from surfinpaint.representation.coupled_jacobian import FaceBlocks, voronoi_area_derivative
    from surfinpaint.representation.mesh_lambda_h import normals_with_jacobian

    _, points, _, (local, uv, _) = _system(30, 6)
    system = on_mesh._CoupledSystem(points, local, uv, _near_border(points, local),
                                    np.ones(len(points), dtype=bool))
    f, m = system.f, system.moving
    phi = points.copy()
    phi[f] += 0.1 * system.scale * np.random.default_rng(5).standard_normal((len(f), 3))
    columns = (3 * f[:, None] + np.arange(3)).ravel()
    rows = (3 * m[:, None] + np.arange(3)).ravel()
    sliced = normals_with_jacobian(phi, system.near)[1][:, columns].tocsr()[rows].toarray()
    area = voronoi_area_derivative(phi, system.near, f)[m].toarray()
    blocks = FaceBlocks.of(system, m)
    assert FaceBlocks.of(system, m) is blocks
    d_unit, d_area = blocks.sparse(phi)
    np.testing.assert_allclose(d_unit.toarray(), sliced, rtol=0, atol=1e-13 * np.abs(sliced).max())
    np.testing.assert_allclose(d_area.toarray(), area, rtol=0, atol=1e-13 * np.abs(area).max())
    assert d_unit.nnz <= np.count_nonzero(sliced) + 9 * len(system.near)
    dense = blocks.dense(phi)
    assert np.array_equal(d_unit.toarray(), dense[0]) and np.array_equal(d_area.toarray(), dense[1])

    derivative = UpdateDerivative(system, phi)
    V = np.random.default_rng(6).standard_normal((3 * len(f), 2))
    made_once = derivative.apply(V)
    derivative.stencil_terms = None  # _d_stencil_H makes them at each product
    assert np.array_equal(derivative.apply(V), made_once)


@pytest.mark.parametrize("case", ["plain", "natural", "folded", "degenerate"])
def test_the_compiled_face_blocks_are_numpy_s_bit_for_bit(case):
    # FaceBlocks.blocks from a numba kernel (session 32 helper): the same bits as its numpy
    # version, on a patch, on one with a natural border, with its free vertices thrown about
    # (obtuse and flipped faces) and with a face made degenerate (a free vertex moved onto a
    # neighbour: zero area, NaN and inf in both)
    from surfinpaint.representation import face_derivatives
    from surfinpaint.representation.coupled_jacobian import FaceBlocks

    kernel = pytest.importorskip("numba") and face_derivatives._BLOCKS_KERNEL.get()
    _, points, _, (local, uv, free) = _system(30, 6)
    natural = case == "natural"
    system = on_mesh._CoupledSystem(points, local, uv,
                                    _near_border(points, local) if natural else free,
                                    np.ones(len(points), dtype=bool) if natural else None)
    f = system.f
    phi = points.copy()
    spread = 2.0 if case == "folded" else 0.1
    phi[f] += spread * system.scale * np.random.default_rng(7).standard_normal((len(f), 3))
    if case == "degenerate":
        face = system.near[np.isin(system.near, f).any(axis=1)][0]
        mover = face[np.isin(face, f)][0]
        phi[mover] = phi[face[face != mover][0]]
    for rows in (system.moving, np.concatenate([system.moving[::2], system.moving[1::2]])):
        blocks = FaceBlocks.of(system, rows)
        with np.errstate(all="ignore"):
            want = blocks._blocks_numpy(phi)
            got = face_derivatives.kept_blocks(phi, blocks.faces, blocks.vertex_i,
                                               blocks.face_j, blocks.with_free, blocks.kept,
                                               lambda: pytest.fail("the kernel did not run"))
        assert kernel is not None
        for a, b in zip(got, want, strict=True):
            assert a.shape == b.shape and a.dtype == b.dtype
            assert np.array_equal(a.view(np.int64), b.view(np.int64))
        if case == "degenerate":
            assert not np.isfinite(want[1]).all()


def test_the_natural_data_s_adjacency_to_the_moving_vertices_is_made_again_where_replaced():
    # _d_stencil_H takes adjacency[:, m] made once a system (session 32 helper), made again
    # where a test replaces the adjacency (as tests above do)
    import scipy.sparse as sp

    from surfinpaint.representation.coupled_jacobian import _adjacency_moving

    _, points, _, (local, uv, _) = _system(30, 6)
    system = on_mesh._CoupledSystem(points, local, uv, _near_border(points, local),
                                    np.ones(len(points), dtype=bool))
    m = system.moving
    first, inner = _adjacency_moving(system)
    assert _adjacency_moving(system)[0] is first
    assert (first != system.adjacency[:, m]).nnz == 0
    assert np.array_equal(inner, system.inner[m][:, None])
    system.adjacency = (system.adjacency + sp.csr_matrix(
        (np.ones(1), ([0], [m[0]])), shape=system.adjacency.shape)).tocsr()
    again = _adjacency_moving(system)[0]
    assert again is not first and (again != system.adjacency[:, m]).nnz == 0


def test_the_compiled_right_hand_side_of_the_dense_jacobian_is_numpy_s_bit_for_bit():
    # _DenseJacobian.at's dn_f c + n_f ⊗ (u d_s_f + α d_H_f) from a numba kernel (session 32
    # helper): the same bits as numpy's four passes, on the Jacobian's own terms (a patch's
    # at a perturbed point) and on random ones with an inf and a NaN
    from surfinpaint.representation import face_derivatives
    from surfinpaint.representation.coupled_jacobian import _DenseJacobian

    kernel = pytest.importorskip("numba") and face_derivatives._RHS_KERNEL.get()
    rng = np.random.default_rng(8)
    m, P = 40, 120
    cases = [[rng.standard_normal((m, 3, P)), rng.standard_normal((m, 3)),
              *rng.standard_normal((2, m)), rng.standard_normal((m, P)),
              rng.standard_normal(m), rng.standard_normal((m, P))]]
    cases[0][0][3, 1, 7], cases[0][4][5, 2] = np.inf, np.nan
    calls = []
    system, _, phi, _ = _system(30, 6)
    original = face_derivatives.update_rhs

    def recording(*args):
        calls.append([np.array(a) for a in args])
        return original(*args)

    try:
        face_derivatives.update_rhs = recording
        import surfinpaint.representation.coupled_jacobian as coupled

        coupled.update_rhs = recording
        _DenseJacobian.of(system).at(phi)
    finally:
        face_derivatives.update_rhs = coupled.update_rhs = original
    assert len(calls) == 1
    for dn_f, n_f, c, u, d_s_f, alpha, d_H_f in cases + calls:
        with np.errstate(all="ignore"):
            q = u[:, None] * d_s_f + alpha[:, None] * d_H_f
            want = dn_f * c[:, None, None]
            want += n_f[:, :, None] * q[:, None, :]
            got = np.empty(dn_f.shape)
            kernel(dn_f, n_f, c, u, d_s_f, alpha, d_H_f, got)
        assert np.array_equal(got.view(np.int64), want.view(np.int64))


def test_the_products_index_and_capacitance_made_once_are_the_ones_made_each_time(large):
    # session 47 helper: UpdateDerivative takes the ring, its rows and Q_fk's columns from
    # an index made once a system (each Newton–Krylov step made them again), and I + K Y
    # from the lagged solve's state (the products' LU and the dense Jacobian made it again):
    # the same arrays, and products bit for bit those of the formulas as written before
    import scipy.linalg as sla

    from surfinpaint.representation.coupled_jacobian import _ProductIndex

    system, points, phi = large
    f, m, n = system.f, system.moving, len(points)
    index = _ProductIndex.of(system)
    assert _ProductIndex.of(system) is index
    where = np.full(n, -1)
    where[m] = np.arange(len(m))
    ring = np.setdiff1d(m, f)
    in_fixed, in_ring = np.full(n, -1), np.full(n, -1)
    in_fixed[system.fixed] = np.arange(len(system.fixed))
    in_ring[ring] = np.arange(len(ring))
    assert np.array_equal(index.where, where) and np.array_equal(index.ring, ring)
    assert all(np.array_equal(index.rows[k], where[ids]) for k, ids in (
        ("ring", ring), ("tied", system.tied), ("f", f)))
    assert np.array_equal(index.tied_in_ring, in_ring[system.tied])
    assert (index.Q_ring != system.Q_fk[:, in_fixed[ring]]).nnz == 0
    state = system._lagged(phi)[1]
    K, C = state[4], state[6]
    assert np.array_equal(C, np.eye(len(system.tied)) + K @ system.Y)
    derivative = UpdateDerivative(system, phi)
    y = np.random.default_rng(7).standard_normal((K.shape[1], 1))
    lu, piv = sla.lu_factor(np.eye(len(system.tied)) + K @ system.Y)
    assert np.array_equal(derivative._capacitance(K, C, y, False),
                          sla.lu_solve((lu, piv), K @ y))
    assert np.array_equal(derivative._capacitance(K, C, y, True),
                          np.linalg.solve(np.eye(len(system.tied)) + K @ system.Y, K @ y))
    assert np.array_equal(C, np.eye(len(system.tied)) + K @ system.Y)  # not factored in place
    # a second derivative at the same positions: its products are the first's, bit for bit
    V = np.random.default_rng(8).standard_normal((3 * len(f), 2))
    assert np.array_equal(UpdateDerivative(system, phi).apply(V), derivative.apply(V))
