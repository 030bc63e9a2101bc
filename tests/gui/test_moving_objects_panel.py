"""Moving objects in the GUI: added, edited and removed through the undo stack in a real
window; the panel asks for a time line while there is none."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox

from designer.gui.qt.panels.moving import NEW_SPEED_M_S
from tests.gui.helpers import set_field, wait_idle

pytestmark = pytest.mark.gui


def _speed_box(panel) -> QDoubleSpinBox:
    return next(b for b in panel.findChildren(QDoubleSpinBox)
                if b.objectName() == "Moving object speed")


def test_moving_objects_are_edited_through_the_undo_stack(qtbot, window):
    w = window
    panel = w.panels["Moving objects"]
    w.docks["Moving objects"].raise_()
    assert w.document.project.scene.moving_objects == ()
    assert not panel.remove.isEnabled() and not _speed_box(panel).isEnabled()

    qtbot.mouseClick(panel.add_car, Qt.MouseButton.LeftButton)
    qtbot.mouseClick(panel.add_person, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    objects = w.document.project.scene.moving_objects
    assert [(o.id, o.shape, o.speed_m_s) for o in objects] == [
        ("car1", "car", NEW_SPEED_M_S["car"]), ("person1", "person", NEW_SPEED_M_S["person"])]
    extent = w.document.project.scene.terrain.extent
    assert (objects[0].path[0].X, objects[0].path[-1].X) == (extent.min_X, extent.max_X)
    assert panel.chooser.currentData() == "person1"
    assert "time line" in panel.warning.text()  # the window's project has none

    set_field(qtbot, _speed_box(panel), "2.5")
    panel.loop.setChecked(True)
    wait_idle(qtbot, w)
    person = w.document.project.scene.moving_objects[1]
    assert (person.speed_m_s, person.loop) == (2.5, True)
    assert w.document.project.scene.moving_objects[0].speed_m_s == NEW_SPEED_M_S["car"]

    panel.chooser.setCurrentIndex(0)
    assert _speed_box(panel).value() == NEW_SPEED_M_S["car"]
    qtbot.mouseClick(panel.remove, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    assert [o.id for o in w.document.project.scene.moving_objects] == ["person1"]

    w.undo_stack.undo()  # the car is back
    w.undo_stack.undo()  # the loop is off
    w.undo_stack.undo()  # the person walks at its first speed
    wait_idle(qtbot, w)
    objects = w.document.project.scene.moving_objects
    assert [o.id for o in objects] == ["car1", "person1"]
    assert (objects[1].speed_m_s, objects[1].loop) == (NEW_SPEED_M_S["person"], False)

    w.panels["Flight"].timed.setChecked(True)
    wait_idle(qtbot, w)
    assert panel.warning.text() == ""
