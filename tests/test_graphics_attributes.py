"""What a graphics user's textured and shaded models need from a fill (session 36): texture
coordinates and normals per face corner on the new faces, colours and objects of trimesh and
PyVista carried whole."""

import warnings

import numpy as np
import pytest

from surfinpaint import fill_holes
from surfinpaint.data import sphere
from surfinpaint.fill.face_attributes import fill_result_corner_attributes
from surfinpaint.geometry.cutting import cut_holes
from surfinpaint.io import MeshWarning


@pytest.fixture(scope="module")
def filled_sphere():
    """A unit sphere with one hole (radius 0.6), filled by the faired fill."""
    v, f = sphere(4)
    cut = cut_holes(v, f, [0], [0.6])
    result = fill_holes(cut.vertices, cut.faces, method="fair")
    assert len(result.vertices) > len(cut.vertices) + 20
    return cut.vertices, cut.faces, result


def _rings_from_loop(faces, loop, n):
    """Each vertex's ring distance from the loop (0 on it), -1 beyond 3 rings."""
    ring = np.full(n, -1)
    ring[loop] = 0
    for k in range(1, 4):
        near = np.isin(faces, np.flatnonzero(ring == k - 1)).any(axis=1)
        grown = np.unique(faces[near])
        ring[grown[ring[grown] < 0]] = k
    return ring


def test_a_uv_seam_in_the_patch_away_from_the_loop_still_gives_the_new_faces_uv(
        filled_sphere):
    # a textured model has seams everywhere: one that crosses the hole's 3-ring patch but
    # not the loop used to give every new face no uv (NaN: untextured in the OBJ)
    v, f, result = filled_sphere
    uv = v[f][:, :, [0, 2]].astype(np.float32)
    ring = _rings_from_loop(f, result.reports[0].loop, len(v))
    # a second chart: the faces two or more rings out on one side, shifted in uv
    centre = v[result.reports[0].loop].mean(axis=0)
    side = (v[f].mean(axis=1) - centre) @ np.cross(centre, [0.0, 0.0, 1.0]) > 0
    second = side & (ring[f] >= 2).all(axis=1)
    assert 5 < second.sum() and ((ring[f] >= 0).all(axis=1) & second).any()
    seamed = uv.copy()
    seamed[second] += 3.0
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshWarning)
        out = fill_result_corner_attributes(result, {"uv": seamed})["uv"]
    assert np.array_equal(out[: len(f)], seamed)
    new = out[len(f):]
    assert not np.isnan(new).any()
    # in the loop's chart: the positions' x and z, as without the seam
    assert np.abs(new - result.vertices[result.new_faces][:, :, [0, 2]]).max() < 0.02


def test_a_seam_through_the_hole_splits_the_new_faces_between_its_charts(filled_sphere):
    # a seam running through the hole gave every new face no uv (NaN: written without vt,
    # and trimesh then loads the whole OBJ without texture coordinates); then (session 36)
    # the chart along most of the loop was continued across the hole, so the faces on the
    # seam's other side drew texels from outside that chart (session 37)
    v, f, result = filled_sphere
    uv = v[f][:, :, [0, 2]]
    loop = result.reports[0].loop
    ring = _rings_from_loop(f, loop, len(v))
    centre = v[loop].mean(axis=0)
    # the seam's plane leaves more of the loop on the unshifted side
    side = (v[f].mean(axis=1) - centre - 0.25 * np.cross(centre, [0.0, 0.0, 1.0])) \
        @ np.cross(centre, [0.0, 0.0, 1.0]) > 0
    seamed = uv.copy()
    seamed[side & (ring[f] >= 0).all(axis=1)] += 3.0
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshWarning)  # the seam continued: nothing to warn of
        out = fill_result_corner_attributes(result, {"uv": seamed})["uv"]
    assert np.array_equal(out[: len(f)], seamed)
    new = out[len(f):]
    assert not np.isnan(new).any()
    # each new face wholly in one chart: the positions' x and z, or those shifted by 3
    # (continued from its own side of the seam, so only as far as its share of the hole;
    # clamped to its chart's range where its share reaches past the seam's plane)
    exact = result.vertices[result.new_faces][:, :, [0, 2]]
    shifted = (new - exact).mean(axis=2) > 1.5
    assert (shifted.all(axis=1) | ~shifted.any(axis=1)).all()
    error = np.abs(new - exact - 3.0 * shifted[:, :, None])
    assert error.max() < 0.2 and error.mean() < 0.01
    assert 0 < shifted[:, 0].sum() < 0.5 * len(new)
    # the seam runs on into the hole: its loop vertices have a value in each chart
    seam_ends = [p for p in loop
                 if len(np.unique(seamed[f == p].round(9), axis=0)) == 2]
    assert len(seam_ends) == 2
    for p in seam_ends:
        assert len(np.unique(new[result.new_faces == p].round(9), axis=0)) == 2


