"""The XML structure of the model classes: what the project XSD's elements, sequences,
choices and named types are generated from (:mod:`designer.project.xsd_gen`).

:mod:`designer.project.declare` declares each attribute once; this module declares the
rest of a class's XML form, beside the class:

* a field holding a model class (or ``A | B`` of them, or a tuple of them) is a child
  element, derived from its type: ``X | None`` and a tuple defaulting to ``()`` are
  optional, a union is an ``xs:choice``, a tuple repeats (at least once unless it
  defaults to ``()``). :func:`nested` gives such a field the documentation of the
  element where it is used, a tag, a wrapper element (``<cameras>`` around the
  ``<camera>`` list) or a simple type (a text element, a list held as text);
* :func:`schema_attrs` declares XML attributes whose value the reader parses by hand
  (a colour triple, a facade's end points): the schema types them, the checks judge them;
  :func:`unwritten` a field the file does not hold (where an element was read);
* :func:`xml_type` declares a class's named complex type, the child elements holding
  attributes of the class (``Attr.child``), and where the default order (field order,
  ``Element.first`` first) or an ``xs:sequence`` does not fit: the order of the content,
  choices across fields, ``xs:all``.

The documentation of an element is the first paragraph of its class's docstring (of a
named type: the type's; the element that refers to it is documented by its field).
Every field of a class reachable from the root is one of these (or ``attr``/``group``):
the generator refuses a field it cannot place. The study model (designer.study.spec)
declares its XML form the same way. This module is lxml-free: the model imports it.
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import MISSING, dataclass
from typing import Any


@dataclass(frozen=True)
class ListOf:
    """A whitespace-separated list of ``item`` (an XSD type), of ``min_length`` to
    ``max_length`` items when given."""

    item: str
    min_length: int | None = None
    max_length: int | None = None


@dataclass(frozen=True)
class OneOf:
    """A value of one of the XSD types ``members`` or one of the words ``words`` (no
    members: one of the words)."""

    members: tuple[str, ...]
    words: tuple[str, ...]


@dataclass(frozen=True)
class Restricted:
    """A value of the XSD type ``base`` within ``facets`` ((facet, value), e.g.
    ("minExclusive", "0"))."""

    base: str
    facets: tuple[tuple[str, str], ...]


#: an XSD simple type: a name ("d:FiniteDouble"), a list, a union or a restriction
SimpleType = str | ListOf | OneOf | Restricted


@dataclass(frozen=True)
class XsdAttr:
    """An XML attribute the schema types and documents: ``xsd`` None takes the choices of
    the field's ``Literal`` type."""

    name: str
    doc: str
    xsd: SimpleType | None = None
    required: bool = False


@dataclass(frozen=True)
class Wrapper:
    """An element around a repeated child (``<cameras>`` around ``<camera>``): its tag, its
    named type and the type's documentation."""

    tag: str
    type_name: str | None = None
    doc: str = ""


@dataclass(frozen=True)
class Nested:
    """The XML form of a field holding elements (see :func:`nested`)."""

    doc: str | None = None
    tag: str | None = None
    optional: bool | None = None
    wrapper: Wrapper | None = None
    item_doc: str | None = None
    xsd: SimpleType | None = None
    item_attrs: tuple[XsdAttr, ...] = ()
    min_items: int | None = None
    alone: tuple[type, ...] = ()
    member_docs: tuple[tuple[type, str], ...] = ()
    any_element: bool = False


