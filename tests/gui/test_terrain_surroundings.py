"""The Terrain panel's surroundings choice and procedural hill size, in a real window:
chosen with the keyboard and the mouse, through the undo stack, saved and reopened with
the same values; a hill size of 0, below 0 or not a number is refused where it is typed;
a mesh terrain is not offered auto surroundings (only a height field can be continued)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QApplication, QComboBox, QDoubleSpinBox

from designer.project import model as m
from tests.gui.helpers import field, open_panel, problems, set_field, wait_idle

pytestmark = pytest.mark.gui

HILL = "scene.terrain.source.hill_size_m"
SURROUNDINGS = "scene.terrain.surroundings"
ALLOWED = "allowed: more than 0 up to 1000000 m"


def _activate(qtbot, w) -> None:
    """Keyboard focus needs the active window (Xvfb has no window manager to give it)."""
    w.activateWindow()
    w.raise_()
    qtbot.waitUntil(w.isActiveWindow)


def _texts(box: QComboBox) -> list[str]:
    return [box.itemText(i) for i in range(box.count())]


def _key(qtbot, w, widget, key) -> None:
    """Give ``widget`` the focus, then press ``key`` as the window's keyboard does."""
    widget.setFocus()
    qtbot.waitUntil(widget.hasFocus)
    QTest.keyClick(w.windowHandle(), key)
    qtbot.wait(20)


def _choose(qtbot, w, box: QComboBox, text: str) -> None:
    """Open the combo box with the mouse and click the entry ``text`` in its list."""
    QTest.mouseClick(w.windowHandle(), Qt.MouseButton.LeftButton,
                     Qt.KeyboardModifier.NoModifier, box.mapTo(w, box.rect().center()))
    view = box.view()
    qtbot.waitUntil(view.isVisible)
    # the list ignores a release within a double-click interval of its opening (the
    # release of the click that opened it)
    qtbot.wait(QApplication.doubleClickInterval() + 50)
    index = box.model().index(_texts(box).index(text), 0)
    qtbot.mouseClick(view.viewport(), Qt.MouseButton.LeftButton,
                     pos=view.visualRect(index).center())
    qtbot.waitUntil(lambda: not view.isVisible())


def _undo_all(w, text: str) -> None:
    while w.undo_stack.undoText() == text:
        w.undo_stack.undo()


def test_surroundings_and_hill_size_are_edited_saved_and_reopened(qtbot, window, tmp_path):
    w = window
    _activate(qtbot, w)
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    panel = open_panel(w, "Terrain")
    before = w.document.project
    assert before.scene.terrain.surroundings is None
    assert before.scene.terrain.source.hill_size_m == 100.0
    around = field(panel, QComboBox, SURROUNDINGS)
    hill = field(panel, QDoubleSpinBox, HILL)
    # the kind's default is named; the field's limits are the file's (> 0 m)
    assert _texts(around) == ["auto (default)", "auto", "none"]
    assert around.currentText() == "auto (default)"
    assert (hill.minimum(), hill.maximum(), hill.suffix(), hill.value()) == (
        0.0, 1e6, " m", 100.0)
    assert not panel.surroundings_note.isVisibleTo(panel)
    heights = w.sync.terrain.heightfield.heights_m.copy()

    # keyboard: Down from the default to an explicit auto; the mouse: none
    _key(qtbot, w, around, Qt.Key.Key_Down)
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.surroundings == "auto"
    _choose(qtbot, w, around, "none")
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.surroundings == "none"
    assert around.currentText() == "none"
    assert "background" in panel.surroundings_note.text()

    # hill size typed, then stepped with the arrow key; the hills drawn change
    set_field(qtbot, hill, "250")
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.source.hill_size_m == 250.0
    _key(qtbot, w, hill, Qt.Key.Key_Up)
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.source.hill_size_m == 260.0
    assert not np.allclose(w.sync.terrain.heightfield.heights_m, heights)
    edited = w.document.project
    assert edited == dataclasses.replace(before, scene=dataclasses.replace(
        before.scene, terrain=dataclasses.replace(
            before.scene.terrain, surroundings="none",
            source=dataclasses.replace(before.scene.terrain.source, hill_size_m=260.0))))

    # undo: the hill size, then the surroundings; redo brings both back
    _undo_all(w, "Terrain hill size")
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.source.hill_size_m == 100.0
    assert hill.value() == 100.0
    assert w.document.project.scene.terrain.surroundings == "none"
    _undo_all(w, "Terrain surroundings")
    wait_idle(qtbot, w)
    assert w.document.project == before
    assert around.currentText() == "auto (default)"
    np.testing.assert_allclose(w.sync.terrain.heightfield.heights_m, heights)
    while w.undo_stack.canRedo():
        w.undo_stack.redo()
    wait_idle(qtbot, w)
    assert w.document.project == edited
    assert (around.currentText(), hill.value()) == ("none", 260.0)

    # saved and reopened: the same values, written as the schema says
    path = tmp_path / "hills.xml"
    assert w.file_actions.save_to(path), problems(w)
    text = path.read_text()
    assert '<surroundings mode="none"/>' in text and 'hill-size-m="260.0"' in text, text
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    assert w.file_actions.open(path), problems(w)
    wait_idle(qtbot, w)
    reopened = w.document.project.scene.terrain
    assert reopened == edited.scene.terrain
    assert (around.currentText(), hill.value()) == ("none", 260.0)

    # back to the kind's default: nothing is written, and it reopens as the default
    _choose(qtbot, w, around, "auto (default)")
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.surroundings is None
    assert w.file_actions.save_to(path), problems(w)
    assert "<surroundings" not in path.read_text()
    assert w.file_actions.open(path), problems(w)
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.surroundings is None
    assert around.currentText() == "auto (default)"