def test_corners_without_a_value_along_the_loop_give_none(filled_sphere):
    v, f, result = filled_sphere
    uv = v[f][:, :, [0, 2]]
    uv[np.isin(f, result.reports[0].loop).any(axis=1)] = np.nan  # the loop's faces untextured
    with pytest.warns(MeshWarning, match="'uv' has no value along the hole's loop"):
        out = fill_result_corner_attributes(result, {"uv": uv})["uv"]
    assert np.isnan(out[len(f):]).all()
    assert np.array_equal(out[: len(f)], uv, equal_nan=True)


@pytest.mark.parametrize("inward", [False, True])
def test_corner_normals_of_new_faces_are_unit_surface_normals_across_hard_edges(
        filled_sphere, inward):
    # per-corner normals (an OBJ's vn with hard edges) were inpainted like any value: not of
    # unit length, and NaN (no vn) wherever a hard edge crossed the patch
    v, f, result = filled_sphere
    sign = -1.0 if inward else 1.0
    normals = sign * v[f] / np.linalg.norm(v[f], axis=2, keepdims=True)
    # a hard edge: the faces on one side of the hole flat-shaded (their face normal)
    loop = result.reports[0].loop
    centre = v[loop].mean(axis=0)
    side = (v[f].mean(axis=1) - centre) @ np.cross(centre, [0.0, 0.0, 1.0]) > 0
    flat = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    flat = sign * flat / np.linalg.norm(flat, axis=1, keepdims=True)
    normals[side] = flat[side][:, None, :]
    out = fill_result_corner_attributes(result, {"normal": normals})["normal"]
    assert np.array_equal(out[: len(f)], normals)
    new = out[len(f):]
    assert not np.isnan(new).any()
    np.testing.assert_allclose(np.linalg.norm(new, axis=2), 1.0, atol=1e-12)
    positions = result.vertices[result.new_faces]
    truth = sign * positions / np.linalg.norm(positions, axis=2, keepdims=True)
    cos = np.einsum("fck,fck->fc", new, truth)
    assert np.degrees(np.arccos(np.clip(cos, -1, 1))).max() < 10.0
    # smooth shading continues: at a loop vertex with one normal, the new corners take it
    smooth_loop = [i for i in loop if not side[(f == i).any(axis=1)].any()]
    assert smooth_loop
    for i in smooth_loop:
        at = result.new_faces == i
        assert np.array_equal(new[at], np.broadcast_to(
            normals[np.nonzero(f == i)][0], new[at].shape))


