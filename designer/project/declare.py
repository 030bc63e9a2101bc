"""One declaration per attribute: what the XML, the checks, the GUI, the study factors and
the docs of a project element are derived from.

A model class declares each attribute once, as a dataclass field made by :func:`attr`
(its XML name, unit, range, default, one-line doc, GUI label and, if a study may vary
it, the factor's name), and the class itself with :func:`element` (its XML tag, title
and where it lives in the project); a field made by :func:`group` holds a small declared
class whose attributes sit on the holder's element (a point's X, Y, Z). From that:

* ``xml_to_model`` / ``model_to_xml`` read and write the element's attributes
  (:func:`designer.project.xml_to_model.read_declared`, ``model_to_xml.write_declared``);
* :mod:`designer.project.validate_declared` checks every single-field range, with the
  located message ``<tag>: name = value must be from low to high unit``;
* the GUI builds the field's spin box (limits, suffix, tooltip) from it
  (``designer.gui.qt.widgets.declared_field``), and the Effects panel a whole group;
* :mod:`designer.study.factors` makes a factor (get/set, its ``designer study factors``
  line) of every attribute with ``factor=``, and a replicate draw of every seed with
  ``draw=``;
* :func:`attribute_table` writes the docs' table, :mod:`designer.project.xsd_gen` the
  XSD (its elements' structure declared in :mod:`designer.project.declare_structure`).

Rules across fields (e.g. highest > lowest) stay hand-written beside the element's
checks. This module is lxml-, Qt- and numpy-free: the model imports it.
"""

from __future__ import annotations

import dataclasses
import math
import types
import typing
from dataclasses import MISSING, dataclass
from typing import Any, Literal

#: how a change of a factor's value is carried out (see designer.study.factors)
Stage = Literal["render", "processing"]

#: the range of every random seed: a whole number that fits 31 bits (the replicate
#: seeds, Qt's spin boxes)
SEED_RANGE = (0, 2147483647)


@dataclass(frozen=True)
class Attr:
    """The declaration of one attribute (see :func:`attr`)."""

    doc: str
    unit: str = ""
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    xml: str | None = None
    label: str | None = None
    factor: str | None = None
    #: False: left out of the written XML while it has its default (optional terms)
    write_default: bool = True
    #: GUI: decimals and step of the spin box (ints ignore them)
    decimals: int = 3
    step: float = 0.1
    #: GUI: the value shown as this text instead of its number (e.g. "off", "auto")
    special: str | None = None
    #: the child element that holds the attribute (e.g. a moving object's "path")
    child: str | None = None
    #: the XSD simple type of a text value ("d:Identifier", "xs:dateTime"; xs:string)
    xsd: str | None = None
    #: the value an absent XML attribute reads as, when not the field's default
    absent: Any = None
    #: False: ``absent`` is not given (an absent attribute reads as the field's default)
    has_absent: bool = False
    #: a seed: the study's replicate draw that re-seeds it (designer.study.factors.DRAWS)
    draw: str | None = None
    #: True: the value is the text of the child element ``<xml>``, not an attribute
    text: bool = False


def attr(default: Any = MISSING, *, doc: str, unit: str = "",
         range: tuple[float | None, float | None] = (None, None),
         low_open: bool = False, high_open: bool = False, xml: str | None = None,
         label: str | None = None, factor: str | None = None, write_default: bool = True,
         decimals: int = 3, step: float = 0.1, special: str | None = None,
         child: str | None = None, xsd: str | None = None, absent: Any = MISSING,
         draw: str | None = None, text: bool = False) -> Any:
    """A dataclass field carrying its declaration: ``range`` (low, high) is inclusive
    unless ``low_open``/``high_open``; ``xml`` defaults to the field's name with ``-`` for
    ``_``; ``factor`` names the study factor that varies it; ``child`` the child element
    the attribute sits on; ``xsd`` the XSD simple type of a text value; ``absent`` what
    an absent XML attribute reads as when that is not the default (e.g. None); ``draw``
    names the study's replicate draw that re-seeds a seed; ``text`` makes the value the
    text of a child element ``<xml>`` instead of an attribute."""
    low, high = range
    meta = Attr(doc=doc, unit=unit, low=low, high=high, low_open=low_open,
                high_open=high_open, xml=xml, label=label, factor=factor,
                write_default=write_default, decimals=decimals, step=step, special=special,
                child=child, xsd=xsd, absent=None if absent is MISSING else absent,
                has_absent=absent is not MISSING, draw=draw, text=text)
    return dataclasses.field(default=default, metadata={"attr": meta})


@dataclass(frozen=True)
class Element:
    """The declaration of an element class (see :func:`element`)."""

    tag: str
    title: str
    #: where the one element of this kind lives in a project ("scene.lighting.clouds"),
    #: None for elements that come in lists
    path: str | None = None
    stage: Stage = "render"
    #: the values it gets when switched on in the GUI or by a factor, beyond its defaults
    on: tuple[tuple[str, Any], ...] = ()
    #: fields whose attributes are written first (the rest follow in field order)
    first: tuple[str, ...] = ()


