"""The least-squares stage's continuation in the curvature weight ends where its weight step,
halved after each failed solve, falls below ``smallest`` (``CONTINUATION_SMALLEST``, or
``ConformalOptions.continuation_smallest``; docs/convergence.md, session 49 helper): a table
of cases on a synthetic continuation whose solves converge up to a weight and fail beyond."""

import numpy as np
import pytest

from surfinpaint import ConformalOptions
from surfinpaint.errors import FillError
from surfinpaint.representation import least_squares_stage as lsq_stage


class _Solvable:
    """A coupled system's stand-in: its solves (the fake ``newton_solve``) converge at
    curvature weights up to ``reach`` and fail beyond; each solve's weight is kept."""

    def __init__(self, reach):
        self.reach, self.curvature, self.tried, self.f = reach, 1.0, [], np.arange(1)


def _fake_solve(system, phi, tol, steps, envelope):
    system.tried.append(system.curvature)
    if system.curvature > system.reach:
        raise FillError("scripted: no fixed point at this weight")
    return phi + 1.0  # a new surface at each converged solve


def _continued(monkeypatch, reach, **kw):
    monkeypatch.setattr(lsq_stage, "newton_solve", _fake_solve)
    system = _Solvable(reach)
    start = [np.zeros((1, 3)), 0.0, lsq_stage.CONTINUATION_STEP, 0, False]
    state = lsq_stage.curvature_continuation(system, np.zeros((1, 3)), resume=start, **kw)
    return state, system


# (solves converge up to, smallest step, weight reached, solves made): the steps are dyadic,
# so every weight is exact. reach 0.3 by hand: 0.125 +, 0.375 -, 0.25 +, 0.5 -, 0.375 -,
# 0.3125 -, 0.28125 +, 0.34375 -, 0.3125 -, 0.296875 +, 0.328125 -, 0.3125 -, 0.3046875 -,
# 0.30078125 -, 0.298828125 +, 0.302734375 -, 0.30078125 - (step 2^-10 < 1e-3: ended)
@pytest.mark.parametrize("reach, smallest, weight, solves", [
    (1.0, 1e-3, 1.0, 4),  # 0.125, 0.375, 0.875, 1: every solve converges
    (1.0, 0.125, 1.0, 4),  # the rule never fires on a continuation that does not stall
    (0.0, 1e-3, 0.0, 7),  # every solve fails: steps 2^-3 .. 2^-9
    (0.0, 0.004, 0.0, 5),  # steps 2^-3 .. 2^-7
    (0.0, 0.0156, 0.0, 4),  # steps 2^-3 .. 2^-6 (2^-6 = 0.015625 is still tried)
    (0.0, 0.125, 0.0, 1),  # the first step only
    (0.3, 1e-3, 0.298828125, 17),
    (0.3, 0.002, 0.296875, 14),  # stops at the step 2^-9 after the 14th solve
    (0.3, 0.004, 0.296875, 13),
    (0.3, 0.0156, 0.296875, 12),  # the 12th solve fails at step 2^-6: 2^-7 is not tried
    (0.3, 0.125, 0.25, 5),  # 0.125 +, 0.375 -, 0.25 +, 0.5 -, 0.375 -: step 2^-4
])
def test_the_continuation_ends_where_its_step_falls_below_smallest(
        monkeypatch, reach, smallest, weight, solves):
    state, system = _continued(monkeypatch, reach, smallest=smallest)
    assert state[1] == weight and state[3] == solves and state[4]
    assert system.curvature == 1.0  # restored
    # the same path as the default's, cut short: its solves are the default's first ones
    _, default = _continued(monkeypatch, reach)
    assert system.tried == default.tried[:solves]
    assert lsq_stage.continuation_ended(state[1], state[2], state[3], smallest)


