"""The validation benchmark's checked-in hole manifest is well formed and split by mesh.

Reads ``benchmarks/holes_manifest.json`` and the tables of ``benchmarks/holes_manifest.py``
and ``benchmarks/validation_meshes.py`` only: no mesh is loaded.
"""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
holes_manifest = pytest.importorskip("holes_manifest")
validation_meshes = pytest.importorskip("validation_meshes")

KINDS = {"range_scan", "organic", "cad", "brain", "teeth", "smooth"}


@pytest.fixture(scope="module")
def manifest():
    return holes_manifest.read()


def test_entries_are_well_formed(manifest):
    assert manifest["meshes"]
    for entry in manifest["meshes"]:
        assert set(entry) - {"sha256_without_avx512", "sha256_missing"} == {
            "mesh", "kind", "source", "split", "n_vertices", "n_faces", "sha256", "h",
            "holes"} - ({"sha256"} if "sha256_missing" in entry else set()), entry["mesh"]
        assert entry["kind"] in KINDS and entry["split"] in ("tuning", "validation")
        assert entry["n_vertices"] > 0 and entry["n_faces"] > 0 and entry["h"] > 0
        assert entry["holes"], entry["mesh"]
        for hole in entry["holes"]:
            assert set(hole) == {"centre", "radius", "radius_h", "near_border", "on_feature"}
            assert len(hole["centre"]) == 3 and np.isfinite(hole["centre"]).all()
            assert 3 <= hole["radius_h"] <= 10
            assert hole["radius"] == pytest.approx(hole["radius_h"] * entry["h"], rel=1e-12)


def test_split_is_by_mesh_and_fixed(manifest):
    ids = [e["mesh"] for e in manifest["meshes"]]
    assert len(ids) == len(set(ids)), "a mesh is listed twice"
    tuning, validation = (set(holes_manifest.SPLIT[s]) for s in ("tuning", "validation"))
    assert not tuning & validation
    for entry in manifest["meshes"]:
        assert entry["mesh"] in holes_manifest.SPLIT[entry["split"]], entry["mesh"]
        source = validation_meshes.SOURCES[entry["mesh"]]
        assert (source.kind, source.source) == (entry["kind"], entry["source"])


def test_size_and_balance(manifest):
    meshes = manifest["meshes"]
    assert len(meshes) >= 25
    assert {e["kind"] for e in meshes} == KINDS
    assert sum(len(e["holes"]) for e in meshes) >= 200
    per = Counter((e["kind"], e["split"]) for e in meshes)
    for kind in KINDS:  # every kind in both halves, balanced
        assert per[(kind, "tuning")] >= 2 and per[(kind, "validation")] >= 2, kind
        assert abs(per[(kind, "tuning")] - per[(kind, "validation")]) <= 1, kind
    holes = [h for e in meshes for h in e["holes"]]
    assert sum(h["near_border"] for h in holes) >= 10
    assert sum(h["on_feature"] for h in holes) >= 10
    assert {h["radius_h"] for h in holes} >= {3, 10}


def test_meshes_used_before_are_in_the_tuning_half(manifest):
    """The meshes of the default accuracy set (on which the self-check rules were chosen)
    must not be in the validation half."""
    split = {e["mesh"]: e["split"] for e in manifest["meshes"]}
    for mesh in ("face000", "bunny", "pial", "white", "sphere", "torus", "cube40", "snowman",
                 "tooth"):
        assert split[mesh] == "tuning", mesh


def test_reserved_sources_are_never_used():
    """Debian's libcgal-demo meshes and the fsaverage5 right hemisphere are kept for an
    independent evaluation."""
    code = (BENCH / "validation_meshes.py").read_text().split('"""', 2)[2].lower()  # no docstring
    assert "libcgal" not in code and "cgal-demo" not in code and "/cgal" not in code
    assert "right" not in code
    assert '"left"' in code
    # holdouts 8 to 29's generators have their own modules (validation_meshes imports them)
    for module in ("holdout8_meshes.py", "holdout9_meshes.py", "holdout10_meshes.py",
                   "holdout11_meshes.py", "holdout12_meshes.py", "holdout13_meshes.py",
                   "holdout14_meshes.py", "holdout15_meshes.py", "holdout16_meshes.py",
                   "holdout17_meshes.py", "holdout18_meshes.py", "holdout19_meshes.py",
                   "holdout20_meshes.py", "holdout21_meshes.py", "holdout22_meshes.py",
                   "holdout23_meshes.py", "holdout24_meshes.py", "holdout25_meshes.py",
                   "holdout26_meshes.py", "holdout27_meshes.py", "holdout28_meshes.py",
                   "holdout29_meshes.py", "smooth_tuning_meshes.py", "curved_scans_meshes.py",
                   "thin_shells_meshes.py"):
        code = (BENCH / module).read_text().split('"""', 2)[2].lower()
        assert "cgal" not in code and "right" not in code and "fsaverage" not in code, module


@pytest.fixture(scope="module")
def holdout():
    return holes_manifest.read(holes_manifest.HOLDOUT_MANIFEST)


