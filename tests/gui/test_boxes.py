"""The boxes the panels share: a file box's button browses, a checked group's checkbox
switches, an item list keeps the chosen item when refilled and says nothing while it
is, its buttons add and remove, and readouts and logs are laid out as asked."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QFormLayout, QPushButton, QVBoxLayout, QWidget

from designer.gui.qt.boxes import (
    checked_group,
    chosen_index,
    file_box,
    item_chooser,
    log_view,
    readouts,
    refill_chooser,
)

pytestmark = pytest.mark.gui


def test_a_file_box_shows_no_file_until_browsed(qtbot):
    browsed = []
    box, name = file_box("image", "Choose…", lambda: browsed.append(True))
    qtbot.addWidget(box)
    assert box.title() == "image" and name.text() == "–" and name.wordWrap()
    button = box.findChild(QPushButton)
    assert button.text() == "Choose…"
    qtbot.mouseClick(button, Qt.MouseButton.LeftButton)
    assert browsed == [True]


def test_a_checked_group_leads_with_its_checkbox(qtbot):
    toggled = []
    box, fields, check = checked_group("wind", "plants sway", toggled.append, "tip")
    qtbot.addWidget(box)
    assert box.title() == "wind" and box.toolTip() == "tip"
    assert fields.rowCount() == 1
    assert fields.itemAt(0, QFormLayout.ItemRole.SpanningRole).widget() is check
    check.setChecked(True)
    check.setChecked(False)
    assert toggled == [True, False]


def test_an_item_list_keeps_its_choice_and_its_buttons_call_back(qtbot):
    widget = QWidget()
    qtbot.addWidget(widget)
    layout = QVBoxLayout(widget)
    calls = []
    chooser, added, remove = item_chooser(
        layout, "things", lambda: calls.append("choose"),
        [("add a", lambda: calls.append("a")), ("add b", lambda: calls.append("b"))],
        lambda: calls.append("remove"))
    assert chooser.objectName() == "things"
    assert [b.text() for b in added] == ["add a", "add b"] and remove.text() == "remove"
    for button in (*added, remove):
        qtbot.mouseClick(button, Qt.MouseButton.LeftButton)
    assert calls == ["a", "b", "remove"]
    calls.clear()

    assert chosen_index(chooser) == 0  # none yet: the first
    refill_chooser(chooser, [("one", 1), ("two", 2), ("three", 3)])
    assert calls == [] and chooser.currentIndex() == 0  # refilled without a choice
    chooser.setCurrentIndex(2)
    assert calls == ["choose"]
    refill_chooser(chooser, [("uno", 1), ("dos", 2), ("tres", 3)])
    assert chooser.currentText() == "tres" and chooser.currentData() == 3
    refill_chooser(chooser, [("uno", 1), ("dos", 2)])  # shorter: the last
    assert chooser.currentText() == "dos" and calls == ["choose"]
    refill_chooser(chooser, [])
    assert chooser.count() == 0 and chosen_index(chooser) == 0


def test_readouts_and_logs(qtbot):
    widget = QWidget()
    qtbot.addWidget(widget)
    layout = QVBoxLayout(widget)
    a, b = readouts(layout, "sun", "shadows")
    fields = layout.itemAt(0).layout()
    assert [fields.itemAt(k, QFormLayout.ItemRole.LabelRole).widget().text()
            for k in range(2)] == ["sun", "shadows"]
    assert fields.itemAt(1, QFormLayout.ItemRole.FieldRole).widget() is b
    assert a.text() == "–"
    log = log_view(3, 90)
    qtbot.addWidget(log)
    for k in range(5):
        log.appendPlainText(f"line {k}")
    assert log.isReadOnly() and log.maximumHeight() == 90
    assert log.toPlainText().splitlines() == ["line 2", "line 3", "line 4"]
