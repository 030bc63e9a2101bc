"""Vegetation in the GUI: switched on, groups added, edited and removed, the wind
switched on, all through the undo stack in a real window; the panel says the plants stand
upright while there is no time line."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox

from designer.gui.state.switched_on import NEW_DENSITY_PER_M2
from designer.project import model as m
from tests.gui.helpers import field, open_panel, set_field, wait_idle

pytestmark = pytest.mark.gui


def test_vegetation_is_edited_through_the_undo_stack(qtbot, window):
    w = window
    panel = open_panel(w, "Vegetation")
    assert w.document.project.scene.vegetation is None
    density = field(panel, QDoubleSpinBox, "Plant density")
    assert not panel.remove.isEnabled() and not density.isEnabled()

    panel.enabled.setChecked(True)
    wait_idle(qtbot, w)
    veg = w.document.project.scene.vegetation
    assert [g.kind for g in veg.plants] == ["shrub"] and veg.wind is None
    qtbot.mouseClick(panel.add_buttons["tree"], Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    groups = w.document.project.scene.vegetation.plants
    assert [(g.kind, g.density_per_m2, g.height_m, g.crown_m) for g in groups] == [
        ("shrub", NEW_DENSITY_PER_M2["shrub"], *m.PLANT_KINDS["shrub"]),
        ("tree", NEW_DENSITY_PER_M2["tree"], *m.PLANT_KINDS["tree"])]
    assert panel.chooser.currentIndex() == 1
    assert "about" in panel.count_label.text()

    set_field(qtbot, field(panel, QDoubleSpinBox, "Plant height"), "12")
    set_field(qtbot, field(panel, QDoubleSpinBox, "Plant density"), "0.02")
    wait_idle(qtbot, w)
    tree = w.document.project.scene.vegetation.plants[1]
    assert (tree.height_m, tree.density_per_m2) == (12.0, 0.02)
    assert w.document.project.scene.vegetation.plants[0].height_m == 1.0

    panel.windy.setChecked(True)
    wait_idle(qtbot, w)
    assert w.document.project.scene.vegetation.wind == m.Wind()
    assert "upright" in panel.wind_note.text()  # the window's project has no time line
    set_field(qtbot, field(panel, QDoubleSpinBox, "scene.vegetation.wind.amplitude_deg"), "8")
    wait_idle(qtbot, w)
    assert w.document.project.scene.vegetation.wind.amplitude_deg == 8.0

    panel.chooser.setCurrentIndex(0)
    assert field(panel, QDoubleSpinBox, "Plant height").value() == 1.0
    qtbot.mouseClick(panel.remove, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    assert [g.kind for g in w.document.project.scene.vegetation.plants] == ["tree"]

    for _ in range(3):  # the shrubs come back, the wind calms, then stops
        w.undo_stack.undo()
    wait_idle(qtbot, w)
    veg = w.document.project.scene.vegetation
    assert [g.kind for g in veg.plants] == ["shrub", "tree"] and veg.wind is None

    w.panels["Flight"].timed.setChecked(True)
    panel.windy.setChecked(True)
    wait_idle(qtbot, w)
    assert "sway" in panel.wind_note.text()
    panel.enabled.setChecked(False)
    wait_idle(qtbot, w)
    assert w.document.project.scene.vegetation is None
