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


def test_the_pipeline_imports_threadpoolctl_and_scipy_spatial_at_their_first_use():
    # 9-17 and 50-60 ms of every start; a large default fill imports both on the thread
    # that loads the kernels (the λ-H modules and the distances use them), beside the
    # whole-mesh passes
    # scipy.special (45 ms; the plane test's tails, in geometry.flatness, which the faired
    # fill imports for meeting_line) likewise, since session 36
    start = "import surfinpaint.app.cli, surfinpaint.fill.pipeline"
    late = ("threadpoolctl", "scipy.spatial", "scipy.special")
    assert _modules_after(start, late) == set()
    assert _modules_after(start + "\nfrom surfinpaint.fill import warmup\n"
                          "warmup.warm_kernels('conformal')", late) == set(late)
    assert _modules_after(start + "\nfrom surfinpaint.fill import scheduler\n"
                          "scheduler.blas_threads.blas_controller",
                          ("threadpoolctl",)) == {"threadpoolctl"}


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


# what a faired fill from the command line never uses (session 14: ~0.1 s CPU of its start):
# the λ-H fill and its self-check, the representation under it, the batch runner, and the
# report's, experiments' and representation commands' modules
NOT_IN_A_FAIRED_FILL = ("surfinpaint.fill.conformal.method", "surfinpaint.fill.selfcheck",
                        "surfinpaint.representation.on_mesh",
                        "surfinpaint.representation.represent", "surfinpaint.app.batch",
                        "surfinpaint.app.report", "surfinpaint.app.experiments",
                        "surfinpaint.app.figures", "surfinpaint.geometry.metrics")


def _modules_after(code: str, names) -> set[str]:
    probe = code + f"\nimport sys\nprint(' '.join(m for m in {tuple(names)!r} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True).stdout
    return set(out.split())


def test_a_faired_fill_from_the_command_line_imports_only_what_it_uses(tmp_path):
    mesh, out = tmp_path / "holed.ply", tmp_path / "out.ply"
    code = ("import warnings; warnings.simplefilter('ignore')\n"
            "from surfinpaint.app import cli\n"
            f"assert cli.main(['fill', {str(mesh)!r}, '-o', {str(out)!r}, '-q', '--method', "
            "'fair']) == 0\n")
    _modules_after("from surfinpaint import data, write_mesh\n"
                   "from surfinpaint.geometry.cutting import cut_holes\n"
                   "v, f = data.sphere(3)\n"
                   "cut = cut_holes(v, f, [v[0]], 0.4)\n"
                   f"write_mesh({str(mesh)!r}, cut.vertices, cut.faces)", ())
    assert _modules_after(code, NOT_IN_A_FAIRED_FILL) == set()
    assert out.stat().st_size > mesh.stat().st_size
    # a quiet run that prints nothing never makes its console (rich: 13-40 ms of a start)
    assert _modules_after(code, ("rich", "rich.console")) == set()
    assert "rich" in _modules_after(code.replace("'-q', ", ""), ("rich",))
    # the probe sees them when they are imported: the default fill uses the first three
    conformal = code.replace("'--method', 'fair'", "'--method', 'conformal'")
    assert set(NOT_IN_A_FAIRED_FILL[:3]) <= _modules_after(conformal, NOT_IN_A_FAIRED_FILL)


def test_the_package_names_every_export_at_first_use():
    import surfinpaint

    for name in surfinpaint.__all__:
        assert getattr(surfinpaint, name) is not None, name
        assert name in dir(surfinpaint)
    from surfinpaint.fill.pipeline import fill_holes
    from surfinpaint.representation.represent import represent

    assert surfinpaint.fill_holes is fill_holes and surfinpaint.represent is represent
    try:
        surfinpaint.no_such_name  # noqa: B018
    except AttributeError as exc:
        assert "no_such_name" in str(exc)
    else:
        raise AssertionError("an unknown name must raise AttributeError")
    assert _modules_after("import surfinpaint", NOT_IN_A_FAIRED_FILL) == set()
    assert _modules_after("from surfinpaint import represent",
                          NOT_IN_A_FAIRED_FILL) >= {"surfinpaint.representation.represent"}


