"""Round two of the desktop designer: nothing fails silently, nothing reads wrong. An
edit that would break the project is refused where it is typed, in the user's terms."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QLineEdit

from designer.gui import edits
from tests.gui.helpers import field, open_panel, wait_idle

pytestmark = pytest.mark.gui


def _type_line(qtbot, line: QLineEdit, text: str) -> None:
    """Select all of a text field, type ``text`` (empty: delete), Enter."""
    line.setFocus()
    line.selectAll()
    if text:
        qtbot.keyClicks(line, text)
    else:
        qtbot.keyClick(line, Qt.Key.Key_Delete)
    qtbot.keyClick(line, Qt.Key.Key_Return)


def test_clearing_the_camera_id_is_refused_and_a_new_id_renames_its_uses(qtbot, window):
    w = window
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "flight")
    wait_idle(qtbot, w)
    camera = open_panel(w, "Camera")
    n_stations = w.sync.stations.n_images
    assert n_stations > 0
    line = field(camera, QLineEdit, "cameras[0].id")
    old = w.document.project.cameras[0].id

    _type_line(qtbot, line, "")
    wait_idle(qtbot, w)
    p = w.document.project
    assert p.cameras[0].id == old and p.trajectory.flight_plan.camera == old
    assert w.sync.stations is not None and w.sync.stations.n_images == n_stations
    message = camera.input_label.text()
    assert camera.input_label.isVisible()
    assert "Camera id" in message and "required" in message and "not applied" in message
    assert line.property("invalid")
    assert w.panels["Flight"].error_label.text() == ""

    _type_line(qtbot, line, "my cam")  # a space: not an id
    wait_idle(qtbot, w)
    assert w.document.project.cameras[0].id == old
    assert "my cam" in camera.input_label.text()

    # a valid id is applied, and the flight plan follows it
    _type_line(qtbot, line, "my-cam")
    wait_idle(qtbot, w)
    p = w.document.project
    assert p.cameras[0].id == "my-cam" and p.trajectory.flight_plan.camera == "my-cam"
    assert w.sync.stations is not None and w.sync.stations.n_images == n_stations
    assert not camera.input_label.isVisible() and not line.property("invalid")
    assert w.panels["Flight"].error_label.text() == ""
    # one undo brings the old id back everywhere
    w.undo_action.trigger()
    p = w.document.project
    assert p.cameras[0].id == old and p.trajectory.flight_plan.camera == old
    assert line.text() == old
