"""The XSD of one declared value (designer.project.declare): an ``xs:attribute``, or an
``xs:element`` for a value held as the text of a child element, with its name, type
(range facets, open or closed; choices as an enumeration; a text value's ``xsd=`` type),
``use="required"`` or its default, and its documentation. Used by
:mod:`designer.project.xsd_gen`, which writes the whole schema.
"""

from __future__ import annotations

import dataclasses
from xml.sax.saxutils import escape

from designer.project.declare import Declared


def number_text(value: float | int) -> str:
    """A range bound or default as the XSD states it: whole numbers in full, others in
    the shortest form that reads back (``1e6``, ``0.5``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    text = repr(float(value))
    if "e" not in text and abs(value) >= 1e6 and float(value).is_integer():
        text = f"{value:.0e}" if float(f"{value:.0e}") == value else text
    return text.replace("e+0", "e").replace("e+", "e").replace("e-0", "e-")


#: units written out in the XSD's documentation
_UNIT_WORDS = {"deg": "degrees", "%": "percent", "m/px": "m per px"}


def documentation(d: Declared) -> str:
    """The attribute's xs:documentation: its doc, range (or choices) with unit, and
    ``required`` or its default."""
    if d.attr.unit in _UNIT_WORDS:
        d = dataclasses.replace(d, attr=dataclasses.replace(d.attr,
                                                            unit=_UNIT_WORDS[d.attr.unit]))
    # an ASCII first letter is capitalised; a symbol (σ, λ) keeps its case and meaning
    first = d.attr.doc[:1]
    parts = [(first.upper() if first.isascii() else first) + d.attr.doc[1:]]
    a = d.attr
    if d.choices is not None:
        parts.append(d.range_text())
    elif d.base in (int, float):
        if a.low is not None or a.high is not None:
            parts.append(d.range_text())
        elif a.unit:
            parts.append(f"in {a.unit}")
    if d.required:
        parts.append("required")
    elif d.xml_default is not None:
        parts.append(f"default {_value_text(d, d.xml_default)}")
    return "; ".join(parts) + "."


def _value_text(d: Declared, value) -> str:
    if d.base is bool:
        return "true" if value else "false"
    if d.base in (int, float):
        return number_text(value)
    return str(value)


def _type(d: Declared) -> tuple[str | None, list[str]]:
    """(the type attribute, or None and the lines of an inline xs:simpleType)."""
    a = d.attr
    if d.choices is not None:
        return None, (['<xs:simpleType>', '  <xs:restriction base="xs:string">']
                      + [f'    <xs:enumeration value="{escape(c)}"/>' for c in d.choices]
                      + ['  </xs:restriction>', '</xs:simpleType>'])
    if d.base is bool:
        return "xs:boolean", []
    if d.base is str:
        return a.xsd or "xs:string", []
    base = "xs:integer" if d.base is int else "d:FiniteDouble"
    facets = []
    if a.low is not None:
        facets.append(f'<xs:min{"Exclusive" if a.low_open else "Inclusive"} '
                      f'value="{number_text(a.low)}"/>')
    if a.high is not None:
        facets.append(f'<xs:max{"Exclusive" if a.high_open else "Inclusive"} '
                      f'value="{number_text(a.high)}"/>')
    if not facets:
        return base, []
    return None, (['<xs:simpleType>', f'  <xs:restriction base="{base}">']
                  + [f"    {f}" for f in facets] + ['  </xs:restriction>', '</xs:simpleType>'])


def attribute_xsd(d: Declared, indent: str) -> str:
    """The ``xs:attribute`` of one declared attribute, each line starting with ``indent``."""
    type_name, simple = _type(d)
    head = f'<xs:attribute name="{d.xml}"'
    if type_name is not None:
        head += f' type="{type_name}"'
    if d.required:
        head += ' use="required"'
    elif d.xml_default is not None:
        head += f' default="{escape(_value_text(d, d.xml_default))}"'
    lines = [head + ">",
             f"  <xs:annotation><xs:documentation>{escape(documentation(d))}"
             "</xs:documentation></xs:annotation>",
             *(f"  {line}" for line in simple), "</xs:attribute>"]
    return "\n".join(indent + line for line in lines)


def element_xsd(d: Declared, indent: str) -> str:
    """The ``xs:element`` of a declared text value (``minOccurs="0"`` unless required;
    its default is stated in the documentation only: an empty element is not a value)."""
    type_name, simple = _type(d)
    head = f'<xs:element name="{d.xml}"'
    if type_name is not None:
        head += f' type="{type_name}"'
    if not d.required:
        head += ' minOccurs="0"'
    lines = [head + ">",
             f"  <xs:annotation><xs:documentation>{escape(documentation(d))}"
             "</xs:documentation></xs:annotation>",
             *(f"  {line}" for line in simple), "</xs:element>"]
    return "\n".join(indent + line for line in lines)
