"""Id arrays (``vtkOriginalPointIds``, ``point_ids``): new vertices and faces get the none id
(-1; an unsigned dtype's largest value), never an interpolated or copied one."""

import warnings

import numpy as np
import pytest

from surfinpaint import fill_holes
from surfinpaint.data import sphere
from surfinpaint.fill.attributes import attribute_kind
from surfinpaint.fill.ids import is_id_name, none_id
from surfinpaint.geometry.cutting import cut_holes


@pytest.fixture(scope="module")
def cut_sphere():
    v, f = sphere(3)
    cut = cut_holes(v, f, [0], [0.6])
    return cut.vertices, cut.faces


def test_names_that_mark_ids_and_their_none_value():
    for name in ("vtkOriginalPointIds", "vtkOriginalCellIds", "GlobalIds", "point_ids",
                 "PointIndex", "vertex_index", "face_indices", "ids", "node_idx"):
        assert is_id_name(name), name
    # a bare "id" is as often an object's (a category) as an element's: copied, as before
    for name in ("material_index", "region_id", "label", "lipids", "thickness", "parcel",
                 "colour_index", "quality", "id"):
        assert not is_id_name(name), name
    assert attribute_kind("vtkOriginalPointIds", np.arange(500)) == "id"
    assert attribute_kind("point_ids", np.arange(5, dtype=np.uint16)) == "id"
    # a float "index" (FreeSurfer's local gyrification index) is a quantity
    assert attribute_kind("gyrification_index", np.linspace(0, 1, 500)) == "values"
    assert attribute_kind("material_index", np.arange(5) % 2) == "label"
    assert (none_id(np.dtype(np.int32)), none_id(np.dtype(np.uint8))) == (-1, 255)


def test_id_arrays_give_new_vertices_and_faces_the_none_id(cut_sphere):
    v, f = cut_sphere
    n, m = len(v), len(f)
    result = fill_holes(v, f, attributes={
        "vertex_ids": np.arange(n, dtype=np.int64) + 1000,
        "PointIndex": np.arange(n, dtype=np.uint32),
        "material_index": (v[:, 0] > 0).astype(np.int16),
        "serial": np.arange(n, dtype=np.int32) * 3,
    }, face_attributes={"face_ids": np.arange(m, dtype=np.uint16),
                        "material": np.full(m, 7, dtype=np.int8)})
    a, fa = result.attributes, result.face_attributes
    assert len(result.vertices) > n + 10 and len(result.faces) > m
    assert np.array_equal(a["vertex_ids"][:n], np.arange(n) + 1000)
    assert (a["vertex_ids"][n:] == -1).all() and a["vertex_ids"].dtype == np.int64
    assert (a["PointIndex"][n:] == np.iinfo(np.uint32).max).all()
    assert a["PointIndex"].dtype == np.uint32
    assert set(a["material_index"][n:]) <= {0, 1}  # a category: continued
    # "serial" is named like nothing: a quantity of > 100 values, inpainted (>= 0)
    assert (a["serial"][n:] >= 0).all()
    assert np.array_equal(fa["face_ids"][:m], np.arange(m))
    assert (fa["face_ids"][m:] == np.iinfo(np.uint16).max).all()
    assert (fa["material"][m:] == 7).all()


def test_attribute_kinds_make_an_array_an_id_or_not(cut_sphere):
    v, f = cut_sphere
    n, m = len(v), len(f)
    result = fill_holes(v, f, attributes={"serial": np.arange(n) * 3,
                                          "point_ids": np.arange(n)},
                        face_attributes={"face_serial": np.arange(m),
                                         "face_ids": np.arange(m)},
                        attribute_kinds={"serial": "id", "point_ids": "values",
                                         "face_serial": "id", "face_ids": "label"})
    a, fa = result.attributes, result.face_attributes
    assert (a["serial"][n:] == -1).all()
    assert (a["point_ids"][n:] >= 0).all()  # inpainted as asked
    assert (fa["face_serial"][m:] == -1).all()
    assert (fa["face_ids"][m:] >= 0).all()  # copied from across the loop
    with pytest.raises(ValueError, match="unknown attribute kinds"):
        fill_holes(v, f, face_attributes={"face_ids": np.arange(m)},
                   attribute_kinds={"face_ids": "identity"})


def test_a_pyvista_mesh_with_original_ids_gets_none_at_new_vertices_and_faces():
    pv = pytest.importorskip("pyvista")
    s = pv.Sphere(theta_resolution=30, phi_resolution=30)
    near = np.linalg.norm(s.cell_centers().points - s.points[100], axis=1) < 0.15
    cut = s.remove_cells(np.flatnonzero(near))
    n, m = cut.n_points, cut.n_cells
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = fill_holes(cut).to_pyvista()
    assert out.n_points > n and out.n_cells > m
    point_ids = np.asarray(out.point_data["vtkOriginalPointIds"])
    cell_ids = np.asarray(out.cell_data["vtkOriginalCellIds"])
    assert np.array_equal(point_ids[:n], cut.point_data["vtkOriginalPointIds"])
    assert np.array_equal(cell_ids[:m], cut.cell_data["vtkOriginalCellIds"])
    assert (point_ids[n:] == -1).all() and (cell_ids[m:] == -1).all()
