"""The declarations (designer.project.declare) against what is derived from them or
stated beside them: the XSD's declared attributes are what the generator makes of the
declarations (names, types, ranges, defaults, requiredness, documentation), and an
independent reading of the XSD agrees; docs/attributes.md is current."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from lxml import etree

from designer.project import model as m
from designer.project.attributes import attribute_tables
from designer.project.declare import declared, declared_elements, element_of
from designer.project.schema import schema_path
from designer.project.xsd_gen import expected_regions, generate, number_text, regions

ROOT = Path(__file__).resolve().parents[2]
XS = "{http://www.w3.org/2001/XMLSchema}"
ELEMENTS = declared_elements(m.Project)


def _attributes(decl: etree._Element, doc: etree._ElementTree) -> dict[str, etree._Element]:
    """name → xs:attribute of an xs:element (inline type, named type, attribute groups)."""
    ctype = decl.find(f"{XS}complexType")
    if ctype is None and decl.get("type"):
        name = decl.get("type").split(":")[-1]
        ctype = doc.getroot().find(f"{XS}complexType[@name='{name}']")
    if ctype is None:
        return {}
    out = {}
    own = [a for a in ctype.iter(f"{XS}attribute", f"{XS}attributeGroup")
           if not any(p.tag == f"{XS}element" for p in _between(a, ctype))]
    for a in own:
        if a.tag == f"{XS}attribute":
            out[a.get("name")] = a
    for g in (a for a in own if a.tag == f"{XS}attributeGroup"):
        group = doc.getroot().find(f"{XS}attributeGroup[@name='{g.get('ref').split(':')[-1]}']")
        out.update({a.get("name"): a for a in group.iter(f"{XS}attribute")})
    return out


def _child_element(decl: etree._Element, tag: str, doc: etree._ElementTree):
    """The xs:element ``tag`` declared inside the type of the xs:element ``decl``."""
    ctype = decl.find(f"{XS}complexType")
    if ctype is None and decl.get("type"):
        name = decl.get("type").split(":")[-1]
        ctype = doc.getroot().find(f"{XS}complexType[@name='{name}']")
    return None if ctype is None else next(
        (e for e in ctype.iter(f"{XS}element") if e.get("name") == tag), None)


def _between(node: etree._Element, top: etree._Element) -> list[etree._Element]:
    """The ancestors of ``node`` below ``top``."""
    out = []
    parent = node.getparent()
    while parent is not None and parent is not top:
        out.append(parent)
        parent = parent.getparent()
    return out


def _facet(a: etree._Element, name: str) -> float | None:
    f = a.find(f".//{XS}{name}")
    return None if f is None else float(f.get("value"))


def schema_disagreements(cls: type, doc: etree._ElementTree) -> list[str]:
    """What the XSD says differently of ``cls`` than its declaration (empty: agree)."""
    el = element_of(cls)
    undeclared = {f.name.replace("_", "-") for f in dataclasses.fields(cls)} - {
        d.name.replace("_", "-") for d in declared(cls)}
    best = None
    for decl in doc.iter(f"{XS}element"):
        if decl.get("name") != el.tag:
            continue
        attrs = {k: v for k, v in _attributes(decl, doc).items() if k not in undeclared}
        for child in {d.attr.child for d in declared(cls)} - {None}:
            child_decl = _child_element(decl, child, doc)
            if child_decl is not None:
                attrs.update({k: v for k, v in _attributes(child_decl, doc).items()
                              if any(d.xml == k and d.attr.child == child
                                     for d in declared(cls))})
        for d in declared(cls):
            if d.attr.text and _child_element(decl, d.xml, doc) is not None:
                attrs[d.xml] = _child_element(decl, d.xml, doc)  # a text element
        problems = []
        missing = sorted({d.xml for d in declared(cls)} - set(attrs))
        if missing:  # (XSD attributes of fields that are not declared are the reader's)
            problems.append(f"<{el.tag}> attributes: XSD {sorted(attrs)} lacks declared "
                            f"{missing}")
        else:
            for d in declared(cls):
                a = attrs[d.xml]
                use = a.get("use") if not d.attr.text else (
                    "required" if a.get("minOccurs", "1") != "0" else "optional")
                if d.required != (use == "required"):
                    problems.append(f"<{el.tag}> {d.xml}: declared "
                                    f"{'required' if d.required else 'optional'}, XSD "
                                    f"use={use}")
                default = d.xml_default
                wanted = (None if d.required or default is None or d.attr.text else
                          ("true" if default else "false") if d.base is bool else
                          number_text(default) if d.base in (int, float) else str(default))
                if a.get("default") != wanted:
                    problems.append(f"<{el.tag}> {d.xml}: XSD default {a.get('default')}, "
                                    f"declared {wanted}")
                if d.attr.doc.lower() not in (a.findtext(
                        f"{XS}annotation/{XS}documentation") or "").lower():
                    problems.append(f"<{el.tag}> {d.xml}: the XSD's documentation does not "
                                    "state the declared doc")
                for facet, bound, open_ in (("minInclusive", d.attr.low, False),
                                            ("minExclusive", d.attr.low, True),
                                            ("maxInclusive", d.attr.high, False),
                                            ("maxExclusive", d.attr.high, True)):
                    value = _facet(a, facet)
                    is_low = facet.startswith("min")
                    declared_open = d.attr.low_open if is_low else d.attr.high_open
                    if value is not None and (value != bound or open_ != declared_open):
                        problems.append(f"<{el.tag}> {d.xml}: XSD {facet} {value:g}, "
                                        f"declared {d.range_text()}")
        if not problems:
            return []
        best = problems if best is None or len(problems) < len(best) else best
    return best if best is not None else [f"<{el.tag}> is not in the XSD"]


@pytest.fixture(scope="module")
def xsd():
    return etree.parse(str(schema_path()))


@pytest.mark.parametrize("cls", ELEMENTS, ids=lambda c: c.__name__)
def test_the_xsd_agrees_with_the_declaration(cls, xsd):
    assert schema_disagreements(cls, xsd) == []


def test_the_xsd_is_generated_from_the_declarations():
    """Every declared element's attributes in the committed XSD are exactly what the
    generator makes of the declarations today."""
    text = schema_path().read_text(encoding="utf-8")
    assert generate(text) == text, (
        "the XSD's declared attributes differ from the declarations: run "
        "python -m designer.project.xsd_gen")


def test_every_declared_element_has_one_region_in_the_xsd():
    found = regions(schema_path().read_text(encoding="utf-8"))
    assert len(found) == len(set(found))
    assert set(found) == expected_regions()


def test_a_hand_edited_declared_attribute_is_found_and_regenerated():
    """The comparison fails for an XSD whose declared part differs from the declaration
    (a default, a facet, a use, a documentation), and the generator restores it; the
    hand-written parts around the regions stay as they are."""
    text = schema_path().read_text(encoding="utf-8")
    start = text.index("<!-- declared CloudShadows:")
    region = text[start:text.index("<!-- end of declared CloudShadows -->")]
    for old, new in (('name="cover" default="0.3"', 'name="cover" default="0.35"'),
                     ('<xs:maxExclusive value="360"/>', '<xs:maxInclusive value="360"/>'),
                     ('name="seed" default="0"', 'name="seed" use="required"'),
                     ("Shadowed fraction", "Shaded fraction")):
        assert old in region
        edited = text[:start] + region.replace(old, new, 1) + text[start + len(region):]
        assert generate(edited) != edited
        assert generate(edited) == text
    outside = text.replace("Optional free-text description.", "A free-text description.")
    assert generate(outside) == outside


def test_a_generated_xsd_lacking_a_region_is_refused():
    text = schema_path().read_text(encoding="utf-8").replace(
        "<!-- declared Sfm:", "<!-- Sfm:")
    with pytest.raises(ValueError, match="no declared region for Sfm"):
        generate(text)


def test_a_disagreement_is_found(xsd):
    """The comparison can fail: a changed range, and an attribute the XSD lacks."""
    from designer.project.declare import attr, element

    Wider = element("cloud-shadows", title="t")(dataclasses.make_dataclass(
        "Wider", [("cover", float, attr(0.3, doc="d", range=(0, 2))),
                  ("haze", float, attr(0.0, doc="d"))], frozen=True))
    found = schema_disagreements(Wider, xsd)
    assert found and "haze" in found[0]
    Narrow = element("jpeg", title="t")(dataclasses.make_dataclass(
        "Narrow", [("quality", int, attr(doc="d", range=(1, 90)))], frozen=True))
    assert any("maxInclusive 100" in p for p in schema_disagreements(Narrow, xsd))


def test_the_attribute_docs_are_current():
    text = (ROOT / "docs" / "attributes.md").read_text(encoding="utf-8")
    assert text == attribute_tables(), (
        "docs/attributes.md is out of date: python -m designer.project.attributes "
        "> docs/attributes.md")


def test_declared_elements_cover_the_world_effects_and_processing():
    names = {c.__name__ for c in ELEMENTS}
    assert {"TimeLine", "SunOverTime", "CloudShadows", "Wind", "Mount", "RollingShutter",
            "TextureVariation", "Vignetting", "Defocus", "SensorNoise", "Sensor", "Blur",
            "MotionBlur", "Jpeg", "ExposureVariation", "ChromaticAberration", "Calibration",
            "GcpProcessing",
            "PositionPrior", "Matching"} <= names
