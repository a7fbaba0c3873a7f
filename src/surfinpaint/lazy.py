"""Modules imported at their first use, named at the top of the module that uses them.

``ndimage = lazy_module("scipy.ndimage")`` at a module's top reads like an import and keeps
the dependency in view, but the module is only imported when one of its attributes is first
read. For the scipy submodules no fill of a mesh touches (``scipy.ndimage``: the grid
representation; ``scipy.optimize``: the bundled meshes' generation), which together cost
about 0.25 s CPU of every ``surfinpaint`` process's start (``python -X importtime``).
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["LazyModule", "lazy_module"]


class LazyModule:
    """Stands for the module ``name``: reading an attribute imports it (once, through
    :func:`importlib.import_module`, which is thread-safe) and gives the module's own
    attribute, the same object a plain import would give."""

    __slots__ = ("_name",)

    def __init__(self, name: str) -> None:
        self._name = name

    @property
    def module(self) -> ModuleType:
        """The module itself, imported now if it was not yet."""
        return importlib.import_module(self._name)

    def __getattr__(self, attr: str):
        return getattr(self.module, attr)

    def __repr__(self) -> str:
        return f"<lazy module {self._name!r}>"


def lazy_module(name: str) -> LazyModule:
    """A :class:`LazyModule` for ``name`` (a full dotted module name)."""
    return LazyModule(name)
