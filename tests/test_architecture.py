"""The package's shape, checked from its source: layers import only downwards, modules and
functions stay readable in size, no module reaches into another's privates, and imports sit
at module tops except the heavy optional ones (design.md, issue 13)."""

import ast
from pathlib import Path

import pytest

import surfinpaint

ROOT = Path(surfinpaint.__file__).parent

# geometry < io < representation < fill < app; errors, compiled and lazy sit below everything,
# data (the bundled and test meshes) between io and representation, the package's own
# __init__ and __main__ above app
RANK = {"errors": 0, "compiled": 0, "lazy": 0, "geometry": 1, "io": 2, "data": 2.5,
        "representation": 3, "fill": 4, "app": 5, "__init__": 6, "__main__": 6}
MAX_MODULE_LINES = 600
MAX_FUNCTION_CODE_LINES = 100
# imported inside functions on purpose: they are slow to import (or, for distributed,
# needed only by one command) and most calls never reach them; so are optional packages,
# tried with ``except ImportError``
HEAVY_OPTIONAL = {"pyvista", "vtkmodules", "matplotlib", "numba", "rich", "trimesh", "nibabel",
                  "dask", "distributed"}
# imports inside a function that break an import cycle, each explained where it stands
CYCLE_BREAKING = {("fill/objects.py", "surfinpaint.fill.pipeline"),
                  ("app/batch_summary.py", "surfinpaint"), ("app/fill_report.py", "surfinpaint")}
# imports inside a function that must come after the process's settings (numpy reads them
# when it is imported), each explained where it stands
AFTER_SETTINGS = {("app/program.py", "surfinpaint.app.cli"),
                  ("app/program.py", "surfinpaint.fill.warmup")}


def _modules():
    return sorted(p for p in ROOT.rglob("*.py"))


def _name(path: Path) -> str:
    return str(path.relative_to(ROOT))


def _layer(module: str) -> str:
    """``surfinpaint.fill.holes`` -> ``fill``; ``surfinpaint`` -> ``__init__``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def _surfinpaint_imports(tree: ast.AST):
    """(import node, module) of every import of the package's own modules;
    ``from surfinpaint import data`` imports ``surfinpaint.data``."""
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module == "surfinpaint":
            for alias in node.names:
                yield node, ("surfinpaint" if alias.name == "__version__"
                             else f"surfinpaint.{alias.name}")
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module.split(".")[0] == "surfinpaint":
                yield node, node.module
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "surfinpaint":
                    yield node, alias.name


def _imported_later(tree: ast.AST):
    """(call node, module) of every module of the package's own imported at first use:
    ``lazy_module("surfinpaint.x")``, ``importlib.import_module("surfinpaint.x")``."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant):
            name = node.func.id if isinstance(node.func, ast.Name) else getattr(
                node.func, "attr", None)
            module = node.args[0].value
            if name in ("lazy_module", "import_module") and isinstance(module, str) \
                    and module.split(".")[0] == "surfinpaint":
                yield node, module


def _optional(tree: ast.AST) -> set[int]:
    """The ids of the imports tried for an optional package (``except ImportError``)."""
    guarded = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Try) and any(
                isinstance(h.type, ast.Name) and h.type.id in ("ImportError",
                                                               "ModuleNotFoundError")
                for h in node.handlers):
            guarded.update(id(n) for stmt in node.body for n in ast.walk(stmt)
                           if isinstance(n, ast.Import | ast.ImportFrom))
    return guarded


def _function_imports(tree: ast.AST):
    """(import node, module) of every import inside a function body, but those of an
    optional package (tried, with ``except ImportError``)."""
    optional = _optional(tree)
    for fn in ast.walk(tree):
        if isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef):
            for node in ast.walk(fn):
                if id(node) in optional:
                    continue
                if isinstance(node, ast.ImportFrom) and node.module:
                    yield node, node.module
                elif isinstance(node, ast.Import):
                    yield node, node.names[0].name


def _code_lines(fn: ast.FunctionDef, lines: list[str]) -> int:
    """Lines of a function's body that hold code: no blank, comment or docstring lines."""
    first = fn.body[0]
    start = first.lineno
    if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) \
            and isinstance(first.value.value, str):
        start = first.end_lineno + 1
    body = lines[start - 1:fn.end_lineno]
    return sum(1 for line in body if line.strip() and not line.strip().startswith("#"))


