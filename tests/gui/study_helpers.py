"""Helpers of the Study panel tests: a tiny base project, adding a factor, waiting for the check."""

from __future__ import annotations

from PySide6.QtCore import Qt

from designer.study.templates import write_template
from tests.gui.helpers import wait_idle


def _tiny_base(qtbot, w, folder):
    """The tiny study's base project (160 × 120 px images) open in the window."""
    write_template("tiny", folder / "tiny-template.xml")
    base = folder / "tiny-template-base.xml"
    assert w.open_project(base)
    wait_idle(qtbot, w)
    panel = w.panels["Study"]
    w.docks["Study"].raise_()
    return panel, base


def _add(qtbot, panel, name: str, levels: str):
    """Choose the factor in the list, press Add, type its levels."""
    choice = panel.factor_choice
    choice.setFocus()
    qtbot.keyClick(choice, Qt.Key.Key_Home)
    while choice.currentData() != name:
        index = choice.currentIndex()
        qtbot.keyClick(choice, Qt.Key.Key_Down)
        assert choice.currentIndex() != index, f"no factor {name} in the list"
    qtbot.mouseClick(panel.add_button, Qt.MouseButton.LeftButton)
    row = panel.rows[-1]
    assert row.name == name
    qtbot.keyClicks(row.levels, levels)
    return row


def _checked(qtbot, w, panel) -> str:
    """Wait for the check of the current study; the plan line (or the errors)."""
    qtbot.waitUntil(lambda: not panel._timer.isActive(), timeout=5000)
    wait_idle(qtbot, w)
    return panel.plan_label.text()