def test_a_textured_trimesh_comes_back_with_its_material_and_image():
    # the filled Trimesh had visual.uv but a blank material: the texture image was gone
    # (with a warning), so the result rendered and exported untextured
    trimesh = pytest.importorskip("trimesh")
    image_module = pytest.importorskip("PIL.Image")
    v, f = sphere(3)
    cut = cut_holes(v, f, [0], [0.5])
    uv = cut.vertices[:, :2] * 0.5 + 0.5
    image = image_module.new("RGB", (8, 8), (200, 30, 40))
    material = trimesh.visual.material.SimpleMaterial(image=image, diffuse=[200, 30, 40, 255])
    mesh = trimesh.Trimesh(cut.vertices, cut.faces, process=False,
                           visual=trimesh.visual.TextureVisuals(uv=uv, material=material))
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshWarning)
        result = fill_holes(mesh, method="fair")
    out = result.to_trimesh()
    assert out.visual.kind == "texture" and out.visual.material is material
    assert out.visual.material.image is image
    assert out.visual.uv.shape == (len(out.vertices), 2) and len(out.vertices) > len(uv)
    assert np.array_equal(out.visual.uv[: len(uv)], uv)
    # arrays in, arrays out: no material
    assert fill_holes(cut.vertices, cut.faces, method="fair").display == {}


def test_a_trimesh_uv_of_another_length_is_named_not_carried():
    trimesh = pytest.importorskip("trimesh")
    v, f = sphere(2)
    cut = cut_holes(v, f, [0], [0.6])
    mesh = trimesh.Trimesh(cut.vertices, cut.faces, process=False)
    mesh.visual = trimesh.visual.TextureVisuals(uv=np.zeros((len(cut.vertices), 2)))
    mesh.visual.uv = np.zeros((3, 2))
    with pytest.warns(MeshWarning, match=rf"visual.uv has 3 rows for {len(cut.vertices)} "
                                         "vertices: not carried"):
        result = fill_holes(mesh, method="fair")
    assert "uv" not in result.attributes


def test_a_pyvista_mesh_comes_back_with_its_active_texture_coordinates_and_no_new_scalars():
    # pyvista.read of an OBJ names its texture coordinates after the material
    # ('01_-_Default'): the filled PolyData had them as its active scalars and no active
    # texture coordinates, so add_mesh(out, texture=...) raised; a PolyData without active
    # scalars came back coloured by its first array
    pyvista = pytest.importorskip("pyvista")
    v, f = sphere(3)
    cut = cut_holes(v, f, [0], [0.5])
    poly = pyvista.PolyData(cut.vertices,
                            np.column_stack([np.full(len(cut.faces), 3), cut.faces]).ravel())
    poly.point_data["01_-_Default"] = (cut.vertices[:, :2] * 0.5 + 0.5).astype(np.float32)
    poly.point_data.active_texture_coordinates_name = "01_-_Default"
    poly.point_data["thickness"] = cut.vertices[:, 2]
    poly.point_data.active_scalars_name = None
    assert poly.point_data.active_scalars_name is None
    out = fill_holes(poly, method="fair").to_pyvista()
    assert out.n_points > poly.n_points
    assert out.point_data.active_texture_coordinates_name == "01_-_Default"
    assert out.active_texture_coordinates.shape == (out.n_points, 2)
    assert out.point_data["01_-_Default"].dtype == np.float32
    assert out.point_data.active_scalars_name is None
    # an active scalar array stays the one shown
    poly.point_data.active_scalars_name = "thickness"
    assert fill_holes(poly, method="fair").to_pyvista().point_data.active_scalars_name == \
        "thickness"


