"""Every count in a message agrees with its noun ("1 face", "2 faces", "0 faces"), through
the one rule :func:`surfinpaint.errors.agreeing` (:func:`~surfinpaint.errors.how_many`):
a table of the messages, each made with one and with two of its things, and a check that
no message of ``src`` spells a plural its own way (``'s' if n > 1``, ``component(s)``)."""

from __future__ import annotations

import ast
import warnings
from pathlib import Path

import numpy as np
import pytest

from surfinpaint.app.fill_report import Summary, summary_lines
from surfinpaint.errors import MeshError, agreeing, how_many, mesh_size
from surfinpaint.geometry.orientation import orientation_note, outward_note
from surfinpaint.geometry.validation import check_loop, validate_mesh
from surfinpaint.io import read_mesh

SRC = Path(__file__).resolve().parents[1] / "src" / "surfinpaint"


@pytest.mark.parametrize("n, said", [(0, "0 faces"), (1, "1 face"), (2, "2 faces"),
                                     (11, "11 faces")])
def test_how_many_agrees_for_every_count(n, said):
    assert how_many(n, "face", "faces") == said
    assert agreeing(n, "face", "faces") == said.split()[1]


def _triangles(*rows):
    """Vertices enough for ``rows``, each at its own place."""
    f = np.array(rows, dtype=np.int64)
    return np.random.default_rng(0).random((f.max() + 1, 3)), f


def _summary(one: bool) -> str:
    v, f = _triangles([0, 1, 2]) if one else _triangles([0, 1, 2], [3, 4, 5])
    return validate_mesh(v, f).summary()


def _bowtie_loop(one: bool) -> str:
    # triangle (0, 1, 2) touches one other triangle at vertex 0, and another at vertex 1
    rows = [[0, 1, 2], [0, 3, 4]] + ([] if one else [[1, 5, 6]])
    v, f = _triangles(*rows)
    with pytest.raises(MeshError) as caught:
        check_loop(f, np.array([0, 1, 2]))
    return str(caught.value)


def _polygons(one: bool, tmp_path: Path) -> str:
    quads = "f 1 2 3 4\n" if one else "f 1 2 3 4\nf 1 3 4 2\n"
    path = tmp_path / "quads.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n" + quads)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        read_mesh(path)
    return " ".join(str(w.message) for w in caught)


def _fill_summary(one: bool) -> str:
    n = 1 if one else 2
    return summary_lines(Summary(holes_found=n, lambda_h=n, faired=0, skipped=0, failed=0,
                                 new_vertices=n, new_faces=n, seconds=0.5, zipped=n))[0]


# (what, the message made with one / with two of its things, what each must say)
CASES = [
    ("a mesh's summary", _summary,
     "3 vertices, 1 face, 1 component, 1 boundary loop",
     "6 vertices, 2 faces, 2 components, 2 boundary loops"),
    ("a hole through bow-tie vertices", _bowtie_loop,
     "non-manifold (bow-tie) vertex 0:", "non-manifold (bow-tie) vertices 0, 1:"),
    ("faces flipped to orient", lambda one: orientation_note(np.array([4] if one else [4, 9])),
     "flipped 1 face (4)", "flipped 2 faces (4, 9)"),
    ("closed pieces turned outward",
     lambda one: outward_note([np.arange(1)] if one else [np.arange(1), np.arange(2)]),
     "turned 1 closed piece outward (negative volume): its 1 face (0)",
     "turned 2 closed pieces outward (negative volume): their 1 face (0); 2 faces (0, 1)"),
    ("a fill's closing summary", _fill_summary,
     "1 hole found: 1 filled by the λ-H fill, 0 by a faired fill, 1 seam zipped, 0 skipped, "
     "0 failed; 1 new vertex, 1 new face;",
     "2 holes found: 2 filled by the λ-H fill, 0 by a faired fill, 2 seams zipped, 0 skipped, "
     "0 failed; 2 new vertices, 2 new faces;"),
    ("a mesh's size", lambda one: mesh_size(1, 1) if one else mesh_size(2, 0),
     "1 vertex, 1 face", "2 vertices, 0 faces"),
]


@pytest.mark.parametrize("one", [True, False], ids=["one", "two"])
@pytest.mark.parametrize("what, make, said_one, said_two", CASES, ids=[c[0] for c in CASES])
def test_a_message_says_its_count_with_the_noun_that_agrees(what, make, said_one, said_two,
                                                           one):
    assert (said_one if one else said_two) in make(one)


@pytest.mark.parametrize("one, said", [
    (True, "1 polygon face with more than three corners was fan-triangulated"),
    (False, "2 polygon faces with more than three corners were fan-triangulated")])
def test_a_readers_polygon_warning_agrees_with_its_count(tmp_path, one, said):
    assert said in _polygons(one, tmp_path)


def _own_plurals(path: Path) -> list[str]:
    """The f-strings of ``path`` that make a plural their own way: a piece that is ``'s'``
    or ``'es'`` chosen by an expression (``{'s' if n > 1 else ''}``, ``{'s' * many}``), or a
    ``(s)`` after a word outside a docstring."""
    found = []
    tree = ast.parse(path.read_text(encoding="utf-8"))
    docstrings = {id(node.body[0].value) for node in ast.walk(tree)
                  if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef))
                  and node.body and isinstance(node.body[0], ast.Expr)}
    for node in ast.walk(tree):
        if isinstance(node, ast.JoinedStr):
            for part in node.values:
                if isinstance(part, ast.FormattedValue) and not isinstance(part.value, ast.Call):
                    if any(isinstance(c, ast.Constant) and c.value in ("s", "es")
                           for c in ast.walk(part.value)):
                        found.append(f"{path.name}:{node.lineno}")
        if (isinstance(node, ast.Constant) and isinstance(node.value, str)
                and id(node) not in docstrings and any(word + "(s)" in node.value for word in
                        ("component", "loop", "face", "ring", "vertex", "file", "hole",
                         "edge", "node", "experiment"))):
            found.append(f"{path.name}:{node.lineno}")
    return found


def test_no_message_spells_a_plural_its_own_way():
    found = [hit for path in sorted(SRC.rglob("*.py")) for hit in _own_plurals(path)]
    assert found == []


def test_the_plural_check_finds_a_plural_spelled_its_own_way(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text('n = 2\nmany = True\na = f"{n} file{\'s\' if n > 1 else \'\'}"\n'
                   'b = f"{n} piece{\'s\' * many}"\nc = f"{n} component(s)"\n'
                   'd = f"{n} {agreeing(n, \'face\', \'faces\')}"\n'
                   'def e():\n    """The hole(s) of a docstring."""\n')
    assert _own_plurals(bad) == ["bad.py:3", "bad.py:4", "bad.py:5"]
