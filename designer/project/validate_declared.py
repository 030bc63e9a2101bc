"""The single-field checks of every declared element (designer.project.declare): each
attribute inside its range or among its choices, with the located message
``<tag>: name = value must be from low to high unit``. Rules across fields stay with
the element's own checks. Each issue carries its structured fields (code "range" or
"choice", the value, the limits or choices) beside the message."""

from __future__ import annotations

from designer.project.declare import attributes, element_of, holder, walk
from designer.project.problems import Issue


def declared_issues(root) -> list[Issue]:
    """A problem for every declared attribute of every element in ``root`` (a project or
    any part of it) whose value is outside its declared range."""
    out: list[Issue] = []
    for obj in walk(root):
        out += element_issues(obj)
    return out


def element_issues(obj) -> list[Issue]:
    """The single-field problems of one model object (none if it is not declared)."""
    el = element_of(type(obj))
    if el is None:
        return []
    out = []
    for group, d in attributes(type(obj)):
        value = getattr(holder(obj, group), d.name)
        if d.in_range(value):
            continue
        if d.choices is not None:
            text = (f"{d.xml} = {value!r} is not one of {', '.join(d.choices)}; "
                    "use one of them")
            fields = {"code": "choice", "value": value, "choices": d.choices}
        else:
            text = f"{d.xml} = {value!r} must be {d.range_text()}"
            fields = {"code": "range", "value": value, "limits": (d.attr.low, d.attr.high)}
        if d.attr.text:  # the value is the text of the child element <xml>
            out.append(Issue(obj, d.xml, text, **fields))
        else:
            out.append(Issue(obj, d.attr.child or el.tag, text, attr=d.xml, key=d.attr.child,
                             **fields))
    return out
