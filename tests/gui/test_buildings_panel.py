"""Buildings in the GUI: added, edited and removed through the undo stack in a real
window, and drawn in the 3D view as the renderer builds them."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox

from designer.gui.qt.panels.buildings import NEW_EAVE_M, NEW_RISE_M, NEW_SIZE_M
from designer.project.geometry import point_in_polygon
from tests.gui.helpers import field, open_panel, refused_message, set_field, wait_idle

pytestmark = pytest.mark.gui


def test_buildings_are_edited_through_the_undo_stack_and_drawn(qtbot, window):
    w = window
    panel = open_panel(w, "Buildings")
    assert w.document.project.scene.buildings == ()
    assert not panel.remove.isEnabled()

    qtbot.mouseClick(panel.add_house, Qt.MouseButton.LeftButton)
    qtbot.mouseClick(panel.add_block, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    p = w.document.project
    house, block = p.scene.buildings
    assert (house.id, house.roof, house.eave_height_m, house.ridge_height_m) == (
        "house1", "gable", NEW_EAVE_M["gable"], NEW_EAVE_M["gable"] + NEW_RISE_M)
    assert (block.id, block.roof, block.ridge_height_m) == ("block1", "flat", None)
    for b in (house, block):
        xy = [(q.X, q.Y) for q in b.footprint]
        assert np.ptp(xy, axis=0) == pytest.approx(NEW_SIZE_M)
        assert not any(point_in_polygon(t.true.X, t.true.Y, xy) for t in p.targets)
    # the block is flat: it has no ridge
    assert not field(panel, QDoubleSpinBox, "Building ridge height").isEnabled()
    # both are drawn in the view, standing on the terrain
    drawn = w.view._meshes["buildings"]
    assert drawn.n_cells == 16 + 12  # walls 8, floor 2, and roof 6 (gable) or 2 (flat)

    set_field(qtbot, field(panel, QDoubleSpinBox, "Building eave height"), "12")
    panel.roof.setCurrentIndex(panel.roof.findData("hip"))
    wait_idle(qtbot, w)
    block = w.document.project.scene.buildings[1]
    assert (block.roof, block.eave_height_m, block.ridge_height_m) == ("hip", 12.0, 15.0)
    assert field(panel, QDoubleSpinBox, "Building ridge height").isEnabled()

    panel.chooser.setCurrentIndex(0)
    qtbot.mouseClick(panel.remove, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    assert [b.id for b in w.document.project.scene.buildings] == ["block1"]

    w.undo_stack.undo()  # the house is back
    w.undo_stack.undo()  # the block is flat again
    w.undo_stack.undo()  # at its first height
    wait_idle(qtbot, w)
    house, block = w.document.project.scene.buildings
    assert (block.roof, block.eave_height_m, block.ridge_height_m) == (
        "flat", NEW_EAVE_M["flat"], None)
    w.undo_stack.undo()
    w.undo_stack.undo()
    wait_idle(qtbot, w)
    assert w.document.project.scene.buildings == ()
    assert "buildings" not in w.view._meshes


def test_a_ridge_at_or_below_the_walls_is_refused_where_it_is_typed(qtbot, window):
    """A gable house's ridge typed below its walls (6 m): refused in the typed numbers
    (the project check would refuse it only at Save or render); a ridge above is applied."""
    w = window
    panel = open_panel(w, "Buildings")
    qtbot.mouseClick(panel.add_house, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    before = w.document.project
    ridge = field(panel, QDoubleSpinBox, "Building ridge height")
    set_field(qtbot, ridge, "3")
    said = refused_message(qtbot, w, before, panel)
    assert "ridge (3 m) must be above the walls (6 m); not applied" in said, said
    assert ridge.property("invalid")
    set_field(qtbot, ridge, "8.5")
    wait_idle(qtbot, w)
    assert w.document.project.scene.buildings[0].ridge_height_m == 8.5
    assert not ridge.property("invalid")
