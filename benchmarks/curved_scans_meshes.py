"""The curved scans set's meshes (session 40): range scans of curved tuning-side shapes.

Holdout set 16's first run had four holes above 1.5x the better faired fill on simulated
scans of curved shapes, where the self-check wrote the bilaplacian fill (fair2) while the
trilaplacian (fair3) and lambda-H fills were about half as far. The tuning side barely had
that case (5 of session 33's 201 near-border scan holes, none of the tuning half's or the CAD
parts' 49 scan holes), so no rule for it could be chosen there. This set is for choosing
rules: rules may be chosen on it (``benchmarks/curved_scans_manifest.json``, split
``curved_scans``; docs/validation.md "Session 40 (helper): the curved scans set").

Fourteen portable simulated scans (``validation_meshes.simulated_scan(..., portable=True)``,
seeds 3500-3513) of tuning-side curved sources only, seen from views no earlier scan of them
used: five meshes of the smooth tuning set (a figure-eight knot tube, a ball with a handle,
a piglet, an octopus, a ram's horn), four of ``animals.py``'s animals (two as remeshed, one
Loop-subdivided, one decimated), and five of the tuning half's curved meshes (bunny, blob_a,
bone, snowman, torus). Their holes are planned by ``holes_manifest.plan_holes`` as every
set's scans are (holes 1, 3 and 5 next to the border), from seed 3600 on. The snowman is
made with the C library's ``exp`` and ``log`` (:func:`c_library`): session 40's machine had no
AVX-512, whose numpy loops round them otherwise (docs/validation.md "Session 43 (helper)").
:mod:`validation_meshes` imports :data:`CURVED_SCAN_SOURCES` from here at its end (import it
first, not this module).
"""

from __future__ import annotations

import math

import numpy as np
import validation_meshes as vm
from validation_meshes import BenchMesh, Source

from surfinpaint import data

# the faces of the decimated animal's coarse mesh (animals.animal(decimated=...)): a
# modeller's low-poly body whose facets the scan sees
DECIMATED_FACES = 3000


def _tuning_source(mesh_id: str):
    """The generator of the tuning-side mesh ``mesh_id``, looked up when the scan is made
    (the smooth tuning set is added to ``SOURCES`` after this module is imported)."""
    def make() -> BenchMesh:
        return vm.SOURCES[mesh_id].make()
    return make


def c_library(function):
    """``function`` (``math.exp``, ``math.log``) elementwise over a float array: the C
    library's, as numpy computes it without its AVX-512 loops (session 43: numpy's AVX-512
    ``exp`` and ``log`` round other last bits, which moved cscan_snowman's source)."""
    elementwise = np.frompyfunc(function, 1, 1)

    def apply(values) -> np.ndarray:
        return elementwise(np.asarray(values, float)).astype(float)

    return apply


# the tuning half's sources whose generator takes its blend's exp and log (its
# validation_meshes.SOURCES entry is data.snowman(edge_length=0.04) with numpy's)
_BLENDED_TUNING_SOURCES = {
    "snowman": lambda exp, log: data.snowman(edge_length=0.04, exp=exp, log=log)}


def _c_library_source(mesh_id: str):
    """The tuning half's ``mesh_id`` with its blend's ``exp`` and ``log`` the C library's
    (:func:`c_library`): for the snowman, the bytes session 40 scanned (that machine's numpy
    had no AVX-512 loops), on every CPU. The tuning half's own snowman keeps numpy's: its
    manifest's centres are vertices of the AVX-512 one (docs/validation.md, "Session 43
    (helper): cscan_snowman's bytes")."""
    def make() -> BenchMesh:
        return vm._mesh(*_BLENDED_TUNING_SOURCES[mesh_id](c_library(math.exp),
                                                          c_library(math.log)))
    return make


def _animal(seed: int, subdivided: int = 0, decimated: int | None = None):
    """``animals.animal(seed, ...)``, imported when the mesh is made: animals.py imports the
    benchmark's harness, which imports validation_meshes (a cycle at import time)."""
    def make() -> BenchMesh:
        import animals

        return animals.animal(seed, subdivided=subdivided, decimated=decimated)
    return make