#: the way back a refusal names: the template's hill size
BACK = " (Esc: back to 100 m)"


@pytest.mark.parametrize("typed, message", [
    ("0", f"Terrain hill size: 0 is out of range; {ALLOWED}; not applied{BACK}"),
    ("-50", f"Terrain hill size: -50 is out of range; {ALLOWED}; not applied{BACK}"),
    # the field keeps 3 decimals: this would be stored as 0
    ("0.0004", f"Terrain hill size: 0.0004 rounds to 0 in this field; {ALLOWED}; "
               f"not applied{BACK}"),
    # the text quoted as the field shows it, with its unit
    ("big", f"Terrain hill size: “big m” is not a number ({ALLOWED}); not applied{BACK}"),
])
def test_a_bad_hill_size_is_refused_where_it_is_typed(qtbot, window, typed, message):
    w = window
    _activate(qtbot, w)
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    panel = open_panel(w, "Terrain")
    before = w.document.project
    hill = field(panel, QDoubleSpinBox, HILL)
    set_field(qtbot, hill, typed)
    wait_idle(qtbot, w)
    assert w.document.project == before, "applied"
    assert hill.property("invalid") and hill.text().strip().startswith(typed)
    assert panel.input_label.text() == message
    assert "hill-size-m" not in panel.input_label.text()
    # a valid size clears the message and is applied
    set_field(qtbot, hill, "0.5")
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.source.hill_size_m == 0.5
    assert not hill.property("invalid") and panel.input_label.text() == ""


def test_stepping_the_hill_size_down_to_0_is_refused(qtbot, window):
    w = window
    _activate(qtbot, w)
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    panel = open_panel(w, "Terrain")
    hill = field(panel, QDoubleSpinBox, HILL)
    set_field(qtbot, hill, "5")  # steps are 10 m: one down would be clamped to 0
    wait_idle(qtbot, w)
    stepped = w.document.project
    _key(qtbot, w, hill, Qt.Key.Key_Down)
    wait_idle(qtbot, w)
    assert w.document.project == stepped
    assert hill.property("invalid")
    assert panel.input_label.text() == (f"Terrain hill size: 0 is out of range; {ALLOWED}; "
                                        "not applied")


def _mesh_terrain(w, surroundings: str | None) -> None:
    """A small mesh terrain (the file need not exist for the panel's choices)."""
    project = w.document.project
    terrain = m.Terrain(project.scene.terrain.extent, m.MeshTerrain("ground.ply"),
                        surroundings)
    w.editor.edit(dataclasses.replace(project, scene=dataclasses.replace(
        project.scene, terrain=terrain)), "mesh")


def test_a_mesh_terrain_is_not_offered_auto_surroundings(qtbot, window):
    w = window
    _activate(qtbot, w)
    panel = open_panel(w, "Terrain")
    around = field(panel, QComboBox, SURROUNDINGS)
    _mesh_terrain(w, None)
    qtbot.waitUntil(lambda: w.document.project.scene.terrain.kind == "mesh")
    assert _texts(around) == ["none (default)", "auto (not for a mesh)", "none"]
    auto = around.model().item(1)
    assert not auto.isEnabled()
    assert "mesh terrain is rendered as it is" in panel.surroundings_note.text()
    # the keyboard passes over auto: Down from the default goes to none
    _key(qtbot, w, around, Qt.Key.Key_Down)
    assert w.document.project.scene.terrain.surroundings == "none"
    _key(qtbot, w, around, Qt.Key.Key_Up)
    assert w.document.project.scene.terrain.surroundings is None

    # a mesh with auto (a file written elsewhere): shown as it is, and why it cannot be
    _mesh_terrain(w, "auto")
    qtbot.waitUntil(lambda: w.document.project.scene.terrain.surroundings == "auto")
    assert around.currentText() == "auto (not for a mesh)"
    note = panel.surroundings_note.text()
    assert note.startswith("auto cannot continue a mesh terrain"), note
    assert "choose none" in note and "mode=" not in note, note
    _choose(qtbot, w, around, "none")
    assert w.document.project.scene.terrain.surroundings == "none"
    assert not panel.surroundings_note.text().startswith("auto cannot")

    # back to procedural hills: auto is offered again, and the default named as auto
    panel.kind.setCurrentIndex(panel.kind.findData("procedural"))
    qtbot.waitUntil(lambda: w.document.project.scene.terrain.kind == "procedural")
    assert _texts(around) == ["auto (default)", "auto", "none"]
    assert around.model().item(1).isEnabled()
