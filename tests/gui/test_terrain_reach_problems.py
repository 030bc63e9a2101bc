"""The Problems list names what lies beyond the terrain as ``designer check`` does: a
project opened with a moving object's path point off the terrain lists the object, the
point and the fix."""

from __future__ import annotations

import pytest

from designer.cli.main import main
from tests.gui.helpers import answer_file_dialog, choose_menu, problems, wait_idle

pytestmark = pytest.mark.gui


def test_opening_a_project_with_a_path_off_the_terrain_lists_it(qtbot, window, tmp_path):
    w = window
    path = tmp_path / "dynamic.xml"
    assert main(["new", str(path), "--template", "survey-dynamic"]) == 0
    text = path.read_text()
    on = '<point X="512045.0" Y="5406010.0"/>'
    assert on in text
    path.write_text(text.replace(on, '<point X="512145.0" Y="5406010.0"/>'))

    answer_file_dialog(path)
    choose_menu(qtbot, w, "File", "Open…")
    wait_idle(qtbot, w)
    assert w.document.path == path
    qtbot.waitUntil(lambda: bool(problems(w)), timeout=10000)
    lines = problems(w)
    assert w.docks["Problems"].isVisible()
    assert len(lines) == 1, lines
    line = lines[0]
    assert "Moving objects › path point 2 of moving object 'car1' at X 512145, Y 5406010 " \
           "lies outside the terrain extent" in line, line
    assert "move the point inside the extent" in line and "Terrain panel" in line, line
    assert "<" not in line, line