def test_the_holdout_set_is_fresh_and_well_formed(manifest, holdout):
    """The holdout set (run once after session 25's choices): its own meshes, from sources
    the two halves do not use, every kind but brain surfaces, 7 holes a mesh."""
    ids = [e["mesh"] for e in holdout["meshes"]]
    assert ids == holes_manifest.SPLIT["holdout"] == list(validation_meshes.HOLDOUT_SOURCES)
    halves = {e["mesh"] for e in manifest["meshes"]}
    assert not halves & set(ids)
    sources = {e["source"] for e in manifest["meshes"]}
    for entry in holdout["meshes"]:
        assert entry["split"] == "holdout" and entry["source"] not in sources, entry["mesh"]
        source = validation_meshes.SOURCES[entry["mesh"]]
        assert (source.kind, source.source) == (entry["kind"], entry["source"])
        assert [h["radius_h"] for h in entry["holes"]] == list(holes_manifest.RADII_H)
        for hole in entry["holes"]:
            assert hole["radius"] == pytest.approx(hole["radius_h"] * entry["h"], rel=1e-12)
    assert {e["kind"] for e in holdout["meshes"]} == KINDS - {"brain"}
    holes = [h for e in holdout["meshes"] for h in e["holes"]]
    assert sum(h["near_border"] for h in holes) >= 6 and sum(h["on_feature"] for h in holes) >= 3


@pytest.fixture(scope="module")
def holdout2():
    return holes_manifest.read(holes_manifest.HOLDOUT2_MANIFEST)


@pytest.fixture(scope="module")
def holdout3():
    return holes_manifest.read(holes_manifest.HOLDOUT3_MANIFEST)


@pytest.fixture(scope="module")
def cad_tuning():
    return holes_manifest.read(holes_manifest.CAD_TUNING_MANIFEST)


@pytest.fixture(scope="module")
def holdout4():
    return holes_manifest.read(holes_manifest.HOLDOUT4_MANIFEST)


@pytest.fixture(scope="module")
def holdout5():
    return holes_manifest.read(holes_manifest.HOLDOUT5_MANIFEST)


@pytest.fixture(scope="module")
def holdout6():
    return holes_manifest.read(holes_manifest.HOLDOUT6_MANIFEST)


@pytest.fixture(scope="module")
def holdout7():
    return holes_manifest.read(holes_manifest.HOLDOUT7_MANIFEST)


@pytest.fixture(scope="module")
def holdout8():
    return holes_manifest.read(holes_manifest.HOLDOUT8_MANIFEST)


@pytest.fixture(scope="module")
def holdout9():
    return holes_manifest.read(holes_manifest.HOLDOUT9_MANIFEST)


@pytest.fixture(scope="module")
def holdout10():
    return holes_manifest.read(holes_manifest.HOLDOUT10_MANIFEST)


@pytest.fixture(scope="module")
def holdout11():
    return holes_manifest.read(holes_manifest.HOLDOUT11_MANIFEST)


@pytest.fixture(scope="module")
def holdout12():
    return holes_manifest.read(holes_manifest.HOLDOUT12_MANIFEST)


@pytest.fixture(scope="module")
def holdout13():
    return holes_manifest.read(holes_manifest.HOLDOUT13_MANIFEST)


@pytest.fixture(scope="module")
def holdout14():
    return holes_manifest.read(holes_manifest.HOLDOUT14_MANIFEST)


@pytest.fixture(scope="module")
def holdout15():
    return holes_manifest.read(holes_manifest.HOLDOUT15_MANIFEST)


@pytest.fixture(scope="module")
def holdout16():
    return holes_manifest.read(holes_manifest.HOLDOUT16_MANIFEST)


@pytest.fixture(scope="module")
def holdout17():
    return holes_manifest.read(holes_manifest.HOLDOUT17_MANIFEST)


@pytest.fixture(scope="module")
def holdout18():
    return holes_manifest.read(holes_manifest.HOLDOUT18_MANIFEST)


@pytest.fixture(scope="module")
def holdout19():
    return holes_manifest.read(holes_manifest.HOLDOUT19_MANIFEST)


@pytest.fixture(scope="module")
def holdout20():
    return holes_manifest.read(holes_manifest.HOLDOUT20_MANIFEST)


@pytest.fixture(scope="module")
def holdout21():
    return holes_manifest.read(holes_manifest.HOLDOUT21_MANIFEST)


@pytest.fixture(scope="module")
def holdout22():
    return holes_manifest.read(holes_manifest.HOLDOUT22_MANIFEST)


@pytest.fixture(scope="module")
def holdout23():
    return holes_manifest.read(holes_manifest.HOLDOUT23_MANIFEST)


@pytest.fixture(scope="module")
def holdout24():
    return holes_manifest.read(holes_manifest.HOLDOUT24_MANIFEST)


@pytest.fixture(scope="module")
def holdout25():
    return holes_manifest.read(holes_manifest.HOLDOUT25_MANIFEST)


@pytest.fixture(scope="module")
def holdout26():
    return holes_manifest.read(holes_manifest.HOLDOUT26_MANIFEST)


@pytest.fixture(scope="module")
def holdout27():
    return holes_manifest.read(holes_manifest.HOLDOUT27_MANIFEST)


@pytest.fixture(scope="module")
def holdout28():
    return holes_manifest.read(holes_manifest.HOLDOUT28_MANIFEST)


@pytest.fixture(scope="module")
def holdout29():
    return holes_manifest.read(holes_manifest.HOLDOUT29_MANIFEST)


@pytest.fixture(scope="module")
def curved_scans():
    return holes_manifest.read(holes_manifest.CURVED_SCANS_MANIFEST)


