"""The status bar says what is wrong only while it is: a terrain or texture error posted
there goes when the error does (fixed, or undone), not at its timeout; a later message
about something else stays."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QDoubleSpinBox

from designer.gui.qt.widgets import format_number as num
from tests.gui.helpers import field, open_panel, set_field, wait_idle

pytestmark = pytest.mark.gui


def _undo(qtbot, w) -> None:
    """Ctrl+Z, as typed (the Edit menu would show its entries' tips over the status bar)."""
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)


def _break_texture(qtbot, w) -> None:
    """An 1100 m wide terrain makes 220 m tiles of 8800 texels: the texture cannot be
    made. The Terrain panel refuses to type such an extent, so it comes as a project
    opened that way would (through the editor, undoable)."""
    from dataclasses import replace

    p = w.document.project
    e = p.scene.terrain.extent
    terrain = replace(p.scene.terrain, extent=replace(e, max_X=e.min_X + 1100))
    w.editor.edit(replace(p, scene=replace(p.scene, terrain=terrain)), "Terrain extent max X")
    wait_idle(qtbot, w)


def test_a_texture_error_leaves_the_status_bar_when_fixed(qtbot, window):
    w = window
    assert w.file_actions.new("survey")  # 100 × 100 m, repeat 5 × 5, 0.025 m texels
    wait_idle(qtbot, w)
    terrain = open_panel(w, "Terrain")
    e = w.document.project.scene.terrain.extent
    max_x = field(terrain, QDoubleSpinBox, "scene.terrain.extent.max_X")
    _break_texture(qtbot, w)
    assert w.sync.errors.get("texture"), w.sync.errors
    assert w.statusBar().currentMessage().startswith("texture:"), \
        w.statusBar().currentMessage()
    set_field(qtbot, max_x, num(e.max_X))  # fixed where it was broken
    wait_idle(qtbot, w)
    assert not w.sync.errors.get("texture"), w.sync.errors
    assert not w.statusBar().currentMessage().startswith("texture:"), \
        w.statusBar().currentMessage()


def test_an_undone_error_leaves_the_status_bar_but_not_a_later_message(qtbot, window):
    w = window
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    open_panel(w, "Terrain")
    e = w.document.project.scene.terrain.extent
    _break_texture(qtbot, w)
    assert w.sync.errors.get("texture"), w.sync.errors
    status = w.statusBar().currentMessage()
    assert status.startswith("texture:"), status
    _undo(qtbot, w)
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.extent == e
    assert not w.sync.errors.get("texture")
    assert w.statusBar().currentMessage() != status, status
    # once more, with a later message about something else: that one stays
    _break_texture(qtbot, w)
    w.statusBar().showMessage("saved elsewhere")  # no timeout: only a withdrawal could clear it
    _undo(qtbot, w)
    wait_idle(qtbot, w)
    assert not w.sync.errors.get("texture")
    assert w.statusBar().currentMessage() == "saved elsewhere"


def test_a_refused_value_leaves_the_status_bar_when_the_field_is_valid_again(qtbot, window):
    """A typed value out of range is said in the panel and the status bar; typing a valid
    one (or an undo putting the project's value back) takes it from both, while a later
    message about something else stays."""
    from PySide6.QtWidgets import QLabel

    from designer.gui.state import edits
    from tests.gui.helpers import activate, type_text

    w = window
    activate(qtbot, w)
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "flight")
    flight = open_panel(w, "Flight")
    wait_idle(qtbot, w)
    box = field(w, QDoubleSpinBox, "trajectory.flight_plan.front_overlap_percent")
    message = flight.findChild(QLabel, "input-errors")
    type_text(qtbot, w, box, "150")
    refusal = w.statusBar().currentMessage()
    assert "150 is out of range" in refusal and message.isVisible(), refusal
    type_text(qtbot, w, box, "75")
    assert w.document.project.trajectory.flight_plan.front_overlap_percent == 75.0
    assert not message.isVisible()
    assert "out of range" not in w.statusBar().currentMessage(), \
        w.statusBar().currentMessage()
    # refused again, then the value put back by an undo
    type_text(qtbot, w, box, "150")
    assert "out of range" in w.statusBar().currentMessage()
    w.undo_action.trigger()
    assert box.property("invalid") is False and not message.isVisible()
    assert "out of range" not in w.statusBar().currentMessage(), \
        w.statusBar().currentMessage()
    # a later message about something else is not taken away with a refusal
    type_text(qtbot, w, box, "150")
    w.statusBar().showMessage("saved elsewhere")
    type_text(qtbot, w, box, "70")
    assert not message.isVisible()
    assert w.statusBar().currentMessage() == "saved elsewhere"
