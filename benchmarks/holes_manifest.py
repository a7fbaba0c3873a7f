"""The validation benchmark's hole manifest: which mesh is in which half, and every hole.

``benchmarks/holes_manifest.json`` is checked in and is the benchmark's definition; this
module wrote it (``python benchmarks/holes_manifest.py --write``) and reads it. The split is
by MESH, fixed in :data:`SPLIT` below, balanced by kind: every mesh the project had used
before this benchmark (the default accuracy set's bunny, face scan, pial, white, sphere,
torus, cube, snowman, tooth) is in the tuning half, so the validation half holds meshes no
rule was chosen on. Meshes derived from one source stay in one half (cow and its scan, the
bracket and its scan, the lblock and its scan).

Holes: 7 per mesh, geodesic radii of 3, 4, 5, 6, 7, 8 and 10 mean edge lengths, centres
spread by farthest-point choice among seeded random candidates; on open meshes (range
scans) holes 1, 3 and 5 lie 1-2.5 edge lengths from the border; on CAD parts holes 0, 2, 4
and 6 are centred on a sharp edge or corner. A candidate whose cut fails (reaches the
border, not a disk) is skipped. Centres are stored as points (snapped to the nearest vertex
when cutting) with the radius in mesh units, so the holes do not depend on this code.

A third set, the holdout (``benchmarks/holdout_manifest.json``, ``--write --holdout``): 11
fresh meshes (``validation_meshes.HOLDOUT_SOURCES``), holes planned the same way, made
after session 25's choices and run once. Reported after the validation half.

A fourth set, the second holdout (``benchmarks/holdout2_manifest.json``, ``--write
--holdout2``): 12 fresh meshes (``validation_meshes.HOLDOUT2_SOURCES``), holes planned the
same way (seeds from 200), made after session 26's defaults and run once.

A fifth set, the third holdout (``benchmarks/holdout3_manifest.json``, ``--write
--holdout3``): 12 fresh meshes (``validation_meshes.HOLDOUT3_SOURCES``), holes planned the
same way (seeds from 300), made in session 28 after the second holdout had been run twice,
and run once.

A tuning-side set of machined parts (``benchmarks/cad_tuning_manifest.json``, ``--write
--cad-tuning``): 12 manifold3d parts and scans of them (``validation_meshes.
CAD_TUNING_SOURCES``), holes planned the same way (seeds from 400), made in session 29 to
choose rules for holes next to bores, bosses and edges on. Rules may be chosen on it.

A sixth set, the fourth holdout (``benchmarks/holdout4_manifest.json``, ``--write
--holdout4``): 12 fresh meshes (``validation_meshes.HOLDOUT4_SOURCES``), holes planned the
same way (seeds from 500), made in session 29 and committed before any fill was run on them;
to be run once.

A seventh set, the fifth holdout (``benchmarks/holdout5_manifest.json``, ``--write
--holdout5``): 12 fresh meshes (``validation_meshes.HOLDOUT5_SOURCES``), holes planned the
same way (seeds from 600), made in session 29 after the fourth holdout had been run once and
committed before any fill was run on them; to be run once by a later session after its
changes.

An eighth set, the sixth holdout (``benchmarks/holdout6_manifest.json``, ``--write
--holdout6``): 12 fresh meshes (``validation_meshes.HOLDOUT6_SOURCES``), holes planned the
same way (seeds from 700), made in session 30 after the fifth holdout had been run once and
committed before any fill was run on them; to be run once by a later session after its
changes.

A ninth set, the seventh holdout (``benchmarks/holdout7_manifest.json``, ``--write
--holdout7``): 12 fresh meshes (``validation_meshes.HOLDOUT7_SOURCES``), holes planned the
same way (seeds from 800), made in session 31 after the sixth holdout had been committed and
committed before any fill was run on them; to be run once by a later session after its
changes.

A tenth set, the eighth holdout (``benchmarks/holdout8_manifest.json``, ``--write
--holdout8``): 12 fresh meshes (``validation_meshes.HOLDOUT8_SOURCES``, made in
``holdout8_meshes.py``), holes planned the same way (seeds from 900), made in session 32 after
the seventh holdout had been run once and committed before any fill was run on them; to be
run once by a later session after its changes.

An eleventh set, the ninth holdout (``benchmarks/holdout9_manifest.json``, ``--write
--holdout9``): 12 fresh meshes (``validation_meshes.HOLDOUT9_SOURCES``, made in
``holdout9_meshes.py``), holes planned the same way (seeds from 1000), made in session 33
after the eighth holdout had been made and committed before any fill was run on them; to be
run once by a later session after its changes.

A twelfth set, the tenth holdout (``benchmarks/holdout10_manifest.json``, ``--write
--holdout10``): 12 fresh meshes (``validation_meshes.HOLDOUT10_SOURCES``, made in
``holdout10_meshes.py``; its four scans made with the portable scanner), holes planned the
same way (seeds from 1100), made in session 34 after the ninth holdout had been made and
committed before any fill was run on them; to be run once by a later session after its
changes.

A thirteenth set, the eleventh holdout (``benchmarks/holdout11_manifest.json``, ``--write
--holdout11``): 12 fresh meshes (``validation_meshes.HOLDOUT11_SOURCES``, made in
``holdout11_meshes.py``; all six kinds, a synthetic folded hemisphere for the brain kind;
its four scans made with the portable scanner), holes planned the same way (seeds from
1200), made in session 35 after the tenth holdout had been made and committed before any
fill was run on them; to be run once by a later session after its changes.

A fourteenth set, the twelfth holdout (``benchmarks/holdout12_manifest.json``, ``--write
--holdout12``): 12 fresh meshes (``validation_meshes.HOLDOUT12_SOURCES``, made in
``holdout12_meshes.py``; all six kinds, a synthetic cerebellum for the brain kind; its four
scans made with the portable scanner), holes planned the same way (seeds from 1300), made in
session 35 after the eleventh holdout had been made and committed before any fill was run on
them; to be run once by a later session after its changes.

A fifteenth set, the thirteenth holdout (``benchmarks/holdout13_manifest.json``, ``--write
--holdout13``): 12 fresh meshes (``validation_meshes.HOLDOUT13_SOURCES``, made in
``holdout13_meshes.py``; all six kinds, a synthetic forebrain for the brain kind; its four
scans made with the portable scanner), holes planned the same way (seeds from 1400), made in
session 36 after the twelfth holdout had been made and committed before any fill was run on
them; to be run once by a later session after its changes.

A sixteenth set, the fourteenth holdout (``benchmarks/holdout14_manifest.json``, ``--write
--holdout14``): 12 fresh meshes (``validation_meshes.HOLDOUT14_SOURCES``, made in
``holdout14_meshes.py``; all six kinds, a synthetic cortex with polygonal gyri for the brain
kind; its four scans made with the portable scanner), holes planned the same way (seeds
from 1500), made in session 37 after the thirteenth holdout had been made and committed
before any fill was run on them; to be run once by a later session after its changes.

A tuning-side set of smooth tubes and organic bodies (``benchmarks/smooth_tuning_manifest.json``,
``--write --smooth-tuning``): 8 meshes (``validation_meshes.SMOOTH_TUNING_SOURCES``, made in
``smooth_tuning_meshes.py``), holes planned the same way (seeds from 3800), made in session 38
to study the self-check's mistakes on smooth tubes and organic shapes. Rules may be chosen on
it.

A seventeenth set, the fifteenth holdout (``benchmarks/holdout15_manifest.json``, ``--write
--holdout15``): 12 fresh meshes (``validation_meshes.HOLDOUT15_SOURCES``, made in
``holdout15_meshes.py``; all six kinds, a synthetic cortex with branched sulci for the brain
kind; its four scans made with the portable scanner), holes planned the same way (seeds
from 1600), made in session 38 after the fourteenth holdout had been made and committed
before any fill was run on them; to be run once by a later session after its changes.

An eighteenth set, the sixteenth holdout (``benchmarks/holdout16_manifest.json``, ``--write
--holdout16``): 12 fresh meshes (``validation_meshes.HOLDOUT16_SOURCES``, made in
``holdout16_meshes.py``; all six kinds, a synthetic cortex with arcuate sulci for the brain
kind; its four scans made with the portable scanner), holes planned the same way (seeds
from 1700), made in session 39 after the fifteenth holdout had been made and committed
before any fill was run on them; to be run once by a later session after its changes.

A nineteenth set, the seventeenth holdout (``benchmarks/holdout17_manifest.json``, ``--write
--holdout17``): 12 fresh meshes (``validation_meshes.HOLDOUT17_SOURCES``, made in
``holdout17_meshes.py``; all six kinds, a synthetic cortex with radiating sulci for the
brain kind; its four scans made with the portable scanner), holes planned the same way
(seeds from 1800), made in session 40 after the sixteenth holdout had been made and
committed before any fill was run on them; to be run once by a later session after its
changes.

A twentieth set, the eighteenth holdout (``benchmarks/holdout18_manifest.json``, ``--write
--holdout18``): 12 fresh meshes (``validation_meshes.HOLDOUT18_SOURCES``, made in
``holdout18_meshes.py``; all six kinds, a synthetic cortex with pinnate sulci for the brain
kind; its four scans made with the portable scanner), holes planned the same way (seeds
from 1900), made in session 41 after the seventeenth holdout had been made and committed
before any fill was run on them; to be run once by a later session after its changes.

A twenty-first set, the nineteenth holdout (``benchmarks/holdout19_manifest.json``,
``--write --holdout19``): 12 fresh meshes (``validation_meshes.HOLDOUT19_SOURCES``, made in
``holdout19_meshes.py``; all six kinds, a synthetic cortex with spiral sulci for the brain
kind; its four scans made with the portable scanner), holes planned the same way (seeds
from 2000), made in session 42 after the eighteenth holdout had been run once and committed
before any fill was run on them; to be run once by a later session after its changes.

A twenty-second set, the twentieth holdout (``benchmarks/holdout20_manifest.json``,
``--write --holdout20``): 12 fresh meshes (``validation_meshes.HOLDOUT20_SOURCES``, made in
``holdout20_meshes.py``; all six kinds, a synthetic cortex with meandering sulci for the
brain kind; its four scans made with the portable scanner), holes planned the same way
(seeds from 2100), made in session 43 after the nineteenth holdout had been run once and
committed before any fill was run on them; to be run once by a later session after its
changes.

A twenty-third set, the twenty-first holdout (``benchmarks/holdout21_manifest.json``,
``--write --holdout21``): 12 fresh meshes (``validation_meshes.HOLDOUT21_SOURCES``, made in
``holdout21_meshes.py``; all six kinds, a synthetic cortex with en echelon sulci for the
brain kind; its four scans made with the portable scanner), holes planned the same way
(seeds from 2200), made in session 44 after the twentieth holdout had been made and
committed before any fill was run on them; to be run once by a later session after its
changes.

A twenty-fourth set, the twenty-second holdout (``benchmarks/holdout22_manifest.json``,
``--write --holdout22``): 12 fresh meshes (``validation_meshes.HOLDOUT22_SOURCES``, made in
``holdout22_meshes.py``; all six kinds, a synthetic cortex with lattice sulci for the brain
kind; its four scans made with the portable scanner), holes planned the same way (seeds
from 2300), made in session 45 after the twenty-first holdout had been made and committed
before any fill was run on them; to be run once by a later session after its changes.

A twenty-fifth set, the twenty-third holdout (``benchmarks/holdout23_manifest.json``,
``--write --holdout23``): 12 fresh meshes (``validation_meshes.HOLDOUT23_SOURCES``, made in
``holdout23_meshes.py``; all six kinds, a synthetic cortex with ring sulci for the brain
kind; its four scans made with the portable scanner), holes planned the same way (seeds
from 2400), made in session 46 after the twenty-second holdout had been made and committed
before any fill was run on them; to be run once by a later session after its changes.

A twenty-sixth set, the twenty-fourth holdout (``benchmarks/holdout24_manifest.json``,
``--write --holdout24``): 12 fresh meshes (``validation_meshes.HOLDOUT24_SOURCES``, made in
``holdout24_meshes.py``; all six kinds, a synthetic cortex with Truchet sulci for the brain
kind; its four scans made with the portable scanner), holes planned the same way (seeds
from 2500), made in session 47 after the twenty-third holdout had been made and committed
before any fill was run on them; to be run once by a later session after its changes.

A twenty-seventh set, the twenty-fifth holdout (``benchmarks/holdout25_manifest.json``,
``--write --holdout25``): 12 fresh meshes (``validation_meshes.HOLDOUT25_SOURCES``, made in
``holdout25_meshes.py``; all six kinds, a synthetic cortex with a Hilbert sulcus for the
brain kind; its four scans made with the portable scanner), holes planned the same way
(seeds from 2600), made in session 48 after the twenty-fourth holdout had been made and
committed before any fill was run on them; to be run once by a later session after its
changes.

A twenty-eighth set, the twenty-sixth holdout (``benchmarks/holdout26_manifest.json``,
``--write --holdout26``): 12 fresh meshes (``validation_meshes.HOLDOUT26_SOURCES``, made in
``holdout26_meshes.py``; all six kinds, a synthetic cortex with triradiate sulci for the
brain kind; its four scans made with the portable scanner), holes planned the same way
(seeds from 2700), made in session 49 after the twenty-fifth holdout had been made and
committed before any fill was run on them; to be run once by a later session after its
changes.

A twenty-ninth set, the twenty-seventh holdout (``benchmarks/holdout27_manifest.json``,
``--write --holdout27``): 12 fresh meshes (``validation_meshes.HOLDOUT27_SOURCES``, made in
``holdout27_meshes.py``; all six kinds, a synthetic cortex with rose-shaped sulci for the
brain kind; its four scans made with the portable scanner), holes planned the same way
(seeds from 2800), made in session 50 after the twenty-sixth holdout had been made and
committed before any fill was run on them; to be run once by a later session after its
changes.

A thirtieth set, the twenty-eighth holdout (``benchmarks/holdout28_manifest.json``,
``--write --holdout28``): 12 fresh meshes (``validation_meshes.HOLDOUT28_SOURCES``, made in
``holdout28_meshes.py``; all six kinds, a synthetic cortex with chevron sulci for the brain
kind; its four scans made with the portable scanner), holes planned the same way (seeds
from 2900), made in session 51 after the twenty-seventh holdout had been made and committed
before any fill was run on them; to be run once by a later session after its changes.

A thirty-first set, the twenty-ninth holdout (``benchmarks/holdout29_manifest.json``,
``--write --holdout29``): 12 fresh meshes (``validation_meshes.HOLDOUT29_SOURCES``, made in
``holdout29_meshes.py``; all six kinds, a synthetic cortex with H-shaped sulci for the brain
kind; its four scans made with the portable scanner), holes planned the same way (seeds
from 3000), made in session 52 after the twenty-eighth holdout had been made and committed
before any fill was run on them; to be run once by a later session after its changes.

A tuning-side set of range scans of curved shapes (``benchmarks/curved_scans_manifest.json``,
``--write --curved-scans``): 14 portable scans (``validation_meshes.CURVED_SCAN_SOURCES``,
made in ``curved_scans_meshes.py``) of the smooth tuning set's, animals.py's and the tuning
half's curved meshes, holes planned the same way (seeds from 3600), made in session 40 to study
the bilaplacian fill kept where the trilaplacian one is twice as close on scans. Rules may be
chosen on it.

A tuning-side set of thin smooth walls (``benchmarks/thin_shells_manifest.json``, ``--write
--thin-shells``): 6 closed shells and thickened sheets 2-6 edges thick with saddle-shaped
parts (``validation_meshes.THIN_SHELL_SOURCES``, made in ``thin_shells_meshes.py``), holes
planned the same way (seeds from 4100), made in session 41 to study the λ-H fill kept where
it loses on thin walls. Rules may be chosen on it.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import validation_meshes as vm  # noqa: E402

MANIFEST = Path(__file__).parent / "holes_manifest.json"
# a third set, fresh meshes run once after session 25's choices (validation_meshes.
# HOLDOUT_SOURCES): its own file, so the two halves' manifest stays as it was
HOLDOUT_MANIFEST = Path(__file__).parent / "holdout_manifest.json"
# a fourth set, fresh meshes run once after session 26's defaults (HOLDOUT2_SOURCES)
HOLDOUT2_MANIFEST = Path(__file__).parent / "holdout2_manifest.json"
# a fifth set, fresh meshes run once in session 28 (HOLDOUT3_SOURCES)
HOLDOUT3_MANIFEST = Path(__file__).parent / "holdout3_manifest.json"
# tuning-side machined parts of session 29 (CAD_TUNING_SOURCES): rules may be chosen on them
CAD_TUNING_MANIFEST = Path(__file__).parent / "cad_tuning_manifest.json"
# a sixth set, fresh meshes of session 29 (HOLDOUT4_SOURCES), committed before any fill
HOLDOUT4_MANIFEST = Path(__file__).parent / "holdout4_manifest.json"
# a seventh set, fresh meshes of session 29 (HOLDOUT5_SOURCES), committed before any fill
HOLDOUT5_MANIFEST = Path(__file__).parent / "holdout5_manifest.json"
# an eighth set, fresh meshes of session 30 (HOLDOUT6_SOURCES), committed before any fill
HOLDOUT6_MANIFEST = Path(__file__).parent / "holdout6_manifest.json"
# a ninth set, fresh meshes of session 31 (HOLDOUT7_SOURCES), committed before any fill
HOLDOUT7_MANIFEST = Path(__file__).parent / "holdout7_manifest.json"
# a tenth set, fresh meshes of session 32 (HOLDOUT8_SOURCES), committed before any fill
HOLDOUT8_MANIFEST = Path(__file__).parent / "holdout8_manifest.json"
# an eleventh set, fresh meshes of session 33 (HOLDOUT9_SOURCES), committed before any fill
HOLDOUT9_MANIFEST = Path(__file__).parent / "holdout9_manifest.json"
# a twelfth set, fresh meshes of session 34 (HOLDOUT10_SOURCES), committed before any fill
HOLDOUT10_MANIFEST = Path(__file__).parent / "holdout10_manifest.json"
# a thirteenth set, fresh meshes of session 35 (HOLDOUT11_SOURCES), committed before any fill
HOLDOUT11_MANIFEST = Path(__file__).parent / "holdout11_manifest.json"
# a fourteenth set, session 35's second (HOLDOUT12_SOURCES), committed before any fill
HOLDOUT12_MANIFEST = Path(__file__).parent / "holdout12_manifest.json"
# a fifteenth set, fresh meshes of session 36 (HOLDOUT13_SOURCES), committed before any fill
HOLDOUT13_MANIFEST = Path(__file__).parent / "holdout13_manifest.json"
# a sixteenth set, fresh meshes of session 37 (HOLDOUT14_SOURCES), committed before any fill
HOLDOUT14_MANIFEST = Path(__file__).parent / "holdout14_manifest.json"
# tuning-side smooth tubes and organic bodies of session 38 (SMOOTH_TUNING_SOURCES)
SMOOTH_TUNING_MANIFEST = Path(__file__).parent / "smooth_tuning_manifest.json"
# a seventeenth set, fresh meshes of session 38 (HOLDOUT15_SOURCES), committed before any fill
HOLDOUT15_MANIFEST = Path(__file__).parent / "holdout15_manifest.json"
# an eighteenth set, fresh meshes of session 39 (HOLDOUT16_SOURCES), committed before any fill
HOLDOUT16_MANIFEST = Path(__file__).parent / "holdout16_manifest.json"
# a nineteenth set, fresh meshes of session 40 (HOLDOUT17_SOURCES), committed before any fill
HOLDOUT17_MANIFEST = Path(__file__).parent / "holdout17_manifest.json"
# a twentieth set, fresh meshes of session 41 (HOLDOUT18_SOURCES), committed before any fill
HOLDOUT18_MANIFEST = Path(__file__).parent / "holdout18_manifest.json"
# a twenty-first set, fresh meshes of session 42 (HOLDOUT19_SOURCES), committed before any fill
HOLDOUT19_MANIFEST = Path(__file__).parent / "holdout19_manifest.json"
# a twenty-second set, fresh meshes of session 43 (HOLDOUT20_SOURCES), committed before any fill
HOLDOUT20_MANIFEST = Path(__file__).parent / "holdout20_manifest.json"
# a twenty-third set, fresh meshes of session 44 (HOLDOUT21_SOURCES), committed before any fill
HOLDOUT21_MANIFEST = Path(__file__).parent / "holdout21_manifest.json"
# a twenty-fourth set, fresh meshes of session 45 (HOLDOUT22_SOURCES), committed before any fill
HOLDOUT22_MANIFEST = Path(__file__).parent / "holdout22_manifest.json"
# a twenty-fifth set, fresh meshes of session 46 (HOLDOUT23_SOURCES), committed before any fill
HOLDOUT23_MANIFEST = Path(__file__).parent / "holdout23_manifest.json"
# a twenty-sixth set, fresh meshes of session 47 (HOLDOUT24_SOURCES), committed before any fill
HOLDOUT24_MANIFEST = Path(__file__).parent / "holdout24_manifest.json"
# a twenty-seventh set, fresh meshes of session 48 (HOLDOUT25_SOURCES), committed before any fill
HOLDOUT25_MANIFEST = Path(__file__).parent / "holdout25_manifest.json"
# a twenty-eighth set, fresh meshes of session 49 (HOLDOUT26_SOURCES), committed before any fill
HOLDOUT26_MANIFEST = Path(__file__).parent / "holdout26_manifest.json"
# a twenty-ninth set, fresh meshes of session 50 (HOLDOUT27_SOURCES), committed before any fill
HOLDOUT27_MANIFEST = Path(__file__).parent / "holdout27_manifest.json"
# a thirtieth set, fresh meshes of session 51 (HOLDOUT28_SOURCES), committed before any fill
HOLDOUT28_MANIFEST = Path(__file__).parent / "holdout28_manifest.json"
# a thirty-first set, fresh meshes of session 52 (HOLDOUT29_SOURCES), committed before any fill
HOLDOUT29_MANIFEST = Path(__file__).parent / "holdout29_manifest.json"
# tuning-side range scans of curved shapes of session 40 (CURVED_SCAN_SOURCES)
CURVED_SCANS_MANIFEST = Path(__file__).parent / "curved_scans_manifest.json"
# tuning-side thin smooth walls with saddle-shaped parts of session 41 (THIN_SHELL_SOURCES)
THIN_SHELLS_MANIFEST = Path(__file__).parent / "thin_shells_manifest.json"
# the sets with their own manifest: split -> (default file, in words, first hole seed)
LATER_SETS = {
    "holdout": (HOLDOUT_MANIFEST, "the holdout set", 100),
    "holdout2": (HOLDOUT2_MANIFEST, "the second holdout set", 200),
    "holdout3": (HOLDOUT3_MANIFEST, "the third holdout set", 300),
    "holdout4": (HOLDOUT4_MANIFEST, "the fourth holdout set", 500),
    "holdout5": (HOLDOUT5_MANIFEST, "the fifth holdout set", 600),
    "holdout6": (HOLDOUT6_MANIFEST, "the sixth holdout set", 700),
    "holdout7": (HOLDOUT7_MANIFEST, "the seventh holdout set", 800),
    "holdout8": (HOLDOUT8_MANIFEST, "the eighth holdout set", 900),
    "holdout9": (HOLDOUT9_MANIFEST, "the ninth holdout set", 1000),
    "holdout10": (HOLDOUT10_MANIFEST, "the tenth holdout set", 1100),
    "holdout11": (HOLDOUT11_MANIFEST, "the eleventh holdout set", 1200),
    "holdout12": (HOLDOUT12_MANIFEST, "the twelfth holdout set", 1300),
    "holdout13": (HOLDOUT13_MANIFEST, "the thirteenth holdout set", 1400),
    "holdout14": (HOLDOUT14_MANIFEST, "the fourteenth holdout set", 1500),
    "holdout15": (HOLDOUT15_MANIFEST, "the fifteenth holdout set", 1600),
    "holdout16": (HOLDOUT16_MANIFEST, "the sixteenth holdout set", 1700),
    "holdout17": (HOLDOUT17_MANIFEST, "the seventeenth holdout set", 1800),
    "holdout18": (HOLDOUT18_MANIFEST, "the eighteenth holdout set", 1900),
    "holdout19": (HOLDOUT19_MANIFEST, "the nineteenth holdout set", 2000),
    "holdout20": (HOLDOUT20_MANIFEST, "the twentieth holdout set", 2100),
    "holdout21": (HOLDOUT21_MANIFEST, "the twenty-first holdout set", 2200),
    "holdout22": (HOLDOUT22_MANIFEST, "the twenty-second holdout set", 2300),
    "holdout23": (HOLDOUT23_MANIFEST, "the twenty-third holdout set", 2400),
    "holdout24": (HOLDOUT24_MANIFEST, "the twenty-fourth holdout set", 2500),
    "holdout25": (HOLDOUT25_MANIFEST, "the twenty-fifth holdout set", 2600),
    "holdout26": (HOLDOUT26_MANIFEST, "the twenty-sixth holdout set", 2700),
    "holdout27": (HOLDOUT27_MANIFEST, "the twenty-seventh holdout set", 2800),
    "holdout28": (HOLDOUT28_MANIFEST, "the twenty-eighth holdout set", 2900),
    "holdout29": (HOLDOUT29_MANIFEST, "the twenty-ninth holdout set", 3000),
    "cad_tuning": (CAD_TUNING_MANIFEST, "the tuning-side CAD parts", 400),
    "smooth_tuning": (SMOOTH_TUNING_MANIFEST, "the tuning-side smooth tubes and organic "
                      "bodies", 3800),
    "curved_scans": (CURVED_SCANS_MANIFEST, "the tuning-side range scans of curved shapes",
                     3600),
    "thin_shells": (THIN_SHELLS_MANIFEST, "the tuning-side thin smooth walls with "
                    "saddle-shaped parts", 4100),
}

RADII_H = (3, 4, 5, 6, 7, 8, 10)
NEAR_BORDER = (1, 3, 5)
ON_FEATURE = (0, 2, 4, 6)
FEATURE_DEG = 45.0

SPLIT = {
    "tuning": ["face000", "scan_bunny", "scan_bracket", "bunny", "bone", "blob_a", "cube40",
               "bracket", "airplane", "pial", "white", "tooth", "premolar", "sphere", "torus",
               "snowman"],
    "validation": ["scan_cow", "scan_wuson", "scan_lblock", "cow", "blob_b", "blob_c", "nut",
                   "flange", "lblock", "inflated", "midthickness", "molar5", "incisor",
                   "ellipsoid", "fs_sphere", "peanut"],
    "holdout": list(vm.HOLDOUT_SOURCES),
    "holdout2": list(vm.HOLDOUT2_SOURCES),
    "holdout3": list(vm.HOLDOUT3_SOURCES),
    "cad_tuning": list(vm.CAD_TUNING_SOURCES),
    "holdout4": list(vm.HOLDOUT4_SOURCES),
    "holdout5": list(vm.HOLDOUT5_SOURCES),
    "holdout6": list(vm.HOLDOUT6_SOURCES),
    "holdout7": list(vm.HOLDOUT7_SOURCES),
    "holdout8": list(vm.HOLDOUT8_SOURCES),
    "holdout9": list(vm.HOLDOUT9_SOURCES),
    "holdout10": list(vm.HOLDOUT10_SOURCES),
    "holdout11": list(vm.HOLDOUT11_SOURCES),
    "holdout12": list(vm.HOLDOUT12_SOURCES),
    "holdout13": list(vm.HOLDOUT13_SOURCES),
    "holdout14": list(vm.HOLDOUT14_SOURCES),
    "smooth_tuning": list(vm.SMOOTH_TUNING_SOURCES),
    "holdout15": list(vm.HOLDOUT15_SOURCES),
    "holdout16": list(vm.HOLDOUT16_SOURCES),
    "holdout17": list(vm.HOLDOUT17_SOURCES),
    "holdout18": list(vm.HOLDOUT18_SOURCES),
    "holdout19": list(vm.HOLDOUT19_SOURCES),
    "holdout20": list(vm.HOLDOUT20_SOURCES),
    "holdout21": list(vm.HOLDOUT21_SOURCES),
    "holdout22": list(vm.HOLDOUT22_SOURCES),
    "holdout23": list(vm.HOLDOUT23_SOURCES),
    "holdout24": list(vm.HOLDOUT24_SOURCES),
    "holdout25": list(vm.HOLDOUT25_SOURCES),
    "holdout26": list(vm.HOLDOUT26_SOURCES),
    "holdout27": list(vm.HOLDOUT27_SOURCES),
    "holdout28": list(vm.HOLDOUT28_SOURCES),
    "holdout29": list(vm.HOLDOUT29_SOURCES),
    "curved_scans": list(vm.CURVED_SCAN_SOURCES),
    "thin_shells": list(vm.THIN_SHELL_SOURCES),
}


def read(path: Path = MANIFEST) -> dict:
    """The manifest: ``{"meshes": [{"mesh", "kind", "source", "split", "n_vertices",
    "n_faces", "sha256", "h", "holes": [{"centre", "radius", "radius_h", "near_border",
    "on_feature"}]}]}`` (``sha256_without_avx512`` too where numpy's SIMD kernels change
    the mesh's bytes, ``sha256_missing`` instead where it could not be recorded: session
    44)."""
    return json.loads(Path(path).read_text())


def _feature_vertices(v: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Vertices on an edge whose dihedral angle exceeds :data:`FEATURE_DEG`."""
    from surfinpaint.geometry.mesh import unique_edges

    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    edges, face_edge, count = unique_edges(f)
    flat = face_edge.ravel()
    owner = np.repeat(np.arange(len(f)), 3)
    order = np.argsort(flat, kind="stable")
    e, o = flat[order], owner[order]
    first = np.flatnonzero(np.r_[True, e[1:] != e[:-1]])
    pair = first[count[e[first]] == 2]
    cos = np.einsum("ij,ij->i", n[o[pair]], n[o[pair + 1]])
    sharp = edges[e[pair][cos < np.cos(np.radians(FEATURE_DEG))]]
    return np.unique(sharp)