@pytest.fixture(scope="module")
def thin_shells():
    return holes_manifest.read(holes_manifest.THIN_SHELLS_MANIFEST)


@pytest.mark.parametrize(("split", "sources"), [
    ("holdout2", validation_meshes.HOLDOUT2_SOURCES),  # run once after session 26's defaults
    ("holdout3", validation_meshes.HOLDOUT3_SOURCES),  # run once after session 28's
    ("holdout4", validation_meshes.HOLDOUT4_SOURCES),  # session 29, committed before a fill
    ("holdout5", validation_meshes.HOLDOUT5_SOURCES),  # session 29, after holdout 4 was run
    ("holdout6", validation_meshes.HOLDOUT6_SOURCES),  # session 30, after holdout 5 was run
    ("holdout7", validation_meshes.HOLDOUT7_SOURCES),  # session 31, after holdout 6 was made
    ("holdout8", validation_meshes.HOLDOUT8_SOURCES),  # session 32, after holdout 7 was run
    ("holdout9", validation_meshes.HOLDOUT9_SOURCES),  # session 33, after holdout 8 was made
    ("holdout10", validation_meshes.HOLDOUT10_SOURCES),  # session 34, after holdout 9 was made
    ("holdout11", validation_meshes.HOLDOUT11_SOURCES),  # session 35, after holdout 10 was made
    ("holdout12", validation_meshes.HOLDOUT12_SOURCES),  # session 35, after holdout 11 was made
    ("holdout13", validation_meshes.HOLDOUT13_SOURCES),  # session 36, after holdout 12 was made
    ("holdout14", validation_meshes.HOLDOUT14_SOURCES),  # session 37, after holdout 13 was made
    ("holdout15", validation_meshes.HOLDOUT15_SOURCES),  # session 38, after holdout 14 was made
    ("holdout16", validation_meshes.HOLDOUT16_SOURCES),  # session 39, after holdout 15 was made
    ("holdout17", validation_meshes.HOLDOUT17_SOURCES),  # session 40, after holdout 16 was made
    ("holdout18", validation_meshes.HOLDOUT18_SOURCES),  # session 41, after holdout 17 was made
    ("holdout19", validation_meshes.HOLDOUT19_SOURCES),  # session 42, after holdout 18 was run
    ("holdout20", validation_meshes.HOLDOUT20_SOURCES),  # session 43, after holdout 19 was run
    ("holdout21", validation_meshes.HOLDOUT21_SOURCES),  # session 44, after holdout 20 was made
    ("holdout22", validation_meshes.HOLDOUT22_SOURCES),  # session 45, after holdout 21 was made
    ("holdout23", validation_meshes.HOLDOUT23_SOURCES),  # session 46, after holdout 22 was made
    ("holdout24", validation_meshes.HOLDOUT24_SOURCES),  # session 47, after holdout 23 was made
    ("holdout25", validation_meshes.HOLDOUT25_SOURCES),  # session 48, after holdout 24 was made
    ("holdout26", validation_meshes.HOLDOUT26_SOURCES),  # session 49, after holdout 25 was made
    ("holdout27", validation_meshes.HOLDOUT27_SOURCES),  # session 50, after holdout 26 was made
    ("holdout28", validation_meshes.HOLDOUT28_SOURCES),  # session 51, after holdout 27 was made
    ("holdout29", validation_meshes.HOLDOUT29_SOURCES),  # session 52, after holdout 28 was made
])
def test_a_later_holdout_set_is_fresh_and_well_formed(manifest, holdout, holdout2, holdout3,
                                                      cad_tuning, holdout4, holdout5, holdout6,
                                                      holdout7, holdout8, holdout9, holdout10,
                                                      holdout11, holdout12, holdout13,
                                                      holdout14, holdout15, holdout16,
                                                      holdout17, holdout18, holdout19,
                                                      holdout20, holdout21, holdout22,
                                                      holdout23, holdout24, holdout25,
                                                      holdout26, holdout27, holdout28,
                                                      holdout29, smooth_tuning, curved_scans,
                                                      thin_shells, split, sources):
    """The second to twenty-ninth holdout sets: their own meshes, from sources no earlier set
    uses (the two halves, the holdouts before them; from the fourth on also the tuning-side
    CAD parts, from the sixteenth on also the smooth tuning set, from the eighteenth on also
    the curved scans, from the nineteenth on also the thin shells), every kind but brain
    surfaces (the eleventh to twenty-ninth: every kind, their brain a synthetic folded
    surface), at least 3 range scans, 7 holes a mesh."""
    sets = {"holdout2": holdout2, "holdout3": holdout3, "holdout4": holdout4,
            "holdout5": holdout5, "holdout6": holdout6, "holdout7": holdout7,
            "holdout8": holdout8, "holdout9": holdout9, "holdout10": holdout10,
            "holdout11": holdout11, "holdout12": holdout12, "holdout13": holdout13,
            "holdout14": holdout14, "holdout15": holdout15, "holdout16": holdout16,
            "holdout17": holdout17, "holdout18": holdout18, "holdout19": holdout19,
            "holdout20": holdout20, "holdout21": holdout21, "holdout22": holdout22,
            "holdout23": holdout23, "holdout24": holdout24, "holdout25": holdout25,
            "holdout26": holdout26, "holdout27": holdout27, "holdout28": holdout28,
            "holdout29": holdout29}
    this = sets[split]
    ids = [e["mesh"] for e in this["meshes"]]
    assert ids == holes_manifest.SPLIT[split] == list(sources)
    earlier = manifest["meshes"] + holdout["meshes"]
    # every set before this one in the order they were made (the tuning-side CAD parts in
    # session 29, between holdouts 3 and 4; the smooth tuning set in session 38, merged after
    # holdout 15's manifest was committed, so before holdout 16; the curved scans in session
    # 40, after holdout 17; the thin shells in session 41, after holdout 18)
    made = [holdout2, holdout3, cad_tuning, holdout4, holdout5, holdout6, holdout7, holdout8,
            holdout9, holdout10, holdout11, holdout12, holdout13, holdout14, holdout15,
            smooth_tuning, holdout16, holdout17, curved_scans, holdout18, thin_shells,
            holdout19, holdout20, holdout21, holdout22, holdout23, holdout24, holdout25,
            holdout26, holdout27, holdout28, holdout29]
    for earlier_set in made[:next(i for i, m in enumerate(made) if m is this)]:
        earlier = earlier + earlier_set["meshes"]
    assert not {e["mesh"] for e in earlier} & set(ids)
    earlier_sources = {e["source"] for e in earlier}
    for entry in this["meshes"]:
        assert entry["split"] == split and entry["source"] not in earlier_sources, entry["mesh"]
        source = validation_meshes.SOURCES[entry["mesh"]]
        assert (source.kind, source.source) == (entry["kind"], entry["source"])
        assert entry["n_vertices"] > 0 and entry["n_faces"] > 0 and entry["h"] > 0
        assert [h["radius_h"] for h in entry["holes"]] == list(holes_manifest.RADII_H)
        for hole in entry["holes"]:
            assert set(hole) == {"centre", "radius", "radius_h", "near_border", "on_feature"}
            assert hole["radius"] == pytest.approx(hole["radius_h"] * entry["h"], rel=1e-12)
    kinds = Counter(e["kind"] for e in this["meshes"])
    assert set(kinds) == (KINDS if split in ("holdout11", "holdout12", "holdout13", "holdout14",
                                             "holdout15", "holdout16", "holdout17",
                                             "holdout18", "holdout19", "holdout20",
                                             "holdout21", "holdout22", "holdout23",
                                             "holdout24", "holdout25", "holdout26",
                                             "holdout27", "holdout28", "holdout29")
                          else KINDS - {"brain"})
    assert kinds["range_scan"] >= 3
    holes = [h for e in this["meshes"] for h in e["holes"]]
    assert len(holes) == 7 * len(ids)
    assert sum(h["near_border"] for h in holes) == 3 * kinds["range_scan"]
    assert sum(h["on_feature"] for h in holes) == 4 * kinds["cad"]


