"""Every Examples section in the package's docstrings runs and prints what it says
(two had drifted from the code before this test: session 25)."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import surfinpaint

MODULES = sorted(m.name for m in pkgutil.walk_packages(surfinpaint.__path__, "surfinpaint.")
                 if not m.name.endswith("__main__"))


def _with_examples(name: str) -> bool:
    spec = importlib.util.find_spec(name)
    return spec is not None and spec.origin is not None and ">>>" in open(
        spec.origin, encoding="utf-8").read()


@pytest.mark.parametrize("name", [m for m in MODULES if _with_examples(m)])
def test_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE,
                             verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed"
    assert result.attempted > 0
