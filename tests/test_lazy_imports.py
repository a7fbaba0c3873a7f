"""Start-up cost (issue 15): the scipy submodules no mesh fill uses are imported at their
first use (surfinpaint.lazy), not by ``import surfinpaint`` or the command line."""

import subprocess
import sys

import numpy as np
import scipy.ndimage
import scipy.optimize

from surfinpaint.lazy import LazyModule, lazy_module

NOT_AT_START = ("scipy.ndimage", "scipy.optimize")


def _loaded_after(code: str) -> set[str]:
    """The modules of NOT_AT_START loaded after running ``code`` in a fresh interpreter."""
    probe = code + f"\nimport sys\nprint(' '.join(m for m in {NOT_AT_START!r} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True).stdout
    return set(out.split())


def test_importing_the_package_and_the_cli_leaves_them_unloaded():
    assert _loaded_after("import surfinpaint, surfinpaint.app.cli") == set()


def test_a_fill_of_each_method_leaves_them_unloaded():
    # the parallel workers are forked from this process: what a fill loads they load each
    code = ("import warnings; warnings.simplefilter('ignore')\n"
            "from surfinpaint import data, fill_holes\n"
            "from surfinpaint.geometry.cutting import cut_holes\n"
            "v, f = data.sphere(3)\n"
            "cut = cut_holes(v, f, [v[0]], 0.4)\n"
            "for method in ('conformal', 'fair'):\n"
            "    r = fill_holes(cut.vertices, cut.faces, method=method, jobs=1)\n"
            "    assert r.reports[0].new_faces > 0, r.reports[0]\n")
    assert _loaded_after(code) == set()


def test_the_check_sees_a_module_imported_at_start():
    # the checks above would pass vacuously if the probe missed imports
    assert _loaded_after("import scipy.ndimage") == {"scipy.ndimage"}


def test_a_lazy_module_gives_the_modules_own_objects():
    ndimage = lazy_module("scipy.ndimage")
    assert isinstance(ndimage, LazyModule)
    assert ndimage.binary_dilation is scipy.ndimage.binary_dilation
    assert ndimage.module is scipy.ndimage
    assert lazy_module("scipy.optimize").brentq is scipy.optimize.brentq
    assert "scipy.ndimage" in repr(ndimage)


def test_the_spelled_out_structures_are_ndimages():
    from surfinpaint.representation import grid_represent, reconstruction

    np.testing.assert_array_equal(reconstruction._CROSS,
                                  scipy.ndimage.generate_binary_structure(2, 1))
    for block in (reconstruction._BLOCK, grid_represent._BLOCK):
        assert block.dtype == bool
        np.testing.assert_array_equal(block, scipy.ndimage.generate_binary_structure(2, 2))