def test_the_tuning_side_cad_parts_are_their_own_set(manifest, holdout, holdout2, holdout3,
                                                     cad_tuning, holdout4, holdout5, holdout6,
                                                     holdout7, holdout8, holdout9, holdout10,
                                                     holdout11, holdout12, holdout13,
                                                     holdout14, holdout15, holdout16,
                                                     holdout17, holdout18, holdout19,
                                                     holdout20, holdout21, holdout22,
                                                     holdout23, holdout24, holdout25,
                                                     holdout26, holdout27, holdout28,
                                                     holdout29):
    """Session 29's machined parts (tuning side, rules may be chosen on them): their own
    meshes and sources, shared with no other set, machined parts and scans of them only."""
    cad = cad_tuning
    ids = [e["mesh"] for e in cad["meshes"]]
    assert ids == holes_manifest.SPLIT["cad_tuning"] == list(validation_meshes.CAD_TUNING_SOURCES)
    others = [e for m in (manifest, holdout, holdout2, holdout3, holdout4, holdout5, holdout6,
                          holdout7, holdout8, holdout9, holdout10, holdout11, holdout12,
                          holdout13, holdout14, holdout15, holdout16, holdout17, holdout18,
                          holdout19, holdout20, holdout21, holdout22, holdout23, holdout24,
                          holdout25, holdout26, holdout27, holdout28, holdout29)
              for e in m["meshes"]]
    assert not {e["mesh"] for e in others} & set(ids)
    assert not {e["source"] for e in others} & {e["source"] for e in cad["meshes"]}
    kinds = Counter(e["kind"] for e in cad["meshes"])
    assert kinds == {"cad": 8, "range_scan": 4}
    holes = [h for e in cad["meshes"] for h in e["holes"]]
    assert all(e["split"] == "cad_tuning" for e in cad["meshes"]) and len(holes) == 84
    assert sum(h["on_feature"] for h in holes) == 4 * 8
    assert sum(h["near_border"] for h in holes) == 3 * 4


@pytest.fixture(scope="module")
def smooth_tuning():
    return holes_manifest.read(holes_manifest.SMOOTH_TUNING_MANIFEST)


