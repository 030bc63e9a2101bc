"""What the project (or study) XSD declares where: each element's and attribute's
documentation, an element's children and attributes, and the simple type of each value
(its facets: limits, choices, pattern), keyed by the instance document's local names.

Read by :mod:`designer.project.xsd_messages` to word a schema error from the declaration
of the value it is about, instead of from libxml2's text.
"""

from __future__ import annotations

import dataclasses
import functools

from lxml import etree

from designer.project.schema import schema_path

_XS = "{http://www.w3.org/2001/XMLSchema}"


@dataclasses.dataclass(frozen=True)
class ValueType:
    """What the schema declares a simple value to be.

    ``builtin`` is the XSD built-in type it is restricted from ("xs:boolean", "xs:double";
    "list" or "union" for those varieties), ``facets`` its constraining facets, the most
    derived one of each kind (the literal as written in the schema; all enumeration values,
    in order), ``item`` a list's item type.
    """

    builtin: str
    facets: dict[str, tuple[str, ...]] = dataclasses.field(default_factory=dict)
    item: ValueType | None = None


class SchemaInfo:
    """What the schema allows where: documentation, children, attributes and value types.

    Keys use the instance document's local names: an element is known by
    ``(parent, name)``, an attribute by ``(parent, element, attribute)``; ``value_type``
    by ``(parent, element, attribute or None)`` (None: the element's text).
    """

    def __init__(self, xsd: etree._ElementTree) -> None:
        self.element_doc: dict[tuple[str | None, str], str] = {}
        self.attribute_doc: dict[tuple[str | None, str, str], str] = {}
        self.children: dict[tuple[str | None, str], list[str]] = {}
        self.attributes: dict[tuple[str | None, str], list[str]] = {}
        self.required: set[tuple[str | None, str]] = set()
        self.value_type: dict[tuple[str | None, str, str | None], ValueType] = {}
        top = xsd.getroot()
        self._types = {t.get("name"): t for t in top if t.tag == _XS + "complexType"}
        self._simple = {t.get("name"): t for t in top if t.tag == _XS + "simpleType"}
        self._groups = {g.get("name"): g for g in top if g.tag == _XS + "attributeGroup"}
        for decl in top.iterfind(_XS + "element"):
            self._element(decl, None)

    def _element(self, decl: etree._Element, parent: str | None) -> None:
        name = decl.get("name")
        self.element_doc[(parent, name)] = _doc(decl)
        self.children.setdefault((parent, name), [])
        self.attributes.setdefault((parent, name), [])
        ctype = decl.find(_XS + "complexType")
        type_name = (decl.get("type") or "").removeprefix("d:")
        if ctype is None:
            ctype = self._types.get(type_name)
        if ctype is not None:
            self._content(ctype, name, parent)
        elif (vtype := self._declared_type(decl)) is not None:
            self.value_type[(parent, name, None)] = vtype

    def _content(self, node: etree._Element, name: str, parent: str | None,
                 optional: bool = False) -> None:
        for child in node:
            tag = child.tag
            if tag == _XS + "element":
                if child.get("name") not in self.children[(parent, name)]:
                    self.children[(parent, name)].append(child.get("name"))
                if not optional and child.get("minOccurs", "1") != "0":
                    self.required.add((name, child.get("name")))
                self._element(child, name)
            elif tag == _XS + "attribute":
                self.attribute_doc[(parent, name, child.get("name"))] = _doc(child)
                if (vtype := self._declared_type(child)) is not None:
                    self.value_type[(parent, name, child.get("name"))] = vtype
                if child.get("name") not in self.attributes[(parent, name)]:
                    self.attributes[(parent, name)].append(child.get("name"))
            elif tag == _XS + "attributeGroup":
                self._content(self._groups[child.get("ref").removeprefix("d:")], name, parent)
            elif tag == _XS + "extension":
                self._content(self._types[child.get("base").removeprefix("d:")], name, parent)
                self._content(child, name, parent)
            elif tag in (_XS + "sequence", _XS + "choice", _XS + "all",
                         _XS + "complexContent"):
                nested_optional = (optional or tag == _XS + "choice"
                                   or child.get("minOccurs", "1") == "0")
                self._content(child, name, parent, nested_optional)


    def _declared_type(self, decl: etree._Element) -> ValueType | None:
        """The simple type of an element or attribute declaration (its ``type`` or its
        own xs:simpleType); None when it has none."""
        if decl.get("type"):
            return self._named_type(decl.get("type"))
        node = decl.find(_XS + "simpleType")
        return None if node is None else self._simple_type(node)

    def _named_type(self, name: str) -> ValueType | None:
        if name.startswith("xs:"):
            return ValueType(name)
        node = self._simple.get(name.removeprefix("d:"))
        return None if node is None else self._simple_type(node)

    def _simple_type(self, node: etree._Element) -> ValueType | None:
        """An xs:simpleType as a :class:`ValueType`: a restriction's facets over its
        base's (the derived facet of a kind replaces the base's), a list with its item."""
        for child in node:
            if child.tag == _XS + "list":
                inner = child.find(_XS + "simpleType")
                item = (self._simple_type(inner) if inner is not None
                        else self._named_type(child.get("itemType", "")))
                return ValueType("list", item=item)
            if child.tag == _XS + "union":
                return ValueType("union")
            if child.tag == _XS + "restriction":
                inner = child.find(_XS + "simpleType")
                base = (self._simple_type(inner) if inner is not None
                        else self._named_type(child.get("base", "")))
                if base is None:
                    return None
                own: dict[str, list[str]] = {}
                for facet in child:
                    if isinstance(facet.tag, str) and facet.get("value") is not None:
                        own.setdefault(facet.tag.removeprefix(_XS), []).append(
                            facet.get("value"))
                facets = {**base.facets, **{k: tuple(v) for k, v in own.items()}}
                return ValueType(base.builtin, facets, base.item)
        return None


def _doc(decl: etree._Element) -> str:
    doc = decl.find(f"{_XS}annotation/{_XS}documentation")
    return " ".join((doc.text or "").split()) if doc is not None else ""


@functools.cache
def schema_info() -> SchemaInfo:
    return SchemaInfo(etree.parse(str(schema_path())))
