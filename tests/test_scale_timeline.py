"""benchmarks/scale_timeline.py: the stages it wraps are the fill's (a renamed function makes
the child fail here, not in the next session's profile), and it reports each stage once per
call, on its thread, with the process's and its workers' usage."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from surfinpaint import data
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.io import write_mesh

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
scale_timeline = pytest.importorskip("scale_timeline")


def test_a_small_fill_is_timed_stage_by_stage(tmp_path):
    v, f = data.sphere(3)
    cut = cut_geodesic_disk(v, f, 0, 0.5)
    mesh = tmp_path / "holed.ply"
    write_mesh(mesh, cut.vertices, cut.faces)
    rows, usage, wall = scale_timeline.run_once(mesh, tmp_path / "out.ply", "fair", tmp_path)
    names = [row[0] for row in rows]
    # one hole, filled here (a small mesh: no worker, no passes beside the checks)
    for stage in ("import the command line", "read_mesh_data", "fill_mesh_data",
                  "check_arrays", "triangle_rows", "EdgeTable.build", "check_topology",
                  "find_holes", "triangle_incidence", "fill_hole", "FilledMesh.result",
                  "far_crossing_triangles", "write_with_materials", "cli.main"):
        assert stage in names, stage
    assert names.count("fill_hole") == 1
    assert {row[1] for row in rows} == {"MainThread"}
    for _, _, start, end, cpu, faults in rows:
        assert 0 <= start <= end <= wall and cpu >= 0 and faults >= 0
    user, system, faults, *workers = usage
    assert user > 0 and faults > 0 and workers == [0.0, 0.0, 0]
    assert (tmp_path / "out.ply").stat().st_size > mesh.stat().st_size