def test_the_smooth_tuning_set_is_its_own_set(manifest, holdout, holdout2, holdout3, cad_tuning,
                                             holdout4, holdout5, holdout6, holdout7, holdout8,
                                             holdout9, holdout10, holdout11, holdout12,
                                             holdout13, holdout14, holdout15, holdout16,
                                             holdout17, holdout18, holdout19, holdout20,
                                             holdout21, holdout22, holdout23, holdout24,
                                             holdout25, holdout26, holdout27, holdout28,
                                             holdout29, smooth_tuning):
    """Session 38's smooth tubes and organic bodies (tuning side, rules may be chosen on
    them): their own split name, meshes and sources, shared with no holdout, half or other
    tuning-side set; 4 smooth and 4 organic meshes, 7 holes each, digests recorded; their
    generators in their own module, which validation_meshes adds to ``SOURCES``."""
    import smooth_tuning_meshes

    entries = smooth_tuning["meshes"]
    ids = [e["mesh"] for e in entries]
    assert (ids == holes_manifest.SPLIT["smooth_tuning"]
            == list(validation_meshes.SMOOTH_TUNING_SOURCES))
    assert validation_meshes.SMOOTH_TUNING_SOURCES is smooth_tuning_meshes.SMOOTH_TUNING_SOURCES
    assert all(validation_meshes.SOURCES[i] is smooth_tuning_meshes.SMOOTH_TUNING_SOURCES[i]
               for i in ids)
    # a tuning-side set: never a holdout by its name, its file or its split
    assert holes_manifest.LATER_SETS["smooth_tuning"][0].name == "smooth_tuning_manifest.json"
    assert "tuning-side" in holes_manifest.LATER_SETS["smooth_tuning"][1]
    assert all(e["split"] == "smooth_tuning" for e in entries)
    others = [e for m in (manifest, holdout, holdout2, holdout3, cad_tuning, holdout4,
                          holdout5, holdout6, holdout7, holdout8, holdout9, holdout10,
                          holdout11, holdout12, holdout13, holdout14, holdout15, holdout16,
                          holdout17, holdout18, holdout19, holdout20, holdout21,
                          holdout22, holdout23, holdout24, holdout25, holdout26,
                          holdout27, holdout28, holdout29)
              for e in m["meshes"]]
    assert not {e["mesh"] for e in others} & set(ids)
    assert not {e["source"] for e in others} & {e["source"] for e in entries}
    assert Counter(e["kind"] for e in entries) == {"smooth": 4, "organic": 4}
    for entry in entries:
        source = validation_meshes.SOURCES[entry["mesh"]]
        assert (source.kind, source.source) == (entry["kind"], entry["source"])
        assert len(entry["sha256"]) == 64 and entry["n_vertices"] > 0
        assert [h["radius_h"] for h in entry["holes"]] == list(holes_manifest.RADII_H)
        assert not any(h["near_border"] or h["on_feature"] for h in entry["holes"])


def test_holdout8_sources_come_from_their_own_module():
    """Holdout 8's generators live in benchmarks/holdout8_meshes.py; validation_meshes takes
    its sources from there, so every benchmark finds them in ``SOURCES`` (no mesh is made)."""
    import holdout8_meshes

    assert validation_meshes.HOLDOUT8_SOURCES is holdout8_meshes.HOLDOUT8_SOURCES
    for mesh_id, source in holdout8_meshes.HOLDOUT8_SOURCES.items():
        assert validation_meshes.SOURCES[mesh_id] is source
    assert holes_manifest.LATER_SETS["holdout8"][1:] == ("the eighth holdout set", 900)


def test_holdout9_sources_come_from_their_own_module():
    """Holdout 9's generators live in benchmarks/holdout9_meshes.py, as holdout 8's in theirs;
    validation_meshes adds them to ``SOURCES`` (no mesh is made)."""
    import holdout9_meshes

    assert validation_meshes.HOLDOUT9_SOURCES is holdout9_meshes.HOLDOUT9_SOURCES
    for mesh_id, source in holdout9_meshes.HOLDOUT9_SOURCES.items():
        assert validation_meshes.SOURCES[mesh_id] is source
    assert holes_manifest.LATER_SETS["holdout9"][1:] == ("the ninth holdout set", 1000)
    assert holes_manifest.SPLIT["holdout9"] == list(holdout9_meshes.HOLDOUT9_SOURCES)


def test_holdout10_sources_come_from_their_own_module():
    """Holdout 10's generators live in benchmarks/holdout10_meshes.py, as holdout 9's in
    theirs; validation_meshes adds them to ``SOURCES``; its scans are the portable scanner's
    (no mesh is made)."""
    import holdout10_meshes

    assert validation_meshes.HOLDOUT10_SOURCES is holdout10_meshes.HOLDOUT10_SOURCES
    for mesh_id, source in holdout10_meshes.HOLDOUT10_SOURCES.items():
        assert validation_meshes.SOURCES[mesh_id] is source
    assert holes_manifest.LATER_SETS["holdout10"][1:] == ("the tenth holdout set", 1100)
    assert holes_manifest.SPLIT["holdout10"] == list(holdout10_meshes.HOLDOUT10_SOURCES)
    scans = [s for s in holdout10_meshes.HOLDOUT10_SOURCES.values() if s.kind == "range_scan"]
    assert len(scans) == 4
    for source in scans:  # _scan's closure holds portable=True
        cells = dict(zip(source.make.__code__.co_freevars,
                         (c.cell_contents for c in source.make.__closure__), strict=True))
        assert cells["portable"] is True, source.source


