"""The window words problems from their fields, not by re-reading their text: a schema
problem carries the element it is about and the elements its sentence names
(designer.project.problems.Problem), and the library's errors about one parameter carry
it, its value and what it must be (designer.errors.ParameterError). Qt-free."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import numpy as np
import pytest

from designer.errors import ParameterError
from designer.gui.state import wording
from designer.gui.state.wording import error_text, problem_text, untagged
from designer.project import ProjectError, project_to_bytes, template
from designer.project.problems import Problem
from designer.project.xml_read import parse_project
from tests.synthetic import phantom4

VALID = project_to_bytes(template("survey").project).decode()


def _compiled_patterns(path: Path) -> set[str]:
    """The names of a module's module-level ``re.compile`` patterns."""
    out = set()
    for node in ast.parse(path.read_text()).body:
        if (isinstance(node, ast.Assign) and isinstance(node.value, ast.Call)
                and isinstance(node.value.func, ast.Attribute)
                and node.value.func.attr == "compile"):
            out |= {t.id for t in node.targets if isinstance(t, ast.Name)}
    return out


def test_only_humanize_reads_message_text():
    """The patterns left are humanize's, for the library's plain text (its parameter
    names and numbers); the elements of a schema problem come from its fields."""
    assert _compiled_patterns(Path(wording.__file__)) == {"_IDENT", "_SCI", "_LONG"}


def _problems(text: str) -> list[Problem]:
    with pytest.raises(ProjectError) as caught:
        parse_project(text.encode(), "p.xml")
    return caught.value.problems


def test_a_structure_problem_carries_its_elements():
    text = VALID.replace("<workers>1</workers>", "<wrokers>1</wrokers>", 1)
    assert text != VALID
    (problem,) = _problems(text)
    assert problem.message.startswith("<wrokers>: unknown element <wrokers> inside <render>")
    assert problem.element == "wrokers"
    assert problem.named[:3] == ("wrokers", "render", "workers")
    assert problem.sentence == problem.message.removeprefix("<wrokers>: ")
    worded = problem_text(problem, "p.xml")
    assert worded.startswith(f"p.xml:{problem.line}:{problem.column}: unknown element "
                             "“wrokers” inside “render”; did you mean “workers”?")
    assert "<" not in worded


def test_the_window_quotes_what_the_fields_name_and_nothing_else():
    """A sentence's ``<name>`` is quoted only when the problem names that element; the
    place comes from the fields, not from the message's head."""
    problem = Problem.about("render", "keep <a> as written, quote <render>", 3, 5,
                            named=("render",))
    assert problem.message == "<render>: keep <a> as written, quote <render>"
    assert untagged(problem, "f.xml") == "f.xml:3:5: keep <a> as written, quote “render”"


@pytest.mark.parametrize(("kwargs", "name", "value", "text"), [
    ({"front_overlap_fraction": 60.0}, "front_overlap_fraction", 60.0,
     "front overlap 60 must be a fraction from 0 to below 1, not a percentage (60 % is 0.6)"),
    ({"side_overlap_fraction": 1.0}, "side_overlap_fraction", 1.0,
     "side overlap 1 must be a fraction below 1 (an overlap of 100 % or more never moves "
     "on)"),
    ({"side_overlap_fraction": -0.5}, "side_overlap_fraction", -0.5,
     "side overlap -0.5 must be a fraction from 0 to below 1"),
    ({"gsd_m": -0.01, "altitude_agl_m": None}, "gsd_m", -0.01,
     "ground sample distance -0.01 m must be greater than 0 m"),
    ({"altitude_agl_m": 0.0}, "altitude_agl_m", 0.0,
     "height above ground 0 m must be greater than 0 m"),
])
def test_the_flights_errors_carry_their_parameter(kwargs, name, value, text):
    from designer.survey.flight import camera_calc

    args = {"altitude_agl_m": 50.0, "gsd_m": None, "front_overlap_fraction": 0.8,
            "side_overlap_fraction": 0.7, **kwargs}
    with pytest.raises(ParameterError) as caught:
        camera_calc(phantom4(), **args)
    error = caught.value
    assert (error.name, error.value) == (name, value)
    assert error_text(error) == text


@pytest.mark.parametrize(("call", "name", "text"), [
    (lambda: _blur(-1.0), "sigma_px", "σ -1 px must be at least 0 px"),
    (lambda: _jpeg(0), "quality", "quality 0 must be a whole number from 1 to 100"),
    (lambda: _vignetting(1.5), "corner_falloff",
     "corner fall-off (ρ²) 1.5 must be from 0 to 1"),
    (lambda: _motion((math.nan, 0.0)), "displacement_px",
     "motion blur displacement “(nan, 0.0)” must be finite"),
])
def test_the_effects_errors_carry_their_parameter_and_stay_value_errors(call, name, text):
    with pytest.raises(ValueError) as caught:
        call()
    error = caught.value
    assert isinstance(error, ParameterError) and error.name == name
    assert error_text(error) == text


def _blur(sigma_px: float):
    from designer.effects.optics import gaussian_blur

    return gaussian_blur(np.zeros((4, 4), np.float32), sigma_px)


def _jpeg(quality: int):
    from designer.effects.jpeg import jpeg_roundtrip

    return jpeg_roundtrip(np.zeros((4, 4), np.uint8), quality)


def _vignetting(falloff: float):
    from designer.effects.optics import RadialVignetting

    return RadialVignetting.from_corner_falloff(phantom4(), falloff)


def _motion(displacement_px):
    from designer.effects.motion import linear_motion_kernel

    return linear_motion_kernel(displacement_px)
