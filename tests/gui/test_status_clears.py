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
