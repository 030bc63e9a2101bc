"""Turn libxml2's XSD validation messages into plain sentences that name the fix.

The schema's own xs:documentation (units, frame, range) is quoted as what is
expected, so the schema stays the one place where each value is described.
"""

from __future__ import annotations

import difflib
import functools
import re

from lxml import etree

from designer.project.problems import Issue, Problem, SourceMap
from designer.project.schema import NAMESPACE, schema_path

_XS = "{http://www.w3.org/2001/XMLSchema}"
_NS = f"{{{NAMESPACE}}}"
_NON_FINITE = {"nan", "inf", "+inf", "-inf", "infinity", "-infinity", "+infinity"}


class SchemaInfo:
    """What the schema allows where: documentation and children of each element.

    Keys use the instance document's local names: an element is known by
    ``(parent, name)``, an attribute by ``(parent, element, attribute)``.
    """

    def __init__(self, xsd: etree._ElementTree) -> None:
        self.element_doc: dict[tuple[str | None, str], str] = {}
        self.attribute_doc: dict[tuple[str | None, str, str], str] = {}
        self.children: dict[tuple[str | None, str], list[str]] = {}
        self.attributes: dict[tuple[str | None, str], list[str]] = {}
        self.required: set[tuple[str | None, str]] = set()
        top = xsd.getroot()
        self._types = {t.get("name"): t for t in top if t.tag == _XS + "complexType"}
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


def _doc(decl: etree._Element) -> str:
    doc = decl.find(f"{_XS}annotation/{_XS}documentation")
    return " ".join((doc.text or "").split()) if doc is not None else ""


@functools.cache
def schema_info() -> SchemaInfo:
    return SchemaInfo(etree.parse(str(schema_path())))


def _local(name: str) -> str:
    return name.replace(_NS, "")


def _names(listing: str) -> list[str]:
    return [_local(n.strip()) for n in listing.split(",") if n.strip()]


def translate_xsd_error(entry, root: etree._Element, smap: SourceMap,
                        info: SchemaInfo | None = None) -> Problem:
    """A located, plain-words :class:`Problem` for one lxml ``error_log`` entry.

    ``info`` describes the schema validated against (default: the project schema).
    """
    info = info or schema_info()
    msg = entry.message
    head = re.match(r"Element '([^']+)'(?:, attribute '([^']+)')?: (.*)", msg, re.S)
    if not head:
        return Problem(f"<project>: {_local(msg)}", entry.line or 1, 1)
    tag, attr, rest = _local(head.group(1)), head.group(2), head.group(3).strip()
    instance = _instance(root, entry.path)
    parent = _parent_name(instance)
    line, column = smap.position(entry.line or 1, tag, attr)
    text = _sentence(info, tag, attr, rest, parent, instance)
    return Problem(f"<{tag}>: {text}", line, column,
                   _value_issue(tag, attr, rest, parent, text, info))


_BOUNDS = {"minInclusive": 0, "minExclusive": 0, "maxInclusive": 1, "maxExclusive": 1}


def _value_issue(tag: str, attr: str | None, rest: str, parent: str | None,
                 text: str, info: SchemaInfo) -> Issue | None:
    """The structured fields of a schema error about one value: code "range" (the value
    and the facet's limit), "choice" (the value and the allowed values), "type" (the
    text as written, not of the value's type: not a number, a fraction for a count, not
    true or false), "pattern" (the text as written, e.g. an id that is not a name),
    "missing-attribute" (``attr``: the one missing) or "unknown-attribute" (``attr``: the
    one written, ``choices``: the element's attributes); None for any other schema
    error."""
    m = re.match(r"The attribute '([^']+)' is required but missing", rest)
    if m is not None:
        return Issue(None, tag, text, attr=m.group(1), code="missing-attribute",
                     parent=parent)
    if attr is not None and re.match(r"The attribute '([^']+)' is not allowed", rest):
        return Issue(None, tag, text, attr=attr, code="unknown-attribute", value=attr,
                     choices=tuple(info.attributes.get((parent, tag), ())), parent=parent)
    m = re.match(r"'(.*)' is not a valid value of the (?:local )?atomic type", rest, re.S)
    if m is not None:
        return Issue(None, tag, text, attr=attr, code="type", value=m.group(1),
                     parent=parent)
    m = re.match(r"\[facet '(\w+)'\] The value '(.*?)'(.*)", rest, re.S)
    if m is None:
        return None
    facet, value, tail = m.groups()
    if facet == "pattern":
        return Issue(None, tag, text, attr=attr, code="pattern", value=value, parent=parent)
    if facet == "enumeration":
        choices = re.search(r"\{(.*)\}", tail)
        if choices is None:
            return None
        allowed = tuple(c.strip().strip("'") for c in choices.group(1).split(","))
        return Issue(None, tag, text, attr=attr, code="choice", value=value,
                     choices=allowed, parent=parent)
    bound = re.search(r"'([^']*)'\)?\.?\s*$", tail)
    if facet not in _BOUNDS or bound is None:
        return None
    try:
        number, limit = float(value), float(bound.group(1))
    except ValueError:
        return None
    limits: list[float | None] = [None, None]
    limits[_BOUNDS[facet]] = limit
    return Issue(None, tag, text, attr=attr, code="range", value=number,
                 limits=(limits[0], limits[1]), parent=parent)


