"""The Study panel holds still while the study is checked: the plan line, errors and
warnings that come and go (or change length) do not move the Run and Cancel buttons,
nor "Open study folder…" and the results' controls below them, under the mouse."""

from __future__ import annotations

import pytest
from PySide6.QtCore import QPoint

from tests.gui.study_helpers import _add, _checked, _tiny_base

pytestmark = pytest.mark.gui


def _buttons_at(panel) -> tuple[QPoint, ...]:
    box, results = panel.run_box, panel.results
    return tuple(b.mapToGlobal(QPoint(0, 0)) for b in (
        box.run_button, box.cancel_button, panel.open_folder_button,
        results.figure_choice, results.report_button, results.figure))


def _type_levels(qtbot, row, text: str) -> None:
    row.levels.selectAll()
    qtbot.keyClicks(row.levels, text)


def test_study_messages_that_come_and_go_leave_the_buttons_in_place(qtbot, window,
                                                                     tmp_path):
    w = window
    panel, _ = _tiny_base(qtbot, w, tmp_path)
    row = _add(qtbot, panel, "marking-sigma-px", "0.2 2")
    assert "3 runs" in _checked(qtbot, w, panel) and not panel.errors.isVisible()
    before = _buttons_at(panel)

    # an error appears (Run refused) ...
    _type_levels(qtbot, row, "2:1:0.5")
    _checked(qtbot, w, panel)
    assert panel.errors.isVisible() and "below start" in panel.errors.text()
    assert not panel.run_box.run_button.isEnabled()
    qtbot.wait(50)
    assert _buttons_at(panel) == before

    # ... and goes
    _type_levels(qtbot, row, "0.2 2")
    assert "3 runs" in _checked(qtbot, w, panel) and not panel.errors.isVisible()
    qtbot.wait(50)
    assert _buttons_at(panel) == before
