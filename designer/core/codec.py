"""Frozen dataclasses ↔ JSON data, driven by their type hints alone.

A value is written as plain JSON data (dicts, lists, numbers, text, null) and read back
into the same classes by walking :func:`dataclasses.fields` and the resolved type hints,
so a dataclass that gains a field, or a model that gains a dataclass, round-trips with no
change here. Understood hints: ``bool``, ``int``, ``float`` (an integer in the data is
read as a float), ``str``, ``None``, ``Any``, ``Literal[...]``, ``tuple[X, ...]``,
``tuple[A, B]``, ``list[X]``, ``dict[K, V]`` (K ``str`` or ``int``; JSON keys are text),
nested dataclasses, and unions of them (``X | None``; a union of several dataclasses is
written tagged by class name, ``{"BrownConrady": {...}}``).

Reading is strict: a field the class does not have, a missing required field, a value
of the wrong kind or a text outside its ``Literal`` is a :class:`CodecError` naming its
place (``frames[3].foo``). Fields with ``init=False`` are neither written nor read.
No numpy, no designer imports: every layer may use it.
"""

from __future__ import annotations

import dataclasses
import types
import typing
from typing import Any, Literal, Union

from designer.errors import DesignerError


class CodecError(DesignerError, ValueError):
    """Data that is not the value its type hints describe; the message names its place."""

    def __init__(self, place: str, problem: str) -> None:
        self.place, self.problem = place, problem
        super().__init__(f"{place or 'the top level'}: {problem}")


_HINTS: dict[type, dict[str, Any]] = {}


def field_hints(cls: type, localns: dict | None = None) -> dict[str, Any]:
    """The resolved type hint of each init field of dataclass ``cls`` (in field order).

    ``localns`` supplies names a module imports only for type checking.
    """
    hints = _HINTS.get(cls)
    if hints is None:
        resolved = typing.get_type_hints(cls, localns=localns)
        hints = {f.name: resolved[f.name] for f in dataclasses.fields(cls) if f.init}
        _HINTS[cls] = hints
    return hints


def _union_args(hint) -> tuple | None:
    if typing.get_origin(hint) in (Union, types.UnionType):
        return typing.get_args(hint)
    return None


def _tagged(args: tuple) -> bool:
    """A union written with its class name: more than one dataclass among its members."""
    return sum(1 for a in args if dataclasses.is_dataclass(a)) > 1


def reachable_dataclasses(hint, localns: dict | None = None) -> list[type]:
    """Every dataclass a value of ``hint`` may hold, itself included, in discovery order."""
    seen: list[type] = []

    def walk(h) -> None:
        if dataclasses.is_dataclass(h) and isinstance(h, type):
            if h in seen:
                return
            seen.append(h)
            for sub in field_hints(h, localns).values():
                walk(sub)
            return
        for arg in typing.get_args(h):
            if arg is not Ellipsis and typing.get_origin(h) is not Literal:
                walk(arg)

    walk(hint)
    return seen


# ------------------------------------------------------------------------- writing
def to_data(value, hint=None, localns: dict | None = None):
    """``value`` as JSON data; ``hint`` (default: its own class) decides union tags."""
    if hint is None:
        hint = type(value)
    if value is None:
        return None
    args = _union_args(hint)
    if args is not None:
        member = next((a for a in args if dataclasses.is_dataclass(a) and type(value) is a),
                      None)
        if member is not None:
            data = to_data(value, member, localns)
            return {member.__name__: data} if _tagged(args) else data
        for a in args:
            if a is not type(None) and _fits(value, a):
                return to_data(value, a, localns)
        raise CodecError("", f"{value!r} is none of {hint}")
    if dataclasses.is_dataclass(value):
        hints = field_hints(type(value), localns)
        return {name: to_data(getattr(value, name), h, localns) for name, h in hints.items()}
    origin = typing.get_origin(hint)
    if isinstance(value, tuple | list):
        items = typing.get_args(hint)
        if origin is tuple and items and items[-1] is not Ellipsis:
            return [to_data(v, h, localns) for v, h in zip(value, items, strict=True)]
        item = items[0] if items else None
        return [to_data(v, item, localns) for v in value]
    if isinstance(value, dict):
        key_value = typing.get_args(hint)
        item = key_value[1] if len(key_value) == 2 else None
        return {str(k): to_data(v, item, localns) for k, v in value.items()}
    return value


def _fits(value, hint) -> bool:
    """Whether a non-dataclass ``value`` is of the kind ``hint`` names (for unions)."""
    origin = typing.get_origin(hint)
    if hint is Any:
        return True
    if origin is Literal:
        return value in typing.get_args(hint)
    if origin in (tuple, list):
        return isinstance(value, tuple | list)
    if origin is dict:
        return isinstance(value, dict)
    if hint is float:
        return isinstance(value, int | float) and not isinstance(value, bool)
    if hint is int:
        return isinstance(value, int) and not isinstance(value, bool)
    return isinstance(hint, type) and isinstance(value, hint)