def _instance(root: etree._Element, path: str | None) -> etree._Element | None:
    if not path:
        return None
    try:
        found = root.getroottree().xpath(path)
    except etree.XPathError:
        return None
    return found[0] if found and isinstance(found[0], etree._Element) else None


def _parent_name(el: etree._Element | None) -> str | None:
    if el is None:
        return None
    parent = el.getparent()
    return None if parent is None else etree.QName(parent).localname


def _expected(info: SchemaInfo, parent: str | None, tag: str, attr: str | None) -> str:
    doc = (info.attribute_doc.get((parent, tag, attr)) if attr
           else info.element_doc.get((parent, tag)))
    return f"; expected: {doc}" if doc else ""


def _sentence(info: SchemaInfo, tag: str, attr: str | None, rest: str, parent: str | None,
              instance: etree._Element | None) -> str:
    expected = _expected(info, parent, tag, attr)
    value_m = re.search(r"(?:The value |^)'(.*?)'", rest, re.S)
    value = value_m.group(1) if value_m else ""
    if len(value) > 60:
        value = value[:57] + "..."
    subject = f'{attr}="{value}"' if attr else f"value '{value}'"

    m = re.match(r"This element is not expected\.(?: Expected is(?: one of)? \( (.*) \))?", rest)
    if m:
        return _unexpected(info, tag, parent, instance, _names(m.group(1) or ""))
    m = re.match(r"Missing child element\(s\)\. Expected is(?: one of)? \( (.*) \)", rest)
    if m:
        wanted = _names(m.group(1))
        have = set() if instance is None else {
            etree.QName(c).localname for c in instance if isinstance(c.tag, str)}
        docs = [info.element_doc.get((tag, w), "") for w in wanted]
        if len(wanted) == 1 and wanted[0] in have:
            return (f"needs more <{wanted[0]}> elements; add them ({docs[0]})")
        names = " or ".join(f"<{w}>" for w in wanted)
        hint = f" ({docs[0]})" if len(wanted) == 1 and docs[0] else ""
        return f"a required child element is missing: add {names} at the end{hint}"
    m = re.match(r"The attribute '([^']+)' is required but missing", rest)
    if m:
        doc = info.attribute_doc.get((parent, tag, m.group(1)), "")
        return f"required attribute {m.group(1)} is missing; add {m.group(1)}=\"...\"" + (
            f" ({doc})" if doc else "")
    if re.match(r"The attribute '([^']+)' is not allowed", rest):
        allowed = info.attributes.get((parent, tag), [])
        close = difflib.get_close_matches(attr or "", allowed, n=1)
        did_you_mean = f" (did you mean {close[0]}?)" if close else ""
        return (f"unknown attribute {attr}{did_you_mean}; remove it. <{tag}> takes: "
                + (", ".join(allowed) if allowed else "no attributes"))
    if rest.startswith("Character content"):
        return f"text is not allowed inside <{tag}>; remove it (values go in attributes " \
               "or child elements)"
    m = re.match(r"'(.*)' is not a valid value of the (?:local )?(?:atomic|union|list) type"
                 r"(?: '([^']+)')?", rest, re.S)
    if m:
        type_name = _local(m.group(2) or "")
        if value.strip().lower() in _NON_FINITE:
            return f"{subject} is not a finite number; give a finite decimal number{expected}"
        kind = {"xs:boolean": " (write true or false)",
                "xs:dateTime": " (write an ISO 8601 date and time with a time zone, e.g. "
                               "2024-06-21T10:30:00+02:00)"}.get(type_name, "")
        return f"{subject} is not valid here{kind}{expected}"
    m = re.match(r"\[facet '(minLength|maxLength)'\] The value has a length of '(\d+)'", rest)
    if m:
        what = "must not be empty" if m.group(2) == "0" else "is too long"
        return f"{attr or 'the text'} {what}{expected}"
    m = re.match(r"\[facet '(\w+)'\] The value '(.*?)'(.*)", rest, re.S)
    if m:
        return _facet(subject, m.group(1), m.group(2), m.group(3), expected)
    return _local(rest).rstrip(".") + expected