def test_a_filled_obj_with_a_seam_through_a_hole_opens_in_trimesh_with_its_uv(tmp_path,
                                                                              capsys):
    # the new faces had no vt (a seam reached the loop), and trimesh loads an OBJ whose faces
    # do not all have one without any texture coordinates: the texture was gone
    trimesh = pytest.importorskip("trimesh")
    from surfinpaint.app.cli import main
    from surfinpaint.io import MeshData, read_mesh_data, write_mesh_data

    v, f = sphere(3)
    cut = cut_holes(v, f, [0], [0.5])
    corners = cut.vertices[cut.faces][:, :, [0, 2]] * 0.4 + 0.5
    # a seam through the hole: the faces on one side of a plane through its centre in a
    # chart of their own
    across = np.cross(v[0], [0.0, 0.0, 1.0]) if abs(v[0][2]) < 0.9 else np.array([1.0, 0, 0])
    corners[(cut.vertices[cut.faces].mean(axis=1) - v[0]) @ across > 0] += [0.0, 0.02]
    (tmp_path / "in.mtl").write_text("newmtl skin\nKd 1 1 1\n")
    mesh = MeshData(cut.vertices, cut.faces, {}, {"material": np.full(len(cut.faces), "skin")},
                    {"uv": corners}, {"mtllib": "in.mtl"})
    write_mesh_data(tmp_path / "in.obj", mesh)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MeshWarning)
        assert main(["fill", str(tmp_path / "in.obj"), "-o", str(tmp_path / "out.obj"),
                     "--method", "fair"]) == 0
        back = read_mesh_data(tmp_path / "out.obj")
    # the seam is continued into the hole between its two charts: nothing to warn of
    assert "a seam of corner attribute 'uv'" not in capsys.readouterr().err
    assert len(back.faces) > len(cut.faces)
    assert not np.isnan(back.corner_attributes["uv"]).any()
    assert set(back.face_attributes["material"]) == {"skin"}
    loaded = trimesh.load(tmp_path / "out.obj", force="mesh", process=False)
    assert loaded.visual.kind == "texture" and loaded.visual.uv is not None
    assert loaded.visual.uv.shape == (len(loaded.vertices), 2)


def test_a_pyvista_mesh_with_a_point_per_face_corner_is_told_to_clean():
    # pyvista.read of an OBJ with texture coordinates gives every face its own points: no
    # face joins another, nothing is filled, and the hint named trimesh and MeshLab only
    pyvista = pytest.importorskip("pyvista")
    v, f = sphere(2)
    cut = cut_holes(v, f, [0], [0.6])
    corners = cut.vertices[cut.faces].reshape(-1, 3)
    own = np.arange(len(corners)).reshape(-1, 3)
    poly = pyvista.PolyData(corners, np.column_stack([np.full(len(own), 3), own]).ravel())
    with pytest.warns(MeshWarning, match=r"PyVista's OBJ reader at every face.*PyVista: "
                                         r"mesh\.clean\(\)"):
        result = fill_holes(poly, method="fair")
    assert len(result.new_faces) == 0
    filled = fill_holes(poly.clean(), method="fair")
    assert len(filled.new_faces) > 0


def _latitude_sphere(n_angles=32, n_rings=24):
    """A unit sphere of latitude rings (the +z pole first), outward faces: a hole around the
    pole has a regular polygon for its loop."""
    phi = np.pi * np.arange(1, n_rings) / n_rings
    t = 2 * np.pi * np.arange(n_angles) / n_angles
    ring = np.stack([np.sin(phi)[:, None] * np.cos(t), np.sin(phi)[:, None] * np.sin(t),
                     np.repeat(np.cos(phi)[:, None], n_angles, 1)], -1).reshape(-1, 3)
    vertices = np.vstack([[0.0, 0, 1], ring, [0, 0, -1]])
    i, j = np.meshgrid(np.arange(n_rings - 2), np.arange(n_angles), indexing="ij")
    a, d = 1 + i * n_angles + j, 1 + i * n_angles + (j + 1) % n_angles
    b, c = a + n_angles, d + n_angles
    last = 1 + (n_rings - 2) * n_angles + np.arange(n_angles)
    faces = np.vstack([
        np.column_stack([np.zeros(n_angles, int), 1 + np.arange(n_angles),
                         1 + (np.arange(n_angles) + 1) % n_angles]),
        np.column_stack([a.ravel(), b.ravel(), c.ravel()]),
        np.column_stack([a.ravel(), c.ravel(), d.ravel()]),
        np.column_stack([np.full(n_angles, len(vertices) - 1), np.roll(last, -1), last])])
    return vertices, faces


