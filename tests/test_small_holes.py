"""The per-hole steps made cheaper for small holes give the same bits as the ways they
replaced (session 32): the k-ring grown through faces, the neighbourhood cut that searches
the added faces only where its new vertices hold one, the plane tests sharing one ring and
summing vertex normals over the faces at it."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from surfinpaint.data import sphere
from surfinpaint.fill.conformal.method import _ring, known_plane, known_two_planes
from surfinpaint.fill.neighbourhood import (
    FilledMesh,
    _distinct,
    _incident,
    neighbourhood_faces,
)
from surfinpaint.fill.results import Fill
from surfinpaint.geometry.cutting import cut_geodesic_disk
from surfinpaint.geometry.mesh import k_ring, vertex_adjacency, vertex_normals


def _k_ring_by_adjacency(faces, seeds, k, n):
    """The k-ring as it was found before: grown through the vertex adjacency matrix."""
    adjacency = vertex_adjacency(faces, n)
    mask = np.zeros(n, dtype=bool)
    mask[np.asarray(seeds)] = True
    for _ in range(k):
        mask = mask | (adjacency @ mask.astype(np.int8) > 0)
    return mask


def _scanning_every_ring(faces, incidence, added, seeds, rings):
    """:func:`neighbourhood_faces` as it was before: all added faces searched every ring."""
    n_original = incidence.shape[0]
    n_all = max(n_original, int(added.max()) + 1 if len(added) else 0, int(np.max(seeds)) + 1)
    in_region = np.zeros(n_all, dtype=bool)
    face_in = np.zeros(len(faces), dtype=bool)
    vertex_stamp, face_stamp = np.empty(n_all, np.int64), np.empty(len(faces), np.int64)
    frontier = np.unique(seeds)
    in_region[frontier] = True
    picked, picked_added = [], []
    for _ in range(rings):
        new = _incident(incidence, frontier[frontier < n_original])
        new = _distinct(new[~face_in[new]], face_stamp)
        face_in[new] = True
        picked.append(new)
        grown = faces[new].ravel()
        if len(added):
            new_added = np.flatnonzero(in_region[added].any(axis=1))
            picked_added.append(new_added)
            grown = np.concatenate([grown, added[new_added].ravel()])
        frontier = _distinct(grown[~in_region[grown]], vertex_stamp)
        if len(frontier) == 0:
            break
        in_region[frontier] = True
    empty = np.empty(0, dtype=np.int64)
    return (np.unique(np.concatenate(picked)).astype(np.int64, copy=False) if picked
            else empty,
            np.unique(np.concatenate(picked_added)) if picked_added else empty)


@pytest.mark.parametrize("k", [0, 1, 2, 5, 40])
def test_the_k_ring_grown_through_faces_is_the_one_through_edges(k):
    v, f = sphere(3)
    f = f[~k_ring(f, [0], 1, len(v))[f].any(axis=1)]  # a hole: a ring stops at it
    seeds = [5, 77]
    assert np.array_equal(k_ring(f, seeds, k, len(v)),
                          _k_ring_by_adjacency(f, seeds, k, len(v)))


def test_the_cut_finds_the_earlier_fills_as_a_search_of_every_ring_does():
    v, f = sphere(4)
    centres = [0, 100, 101, 500]  # two holes side by side, two apart
    keep = ~np.any([k_ring(f, [c], 1, len(v))[f].any(axis=1) for c in centres], axis=0)
    mesh = FilledMesh(v, f[keep])
    # an earlier hole's "fill": new vertices and faces over old and new ids
    ids = np.unique(f[keep][:40])
    new = Fill(v[ids[:3]] + 0.01, np.array([[0, 1, 2], [1, len(ids), 2],
                                            [len(ids), len(ids) + 1, len(ids) + 2]]), "fair")
    mesh.append(ids, new)
    added = np.concatenate(mesh.face_blocks)
    for seeds in ([0, 1, 2], [int(ids[5])], [len(v)], [700, 701]):
        for rings in (1, 3, 8):
            got = neighbourhood_faces(mesh.faces, mesh.vertex_faces, added,
                                      np.array(seeds), rings)
            want = _scanning_every_ring(mesh.faces, mesh.vertex_faces, added,
                                        np.array(seeds), rings)
            for a, b in zip(got, want, strict=True):
                assert a.dtype == b.dtype and np.array_equal(a, b)


def test_the_plane_tests_give_the_same_answers_on_a_shared_ring():
    v, f = sphere(4)
    v = v * (1 + 0.05 * np.sin(6 * v[:, 0]))[:, None]
    cut = cut_geodesic_disk(v, f, 7, 0.25)
    ring = _ring(cut.vertices, cut.faces, cut.loop, 2)
    for test in (known_plane, known_two_planes):
        shared = test(cut.vertices, cut.faces, cut.loop, ring=ring)
        own = test(cut.vertices, cut.faces, cut.loop)
        assert _same(shared, own), test.__name__


def _same(a, b) -> bool:
    """Whether two results (dataclasses of arrays and numbers, or None) are the same bits."""
    if dataclasses.is_dataclass(a) and dataclasses.is_dataclass(b):
        return type(a) is type(b) and all(
            _same(getattr(a, x.name), getattr(b, x.name)) for x in dataclasses.fields(a))
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()
    return a == b or (a != a and b != b)  # NaN equals NaN here


def test_vertex_normals_over_the_faces_at_a_ring_are_the_same_bits():
    v, f = sphere(4)
    v = v * (1 + 0.05 * np.sin(6 * v[:, 0]) * np.cos(5 * v[:, 1]))[:, None]
    near = k_ring(f, [3, 9], 2, len(v))
    at = f[near[f].any(axis=1)]
    assert vertex_normals(v, at)[near].tobytes() == vertex_normals(v, f)[near].tobytes()


def _own_face_by_keys(vertices, faces, loop, rings=2, angle=30.0):
    """:func:`own_face` as it was before: the sharp edges told apart by their keys."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    from surfinpaint.fill.creases import sharp_edges
    from surfinpaint.geometry.edges import edge_keys
    from surfinpaint.geometry.mesh import edge_faces

    near = k_ring(faces, loop, rings, len(vertices))
    inside = faces[near[faces].all(axis=1)]
    edges, owners, count = edge_faces(inside)
    sharp = sharp_edges(vertices, inside, angle)[0]
    n = len(vertices)
    keys = edge_keys(edges[:, 0], edges[:, 1], n)
    crossing = (count == 2) & ~np.isin(keys, edge_keys(sharp[:, 0], sharp[:, 1], n))
    step = sp.coo_matrix((np.ones(int(crossing.sum())), tuple(owners[crossing].T)),
                         shape=(len(inside), len(inside))).tocsr()
    step = step + step.T
    reached = np.unique(owners[np.isin(keys, edge_keys(loop, np.roll(loop, -1), n)), 0])
    labels = connected_components(step, directed=False)[1]
    face = np.zeros(n, dtype=bool)
    face[inside[np.isin(labels, labels[reached])]] = True
    return face


