"""Lazy package faces (PEP 562), in the manner of scikit-image's ``lazy.attach``.

A package ``__init__`` names what it offers and the module each name lives in; the module
is imported when the name is first used, so importing the package loads none of them::

    __getattr__, __dir__, __all__ = attach(__name__, {"load_project": "designer.project.load"})
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping


def attach(
    package: str, names: Mapping[str, str]
) -> tuple[Callable[[str], object], Callable[[], list[str]], list[str]]:
    """``(__getattr__, __dir__, __all__)`` for ``package``: ``names`` maps each public
    name to the module that defines it."""
    table = dict(names)

    def __getattr__(name: str) -> object:
        module = table.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module), name)
        setattr(sys.modules[package], name, value)  # later look-ups skip this function
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(table))

    return __getattr__, __dir__, sorted(table)