def test_layers_import_only_downwards():
    upward = []
    for path in _modules():
        importer = _layer("surfinpaint." + _name(path).removesuffix(".py").replace("/", "."))
        assert importer in RANK, f"{_name(path)}: no layer for {importer!r}"
        tree = ast.parse(path.read_text())
        for node, module in [*_surfinpaint_imports(tree), *_imported_later(tree)]:
            if module == "surfinpaint":
                continue  # the version string, not the package's code
            imported = _layer(module)
            if RANK[imported] > RANK[importer]:
                upward.append(f"{_name(path)}:{node.lineno} imports {module}")
    assert not upward, "imports reaching up a layer:\n" + "\n".join(upward)


def test_the_layer_check_sees_an_upward_import():
    # the check above would pass vacuously if it missed imports: it must see this one
    tree = ast.parse("def f():\n    from surfinpaint.app.cli import main\n")
    assert [m for _, m in _surfinpaint_imports(tree)] == ["surfinpaint.app.cli"]
    assert RANK[_layer("surfinpaint.app.cli")] > RANK[_layer("surfinpaint.geometry.mesh")]
    # and the imports made at first use
    tree = ast.parse('cli = lazy_module("surfinpaint.app.cli")\n'
                     'm = importlib.import_module("surfinpaint.app.report")\n')
    assert [m for _, m in _imported_later(tree)] == ["surfinpaint.app.cli",
                                                     "surfinpaint.app.report"]


def test_nothing_below_app_draws():
    drawing = []
    for path in _modules():
        if _name(path).startswith("app/"):
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            names = ([node.module or ""] if isinstance(node, ast.ImportFrom) else
                     [a.name for a in node.names] if isinstance(node, ast.Import) else [])
            drawing += [f"{_name(path)}:{node.lineno} {n}" for n in names
                        if n.split(".")[0] == "matplotlib"]
    assert not drawing, drawing


def test_no_module_over_600_lines():
    long = {_name(p): n for p in _modules()
            if (n := len(p.read_text().splitlines())) > MAX_MODULE_LINES}
    assert not long, f"modules over {MAX_MODULE_LINES} lines: {long}"


def test_no_function_over_100_code_lines():
    long = []
    for path in _modules():
        text = path.read_text()
        lines = text.splitlines()
        for fn in ast.walk(ast.parse(text)):
            if isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef):
                n = _code_lines(fn, lines)
                if n > MAX_FUNCTION_CODE_LINES:
                    long.append(f"{_name(path)}:{fn.lineno} {fn.name} ({n} code lines)")
    assert not long, "functions over 100 code lines:\n" + "\n".join(long)


def test_code_lines_leave_out_docstrings_comments_and_blanks():
    text = ('def f(a,\n      b):\n    """Doc.\n\n    More."""\n    # why\n\n    x = 1\n'
            '    return x\n')
    fn = ast.parse(text).body[0]
    assert _code_lines(fn, text.splitlines()) == 2


def test_no_module_imports_another_modules_privates():
    found = []
    for path in _modules():
        tree = ast.parse(path.read_text())
        aliases = set()
        for node, module in _surfinpaint_imports(tree):
            if isinstance(node, ast.ImportFrom):
                found += [f"{_name(path)}:{node.lineno} {module}.{a.name}" for a in node.names
                          if a.name.startswith("_") and not a.name.startswith("__")]
                aliases.update(a.asname or a.name for a in node.names)
            else:
                aliases.update(a.asname or a.name.split(".")[0] for a in node.names)
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) \
                    and node.value.id in aliases and node.attr.startswith("_") \
                    and not node.attr.startswith("__"):
                found.append(f"{_name(path)}:{node.lineno} {node.value.id}.{node.attr}")
    assert not found, "private names used across modules:\n" + "\n".join(found)


def test_imports_sit_at_module_tops_but_heavy_optional_ones():
    inside = []
    for path in _modules():
        for node, module in _function_imports(ast.parse(path.read_text())):
            if module.split(".")[0] in HEAVY_OPTIONAL or (_name(path), module) in (
                    CYCLE_BREAKING | AFTER_SETTINGS):
                continue
            inside.append(f"{_name(path)}:{node.lineno} {module}")
    assert not inside, "imports inside functions:\n" + "\n".join(inside)


@pytest.mark.parametrize("name, module", sorted(CYCLE_BREAKING | AFTER_SETTINGS))
def test_each_cycle_breaking_import_says_why(name, module):
    lines = (ROOT / name).read_text().splitlines()
    at = [i for i, line in enumerate(lines)
          if line.strip().startswith(f"from {module} import")]
    assert at, f"{name} no longer imports {module} (drop it from CYCLE_BREAKING)"
    assert all("here, not at the top" in lines[i - 1] + lines[i - 2] for i in at)
