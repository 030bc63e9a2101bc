"""The Render panel's resolution scale offers the nearest scale giving whole pixels, and
that scale can be typed and is shown as it is (the example camera: 5472 × 3648 px)."""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QDoubleSpinBox

from designer.gui.state import edits
from tests.gui.helpers import field, open_panel, problems, set_field, wait_idle

pytestmark = pytest.mark.gui


def test_the_nearest_whole_pixel_scale_is_offered_and_accepted_as_shown(
        qtbot, window, tmp_path):
    w = window
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "flight")
    wait_idle(qtbot, w)
    assert w.file_actions.save_to(tmp_path / "scale.xml"), problems(w)
    render = open_panel(w, "Render")
    scale = field(render, QDoubleSpinBox, "render.resolution_scale")
    cam = w.document.project.cameras[0]
    assert (cam.image_width_px, cam.image_height_px) == (5472, 3648)

    # 0.05 gives 273.6 px; 0.0625 (342 × 228 px) is nearer than 0.125
    set_field(qtbot, scale, "0.05")
    wait_idle(qtbot, w)
    message = render.input_label.text()
    assert "nearest scale giving whole pixels: 0.0625" in message, message
    # the offered scale is what the field takes and shows
    set_field(qtbot, scale, "0.0625")
    wait_idle(qtbot, w)
    assert w.document.project.render.resolution_scale == 0.0625
    assert not render.input_label.isVisible()
    assert scale.text().rstrip("0") == "0.0625", scale.text()