def test_the_fill_parser_leaves_the_report_and_experiments_commands_out():
    from surfinpaint.app import cli

    assert cli._command_word(["fill", "a.ply", "-o", "b.ply"]) == "fill"
    assert cli._command_word(["--version"]) is None
    assert _modules_after("from surfinpaint.app import cli; cli.build_parser('fill')",
                          NOT_IN_A_FAIRED_FILL) == set()
    # without a command named (help, a usage error) every command is listed
    full = cli.build_parser().format_help()
    assert "report" in full and "experiments" in full
    assert cli.build_parser("report").parse_args(["report", "m.ply", "-o", "d"]).func


def test_conformal_fill_is_the_methods_own():
    from surfinpaint.fill import conformal
    from surfinpaint.fill.conformal.method import conformal_fill

    assert conformal.conformal_fill is conformal_fill
    try:
        conformal.no_such_name  # noqa: B018
    except AttributeError:
        pass
    else:
        raise AssertionError("an unknown name must raise AttributeError")


def test_loading_the_conformal_kernels_imports_the_lambda_h_fill():
    # forked workers inherit what the parent imported before the fork
    code = "from surfinpaint.fill import warmup; warmup.warm_kernels('conformal')"
    assert "surfinpaint.fill.conformal.method" in _modules_after(
        code, ("surfinpaint.fill.conformal.method",))


# ------------------------------------------- modules other packages import unused (defer_modules)


def _run(code: str, *paths) -> list[str]:
    """The words ``code`` prints in a fresh interpreter (``paths`` first on its sys.path)."""
    probe = f"import sys\nsys.path[:0] = {[str(p) for p in paths]!r}\n" + code
    return subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                          check=True, timeout=120).stdout.split()


def _package(root) -> None:
    """``pkg``, whose ``__init__`` imports its submodule ``sub`` (``from . import sub``) as
    scipy.spatial imports its ``transform``; ``sub`` takes 50 ms to run and counts its runs
    in the module ``runs``."""
    (root / "pkg").mkdir()
    (root / "pkg" / "__init__.py").write_text("from . import sub\n")
    (root / "pkg" / "sub.py").write_text("import time, runs\ntime.sleep(0.05)\n"
                                         "runs.count += 1\nVALUE = object()\n")
    (root / "runs.py").write_text("count = 0\n")


def test_a_deferred_module_runs_once_at_its_first_attribute_read(tmp_path):
    _package(tmp_path)
    out = _run("import threading, types\n"
               "from surfinpaint.lazy import DeferredModule, defer_modules\n"
               "print(*defer_modules(('pkg.sub', 'no_such_module_here')))\n"
               "import pkg, runs\n"
               "print(type(pkg.sub).__name__, runs.count)\n"
               "from pkg import sub\n"  # a stand-in held before the module ran
               "got = []\n"
               "threads = [threading.Thread(target=lambda: got.append(sub.VALUE))\n"
               "           for _ in range(8)]\n"
               "[t.start() for t in threads]; [t.join() for t in threads]\n"
               "real = sys.modules['pkg.sub']\n"
               "print(runs.count, len(got), all(g is real.VALUE for g in got),\n"
               "      type(real) is types.ModuleType, pkg.sub is real)\n"
               "try:\n    import no_such_module_here\nexcept ModuleNotFoundError:\n"
               "    print('missing')\n", tmp_path)
    # a module that is not there is not stood in for: its import still fails
    assert out == ["pkg.sub", "DeferredModule", "0", "1", "8", "True", "True", "True",
                   "missing"]


def test_the_check_sees_the_package_run_its_submodule(tmp_path):
    # the test above would pass vacuously if importing pkg did not run pkg.sub
    _package(tmp_path)
    assert _run("import pkg, runs\nprint(runs.count)\n", tmp_path) == ["1"]


def test_the_program_starts_without_numpys_unused_submodules():
    start = ("from surfinpaint.app import program\n"
             "program.command_line()\n"
             "print(*(type(sys.modules[m]).__name__ for m in program.UNUSED_MODULES))\n"
             "import numpy as np\n"  # still there for whatever reads them
             "np.testing.assert_array_equal(np.char.upper(['a']), ['A'])\n"
             "print(type(sys.modules['numpy.testing']).__name__)\n")
    names = ("f2py", "testing", "char", "rec", "ctypeslib")
    assert _run(start) == ["DeferredModule"] * len(names) + ["module"]
    # scipy (with the command line) imports each of them otherwise
    plain = ("from surfinpaint.app import cli\n"
             f"print(*(f'numpy.{{m}}' in sys.modules for m in {names!r}))\n")
    assert _run(plain) == ["True"] * len(names)
