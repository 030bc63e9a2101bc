"""The Study panel as a new user meets it: a study without factors says how to add one
(not the study file's XML), and the base project's line follows a save."""

from __future__ import annotations

import shutil

import pytest
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest

from designer.gui.qt.panels.study import NO_FACTOR
from tests.flight.helpers import EXAMPLE
from tests.gui.helpers import activate, open_panel, problems, type_text, wait_idle
from tests.gui.study_helpers import _add, _checked

pytestmark = pytest.mark.gui


def test_a_study_without_factors_says_how_to_add_one(qtbot, window, tmp_path):
    w = window
    base = tmp_path / "base" / "survey.xml"
    shutil.copytree(EXAMPLE.parent, base.parent)
    assert w.open_project(base)
    wait_idle(qtbot, w)
    panel = open_panel(w, "Study")
    _checked(qtbot, w, panel)
    assert panel.errors.isVisible() and panel.errors.text() == NO_FACTOR
    assert "<" not in panel.errors.text() and ".xml" not in panel.errors.text()
    assert not panel.run_box.run_button.isEnabled()

    # a factor added (the list, Add, its levels typed): the study is checked as a file
    _add(qtbot, panel, "marking-sigma-px", "0.2 2")
    text = _checked(qtbot, w, panel)
    assert "3 runs" in text and not panel.errors.isVisible(), panel.errors.text()


def test_the_base_line_follows_a_save(qtbot, window, tmp_path):
    w = window
    base = tmp_path / "base" / "survey.xml"
    shutil.copytree(EXAMPLE.parent, base.parent)
    assert w.open_project(base)
    wait_idle(qtbot, w)
    panel = open_panel(w, "Study")
    assert panel.base_label.text() == f"the open project: {base}"

    flight = open_panel(w, "Flight")
    activate(qtbot, w)
    type_text(qtbot, w, flight.altitude_spin, "60")  # an edit: unsaved changes
    wait_idle(qtbot, w)
    assert w.document.dirty
    assert panel.base_label.text() == (f"the open project: {base} (unsaved changes: saved "
                                       "with the study)")

    QTest.keyClick(w.windowHandle(), Qt.Key.Key_S, Qt.KeyboardModifier.ControlModifier)
    wait_idle(qtbot, w)
    assert problems(w) == [] and not w.document.dirty
    assert panel.base_label.text() == f"the open project: {base}"


def test_the_open_projects_problems_are_worded_as_the_problems_list_words_them(
        qtbot, window, tmp_path):
    w = window
    base = tmp_path / "base" / "survey.xml"
    shutil.copytree(EXAMPLE.parent, base.parent)
    assert w.open_project(base)
    wait_idle(qtbot, w)
    moving = open_panel(w, "Moving objects")
    qtbot.mouseClick(moving.add_car, Qt.MouseButton.LeftButton)  # no time line: not valid
    wait_idle(qtbot, w)
    assert w.document.dirty
    panel = open_panel(w, "Study")
    _add(qtbot, panel, "marking-sigma-px", "0.2 2")
    _checked(qtbot, w, panel)
    errors = panel.errors.text()
    assert "unsaved changes" in errors.splitlines()[0], errors
    assert ("moving object 'car1' is posed at each photo's time, but the flight has no time "
            "line; switch on the time line in the Flight panel") in errors, errors
    assert "<time-line>" not in errors and "<moving-objects>" not in errors, errors
