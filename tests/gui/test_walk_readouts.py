"""Readouts that must follow the project as a new user changes it with the mouse and the
keyboard: the Flight panel's grid figures after a flight is imported, the Processing
panel's greyed fields while the project has no processing settings of its own, a GCP
cell typed back to the project's value."""

from __future__ import annotations

import shutil

import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtTest import QTest

from tests.flight.helpers import EXAMPLE
from tests.gui.flight_helpers import _flown_images
from tests.gui.helpers import answer_file_dialogs, choose_menu, open_panel, problems, wait_idle

pytestmark = pytest.mark.gui


def test_the_grid_figures_go_when_an_imported_flight_replaces_the_grid(qtbot, window,
                                                                     tmp_path):
    from designer.gui.qt.panels.flight import NO_GRID

    w = window
    base = tmp_path / "base" / "survey.xml"
    shutil.copytree(EXAMPLE.parent, base.parent)
    assert w.open_project(base)
    wait_idle(qtbot, w)
    flight = open_panel(w, "Flight")
    assert "lines 22.5 m apart" in flight.calc_label.text()
    _flown_images(tmp_path / "flown", 4)

    answer_file_dialogs([tmp_path / "flown"])
    choose_menu(qtbot, w, "File", "Import flight", "From a folder of images…")
    wait_idle(qtbot, w)
    assert problems(w) == []
    assert w.document.project.trajectory.flight_plan is None
    assert flight.images_label.text() == "4"
    # no grid any more: the grid's spacing and trigger distance are not described
    assert flight.calc_label.text() == NO_GRID

    # undo (Ctrl+Z) brings the grid and its figures back
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    wait_idle(qtbot, w)
    assert "lines 22.5 m apart" in flight.calc_label.text()


def test_greyed_processing_fields_show_the_defaults_the_reconstruction_uses(qtbot, window):
    from PySide6.QtWidgets import QComboBox, QSpinBox

    from designer.project import model as m
    from tests.gui.helpers import field

    w = window
    panel = open_panel(w, "Processing")
    wait_idle(qtbot, w)
    assert w.document.project.processing is None
    defaults = m.Processing()
    features = field(w, QSpinBox, "processing.matching.max_features")
    mode = field(w, QComboBox, "processing.gcps.mode")
    shown = (features.value(), mode.currentData())
    # greyed, and showing what designer reconstruct uses without <processing>
    assert not features.isEnabled() and not mode.isEnabled()
    assert shown == (defaults.matching.max_features, defaults.gcps.mode)

    # the check box (a real click) adds exactly those settings: nothing shown changes
    box = panel.enabled
    QTest.mouseClick(box, Qt.MouseButton.LeftButton, pos=QPoint(8, box.height() // 2))
    wait_idle(qtbot, w)
    assert w.document.project.processing == defaults
    assert features.isEnabled()
    assert (features.value(), mode.currentData()) == shown


def test_a_gcp_cell_typed_back_to_its_value_reads_like_the_others(qtbot, window):
    from PySide6.QtGui import QBrush

    from designer.gui.qt.widgets import format_number as num
    from tests.gui.helpers import activate, type_cell

    w = window
    activate(qtbot, w)
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    panel = open_panel(w, "GCPs")
    table = panel.table
    x = w.document.project.targets[0].true.X
    before, steps = w.document.project, w.undo_stack.count()

    type_cell(qtbot, w, table, 0, 2, "abc")  # refused: red, said
    assert table.item(0, 2).background() != QBrush()
    assert "not applied" in panel.error_label.text()

    type_cell(qtbot, w, table, 0, 2, num(x, 0))  # the project's value, typed without decimals
    wait_idle(qtbot, w)
    assert w.document.project == before and w.undo_stack.count() == steps
    assert table.item(0, 2).text() == f"{x:.3f}"  # as every other coordinate is shown
    assert table.item(0, 2).background() == QBrush()
    assert panel.error_label.text() == ""


def test_a_cloud_says_which_truth_it_is_measured_against(qtbot, window, tmp_path):
    from PySide6.QtWidgets import QPushButton

    from tests.gui.helpers import activate, answer_file_dialog, type_text

    w = window
    base = tmp_path / "base" / "survey.xml"
    shutil.copytree(EXAMPLE.parent, base.parent)
    assert w.open_project(base)
    wait_idle(qtbot, w)
    activate(qtbot, w)
    type_text(qtbot, w, open_panel(w, "Flight").altitude_spin, "60")  # unsaved changes
    wait_idle(qtbot, w)
    path = _cloud_on_the_terrain(w, tmp_path, 400)
    results = open_panel(w, "Results")
    button = next(b for b in results.findChildren(QPushButton)
                  if b.text() == "Open point cloud…")

    answer_file_dialog(path)
    qtbot.mouseClick(button, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    assert results.result is not None, results.state.text()
    # the project has a file, but the truth is the terrain in the window, without plates
    assert ("400 points against the terrain as edited (unsaved changes: the GCP plates "
            "left out)") in results.state.text(), results.state.text()

    QTest.keyClick(w.windowHandle(), Qt.Key.Key_S, Qt.KeyboardModifier.ControlModifier)
    wait_idle(qtbot, w)
    assert not w.document.dirty
    answer_file_dialog(path)
    qtbot.mouseClick(button, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    qtbot.waitUntil(lambda: "survey.xml" in results.state.text(), timeout=60000)
    assert "400 points against terrain and targets of survey.xml" in results.state.text()


def _cloud_on_the_terrain(w, tmp_path, n: int):
    """``n`` points 1 cm (σ) about the open terrain, in world coordinates (seeded)."""
    import numpy as np

    from tests.gui.helpers import write_xyz_ply

    e = w.document.project.scene.terrain.extent
    rng = np.random.default_rng(3)
    x = rng.uniform(e.min_X + 10, e.max_X - 10, n)
    y = rng.uniform(e.min_Y + 10, e.max_Y - 10, n)
    z = w.sync.terrain.heightfield.height_at(x, y) + rng.normal(0.0, 0.01, n)
    path = tmp_path / "cloud.ply"
    write_xyz_ply(path, np.column_stack([x, y, z]))
    return path


def test_greyed_cloud_fields_show_what_switching_the_clouds_on_gives(qtbot, window):
    from PySide6.QtWidgets import QDoubleSpinBox

    from designer.gui.qt.panels.lighting import DEFAULT_CLOUDS
    from tests.gui.helpers import field

    w = window
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    panel = open_panel(w, "Lighting")
    assert w.document.project.scene.lighting.clouds is None
    boxes = {name: field(w, QDoubleSpinBox, f"scene.lighting.clouds.{name}")
             for name in ("cover", "size_m", "softness_m", "depth", "wind_speed_m_s")}
    shown = {name: box.value() for name, box in boxes.items()}
    assert not any(box.isEnabled() for box in boxes.values())
    assert shown == {name: getattr(DEFAULT_CLOUDS, name) for name in boxes}

    box = panel.cloudy  # the check box, clicked: the clouds the fields showed
    QTest.mouseClick(box, Qt.MouseButton.LeftButton, pos=QPoint(8, box.height() // 2))
    wait_idle(qtbot, w)
    assert w.document.project.scene.lighting.clouds == DEFAULT_CLOUDS
    assert all(box.isEnabled() for box in boxes.values())
    assert {name: box.value() for name, box in boxes.items()} == shown
