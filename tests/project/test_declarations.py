"""The declarations (designer.project.declare, .declare_structure) against what is
derived from them or stated beside them: the XSD is what the generator makes of the model
(elements, named types, attributes: names, types, ranges, defaults, requiredness,
documentation), with no hand-kept part; an independent reading of the XSD agrees; a new
element class reaches the XSD without an edit of it; docs/attributes.md is current."""

from __future__ import annotations

import dataclasses
import typing
from pathlib import Path

import pytest
from lxml import etree

from designer.project import model as m
from designer.project.attributes import attribute_tables
from designer.project.declare import declared, declared_elements, element_of
from designer.project.schema import schema_path
from designer.project.xsd_gen import generate, main
from designer.project.xsd_values import number_text

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


def test_the_xsd_is_generated_from_the_model():
    """The committed XSD is exactly what the generator makes of the model today: no part of
    it is kept by hand."""
    text = schema_path().read_text(encoding="utf-8")
    assert generate() == text, (
        "the XSD differs from the model: run python -m designer.project.xsd_gen")
    assert "declared" not in "".join(
        c.text for c in etree.parse(str(schema_path())).iter(etree.Comment))


def test_a_hand_edited_xsd_is_found_and_rewritten(tmp_path, capsys):
    """--check fails on an XSD edited by hand (a default, a documentation, an element's
    occurrence) and the command writes it back as the model says."""
    text = schema_path().read_text(encoding="utf-8")
    for old, new in (('name="cover" default="0.3"', 'name="cover" default="0.35"'),
                     ("Optional free-text description.", "A free-text description."),
                     ('<xs:element name="blur" minOccurs="0">', '<xs:element name="blur">')):
        assert text.count(old) == 1
        path = tmp_path / "edited.xsd"
        path.write_text(text.replace(old, new), encoding="utf-8")
        assert main(["--check", "--xsd", str(path)]) == 1
        assert "differs from the model" in capsys.readouterr().err
        assert main(["--xsd", str(path)]) == 0
        assert path.read_text(encoding="utf-8") == text


def _with_new_effect():
    """A Project class whose Effects hold one more, made-up effect ``<glow>``: what adding
    an effect's model class and its field in Effects amounts to for the schema."""
    from designer.project.declare import attr, element
    from designer.project.declare_structure import xml_type_of

    @element("glow", title="glow", path="effects.glow")
    @dataclasses.dataclass(frozen=True)
    class Glow:
        """A soft glow around bright areas (made up for this test).

        Developer notes stay out of the schema."""

        radius_px: float = attr(doc="radius of the glow", unit="px", range=(0, 100),
                                low_open=True)
        strength: float = attr(0.5, doc="share of the light spread", range=(0, 1))

    def copy(f):
        return dataclasses.field(default=f.default, default_factory=f.default_factory,
                                 metadata=f.metadata)

    hints = {cls: typing.get_type_hints(cls) for cls in (m.Effects, m.Project)}
    effects = dataclasses.make_dataclass(
        "Effects", [(f.name, hints[m.Effects][f.name], copy(f))
                    for f in dataclasses.fields(m.Effects)]
        + [("glow", Glow | None, dataclasses.field(default=None))], frozen=True)
    effects.__xml_type__ = xml_type_of(m.Effects)
    effects.__doc__ = m.Effects.__doc__
    project = dataclasses.make_dataclass(
        "Project", [(f.name, effects | None if f.name == "effects" else hints[m.Project][f.name],
                     copy(f)) for f in dataclasses.fields(m.Project)], frozen=True)
    project.__xml_type__ = xml_type_of(m.Project)
    project.__doc__ = m.Project.__doc__
    return project


def test_a_new_effect_needs_no_xsd_edit(tmp_path):
    """A new element class and the field that holds it are all the schema needs: the
    generated XSD gains its element (documented by the docstring's first paragraph) and
    attributes (from the declarations) in <effects>, nothing else changes, and a project
    using it validates against that XSD while a wrong value is refused."""
    text = schema_path().read_text(encoding="utf-8")
    new = generate(_with_new_effect())
    added = [line.strip() for line in new.splitlines() if line not in text.splitlines()]
    assert added[0] == '<xs:element name="glow" minOccurs="0">'
    assert any("A soft glow around bright areas (made up for this test)." in a for a in added)
    assert not any("Developer notes" in a for a in added)
    assert any('<xs:attribute name="radius-px" use="required">' in a for a in added)
    assert [line for line in text.splitlines() if line not in new.splitlines()] == []
    schema = etree.XMLSchema(etree.fromstring(new.encode()))
    example = etree.parse(str(ROOT / "resources" / "examples" / "survey" / "survey.xml"))
    ns = "{urn:designer:project:1}"
    root = example.getroot()
    effects = root.find(f"{ns}effects")
    if effects is None:
        effects = etree.Element(f"{ns}effects")
        root.find(f"{ns}render").addprevious(effects)
    glow = etree.SubElement(effects, f"{ns}glow", {"radius-px": "3"})
    assert schema.validate(example), schema.error_log
    glow.set("strength", "2")
    assert not schema.validate(example)
    assert not etree.XMLSchema(etree.parse(str(schema_path()))).validate(example)


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


def test_a_field_the_generator_cannot_place_is_refused():
    """A field that is neither a declared attribute nor a model class nor declared with
    nested/schema_attrs/unwritten stops the generator, naming it: no element is left out
    of the schema silently."""
    from designer.project.declare_structure import xml_type

    Loose = xml_type(tag="loose")(dataclasses.make_dataclass(
        "Loose", [("weight", float, dataclasses.field(default=1.0))], frozen=True))
    with pytest.raises(ValueError, match="field weight holds no model class"):
        generate(Loose)