def group() -> Any:
    """A dataclass field holding an attribute group: a small declared dataclass (a point's
    X, Y, Z; three standard deviations) whose attributes sit on the element of the class
    that holds it, not on an element of their own."""
    return dataclasses.field(metadata={"group": True})


def element(tag: str, *, title: str, path: str | None = None, stage: Stage = "render",
            on: dict[str, Any] | None = None, first: tuple[str, ...] = ()):
    """Class decorator declaring a model class as the element ``<tag>``."""
    def deco(cls):
        cls.__element__ = Element(tag, title, path, stage, tuple((on or {}).items()), first)
        return cls
    return deco


@dataclass(frozen=True)
class Declared:
    """One declared attribute of a class: its field name, declaration and value type."""

    name: str
    attr: Attr
    #: float, int, bool or str
    base: type
    optional: bool
    choices: tuple[str, ...] | None
    default: Any

    @property
    def xml(self) -> str:
        return self.attr.xml or self.name.replace("_", "-")

    @property
    def required(self) -> bool:
        return self.default is MISSING

    @property
    def xml_default(self) -> Any:
        """What an absent XML attribute reads as (MISSING: it is required)."""
        return self.attr.absent if self.attr.has_absent else self.default

    @property
    def label(self) -> str:
        return self.attr.label or self.xml.replace("-", " ")

    def in_range(self, value: Any) -> bool:
        a = self.attr
        if value is None:
            return self.optional
        if self.choices is not None:
            return value in self.choices
        if self.base not in (float, int):
            return True
        if not (isinstance(value, int | float) and math.isfinite(value)):
            return False
        if a.low is not None and (value <= a.low if a.low_open else value < a.low):
            return False
        return not (a.high is not None and (value >= a.high if a.high_open else
                                            value > a.high))

    def range_text(self) -> str:
        """``from 0 to 1 m``, ``greater than 0 and at most 100 m/s``, ``one of a, b``."""
        a = dataclasses.replace(self.attr, low=_Bound(self.attr.low),
                                high=_Bound(self.attr.high))
        unit = f" {a.unit}" if a.unit else ""
        if self.choices is not None:
            return "one of " + ", ".join(self.choices)
        if a.low is None and a.high is None:
            return "a finite number"
        if a.high is None:
            return (f"greater than {a.low:g}" if a.low_open else f"at least {a.low:g}") + unit
        if a.low is None:
            return (f"below {a.high:g}" if a.high_open else f"at most {a.high:g}") + unit
        if not (a.low_open or a.high_open):
            return f"from {a.low:g} to {a.high:g}{unit}"
        low = f"greater than {a.low:g}" if a.low_open else f"at least {a.low:g}"
        return f"{low} and " + (f"below {a.high:g}" if a.high_open else
                                f"at most {a.high:g}") + unit


class _Bound(float):
    """A range bound that prints whole numbers in full (a seed's 2147483647, not 2.14748e+09)
    and others as ``:g`` does."""

    def __new__(cls, value):
        return None if value is None else super().__new__(cls, value)

    def __init__(self, value):
        self.whole = isinstance(value, int)

    def __format__(self, spec: str) -> str:
        return str(int(self)) if self.whole else format(float(self), spec)


def element_of(cls: type) -> Element | None:
    """The element declaration of a model class, or None."""
    return cls.__dict__.get("__element__")


def _value_type(hint: Any) -> tuple[type, bool, tuple[str, ...] | None]:
    optional = False
    args = typing.get_args(hint)
    if typing.get_origin(hint) in (typing.Union, types.UnionType):
        optional = type(None) in args
        rest = [a for a in args if a is not type(None)]
        hint = rest[0] if len(rest) == 1 else hint
    if typing.get_origin(hint) is Literal:
        return str, optional, tuple(typing.get_args(hint))
    if hint in (float, int, bool, str):
        return hint, optional, None
    raise TypeError(f"a declared attribute must be a number, bool, text or Literal, not {hint}")


_CACHE: dict[type, tuple[Declared, ...]] = {}


def declared(cls: type) -> tuple[Declared, ...]:
    """The declared attributes of ``cls`` in field order (empty for undeclared classes)."""
    if cls in _CACHE:
        return _CACHE[cls]
    if not dataclasses.is_dataclass(cls):
        return ()
    hints = None
    out = []
    for f in dataclasses.fields(cls):
        a = f.metadata.get("attr")
        if a is None:
            continue
        if hints is None:
            hints = typing.get_type_hints(cls)
        base, optional, choices = _value_type(hints[f.name])
        default = f.default if f.default is not MISSING else MISSING
        out.append(Declared(f.name, a, base, optional, choices, default))
    _CACHE[cls] = tuple(out)
    return _CACHE[cls]


def groups(cls: type) -> tuple[tuple[str, type], ...]:
    """(field name, class) of every attribute group ``cls`` holds (:func:`group`)."""
    if not dataclasses.is_dataclass(cls):
        return ()
    return tuple((f.name, field_class(cls, f.name)) for f in dataclasses.fields(cls)
                 if f.metadata.get("group"))