@pytest.mark.parametrize("size", [6, 9])
def test_the_own_face_from_rows_of_the_edge_table_is_the_one_from_keys(size):
    from surfinpaint.data import cube
    from surfinpaint.fill.conformal.method import own_face
    from surfinpaint.fill.creases import sharp_edge_rows, sharp_edges
    from surfinpaint.geometry.mesh import boundary_loops, edge_faces

    v, f = cube(size)
    # a hole next to the top face's edge: its rings reach over the edge
    top = np.flatnonzero(np.isclose(v[:, 2], 1.0) & np.isclose(v[:, 0], 1 - 2 / size)
                         & np.isclose(v[:, 1], 0.5 if size % 2 == 0 else (size // 2) / size))
    f = f[~k_ring(f, top, 0, len(v))[f].any(axis=1)]
    loop = boundary_loops(f)[0]
    face = {}
    for angle in (30.0, 95.0):
        face[angle] = own_face(v, f, loop, angle=angle)
        assert np.array_equal(face[angle], _own_face_by_keys(v, f, loop, angle=angle))
    # the top face only, stopped at the cube's edge; past it where that edge is not sharp
    assert np.isclose(v[face[30.0], 2], 1.0).all()
    assert not np.isclose(v[face[95.0], 2], 1.0).all()
    table = edge_faces(f)
    rows, turn = sharp_edge_rows(v, f, table)
    edges, turns = sharp_edges(v, f)
    assert np.array_equal(table[0][rows], edges) and np.array_equal(turn, turns)
