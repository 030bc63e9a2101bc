"""``designer check`` words the control selection as the Processing panel shows it
("control GCPs (G01, G04)", "control count 40") and says where to fix it, never in the
file's attribute names."""

from __future__ import annotations

import pytest

from designer.cli.main import main
from designer.study.templates import write_template

CONTROL = '<control count="4" spread="even" seed="0"/>'

CASES = {
    '<control ids="G01 G04"/>':
        "control GCPs (G01, G04): 2 GCPs, but a similarity after SfM needs at least 3; "
        "name more (Processing panel, ground control, by id) or set GCPs to “in the bundle "
        "adjustment”",
    '<control ids="G01 G99 G04"/>':
        "control GCPs (G01, G99, G04): G99 is not a GCP of the project (G00, G01, …, G09); "
        "name its GCPs or remove G99 (Processing panel, ground control, by id)",
    '<control ids="G01 G01 G04"/>':
        "control GCPs (G01, G01, G04): G01 is listed twice; list each once (Processing "
        "panel, ground control, by id)",
    '<control count="40"/>':
        "control count 40, but the project has 10 GCPs; choose 1 to 10 (Processing panel, "
        "ground control, or a count)",
}


@pytest.mark.parametrize("control", CASES)
def test_a_control_selection_problem_is_worded_as_the_panel_shows_it(control, tmp_path,
                                                                     capsys):
    write_template("tiny", tmp_path / "study.xml")
    path = tmp_path / "study-base.xml"
    text = path.read_text()
    assert CONTROL in text
    path.write_text(text.replace(CONTROL, control))
    line = text[:text.index(CONTROL)].count("\n") + 1
    assert main(["check", str(path)]) == 2
    lines = capsys.readouterr().err.splitlines()
    assert lines[0] == f"{path}:{line}:16: <control>: {CASES[control]}", lines
    for xml_term in ("target id", "ids", "count =", "mode=", "<target>", "point(s)"):
        assert xml_term not in lines[0]
