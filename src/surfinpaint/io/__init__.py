"""Mesh files: one reader and writer per format family, and the one atomic writer.

Knows nothing of geometry algorithms beyond checking what it reads.
"""

from surfinpaint.io.formats import SUPPORTED_FORMATS, MeshWarning, read_mesh, write_mesh

__all__ = ["SUPPORTED_FORMATS", "MeshWarning", "read_mesh", "write_mesh"]
