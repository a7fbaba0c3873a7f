"""Progress inside a hole: the conformal fill says each of its stages as it starts, to the
``progress`` of ``fill_holes`` and so to ``fill``'s bar and ``batch``'s (session 47: a
200-edge hole's fill took 5-30 s, a nut's bore 367 s, with the display standing still)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from surfinpaint import fill_holes
from surfinpaint.app.batch import fill_files
from surfinpaint.data import sphere
from surfinpaint.fill.conformal.method import STAGES, conformal_fill
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import boundary_loops
from surfinpaint.io import write_mesh


@pytest.fixture(scope="module")
def holed():
    """A sphere with one 15-edge hole, whose fill is the λ-H fill (no plane around it)."""
    v, f = sphere(3)
    cut = cut_geodesic_disk(v, f, 0, 0.5)
    return cut.vertices, cut.faces


def test_the_conformal_fill_tells_its_stages_in_order(holed):
    vertices, faces = holed
    heard: list[str] = []
    fill = conformal_fill(vertices, faces, boundary_loops(faces)[0], stage=heard.append)
    assert fill.kind == "conformal"  # the λ-H fill won: every stage it ran is said
    assert heard[0] == STAGES[0] and heard[-1] == "λ-H fill"
    assert "self-check: hidden-ring test" in heard
    positions = [STAGES.index(name) for name in heard]
    assert positions == sorted(set(positions))  # in order, each once


def test_fill_holes_progress_says_the_hole_and_its_stage(holed):
    vertices, faces = holed
    said: list[tuple[int, int, str]] = []
    result = fill_holes(vertices, faces, jobs=1,
                        progress=lambda done, total, message: said.append((done, total,
                                                                           message)))
    stages = [m for _, _, m in said if "(stage " in m]
    assert said[0] == (0, 1, "hole 0: 15 edges, conformal")
    assert said[-1][:2] == (1, 1) and said[-1][2].startswith("hole 0: done in")
    assert stages[0] == f"hole 0: 15 edges, faired fills (stage 1 of {len(STAGES)})"
    assert stages[-1] == f"hole 0: 15 edges, λ-H fill (stage {len(STAGES)} of {len(STAGES)})"
    # between the hole's start and its end, the holes done still 0 of 1
    assert said[1:-1] == [(0, 1, m) for m in stages]
    numbers = [int(re.search(r"stage (\d) of", m).group(1)) for m in stages]
    assert numbers == sorted(set(numbers))
    # progress only: the same fill as without anyone listening
    quiet = fill_holes(vertices, faces, jobs=1)
    np.testing.assert_array_equal(result.vertices, quiet.vertices)
    np.testing.assert_array_equal(result.faces, quiet.faces)


def test_a_faired_fill_has_no_stages(holed):
    said: list[str] = []
    fill_holes(*holed, method="fair", jobs=1, progress=lambda d, t, m: said.append(m))
    assert not any("stage" in m for m in said) and len(said) == 2


def test_batch_progress_names_the_file_its_hole_and_the_stage(holed, tmp_path):
    (tmp_path / "in").mkdir()
    write_mesh(tmp_path / "in" / "scan.ply", *holed)
    said: list[str] = []
    fill_files([tmp_path / "in"], tmp_path / "out", jobs=1,
               progress=lambda done, total, message: said.append(message))
    assert (f"{tmp_path / 'in' / 'scan.ply'}: 0/1 holes (hole 0: 15 edges, λ-H fill (stage "
            f"{len(STAGES)} of {len(STAGES)}))") in said, said