def _holes_of(mesh_id: str, index: int) -> dict:
    from surfinpaint.geometry.mesh import mean_edge_length

    m = vm.load(mesh_id)
    v, f = m.vertices, m.faces
    kind = vm.SOURCES[mesh_id].kind
    holes = plan_holes(v, f, kind, 1000 + index, mesh_id)
    split = next(s for s, ids in SPLIT.items() if mesh_id in ids)
    entry = {"mesh": mesh_id, "kind": kind, "source": vm.SOURCES[mesh_id].source,
             "split": split, "n_vertices": len(v), "n_faces": len(f)}
    # every set's entries since session 44 (holdout set 13 was the first written with it)
    entry["sha256"] = vm.mesh_digest(m)
    return {**entry, "h": mean_edge_length(v, f), "holes": holes}


def plan_holes(v: np.ndarray, f: np.ndarray, kind: str, seed: int, name: str = "mesh"
               ) -> list[dict]:
    """The manifest's holes of one mesh (module docstring): one per radius of ``RADII_H``,
    ``{"centre", "radius", "radius_h", "near_border", "on_feature"}``."""
    from scipy.sparse.csgraph import dijkstra

    from surfinpaint.geometry.cutting import _Topology, cut_geodesic_disk
    from surfinpaint.geometry.mesh import mean_edge_length

    h = mean_edge_length(v, f)
    topo = _Topology(v, f)
    border = np.flatnonzero(topo.on_boundary)
    to_border = (dijkstra(topo.graph, directed=False, indices=border, min_only=True)
                 if len(border) else np.full(len(v), np.inf))
    features = _feature_vertices(v, f) if kind == "cad" else np.zeros(0, np.int64)
    rng = np.random.default_rng(seed)
    holes, centres = [], []
    for k, r_h in enumerate(RADII_H):
        r = r_h * h
        near = len(border) > 0 and k in NEAR_BORDER
        on_feature = len(features) > 0 and k in ON_FEATURE
        if near:
            pool = np.flatnonzero((to_border >= r + h) & (to_border <= r + 2.5 * h))
        else:
            pool = np.flatnonzero(to_border >= r + 3 * h)
        if on_feature:
            pool = np.intersect1d(pool, features)
        pool = rng.permutation(pool)[:300]
        if centres:  # farthest from the holes so far first
            gap = np.linalg.norm(v[pool][:, None] - np.array(centres)[None], axis=2).min(1)
            pool = pool[np.argsort(-gap, kind="stable")]
        for c in pool[:40]:
            try:
                cut_geodesic_disk(v, f, int(c), r)
            except ValueError:
                continue
            centres.append(v[c])
            holes.append({"centre": v[c].tolist(), "radius": float(r), "radius_h": r_h,
                          "near_border": bool(near), "on_feature": bool(on_feature)})
            break
        else:
            print(f"{name}: no hole of radius {r_h} h could be cut", file=sys.stderr)
    return holes


