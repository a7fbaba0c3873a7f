"""benchmarks/fill_fingerprints.py: the digests see a moved position and a changed decision,
and the tool never fills a holdout set or the validation half."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from surfinpaint import data
from surfinpaint.geometry.cutting import cut_geodesic_disk

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
fill_fingerprints = pytest.importorskip("fill_fingerprints")


@pytest.fixture(scope="module")
def sphere_cut():
    v, f = data.sphere(3)
    return cut_geodesic_disk(v, f, 0, 0.5)


def test_the_same_fill_gives_the_same_digests(sphere_cut):
    a = fill_fingerprints.fingerprint(sphere_cut)
    b = fill_fingerprints.fingerprint(sphere_cut)
    assert a == b
    assert len(a["geometry"]) == len(a["report"]) == 16


def test_a_moved_known_vertex_changes_the_geometry_digest(sphere_cut):
    from dataclasses import replace

    v = sphere_cut.vertices.copy()
    v[sphere_cut.loop[0]] *= 1.0 + 1e-9  # one boundary vertex, a billionth: the fill moves
    moved = replace(sphere_cut, vertices=v)
    assert (fill_fingerprints.fingerprint(moved)["geometry"]
            != fill_fingerprints.fingerprint(sphere_cut)["geometry"])


@pytest.mark.parametrize(("now", "geometry", "report"), [
    ({"a": {"geometry": "1", "report": "x"}}, [], []),              # the same
    ({"a": {"geometry": "2", "report": "x"}}, ["a"], []),           # a position moved
    ({"a": {"geometry": "2", "report": "y"}}, ["a"], []),           # both: counted as geometry
    ({"a": {"geometry": "1", "report": "y"}}, [], ["a"]),           # a decision or score only
    ({"b": {"geometry": "9", "report": "z"}}, [], []),              # not in the reference
])
def test_compare_sorts_the_holes_that_changed(now, geometry, report):
    reference = {"a": {"geometry": "1", "report": "x"}}
    assert fill_fingerprints.compare(now, reference) == (geometry, report)


@pytest.mark.parametrize("name", ["holdout29", "holdout28", "holdout27", "holdout26",
                                  "holdout25", "holdout24", "holdout23", "holdout22",
                                  "holdout21", "holdout20", "holdout19", "validation",
                                  "holdout9"])
def test_holdout_sets_and_the_validation_half_are_refused(name):
    with pytest.raises(SystemExit, match="not a tuning-side set"):
        fill_fingerprints.tuning_entries([name])


def test_the_default_sets_are_the_196_tuning_side_holes():
    entries = fill_fingerprints.tuning_entries(list(fill_fingerprints.DEFAULT_SETS))
    assert {e["split"] for _, e in entries} == {"tuning", "cad_tuning"}
    assert sum(len(e["holes"]) for _, e in entries) == 196


def test_a_mesh_this_machine_cannot_make_is_skipped_and_named(monkeypatch, capsys):
    def differs(entry):
        raise RuntimeError(f"{entry['mesh']} has the manifest's counts but not its bytes")

    monkeypatch.setattr(fill_fingerprints.validation.vm, "load_entry", differs)
    assert fill_fingerprints.run(["cad_tuning"], meshes=["shaft"]) == {}
    assert "skipping cad_tuning/shaft: shaft has the manifest's counts" in capsys.readouterr().err
