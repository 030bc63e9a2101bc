"""Camera panel: every field's limits are the file's (round three, issue item 1): a sensor
width the file check refuses (more than 1000 mm) is refused where it is typed, with the
file's limit; the focal length field names the same limit."""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QDoubleSpinBox, QLabel

from designer.project import model as m
from designer.project.declare import declared_field
from tests.gui.helpers import activate as _activate
from tests.gui.helpers import field, wait_idle
from tests.gui.helpers import type_text as _type

pytestmark = pytest.mark.gui

CAM = "cameras[0]"


def test_sensor_width_over_the_files_limit_is_refused_in_the_field(qtbot, window):
    w = window
    _activate(qtbot, w)
    w.docks["Camera"].raise_()
    wait_idle(qtbot, w)
    panel = w.panels["Camera"]
    box = field(w, QDoubleSpinBox, f"{CAM}.sensor_width_mm")
    original = w.document.project.cameras[0].sensor_width_mm
    message = panel.findChild(QLabel, "input-errors")
    _type(qtbot, w, box, "100000")
    assert w.document.project.cameras[0].sensor_width_mm == original
    assert box.property("invalid") is True
    assert "out of range" in message.text() and "to 1000 mm" in message.text(), message.text()
    # the same limit the file check gives
    assert declared_field(m.Camera, "sensor_width_mm").range_text().endswith("1000 mm")
    focal = field(w, QDoubleSpinBox, f"{CAM}.focal_length_mm")
    assert focal.maximum() == 1000
    _type(qtbot, w, box, "36")
    assert w.document.project.cameras[0].sensor_width_mm == 36.0


def test_distortion_fields_take_the_files_limits(qtbot, window):
    """A coefficient the file accepts (-1000 to 1000, the schema's Coefficient) fits its
    field: none is cut to a narrower range of the panel's own."""
    w = window
    panel = w.panels["Camera"]
    for name, box in panel.coeffs.items():
        assert (box.minimum(), box.maximum()) == (-1000, 1000), name