def test_holdout11_sources_come_from_their_own_module():
    """Holdout 11's generators live in benchmarks/holdout11_meshes.py, as holdout 10's in
    theirs; validation_meshes adds them to ``SOURCES``; its scans are the portable scanner's;
    its brain-kind mesh is the synthetic folded hemisphere, no real brain (no mesh is
    made)."""
    import holdout11_meshes

    assert validation_meshes.HOLDOUT11_SOURCES is holdout11_meshes.HOLDOUT11_SOURCES
    for mesh_id, source in holdout11_meshes.HOLDOUT11_SOURCES.items():
        assert validation_meshes.SOURCES[mesh_id] is source
    assert holes_manifest.LATER_SETS["holdout11"][1:] == ("the eleventh holdout set", 1200)
    assert holes_manifest.SPLIT["holdout11"] == list(holdout11_meshes.HOLDOUT11_SOURCES)
    sources = holdout11_meshes.HOLDOUT11_SOURCES
    scans = [s for s in sources.values() if s.kind == "range_scan"]
    assert len(scans) == 4
    for source in scans:  # _scan's closure holds portable=True
        cells = dict(zip(source.make.__code__.co_freevars,
                         (c.cell_contents for c in source.make.__closure__), strict=True))
        assert cells["portable"] is True, source.source
    brains = [s for s in sources.values() if s.kind == "brain"]
    assert [s.make.__name__ for s in brains] == ["_folded_hemisphere"]
    assert "synthetic" in brains[0].source


@pytest.mark.parametrize("split", ["holdout12", "holdout13", "holdout14", "holdout15",
                                   "holdout16", "holdout17", "holdout18", "holdout19",
                                   "holdout20", "holdout21", "holdout22", "holdout23",
                                   "holdout24", "holdout25", "holdout26", "holdout27",
                                   "holdout28", "holdout29"])
def test_later_holdout_manifest_counts(split):
    """The twelfth to twenty-ninth holdouts' manifests as committed before any fill: 12 meshes
    in their module's order, 84 holes, 3 near the border on each of the 4 scans, 4 on a sharp
    edge or corner on each of the 3 CAD parts, every other hole neither."""
    entries = holes_manifest.read(holes_manifest.LATER_SETS[split][0])["meshes"]
    assert [e["mesh"] for e in entries] == holes_manifest.SPLIT[split]
    assert Counter(e["kind"] for e in entries) == {"range_scan": 4, "organic": 2, "cad": 3,
                                                   "teeth": 1, "smooth": 1, "brain": 1}
    assert sum(len(e["holes"]) for e in entries) == 84
    for entry in entries:
        near = [h["near_border"] for h in entry["holes"]]
        feature = [h["on_feature"] for h in entry["holes"]]
        scan, cad = entry["kind"] == "range_scan", entry["kind"] == "cad"
        assert near == [scan and k in holes_manifest.NEAR_BORDER for k in range(7)], entry["mesh"]
        assert feature == [cad and k in holes_manifest.ON_FEATURE for k in range(7)], entry["mesh"]


@pytest.mark.parametrize(("number", "words", "first_seed", "seeds", "brain"), [
    (12, "the twelfth holdout set", 1300, [159, 160, 161, 162], "_cerebellum"),
    (13, "the thirteenth holdout set", 1400, [163, 164, 165, 166], "_forebrain"),
    (14, "the fourteenth holdout set", 1500, [167, 168, 169, 170], "_polygyral_brain"),
    (15, "the fifteenth holdout set", 1600, [171, 172, 173, 174], "_branched_cortex"),
    (16, "the sixteenth holdout set", 1700, [175, 176, 177, 178], "_arcuate_cortex"),
    (17, "the seventeenth holdout set", 1800, [179, 180, 181, 182], "_stellate_cortex"),
    (18, "the eighteenth holdout set", 1900, [183, 184, 185, 186], "_pinnate_cortex"),
    (19, "the nineteenth holdout set", 2000, [187, 188, 189, 190], "_spiral_cortex"),
    (20, "the twentieth holdout set", 2100, [191, 192, 193, 194], "_meander_cortex"),
    (21, "the twenty-first holdout set", 2200, [195, 196, 197, 198], "_echelon_cortex"),
    (22, "the twenty-second holdout set", 2300, [199, 200, 201, 202], "_lattice_cortex"),
    (23, "the twenty-third holdout set", 2400, [203, 204, 205, 206], "_annular_cortex"),
    (24, "the twenty-fourth holdout set", 2500, [207, 208, 209, 210], "_truchet_cortex"),
    (25, "the twenty-fifth holdout set", 2600, [211, 212, 213, 214], "_hilbert_cortex"),
    (26, "the twenty-sixth holdout set", 2700, [215, 216, 217, 218], "_triradiate_cortex"),
    (27, "the twenty-seventh holdout set", 2800, [219, 220, 221, 222], "_rose_cortex"),
    (28, "the twenty-eighth holdout set", 2900, [223, 224, 225, 226], "_chevron_cortex"),
    (29, "the twenty-ninth holdout set", 3000, [227, 228, 229, 230], "_orbital_cortex"),
])
def test_later_holdout_sources_come_from_their_own_module(number, words, first_seed, seeds,
                                                          brain):
    """Holdouts 12 to 29's generators live in benchmarks/holdout<N>_meshes.py, as holdout
    11's in theirs; validation_meshes adds them to ``SOURCES`` in the order they were made,
    after holdout 11's; their scans are the portable scanner's with seeds of their own
    (159-162, 163-166, 167-170, 171-174, 175-178, 179-182, 183-186, 187-190, 191-194,
    195-198, 199-202, 203-206, 207-210, 211-214, 215-218, 219-222, 223-226, 227-230); their
    brain-kind mesh is a synthetic one, no real brain (no mesh is made)."""
    import importlib

    module = importlib.import_module(f"holdout{number}_meshes")
    split = f"holdout{number}"
    sources = getattr(module, f"HOLDOUT{number}_SOURCES")
    assert getattr(validation_meshes, f"HOLDOUT{number}_SOURCES") is sources
    for mesh_id, source in sources.items():
        assert validation_meshes.SOURCES[mesh_id] is source
    ids = [i for i in validation_meshes.SOURCES  # the tuning-side sets are added after them
           if i not in validation_meshes.SMOOTH_TUNING_SOURCES
           and i not in validation_meshes.CURVED_SCAN_SOURCES
           and i not in validation_meshes.THIN_SHELL_SOURCES]
    later = [f"holdout{n}" for n in range(11, 30)]  # SOURCES' last sets, in order
    tail = ids[-12 * len(later):]
    assert tail[12 * later.index(split):][:12] == list(sources)
    assert holes_manifest.LATER_SETS[split][1:] == (words, first_seed)
    assert holes_manifest.SPLIT[split] == list(sources)
    scans = [s for s in sources.values() if s.kind == "range_scan"]
    assert len(scans) == 4
    cells = [dict(zip(s.make.__code__.co_freevars,
                      (c.cell_contents for c in s.make.__closure__), strict=True))
             for s in scans]  # _scan's closure: portable=True, and a seed of its own
    assert all(c["portable"] is True for c in cells)
    assert [c["seed"] for c in cells] == seeds
    brains = [s for s in sources.values() if s.kind == "brain"]
    assert [s.make.__name__ for s in brains] == [brain]
    assert "synthetic" in brains[0].source


