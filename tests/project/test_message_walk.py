"""A walk of every message ``designer check``, ``designer plan`` and the window can show:
none speaks raw XML (``<project>``, ``attr="…"``) or Python (``snake_case`` names) in the
part a person reads (issue #53, finding 3).

The messages are enumerated from the code, so a new one is walked without being listed:

* every sentence the modules that word problems and warnings hold (their string and
  f-string literals, docstrings aside) names no XML element and no Python identifier;
  the command line's ``FILE:LINE:COL: <element>:`` locator is the one place for
  ``<element>``;
* every semantic check without a code (the window shows its message as it is) and every
  warning in the window's words names no attribute of the file (``altitude-agl-m``);
* every issue code is worded by the window from its fields (designer.gui.state.wording);
* every problem of the file as a whole (missing, a folder, empty, binary, not XML,
  malformed, a DOCTYPE, not a designer project, another namespace, no or a newer
  version, too large) is triggered and read as the window lists it and as check prints it;
* the issue's cases (a flight inside the hills, a 0.001 mm lens) are read as check, plan
  and the window word them.
"""

from __future__ import annotations

import ast
import contextlib
import functools
import io
import re
from pathlib import Path

import pytest

from designer.cli.main import main
from designer.gui.state.wording import problem_text
from designer.project.problems import ProjectError
from tests.project.message_text import LOCATOR, SNAKE, XML, _literal, _sentences

ROOT = Path(__file__).resolve().parents[2]
#: the modules that word what check, plan and the window say
MESSAGE_MODULES = sorted(
    [*ROOT.glob("designer/project/validate*.py")] + [ROOT / "designer" / p for p in (
        "project/validate_shared.py", "project/files.py", "project/xml_read.py",
        "checks/hard_cases.py", "checks/terrain_reach.py", "checks/station_clearance.py",
        "checks/project_checks.py",
        "survey/surroundings.py", "checks/plan_report.py", "survey/project_poses.py",
        "gui/state/wording.py", "gui/state/plan_figures.py", "gui/state/hard_cases.py",
        "gui/state/station_problems.py", "gui/state/files.py", "cli/check.py",
        "cli/plan.py")])
def _kebab_names() -> set[str]:
    """Every attribute and element of the project file with a hyphen in its name."""
    from designer.project import model as m
    from designer.project.declare import attributes, declared_elements, element_of

    names = set()
    for cls in declared_elements(m.Project):
        if element_of(cls) is not None:
            names.add(element_of(cls).tag)
        names.update(d.xml for _, d in attributes(cls))
    return {n for n in names if n and "-" in n}


def _file_words(text: str) -> list[str]:
    return sorted(n for n in _kebab_names() if re.search(rf"(?<![\w-]){re.escape(n)}(?![\w-])",
                                                         text))


def test_no_sentence_speaks_xml_or_python():
    found = []
    for path in MESSAGE_MODULES:
        for line, text in _sentences(path):
            bare = LOCATOR.sub(r"\1", text)
            bad = XML.findall(bare) + SNAKE.findall(bare)
            if bad:
                found.append(f"{path.relative_to(ROOT)}:{line}: {bad} in {text!r}")
    assert len(MESSAGE_MODULES) > 20
    assert not found, "\n".join(found)


@functools.cache
def _package_calls() -> tuple:
    """(path, call) of every call of a plain name in the package (parsed once)."""
    out = []
    for path in sorted((ROOT / "designer").rglob("*.py")):
        text = path.read_text()
        if "Issue(" not in text and "HardCaseWarning(" not in text:
            continue
        out += [(path, node) for node in ast.walk(ast.parse(text))
                if isinstance(node, ast.Call) and isinstance(node.func, ast.Name)]
    return tuple(out)


def _calls(name: str):
    """(path, line, call) of every call of ``name`` in the package."""
    for path, node in _package_calls():
        if node.func.id == name:
            yield path, node.lineno, node


def _argument(call: ast.Call, position: int, name: str):
    if len(call.args) > position:
        return call.args[position]
    return next((k.value for k in call.keywords if k.arg == name), None)


def test_checks_the_window_shows_as_written_name_no_attribute_of_the_file():
    """A semantic issue without a code is shown by the window as its message; a warning
    by its fix in the window's words (``panel_fix``, else ``fix``) and its message."""
    found, walked = [], 0
    for path, line, call in _calls("Issue"):
        code = _argument(call, 5, "code")
        if code is not None and _literal(code):
            continue  # worded by the window from its fields (next test)
        walked += 1
        text = _literal(_argument(call, 2, "message"))
        if text and (bad := _file_words(text)):
            found.append(f"{path.relative_to(ROOT)}:{line}: {bad} in {text!r}")
    for path, line, call in _calls("HardCaseWarning"):
        walked += 1
        fix = _argument(call, 3, "panel_fix") or _argument(call, 2, "fix")
        for node in (_argument(call, 1, "message"), fix):
            text = _literal(node)
            if text and (bad := _file_words(text)):
                found.append(f"{path.relative_to(ROOT)}:{line}: {bad} in {text!r}")
    assert walked > 60
    assert not found, "\n".join(found)


def test_every_issue_code_is_worded_by_the_window():
    from designer.project.problems import CODES

    wording = ROOT / "designer" / "gui" / "state" / "wording.py"
    said = {_literal(n) for n in ast.walk(ast.parse(wording.read_text()))}
    schema = {"range", "choice", "type", "pattern", "missing-attribute",
              "unknown-attribute"}  # worded from the declarations
    used = {_literal(_argument(c, 5, "code")) for _, _, c in _calls("Issue")} - {None}
    assert used <= set(CODES), used - set(CODES)
    assert not set(CODES) - said - schema, set(CODES) - said - schema


