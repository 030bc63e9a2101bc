"""The texture panel's non-repeating variation: on/off and its fields through the undo
stack, and the repeat readout that says when the tiled texture repeats inside an image."""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QDoubleSpinBox, QSpinBox

from designer.gui.state import edits
from tests.gui.helpers import field, set_field, wait_idle

pytestmark = pytest.mark.gui


def test_variation_on_edit_undo(qtbot, window):
    w = window
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "flight")
    wait_idle(qtbot, w)
    w.docks["Texture"].raise_()
    panel = w.panels["Texture"]
    w.editor.edit(edits.replace_path(w.document.project, "scene.texture.repeat_X", 10),
                  "tiles")
    w.editor.edit(edits.replace_path(w.document.project, "scene.texture.repeat_Y", 10),
                  "tiles")
    wait_idle(qtbot, w)
    assert w.document.project.scene.texture.variation is None
    strength = field(w, QDoubleSpinBox, "scene.texture.variation.strength")
    assert not strength.isEnabled()  # no variation: its fields are off
    assert "texture repeats every" in panel.repeat_label.text()

    panel.variation.setChecked(True)
    variation = w.document.project.scene.texture.variation
    assert variation is not None and variation.strength == 0.35
    assert strength.isEnabled()
    assert "does not repeat" in panel.repeat_label.text()

    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)
    set_field(qtbot, strength, "0.6")
    set_field(qtbot, field(w, QSpinBox, "scene.texture.variation.octaves"), "3")
    variation = w.document.project.scene.texture.variation
    assert (variation.strength, variation.octaves) == (0.6, 3)

    w.undo_stack.undo()  # octaves
    w.undo_stack.undo()  # strength
    assert w.document.project.scene.texture.variation.strength == 0.35
    assert w.document.project.scene.texture.variation.octaves == 4
    w.undo_stack.undo()  # on
    assert w.document.project.scene.texture.variation is None
    assert not panel.variation.isChecked()
    w.undo_stack.redo()
    assert panel.variation.isChecked()
    assert w.document.project.scene.texture.variation.strength == 0.35
