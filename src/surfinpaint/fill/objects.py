"""Meshes as objects of other libraries: ``trimesh.Trimesh`` and ``pyvista.PolyData`` in, and
out again with every attribute.

Neither library is needed to import surfinpaint: each is imported only when one of its
objects is passed in or asked for.

What is carried (one name a per-vertex or per-face array, as in ``FillResult.attributes``):

- ``trimesh.Trimesh``: vertex colours (``visual.vertex_colors``, RGBA uint8) as the attribute
  ``"color"`` and face colours (``visual.face_colors``) as the face attribute ``"color"`` (the
  names :mod:`surfinpaint.io` reads colours of every format under), ``vertex_attributes`` and
  ``face_attributes``; a texture's ``uv`` as the attribute ``"uv"`` and its material (the
  image) in ``FillResult.display``, which ``FillResult.to_trimesh`` gives back; a PLY's
  other vertex and face properties (``quality``), which trimesh keeps in its metadata;
  vertex normals given to it (``vertex_normals=``, or a file's read by ``trimesh.load``) as
  the attribute ``"normal"`` (:func:`given_vertex_normals`), which ``to_trimesh`` gives
  back as ``vertex_normals``: :data:`NORMALS_ATTRIBUTE` is the one name ``to_trimesh``
  gives as the mesh's normals (the name :mod:`surfinpaint.io` gives a file's normals too);
  an attribute of any other name, ``"normals"`` or ``"vertex_normals"`` included, comes
  back in ``vertex_attributes`` under its name, as it went in.
- ``pyvista.PolyData``: ``point_data`` and ``cell_data`` (polygons fan-triangulated first,
  with a warning; cell data then follow the triangles); its active texture coordinates,
  normals and scalars in ``FillResult.display``, made active again by
  ``FillResult.to_pyvista``.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping

import numpy as np

from surfinpaint.fill.face_attributes import fill_result_corner_attributes
from surfinpaint.io import MeshData, MeshWarning
from surfinpaint.io.brain import label_overlays

__all__ = ["ACTIVE_ROLES", "COLOUR_NAMES", "NORMALS_ATTRIBUTE", "display_of", "fill_mesh_data",
           "given_vertex_normals", "mesh_arrays", "to_pyvista", "to_trimesh"]

#: Attribute names that ``to_trimesh`` puts in ``visual`` (the first one found) rather than
#: ``vertex_attributes``.
COLOUR_NAMES = ("color", "colour", "colors", "colours", "vertex_colors", "vertex_colours",
                "rgba", "rgb")

#: The attribute ``to_trimesh`` gives as the mesh's ``vertex_normals`` (when ``(n, 3)``
#: float) rather than in ``vertex_attributes``: the name the normals of a trimesh's own
#: (:func:`given_vertex_normals`) and of a file (:mod:`surfinpaint.io`) are carried under.
#: Only it (session 38): a user's ``vertex_attributes["normals"]`` (a field of directions, a
#: second set of normals) came back as the mesh's normals before, and was gone from its
#: ``vertex_attributes``.
NORMALS_ATTRIBUTE = "normal"


def _library(mesh) -> str | None:
    module = type(mesh).__module__
    for name in ("trimesh", "pyvista"):
        if module == name or module.startswith(name + "."):
            return name
    return None


def _from_trimesh(mesh) -> tuple[np.ndarray, np.ndarray, dict, dict]:
    if not hasattr(mesh, "vertex_attributes"):
        raise TypeError(f"a trimesh {type(mesh).__name__} is not one triangle mesh: pass a "
                        "trimesh.Trimesh (a Scene's meshes as one: scene.to_geometry(), or "
                        "trimesh.load(path, force='mesh'))")
    attributes = {name: np.asarray(a) for name, a in mesh.vertex_attributes.items()}
    face_attributes = {name: np.asarray(a) for name, a in mesh.face_attributes.items()}
    visual = mesh.visual
    if visual.kind == "vertex":
        attributes.setdefault("color", np.asarray(visual.vertex_colors))
    elif visual.kind == "face":
        face_attributes.setdefault("color", np.asarray(visual.face_colors))
    elif visual.kind == "texture":
        # the material (its image) is given back by FillResult.to_trimesh (display_of)
        uv = getattr(visual, "uv", None)
        if uv is not None and len(uv) == len(mesh.vertices):
            attributes.setdefault("uv", np.asarray(uv))
        elif uv is not None:
            warnings.warn(f"trimesh texture: visual.uv has {len(uv)} rows for "
                          f"{len(mesh.vertices)} vertices: not carried", MeshWarning,
                          stacklevel=4)
    normals = given_vertex_normals(mesh)
    if normals is not None and NORMALS_ATTRIBUTE in attributes:
        warnings.warn(f"trimesh: vertex_attributes[{NORMALS_ATTRIBUTE!r}] is carried under "
                      "the name of the mesh's own vertex normals, which are not carried "
                      "(trimesh computes the filled mesh's)", MeshWarning, stacklevel=4)
    elif normals is not None:
        attributes[NORMALS_ATTRIBUTE] = normals
    _ply_properties(mesh, attributes, face_attributes)
    return np.asarray(mesh.vertices), np.asarray(mesh.faces), attributes, face_attributes


def given_vertex_normals(mesh) -> np.ndarray | None:
    """The vertex normals a ``trimesh.Trimesh`` was given (``vertex_normals=``, or a file's
    ``vn``/``nx ny nz`` read by ``trimesh.load``), or None when it has none of its own.

    trimesh keeps given normals where it keeps the ones it computes, in its cache (its own
    PLY exporter writes normals when they are there); computed ones are those of
    ``trimesh.geometry.weighted_vertex_normals`` of the same faces, so cached normals equal
    to them bit for bit are trimesh's and not the user's (a trimesh whose ``vertex_normals``
    was only read): those are None too, and the filled mesh's are computed again by trimesh,
    the loop's vertices' over their new faces too.
    """
    cache = getattr(mesh, "_cache", None)
    try:
        cached = cache["vertex_normals"] if cache is not None else None
    except (KeyError, TypeError):  # a trimesh without the cache of trimesh 4 and 5
        return None
    if cached is None or np.shape(cached) != np.shape(mesh.vertices):
        return None
    import trimesh

    computed = trimesh.geometry.weighted_vertex_normals(
        vertex_count=len(mesh.vertices), faces=mesh.faces, face_normals=mesh.face_normals,
        face_angles=mesh.face_angles)
    return None if np.array_equal(cached, computed) else np.array(cached, dtype=float)


#: PLY properties trimesh reads into its own fields (positions, normals, colours, UVs, the
#: faces' vertex lists); any other property of the vertex or face element is carried.
_PLY_READ_BY_TRIMESH = frozenset({"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue",
                                  "alpha", "s", "t", "u", "v", "texture_u", "texture_v",
                                  "vertex_indices", "vertex_index", "texcoord"})


def _ply_properties(mesh, attributes: dict, face_attributes: dict) -> None:
    """A PLY's other per-vertex and per-face properties (a scanner's ``quality`` or
    ``confidence``), which trimesh keeps only in ``metadata["_ply_raw"]``, added to the
    attributes, where the element has a row per vertex (face) of the mesh; else a warning
    that they are not carried (trimesh merged or dropped rows on loading:
    ``trimesh.load(path, process=False)`` keeps them)."""
    raw = getattr(mesh, "metadata", {}).get("_ply_raw")
    if not isinstance(raw, dict):
        return
    for element, rows, into in (("vertex", len(mesh.vertices), attributes),
                                ("face", len(mesh.faces), face_attributes)):
        data = raw.get(element, {}).get("data") if isinstance(raw.get(element), dict) else None
        names = [n for n in getattr(getattr(data, "dtype", None), "names", None) or ()
                 if n not in _PLY_READ_BY_TRIMESH and n not in into]
        if not names:
            continue
        if len(data) != rows:
            warnings.warn(f"trimesh PLY: the {element} properties {', '.join(names)} have "
                          f"{len(data)} rows for {rows} {element}s of the mesh (trimesh "
                          "merged or dropped some on loading: load with process=False): "
                          "not carried", MeshWarning, stacklevel=5)
            continue
        for name in names:
            if data.dtype[name].names is None and data.dtype[name].kind in "biuf":
                into[name] = np.asarray(data[name])
            else:  # a list property: no one array of rows
                warnings.warn(f"trimesh PLY: the {element} property {name} is a list: not "
                              "carried", MeshWarning, stacklevel=5)


def _from_pyvista(mesh) -> tuple[np.ndarray, np.ndarray, dict, dict]:
    import pyvista

    if not isinstance(mesh, pyvista.PolyData):
        raise TypeError(f"a pyvista {type(mesh).__name__} is not a surface: pass a "
                        "pyvista.PolyData (its boundary surface: mesh.extract_surface())")
    extra = {"line cells": mesh.n_lines, "vertex cells": mesh.n_verts}
    if any(extra.values()):
        raise ValueError("the PolyData has " + ", ".join(f"{n} {k}" for k, n in extra.items()
                                                          if n)
                         + f" beside {mesh.n_cells - sum(extra.values())} polygons or strips: "
                         "keep only the surface (extract_surface)")
    if not mesh.is_all_triangles:
        from vtkmodules.util.numpy_support import vtk_to_numpy

        sides = np.diff(vtk_to_numpy(mesh.GetPolys().GetOffsetsArray()))
        made = [f"{n} {what}" for n, what in ((int((sides > 3).sum()), "polygons of more "
                                               "than 3 sides"), (mesh.n_strips, "strips"))
                if n]
        warnings.warn(f"PolyData: {' and '.join(made)} fan-triangulated (cell data follow "
                      "the triangles)", MeshWarning, stacklevel=4)
        mesh = mesh.triangulate()
    if mesh.field_data.keys():  # neither per point nor per cell: the arrays have no place
        warnings.warn(f"PolyData field data {', '.join(map(repr, mesh.field_data.keys()))} "
                      "not carried (one value for the whole mesh, not per point or cell): "
                      "copy it to the filled mesh, out.field_data.update(mesh.field_data)",
                      MeshWarning, stacklevel=4)
    faces = np.asarray(mesh.regular_faces, dtype=np.int64).reshape(-1, 3)
    attributes = {name: np.asarray(mesh.point_data[name]) for name in mesh.point_data.keys()}
    face_attributes = {name: np.asarray(mesh.cell_data[name])
                       for name in mesh.cell_data.keys()}
    return np.asarray(mesh.points), faces, attributes, face_attributes


def mesh_arrays(
    mesh, faces=None, attributes: Mapping[str, np.ndarray] | None = None,
    face_attributes: Mapping[str, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Vertices, faces and attributes of a mesh given as arrays or as a library's object.

    Parameters
    ----------
    mesh : (n, 3) array, ``trimesh.Trimesh`` or ``pyvista.PolyData``
        The vertices (then ``faces`` is required) or a mesh object (then ``faces`` must be
        None); an object's own attributes are picked up (see the module docstring).
    faces : (f, 3) int array, optional
    attributes, face_attributes : mapping of name to array, optional
        Per-vertex and per-face arrays; they take precedence over an object's own of the
        same name.

    Returns
    -------
    vertices, faces, attributes, face_attributes

    Raises
    ------
    TypeError
        An object of another kind (a pyvista dataset other than ``PolyData`` too), a mesh
        object with ``faces`` too, or arrays without ``faces``.
    ValueError
        A PolyData with lines or vertex cells.
    """
    library = _library(mesh)
    if library is None:
        if faces is None and hasattr(mesh, "corner_attributes"):
            raise TypeError("a MeshData is given by its parts: fill_holes(mesh.vertices, "
                            "mesh.faces, attributes=mesh.attributes, face_attributes="
                            "mesh.face_attributes); its corner data through surfinpaint.fill."
                            "face_attributes.fill_result_corner_attributes")
        if faces is None:
            raise TypeError(f"a mesh needs faces with vertices given as an array; got a "
                            f"{type(mesh).__name__} and no faces (trimesh.Trimesh and "
                            "pyvista.PolyData are taken whole)")
        own_vertices, own_faces, own, own_faces_attributes = mesh, faces, {}, {}
    else:
        if faces is not None:
            raise TypeError(f"faces given with a {type(mesh).__name__}: pass the mesh alone")
        reader = _from_trimesh if library == "trimesh" else _from_pyvista
        own_vertices, own_faces, own, own_faces_attributes = reader(mesh)
    return (own_vertices, own_faces, {**own, **dict(attributes or {})},
            {**own_faces_attributes, **dict(face_attributes or {})})


