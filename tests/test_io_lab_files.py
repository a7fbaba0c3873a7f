"""What a brain-imaging lab and a dental lab meet first (docs/robustness.md "Session 35
(helper 2)"): an ascii PLY or STL stays ascii, a GIFTI surface keeps its coordinate system,
a segmentation overlay (``.label.gii``, FreeSurfer ``.annot``) is filled as labels and
written back with its label table, and a crown scanned down to the gum keeps its margin
open with ``--keep-margins`` in a batch."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import trimesh

from surfinpaint.app.cli import main
from surfinpaint.fill.holes import find_holes
from surfinpaint.fill.objects import fill_mesh_data
from surfinpaint.fill.pipeline import fill_holes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.io import MeshData, MeshWarning, read_mesh, read_mesh_data, write_mesh
from surfinpaint.io.formats import ascii_like, write_mesh_data

nib = pytest.importorskip("nibabel")


def _holey_sphere(subdivisions: int = 3):
    s = trimesh.creation.icosphere(subdivisions)
    cut = cut_holes(np.asarray(s.vertices), np.asarray(s.faces), [0, 40], [0.35, 0.3])
    return cut.vertices, cut.faces


def _quiet(function, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return function(*args, **kwargs)


def _head(path, n: int = 5) -> bytes:
    return path.read_bytes()[:n]


# ------------------------------------------------------------------ ascii stays ascii


def test_ascii_stl_round_trips_float64_vertices_exactly(tmp_path):
    v, f = _holey_sphere()
    v = v * 7.3 + 1e-3  # digits a float32 does not hold
    _quiet(write_mesh, tmp_path / "a.stl", v, f, ascii=True)
    assert _head(tmp_path / "a.stl") == b"solid"
    back_v, back_f = read_mesh(tmp_path / "a.stl")
    used = np.unique(f)  # STL numbers vertices by first use; every vertex here is used
    assert len(back_v) == len(used)
    np.testing.assert_array_equal(np.sort(back_v, axis=0), np.sort(v[used], axis=0))
    np.testing.assert_array_equal(back_v[back_f], v[f])  # the same triangles, bit for bit
    loaded = trimesh.load(tmp_path / "a.stl", process=False)  # another reader takes it
    assert len(loaded.faces) == len(f)


def _files(tmp_path):
    """(name, bytes) of each encoding of one mesh: ascii and binary PLY and STL, OBJ."""
    v, f = _holey_sphere()
    made = {}
    for name, ascii in (("a.ply", True), ("b.ply", False), ("a.stl", True),
                        ("b.stl", False), ("c.obj", False)):
        _quiet(write_mesh, tmp_path / name, v, f, ascii=ascii)
        made[name] = tmp_path / name
    header = b"solid but binary".ljust(80, b" ")  # a binary STL whose header says "solid"
    body = (tmp_path / "b.stl").read_bytes()[80:]
    (tmp_path / "solid_binary.stl").write_bytes(header + body)
    made["solid_binary.stl"] = tmp_path / "solid_binary.stl"
    return made


# (input, output name, written as ascii): only the same format keeps the encoding
ASCII_CASES = [
    ("a.ply", "out.ply", True),
    ("b.ply", "out.ply", False),
    ("a.stl", "out.stl", True),
    ("b.stl", "out.stl", False),
    ("solid_binary.stl", "out.stl", False),
    ("a.ply", "out.stl", False),
    ("a.stl", "out.ply", False),
    ("c.obj", "out.obj", False),
    ("missing.ply", "out.ply", False),
]


@pytest.mark.parametrize("source, target, expected", ASCII_CASES,
                         ids=[f"{a}->{b}" for a, b, _ in ASCII_CASES])
def test_ascii_like_keeps_the_input_encoding_for_the_same_format(tmp_path, source, target,
                                                                 expected):
    _files(tmp_path)
    assert ascii_like(tmp_path / source, tmp_path / target) is expected


@pytest.mark.parametrize("name", ["a.ply", "b.ply", "a.stl", "b.stl"])
def test_fill_and_batch_write_an_ascii_input_as_ascii(tmp_path, name):
    made = _files(tmp_path)
    source = made[name]
    suffix = source.suffix
    out = tmp_path / f"filled{suffix}"
    assert _quiet(main, ["fill", str(source), "-o", str(out), "-q", "--method", "fair"]) == 0
    folder = tmp_path / "in"
    folder.mkdir()
    (folder / source.name).write_bytes(source.read_bytes())
    assert _quiet(main, ["batch", str(folder), "-o", str(tmp_path / "out"), "-q",
                         "--method", "fair"]) == 0
    ascii_input = name.startswith("a.")
    for written in (out, tmp_path / "out" / source.name):
        text = _head(written, 20)
        if suffix == ".ply":
            assert (b"format ascii" in (written.read_bytes()[:40])) is ascii_input
        else:
            assert text.startswith(b"solid") is ascii_input
        before, _ = read_mesh(source)
        after, _ = read_mesh(written)
        assert len(after) > len(before)
        np.testing.assert_array_equal(after[:len(before)], before)


# ------------------------------------------------------------------ GIFTI coordinate system


def test_gifti_coordinate_system_is_kept_and_no_warning_says_it_is_dropped(tmp_path):
    v, f = _holey_sphere()
    xform = np.array([[1, 0, 0, 2.5], [0, 0.9, 0, -1], [0, 0, 1.1, 3], [0, 0, 0, 1]])
    points = nib.gifti.GiftiDataArray(
        v.astype(np.float32), intent="NIFTI_INTENT_POINTSET", datatype="NIFTI_TYPE_FLOAT32",
        coordsys=nib.gifti.GiftiCoordSystem(3, 3, xform),  # Talairach to Talairach
        meta=nib.gifti.GiftiMetaData({"AnatomicalStructurePrimary": "CortexLeft"}))
    triangles = nib.gifti.GiftiDataArray(f.astype(np.int32), intent="NIFTI_INTENT_TRIANGLE",
                                         datatype="NIFTI_TYPE_INT32")
    (tmp_path / "lh.pial.gii").write_bytes(
        nib.gifti.GiftiImage(darrays=[points, triangles]).to_bytes())
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshWarning)
        mesh = read_mesh_data(tmp_path / "lh.pial.gii")
    result, filled = _quiet(fill_mesh_data, mesh, method="fair")
    write_mesh_data(tmp_path / "out.gii", filled)
    back = nib.load(tmp_path / "out.gii").darrays[0]
    assert (back.coordsys.dataspace, back.coordsys.xformspace) == (3, 3)
    np.testing.assert_array_equal(back.coordsys.xform, xform)
    assert back.meta["AnatomicalStructurePrimary"] == "CortexLeft"
    assert "coordsys" not in nib.load(tmp_path / "out.gii").meta  # kept where it belongs
    np.testing.assert_array_equal(back.data[:len(v)], v.astype(np.float32))


# ------------------------------------------------------------------ segmentations


def _label_table(keys, prefix="area"):
    table = nib.gifti.GiftiLabelTable()
    for k, key in enumerate(keys):
        label = nib.gifti.GiftiLabel(int(key), k / len(keys), 0.5, 1 - k / len(keys), 1.0)
        label.label = f"{prefix}{key}"
        table.labels.append(label)
    return table


def _atlas(v, n_areas: int) -> np.ndarray:
    """``n_areas`` bands along z, numbered by sparse shuffled keys: a blend of two keys is
    no key (a segmentation filled as values would show it)."""
    band = np.minimum((v[:, 2] + 1) / 2 * n_areas, n_areas - 1).astype(int)
    keys = 1000 * np.random.default_rng(3).permutation(n_areas) + 7
    return keys[band].astype(np.int32), np.sort(keys)


@pytest.mark.parametrize("n_areas", [4, 150])  # below and above MAX_LABELS (100)
def test_label_gii_overlay_is_filled_as_labels_and_written_with_its_table(tmp_path,
                                                                        n_areas):
    v, f = _holey_sphere(4)
    labels, keys = _atlas(v, n_areas)
    _quiet(write_mesh, tmp_path / "lh.pial.gii", v, f)
    image = nib.gifti.GiftiImage(labeltable=_label_table(keys), darrays=[
        nib.gifti.GiftiDataArray(labels, intent="NIFTI_INTENT_LABEL",
                                 datatype="NIFTI_TYPE_INT32")])
    (tmp_path / "lh.pial.atlas.label.gii").write_bytes(image.to_bytes())
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshWarning)  # the table is kept: nothing to say
        mesh = read_mesh_data(tmp_path / "lh.pial.gii")
    result, filled = _quiet(fill_mesh_data, mesh, method="fair")
    atlas = filled.attributes["atlas"]
    n = len(v)
    assert len(atlas) > n and atlas.dtype == np.int32
    np.testing.assert_array_equal(atlas[:n], labels)
    assert np.isin(atlas[n:], labels[np.unique(np.concatenate(
        [h.loop for h in find_holes(v, f)]))]).all()  # labels of the loops, no blends
    write_mesh_data(tmp_path / "out.gii", filled)
    written = nib.load(tmp_path / "out.atlas.label.gii")
    assert not (tmp_path / "out.atlas.shape.gii").exists()
    assert written.darrays[0].intent == nib.nifti1.intent_codes["NIFTI_INTENT_LABEL"]
    table = written.labeltable.get_labels_as_dict()
    assert table == {int(k): f"area{k}" for k in keys}
    back = read_mesh_data(tmp_path / "out.gii")
    np.testing.assert_array_equal(back.attributes["atlas"], atlas)
    assert back.metadata["labels.atlas"] == filled.metadata["labels.atlas"]


def test_a_label_overlay_may_still_be_filled_as_values_when_told(tmp_path):
    v, f = _holey_sphere()
    labels, keys = _atlas(v, 4)
    mesh = MeshData(v, f, {"atlas": labels}, metadata={"labels.atlas": "[]"})
    _, as_values = _quiet(fill_mesh_data, mesh, method="fair",
                          attribute_kinds={"atlas": "values"})
    _, as_labels = _quiet(fill_mesh_data, mesh, method="fair")
    assert np.isin(as_labels.attributes["atlas"], keys).all()
    assert not np.isin(as_values.attributes["atlas"], keys).all()  # blends of the keys


def test_freesurfer_annot_overlay_is_read_filled_and_written_as_label_gii(tmp_path):
    v, f = _holey_sphere(4)
    band = np.minimum((v[:, 2] + 1) * 2, 3).astype(np.int32)
    band[:5] = -1  # vertices no label covers
    ctab = np.array([[200, 10, 10, 0, 0], [10, 200, 10, 0, 0], [10, 10, 200, 0, 0],
                     [90, 90, 90, 0, 0]])
    ctab[:, 4] = ctab[:, 0] + ctab[:, 1] * 256 + ctab[:, 2] * 65536
    names = [b"frontal", b"parietal", b"temporal", b"occipital"]
    nib.freesurfer.write_geometry(str(tmp_path / "lh.white"), v.astype(np.float32),
                                  f.astype(np.int32))
    nib.freesurfer.write_annot(str(tmp_path / "lh.aparc.annot"), band, ctab, names)
    mesh = read_mesh_data(tmp_path / "lh.white", overlays=[tmp_path / "lh.aparc.annot"])
    np.testing.assert_array_equal(mesh.attributes["aparc"], band)
    out = tmp_path / "lh.filled.white"
    code = _quiet(main, ["fill", str(tmp_path / "lh.white"), "-o", str(out), "-q",
                         "--method", "fair", "--overlay", str(tmp_path / "lh.aparc.annot")])
    assert code == 0
    written = nib.load(tmp_path / "lh.filled.white.aparc.label.gii")
    assert written.labeltable.get_labels_as_dict() == {
        k: name.decode() for k, name in enumerate(names)}
    values = written.darrays[0].data
    np.testing.assert_array_equal(values[:len(v)], band)
    assert len(values) > len(v) and np.isin(values[len(v):], band).all()


# ------------------------------------------------------------------ a crown's margin


def _crown(height: float = 0.3):
    """A sphere cut above ``height`` (its loop spans 30-35 % of what remains: "the
    margin?") with a small hole cut at its bottom."""
    s = trimesh.creation.icosphere(3)
    v, f = np.asarray(s.vertices), np.asarray(s.faces)
    f = f[v[f].mean(axis=1)[:, 2] < height]
    near = np.linalg.norm(v[f].mean(axis=1) - v[np.argmin(v[:, 2])], axis=1) < 0.25
    return v, f[~near]


def test_keep_margins_leaves_the_margin_open_and_fills_the_other_holes(tmp_path):
    v, f = _crown()
    margin = next(h for h in find_holes(v, f) if h.may_be_border)
    with pytest.warns(MeshWarning, match=r"keep it open with --keep-margins"):
        default = fill_holes(v, f, method="fair")
    assert not find_holes(default.vertices, default.faces)  # both capped
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshWarning)  # nothing filled that may be the margin
        kept = fill_holes(v, f, method="fair", keep_margins=True)
    (left,) = find_holes(kept.vertices, kept.faces)
    assert sorted(left.loop.tolist()) == sorted(margin.loop.tolist())
    assert len(kept.new_faces) > 0
    with pytest.raises(ValueError, match="keep_margins must be True or False"):
        fill_holes(v, f, keep_margins="yes")


