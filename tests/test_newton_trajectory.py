"""The turning test of a Newton stage (representation.newton_trajectory.turning) on trajectories
logged on the tuning side (docs/convergence.md, session 35 (helper)): through the Newton stage
itself, with its steps and line searches scripted."""

import numpy as np
import pytest

import surfinpaint.representation.newton_trajectory as newton_trajectory
import surfinpaint.representation.on_mesh as on_mesh
from surfinpaint.errors import FillError


class _Script:
    """A stand-in for the coupled system whose Newton stage takes the logged steps: step k's
    longest entry is ``longest[k]`` (before the trust region's cut), its line search takes the
    fraction ``fractions[k]`` of it and leaves the residual ``residuals[k + 1]`` (edge lengths,
    scale 1); ``residuals[0]`` is the start's. The line search after the last fraction fails
    (no step lowers the residual), as the logged failing stages did."""

    def __init__(self, residuals, longest, fractions):
        self.f = np.arange(4)
        self.scale = 1.0
        self.residuals, self.longest, self.fractions = residuals, longest, fractions
        self.steps = 0

    def update(self, phi):
        return phi[self.f] + self.residuals[0]


def _scripted(monkeypatch, residuals, longest, fractions) -> _Script:
    script = _Script(residuals, longest, fractions)

    def newton_step(system, points, x, r):
        return np.full(x.shape, script.longest[script.steps])

    def line_search(residual, x, r, dx):
        if script.steps == len(script.fractions):  # where the logged stage failed
            raise FillError("no step lowers its residual")
        taken = script.fractions[script.steps]
        script.steps += 1
        return x + taken * dx, np.full(r.shape, script.residuals[script.steps]), taken

    monkeypatch.setattr(on_mesh, "newton_step", newton_step)
    monkeypatch.setattr(on_mesh, "_line_search", line_search)
    return script


# (name, continuation solve?, residuals, longest steps, line-search fractions, given up after)
_CASES = [
    # converged on the tuning side, and keep going: the closest to the test, a CAD part's
    # 225-vertex stage, every step cut to a quarter for 7 steps but shrinking (by 0.91 at most
    # over two)
    ("cut, shrinking", False,
     [1.43, 1.44, 0.899, 0.61, 0.567, 0.543, 0.508, 0.476, 0.442, 0.404, 0.374, 0.333, 0.0546,
      0.00108, 1.48e-06],
     [5.11, 11.0, 10.8, 7.41, 6.97, 6.37, 5.49, 4.45, 3.33, 2.21, 1.37, 0.45, 0.071, 0.00128],
     [1, 1, 1, 0.25, 0.25, 0.25, 0.25, 0.25, 0.25, 0.25, 0.5, 1, 1, 1], None),
    # an animal's continuation solve: growing by 1.23 and 1.62, cut to a half and a sixteenth
    ("grows, cut by half first", True,
     [1.89, 1.48, 1.38, 1.37, 1.21, 1.08, 0.136, 0.00461, 8.31e-06],
     [1.6, 1.97, 3.19, 1.01, 0.753, 0.0844, 0.0269, 0.00149],
     [0.5, 0.5, 0.0625, 0.5, 0.5, 1, 1, 1], None),
    # a quadruped's continuation solve: a step 9 times as long as the one before, taken whole
    ("grows, taken whole", True,
     [4.08, 4.0, 3.79, 3.69, 1.83, 1.65, 0.436, 0.282, 0.132, 0.00618, 1.97e-05],
     [29.6, 271.0, 12.0, 19.6, 6.24, 2.54, 0.494, 0.413, 0.0254, 0.00134],
     [1, 1, 0.5, 0.5, 0.5, 1, 0.25, 1, 1, 1], None),
    # an egg-crate's continuation solve: cut for six steps, one of them growing by 1.02
    ("cut, one growing", True,
     [0.166, 0.0248, 0.0235, 0.0209, 0.019, 0.017, 0.0147, 0.0107, 0.00235, 2.23e-05],
     [0.286, 0.217, 0.183, 0.187, 0.167, 0.125, 0.089, 0.0412, 0.00239],
     [0.5, 0.25, 0.25, 0.125, 0.25, 0.25, 0.5, 1, 1], None),
    # failed on the tuning side, given up where two steps in a row grew by 1.25 at least and
    # were cut to a quarter at most: CAD channel #5's continuation solve at w = 0.875 (it
    # failed at step 5 where no step lowered its residual)
    ("channel #5 at a fold", True,
     [0.643, 0.642, 0.643, 0.643, 0.643],
     [1.52, 2.85, 8.74, 17.7, 35.7],
     [0.0625, 0.0625, 0.0156, 0.00781], 3),
    # the same outside the continuation, and a step that grows only on the second cut
    ("fold, a stage", False,
     [0.643, 0.642, 0.643, 0.643, 0.643],
     [1.52, 2.85, 8.74, 17.7, 35.7],
     [0.0625, 0.0625, 0.0156, 0.00781], 3),
    ("grows from step 2", False,
     [0.5, 0.4, 0.39, 0.39, 0.39, 0.39],
     [1.0, 0.9, 1.2, 1.6, 3.0, 5.0],
     [1, 0.25, 0.25, 0.25, 0.125], 4),
]


@pytest.mark.parametrize("name, continuation, residuals, longest, fractions, given_up_after",
                         _CASES, ids=[case[0] for case in _CASES])
def test_a_newton_stage_is_given_up_where_its_steps_turn(monkeypatch, name, continuation,
                                                         residuals, longest, fractions,
                                                         given_up_after):
    script = _scripted(monkeypatch, residuals, longest, fractions)
    envelope = on_mesh.CONTINUATION_ENVELOPE if continuation else None
    steps = on_mesh.CONTINUATION_NEWTON if continuation else on_mesh.NEWTON_STEPS
    points = np.zeros((4, 3))

    def solve():
        return on_mesh._newton_solve(script, points, 1e-3, steps, envelope)

    if given_up_after is None:
        solve()  # converges: every logged step taken
        assert script.steps == len(longest)
        return
    with pytest.raises(FillError, match=f"after {given_up_after} steps, its steps growing"):
        solve()
    assert script.steps == given_up_after
    # without the test the stage runs on past that step (where it failed on the log)
    monkeypatch.setattr(newton_trajectory, "TURN_CUT", 0.0)
    script.steps = 0
    with pytest.raises(FillError) as failure:
        solve()
    assert "its steps growing" not in str(failure.value)
    assert script.steps > given_up_after


@pytest.mark.parametrize("longest, fractions, turns", [
    ([1.0, 1.25, 1.5625], [0.25, 0.25, 0.25], True),  # both at the bounds
    ([1.0, 1.25, 1.5625], [1.0, 0.25, 0.25], True),  # the first step's cut is not read
    ([1.0, 1.24, 1.55], [0.25, 0.25, 0.25], False),  # growing by less
    ([1.0, 1.25, 1.5625], [0.25, 0.5, 0.25], False),  # one step cut by half only
    ([1.0, 1.25], [0.25, 0.25], False),  # two steps: no step before the first to compare
    ([3.0, 1.0, 2.0, 0.5, 1.0], [1, 1, 0.125, 0.125, 0.125], False),  # not two in a row
])
def test_the_turning_test_reads_the_last_two_steps(longest, fractions, turns):
    assert newton_trajectory.turning(longest, fractions) is turns