def _normal_name(attributes: Mapping[str, np.ndarray]) -> str | None:
    """:data:`NORMALS_ATTRIBUTE` when ``attributes`` holds it as ``(n, 3)`` floats."""
    a = attributes.get(NORMALS_ATTRIBUTE)
    return NORMALS_ATTRIBUTE if a is not None and np.shape(a)[1:] == (3,) and \
        np.asarray(a).dtype.kind == "f" else None


def _colour_name(attributes: Mapping[str, np.ndarray]) -> str | None:
    for name in COLOUR_NAMES:
        for key, a in attributes.items():
            if key.lower() == name and np.ndim(a) == 2 and np.shape(a)[1] in (3, 4):
                return key
    return None


#: The ``point_data`` roles of a ``pyvista.PolyData`` that :func:`display_of` keeps.
ACTIVE_ROLES = ("active_normals_name", "active_texture_coordinates_name",
                "active_scalars_name")


def display_of(mesh) -> dict[str, object]:
    """How a mesh object is shown, beside its arrays: a textured ``trimesh.Trimesh``'s
    material (``"material"``: ``visual.material``, its image included); a
    ``pyvista.PolyData``'s active point arrays (:data:`ACTIVE_ROLES`: the texture
    coordinates a texture is drawn with, the normals, the scalars it is coloured by, None
    when none is). :func:`to_trimesh` and :func:`to_pyvista` give them back. Empty for
    anything else."""
    library = _library(mesh)
    if library == "trimesh":
        visual = getattr(mesh, "visual", None)
        material = getattr(visual, "material", None) \
            if getattr(visual, "kind", None) == "texture" else None
        return {} if material is None else {"material": material}
    if library == "pyvista" and hasattr(mesh, "point_data"):
        return {role: getattr(mesh.point_data, role) for role in ACTIVE_ROLES}
    return {}