def test_batch_keep_margins_on_a_folder_of_crowns(tmp_path):
    folder = tmp_path / "scans" / "patient0"
    folder.mkdir(parents=True)
    for k, height in enumerate((0.3, 0.4)):
        _quiet(write_mesh, folder / f"crown{k}.stl", *_crown(height))
    assert _quiet(main, ["batch", str(tmp_path / "scans"), "-o", str(tmp_path / "out"),
                         "-q", "--method", "fair", "--keep-margins", "--jobs", "1"]) == 0
    for k in range(2):
        before, before_f = read_mesh(folder / f"crown{k}.stl")
        after, after_f = read_mesh(tmp_path / "out" / "patient0" / f"crown{k}.stl")
        (left,) = find_holes(after, after_f)
        (margin,) = [h for h in find_holes(before, before_f) if h.may_be_border]
        assert left.n_edges == margin.n_edges
        assert len(after_f) > len(before_f)


# ------------------------------------------------------------------ STL numbering notes


def _soup():
    """Four triangles over 6 vertices, numbered by first use (as an STL reads), and a
    fill's two new faces with new vertices 6 and 7 used 7 first."""
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 0, 0], [2, 1, 0],
                  [0.5, 0.5, 1], [1.5, 0.5, 1]], float)
    f = np.array([[0, 1, 2], [1, 3, 2], [1, 4, 3], [4, 5, 3]])
    return v, f, np.array([[1, 7, 3], [0, 6, 1]])


