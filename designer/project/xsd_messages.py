"""Turn libxml2's XSD validation errors into plain sentences that name the fix.

The kind of error is decided by its libxml2 type code (``error.type``, a table from code
to wording function); the element comes from the instance node at ``error.path``, the
offending value from that node, and the limit, the allowed values or the pattern from the
schema's declaration of the value. The schema's own xs:documentation (units, frame,
range) is quoted as what is expected, so the schema stays the one place where each value
is described. The message text is read only for what libxml2 gives nowhere else: the
attribute an error is about, and what its content automaton expected next.
"""

from __future__ import annotations

import dataclasses
import difflib
import re
from collections.abc import Callable

from lxml import etree

from designer.project.problems import Issue, Problem, SourceMap
from designer.project.schema import NAMESPACE
from designer.project.xsd_info import SchemaInfo, ValueType, schema_info

__all__ = ["WORDING", "SchemaInfo", "schema_info", "translate_xsd_error"]

_NS = f"{{{NAMESPACE}}}"
_NON_FINITE = {"nan", "inf", "+inf", "-inf", "infinity", "-infinity", "+infinity"}


def _local(name: str) -> str:
    return name.replace(_NS, "")


def _names(listing: str) -> list[str]:
    return [_local(n.strip()) for n in listing.split(",") if n.strip()]


#: the head of every libxml2 schema message: "Element '{ns}tag'[, attribute 'name']: ".
#: Read for the attribute alone: lxml's ``error.path`` locates the element, and libxml2
#: gives the attribute an error is about nowhere but in this text.
_HEAD = re.compile(r"Element '([^']+)'(?:, attribute '([^']+)')?: (.*)", re.S)
#: a missing required attribute: libxml2 names it only in the text (the element may lack
#: several, each reported in its own error)
_MISSING_ATTRIBUTE = re.compile(r"The attribute '([^']+)' is required but missing")
#: SCHEMAV_ELEMENT_CONTENT is both a child out of place and a missing child (only the
#: text tells which), and the elements expected next are computed by libxml2's content
#: automaton and given nowhere but in this text
_CONTENT = re.compile(r"(Missing child element\(s\)|This element is not expected)\."
                      r"(?: Expected is(?: one of)? \( (.*) \))?", re.S)


@dataclasses.dataclass(frozen=True)
class _Error:
    """One schema error, read from lxml's structured fields and the instance document."""

    type: int
    tag: str
    #: the attribute written in the file that the error is about (None: the element)
    attr: str | None
    instance: etree._Element | None
    parent: str | None
    #: the offending value as written (around a non-string value, no white space)
    value: str
    vtype: ValueType | None
    info: SchemaInfo
    #: the message after its head (the fallback wording and what only the text says)
    rest: str

    @property
    def expected(self) -> str:
        return _expected(self.info, self.parent, self.tag, self.attr)

    @property
    def subject(self) -> str:
        value = self.value if len(self.value) <= 60 else self.value[:57] + "..."
        return f'{self.attr}="{value}"' if self.attr else f"value '{value}'"

    @property
    def non_finite(self) -> bool:
        return self.value.strip().lower() in _NON_FINITE

    def issue(self, code: str, **fields) -> Issue:
        return Issue(None, self.tag, "", attr=self.attr, code=code, parent=self.parent,
                     **fields)


Wording = Callable[[_Error], tuple[str, Issue | None]]


def translate_xsd_error(entry, root: etree._Element, smap: SourceMap,
                        info: SchemaInfo | None = None) -> Problem:
    """A located, plain-words :class:`Problem` for one lxml ``error_log`` entry.

    ``info`` describes the schema validated against (default: the project schema).
    """
    info = info or schema_info()
    error = _read(entry, root, info)
    if error is None:
        return Problem.about("project", _local(entry.message), entry.line or 1, 1)
    text, issue = WORDING.get(entry.type, _fallback)(error)
    line, column = smap.position(entry.line or 1, error.tag, error.attr)
    if issue is not None:
        issue = dataclasses.replace(issue, message=text)
    return Problem.about(error.tag, text, line, column, issue=issue,
                         named=_named(text, error))


def _named(text: str, error: _Error) -> tuple[str, ...]:
    """The elements ``text`` names as ``<name>``: of the schema's elements (its wording
    and the documentation it quotes name no others) and the element at fault and its
    parent (an unknown element is in no schema), in the order of first mention."""
    names = {error.tag, *((error.parent,) if error.parent else ()),
             *(name for _, name in error.info.element_doc)}
    return tuple(sorted((n for n in names if f"<{n}>" in text),
                        key=lambda n: text.index(f"<{n}>")))


def _read(entry, root: etree._Element, info: SchemaInfo) -> _Error | None:
    head = _HEAD.match(entry.message)
    if not head:
        return None
    instance = _instance(root, entry.path)
    tag = _local(head.group(1)) if instance is None else etree.QName(instance).localname
    attr = head.group(2)
    parent = _parent_name(instance)
    vtype = info.value_type.get((parent, tag, attr))
    value = _value(instance, attr, vtype)
    return _Error(entry.type, tag, attr, instance, parent, value, vtype, info,
                  head.group(3).strip())


