"""Modules imported at their first use, named at the top of the module that uses them.

``ndimage = lazy_module("scipy.ndimage")`` at a module's top reads like an import and keeps
the dependency in view, but the module is only imported when one of its attributes is first
read. For the scipy submodules no fill of a mesh touches (``scipy.ndimage``: the grid
representation; ``scipy.optimize``: the bundled meshes' generation), which together cost
about 0.25 s CPU of every ``surfinpaint`` process's start (``python -X importtime``).

:func:`defer_modules` does the same for third-party modules that another package imports
without using them (the program's, :mod:`surfinpaint.app.program`).
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
import threading
from types import ModuleType

__all__ = ["DeferredModule", "LazyModule", "defer_modules", "lazy_module"]


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


class DeferredModule(ModuleType):
    """Stands for a module in ``sys.modules`` (and as its package's attribute) until one of
    its attributes is read: then the module is imported in its place and that attribute
    given, the real module's own. Holding the stand-in (``from package import module``
    before that) stays correct: every attribute read goes to the real module."""

    _lock = threading.Lock()

    def __getattr__(self, attr: str):  # only for what the stand-in's own dict lacks
        # the stand-in leaves sys.modules once, under the lock; the import itself is the
        # import system's, whose per-module locks make a second thread wait for the first
        with DeferredModule._lock:
            if sys.modules.get(self.__name__) is self:
                del sys.modules[self.__name__]
        # the import system sets the package's attribute to the real module too
        return getattr(importlib.import_module(self.__name__), attr)


def defer_modules(names: tuple[str, ...]) -> list[str]:
    """Put a :class:`DeferredModule` for each module of ``names`` (full dotted names) that
    is not imported yet into ``sys.modules``, and onto its package where that is imported
    (a package imported later binds it by ``from . import name``), so that code that
    imports a module without using it (or lists a package's submodules with ``hasattr``)
    does not run it. A top-level module that is not installed is left alone (its import
    must still fail); a submodule is not looked up (that would import its package). The
    names deferred are returned."""
    deferred = []
    for full in names:
        package, _, name = full.rpartition(".")
        if full in sys.modules or not package and importlib.util.find_spec(full) is None:
            continue
        stand_in = DeferredModule(full)
        sys.modules[full] = stand_in
        if package in sys.modules:
            setattr(sys.modules[package], name, stand_in)
        deferred.append(full)
    return deferred
