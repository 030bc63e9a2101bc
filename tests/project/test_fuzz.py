"""Damaged project files give ProjectError (exit code 2), never another exception."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from designer.project import ProjectError, project_to_bytes, template
from designer.project.validate import semantic_problems
from designer.project.xml_read import parse_project

VALID = project_to_bytes(template("survey").project)


def _load(data: bytes) -> None:
    try:
        project, smap = parse_project(data, "fuzz.xml")
    except ProjectError as error:
        assert error.problems and all(p.line >= 1 and p.column >= 1 for p in error.problems)
        assert all(line.startswith("fuzz.xml:") and "\n" not in line for line in error.lines)
        return
    semantic_problems(project, None, smap)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, len(VALID)), st.integers(0, 40), st.binary(max_size=12))
def test_byte_damage_never_escapes_as_a_traceback(start, length, insert):
    _load(VALID[:start] + insert + VALID[start + length:])


NUMBERS = [b"0", b"-1", b"1e308", b"-1e309", b"NaN", b"INF", b"", b" ", b"1.5", b"abc",
           b"99999999999999999999", b"0x10", b"1e-320", b"+.5", b"5."]


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_any_attribute_or_text_value_is_reported_cleanly(data):
    quotes = [i for i in range(len(VALID)) if VALID[i:i + 2] == b'="']
    at = data.draw(st.sampled_from(quotes)) + 2
    end = VALID.index(b'"', at)
    value = data.draw(st.sampled_from(NUMBERS) | st.text(max_size=8).map(str.encode))
    _load(VALID[:at] + value.replace(b'"', b"") + VALID[end:])
