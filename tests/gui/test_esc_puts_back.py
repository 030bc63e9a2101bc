"""Esc in a refused number field puts the project's value back (the typed text was never
applied), and the refusal says so; Esc in a field that holds a valid value is still the
window's key (back to navigating the view)."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QDoubleSpinBox

from tests.gui.helpers import activate, field, open_panel, type_text, wait_idle

pytestmark = pytest.mark.gui

HILL = "scene.terrain.source.hill_size_m"


def _esc(qtbot, w) -> None:
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Escape)
    qtbot.wait(20)


def test_esc_in_a_refused_field_puts_the_value_back(qtbot, window):
    w = window
    activate(qtbot, w)
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    panel = open_panel(w, "Terrain")
    hill = field(panel, QDoubleSpinBox, HILL)
    before, steps = w.document.project, w.undo_stack.count()

    for typed in ("abc", "-5", "\b"):  # letters, out of range, emptied (Backspace)
        type_text(qtbot, w, hill, typed)
        assert hill.property("invalid")
        message = panel.input_label.text()
        assert message.endswith("not applied (Esc: back to 100 m)"), message
        assert w.statusBar().currentMessage() == message

        _esc(qtbot, w)  # the key goes to the focused field, as a person's would
        assert hill.hasFocus()
        assert hill.lineEdit().text() == "100 m"
        assert not hill.property("invalid")
        assert panel.input_label.text() == "" and not panel.input_label.isVisible()
        assert w.statusBar().currentMessage() == ""
        assert w.document.project == before and w.undo_stack.count() == steps

    # a valid field leaves Esc to the window: it ends the place-GCPs mode
    w.panels["GCPs"].place.setChecked(True)
    assert w.view.interaction.mode == "place"
    hill.setFocus()
    qtbot.waitUntil(hill.hasFocus)
    _esc(qtbot, w)
    assert w.view.interaction.mode == "navigate"
    assert w.document.project == before


def test_render_waits_while_a_field_holds_what_it_refused(qtbot, saved_project,
                                                         monkeypatch, tmp_path):
    from designer.gui.qt.command_process import RenderProcess

    w = saved_project
    started = []
    monkeypatch.setattr(RenderProcess, "start", lambda self, *a, **k: started.append(a))
    activate(qtbot, w)
    panel = open_panel(w, "Render")
    scale = field(panel, QDoubleSpinBox, "render.resolution_scale")
    kept = scale.lineEdit().text()
    type_text(qtbot, w, scale, "0.01")  # no whole number of pixels: refused
    assert scale.property("invalid")

    QTest.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    assert started == []  # nothing renders with the project's other value unsaid
    said = panel.state.text()
    assert said.startswith("not rendered: a field refused what was typed: resolution "
                           "scale 0.01"), said
    assert said.endswith(f"(Esc: back to {kept})"), said

    scale.setFocus()
    _esc(qtbot, w)
    QTest.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    assert len(started) == 1