def test_every_set_records_its_meshes_digests():
    """Holdout set 13 on were written with each mesh's sha256, the earlier sets got theirs
    in session 44 (where the mesh could be made: else ``sha256_missing`` says why)."""
    for path in [holes_manifest.MANIFEST] + [p for p, _, _ in holes_manifest.LATER_SETS.values()]:
        for entry in holes_manifest.read(path)["meshes"]:
            assert ("sha256" in entry) != ("sha256_missing" in entry), entry["mesh"]


def test_the_curved_scans_set_is_its_own_set():
    """Session 40's range scans of curved shapes (tuning side, rules may be chosen on them):
    their own split name, meshes and sources, shared with no holdout, half or other set; 14
    portable scans whose noise seeds (3500-3513) no other scan uses, of tuning-side sources
    only (the smooth tuning set, animals.py's animals, the tuning half), none a holdout's;
    the holes as every scan's (radii as planned, 1, 3 and 5 next to the border), digests
    recorded; the generators in their own module, which validation_meshes adds to
    ``SOURCES`` last."""
    import curved_scans_meshes

    sources = curved_scans_meshes.CURVED_SCAN_SOURCES
    entries = holes_manifest.read(holes_manifest.CURVED_SCANS_MANIFEST)["meshes"]
    ids = [e["mesh"] for e in entries]
    assert ids == holes_manifest.SPLIT["curved_scans"] == list(sources)
    assert validation_meshes.CURVED_SCAN_SOURCES is sources
    # added after every other set but the thin shells (session 41), which follow it
    later = list(validation_meshes.SOURCES)[
        -len(sources) - len(validation_meshes.THIN_SHELL_SOURCES):]
    assert later[:len(sources)] == ids
    assert all(validation_meshes.SOURCES[i] is sources[i] for i in ids)
    # a tuning-side set: never a holdout by its name, its file or its split
    path, words, first_seed = holes_manifest.LATER_SETS["curved_scans"]
    assert path.name == "curved_scans_manifest.json" and "tuning-side" in words
    assert first_seed == 3600
    others = [e for split, (p, _, _) in holes_manifest.LATER_SETS.items()
              if split != "curved_scans" for e in holes_manifest.read(p)["meshes"]]
    others += holes_manifest.read()["meshes"]
    assert not {e["mesh"] for e in others} & set(ids)
    assert not {e["source"] for e in others} & {e["source"] for e in entries}
    # the scanned meshes: the smooth tuning set's, the tuning half's or animals.py's
    scanned, seeds = [], []
    for source in sources.values():
        cells = dict(zip(source.make.__code__.co_freevars,
                         (c.cell_contents for c in source.make.__closure__), strict=True))
        assert cells["portable"] is True, source.source
        seeds.append(cells["seed"])
        inner = dict(zip(cells["source"].__code__.co_freevars,
                         (c.cell_contents for c in cells["source"].__closure__), strict=True))
        scanned.append(inner.get("mesh_id", "animal"))
    assert seeds == list(range(3500, 3514))
    tuning_side = (set(holes_manifest.SPLIT["tuning"])
                   | set(validation_meshes.SMOOTH_TUNING_SOURCES) | {"animal"})
    assert set(scanned) <= tuning_side
    assert scanned.count("animal") == 4
    for entry in entries:
        source = validation_meshes.SOURCES[entry["mesh"]]
        assert entry["split"] == "curved_scans" and entry["kind"] == "range_scan"
        assert (source.kind, source.source) == (entry["kind"], entry["source"])
        assert len(entry["sha256"]) == 64 and entry["n_vertices"] > 0
        radii = [h["radius_h"] for h in entry["holes"]]
        assert radii == [r for r in holes_manifest.RADII_H if r in radii]
        for hole in entry["holes"]:
            k = holes_manifest.RADII_H.index(hole["radius_h"])
            assert hole["near_border"] == (k in holes_manifest.NEAR_BORDER), entry["mesh"]
            assert not hole["on_feature"]
            assert hole["radius"] == pytest.approx(hole["radius_h"] * entry["h"], rel=1e-12)
    # a hole that could not be cut is skipped: radii 7 and 10 h on the knot tube, 10 h on the
    # bone and on the decimated animal
    assert sum(len(e["holes"]) for e in entries) == 94
    assert sum(h["near_border"] for e in entries for h in e["holes"]) == 3 * 14