def test_uvs_that_fold_when_inpainted_are_placed_again_without_folds(monkeypatch):
    """A chart whose biharmonic continuation mirrors new faces (the bunny's 2 of 446): the
    new UVs are placed again by the mean-value map, which folds none inside a convex loop."""
    v, f = _latitude_sphere()
    f = f[v[f].mean(axis=1)[:, 2] < np.cos(np.radians(40))]  # a hole around the pole
    result = fill_holes(v, f, method="fair", holes=[0])
    # a chart seen from above the pole, stretched by the 5th power of the distance from the
    # axis: one-to-one and counter-clockwise on every face of the patch (none beyond z = 0.5)
    radius = np.linalg.norm(v[:, :2], axis=1)
    chart = v[:, :2] * radius[:, None] ** 4
    near = v[f].mean(axis=1)[:, 2] > 0.5
    d1, d2 = chart[f[near, 1]] - chart[f[near, 0]], chart[f[near, 2]] - chart[f[near, 0]]
    assert (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] > 0).all()

    def mirrored():
        uv = fill_result_corner_attributes(result, {"uv": chart[f]})["uv"][len(f):]
        e1, e2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
        assert np.isfinite(uv).all() and len(uv) > 100
        return int((e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] < 0).sum())

    assert mirrored() == 0
    from surfinpaint.fill import face_attributes
    monkeypatch.setattr(face_attributes, "_unfolded_uv", lambda dom, new, uv, *rest: (uv, 0))
    assert mirrored() > 20  # the biharmonic continuation alone: measured 38 of 166


def _ply_with_quality(path, vertices, faces):
    """A binary PLY with a per-vertex ``quality`` and a per-face ``confidence`` (a scanner's
    extra properties), written by surfinpaint's PLY writer."""
    from surfinpaint import write_mesh_data
    from surfinpaint.io import MeshData

    quality = np.linspace(0.0, 1.0, len(vertices))
    confidence = np.arange(len(faces), dtype=np.float32)
    write_mesh_data(path, MeshData(vertices, faces, attributes={"quality": quality},
                                   face_attributes={"confidence": confidence}))
    return quality, confidence


def test_a_trimesh_plys_extra_properties_are_carried_and_filled(tmp_path):
    # trimesh keeps a PLY's other properties only in metadata["_ply_raw"]: before this they
    # never reached the fill, and to_trimesh gave the mesh back without them, unwarned
    trimesh = pytest.importorskip("trimesh")
    v, f = sphere(3)
    cut = cut_holes(v, f, [0], 0.3)
    path = tmp_path / "scan.ply"
    quality, confidence = _ply_with_quality(path, cut.vertices, cut.faces)
    mesh = trimesh.load(path, process=False)
    assert "quality" not in mesh.vertex_attributes  # where trimesh leaves it
    result = fill_holes(mesh)
    n, m = len(cut.vertices), len(cut.faces)
    assert np.array_equal(result.attributes["quality"][:n], quality)
    new = result.attributes["quality"][n:]
    assert len(new) > 0 and np.all((new >= 0) & (new <= 1))
    assert np.array_equal(result.face_attributes["confidence"][:m], confidence)
    assert len(result.face_attributes["confidence"]) == len(result.faces)
    back = result.to_trimesh()
    assert len(back.vertex_attributes["quality"]) == len(back.vertices)


def test_a_trimesh_ply_loaded_with_merging_names_its_properties_not_carried(tmp_path):
    trimesh = pytest.importorskip("trimesh")
    v, f = sphere(2)
    cut = cut_holes(v, f, [0], 0.4)
    # a duplicate of vertex 0, unused: trimesh's default processing drops it
    vertices = np.vstack([cut.vertices, cut.vertices[:1]])
    path = tmp_path / "scan.ply"
    _ply_with_quality(path, vertices, cut.faces)
    mesh = trimesh.load(path)  # process=True: the rows no longer match the PLY's
    assert len(mesh.vertices) == len(cut.vertices)
    with pytest.warns(MeshWarning, match="vertex properties quality have .* process=False"):
        result = fill_holes(mesh)
    assert "quality" not in result.attributes


def _noisy_normals(vertices, seed=37):
    """Unit normals a scanner might give: the sphere's radial direction, perturbed (not
    what trimesh computes from the faces)."""
    rng = np.random.default_rng(seed)
    normals = vertices / np.linalg.norm(vertices, axis=1, keepdims=True)
    normals += 0.05 * rng.normal(size=normals.shape)
    return normals / np.linalg.norm(normals, axis=1, keepdims=True)