def _value(instance: etree._Element | None, attr: str | None,
           vtype: ValueType | None) -> str:
    """The value as written: the attribute's, or the element's text (none when it holds
    child elements, as libxml2 validates); white space around a value that is not a
    string left out, as XSD does (inside it, it stays as written: line breaks show)."""
    if instance is None:
        return ""
    if attr is not None:
        value = instance.get(attr, "")
    elif any(isinstance(c.tag, str) for c in instance):
        value = ""
    else:
        value = "".join(instance.itertext())
    if vtype is not None and vtype.builtin not in ("xs:string", "list"):
        value = value.strip()
    return value


def _item(error: _Error, fails: Callable[[str, ValueType], bool]) -> _Error:
    """For a list value, the error about its first item that ``fails`` its item type's
    facet (libxml2 checks the items one by one)."""
    vtype = error.vtype
    if vtype is None or vtype.builtin != "list" or vtype.item is None:
        return error
    bad = next((t for t in error.value.split() if fails(t, vtype.item)), None)
    if bad is None:
        return error
    return dataclasses.replace(error, value=bad, vtype=vtype.item)


def _facet(error: _Error, name: str) -> tuple[str, ...]:
    vtype = error.vtype
    if vtype is not None and name not in vtype.facets and vtype.item is not None:
        vtype = vtype.item
    return () if vtype is None else vtype.facets.get(name, ())


def _not_finite(error: _Error) -> str:
    return (f"{error.subject} is not a finite number; give a finite decimal number"
            f"{error.expected}")


_KIND = {"xs:boolean": " (write true or false)",
         "xs:dateTime": " (write an ISO 8601 date and time with a time zone, e.g. "
                        "2024-06-21T10:30:00+02:00)"}


def _not_of_type(error: _Error) -> tuple[str, Issue | None]:
    """Not of its type: not a number, not true or false, not a date (any variety)."""
    issue = (error.issue("type", value=error.value)
             if error.type == etree.ErrorTypes.SCHEMAV_CVC_DATATYPE_VALID_1_2_1 else None)
    if error.non_finite:
        return _not_finite(error), issue
    kind = _KIND.get(error.vtype.builtin, "") if error.vtype is not None else ""
    return f"{error.subject} is not valid here{kind}{error.expected}", issue


def _out_of_range(facet: str, words: str, side: int) -> Wording:
    """A bound facet: ``words`` before the schema's limit; ``side`` 0 low, 1 high."""
    def word(error: _Error) -> tuple[str, Issue | None]:
        limit = (_facet(error, facet) or ("",))[0]
        try:
            limits: list[float | None] = [None, None]
            limits[side] = float(limit)
            issue = error.issue("range", value=float(error.value),
                                limits=(limits[0], limits[1]))
        except ValueError:
            issue = None
        if error.non_finite:
            return _not_finite(error), issue
        return f"{error.subject} {words} {limit}{error.expected}", issue
    return word


def _not_a_choice(error: _Error) -> tuple[str, Issue | None]:
    error = _item(error, lambda t, item: t not in item.facets.get("enumeration", ()))
    allowed = _facet(error, "enumeration")
    return (f"{error.subject} is not allowed; use one of: {', '.join(allowed) or '?'}",
            error.issue("choice", value=error.value, choices=allowed))


def _matches(pattern: str, text: str) -> bool:
    """Whether ``text`` matches an XSD pattern read as a Python one (the schema's are
    plain classes and counts); True for one Python cannot read, so that it is not blamed."""
    try:
        return re.fullmatch(pattern, text) is not None
    except re.error:
        return True


def _no_pattern(error: _Error) -> tuple[str, Issue | None]:
    error = _item(error, lambda t, item: not all(
        _matches(p, t) for p in item.facets.get("pattern", ())))
    issue = error.issue("pattern", value=error.value)
    if error.non_finite:
        return _not_finite(error), issue
    pattern = " ".join(_facet(error, "pattern"))
    if pattern.startswith("[A-Za-z0-9]["):
        words = ("may contain only letters, digits, '_', '.', '+' and '-', starting with "
                 "a letter or digit")
    elif "A-Za-z0-9" in pattern:
        words = "may contain only letters, digits, '_', '.', '+' and '-'"
    else:
        words = "is not a plain decimal number"
    return f"{error.subject} {words}{error.expected}", issue


def _length(error: _Error) -> tuple[str, Issue | None]:
    """minLength / maxLength / length: of a text its characters, of a list its items."""
    listed = error.vtype is not None and error.vtype.builtin == "list"
    length = len(error.value.split()) if listed else len(error.value)
    if length == 0:
        what = "must not be empty"
    elif error.type == etree.ErrorTypes.SCHEMAV_CVC_MINLENGTH_VALID:
        what = "is too short"
    else:
        what = "is too long"
    return f"{error.attr or 'the text'} {what}{error.expected}", None


