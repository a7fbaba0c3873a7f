"""The self-check's work whose result cannot change what is written is skipped (session 36):
the smooth λ-H fill of a test hole where only a crease fill scores, and the λ-H fills of
sibling holes after it failed on one. The fill written must be the one of the eager path."""

import numpy as np
import pytest

import surfinpaint.fill.conformal.method as method
from surfinpaint.data import cube
from surfinpaint.errors import FillError
from surfinpaint.fill.conformal import ConformalOptions
from surfinpaint.fill.conformal.candidates import Candidates
from surfinpaint.fill.conformal.method import _lambda_h_until_it_fails, conformal_fill
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import mean_edge_length


class _Scripted:
    """A stand-in for :class:`Candidates` whose test fills follow a script: the λ-H fill of
    the k-th call with it fails where ``fails[k]``; the calls are counted."""

    def __init__(self, fails):
        self.fails = list(fails)
        self.calls = {True: 0, False: 0}

    def for_tests(self, *, with_lambda_h=True):
        def fills(vertices, faces, loop):
            self.calls[with_lambda_h] += 1
            out = {"fair2": "f2", "fair3": "f3"}
            if with_lambda_h:
                k = self.calls[True] - 1
                out["conformal"] = FillError(f"failed {k}") if self.fails[k] else f"lh{k}"
            return out
        return fills


def test_the_lambda_h_fill_is_left_out_after_it_failed_on_a_sibling_hole():
    scripted = _Scripted([False, True, False, False])
    fills = _lambda_h_until_it_fails(scripted)
    first, second, third, fourth = (fills(None, None, None) for _ in range(4))
    assert first == {"fair2": "f2", "fair3": "f3", "conformal": "lh0"}
    assert isinstance(second["conformal"], FillError)
    # after the failure: the faired fills only, the same failure given again
    assert third["conformal"] is second["conformal"] is fourth["conformal"]
    assert (third["fair2"], third["fair3"]) == ("f2", "f3")
    assert scripted.calls == {True: 2, False: 2}


def test_without_the_lambda_h_fill_nothing_is_left_out():
    scripted = _Scripted([True, True])
    fills = _lambda_h_until_it_fails(scripted, with_lambda_h=False)
    assert [fills(None, None, None) for _ in range(2)] == [{"fair2": "f2", "fair3": "f3"}] * 2
    assert scripted.calls == {True: 0, False: 2}


def _crossed_cube_hole():
    """A hole across an edge of a cube: a crease crosses it; its hidden-ring hole and sibling
    holes are not all crossed, so their λ-H fills fail there."""
    v, f = cube(8)
    h = mean_edge_length(v, f)
    cut = cut_geodesic_disk(v, f, np.array([1.0, 1.0, 0.5]), 2.0 * h)
    return cut.vertices, cut.faces, cut.loop


def test_a_test_hole_of_a_crossed_hole_gets_no_smooth_lambda_h_fill():
    v, f, loop = _crossed_cube_hole()
    candidates = Candidates.for_hole(v, f, loop, ConformalOptions())
    assert candidates.crossed
    # a test hole on one side of the edge: no crease crosses it
    h = mean_edge_length(v, f)
    side = cut_geodesic_disk(v, f, np.array([0.35, 1.0, 0.5]), 2.2 * h)
    s0 = candidates.initial(side.vertices, side.faces, side.loop)
    smooth = candidates.lambda_h(side.vertices, side.faces, side.loop, s0, test=True)
    assert smooth.crease is None and len(smooth.vertices)
    with pytest.raises(FillError, match="no crease crosses the test hole"):
        candidates.lambda_h(side.vertices, side.faces, side.loop, s0, test=True,
                            crease_only=True)


def _eager_for_tests(self, *, with_lambda_h=True):
    """:meth:`Candidates.for_tests` as before session 36: every test hole's λ-H fill made,
    a smooth one thrown away afterwards where a crease crosses the hole."""
    def fills(vertices, faces, loop):
        out = dict(self.faired(vertices, faces, loop))
        if not with_lambda_h:
            return out
        s0 = self.initial(vertices, faces, loop, out)
        try:
            made = self.lambda_h(vertices, faces, loop, s0, test=True)
            if self.crossed and made.crease is None:
                raise FillError("no crease crosses the test hole")
            out["conformal"] = made
        except FillError as exc:
            out["conformal"] = exc
        return out
    return fills


def _written(fill):
    return (fill.vertices.tobytes(), fill.faces.tobytes(), fill.kind, fill.fair_order,
            fill.selection, repr(fill.verdict), fill.crease, repr(fill.diagnostics))


def test_the_lazy_self_check_writes_the_eager_fill(monkeypatch):
    v, f, loop = _crossed_cube_hole()
    passes = []  # the λ-H passes run (the costly part of a λ-H fill)
    run_passes = Candidates._passes

    def counting(self, *args, **kwargs):
        passes.append(kwargs.get("test"))
        return run_passes(self, *args, **kwargs)

    monkeypatch.setattr(Candidates, "_passes", counting)
    # the self-check's path (the default writes the ear-cut fill here: session 51)
    lambda_h = ConformalOptions(ear_cut_flat=None)
    lazy = conformal_fill(v, f, loop, lambda_h)
    lazy_passes = len(passes)
    assert "sibling holes: λ-H inf" in lazy.selection  # both skips are on this path
    monkeypatch.setattr(Candidates, "for_tests", _eager_for_tests)
    monkeypatch.setattr(method, "_lambda_h_until_it_fails",
                        lambda candidates, with_lambda_h=True:
                        candidates.for_tests(with_lambda_h=with_lambda_h))
    passes.clear()
    eager = conformal_fill(v, f, loop, lambda_h)
    assert _written(lazy) == _written(eager)
    assert lazy_passes < len(passes)
