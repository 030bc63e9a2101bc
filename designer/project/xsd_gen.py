"""The project XSD (``schema/designer-project-1.0.xsd``), generated whole from the model.

Nothing in the file is written by hand: :func:`generate` walks the model's classes from
:class:`designer.project.model.Project` and writes

* the preamble and the named simple types of :mod:`designer.project.xsd_types`;
* one element per field holding a model class (:mod:`designer.project.declare_structure`
  derives sequences, choices, optional and repeated elements, wrappers and named complex
  types from the field types and :func:`~designer.project.declare_structure.xml_type`),
  documented by the first paragraph of the class docstring, or by the field's
  ``nested(doc=...)`` where it refers to a named type;
* one ``xs:attribute`` per declared attribute (:mod:`designer.project.declare`) with its
  name, type (range facets, open or closed; choices as an enumeration; a text value's
  ``xsd=`` type), ``use="required"`` or its default, and its documentation (or
  ``xs:element`` per value held as the text of a child element), and those of
  ``schema_attrs``.

``python -m designer.project.xsd_gen`` rewrites the committed file; ``--check`` exits 1
when it differs from the model.

Adding an element (e.g. an image effect) is adding its model class: an ``@element``
dataclass with a docstring (its first paragraph documents the element) and ``attr()``
fields, and a field holding it in its parent (``Effects``: ``name: NewEffect | None =
None``; an effect also has its module in ``designer/effects``, see docs/effects.md).
Then ``python -m designer.project.xsd_gen`` writes the schema; no XSD edit.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import types
import typing
from pathlib import Path
from xml.sax.saxutils import escape, quoteattr

from designer.project.declare import declared, element_of, groups
from designer.project.declare_structure import (
    Choice,
    ListOf,
    Nested,
    OneOf,
    Restricted,
    Seq,
    XsdAttr,
    class_doc,
    is_unwritten,
    nested_of,
    schema_attrs_of,
    xml_type_of,
)
from designer.project.xsd_values import attribute_xsd, element_xsd

_STEP = "  "


def _indent(lines: list[str], depth: int = 1) -> list[str]:
    return [_STEP * depth + line if line else "" for line in lines]


def _annotation(doc: str | None) -> list[str]:
    if not doc:
        return []
    return [f"{_STEP}<xs:annotation><xs:documentation>{escape(doc)}"
            "</xs:documentation></xs:annotation>"]


def _occurs(optional: bool, repeated: bool = False, low: int | None = None) -> str:
    out = ""
    if optional:
        out += ' minOccurs="0"'
    elif low is not None and low != 1:
        out += f' minOccurs="{low}"'
    if repeated:
        out += ' maxOccurs="unbounded"'
    return out


def _simple_type(xsd) -> tuple[str | None, list[str]]:
    """(a type name, or None and the lines of an inline xs:simpleType)."""
    if isinstance(xsd, str):
        return xsd, []
    if isinstance(xsd, ListOf):
        if xsd.min_length is None and xsd.max_length is None:
            return None, [f'<xs:simpleType><xs:list itemType="{xsd.item}"/></xs:simpleType>']
        facets = ([f'    <xs:minLength value="{xsd.min_length}"/>']
                  if xsd.min_length is not None else [])
        facets += ([f'    <xs:maxLength value="{xsd.max_length}"/>']
                   if xsd.max_length is not None else [])
        return None, ["<xs:simpleType>", "  <xs:restriction>", "    <xs:simpleType>",
                      f'      <xs:list itemType="{xsd.item}"/>', "    </xs:simpleType>",
                      *facets, "  </xs:restriction>", "</xs:simpleType>"]
    if isinstance(xsd, OneOf) and not xsd.members:
        return None, _enumeration(xsd.words)
    if isinstance(xsd, Restricted):
        return None, ["<xs:simpleType>", f'  <xs:restriction base="{xsd.base}">',
                      *(f"    <xs:{facet} value={quoteattr(value)}/>"
                        for facet, value in xsd.facets),
                      "  </xs:restriction>", "</xs:simpleType>"]
    if isinstance(xsd, OneOf):
        return None, ["<xs:simpleType>",
                      f'  <xs:union memberTypes="{" ".join(xsd.members)}">',
                      *_enumeration(xsd.words, 2), "  </xs:union>", "</xs:simpleType>"]
    raise TypeError(f"not an XSD simple type: {xsd!r}")


def _enumeration(words, depth: int = 0) -> list[str]:
    return _indent(["<xs:simpleType>", '  <xs:restriction base="xs:string">',
                    *(f"    <xs:enumeration value={quoteattr(w)}/>" for w in words),
                    "  </xs:restriction>", "</xs:simpleType>"], depth)


def _schema_attr(a: XsdAttr, choices: tuple[str, ...] | None = None) -> list[str]:
    """The xs:attribute of a :class:`XsdAttr` (``choices``: of the field's Literal)."""
    if a.xsd is None:
        type_name, simple = None, _enumeration(choices or ())
    else:
        type_name, simple = _simple_type(a.xsd)
    head = f'<xs:attribute name="{a.name}"'
    head += f' type="{type_name}"' if type_name else ""
    head += ' use="required"' if a.required else ""
    return [head + ">", *_annotation(a.doc), *_indent(simple), "</xs:attribute>"]


def _members(hint) -> tuple[bool, list]:
    """(repeated, the member types) of a field's type: ``X | None``, ``A | B``,
    ``tuple[X, ...]``, ``tuple[A | B, ...]``."""
    def union(h):
        if typing.get_origin(h) in (typing.Union, types.UnionType):
            return [a for a in typing.get_args(h) if a is not type(None)]
        return [h]

    members = union(hint)
    if len(members) == 1 and typing.get_origin(members[0]) is tuple \
            and typing.get_args(members[0])[-1:] == (Ellipsis,):
        return True, union(typing.get_args(members[0])[0])
    return False, members


class _Schema:
    """The XSD's elements and named complex types, built by walking the model."""

    def __init__(self) -> None:
        #: type name → its lines (None while it is being built), in the order first met
        self.named: dict[str, list[str] | None] = {}

    def named_type(self, name: str, doc: str, body) -> None:
        if name in self.named:
            return
        self.named[name] = None
        lines = body()
        self.named[name] = [f'<xs:complexType name="{name}">', *_annotation(doc),
                            *_indent(lines), "</xs:complexType>"]

    # ------------------------------------------------------------------ a class
    def body(self, cls: type) -> list[str]:
        """The content and attributes of the complex type of ``cls``."""
        return self.content(cls) + self.attribute_lines(cls)

    def attribute_lines(self, cls: type, child: str | None = None) -> list[str]:
        """The attributes of the element of ``cls`` (``child``: of its child element
        ``<child>``): the declared ones in field order, those of ``schema_attrs`` after
        them (before them: the fields the class's ``xml_type(lead=...)`` names)."""
        own = {d.name: d for d in declared(cls)}
        group_of = dict(groups(cls))
        hints = typing.get_type_hints(cls)
        lead = xml_type_of(cls).lead
        declared_lines: list[str] = []
        schema_lines: dict[bool, list[str]] = {True: [], False: []}
        for f in dataclasses.fields(cls):
            d = own.get(f.name)
            if d is not None and not d.attr.text and d.attr.child == child:
                declared_lines += attribute_xsd(d, "").split("\n")
            elif f.name in group_of and child is None:
                declared_lines += [line for g in declared(group_of[f.name])
                                   for line in attribute_xsd(g, "").split("\n")]
            elif schema_attrs_of(f) and child is None:
                choices = _literal_choices(hints[f.name])
                schema_lines[f.name in lead] += [line for a in schema_attrs_of(f)
                                                 for line in _schema_attr(a, choices)]
        extra = [line for a in xml_type_of(cls).extra_attrs for line in _schema_attr(a)]
        if child is not None:
            extra = []
        return extra + schema_lines[True] + declared_lines + schema_lines[False]

    def items(self, cls: type) -> dict[str, tuple]:
        """key → content item of ``cls`` in the default order: field name → ("text",
        declared) or ("field", field); holder tag → ("holder", tag)."""
        own = {d.name: d for d in declared(cls)}
        fields = dataclasses.fields(cls)
        wrapped = {n.wrapper.tag for f in fields
                   if (n := nested_of(f)) is not None and n.wrapper is not None}
        out: list[tuple[str, tuple]] = []
        for f in fields:
            d = own.get(f.name)
            if d is not None:
                if d.attr.text:
                    out.append((f.name, ("text", d)))
                elif d.attr.child and d.attr.child not in wrapped and \
                        all(k != d.attr.child for k, _ in out):
                    out.append((d.attr.child, ("holder", d.attr.child)))
            elif not (f.metadata.get("group") or schema_attrs_of(f) or is_unwritten(f)):
                out.append((f.name, ("field", f)))
        el = element_of(cls)
        first = el.first if el is not None else ()
        out.sort(key=lambda kv: kv[0] not in first)
        return dict(out)

    def content(self, cls: type) -> list[str]:
        xt = xml_type_of(cls)
        items = self.items(cls)
        spec = xt.content if xt.content is not None else tuple(items)
        listed = set(_keys(spec))
        unknown = listed - set(items)
        if unknown:
            raise ValueError(f"{cls.__name__}'s xml_type content names {sorted(unknown)}, "
                             "which are not its fields or holder elements")
        rest = [k for k in items if k not in listed]
        body = self.entries(cls, items, spec, rest)
        if not body:
            return []
        alone = [m for k, (kind, f) in items.items() if kind == "field"
                 for m in (nested_of(f) or _NO_NESTED).alone]
        if alone:
            return ["<xs:choice>", *_indent(["<xs:sequence>", *_indent(body), "</xs:sequence>",
                                             *(line for m in alone for line in
                                               self.class_element(m, element_of(m).tag,
                                                                  class_doc(m), ""))]),
                    "</xs:choice>"]
        tag = "xs:all" if xt.all else "xs:sequence"
        return [f"<{tag}>", *_indent(body), f"</{tag}>"]

    def entries(self, cls: type, items: dict, spec, rest: list[str]) -> list[str]:
        out: list[str] = []
        for entry in spec:
            if entry is Ellipsis:
                out += [line for k in rest for line in self.item(cls, items[k])]
            elif isinstance(entry, Choice):
                out += [f"<xs:choice{_occurs(entry.optional, entry.repeated)}>",
                        *_indent(self.entries(cls, items, entry.items, rest)), "</xs:choice>"]
            elif isinstance(entry, Seq):
                out += ["<xs:sequence>", *_indent(self.entries(cls, items, entry.items, rest)),
                        "</xs:sequence>"]
            else:
                out += self.item(cls, items[entry])
        return out

    def item(self, cls: type, item: tuple) -> list[str]:
        kind, what = item
        if kind == "text":
            return element_xsd(what, "").split("\n")
        if kind == "holder":
            holders = {t: (doc, optional) for t, doc, optional in xml_type_of(cls).holders}
            if what not in holders:
                raise ValueError(f"{cls.__name__} declares attributes on <{what}> but no "
                                 f"holders={{'{what}': (doc, optional)}} in its xml_type")
            doc, optional = holders[what]
            return [f'<xs:element name="{what}"{_occurs(optional)}>', *_annotation(doc),
                    *_indent(["<xs:complexType>",
                              *_indent(self.attribute_lines(cls, what)),
                              "</xs:complexType>"]), "</xs:element>"]
        return self.field(cls, what)

    # ------------------------------------------------------------------ a field
    def field(self, cls: type, f: dataclasses.Field) -> list[str]:
        n = nested_of(f) or _NO_NESTED
        has_default = (f.default is not dataclasses.MISSING
                       or f.default_factory is not dataclasses.MISSING)
        optional = n.optional if n.optional is not None else has_default
        if n.any_element:
            return [f'<xs:any namespace="##targetNamespace" processContents="skip"'
                    f'{_occurs(optional)}/>']
        if n.xsd is not None:
            type_name, simple = _simple_type(n.xsd)
            head = f'<xs:element name="{n.tag or f.name.replace("_", "-")}"'
            head += f' type="{type_name}"' if type_name else ""
            return [head + _occurs(optional) + ">", *_annotation(n.doc), *_indent(simple),
                    "</xs:element>"]
        repeated, members = _members(typing.get_type_hints(cls)[f.name])
        if n.wrapper is None:
            return self.elements(f, n, members, n.doc, optional, repeated, n.min_items)
        w = n.wrapper
        inner = ["<xs:sequence>",
                 *_indent(self.elements(f, n, members, n.item_doc, False, repeated,
                                        n.min_items)),
                 "</xs:sequence>", *self.attribute_lines(cls, w.tag)]
        if w.type_name:
            self.named_type(w.type_name, w.doc, lambda: inner)
            return [f'<xs:element name="{w.tag}" type="d:{w.type_name}"{_occurs(optional)}>',
                    *_annotation(n.doc), "</xs:element>"]
        return [f'<xs:element name="{w.tag}"{_occurs(optional)}>', *_annotation(n.doc),
                *_indent(["<xs:complexType>", *_indent(inner), "</xs:complexType>"]),
                "</xs:element>"]

    def elements(self, f: dataclasses.Field, n: Nested, members: list, doc: str | None,
                 optional: bool, repeated: bool, low: int | None) -> list[str]:
        """The element(s) of a field's members: one element, or a choice of them."""
        occurs = _occurs(optional, repeated, low)
        classes = [m for m in members if dataclasses.is_dataclass(m) and m not in n.alone]
        if not classes:
            if not n.item_attrs:
                raise ValueError(f"field {f.name} holds no model class: declare it with "
                                 "attr(), nested(xsd=...), nested(item_attrs=...) or "
                                 "schema_attrs()")
            choices = _literal_choices(members[0])
            return [f'<xs:element name="{n.tag}"{occurs}>', *_annotation(doc),
                    *_indent(["<xs:complexType>",
                              *_indent([line for a in n.item_attrs
                                        for line in _schema_attr(a, choices)]),
                              "</xs:complexType>"]), "</xs:element>"]
        if len(classes) == 1:
            return self.class_element(classes[0], n.tag or _tag(classes[0], f), doc, occurs)
        return [f"<xs:choice{occurs}>",
                *_indent([line for m in classes
                          for line in self.class_element(m, _tag(m, f),
                                                         dict(n.member_docs).get(m), "")]),
                "</xs:choice>"]

    def class_element(self, cls: type, tag: str, doc: str | None, occurs: str) -> list[str]:
        """The element ``<tag>`` holding an instance of ``cls``: of its named type
        (documented by ``doc``), or with its type inline (documented by ``doc`` or the
        class docstring)."""
        xt = xml_type_of(cls)
        if xt.type_name:
            self.named_type(xt.type_name, class_doc(cls), lambda: self.body(cls))
            return [f'<xs:element name="{tag}" type="d:{xt.type_name}"{occurs}>',
                    *_annotation(doc), "</xs:element>"]
        return [f'<xs:element name="{tag}"{occurs}>', *_annotation(doc or class_doc(cls)),
                *_indent(["<xs:complexType>", *_indent(self.body(cls)), "</xs:complexType>"]),
                "</xs:element>"]


_NO_NESTED = Nested()


def _keys(spec) -> list[str]:
    out: list[str] = []
    for entry in spec:
        if isinstance(entry, Choice | Seq):
            out += _keys(entry.items)
        elif entry is not Ellipsis:
            out.append(entry)
    return out


def _tag(cls: type, f: dataclasses.Field) -> str:
    el = element_of(cls)
    return el.tag if el is not None else f.name.replace("_", "-")


def _literal_choices(hint) -> tuple[str, ...] | None:
    for h in [hint, *typing.get_args(hint)]:
        if typing.get_origin(h) is typing.Literal:
            return tuple(typing.get_args(h))
    return None


def generate(root: type | None = None) -> str:
    """The whole project XSD, generated from the model (``root``: the class of its root
    element, default :class:`designer.project.model.Project`)."""
    from designer.project import model as m
    from designer.project.xsd_types import SCHEMA_DOC, SIMPLE_TYPES

    return schema_text(root or m.Project, doc=SCHEMA_DOC, simple_types=SIMPLE_TYPES,
                       made_by="designer.project.xsd_gen",
                       source="designer/project/model.py")


def schema_text(root: type, *, doc: str, simple_types, made_by: str, source: str) -> str:
    """An XSD in the project namespace whose root element holds ``root`` (a class with
    ``xml_type(tag=...)``): the documentation ``doc``, the named simple types
    ``simple_types`` (:class:`designer.project.xsd_types.NamedSimpleType`), the root
    element and the named complex types met on the way; ``made_by`` (the generating
    module) and ``source`` (the model's file) are named in its first comment."""
    schema = _Schema()
    root_lines = [f'<xs:element name="{xml_type_of(root).tag}">',
                  *_annotation(class_doc(root)),
                  *_indent(["<xs:complexType>", *_indent(schema.body(root)),
                            "</xs:complexType>"]), "</xs:element>"]
    simple = [line for t in simple_types for line in [*_named_simple_type(t), ""]]
    named = [line for lines in schema.named.values() for line in [*lines, ""]]
    head = ['<?xml version="1.0" encoding="UTF-8"?>',
            f"<!-- Generated by python -m {made_by} from the model ({source}): edit the "
            "model, not this file. -->",
            '<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema"',
            '           xmlns:d="urn:designer:project:1"',
            '           targetNamespace="urn:designer:project:1"',
            '           elementFormDefault="qualified"',
            '           attributeFormDefault="unqualified"',
            '           version="1.0">', "",
            '  <xs:annotation>', '    <xs:documentation xml:lang="en">',
            *escape(doc).rstrip("\n").split("\n"),
            '    </xs:documentation>', '  </xs:annotation>', ""]
    return "\n".join([*head, *_indent(simple), *_indent(root_lines), "",
                      *_indent(named)]).rstrip() + "\n</xs:schema>\n"


def _named_simple_type(t) -> list[str]:
    """The lines of a :class:`designer.project.xsd_types.NamedSimpleType`: a restriction
    of its base by its facets (an enumeration value may carry its documentation), or a
    list of its base's items."""
    facets = []
    for facet, value, *value_doc in t.facets:
        if value_doc:
            facets.append(f"    <xs:{facet} value={quoteattr(value)}>"
                          f"{_annotation(value_doc[0])[0].strip()}</xs:{facet}>")
        else:
            facets.append(f"    <xs:{facet} value={quoteattr(value)}/>")
    if isinstance(t.base, ListOf):
        body = [f'  <xs:list itemType="{t.base.item}"/>']
        if facets:
            body = ["  <xs:restriction>", "    <xs:simpleType>",
                    f'      <xs:list itemType="{t.base.item}"/>', "    </xs:simpleType>",
                    *facets, "  </xs:restriction>"]
    else:
        body = [f'  <xs:restriction base="{t.base}">', *facets, "  </xs:restriction>"]
    return [f'<xs:simpleType name="{t.name}">', *_annotation(t.doc), *body,
            "</xs:simpleType>"]


def regenerate(argv: list[str] | None, *, prog: str, description: str, default_xsd: Path,
               generate_xsd, differs: str) -> int:
    """The command line of an XSD generator: rewrite the XSD (``--xsd``, default
    ``default_xsd``) with ``generate_xsd(text)``, or with ``--check`` only compare (exit 1
    naming ``differs``); 2 when the XSD cannot be generated."""
    parser = argparse.ArgumentParser(prog=prog, description=description)
    parser.add_argument("--check", action="store_true",
                        help=f"only compare; exit 1 when {differs}")
    parser.add_argument("--xsd", type=Path, default=None,
                        help=f"the XSD (default: the packaged schema/{default_xsd.name})")
    args = parser.parse_args(argv)
    path = args.xsd or default_xsd
    text = path.read_text(encoding="utf-8")
    try:
        new = generate_xsd(text)
    except ValueError as error:
        print(f"{path}: {error}", file=sys.stderr)
        return 2
    if new == text:
        return 0
    if args.check:
        print(f"{path}: {differs}; run python -m {prog.split()[-1]}", file=sys.stderr)
        return 1
    path.write_text(new, encoding="utf-8")
    return 0


def main(argv: list[str] | None = None) -> int:
    from designer.project.schema import schema_path

    return regenerate(argv, prog="python -m designer.project.xsd_gen",
                      description="Write the project XSD from the model.",
                      default_xsd=schema_path(), generate_xsd=lambda _text: generate(),
                      differs="the XSD differs from the model")

if __name__ == "__main__":
    sys.exit(main())