def _text_not_allowed(error: _Error) -> tuple[str, Issue | None]:
    return (f"text is not allowed inside <{error.tag}>; remove it (values go in attributes "
            "or child elements)"), None


def _children_not_allowed(error: _Error) -> tuple[str, Issue | None]:
    return (f"child elements are not allowed inside <{error.tag}>; remove them (its value "
            f"is written as text){error.expected}"), None


def _unknown_attribute(error: _Error) -> tuple[str, Issue | None]:
    allowed = error.info.attributes.get((error.parent, error.tag), [])
    close = difflib.get_close_matches(error.attr or "", allowed, n=1)
    did_you_mean = f" (did you mean {close[0]}?)" if close else ""
    text = (f"unknown attribute {error.attr}{did_you_mean}; remove it. <{error.tag}> "
            "takes: " + (", ".join(allowed) if allowed else "no attributes"))
    return text, error.issue("unknown-attribute", value=error.attr, choices=tuple(allowed))


def _missing_attribute(error: _Error) -> tuple[str, Issue | None]:
    found = _MISSING_ATTRIBUTE.search(error.rest)
    if found is None:
        return _fallback(error)
    name = found.group(1)
    doc = error.info.attribute_doc.get((error.parent, error.tag, name), "")
    text = f"required attribute {name} is missing; add {name}=\"...\"" + (
        f" ({doc})" if doc else "")
    return text, dataclasses.replace(error.issue("missing-attribute"), attr=name)


def _element_content(error: _Error) -> tuple[str, Issue | None]:
    found = _CONTENT.match(error.rest)
    if found is None:
        return _fallback(error)
    wanted = _names(found.group(2) or "")
    if found.group(1).startswith("This"):
        return _unexpected(error.info, error.tag, error.parent, error.instance, wanted), None
    have = set() if error.instance is None else {
        etree.QName(c).localname for c in error.instance if isinstance(c.tag, str)}
    docs = [error.info.element_doc.get((error.tag, w), "") for w in wanted]
    if len(wanted) == 1 and wanted[0] in have:
        return f"needs more <{wanted[0]}> elements; add them ({docs[0]})", None
    names = " or ".join(f"<{w}>" for w in wanted)
    hint = f" ({docs[0]})" if len(wanted) == 1 and docs[0] else ""
    return f"a required child element is missing: add {names} at the end{hint}", None


def _fallback(error: _Error) -> tuple[str, Issue | None]:
    """An error of a kind the table does not word: libxml2's own sentence."""
    return _local(error.rest).rstrip(".") + error.expected, None


_T = etree.ErrorTypes
#: libxml2's schema error type code → the function that words it
WORDING: dict[int, Wording] = {
    _T.SCHEMAV_CVC_DATATYPE_VALID_1_2_1: _not_of_type,  # atomic
    _T.SCHEMAV_CVC_DATATYPE_VALID_1_2_2: _not_of_type,  # list
    _T.SCHEMAV_CVC_DATATYPE_VALID_1_2_3: _not_of_type,  # union
    _T.SCHEMAV_CVC_MININCLUSIVE_VALID: _out_of_range("minInclusive", "must be at least", 0),
    _T.SCHEMAV_CVC_MINEXCLUSIVE_VALID: _out_of_range("minExclusive",
                                                     "must be greater than", 0),
    _T.SCHEMAV_CVC_MAXINCLUSIVE_VALID: _out_of_range("maxInclusive", "must be at most", 1),
    _T.SCHEMAV_CVC_MAXEXCLUSIVE_VALID: _out_of_range("maxExclusive", "must be less than", 1),
    _T.SCHEMAV_CVC_ENUMERATION_VALID: _not_a_choice,
    _T.SCHEMAV_CVC_PATTERN_VALID: _no_pattern,
    _T.SCHEMAV_CVC_MINLENGTH_VALID: _length,
    _T.SCHEMAV_CVC_MAXLENGTH_VALID: _length,
    _T.SCHEMAV_CVC_LENGTH_VALID: _length,
    _T.SCHEMAV_ELEMENT_CONTENT: _element_content,
    _T.SCHEMAV_CVC_COMPLEX_TYPE_2_1: _text_not_allowed,  # in an empty element
    _T.SCHEMAV_CVC_COMPLEX_TYPE_2_3: _text_not_allowed,  # in an element-only one
    _T.SCHEMAV_CVC_COMPLEX_TYPE_2_2: _children_not_allowed,  # in simple content
    _T.SCHEMAV_CVC_TYPE_3_1_2: _children_not_allowed,  # in a simple-typed element
    _T.SCHEMAV_CVC_COMPLEX_TYPE_3_2_1: _unknown_attribute,
    _T.SCHEMAV_CVC_COMPLEX_TYPE_3_2_2: _unknown_attribute,
    _T.SCHEMAV_CVC_TYPE_3_1_1: _unknown_attribute,  # on a simple-typed element
    _T.SCHEMAV_CVC_COMPLEX_TYPE_4: _missing_attribute,
}


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
