"""A refused save says in the status bar how many problems are listed, in plain number:
"1 problem", "2 problems" (not "problem(s)")."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest

from designer.gui.qt.widgets import format_number as num
from tests.gui.helpers import answer_file_dialog, problems, type_cell, wait_idle

pytestmark = pytest.mark.gui


def _save_with_ctrl_s(qtbot, w, path) -> None:
    answer_file_dialog(path)
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_S, Qt.KeyboardModifier.ControlModifier)
    wait_idle(qtbot, w)


def test_a_refused_save_counts_its_problems_in_words(qtbot, window, tmp_path):
    w = window
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    w.docks["GCPs"].raise_()
    table = w.panels["GCPs"].table
    far_x = num(w.document.project.scene.terrain.extent.max_X + 500)
    type_cell(qtbot, w, table, 0, 2, far_x)  # a GCP off the terrain
    wait_idle(qtbot, w)
    _save_with_ctrl_s(qtbot, w, tmp_path / "off.xml")
    assert len(problems(w)) == 1, problems(w)
    assert w.statusBar().currentMessage() == "Not saved: 1 problem to fix"
    assert not (tmp_path / "off.xml").exists()

    type_cell(qtbot, w, table, 1, 2, far_x)  # and a second one
    wait_idle(qtbot, w)
    _save_with_ctrl_s(qtbot, w, tmp_path / "off.xml")
    assert len(problems(w)) == 2, problems(w)
    assert w.statusBar().currentMessage() == "Not saved: 2 problems to fix"
