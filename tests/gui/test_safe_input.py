"""Safe input: the wheel scrolls past fields, typed text is checked, not clamped, and
Ctrl+Z in a field undoes one step of the project (problems 2, 3 and 7 of the user test).

Events go through Qt's window-system path (QTest on the window), as a real mouse's and
keyboard's do: shortcuts, focus and wheel propagation are Qt's own.
"""

from __future__ import annotations

import pytest
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QComboBox, QDoubleSpinBox, QLabel, QScrollArea

from designer.gui.state import edits
from tests.gui.helpers import activate as _activate
from tests.gui.helpers import field, wait_idle
from tests.gui.helpers import type_text as _type

pytestmark = pytest.mark.gui

FP = "trajectory.flight_plan"


def _flight(qtbot, w) -> None:
    _activate(qtbot, w)
    project = edits.ensure_flight_plan(w.document.project)
    w.editor.edit(project, "flight")
    w.docks["Flight"].raise_()
    wait_idle(qtbot, w)


def _wheel(qtbot, w, widget, notches: int = -3) -> None:
    """Turn the wheel with the pointer over the middle of ``widget`` (no click)."""
    pos = widget.mapTo(w, widget.rect().center())
    QTest.mouseMove(w.windowHandle(), pos)
    for _ in range(abs(notches)):
        QTest.wheelEvent(w.windowHandle(), QPointF(pos), QPoint(0, 120 if notches > 0 else -120))
        qtbot.wait(20)


def _scroll_area(widget) -> QScrollArea:
    while not isinstance(widget, QScrollArea):
        widget = widget.parent()
    return widget


def test_wheel_over_fields_scrolls_the_panel_and_changes_nothing(qtbot, window):
    w = window
    _flight(qtbot, w)
    flight = w.panels["Flight"]
    flight.noisy.setChecked(True)
    wait_idle(qtbot, w)
    w.resize(1600, 700)  # the panel's content is taller than the dock: it scrolls
    qtbot.wait(100)
    sigma = field(w, QDoubleSpinBox, f"{FP}.pose_noise.sigma_X_m")
    area = _scroll_area(sigma)
    scroll = area.verticalScrollBar()
    assert scroll.maximum() > 0
    w.view.plotter.setFocus()
    before, steps = w.document.project, w.undo_stack.count()
    for box in (sigma, field(w, QComboBox, f"{FP}.orientation"),
                field(w, QDoubleSpinBox, f"{FP}.side_overlap_percent")):
        area.ensureWidgetVisible(box, 60, 60)
        qtbot.wait(50)
        start = scroll.value()
        _wheel(qtbot, w, box, -2 if start < scroll.maximum() else 2)
        assert scroll.value() != start             # the panel scrolled …
        assert w.document.project == before        # … and no value changed
    assert w.undo_stack.count() == steps

    # with the focus in the field, the wheel does step it
    sigma = field(w, QDoubleSpinBox, f"{FP}.pose_noise.sigma_X_m")
    _scroll_area(sigma).ensureWidgetVisible(sigma)
    qtbot.wait(50)
    sigma.setFocus()
    qtbot.waitUntil(sigma.hasFocus)
    _wheel(qtbot, w, sigma, 1)
    assert w.document.project.trajectory.flight_plan.pose_noise.sigma_X_m == pytest.approx(0.35)


def test_wheel_over_a_role_in_the_gcp_table_does_not_flip_it(qtbot, window):
    w = window
    _activate(qtbot, w)
    project = w.document.project
    for k in range(12):
        project = edits.add_target(project, -40.0 + 7 * k, 0.0)
    w.editor.edit(project, "twelve GCPs")
    w.docks["GCPs"].raise_()
    wait_idle(qtbot, w)
    table = w.panels["GCPs"].table
    role = table.cellWidget(1, 1)
    assert role.currentText() == "control"
    w.view.plotter.setFocus()
    start = table.verticalScrollBar().value()
    _wheel(qtbot, w, role, -2)
    assert [t.role for t in w.document.project.targets] == ["control"] * 12
    assert table.verticalScrollBar().value() > start  # the table scrolled


def test_out_of_range_and_letters_are_refused_with_a_message(qtbot, window):
    w = window
    _flight(qtbot, w)
    flight = w.panels["Flight"]
    box = field(w, QDoubleSpinBox, f"{FP}.front_overlap_percent")
    original = w.document.project.trajectory.flight_plan.front_overlap_percent
    message = flight.findChild(QLabel, "input-errors")
    for typed, words in (("150", "out of range"), ("-20", "out of range"),
                         ("7x0", "is not a number")):
        _type(qtbot, w, box, typed)
        assert w.document.project.trajectory.flight_plan.front_overlap_percent == original
        assert box.property("invalid") is True
        assert box.lineEdit().text().strip().startswith(typed)   # kept, to be corrected
        assert words in message.text() and "0 to 99 %" in message.text()
        assert message.isVisible()
    # a valid value is applied and the message goes away
    _type(qtbot, w, box, "70")
    assert w.document.project.trajectory.flight_plan.front_overlap_percent == 70.0
    assert box.property("invalid") is False
    assert not message.isVisible() and message.text() == ""

    # leaving the field with a bad value: refused as well, still red
    _type(qtbot, w, box, "120")
    other = field(w, QDoubleSpinBox, f"{FP}.side_overlap_percent")
    QTest.mouseClick(w.windowHandle(), Qt.MouseButton.LeftButton,
                     Qt.KeyboardModifier.NoModifier, other.mapTo(w, other.rect().center()))
    qtbot.waitUntil(other.hasFocus)
    assert w.document.project.trajectory.flight_plan.front_overlap_percent == 70.0
    assert box.property("invalid") is True and "120" in box.lineEdit().text()
    # an undo puts the model's value back into the field and takes the message away
    w.undo_action.trigger()
    assert box.property("invalid") is False and not message.isVisible()


def test_ctrl_z_in_a_field_undoes_one_project_step(qtbot, window):
    w = window
    _flight(qtbot, w)
    altitude = field(w, QDoubleSpinBox, f"{FP}.altitude_agl_m")
    front = field(w, QDoubleSpinBox, f"{FP}.front_overlap_percent")
    _type(qtbot, w, altitude, "40")
    _type(qtbot, w, front, "70")
    _type(qtbot, w, altitude, "45")
    plan = w.document.project.trajectory.flight_plan
    assert (plan.altitude_agl_m, plan.front_overlap_percent) == (45.0, 70.0)
    steps = w.undo_stack.index()
    assert altitude.hasFocus()

    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    plan = w.document.project.trajectory.flight_plan
    assert w.undo_stack.index() == steps - 1        # exactly one step
    assert (plan.altitude_agl_m, plan.front_overlap_percent) == (40.0, 70.0)
    assert altitude.value() == 40.0 and altitude.hasFocus()

    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    plan = w.document.project.trajectory.flight_plan
    assert w.undo_stack.index() == steps - 2
    assert plan.front_overlap_percent != 70.0 and plan.altitude_agl_m == 40.0

    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Z,
                   Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.ShiftModifier)
    assert w.undo_stack.index() == steps - 1
    assert w.document.project.trajectory.flight_plan.front_overlap_percent == 70.0
    # leaving the field afterwards adds no step of its own
    w.view.plotter.setFocus()
    qtbot.wait(50)
    assert w.undo_stack.index() == steps - 1 and w.undo_stack.count() == steps