def nested(default: Any = MISSING, *, doc: str | None = None, tag: str | None = None,
           optional: bool | None = None, wrapper: Wrapper | None = None,
           item_doc: str | None = None, xsd: SimpleType | None = None,
           item_attrs: tuple[XsdAttr, ...] = (), min_items: int | None = None,
           alone: tuple[type, ...] = (), member_docs: dict[type, str] | None = None,
           any_element: bool = False, factory: Any = MISSING) -> Any:
    """A dataclass field holding child elements: ``doc`` documents the element where it is
    used (required for a named type's element, else the class docstring serves), ``tag``
    names it (default: the class's ``@element`` tag, or the field name with ``-``),
    ``optional`` overrides the derived occurrence, ``wrapper`` puts the elements in an
    element of their own (documented by ``doc``; ``item_doc`` then documents an item of a
    named type), ``xsd`` makes it a text element of that simple type, ``item_attrs``
    makes each item of a tuple of plain values an empty element with these attributes,
    ``min_items`` is the fewest items, and ``alone`` names members of a union that
    replace the whole content of the holding element (an orthophoto: no tiling);
    ``member_docs`` documents the elements of a union's members of named types;
    ``any_element``: any one element of the namespace, not checked (an inline project)."""
    meta = {"nested": Nested(doc, tag, optional, wrapper, item_doc, xsd, tuple(item_attrs),
                             min_items, tuple(alone), tuple((member_docs or {}).items()),
                             any_element)}
    if factory is not MISSING:
        return dataclasses.field(default_factory=factory, metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


def unwritten(default: Any = MISSING, *, factory: Any = MISSING) -> Any:
    """A dataclass field the file does not hold (where an element was read, the file's
    own path)."""
    if factory is not MISSING:
        return dataclasses.field(default_factory=factory, metadata={"unwritten": True})
    return dataclasses.field(default=default, metadata={"unwritten": True})


def schema_attrs(default: Any = MISSING, *attrs: XsdAttr) -> Any:
    """A dataclass field written as the XML attributes ``attrs`` (parsed by hand, e.g. a
    size as length-m, width-m, height-m)."""
    return dataclasses.field(default=default, metadata={"schema_attrs": tuple(attrs)})


@dataclass(frozen=True)
class Choice:
    """An ``xs:choice`` of content items (field names, holder tags or :class:`Seq`)."""

    items: tuple[Any, ...]
    optional: bool = False
    repeated: bool = False


@dataclass(frozen=True)
class Seq:
    """An ``xs:sequence`` of content items inside a :class:`Choice`."""

    items: tuple[Any, ...]


@dataclass(frozen=True)
class XmlType:
    """The XML structure of a class beyond its fields' declarations (see :func:`xml_type`)."""

    tag: str | None = None
    type_name: str | None = None
    holders: tuple[tuple[str, str, bool], ...] = ()
    content: tuple[Any, ...] | None = None
    all: bool = False
    lead: tuple[str, ...] = ()
    extra_attrs: tuple[XsdAttr, ...] = ()


def xml_type(*, tag: str | None = None, named: bool | str = False,
             holders: dict[str, tuple[str, bool]] | None = None,
             content: tuple[Any, ...] | None = None, all: bool = False,
             lead: tuple[str, ...] = (), extra_attrs: tuple[XsdAttr, ...] = ()):
    """Class decorator: ``tag`` (an element no field names: the root), ``named`` (True: a
    named complex type of the class's name, or that name), ``holders`` (child tag →
    (documentation, optional) of each child element holding attributes declared with
    ``child=``), ``content`` (the content's order: field names, holder tags,
    :class:`Choice`, :class:`Seq`, and ``...`` for the rest in the default order),
    ``all`` (an ``xs:all``: any order), ``lead`` (fields whose ``schema_attrs`` come
    before the declared attributes; the others follow them) and ``extra_attrs``
    (attributes the reader checks but the class does not keep, e.g. a schema version;
    first of all)."""
    def deco(cls):
        type_name = (cls.__name__ if named is True else named) or None
        cls.__xml_type__ = XmlType(tag, type_name,
                                   tuple((t, d, o) for t, (d, o) in (holders or {}).items()),
                                   content, all, tuple(lead), tuple(extra_attrs))
        return cls
    return deco


def xml_type_of(cls: type) -> XmlType:
    """The XML structure declared on ``cls`` (an empty one when none is)."""
    return cls.__dict__.get("__xml_type__", XmlType())


def nested_of(f: dataclasses.Field) -> Nested | None:
    return f.metadata.get("nested")


def is_unwritten(f: dataclasses.Field) -> bool:
    return bool(f.metadata.get("unwritten"))


def schema_attrs_of(f: dataclasses.Field) -> tuple[XsdAttr, ...]:
    return f.metadata.get("schema_attrs", ())


_ROLE = re.compile(r":\w+:`~?([^`]+)`")


def class_doc(cls: type) -> str:
    """The first paragraph of the class's docstring on one line, reST markup dropped: the
    documentation of its element in the schema ("" without a docstring)."""
    text = (cls.__dict__.get("__doc__") or "").strip()
    if text.startswith(cls.__name__ + "("):  # the signature dataclass writes without one
        return ""
    first = text.split("\n\n", 1)[0]
    first = _ROLE.sub(r"\1", first).replace("``", "")
    return " ".join(first.split())
