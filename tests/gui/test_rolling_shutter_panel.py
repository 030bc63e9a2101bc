"""The rolling shutter in the Camera panel: a readout edited through the undo stack, the
direction off for a global shutter, the motion during the readout shown."""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QComboBox, QDoubleSpinBox

from designer.project import model as m
from tests.gui.helpers import field, set_field, wait_idle

pytestmark = pytest.mark.gui


def test_the_readout_is_edited_through_the_undo_stack(qtbot, window):
    w = window
    panel = w.panels["Camera"]
    w.docks["Camera"].raise_()
    cam = lambda: w.document.project.cameras[0]  # noqa: E731
    assert cam().rolling_shutter is None
    readout = field(w, QDoubleSpinBox, "Rolling-shutter readout")
    direction = field(w, QComboBox, "Rolling-shutter direction")
    assert readout.value() == 0.0 and not direction.isEnabled()
    assert panel.shutter_label.text() == "global shutter"

    set_field(qtbot, readout, "0.03")
    wait_idle(qtbot, w)
    assert cam().rolling_shutter == m.RollingShutter(0.03, "top-to-bottom")
    assert direction.isEnabled()
    assert "time line" in panel.shutter_label.text()

    direction.setCurrentIndex(direction.findData("bottom-to-top"))
    wait_idle(qtbot, w)
    assert cam().rolling_shutter == m.RollingShutter(0.03, "bottom-to-top")

    w.panels["Flight"].timed.setChecked(True)  # a time line: the motion is shown
    wait_idle(qtbot, w)
    speed = w.document.project.trajectory.time_line.speed_m_s
    assert f"{100 * speed * 0.03:.1f} cm flown" in panel.shutter_label.text()

    w.undo_stack.undo()  # the time line
    w.undo_stack.undo()  # the direction
    wait_idle(qtbot, w)
    assert cam().rolling_shutter == m.RollingShutter(0.03, "top-to-bottom")
    set_field(qtbot, readout, "0")
    wait_idle(qtbot, w)
    assert cam().rolling_shutter is None and not direction.isEnabled()
    w.undo_stack.undo()
    w.undo_stack.undo()
    wait_idle(qtbot, w)
    assert cam().rolling_shutter is None and readout.value() == 0.0
