"""What the window tells the user to do names its panels and controls, never the XML: a
sun that follows the time line, or a rolling shutter, without a time line points to the
Flight panel's time line, in the Lighting panel and in the Problems list of a refused
save; switching the time line on there clears both."""

from __future__ import annotations

import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtWidgets import QDoubleSpinBox, QScrollArea

from tests.gui.helpers import field, open_panel, problems, set_field, wait_idle

pytestmark = pytest.mark.gui

XML_WORDS = ("<time-line>", "<trajectory>", "<sun>", "<sun-position>", "add one",
             "readout-s", "takeoff-utc")


def _no_xml(text: str) -> None:
    # the Problems line starts with where the element is in the file: judge what follows
    said = text.split(">: ", 1)[-1]
    assert not any(word in said for word in XML_WORDS), text


def _click(qtbot, widget) -> None:
    qtbot.mouseClick(widget, Qt.MouseButton.LeftButton,
                     pos=QPoint(8, widget.height() // 2))


def _plan_a_flight(qtbot, w) -> None:
    qtbot.mouseClick(open_panel(w, "Flight").create, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)


def _switch_on_the_time_line(qtbot, w) -> None:
    flight = open_panel(w, "Flight")
    flight.findChild(QScrollArea).ensureWidgetVisible(flight.timed)
    _click(qtbot, flight.timed)
    wait_idle(qtbot, w)
    assert w.document.project.trajectory.time_line is not None


def _save_is_refused_pointing_to_the_flight_panel_until_the_time_line_is_on(qtbot, w,
                                                                            tmp_path):
    assert not w.file_actions.save_to(tmp_path / "p.xml")  # refused, with why
    lines = problems(w)
    assert any("Flight panel" in line for line in lines), lines
    for line in lines:
        _no_xml(line)
    _switch_on_the_time_line(qtbot, w)
    qtbot.waitUntil(lambda: problems(w) == [], timeout=5000)


def test_a_sun_over_time_without_a_time_line_points_to_the_flight_panel(qtbot, window,
                                                                         tmp_path):
    w = window
    _plan_a_flight(qtbot, w)
    lighting = open_panel(w, "Lighting")
    lighting.kind.setFocus()
    while lighting.kind.currentData() != "over-time":
        qtbot.keyClick(lighting.kind, Qt.Key.Key_Down)
    wait_idle(qtbot, w)
    said = lighting.error_label.text()
    assert lighting.error_label.isVisible() and "Flight panel" in said, said
    _no_xml(said)

    _save_is_refused_pointing_to_the_flight_panel_until_the_time_line_is_on(qtbot, w,
                                                                             tmp_path)
    assert lighting.error_label.text() == ""
    assert w.file_actions.save_to(tmp_path / "p.xml")


def test_a_rolling_shutter_without_a_time_line_points_to_the_flight_panel(qtbot, window,
                                                                          tmp_path):
    w = window
    _plan_a_flight(qtbot, w)
    camera = open_panel(w, "Camera")
    box = field(camera, QDoubleSpinBox, "Rolling-shutter readout")
    camera.findChild(QScrollArea).ensureWidgetVisible(box)
    set_field(qtbot, box, "0.02")
    wait_idle(qtbot, w)
    assert w.document.project.cameras[0].rolling_shutter is not None

    _save_is_refused_pointing_to_the_flight_panel_until_the_time_line_is_on(qtbot, w,
                                                                             tmp_path)


def test_the_cloud_note_follows_the_time_line_switched_in_the_flight_panel(qtbot, window):
    w = window
    _plan_a_flight(qtbot, w)
    lighting = open_panel(w, "Lighting")
    lighting.findChild(QScrollArea).ensureWidgetVisible(lighting.cloudy)
    _click(qtbot, lighting.cloudy)
    wait_idle(qtbot, w)
    assert lighting.clouds_note.text().startswith("no time line")
    _switch_on_the_time_line(qtbot, w)
    assert lighting.clouds_note.text() == "they drift with each photo's time"
