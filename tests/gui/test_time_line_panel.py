"""The flight's time line and the sun over time in the GUI: switched on, edited and
undone through the undo stack in a real window."""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QDoubleSpinBox, QLineEdit

from designer.gui.qt.panels.flight import DEFAULT_TIME_LINE
from designer.project import model as m
from tests.gui.helpers import field, set_field, wait_idle

pytestmark = pytest.mark.gui


def test_the_time_line_is_edited_through_the_undo_stack(qtbot, window):
    w = window
    panel = w.panels["Flight"]
    w.docks["Flight"].raise_()
    assert w.document.project.trajectory.time_line is None
    panel.timed.setChecked(True)
    wait_idle(qtbot, w)
    assert w.document.project.trajectory.time_line == DEFAULT_TIME_LINE
    set_field(qtbot, field(w, QDoubleSpinBox, "trajectory.time_line.speed_m_s"), "7.5")
    wait_idle(qtbot, w)
    assert w.document.project.trajectory.time_line.speed_m_s == 7.5
    takeoff = field(w, QLineEdit, "trajectory.time_line.takeoff_utc")
    takeoff.selectAll()
    qtbot.keyClicks(takeoff, "2026-06-21T15:00:00Z")
    takeoff.editingFinished.emit()
    wait_idle(qtbot, w)
    assert w.document.project.trajectory.time_line.takeoff_utc == "2026-06-21T15:00:00Z"

    # the sun follows the time line; the panel shows it at take-off
    lighting = w.panels["Lighting"]
    lighting.kind.setCurrentIndex(lighting.kind.findData("over-time"))
    wait_idle(qtbot, w)
    # the window's project has a local CRS: the sun is placed at the default site
    assert w.document.project.scene.lighting.sun == m.SunOverTime(47.37, 8.54)
    assert "at take-off" in lighting.sun_label.text(), lighting.error_label.text()

    w.undo_stack.undo()  # the sun
    w.undo_stack.undo()  # the take-off
    w.undo_stack.undo()  # the speed
    wait_idle(qtbot, w)
    assert w.document.project.trajectory.time_line == DEFAULT_TIME_LINE
    assert not isinstance(w.document.project.scene.lighting.sun, m.SunOverTime)
    w.undo_stack.undo()
    wait_idle(qtbot, w)
    assert w.document.project.trajectory.time_line is None
    assert not panel.timed.isChecked()
