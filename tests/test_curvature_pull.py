"""The pull of the coupled solve's H inpainting towards the start's H
(surfinpaint.representation.curvature_pull; option ConformalOptions.curvature_pull)."""

import numpy as np
import pytest
import scipy.sparse as sp
from test_on_mesh import grid_mesh

from surfinpaint.fill.conformal.options import ConformalOptions
from surfinpaint.geometry.mesh import laplacian_and_areas
from surfinpaint.representation.analytic import enneper, isothermal_torus
from surfinpaint.representation.curvature_pull import pulled_energy, start_pull
from surfinpaint.representation.on_mesh import coupled_system, inpaint_on_mesh


def enneper_hole(n=25, radius=0.55):
    u, v, uv, faces = grid_mesh(n)
    phi, _, _ = enneper(u, v)
    truth = phi.reshape(-1, 3)
    free = np.linalg.norm(uv, axis=1) < radius
    return truth, faces, uv, free


def test_no_pull_is_the_plain_biharmonic_block():
    truth, faces, uv, free = enneper_hole()
    L, area = laplacian_and_areas(uv, faces)
    Q = (L @ sp.diags(1.0 / area) @ L).tocsc()
    f = np.flatnonzero(free)
    block = Q[f][:, f]
    out = start_pull(block, block, truth, faces, uv, f, area, 0.0)
    assert out[0] is block and out[2] is block and out[1] == 0.0 and out[3] == 0.0
    pulled, rhs = pulled_energy(block, np.full(len(f), 2.0), area[f], 0.5)
    added = (pulled - block).diagonal()
    # the pull is on the free rows' diagonal only, area / scale, towards the target
    assert abs(pulled - block - sp.diags(added)).max() == 0.0
    assert np.allclose(added, area[f] / 0.5) and np.allclose(rhs, 2.0 * added)
    H_h, rhs_h, lam_h, rhs_lam = start_pull(block, block, truth, faces, uv, f, area, 1.0)
    # Enneper's surface is minimal: its H, the H pull's target, is ~0 on the grid; its λ
    # (1 + u² + v²) is not
    assert np.abs(rhs_h).max() < 1e-6 * np.abs(rhs_lam).max()


def test_the_pull_holds_the_fill_to_a_true_start():
    # a torus hole, whose λ and H the biharmonic inpainting does not continue exactly:
    # started from the surface itself, whose own λ and H are the truth, the pulled ones
    # have less to get wrong and the fill stays nearer the truth than the plain one
    # (measured 0.07e-3 against 0.78e-3)
    u, v, uv, faces = grid_mesh(25, (0.0, 1.5, -0.75, 0.75))
    truth = isothermal_torus(u, v)[0].reshape(-1, 3)
    free = np.linalg.norm(uv - uv.mean(axis=0), axis=1) < 0.3
    start = truth.copy()
    plain = inpaint_on_mesh(start, faces, uv, free)
    pulled = inpaint_on_mesh(start, faces, uv, free,
                             system=coupled_system(start, faces, uv, free, pull=10.0))
    error_plain = np.abs(plain - truth)[free].max()
    error_pulled = np.abs(pulled - truth)[free].max()
    assert error_pulled < 0.5 * error_plain
    # without a pull the system is the default one, to the bit
    again = inpaint_on_mesh(start, faces, uv, free,
                            system=coupled_system(start, faces, uv, free, pull=0.0))
    assert np.array_equal(again, plain)


@pytest.mark.parametrize("bad", [-1.0, float("nan"), True, "1"])
def test_the_pull_option_is_checked(bad):
    assert ConformalOptions().curvature_pull == 0.0
    with pytest.raises(ValueError, match="curvature_pull"):
        ConformalOptions(curvature_pull=bad)