# (what, source, faces of the written mesh, the note expected): the note goes only where
# the output's original vertices keep their ids (an STL's new vertices are renumbered
# silently: nothing names them by id, and the input's numbering was first use already)
NOTE_CASES = [
    ("STL filled into STL", "in.stl", "kept", False),
    ("STL whose vertex 0 lost its face: first used after new ones", "in.stl", "lost", True),
    ("STL whose originals are first used out of order", "in.stl", "shuffled", True),
    ("PLY written as STL", "in.ply", "kept", True),
]


@pytest.mark.parametrize("what, source, faces, noted", NOTE_CASES,
                         ids=[c[0] for c in NOTE_CASES])
def test_the_stl_renumbering_note_only_where_an_original_id_changes(tmp_path, what, source,
                                                                   faces, noted):
    from surfinpaint.app.outputs import write_output
    from surfinpaint.io.base import RenumberedWarning

    v, f, new = _soup()
    written = {"kept": np.vstack([f, new]), "lost": np.vstack([f[1:], new]),
               "shuffled": np.vstack([f[::-1], new])}[faces]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        write_output(tmp_path / source, tmp_path / "out.stl", MeshData(v, written), 6)
    notes = [w for w in caught if issubclass(w.category, RenumberedWarning)]
    assert bool(notes) is noted
    back_v, back_f = read_mesh(tmp_path / "out.stl")
    np.testing.assert_array_equal(back_v[back_f], v[written].astype(np.float32))


def test_a_batch_of_stl_scans_has_no_renumbering_note_in_its_summary(tmp_path, capsys):
    folder = tmp_path / "scans"
    folder.mkdir()
    v, f = _holey_sphere()
    for k in range(2):
        _quiet(write_mesh, folder / f"scan{k}.stl", v * (k + 1), f)
    assert main(["batch", str(folder), "-o", str(tmp_path / "out"), "--method", "fair",
                 "-q", "--jobs", "1"]) == 0
    summary = (tmp_path / "out" / "summary.csv").read_text()
    assert summary.count(",filled,") == 2
    assert "renumbered" not in summary and "renumbered" not in capsys.readouterr().err
