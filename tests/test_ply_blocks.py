"""The binary PLY writer's blocks of rows: the bytes of one record array per element, with no
buffer the size of an element."""

import tracemalloc

import numpy as np
import pytest

from surfinpaint.io import MeshWarning, ply
from surfinpaint.io.formats import read_mesh_data, write_mesh_data
from surfinpaint.io.meshdata import MeshData


def _mesh_with_attributes(n_vertices: int) -> MeshData:
    rng = np.random.default_rng(5)
    vertices = rng.normal(size=(n_vertices, 3))
    ring = np.arange(2 * n_vertices)
    faces = np.column_stack([ring % n_vertices, (ring + 1) % n_vertices,
                             (ring + 2) % n_vertices])
    return MeshData(
        vertices, faces,
        {"quality": rng.normal(size=n_vertices).astype(np.float32),
         "red": rng.integers(0, 256, n_vertices).astype(np.uint8)},
        {"weight": rng.normal(size=len(faces))},
        {"texcoord": rng.random((len(faces), 3, 2)).astype(np.float32)})


def _one_record_array(mesh: MeshData) -> bytes:
    """The data section as whole-element record arrays (the writer before blocks), written
    out field by field from the mesh: what the blocks must reproduce."""
    n, m = len(mesh.vertices), len(mesh.faces)
    vertex = np.empty(n, dtype=[("x", "<f8"), ("y", "<f8"), ("z", "<f8"),
                                ("quality", "<f4"), ("red", "u1")])
    for k, axis in enumerate("xyz"):
        vertex[axis] = mesh.vertices[:, k]
    vertex["quality"], vertex["red"] = mesh.attributes["quality"], mesh.attributes["red"]
    face = np.empty(m, dtype=[("n", "u1"), ("ids", "<i4", (3,)), ("weight", "<f8"),
                              ("tn", "u1"), ("texcoord", "<f4", (6,))])
    face["n"], face["ids"], face["weight"] = 3, mesh.faces, mesh.face_attributes["weight"]
    face["tn"], face["texcoord"] = 6, mesh.corner_attributes["texcoord"].reshape(m, 6)
    return vertex.tobytes() + face.tobytes()


@pytest.mark.parametrize("block_rows", [1, 7, 64, 10_000])
def test_blocks_write_the_bytes_of_one_record_array(tmp_path, monkeypatch, block_rows):
    # 40 vertices and 80 faces: blocks of 7 rows end mid-element (a short last block), one
    # row per block and one block for everything are the extremes
    monkeypatch.setattr(ply, "BINARY_BLOCK_ROWS", block_rows)
    mesh = _mesh_with_attributes(40)
    path = tmp_path / "m.ply"
    write_mesh_data(path, mesh)
    data = path.read_bytes()
    body = data[data.index(b"end_header\n") + len(b"end_header\n"):]
    assert body == _one_record_array(mesh)
    with pytest.warns(MeshWarning, match="kept per face corner"):  # random corners: seams
        back = read_mesh_data(path)
    np.testing.assert_array_equal(back.vertices, mesh.vertices)
    np.testing.assert_array_equal(back.faces, mesh.faces)
    np.testing.assert_array_equal(back.corner_attributes["texcoord"],
                                  mesh.corner_attributes["texcoord"])


def test_no_buffer_the_size_of_an_element(tmp_path):
    # 200k vertices (4.8 MB of x y z) and 400k faces (5.2 MB of rows): one record array per
    # element, and the faces' int32 copy, peaked at 15 MB; the blocks at under 2 MB
    n = 200_000
    ring = np.arange(2 * n)
    mesh = MeshData(np.random.default_rng(0).normal(size=(n, 3)),
                    np.column_stack([ring % n, (ring + 1) % n, (ring + 2) % n]))
    tracemalloc.start()
    try:
        write_mesh_data(tmp_path / "big.ply", mesh)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 4_000_000
    assert (tmp_path / "big.ply").stat().st_size > 10_000_000
