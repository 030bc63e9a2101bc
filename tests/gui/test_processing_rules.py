"""The Processing panel checks its control selection against the project's GCPs where it
is typed: an id that names no GCP, a count above the number of GCPs, or fewer control
points than a similarity needs is refused in the user's words — the field turns red and
says why, nothing reaches the project. The position prior's σ and seed fields are off
while the prior is not used."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QComboBox, QDoubleSpinBox, QLineEdit, QSpinBox

from tests.gui.helpers import field, open_panel, refused_message, set_field, wait_idle

pytestmark = pytest.mark.gui


def _with_subset(qtbot, w):
    assert w.file_actions.new("survey")  # 10 GCPs, GCP01 … GCP10
    wait_idle(qtbot, w)
    panel = open_panel(w, "Processing")
    qtbot.mouseClick(panel.enabled, Qt.MouseButton.LeftButton)
    qtbot.mouseClick(panel.subset, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    return panel


def _type_ids(qtbot, box: QLineEdit, text: str) -> None:
    box.setFocus()
    box.selectAll()
    qtbot.keyClicks(box, text)
    qtbot.keyClick(box, Qt.Key.Key_Return)


def test_control_ids_that_name_no_gcp_are_refused(qtbot, window):
    w = window
    panel = _with_subset(qtbot, w)
    before = w.document.project
    ids = field(w, QLineEdit, "Control ids")
    _type_ids(qtbot, ids, "GCP01, GCP99, GCP03, GCP04")
    message = refused_message(qtbot, w, before, panel)
    assert ("control GCPs: GCP99 is not a GCP of the project (GCP01, GCP02, …, GCP10); "
            "not applied") in message, message
    assert ids.property("invalid") and ids.text() == "GCP01, GCP99, GCP03, GCP04"
    assert "<target>" not in message and "ids=" not in message
    # too few for the similarity after SfM
    _type_ids(qtbot, ids, "GCP01, GCP03")
    message = refused_message(qtbot, w, before, panel)
    assert ("control GCPs: 2 GCPs, but a similarity after SfM needs at least 3; name more "
            "or let the GCPs enter in the bundle adjustment; not applied") in message, message
    assert 'mode="bundle"' not in message
    # a valid list is applied and the message goes
    _type_ids(qtbot, ids, "GCP01, GCP03, GCP05")
    wait_idle(qtbot, w)
    assert w.document.project.processing.gcps.control.ids == ("GCP01", "GCP03", "GCP05")
    assert not ids.property("invalid") and not panel.input_label.text()


def test_a_control_count_above_the_gcps_is_refused(qtbot, window):
    w = window
    panel = _with_subset(qtbot, w)
    before = w.document.project
    count = field(w, QSpinBox, "Control count")
    set_field(qtbot, count, "50")
    message = refused_message(qtbot, w, before, panel)
    assert ("control count 50 is more than the project's 10 GCPs; choose 1 to 10; "
            "not applied") in message, message
    set_field(qtbot, count, "2")
    assert "a similarity after SfM needs at least 3" in refused_message(qtbot, w, before,
                                                                        panel)
    set_field(qtbot, count, "7")
    wait_idle(qtbot, w)
    assert w.document.project.processing.gcps.control.count == 7
    assert not panel.input_label.text()


def test_the_prior_sigmas_are_off_while_the_prior_is_not_used(qtbot, window):
    w = window
    _with_subset(qtbot, w)
    sigmas = [field(w, QDoubleSpinBox, f"Position prior σ {s}")
              for s in ("horizontal", "vertical")]
    seed = field(w, QSpinBox, "processing.position_prior.seed")
    assert w.document.project.processing.position_prior.mode == "none"
    assert not any(b.isEnabled() for b in (*sigmas, seed))
    prior = field(w, QComboBox, "processing.position_prior.mode")
    prior.setCurrentIndex(prior.findData("gnss"))
    wait_idle(qtbot, w)
    assert all(b.isEnabled() for b in (*sigmas, seed))
    prior.setCurrentIndex(prior.findData("none"))
    wait_idle(qtbot, w)
    assert not any(b.isEnabled() for b in (*sigmas, seed))


def _choose(qtbot, box: QComboBox, data: str) -> None:
    box.setFocus()
    for _ in range(box.currentIndex()):  # up to the first entry, then down to ``data``
        qtbot.keyClick(box, Qt.Key.Key_Up)
    for _ in range(box.count()):
        if box.currentData() == data:
            return
        qtbot.keyClick(box, Qt.Key.Key_Down)
    assert box.currentData() == data, [box.itemData(i) for i in range(box.count())]


def test_rolling_shutter_compensation_is_set_in_the_panel_and_needs_a_rolling_camera(
        qtbot, window):
    """The rolling-shutter processing (`<calibration rolling-shutter>`, the study factor
    rolling-shutter-processing) has its control in the Processing panel; asking for
    compensation while no camera of the project reads its rows out says so, and points
    to the Camera panel's readout, which clears it."""
    w = window
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    panel = open_panel(w, "Processing")
    qtbot.mouseClick(panel.enabled, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    box = field(w, QComboBox, "processing.calibration.rolling_shutter")
    _choose(qtbot, box, "compensate")
    wait_idle(qtbot, w)
    assert w.document.project.processing.calibration.rolling_shutter == "compensate"
    said = panel.rolling_note.text()
    assert "no camera" in said and "Camera panel" in said, said
    assert "<" not in said and "readout-s" not in said, said
    camera = open_panel(w, "Camera")
    readout = field(camera, QDoubleSpinBox, "Rolling-shutter readout")
    set_field(qtbot, readout, "0.02")
    wait_idle(qtbot, w)
    assert panel.rolling_note.text() == ""
    _choose(qtbot, box, "none")
    wait_idle(qtbot, w)
    assert w.document.project.processing.calibration.rolling_shutter == "none"
