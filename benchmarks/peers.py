"""Reference hole fillers from other libraries, for benchmarks only (never imported by the
package; they need the ``peers`` extras: ``pip install surfinpaint[peers]``).

Both follow the convention of :func:`surfinpaint.fill.liepa.baseline.conventional_fill`: given a
mesh and
one boundary loop, return ``(new_vertices, new_faces)`` where ``new_vertices`` are the added
vertices (ids ``n .. n + m - 1`` after the ``n`` original ones, which never move) and
``new_faces`` the patch faces over original and new ids, oriented like the mesh.

- :func:`cgal_fill`: CGAL ``Polygon_mesh_processing::triangulate_refine_and_fair_hole``
  (Liepa 2003: minimum-weight triangulation, refinement, biharmonic fairing), through the
  SWIG bindings of the ``cgal`` package; :func:`cgal3_fill` the same with triharmonic
  fairing (``fairing_continuity=2``).
- :func:`meshlib_fill`: MeshLib ``fillHoleNicely`` (triangulation, subdivision to a maximum
  edge length, curvature-smooth fill), through the ``meshlib`` package.
- :func:`pymeshlab_fill`: MeshLab's ``meshing_close_holes`` with hole refinement, through
  ``pymeshlab``.
- :func:`pymeshfix_fill`: MeshFix's ``fill_small_boundaries`` (triangulation and
  refinement; MeshFix does not fair a hole's patch), through ``pymeshfix``.

The last two fill every hole up to a number of boundary edges: every other boundary loop is
capped by a temporary fan (removed again from their output) before they are called, so they
fill the given hole only.
"""

from __future__ import annotations

import importlib.metadata
import os
import tempfile

import numpy as np

__all__ = ["PEERS", "available", "cgal3_fill", "cgal_fill", "meshlib_fill",
           "pymeshfix_bare_fill", "pymeshfix_fill", "pymeshlab_fill", "versions"]


def _boundary_edge_lengths(vertices: np.ndarray, loop: np.ndarray) -> np.ndarray:
    p = vertices[loop]
    return np.linalg.norm(p - np.roll(p, -1, axis=0), axis=1)


