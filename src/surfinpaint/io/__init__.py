"""Mesh files: one reader and writer per format family, attributes, and the one atomic writer.

Knows nothing of geometry algorithms beyond checking what it reads.
"""

from surfinpaint.io.formats import (
    SUPPORTED_FORMATS,
    DataNotReturnedWarning,
    MeshWarning,
    read_mesh,
    read_mesh_data,
    write_mesh,
    write_mesh_data,
)
from surfinpaint.io.meshdata import MeshData

__all__ = ["SUPPORTED_FORMATS", "DataNotReturnedWarning", "MeshData", "MeshWarning", "read_mesh",
           "read_mesh_data", "write_mesh", "write_mesh_data"]