# ------------------------------------------------------------------------- reading
def from_data(hint, data, place: str = "", localns: dict | None = None):
    """The value of type ``hint`` that ``data`` (JSON data) describes; CodecError names
    the place (``place`` is the prefix of the top level, '' for none)."""
    if hint is Any:
        return data
    if hint is type(None):
        if data is not None:
            raise CodecError(place, f"{data!r} must be null")
        return None
    args = _union_args(hint)
    if args is not None:
        return _union(args, data, place, localns)
    if dataclasses.is_dataclass(hint) and isinstance(hint, type):
        return _dataclass(hint, data, place, localns)
    origin = typing.get_origin(hint)
    if origin is Literal:
        choices = typing.get_args(hint)
        if data not in choices or isinstance(data, bool) != any(isinstance(c, bool)
                                                               for c in choices):
            raise CodecError(place, f"{data!r} is not one of "
                             f"{', '.join(repr(c) for c in choices)}")
        return data
    if origin in (tuple, list):
        if not isinstance(data, list):
            raise CodecError(place, f"{_kind(data)} where a list belongs")
        items = typing.get_args(hint)
        if origin is tuple and items and items[-1] is not Ellipsis:
            if len(data) != len(items):
                raise CodecError(place, f"{len(data)} items where {len(items)} belong")
            return tuple(from_data(h, v, f"{place}[{i}]", localns)
                         for i, (h, v) in enumerate(zip(items, data, strict=True)))
        item = items[0] if items else Any
        out = [from_data(item, v, f"{place}[{i}]", localns) for i, v in enumerate(data)]
        return tuple(out) if origin is tuple else out
    if origin is dict:
        if not isinstance(data, dict):
            raise CodecError(place, f"{_kind(data)} where an object belongs")
        key, item = typing.get_args(hint) or (str, Any)
        out = {}
        for k, v in data.items():
            if key is int:
                try:
                    k = int(k)
                except ValueError:
                    raise CodecError(f"{place}[{k}]", "the key must be a whole number") from None
            out[k] = from_data(item, v, f"{place}[{k}]", localns)
        return out
    if hint is bool:
        if not isinstance(data, bool):
            raise CodecError(place, f"{_kind(data)} where true or false belongs")
        return data
    if hint is int:
        if isinstance(data, bool) or not isinstance(data, int):
            raise CodecError(place, f"{_kind(data)} where a whole number belongs")
        return data
    if hint is float:
        if isinstance(data, bool) or not isinstance(data, int | float):
            raise CodecError(place, f"{_kind(data)} where a number belongs")
        return float(data)
    if hint is str:
        if not isinstance(data, str):
            raise CodecError(place, f"{_kind(data)} where text belongs")
        return data
    raise TypeError(f"{place}: the codec cannot read type {hint!r}")


def _union(args: tuple, data, place: str, localns):
    if data is None:
        if type(None) in args:
            return None
        raise CodecError(place, "null where a value belongs")
    members = [a for a in args if a is not type(None)]
    if _tagged(args):
        classes = {a.__name__: a for a in members if dataclasses.is_dataclass(a)}
        if isinstance(data, dict) and any(k in classes for k in data):
            other = next((k for k in data if k not in classes), None)
            if other is not None or len(data) > 1:
                raise CodecError(f"{place}.{other or list(data)[1]}",
                                 f"not alone: one key naming one of {', '.join(classes)} "
                                 "belongs here")
            name, inner = next(iter(data.items()))
            return _dataclass(classes[name], inner, f"{place}.{name}", localns)
    if len(members) == 1:
        return from_data(members[0], data, place, localns)
    problems = []
    for member in members:
        if _tagged(args) and dataclasses.is_dataclass(member):
            continue
        try:
            return from_data(member, data, place, localns)
        except CodecError as error:
            problems.append(error.problem)
    tags = [a.__name__ for a in members if dataclasses.is_dataclass(a)] if _tagged(args) else []
    expected = f"an object with one key of {', '.join(tags)}" if tags else ""
    raise CodecError(place, "; ".join(filter(None, [expected, *problems]))
                     or f"{_kind(data)} fits none of {args}")


def _dataclass(cls: type, data, place: str, localns):
    if not isinstance(data, dict):
        raise CodecError(place, f"{_kind(data)} where an object ({cls.__name__}) belongs")
    hints = field_hints(cls, localns)
    prefix = f"{place}." if place else ""
    for name in data:
        if name not in hints:
            raise CodecError(f"{prefix}{name}", f"{cls.__name__} has no field {name!r}")
    values = {}
    for f in dataclasses.fields(cls):
        if not f.init:
            continue
        if f.name in data:
            values[f.name] = from_data(hints[f.name], data[f.name], f"{prefix}{f.name}",
                                       localns)
        elif f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
            raise CodecError(f"{prefix}{f.name}", f"{cls.__name__} needs this field")
    return cls(**values)


def _kind(data) -> str:
    if data is None:
        return "null"
    if isinstance(data, bool):
        return f"{str(data).lower()}"
    if isinstance(data, dict):
        return "an object"
    if isinstance(data, list):
        return "a list"
    return repr(data)