def test_a_trimesh_given_vertex_normals_keeps_them_and_gets_the_new_vertices_normals(
        tmp_path):
    # trimesh keeps vertex_normals= (and a file's normals) only in its cache: before this
    # the fill never saw them, and to_trimesh let trimesh recompute every vertex's normal,
    # the originals' too, without a word
    trimesh = pytest.importorskip("trimesh")
    v, f = sphere(3)
    cut = cut_holes(v, f, [0], 0.3)
    n = len(cut.vertices)
    given = _noisy_normals(cut.vertices)
    mesh = trimesh.Trimesh(cut.vertices, cut.faces, process=False, vertex_normals=given)
    path = tmp_path / "scan.ply"
    mesh.export(path)  # trimesh writes its given normals as nx ny nz (float32)
    for source, want in ((mesh, given), (trimesh.load(path, process=False),
                                         given.astype(np.float32))):
        result = fill_holes(source)
        assert np.array_equal(result.attributes["normal"][:n], want)
        new = result.vertices[n:]
        assert len(new) > 0
        cos = np.einsum("ij,ij->i", result.attributes["normal"][n:],
                        new / np.linalg.norm(new, axis=1, keepdims=True))
        assert cos.min() > np.cos(np.radians(10.0))  # the filled surface's, outward
        back = result.to_trimesh()
        assert np.array_equal(back.vertex_normals, result.attributes["normal"])
        assert "normal" not in back.vertex_attributes
    # normals trimesh computed itself (only read) are not the user's: computed again after
    # the fill, the loop's vertices' over their new faces too
    computed = trimesh.Trimesh(cut.vertices, cut.faces, process=False)
    assert computed.vertex_normals.shape == (n, 3)
    assert "normal" not in fill_holes(computed).attributes


def test_to_trimesh_gives_only_the_attribute_normal_as_the_meshs_normals():
    # session 38: any attribute named normals / vertex_normals / vertex_normal (any case)
    # became the mesh's vertex_normals and left its vertex_attributes: a trimesh's own
    # vertex_attributes["normals"] (a field of directions, a second set of normals) came
    # back under another name. Now "normal" only: the name the trimesh's own normals and a
    # file's are carried under
    trimesh = pytest.importorskip("trimesh")
    v, f = sphere(3)
    cut = cut_holes(v, f, [0], 0.3)
    n = len(cut.vertices)
    field = _noisy_normals(cut.vertices, seed=4)
    mesh = trimesh.Trimesh(cut.vertices, cut.faces, process=False,
                           vertex_attributes={"normals": field, "Vertex_Normals": -field})
    back = fill_holes(mesh).to_trimesh()
    assert set(back.vertex_attributes) == {"normals", "Vertex_Normals"}
    assert np.array_equal(back.vertex_attributes["normals"][:n], field)
    assert np.array_equal(back.vertex_attributes["Vertex_Normals"][:n], -field)
    computed = trimesh.Trimesh(back.vertices, back.faces, process=False).vertex_normals
    assert np.array_equal(back.vertex_normals, computed)  # trimesh's own, not the field
    # the attribute "normal" (a file's normals, as surfinpaint.io names them) is the mesh's
    result = fill_holes(cut.vertices, cut.faces, attributes={"normal": field})
    back = result.to_trimesh()
    assert np.array_equal(back.vertex_normals, result.attributes["normal"])
    assert "normal" not in back.vertex_attributes
    # a trimesh with its own normals and an attribute of that name: the attribute is
    # carried, the normals are not, and a warning says so
    own = trimesh.Trimesh(cut.vertices, cut.faces, process=False,
                          vertex_normals=_noisy_normals(cut.vertices),
                          vertex_attributes={"normal": field})
    with pytest.warns(MeshWarning, match=r"vertex_attributes\['normal'\] is carried under"):
        result = fill_holes(own)
    assert np.array_equal(result.attributes["normal"][:n], field)