def _facet(subject: str, facet: str, value: str, tail: str, expected: str) -> str:
    if value.strip().lower() in _NON_FINITE:
        return f"{subject} is not a finite number; give a finite decimal number{expected}"
    bound = re.search(r"'([^']*)'\)?\.?\s*$", tail)
    limit = bound.group(1) if bound else ""
    words = {
        "minExclusive": f"must be greater than {limit}",
        "minInclusive": f"must be at least {limit}",
        "maxExclusive": f"must be less than {limit}",
        "maxInclusive": f"must be at most {limit}",
        "pattern": ("may contain only letters, digits, '_', '.', '+' and '-', starting "
                    "with a letter or digit" if "A-Za-z0-9" in tail
                    else "is not a plain decimal number"),
    }
    if facet == "enumeration":
        choices = re.search(r"\{(.*)\}", tail)
        allowed = choices.group(1).replace("'", "") if choices else "?"
        return f"{subject} is not allowed; use one of: {allowed}"
    text = words.get(facet, f"violates the schema's {facet} rule")
    return f"{subject} {text}{expected}"


def _unexpected(info: SchemaInfo, tag: str, parent: str | None,
                instance: etree._Element | None, wanted: list[str]) -> str:
    parent_el = instance.getparent() if instance is not None else None
    allowed = info.children.get((_parent_name(parent_el), parent or ""))
    if allowed is None:
        allowed = sorted({c for (p, n), cs in info.children.items() if n == parent for c in cs})
    want = " or ".join(f"<{w}>" for w in wanted)
    if tag not in allowed:
        close = difflib.get_close_matches(tag, allowed, n=1)
        did_you_mean = f"did you mean <{close[0]}>? " if close else ""
        where = f" inside <{parent}>" if parent else ""
        listing = ", ".join(f"<{a}>" for a in allowed) or "no child elements"
        return (f"unknown element <{tag}>{where}; {did_you_mean}remove or rename it "
                f"(allowed here: {listing})")
    siblings = [] if parent_el is None else [
        etree.QName(c).localname for c in parent_el if isinstance(c.tag, str)]
    if instance is not None and parent_el is not None \
            and parent_el.index(instance) > _first_index(parent_el, tag):
        return f"<{tag}> is repeated; only one is allowed here, remove this one"
    missing = [w for w in wanted if w not in siblings and (parent, w) in info.required]
    if len(wanted) == 1 and wanted[0] not in siblings:
        missing = wanted
    if len(missing) == 1:
        doc = info.element_doc.get((parent, missing[0]), "")
        return (f"required element <{missing[0]}> is missing; add it before <{tag}>"
                + (f" ({doc})" if doc else ""))
    if want:
        return (f"<{tag}> is not allowed at this place (out of order, an alternative to an "
                f"element already given, or an earlier element is missing); {want} is "
                "expected here")
    return f"<{tag}> is not allowed at this place (repeated, or it conflicts with another " \
           "element); remove it"


def _first_index(parent: etree._Element, tag: str) -> int:
    for i, child in enumerate(parent):
        if isinstance(child.tag, str) and etree.QName(child).localname == tag:
            return i
    return -1