def test_a_continuation_cut_short_resumes_to_the_same_end(monkeypatch):
    # stopped after each solve and resumed with the same smallest step: the one made in one go
    whole, _ = _continued(monkeypatch, 0.3, smallest=0.004)
    monkeypatch.setattr(lsq_stage, "newton_solve", _fake_solve)
    system = _Solvable(0.3)
    state = [np.zeros((1, 3)), 0.0, lsq_stage.CONTINUATION_STEP, 0, False]
    while not state[4]:
        state = lsq_stage.curvature_continuation(system, np.zeros((1, 3)), solves=1,
                                                 resume=state, smallest=0.004)
    np.testing.assert_array_equal(state[0], whole[0])
    assert state[1:] == whole[1:]


def test_the_option_reaches_the_continuation_and_least_squares(monkeypatch):
    # ConformalOptions.continuation_smallest is the smallest step of both calls of the stage
    # (the continuation made first, solve by solve, and the least-squares stage that takes it
    # on), on a patch whose solve fails
    import sys
    from pathlib import Path

    from surfinpaint.fill.conformal import mesh_pass
    from surfinpaint.fill.liepa.baseline import faired_fill

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from eggcrate import egg_crate

    cut = egg_crate(20, 3, 7, 2.5, 0.4, 6)
    new_v, new_f, _ = faired_fill(cut.vertices, cut.faces, cut.loop, 3)
    vertices = np.vstack([cut.vertices, new_v])
    _, ids, faces, uv, _, _ = mesh_pass._mapped_patch(vertices, cut.faces, cut.loop, new_f, 4)
    points, free = vertices[ids], ids >= len(cut.vertices)
    seen = []
    continuation = mesh_pass.curvature_continuation
    least_squares = mesh_pass.least_squares_on_mesh

    def failing_solve(*args, **kw):
        raise FillError("scripted: Newton's method fails")

    def spied_continuation(*args, smallest, **kw):
        seen.append(("continuation", smallest))
        return continuation(*args, smallest=smallest, **kw)

    def spied_least_squares(*args, smallest, **kw):
        seen.append(("least squares", smallest))
        return least_squares(*args, smallest=smallest, **kw)

    monkeypatch.setattr(mesh_pass, "inpaint_on_mesh", failing_solve)
    monkeypatch.setattr(mesh_pass, "curvature_continuation", spied_continuation)
    monkeypatch.setattr(mesh_pass, "least_squares_on_mesh", spied_least_squares)
    natural = np.zeros(len(points), dtype=bool)
    try:
        mesh_pass._solve_or_subdivide(points, faces, uv, free, len(new_f), natural, 20, 1e-3,
                                      True, False, 0.0625)
    except FillError:
        pass  # the lattice stage after it may fail too: what is checked is what was called
    assert seen and {s for _, s in seen} == {0.0625}
    assert {name for name, _ in seen} == {"continuation", "least squares"}


def test_the_continuation_option_is_the_default_s_step_and_checked():
    assert ConformalOptions().continuation_smallest == lsq_stage.CONTINUATION_SMALLEST
    assert ConformalOptions(continuation_smallest=0.004).continuation_smallest == 0.004
    for bad in (0, -1e-3, 0.2, True, float("nan"), "0.01"):
        with pytest.raises(ValueError, match="continuation_smallest"):
            ConformalOptions(continuation_smallest=bad)


def test_the_fill_passes_the_option_to_its_patch_solve(monkeypatch):
    # conformal_fill's λ-H pass gives the patch solve the option's smallest step
    import sys
    from pathlib import Path

    from surfinpaint.fill.conformal import candidates, conformal_fill

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
    from eggcrate import egg_crate

    seen = []
    solve = candidates.inpaint_patch_on_mesh

    def spied(*args, **kw):
        seen.append(kw["continuation_smallest"])
        return solve(*args, **kw)

    monkeypatch.setattr(candidates, "inpaint_patch_on_mesh", spied)
    cut = egg_crate(20, 1, 8, 3.0, 0.4, 4)
    conformal_fill(cut.vertices, cut.faces, cut.loop,
                   ConformalOptions(select=False, continuation_smallest=0.03))
    assert seen and set(seen) == {0.03}
