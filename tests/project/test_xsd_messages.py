"""Schema errors are worded by their libxml2 type code (designer.project.xsd_messages.WORDING),
with the values read from the file and the schema, never through the fallback that repeats
libxml2's own sentence."""

from __future__ import annotations

from pathlib import Path

import pytest
from lxml import etree

from designer.project import ProjectError, project_to_bytes, template, xsd_messages
from designer.project.schema import NAMESPACE, xml_schema
from designer.project.xml_read import parse_project

VALID = project_to_bytes(template("survey").project).decode()
CORPUS = Path(__file__).resolve().parent / "invalid"

#: (kind, change to the survey template, its libxml2 error type, a start of its message)
KINDS = [
    ("bad number", ('<focal-length-mm>8.8<', '<focal-length-mm>8,8<'),
     "SCHEMAV_CVC_DATATYPE_VALID_1_2_1", "<focal-length-mm>: value '8,8' is not valid here"),
    ("bad integer attribute", ('quality="95"', 'quality="9.5"'),
     "SCHEMAV_CVC_DATATYPE_VALID_1_2_1", '<jpeg>: quality="9.5" is not valid here'),
    ("bad boolean", ("<crosshatch>false<", "<crosshatch>no<"),
     "SCHEMAV_CVC_DATATYPE_VALID_1_2_1",
     "<crosshatch>: value 'no' is not valid here (write true or false)"),
    ("bad union", ("<altitude-reference>mean<", "<altitude-reference>highest<"),
     "SCHEMAV_CVC_DATATYPE_VALID_1_2_3", "<altitude-reference>: value 'highest' is not valid"),
    ("below minimum", ('quality="95"', 'quality="0"'),
     "SCHEMAV_CVC_MININCLUSIVE_VALID", '<jpeg>: quality="0" must be at least 1;'),
    ("above maximum", ("<front-overlap-percent>80.0<", "<front-overlap-percent>99<"),
     "SCHEMAV_CVC_MAXINCLUSIVE_VALID", "<front-overlap-percent>: value '99' must be at most 95;"),
    ("not above an open minimum", ('elevation-deg="50.0"', 'elevation-deg="0"'),
     "SCHEMAV_CVC_MINEXCLUSIVE_VALID", '<sun>: elevation-deg="0" must be greater than 0;'),
    ("not below an open maximum", ('azimuth-deg="135.0"', 'azimuth-deg="360"'),
     "SCHEMAV_CVC_MAXEXCLUSIVE_VALID", '<sun>: azimuth-deg="360" must be less than 360;'),
    ("bad enum", ('role="check"', 'role="reference"'),
     "SCHEMAV_CVC_ENUMERATION_VALID",
     '<target>: role="reference" is not allowed; use one of: control, check'),
    ("not a finite number", ("<altitude-agl-m>50.0<", "<altitude-agl-m>NaN<"),
     "SCHEMAV_CVC_PATTERN_VALID", "<altitude-agl-m>: value 'NaN' is not a finite number"),
    ("bad id", ('id="GCP01"', 'id="GCP 1"'),
     "SCHEMAV_CVC_PATTERN_VALID", '<target>: id="GCP 1" may contain only letters, digits'),
    ("empty text", ("<crs>EPSG:32632 (WGS 84 / UTM zone 32N)<", "<crs><"),
     "SCHEMAV_CVC_MINLENGTH_VALID", "<crs>: the text must not be empty"),
    ("missing required attribute", ('quality="95"', ""),
     "SCHEMAV_CVC_COMPLEX_TYPE_4", '<jpeg>: required attribute quality is missing; add'),
    ("unknown attribute", ('quality="95"', 'quality="95" qualty="9"'),
     "SCHEMAV_CVC_COMPLEX_TYPE_3_2_1",
     "<jpeg>: unknown attribute qualty (did you mean quality?); remove it"),
    ("attribute on a simple element", ("<workers>1<", '<workers n="1">1<'),
     "SCHEMAV_CVC_TYPE_3_1_1", "<workers>: unknown attribute n; remove it"),
    ("unexpected element", ("<workers>1</workers>", "<wrokers>1</wrokers>"),
     "SCHEMAV_ELEMENT_CONTENT", "<wrokers>: unknown element <wrokers> inside <render>; did "
                                "you mean <workers>?"),
    ("repeated element", ("<workers>1</workers>", "<workers>1</workers><workers>1</workers>"),
     "SCHEMAV_ELEMENT_CONTENT", "<workers>: <workers> is repeated; only one is allowed here"),
    ("missing element", ("<crs>EPSG:32632 (WGS 84 / UTM zone 32N)</crs>", ""),
     "SCHEMAV_ELEMENT_CONTENT", "<origin>: required element <crs> is missing; add it before"),
    ("missing last element", ('<output format="png" bit-depth="8"/>', ""),
     "SCHEMAV_ELEMENT_CONTENT", "<render>: a required child element is missing: add <output>"),
    ("text in an element-only element", ("<terrain>", "<terrain>hills"),
     "SCHEMAV_CVC_COMPLEX_TYPE_2_3", "<terrain>: text is not allowed inside <terrain>"),
    ("text in an empty element", ('<jpeg quality="95"/>', '<jpeg quality="95">x</jpeg>'),
     "SCHEMAV_CVC_COMPLEX_TYPE_2_1", "<jpeg>: text is not allowed inside <jpeg>"),
    ("element in a simple element", ("<workers>1<", "<workers><n/>1<"),
     "SCHEMAV_CVC_TYPE_3_1_2", "<workers>: child elements are not allowed inside <workers>"),
]


