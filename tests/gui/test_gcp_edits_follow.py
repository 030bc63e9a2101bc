"""The GCP table and the control selection follow what is done to a GCP: a moved GCP's
image count, a renamed or deleted GCP's control id, the GCP mode kept over save and
reopen."""

from __future__ import annotations

import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtTest import QTest

from designer.gui.qt.panels.gcps import IMAGES_COLUMN
from designer.gui.state import edits
from designer.survey.plan_report import plan_project, plan_summary
from tests.gui.helpers import activate, open_panel, wait_idle

pytestmark = pytest.mark.gui


def _images_column(table) -> dict[str, str]:
    return {table.item(r, 0).text(): table.item(r, IMAGES_COLUMN).text()
            for r in range(table.rowCount())}


def _plan_counts(w) -> dict[str, str]:
    s = plan_summary(plan_project(w.document.project, w.document.base_dir))
    return {g["id"]: str(g["images"]) for g in s["gcps"]}


def _type_over(qtbot, w, table, row: int, col: int, text: str) -> None:
    """Double-click the cell, type over it, Enter; returns as soon as the edit is in
    (no time for background work after it)."""
    rect = table.visualItemRect(table.item(row, col))
    pos = table.viewport().mapTo(w, rect.center())
    QTest.mouseDClick(w.windowHandle(), Qt.MouseButton.LeftButton,
                      Qt.KeyboardModifier.NoModifier, pos)
    qtbot.wait(100)
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_A, Qt.KeyboardModifier.ControlModifier)
    for ch in text:
        QTest.keyClick(w.windowHandle(), ch)
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Return)


def _on_screen(w, xyz) -> QPoint:
    ren = w.view.plotter.renderer
    ren.SetWorldPoint(*(xyz - w.view.offset), 1.0)
    ren.WorldToDisplay()
    xd, yd, _ = ren.GetDisplayPoint()
    return QPoint(round(xd), round(w.view.plotter.height() - 1 - yd))


def test_a_moved_gcp_shows_its_new_image_count_at_once(qtbot, window):
    w = window
    activate(qtbot, w)
    project = edits.set_flight(edits.ensure_flight_plan(w.document.project),
                               area=((-20.0, -20.0), (20.0, -20.0), (20.0, 20.0),
                                     (-20.0, 20.0)), altitude_agl_m=20.0)
    project = edits.add_target(edits.add_target(project, 0.0, 0.0), -49.0, 49.5)
    w.editor.edit(project, "a flight, a GCP in it and one in a corner")
    gcps = open_panel(w, "GCPs")
    wait_idle(qtbot, w)
    table = gcps.table
    before = _images_column(table)
    assert before == _plan_counts(w) and int(before["GCP02"]) < 3

    # the corner GCP typed into the flight's middle: its count follows with the edit
    _type_over(qtbot, w, table, 1, 2, "2")
    assert w.document.project.targets[1].true.X == 2.0
    assert _images_column(table) == _plan_counts(w), "the old count shown"
    qtbot.wait(50)
    _type_over(qtbot, w, table, 1, 3, "3")
    assert w.document.project.targets[1].true.Y == 3.0
    after = _images_column(table)
    assert after == _plan_counts(w), "the old count shown"
    assert int(after["GCP02"]) >= 3
    assert table.item(1, IMAGES_COLUMN).background().color().red() < 200
    assert "GCPs seen" not in w.panels["Flight"].warnings_label.text()
    wait_idle(qtbot, w)
    assert _images_column(table) == after  # and the flight's own analysis agrees

    # dragged in the 3D view: the same
    w.view.interaction.set_mode("place")
    start = _on_screen(w, w.sync.targets.true_xyz[1])
    end = start + QPoint(80, 40)
    qtbot.mousePress(w.view.plotter, Qt.MouseButton.LeftButton, pos=start)
    qtbot.mouseMove(w.view.plotter, pos=start + QPoint(40, 20))
    qtbot.mouseMove(w.view.plotter, pos=end)
    qtbot.mouseRelease(w.view.plotter, Qt.MouseButton.LeftButton, pos=end)
    moved = w.document.project.targets[1].true
    assert (moved.X, moved.Y) != (2.0, 3.0)
    dragged = _images_column(table)
    assert dragged == _plan_counts(w), "the old count shown"
    wait_idle(qtbot, w)
    assert _images_column(table) == dragged
    # and undone, twice: the counts come back with the positions
    w.undo_stack.undo()
    assert _images_column(table) == after
    w.undo_stack.undo()
    w.undo_stack.undo()
    assert _images_column(table) == before
    wait_idle(qtbot, w)
    assert _images_column(table) == before