def _read(path) -> list:
    from designer.project.load import read_project_file

    try:
        read_project_file(path)
    except ProjectError as error:
        return error.problems
    return []


TEMPLATE_HEAD = ('<?xml version="1.0"?>\n<project xmlns="urn:designer:project:1" '
                 'schema-version="1.0">\n')


@pytest.mark.parametrize(("name", "content"), [
    ("missing.xml", None),
    ("folder.xml", "folder"),
    ("empty.xml", b""),
    ("binary.xml", b"\x00\x01"),
    ("text.xml", b"just text"),
    ("mismatch.xml", (TEMPLATE_HEAD + "<name>a</crs></project>").encode()),
    ("entity.xml", (TEMPLATE_HEAD + "<name>a & b</name></project>").encode()),
    ("unclosed.xml", b"<project"),
    ("doctype.xml", b'<?xml version="1.0"?>\n<!DOCTYPE project>\n<project/>'),
    ("root.xml", b'<projekt xmlns="urn:designer:project:1" schema-version="1.0"/>'),
    ("newer.xml", b'<project xmlns="urn:designer:project:2" schema-version="2.0"/>'),
    ("namespace.xml", b'<project schema-version="1.0"/>'),
    ("no-version.xml", b'<project xmlns="urn:designer:project:1"/>'),
    ("version.xml", b'<project xmlns="urn:designer:project:1" schema-version="2.0"/>'),
    ("big.xml", b"<project/>" + b" " * 64),
])
def test_problems_of_the_file_as_a_whole(name, content, tmp_path, monkeypatch, capsys):
    from designer.project import xml_read

    path = tmp_path / name
    if content == "folder":
        path.mkdir()
    elif content is not None:
        path.write_bytes(content)
    if name == "big.xml":
        monkeypatch.setattr(xml_read, "MAX_PROJECT_BYTES", 32)
    (problem,) = _read(path)
    window = problem_text(problem, str(path))
    assert window.startswith(f"{path}: ") and not XML.search(window), window
    assert not SNAKE.search(window) and ":1:1:" not in window, window
    assert main(["check", str(path)]) == 2
    (line, _) = capsys.readouterr().err.splitlines()
    assert line.startswith(f"{path}:"), line
    body = LOCATOR.sub("", line.split(f"{path}:", 1)[1].split(": ", 1)[1], count=1)
    assert not XML.search(body) and not SNAKE.search(body), line


def test_the_issues_cases_as_check_plan_and_the_window_word_them(tmp_path, capsys):
    """A flight inside the hills (an error of check and plan, a line of the Problems
    list) and a 0.001 mm lens (check's warnings, the Flight panel's lines)."""
    from designer.checks.station_clearance import clearance_issues
    from designer.gui.state.hard_cases import hard_case_lines
    from designer.gui.state.wording import issue_line
    from designer.project import load_project
    from tests.survey.scenes import survey_flown

    low = survey_flown(tmp_path, 5.0)
    lines = []
    for command in ("check", "plan"):
        assert main([command, str(low)]) == 2
        lines += capsys.readouterr().err.splitlines()
    project = load_project(survey_flown(tmp_path, 50.0, 80.0, 70.0, name="high.xml"))
    wide = re.sub(r"<focal-length-mm>[^<]*<", "<focal-length-mm>0.001<",
                  (tmp_path / "high.xml").read_text())
    (tmp_path / "wide.xml").write_text(wide)
    with contextlib.redirect_stdout(io.StringIO()):  # the optics need no terrain
        assert main(["check", "--no-files", str(tmp_path / "wide.xml")]) == 0
    lines += capsys.readouterr().err.splitlines()
    assert sum("camera stations" in line for line in lines) == 2, lines
    assert sum("across the diagonal" in line for line in lines) == 1, lines
    for line in lines:
        body = LOCATOR.sub("", line.split(".xml", 1)[1], count=1)
        assert not XML.search(body) and not SNAKE.search(body), line
    window = [issue_line(i) for i in clearance_issues(load_project(low), tmp_path)]
    window += hard_case_lines(load_project(tmp_path / "wide.xml"), None, None)
    assert len(window) == 3 and project is not None, window
    for line in window:
        assert not XML.search(line) and not SNAKE.search(line), line
        assert not _file_words(line), line


@pytest.mark.parametrize(("old", "new"), [
    ('<camera id="p4p">', '<camerra id="p4p">'),                 # an unknown element
    ("<focal-length-mm>8.8</focal-length-mm>", ""),              # a missing one
    ("<name>Example", "<crs>X</crs><name>Example"),              # out of order
    ('<jpeg quality="95"/>', '<jpeg quality="95"/><jpeg quality="95"/>'),  # repeated
    ("<terrain>", "<terrain>hello"),                             # text inside
])
def test_a_hand_edited_files_structure_is_read_without_angle_brackets(old, new, tmp_path):
    """Only a file edited by hand has elements out of their place; the window names them
    in quotes, the command line keeps its ``<element>`` (it is about the file's XML)."""
    from designer.project import parse_project

    path = tmp_path / "s.xml"
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["new", str(path), "--template", "survey"]) == 0
    text = path.read_text().replace(old, new).replace("</camera>", "</camerra>" if
                                                        "camerra" in new else "</camera>")
    with pytest.raises(ProjectError) as error:
        parse_project(text.encode(), str(path))
    for problem in error.value.problems:
        line = problem_text(problem, str(path))
        assert not XML.search(line) and not SNAKE.search(line), line
        assert "“" in line or problem.issue is not None, line