def write(path: Path = MANIFEST, only: list[str] | None = None,
          splits: tuple[str, ...] = ("tuning", "validation")) -> dict:
    """Build the manifest of ``splits`` from :data:`SPLIT` and :mod:`validation_meshes` and
    write it; meshes whose source is not installed are skipped with a note. The holes'
    seeds follow each mesh's place in the list (the holdout's start at 100, the second
    holdout's at 200, the third's at 300, the tuning-side CAD parts' at 400, the fourth
    holdout's at 500, the fifth holdout's at 600, the sixth holdout's at 700, the seventh
    holdout's at 800, the eighth holdout's at 900, the ninth holdout's at 1000, the tenth
    holdout's at 1100, the eleventh holdout's at 1200, the twelfth holdout's at
    1300, the thirteenth holdout's at 1400, the fourteenth holdout's at 1500, the fifteenth
    holdout's at 1600, the sixteenth holdout's at 1700, the seventeenth holdout's at 1800,
    the eighteenth holdout's at 1900, the nineteenth holdout's at 2000, the twentieth
    holdout's at 2100, the twenty-first holdout's at 2200, the twenty-second holdout's at
    2300, the twenty-third holdout's at 2400, the twenty-fourth holdout's at 2500, the
    twenty-fifth holdout's at 2600, the twenty-sixth holdout's at 2700, the twenty-seventh
    holdout's at 2800, the twenty-eighth holdout's at 2900, the twenty-ninth holdout's at
    3000;
    the smooth tuning set's at 3800, the curved scans set's at 3600, the thin shells set's
    at 4100)."""
    meshes = []
    ids = [i for s in splits for i in SPLIT[s]]
    first = LATER_SETS[splits[0]][2] if len(splits) == 1 and splits[0] in LATER_SETS else 0
    for index, mesh_id in enumerate(ids, start=first):
        if only and mesh_id not in only:
            continue
        try:
            meshes.append(_holes_of(mesh_id, index))
        except (FileNotFoundError, ModuleNotFoundError) as exc:
            print(f"skipping {mesh_id}: {exc}", file=sys.stderr)
            continue
        print(f"{mesh_id}: {len(meshes[-1]['holes'])} holes", file=sys.stderr, flush=True)
    manifest = {"about": "validation benchmark holes; written by benchmarks/holes_manifest.py",
                "meshes": meshes}
    Path(path).write_text(json.dumps(manifest, indent=1) + "\n")
    return manifest


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="write benchmarks/holes_manifest.json")
    parser.add_argument("--write", action="store_true")
    parser.add_argument("--out", default=None)
    for split, (default, words, _) in LATER_SETS.items():
        parser.add_argument(f"--{split.replace('_', '-')}", action="store_true",
                            help=f"{words} instead (default --out: {default.name})")
    args = parser.parse_args()
    if not args.write:
        parser.error("pass --write to (re)write the manifest")
    chosen = [split for split in LATER_SETS if getattr(args, split)]
    if chosen:
        write(Path(args.out or LATER_SETS[chosen[0]][0]), splits=(chosen[0],))
    else:
        write(Path(args.out or MANIFEST))
