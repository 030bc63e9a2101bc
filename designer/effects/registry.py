"""Which effect implements which project element: a registry filled by the effect modules.

An effect module marks its effect class with ``@implements(ModelClass)``; the class then
names its element (``model``) and builds itself from it (``from_model(element, camera)``).
``registered_effects()`` imports every public module of ``designer.effects`` first, so a
new effect is its model class and its own module: nothing else lists it.
"""

from __future__ import annotations

import dataclasses
import importlib
import pkgutil
import typing
from collections.abc import Callable, Mapping
from typing import TypeVar

from designer.effects.base import Effect

E = TypeVar("E", bound=type[Effect])

#: model class → the effect class that implements it
_REGISTRY: dict[type, type[Effect]] = {}


def implements(model_class: type) -> Callable[[E], E]:
    """Class decorator: the effect implements ``model_class`` (one effect per element).

    Sets ``cls.model``; the class must define its own ``from_model``.
    """
    def register(cls: E) -> E:
        if not (isinstance(cls, type) and issubclass(cls, Effect)):
            raise TypeError(f"{cls!r} is not an Effect class")
        if "from_model" not in vars(cls):
            raise TypeError(f"{cls.__name__} implements {model_class.__name__} but defines "
                            f"no from_model")
        other = _REGISTRY.get(model_class)
        if other is not None and other.__qualname__ != cls.__qualname__:
            raise ValueError(f"{model_class.__name__} is implemented twice: by "
                             f"{other.__name__} and {cls.__name__}")
        cls.model = model_class
        _REGISTRY[model_class] = cls
        return cls
    return register


def registered_effects() -> dict[type, type[Effect]]:
    """Model class → effect class, after importing every effect module of the package."""
    package = importlib.import_module("designer.effects")
    for info in pkgutil.iter_modules(package.__path__):
        if not info.name.startswith("_"):
            importlib.import_module(f"designer.effects.{info.name}")
    return dict(_REGISTRY)


def effect_elements(effects_class: type) -> dict[str, type]:
    """Field name → model class of every element an ``Effects`` model class holds
    (its fields are ``Element | None``)."""
    hints = typing.get_type_hints(effects_class)
    elements = {}
    for field in dataclasses.fields(effects_class):
        classes = [a for a in typing.get_args(hints[field.name]) if a is not type(None)]
        if len(classes) != 1:
            raise TypeError(f"{effects_class.__name__}.{field.name} is not one element or "
                            f"None")
        elements[field.name] = classes[0]
    return elements


def registry_problems(registry: Mapping[type, type[Effect]], effects_class: type
                      ) -> list[str]:
    """What keeps ``registry`` from matching the elements of ``effects_class`` one to
    one: elements without an effect, registered classes that are no element, and effect
    classes registered for more than one element. Empty when they match."""
    elements = set(effect_elements(effects_class).values())
    problems = [f"<{c.__name__}> has no registered effect" for c in elements
                if c not in registry]
    problems += [f"{e.__name__} implements {c.__name__}, which Effects does not hold"
                 for c, e in registry.items() if c not in elements]
    by_effect: dict[type, list[type]] = {}
    for c, e in registry.items():
        by_effect.setdefault(e, []).append(c)
    problems += [f"{e.__name__} implements {len(cs)} elements" for e, cs in by_effect.items()
                 if len(cs) > 1]
    return sorted(problems)
