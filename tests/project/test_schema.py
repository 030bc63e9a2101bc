"""The XSD: one file, compiles in two validators, documents everything."""

from __future__ import annotations

from pathlib import Path

import pytest
import xmlschema
from lxml import etree

from designer.project import project_to_bytes, template
from designer.project.schema import NAMESPACE, SUPPORTED_VERSIONS, schema_path, xml_schema

ROOT = Path(__file__).resolve().parents[2]
CANONICAL = ROOT / "schema" / "designer-project-1.0.xsd"
XS = "{http://www.w3.org/2001/XMLSchema}"


def test_the_repository_holds_one_schema_file_the_package_reads():
    """schema/ at the top of the repository is a link to the package's schema folder, so
    the file a reader opens there and the one an installed designer validates with are
    one file (no copy to keep in step)."""
    assert schema_path().is_file()
    assert (ROOT / "schema").is_symlink()
    assert CANONICAL.resolve() == schema_path().resolve()
    copies = [p for p in ROOT.rglob("designer-project-*.xsd")
              if ".venv" not in p.parts and not p.is_symlink()
              and p.resolve() == p and "schema" in p.parent.name]
    assert copies == [schema_path().resolve()]


def test_schema_is_versioned_and_namespaced():
    root = etree.parse(str(CANONICAL)).getroot()
    assert root.get("targetNamespace") == NAMESPACE
    assert root.get("version") == "1.0" == SUPPORTED_VERSIONS[-1]
    enum = root.find(f"{XS}simpleType[@name='SchemaVersion']/{XS}restriction")
    assert [e.get("value") for e in enum] == list(SUPPORTED_VERSIONS)


def test_both_validators_compile_it():
    schema = xml_schema()
    good = etree.fromstring(project_to_bytes(template("survey").project))
    assert schema.validate(good), schema.error_log
    good.set("version", "9.9")
    assert not schema.validate(good)
    assert xmlschema.XMLSchema10(str(CANONICAL)).target_namespace == NAMESPACE


def test_every_element_and_attribute_is_documented():
    doc = etree.parse(str(CANONICAL))
    undocumented = [
        f"{decl.tag.replace(XS, 'xs:')} {decl.get('name')} (line {decl.sourceline})"
        for decl in doc.iter(f"{XS}element", f"{XS}attribute")
        if not (decl.findtext(f"{XS}annotation/{XS}documentation") or "").strip()]
    assert undocumented == []


@pytest.mark.parametrize("words", [
    "X = Easting", "Y = Northing", "Z = height", "metres", "DEGREES", "R = Rx(omega)",
    "top-left CORNER", "mm", "origin (E0, N0, H0)", "relative to the folder"])
def test_the_top_level_documentation_states_the_conventions(words):
    top = etree.parse(str(CANONICAL)).getroot().findtext(f"{XS}annotation/{XS}documentation")
    assert words in top


@pytest.mark.parametrize("name, unit", [
    ("focal-length-mm", "mm"), ("altitude-agl-m", "m"), ("gsd-m", "m per px"),
    ("front-overlap-percent", "percent"), ("grid-angle-deg", "degrees"), ("tilt-deg", "degrees"),
])
def test_numeric_elements_state_their_unit(name, unit):
    doc = etree.parse(str(CANONICAL))
    decl = doc.find(f".//{XS}element[@name='{name}']")
    assert unit in decl.findtext(f"{XS}annotation/{XS}documentation")