def _errors(text: str) -> list:
    schema = xml_schema()
    assert not schema.validate(etree.fromstring(text.encode()).getroottree())
    return list(schema.error_log)


def _problems(text: str) -> list:
    with pytest.raises(ProjectError) as caught:
        parse_project(text.encode(), "p.xml")
    return caught.value.problems


def _messages(text: str) -> list[str]:
    return [p.message for p in _problems(text)]


@pytest.mark.parametrize(("kind", "change", "type_name", "start"), KINDS,
                         ids=[k[0] for k in KINDS])
def test_each_kind_is_worded_through_its_type_code(kind, change, type_name, start):
    text = VALID.replace(*change, 1)
    assert text != VALID, kind
    errors = _errors(text)
    assert type_name in {e.type_name for e in errors}
    unworded = {e.type_name for e in errors if e.type not in xsd_messages.WORDING}
    assert not unworded, f"{kind}: no wording for {unworded}"
    assert any(m.startswith(start) for m in _messages(text)), _messages(text)


def test_no_error_of_the_invalid_corpus_falls_back_to_libxml2s_sentence():
    """Every schema error the corpus of invalid files provokes has a wording in the table."""
    seen = set()
    for path in sorted(CORPUS.glob("*.xml")):
        try:
            root = etree.parse(str(path), etree.XMLParser(resolve_entities=False,
                                                          no_network=True)).getroot()
        except etree.XMLSyntaxError:
            continue
        if root.tag != f"{{{NAMESPACE}}}project":
            continue  # refused by the reader before the schema (another root, namespace)
        schema = xml_schema()
        if not schema.validate(root.getroottree()):
            seen |= {(e.type, e.type_name) for e in schema.error_log}
    assert len(seen) >= 8
    missing = sorted(name for code, name in seen if code not in xsd_messages.WORDING)
    assert not missing, missing


def test_a_range_error_carries_the_schemas_limit_and_the_files_value():
    problem, = _problems(VALID.replace('quality="95"', 'quality=" 0 "', 1))
    issue = problem.issue
    assert (issue.code, issue.attr, issue.value, issue.limits) == ("range", "quality", 0.0,
                                                                   (1.0, None))
    assert problem.message.startswith('<jpeg>: quality="0" must be at least 1;')


def test_a_choice_error_carries_the_schemas_choices():
    text = VALID.replace('format="odm"', 'format="pix4d"', 1)
    issue = next(p.issue for p in _problems(text) if p.issue is not None)
    assert (issue.code, issue.value, issue.choices) == (
        "choice", "pix4d", ("colmap", "odm", "metashape", "opk", "gcp"))



def test_a_list_names_its_item_that_is_not_a_choice(tmp_path):
    from designer.study.xml import read_study

    path = tmp_path / "s.xml"
    path.write_text('<?xml version="1.0"?>\n<study xmlns="urn:designer:project:1" '
                    'schema-version="1.0" name="s">\n  <base-project file="b.xml"/>\n'
                    '  <factor name="k1"><values>0 0.1</values></factor>\n'
                    '  <replicates count="2" vary="clouds weather"/>\n</study>\n')
    with pytest.raises(ProjectError) as caught:
        read_study(path)
    choice = next(p for p in caught.value.problems if p.issue is not None)
    assert choice.message.startswith('<replicates>: vary="weather" is not allowed; use one '
                                     "of: gcp-selection, clouds, survey-error")
    assert (choice.issue.code, choice.issue.value) == ("choice", "weather")


def test_a_list_names_its_item_that_is_not_a_name(tmp_path):
    from designer.study.xml import read_study

    path = tmp_path / "s.xml"
    path.write_text('<?xml version="1.0"?>\n<study xmlns="urn:designer:project:1" '
                    'schema-version="1.0" name="s">\n  <base-project file="b.xml"/>\n'
                    '  <factor name="k1"><values>0 0.1</values></factor>\n'
                    '  <metrics>check_rmse_z_m -bad</metrics>\n</study>\n')
    with pytest.raises(ProjectError) as caught:
        read_study(path)
    messages = [p.message for p in caught.value.problems]
    assert any(m.startswith("<metrics>: value '-bad' may contain only letters, digits")
               for m in messages), messages