def cgal_fill(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, *,
              continuity: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Fill the hole bounded by ``loop`` with CGAL's triangulate_refine_and_fair_hole.

    ``continuity`` is CGAL's ``fairing_continuity``: 1 (default, bilaplacian fairing) or 2
    (trilaplacian), with CGAL's default density factor √2.

    The mesh goes to a ``Polyhedron_3`` through a temporary OFF file (the bindings have no
    array constructor; vertices keep the file order and get their index as id). The border
    half-edge handed to CGAL is one whose target is a loop vertex, so other holes are left
    alone.

    Raises
    ------
    RuntimeError
        When CGAL reports failure, the loop is not a border of the mesh, or an original
        vertex moved.
    """
    from CGAL.CGAL_Polygon_mesh_processing import triangulate_refine_and_fair_hole
    from CGAL.CGAL_Polyhedron_3 import Polyhedron_3

    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    loop_set = set(np.asarray(loop).tolist())
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "mesh.off")
        with open(path, "w") as fh:
            fh.write(f"OFF\n{len(v)} {len(f)} 0\n")
            np.savetxt(fh, v, fmt="%.17g")
            np.savetxt(fh, np.column_stack([np.full(len(f), 3), f]), fmt="%d")
        poly = Polyhedron_3(path)
    if poly.size_of_vertices() != len(v) or poly.size_of_facets() != len(f):
        raise RuntimeError(f"CGAL read {poly.size_of_vertices()} vertices and "
                           f"{poly.size_of_facets()} faces instead of {len(v)} and {len(f)}")
    for i, vh in enumerate(poly.vertices()):
        vh.set_id(i)
    border = None
    for h in poly.halfedges():
        if h.is_border() and h.vertex().id() in loop_set and h.opposite().vertex().id() in loop_set:
            border = h
            break
    if border is None:
        raise RuntimeError("no border half-edge of CGAL's polyhedron lies on the given loop")
    out_faces: list = []
    out_vertices: list = []
    ok = triangulate_refine_and_fair_hole(poly, border, out_faces, out_vertices,
                                          float(np.sqrt(2.0)), int(continuity))
    if ok is False:
        raise RuntimeError("CGAL triangulate_refine_and_fair_hole reported failure (fairing)")
    n = len(v)
    # the original vertices must not have moved (fairing touches the new ones only)
    moved = [vh.id() for vh in poly.vertices() if 0 <= vh.id() < n and not np.array_equal(
        [vh.point().x(), vh.point().y(), vh.point().z()], v[vh.id()])]
    if moved:
        raise RuntimeError(f"CGAL moved original vertices {moved[:10]}")
    new_v = np.array([[vh.point().x(), vh.point().y(), vh.point().z()] for vh in out_vertices],
                     dtype=float).reshape(-1, 3)
    for k, vh in enumerate(out_vertices):
        vh.set_id(n + k)
    new_f = np.array([[fh.halfedge().vertex().id(), fh.halfedge().next().vertex().id(),
                       fh.halfedge().next().next().vertex().id()] for fh in out_faces],
                     dtype=np.int64).reshape(-1, 3)
    return new_v, new_f


def meshlib_fill(vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray, *,
                 max_edge_length: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Fill the hole bounded by ``loop`` with MeshLib's fillHoleNicely.

    Settings: ``triangulateOnly=False`` (subdivide), ``smoothCurvature=True`` (curvature-
    continuous fill), no cap on the number of edge splits, and ``maxEdgeLen`` just above the
    longest boundary edge unless given: MeshLib splits every edge longer than that, boundary
    edges included, which would change the original faces along the hole (checked: the
    call raises if any original face changed). MeshLib stores float32 positions: the new
    vertices are float32-accurate (relative 1e-7), the original ones are returned untouched.

    Raises
    ------
    RuntimeError
        When no hole of MeshLib's mesh lies on the loop, or MeshLib moved original vertices
        or changed original faces.
    """
    import meshlib.mrmeshnumpy as mn
    import meshlib.mrmeshpy as mm

    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    loop = np.asarray(loop, np.int64)
    mesh = mn.meshFromFacesVerts(f.astype(np.int32), v.astype(np.float32))
    top = mesh.topology
    loop_set = set(loop.tolist())
    edge = None
    for e in top.findHoleRepresentiveEdges():
        if top.org(e).get() in loop_set and top.dest(e).get() in loop_set:
            edge = e
            break
    if edge is None:
        raise RuntimeError("no hole of MeshLib's mesh lies on the given loop")
    settings = mm.FillHoleNicelySettings()
    settings.triangulateOnly = False
    settings.smoothCurvature = True
    settings.subdivideSettings.maxEdgeLen = float(
        max_edge_length if max_edge_length is not None
        else 1.001 * _boundary_edge_lengths(v, loop).max())
    settings.subdivideSettings.maxEdgeSplits = 10_000_000
    patch = mm.fillHoleNicely(mesh, edge, settings)
    out_v = mn.getNumpyVerts(mesh)
    if len(out_v) < len(v) or np.abs(out_v[: len(v)] - v.astype(np.float32)).max() > 0:
        raise RuntimeError("MeshLib did not keep the original vertices in place")
    in_patch = np.asarray(mn.getNumpyBitSet(patch), bool)
    all_faces = mn.getNumpyFaces(top).astype(np.int64)  # by face id; new faces follow
    in_patch = np.concatenate([in_patch, np.zeros(len(all_faces) - len(in_patch), bool)])
    new_f = all_faces[in_patch]
    kept = all_faces[~in_patch]
    if len(kept) != len(f) or not np.array_equal(np.sort(np.sort(kept, 1), 0),
                                                 np.sort(np.sort(f, 1), 0)):
        raise RuntimeError("MeshLib changed original faces next to the hole")
    return out_v[len(v):].astype(float), new_f


def cgal3_fill(vertices: np.ndarray, faces: np.ndarray,
               loop: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`cgal_fill` with trilaplacian fairing (``fairing_continuity=2``)."""
    return cgal_fill(vertices, faces, loop, continuity=2)


def _split_new(vertices: np.ndarray, faces: np.ndarray, out_v: np.ndarray, out_f: np.ndarray,
               name: str) -> tuple[np.ndarray, np.ndarray]:
    """(new vertices, new faces) of a peer's whole output mesh.

    Peers may reorder vertices (MeshFix does): output vertices at exactly an original
    position are that original vertex, the others are new (numbered after the originals in
    output order). Raises when an original vertex is missing or moved, or an original face
    is missing.
    """
    from scipy.spatial import cKDTree

    n = len(vertices)
    dist, nearest = cKDTree(out_v).query(vertices)
    if (dist > 0).any() or len(np.unique(nearest)) != n:
        raise RuntimeError(f"{name} moved or dropped original vertices "
                           f"{np.flatnonzero(dist > 0)[:10].tolist()}")
    new_id = np.full(len(out_v), -1, np.int64)
    new_id[nearest] = np.arange(n)
    added = new_id < 0
    new_id[added] = n + np.arange(int(added.sum()))
    out_f = new_id[out_f]
    key = lambda a: {tuple(t) for t in np.sort(a, axis=1).tolist()}  # noqa: E731
    before = key(faces)
    missing = before - key(out_f)
    if missing:
        raise RuntimeError(f"{name} changed {len(missing)} original faces")
    is_new = np.array([tuple(t) not in before for t in np.sort(out_f, axis=1).tolist()], bool)
    return out_v[added], out_f[is_new]


def _only_this_hole(fill, vertices: np.ndarray, faces: np.ndarray, loop: np.ndarray,
                    name: str) -> tuple[np.ndarray, np.ndarray]:
    """Run ``fill(vertices, faces)`` (a whole-mesh hole filler returning its output mesh) with
    every boundary loop but ``loop`` capped by a fan to its centroid, and return the
    (new vertices, new faces) of the given hole, as the other peers do."""
    from surfinpaint.geometry.mesh import boundary_loops

    n = len(vertices)
    target = set(np.asarray(loop).tolist())
    others = [lp for lp in boundary_loops(faces) if set(lp.tolist()) != target]
    centres = np.array([vertices[lp].mean(axis=0) for lp in others]).reshape(-1, 3)
    caps = [np.column_stack([np.roll(lp, -1), lp, np.full(len(lp), n + k)])
            for k, lp in enumerate(others)]  # reversed edges: orientation consistent
    capped_v = np.vstack([vertices, centres])
    capped_f = np.vstack([faces, *caps]) if caps else faces
    out_v, out_f = fill(capped_v, capped_f)
    new_v, new_f = _split_new(capped_v, capped_f, out_v, out_f, name)
    if ((new_f >= n) & (new_f < n + len(others))).any():
        raise RuntimeError(f"{name} attached its fill to a temporary cap")
    return new_v, np.where(new_f >= n, new_f - len(others), new_f)


def pymeshlab_fill(vertices: np.ndarray, faces: np.ndarray,
                   loop: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Fill the hole bounded by ``loop`` with MeshLab's ``meshing_close_holes``.

    Settings: ``maxholesize`` = the loop's edge count + 1 (MeshLab closes holes below that
    size),
    ``refinehole=True`` with ``refineholeedgelen`` the mean boundary edge length, and
    ``selfintersection=True`` (MeshLab's default: no fill faces that intersect the mesh).

    Raises
    ------
    RuntimeError
        When MeshLab adds no face, or moves or changes original vertices or faces.
    """
    import pymeshlab

    v = np.asarray(vertices, float)
    edge = float(_boundary_edge_lengths(v, loop).mean())

    def fill(cv, cf):
        ms = pymeshlab.MeshSet()
        ms.add_mesh(pymeshlab.Mesh(vertex_matrix=cv, face_matrix=cf.astype(np.int32)))
        ms.meshing_close_holes(maxholesize=int(len(loop)) + 1, selected=False,
                               newfaceselected=True, selfintersection=True, refinehole=True,
                               refineholeedgelen=pymeshlab.PureValue(edge))
        m = ms.current_mesh()
        return m.vertex_matrix().astype(float), m.face_matrix().astype(np.int64)

    new_v, new_f = _only_this_hole(fill, v, np.asarray(faces, np.int64), loop, "MeshLab")
    if len(new_f) == 0:
        raise RuntimeError("MeshLab's meshing_close_holes added no face")
    return new_v, new_f


def pymeshfix_fill(vertices: np.ndarray, faces: np.ndarray,
                   loop: np.ndarray, refine: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Fill the hole bounded by ``loop`` with MeshFix's ``fill_small_boundaries``
    (``nbe`` = the loop's edge count + 1, ``refine=True``; MeshFix may reorder vertices,
    they are matched back by position). ``refine=False``: MeshFix's triangulation of the
    loop alone (its greedy ear cutting, no new vertex; session 49).

    Raises
    ------
    RuntimeError
        When MeshFix adds no face, or moves or changes original vertices or faces.
    """
    import pymeshfix

    def fill(cv, cf):
        tin = pymeshfix.PyTMesh()
        tin.set_quiet(True)
        tin.load_array(cv, cf.astype(np.int32))
        tin.fill_small_boundaries(nbe=int(len(loop)) + 1, refine=refine)
        out_v, out_f = tin.return_arrays()
        return np.asarray(out_v, float), np.asarray(out_f, np.int64)

    new_v, new_f = _only_this_hole(fill, np.asarray(vertices, float),
                                   np.asarray(faces, np.int64), loop, "MeshFix")
    if len(new_f) == 0:
        raise RuntimeError("MeshFix's fill_small_boundaries added no face")
    return new_v, new_f


def pymeshfix_bare_fill(vertices: np.ndarray, faces: np.ndarray,
                        loop: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`pymeshfix_fill` without its refinement: MeshFix's triangulation alone."""
    return pymeshfix_fill(vertices, faces, loop, refine=False)


PEERS = {"cgal": cgal_fill, "cgal3": cgal3_fill, "meshlib": meshlib_fill,
         "pymeshlab": pymeshlab_fill, "pymeshfix": pymeshfix_fill}
_PACKAGES = {"cgal": "cgal", "meshlib": "meshlib", "pymeshlab": "pymeshlab",
             "pymeshfix": "pymeshfix"}


def available() -> list[str]:
    """Names of the peers whose package imports."""
    out = []
    for names, module in ((("cgal", "cgal3"), "CGAL.CGAL_Polygon_mesh_processing"),
                          (("meshlib",), "meshlib.mrmeshpy"), (("pymeshlab",), "pymeshlab"),
                          (("pymeshfix",), "pymeshfix")):
        try:
            __import__(module)
        except ImportError:
            continue
        out.extend(names)
    return out


def versions() -> dict[str, str]:
    """Installed version of each peer's package (``"missing"`` when absent)."""
    out = {}
    for name, dist in _PACKAGES.items():
        try:
            out[name] = importlib.metadata.version(dist)
        except importlib.metadata.PackageNotFoundError:
            out[name] = "missing"
    return out