def to_trimesh(vertices: np.ndarray, faces: np.ndarray,
               attributes: Mapping[str, np.ndarray] | None = None,
               face_attributes: Mapping[str, np.ndarray] | None = None,
               display: Mapping[str, object] | None = None):
    """A ``trimesh.Trimesh`` (``process=False``: nothing merged or reordered) with the vertex
    colours in ``visual`` (the first attribute named in :data:`COLOUR_NAMES`; when there is
    none, the face attribute so named; when there are no colours, an ``(n, 2)`` attribute
    ``"uv"`` as ``visual.uv`` of a ``TextureVisuals`` with ``display["material"]``, the
    texture's image, when given: :func:`display_of`), the attribute
    :data:`NORMALS_ATTRIBUTE` (``"normal"``) as ``vertex_normals``, and every other
    attribute in ``vertex_attributes`` / ``face_attributes`` under its own name."""
    import trimesh

    attributes = dict(attributes or {})
    face_attributes = dict(face_attributes or {})
    colour = _colour_name(attributes)
    vertex_colors = attributes.pop(colour) if colour else None
    face_colour = None if colour else _colour_name(face_attributes)
    face_colors = face_attributes.pop(face_colour) if face_colour else None
    normal = _normal_name(attributes)
    normals = attributes.pop(normal) if normal else None
    uv = attributes.get("uv")
    visual = None
    if colour is None and face_colour is None and uv is not None \
            and np.shape(uv) == (len(vertices), 2):
        visual = trimesh.visual.TextureVisuals(uv=attributes.pop("uv"),
                                                material=(display or {}).get("material"))
    return trimesh.Trimesh(vertices=vertices, faces=faces, process=False, validate=False,
                           vertex_colors=vertex_colors, face_colors=face_colors,
                           vertex_normals=normals, visual=visual, vertex_attributes=attributes,
                           face_attributes=face_attributes)