@pytest.mark.parametrize("number, level_sets, radial", [(17, 4, 1), (18, 4, 1), (19, 4, 1),
                                                      (20, 4, 1), (21, 3, 2), (22, 4, 1),
                                                      (23, 4, 1), (24, 4, 1), (25, 4, 1),
                                                      (26, 3, 2), (27, 4, 1),
                                                      (28, 4, 1), (29, 4, 1)])
def test_holdout_generators_pass_the_surface_check(monkeypatch, number, level_sets, radial):
    """Holdouts 17 to 29's generators pass PyMeshLab's surface-distance check to every
    remeshing (``surface_check=True``), not the filter's default, which is a leftover byte
    of the heap (docs/validation.md "Holdout set 17"): every level set, manifold3d part and
    radial surface of the set is asked for with it (the meshing itself is replaced: no mesh
    is made); holdouts 21 and 26 make their smooth mesh (the golf ball, the supershape) as a
    radial surface too."""
    import importlib
    import inspect

    module = importlib.import_module(f"holdout{number}_meshes")
    asked = []

    def recording(real):
        def fake(*args, **kwargs):
            bound = inspect.signature(real).bind(*args, **kwargs)
            asked.append((real.__name__, bound.arguments.get("surface_check")))
            return validation_meshes.BenchMesh(np.zeros((3, 3)), np.array([[0, 1, 2]]))
        return fake

    monkeypatch.setattr(validation_meshes, "_level_set_mesh",
                        recording(validation_meshes._level_set_mesh))
    monkeypatch.setattr(validation_meshes, "_manifold_mesh",
                        recording(validation_meshes._manifold_mesh))
    monkeypatch.setattr(module, "_radial_surface", recording(module._radial_surface))
    for source in getattr(module, f"HOLDOUT{number}_SOURCES").values():
        if source.kind != "range_scan":  # the scans are made from these meshes
            source.make()
    assert sorted(name for name, _ in asked) == (["_level_set_mesh"] * level_sets
                                                 + ["_manifold_mesh"] * 3
                                                 + ["_radial_surface"] * radial)
    assert all(check is True for _, check in asked), asked


def test_the_thin_shells_set_is_its_own_set():
    """Session 41's thin smooth walls (tuning side, rules may be chosen on them): their own
    split name, meshes and sources, shared with no holdout, half or other set (holdout 17's
    cooling tower is a hyperboloid; this set's neck is a catenoid); 9 smooth meshes, 7 holes
    each as planned (every radius, none by a border or a feature), seeds from 4100, digests
    recorded; the generators in their own module, which validation_meshes adds to
    ``SOURCES`` last."""
    import thin_shells_meshes

    sources = thin_shells_meshes.THIN_SHELL_SOURCES
    entries = holes_manifest.read(holes_manifest.THIN_SHELLS_MANIFEST)["meshes"]
    ids = [e["mesh"] for e in entries]
    assert ids == holes_manifest.SPLIT["thin_shells"] == list(sources) and len(ids) == 9
    assert validation_meshes.THIN_SHELL_SOURCES is sources
    assert list(validation_meshes.SOURCES)[-len(sources):] == ids
    assert all(validation_meshes.SOURCES[i] is sources[i] for i in ids)
    # a tuning-side set: never a holdout by its name, its file or its split
    path, words, first_seed = holes_manifest.LATER_SETS["thin_shells"]
    assert path.name == "thin_shells_manifest.json" and "tuning-side" in words
    assert first_seed == 4100
    others = [e for split, (p, _, _) in holes_manifest.LATER_SETS.items()
              if split != "thin_shells" for e in holes_manifest.read(p)["meshes"]]
    others += holes_manifest.read()["meshes"]
    assert not {e["mesh"] for e in others} & set(ids)
    assert not {e["source"] for e in others} & {e["source"] for e in entries}
    assert not any("hyperboloid" in e["source"] for e in entries)
    for entry in entries:
        source = validation_meshes.SOURCES[entry["mesh"]]
        assert entry["split"] == "thin_shells" and entry["kind"] == "smooth"
        assert (source.kind, source.source) == (entry["kind"], entry["source"])
        assert "wall" in entry["source"]
        assert len(entry["sha256"]) == 64 and entry["n_vertices"] > 0
        assert [h["radius_h"] for h in entry["holes"]] == list(holes_manifest.RADII_H)
        assert not any(h["near_border"] or h["on_feature"] for h in entry["holes"])
        for hole in entry["holes"]:
            assert hole["radius"] == pytest.approx(hole["radius_h"] * entry["h"], rel=1e-12)
