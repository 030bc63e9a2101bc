"""Positions of problems: FILE:LINE:COLUMN, also for tags and attributes over several lines."""

from __future__ import annotations

from designer.project import project_to_bytes, template
from designer.project.problems import Issue, Problem, ProjectError, SourceMap
from designer.project.xml_read import parse_project

TEXT = """<project>
  <photo name="a"
         camera="c" X="1"
         Z="5"/>
  <d:photo name="b" camera="x"/>
</project>
"""


def test_positions_of_tags_and_attributes_on_later_lines():
    smap = SourceMap(TEXT)
    # lxml gives the line where a start tag ends (4); the tag is searched backwards
    assert smap.position(4, "photo") == (2, 3)
    assert smap.position(4, "photo", "camera") == (3, 10)
    assert smap.position(4, "photo", "X") == (3, 21)
    assert smap.position(4, "photo", "Z") == (4, 10)
    assert smap.position(5, "photo", "camera") == (5, 21)
    assert smap.position(4, "photo", "missing") == (2, 3)
    assert smap.position(99, "photo") == (99, 1)


def test_locate_uses_the_registered_element():
    smap = SourceMap(TEXT)
    obj = object()
    smap.add(obj, "photo", 4)
    problem = smap.locate(Issue(obj, "photo", "bad camera", attr="camera"))
    assert problem == Problem("<photo>: bad camera", 3, 10)


def test_a_value_with_line_breaks_stays_on_one_line():
    data = project_to_bytes(template("psf").project).replace(
        b"<workers>2</workers>", b"<workers>2\n\n3</workers>")
    try:
        parse_project(data, "p.xml")
    except ProjectError as error:
        assert error.lines == [
            "p.xml:56:5: <workers>: value '2\\n\\n3' is not valid here; expected: Blender "
            "worker processes run at once; from 1 to 256; default 1."]
    else:
        raise AssertionError("not refused")


def test_project_error_lists_every_problem_one_a_line():
    error = ProjectError("p.xml", [Problem("<a>: one", 1, 2), Problem("<b>: two", 3, 4)])
    assert str(error) == "p.xml:1:2: <a>: one\np.xml:3:4: <b>: two"
    assert error.exit_code == 2


def test_a_located_problem_carries_its_issue_s_structured_fields():
    """A range problem says in fields what its message says in words (code, element,
    attribute, value, limits), and the located Problem keeps them: no program has to
    parse a message (the GUI words problems from these fields)."""
    from designer.project import model as m
    from designer.project.validate_declared import element_issues

    (issue,) = element_issues(m.RollingShutter(readout_s=0.9))
    assert (issue.code, issue.tag, issue.attr, issue.value, issue.limits) == (
        "range", "rolling-shutter", "readout-s", 0.9, (0, 0.5))
    assert issue.message == "readout-s = 0.9 must be from 0 to 0.5 s"
    problem = SourceMap('<rolling-shutter readout-s="0.9"/>\n').locate(issue)
    assert problem.issue is issue and (problem.line, problem.column) == (1, 18)
    assert problem == Problem(problem.message, 1, 18)  # the issue is not part of its value
