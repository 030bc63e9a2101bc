"""Camera panel: the pixel aspect the Problems list asks for is a field of the panel
(blank — "square (from the sizes)" — when the file states none), and a whole-number
field's limits read with their thousands grouped."""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QDoubleSpinBox, QLabel, QSpinBox

from tests.gui.helpers import activate, field, open_panel, problems, wait_idle
from tests.gui.helpers import type_text as _type

pytestmark = pytest.mark.gui

CAM = "cameras[0]"


def _camera_panel(qtbot, w):
    """The Camera panel raised in the active window."""
    activate(qtbot, w)
    panel = open_panel(w, "Camera")
    wait_idle(qtbot, w)
    return panel


def test_a_non_square_sensor_is_mended_with_the_pixel_aspect_field(qtbot, window):
    w = window
    said = _camera_panel(qtbot, w).error_label
    aspect = field(w, QDoubleSpinBox, f"{CAM}.pixel_aspect")
    assert w.document.project.cameras[0].pixel_aspect is None
    assert aspect.text() == "square (from the sizes)"
    cam = w.document.project.cameras[0]
    # a sensor 10 % taller than square pixels allow
    taller = cam.sensor_width_mm * cam.image_height_px / cam.image_width_px * 1.1
    _type(qtbot, w, field(w, QDoubleSpinBox, f"{CAM}.sensor_height_mm"), f"{taller:.4f}")
    wait_idle(qtbot, w)
    assert "pixels are not square" in said.text() and "pixel aspect" in said.text()
    _type(qtbot, w, aspect, "1.1")
    wait_idle(qtbot, w)
    assert w.document.project.cameras[0].pixel_aspect == pytest.approx(1.1)
    assert "pixel" not in said.text() and not [t for t in problems(w) if "pixel" in t]
    _type(qtbot, w, aspect, "0")  # back to square pixels: the problem again
    wait_idle(qtbot, w)
    assert w.document.project.cameras[0].pixel_aspect is None
    assert aspect.text() == "square (from the sizes)"
    assert "pixels are not square" in said.text()


def test_whole_number_limits_read_with_grouped_thousands(qtbot, window):
    w = window
    panel = _camera_panel(qtbot, w)
    width = field(w, QSpinBox, f"{CAM}.image_width_px")
    before = w.document.project.cameras[0].image_width_px
    _type(qtbot, w, width, "999999")
    wait_idle(qtbot, w)
    message = panel.findChild(QLabel, "input-errors").text()
    assert "allowed: 1 to 100\u202f000 px" in message, message
    assert w.document.project.cameras[0].image_width_px == before
    seed = field(w, QSpinBox, "scene.terrain.source.seed")  # greyed on the flat terrain
    assert seed.allowed() == "0 to 2\u202f147\u202f483\u202f647"