def to_pyvista(vertices: np.ndarray, faces: np.ndarray,
               attributes: Mapping[str, np.ndarray] | None = None,
               face_attributes: Mapping[str, np.ndarray] | None = None,
               display: Mapping[str, object] | None = None):
    """A ``pyvista.PolyData`` with every attribute in ``point_data`` and every face attribute
    in ``cell_data``. The arrays PyVista reads and the file formats write under these names
    are made active again: normals (``Normals``, ``normal``), texture coordinates
    (``TCoords``, ``Texture Coordinates``, ``uv``) and colours (:data:`COLOUR_NAMES`,
    ``RGB``, ``RGBA``); for a role none of them fills, the active array of ``display`` (an
    input PolyData's, by :func:`display_of`: texture coordinates of any name, the scalars
    it was shown with, or none)."""
    import pyvista

    faces = np.asarray(faces, dtype=np.int64)
    cells = np.column_stack([np.full(len(faces), 3, dtype=np.int64), faces]).ravel()
    mesh = pyvista.PolyData(np.asarray(vertices, dtype=float), cells)
    for name, a in (attributes or {}).items():
        mesh.point_data[name] = np.asarray(a)
    for name, a in (face_attributes or {}).items():
        mesh.cell_data[name] = np.asarray(a)
    data = mesh.point_data
    display = display or {}
    for active, names, width in (("active_normals_name", ("Normals", "normal"), (3,)),
                                 ("active_texture_coordinates_name",
                                  ("TCoords", "Texture Coordinates", "uv"), (2,)),
                                 ("active_scalars_name", (_colour_name(attributes or {}),),
                                  (3, 4))):
        name = next((n for n in names if n in data.keys() and data[n].ndim == 2
                     and data[n].shape[1] in width), None)
        if name is None and active in display:
            # the input PolyData's own: texture coordinates of any name (an OBJ's are named
            # after its material), the scalars it was shown with or none
            name = display[active]
            if name is None or name in data.keys():
                setattr(data, active, name)
        elif name is not None:
            setattr(data, active, name)
    return mesh