def _scan_of(source, view, seed: int):
    """A portable simulated scan of ``source()`` from ``view`` with noise seed ``seed``."""
    return vm._scan(source, view, seed, portable=True)


# Session 40's tuning-side set: every source is a tuning-side mesh (the smooth tuning set,
# animals.py's animals, the tuning half), none a holdout's; the views are new (no earlier
# scan of these sources looks from them) and the noise seeds (3500-3513) unused elsewhere.
CURVED_SCAN_SOURCES: dict[str, Source] = {
    "cscan_knot8": Source("range_scan", "simulated scan of the figure-eight knot tube of the "
                          "smooth tuning set (portable scanner)",
                          _scan_of(_tuning_source("knot8"), (0.2, 0.4, 1.0), 3500)),
    "cscan_handle_ball": Source("range_scan", "simulated scan of the ball with a handle of the "
                                "smooth tuning set (portable scanner)",
                                _scan_of(_tuning_source("handle_ball"), (0.8, -0.5, 0.4),
                                               3501)),
    "cscan_piglet": Source("range_scan", "simulated scan of the piglet of the smooth tuning set "
                           "(portable scanner)",
                           _scan_of(_tuning_source("piglet"), (0.3, -1.0, 0.5), 3502)),
    "cscan_octopus": Source("range_scan", "simulated scan of the octopus of the smooth tuning "
                            "set (portable scanner)",
                            _scan_of(_tuning_source("octopus"), (0.2, -0.3, -1.0), 3503)),
    "cscan_horn": Source("range_scan", "simulated scan of the ram's horn of the smooth tuning "
                         "set (portable scanner)",
                         _scan_of(_tuning_source("horn"), (0.6, 0.6, 0.6), 3504)),
    "cscan_animal2": Source("range_scan", "simulated scan of animals.py's animal 2 (portable "
                            "scanner)", _scan_of(_animal(2), (0.4, -1.0, 0.3), 3505)),
    "cscan_animal7": Source("range_scan", "simulated scan of animals.py's animal 7 (portable "
                            "scanner)", _scan_of(_animal(7), (-0.6, 0.8, 0.5), 3506)),
    "cscan_animal4s1": Source("range_scan", "simulated scan of animals.py's animal 4, remeshed "
                              "coarser and Loop-subdivided once (portable scanner)",
                              _scan_of(_animal(4, subdivided=1), (0.5, 0.9, 0.4), 3507)),
    "cscan_animal9d": Source("range_scan", "simulated scan of animals.py's animal 9, decimated "
                             f"to {DECIMATED_FACES} faces (portable scanner)",
                             _scan_of(_animal(9, decimated=DECIMATED_FACES),
                                            (0.2, -0.9, 0.6), 3508)),
    "cscan_bunny": Source("range_scan", "simulated scan of PyMeshLab bunny.obj from above and "
                          "behind (portable scanner)",
                          _scan_of(_tuning_source("bunny"), (-0.5, 0.9, -0.4), 3509)),
    "cscan_blob_a": Source("range_scan", "simulated scan of blob_a (portable scanner)",
                           _scan_of(_tuning_source("blob_a"), (0.5, 0.5, -0.7), 3510)),
    "cscan_bone": Source("range_scan", "simulated scan of the subdivided PyMeshLab bone "
                         "(portable scanner)",
                         _scan_of(_tuning_source("bone"), (-0.6, 0.4, 0.7), 3511)),
    "cscan_snowman": Source("range_scan", "simulated scan of surfinpaint.data.snowman(0.04) "
                            "(portable scanner)",
                            _scan_of(_c_library_source("snowman"), (0.7, 0.6, 0.4),
                                   3512)),
    "cscan_torus": Source("range_scan", "simulated scan of surfinpaint.data.torus(160, 64), "
                          "obliquely (portable scanner)",
                          _scan_of(_tuning_source("torus"), (0.3, -0.4, 0.6), 3513)),
}
