"""Brain surfaces: GIFTI (``.gii``, ``.gii.gz``) and FreeSurfer geometry files, via nibabel."""

from __future__ import annotations

import gzip
import struct
import warnings
from pathlib import Path

import numpy as np

from surfinpaint.errors import MeshError
from surfinpaint.io.base import describe

FREESURFER_MAGIC = b"\xff\xff\xfe"


def read_gifti(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    import nibabel as nib

    if data[:2] == b"\x1f\x8b":
        try:
            data = gzip.decompress(data)
        except (OSError, EOFError) as exc:
            raise MeshError(f"corrupt gzip data ({describe(exc)})") from None
    image = nib.gifti.GiftiImage.from_bytes(data)
    points = image.get_arrays_from_intent("NIFTI_INTENT_POINTSET")
    triangles = image.get_arrays_from_intent("NIFTI_INTENT_TRIANGLE")
    if not points:
        raise MeshError("GIFTI file has no NIFTI_INTENT_POINTSET array (not a surface)")
    if not triangles:
        raise MeshError("GIFTI file has no NIFTI_INTENT_TRIANGLE array (not a surface)")
    vertices = np.asarray(points[0].data, dtype=np.float64)
    faces = np.asarray(triangles[0].data)
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise MeshError(f"GIFTI pointset has shape {vertices.shape}, expected (n, 3)")
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise MeshError(f"GIFTI triangle array has shape {faces.shape}, expected (f, 3)")
    return vertices, np.full(len(faces), 3, np.int64), faces.astype(np.int64).ravel()


def read_freesurfer(data: bytes, path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    from nibabel.freesurfer import read_geometry

    if data[:3] not in (FREESURFER_MAGIC, b"\xff\xff\xff"):
        raise MeshError("not a FreeSurfer surface (magic bytes are not FF FF FE)")
    if data[:3] == FREESURFER_MAGIC:
        # the two creation lines end in "\n\n"; the counts follow as big-endian int32
        end = data.find(b"\n\n", 3, 3 + 4096)
        if end < 0 or end + 10 > len(data):
            raise MeshError("FreeSurfer surface is truncated (no header)")
        nv, nf = struct.unpack_from(">ii", data, end + 2)
        need = end + 10 + 12 * nv + 12 * nf
        if nv < 0 or nf < 0 or len(data) < need:
            raise MeshError(f"FreeSurfer surface is truncated (header announces {nv} vertices "
                            f"and {nf} faces = {need} bytes, the file has {len(data)})")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # nibabel warns about missing volume info footers
        vertices, faces = read_geometry(str(path))
    return (np.asarray(vertices, dtype=np.float64), np.full(len(faces), 3, np.int64),
            np.asarray(faces, dtype=np.int64).ravel())



def gifti_bytes(v: np.ndarray, f: np.ndarray) -> bytes:
    import nibabel as nib

    points = nib.gifti.GiftiDataArray(v.astype(np.float32), intent="NIFTI_INTENT_POINTSET",
                                      datatype="NIFTI_TYPE_FLOAT32")
    triangles = nib.gifti.GiftiDataArray(f.astype(np.int32), intent="NIFTI_INTENT_TRIANGLE",
                                         datatype="NIFTI_TYPE_INT32")
    return nib.gifti.GiftiImage(darrays=[points, triangles]).to_bytes()


def write_gifti(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    fh.write(gifti_bytes(v, f))


def write_gifti_gz(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    fh.write(gzip.compress(gifti_bytes(v, f)))


def write_freesurfer(fh, tmp: str, v: np.ndarray, f: np.ndarray, ascii: bool) -> None:
    from nibabel.freesurfer import write_geometry

    # nibabel writes by file name; it goes to the same temporary file
    write_geometry(tmp, v.astype(np.float32), f.astype(np.int32))