def attributes(cls: type) -> tuple[tuple[str | None, Declared], ...]:
    """Every declared attribute on the element of ``cls``, in field order: (None, its own
    declaration) or (the group field, a declaration of the group's class)."""
    out: list[tuple[str | None, Declared]] = []
    own = {d.name: d for d in declared(cls)}
    group_of = dict(groups(cls))
    for f in dataclasses.fields(cls) if dataclasses.is_dataclass(cls) else ():
        if f.name in own:
            out.append((None, own[f.name]))
        elif f.name in group_of:
            out += [(f.name, d) for d in declared(group_of[f.name])]
    return tuple(out)


def holder(obj: Any, group_name: str | None) -> Any:
    """The object that holds an attribute of :func:`attributes`: ``obj`` or its group."""
    return obj if group_name is None else getattr(obj, group_name)


def declared_field(cls: type, name: str) -> Declared:
    """The declaration of field ``name`` of ``cls`` (KeyError if it has none)."""
    for d in declared(cls):
        if d.name == name:
            return d
    raise KeyError(f"{cls.__name__}.{name} is not declared")


def switched_on(cls: type) -> Any:
    """An instance of an element class as it is when switched on: its defaults and the
    values its declaration gives for the rest."""
    el = element_of(cls)
    return cls(**dict(el.on if el is not None else ()))


def walk(obj: Any):
    """Every dataclass instance inside ``obj`` (itself first), depth first, in field order."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        yield obj
        for f in dataclasses.fields(obj):
            yield from walk(getattr(obj, f.name))
    elif isinstance(obj, tuple | list):
        for item in obj:
            yield from walk(item)


def field_class(cls: type, name: str) -> type:
    """The dataclass a field holds (``X | None`` → X)."""
    hint = typing.get_type_hints(cls)[name]
    args = [a for a in typing.get_args(hint) if a is not type(None)] or [hint]
    candidates = [a for a in args if dataclasses.is_dataclass(a)]
    if len(candidates) != 1:
        raise TypeError(f"{cls.__name__}.{name} does not hold one kind of element")
    return candidates[0]


def declared_elements(root: type) -> list[type]:
    """Every declared element class reachable from the dataclass ``root`` by its fields'
    type hints, in field order (each once)."""
    seen: list[type] = []

    def visit(cls: type) -> None:
        if cls in seen or not dataclasses.is_dataclass(cls):
            return
        seen.append(cls)
        for hint in typing.get_type_hints(cls).values():
            for arg in _classes_in(hint):
                visit(arg)

    visit(root)
    return [c for c in seen if element_of(c) is not None]


def _classes_in(hint: Any) -> list[type]:
    if isinstance(hint, type):
        return [hint]
    out = []
    for arg in typing.get_args(hint):
        out += _classes_in(arg)
    return out


def attribute_table(cls: type) -> str:
    """The docs' Markdown table of an element's attributes."""
    el = element_of(cls)
    rows = [f"`<{el.tag}>` — {el.title}" if el else cls.__name__, "",
            "| attribute | unit | range | default | meaning | study factor |",
            "|---|---|---|---|---|---|"]
    for _, d in attributes(cls):
        value = d.xml_default
        default = "required" if d.required else ("none" if value is None else
                                                  str(value).lower()
                                                  if isinstance(value, bool) else f"{value}")
        rng = d.range_text() if (d.choices or d.base in (int, float)) else ""
        rows.append(f"| `{d.xml}` | {d.attr.unit} | {rng} | {default} | {d.attr.doc} | "
                    f"{'`' + d.attr.factor + '`' if d.attr.factor else ''} |")
    return "\n".join(rows) + "\n"


def element_at(root: Any, path: str) -> Any:
    """The element at the dotted ``path`` of ``root`` (None when it, or one above it, is
    absent)."""
    obj = root
    for part in path.split("."):
        obj = getattr(obj, part)
        if obj is None:
            return None
    return obj


def value_at(root: Any, path: str, name: str) -> Any:
    """Field ``name`` of the element at the dotted ``path`` of ``root`` (None when the
    element, or one above it, is absent)."""
    obj = root
    for part in path.split("."):
        obj = getattr(obj, part)
        if obj is None:
            return None
    return getattr(obj, name)


def with_value(root: Any, path: str, name: str, value: Any) -> Any:
    """``root`` with field ``name`` of the element at ``path`` set to ``value``; an absent
    element on the way is switched on (:func:`switched_on`) — ValueError naming it when it
    has required values the declaration cannot give."""
    head, _, rest = path.partition(".")
    child = getattr(root, head)
    if child is None:
        cls = field_class(type(root), head)
        try:
            child = switched_on(cls)
        except TypeError:
            el = element_of(cls)
            tag = el.tag if el is not None else head.replace("_", "-")
            raise ValueError(f"the base project has no <{tag}>; add one to vary it") from None
    child = (dataclasses.replace(child, **{name: value}) if not rest
             else with_value(child, rest, name, value))
    return dataclasses.replace(root, **{head: child})