def fill_mesh_data(mesh, **fill_options):
    """Fill the holes of a :class:`surfinpaint.io.MeshData` with all its data: what a file
    read by :func:`surfinpaint.io.read_mesh_data` becomes, ready for
    :func:`surfinpaint.io.write_mesh_data`.

    Parameters
    ----------
    mesh : MeshData
    **fill_options
        Passed to :func:`surfinpaint.fill_holes` (not ``attributes``/``face_attributes``:
        the mesh's own are used). An overlay read with a label table (``.label.gii``,
        ``.annot``) is filled as labels (``attribute_kinds`` may say otherwise).

    Returns
    -------
    result : FillResult
    filled : MeshData
        The filled mesh with every attribute (new vertices', faces' and corners' values by
        :mod:`surfinpaint.fill.attributes` and :mod:`surfinpaint.fill.face_attributes`) and
        the metadata of ``mesh``.
    """
    # here, not at the top: the pipeline imports this module (mesh_arrays, to_trimesh)
    from surfinpaint.fill.pipeline import fill_holes

    # a .label.gii or .annot overlay is a segmentation however many labels it has (an atlas
    # of 180 areas): its new vertices take labels, never blends of label numbers
    kinds = {name: "label" for name in label_overlays(mesh.metadata) if name in mesh.attributes}
    kinds.update(fill_options.pop("attribute_kinds", None) or {})
    result = fill_holes(mesh.vertices, mesh.faces, attributes=mesh.attributes,
                        face_attributes=mesh.face_attributes, attribute_kinds=kinds or None,
                        **fill_options)
    corners = fill_result_corner_attributes(result, mesh.corner_attributes)
    return result, MeshData(result.vertices, result.faces, result.attributes,
                            result.face_attributes, corners, mesh.metadata)
