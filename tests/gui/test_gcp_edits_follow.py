"""The GCP table and the control selection follow what is done to a GCP: a moved GCP's
image count, a renamed or deleted GCP's control id, the GCP mode kept over save and
reopen."""

from __future__ import annotations

import dataclasses

import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QPushButton

from designer.checks.plan_report import plan_project, plan_summary
from designer.gui.qt.panels.gcps import IMAGES_COLUMN
from designer.gui.state import edits
from tests.gui.helpers import (
    activate,
    open_panel,
    problems,
    set_field,
    type_cell,
    wait_idle,
)

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


def _select_row(qtbot, w, table, row: int) -> None:
    """Click the row's id cell (the table takes the focus and selects the row)."""
    rect = table.visualItemRect(table.item(row, 0))
    QTest.mouseClick(w.windowHandle(), Qt.MouseButton.LeftButton,
                     Qt.KeyboardModifier.NoModifier, table.viewport().mapTo(w, rect.center()))
    qtbot.waitUntil(table.hasFocus)


def _ids(w) -> tuple[str, ...]:
    return w.document.project.processing.gcps.control.ids


def test_control_ids_follow_a_renamed_or_deleted_gcp(qtbot, window, tmp_path):
    from designer.project import load_project
    from designer.project import processing as pr

    w = window
    activate(qtbot, w)
    project = edits.ensure_flight_plan(w.document.project)
    for x in (-10.0, 10.0, 0.0, -5.0):
        project = edits.add_target(project, x, 5.0)
    project = dataclasses.replace(project, processing=pr.Processing(gcps=pr.GcpProcessing(
        mode="bundle", control=pr.ControlSelection(ids=("GCP01", "GCP03")))))
    w.editor.edit(project, "four GCPs, GCP01 and GCP03 the control points")
    gcps = open_panel(w, "GCPs")
    wait_idle(qtbot, w)
    table = gcps.table
    ids_field = w.panels["Processing"].ids

    # renamed in the table: the control ids name the new id, and the file is valid
    type_cell(qtbot, w, table, 2, 0, "GCP09")
    assert _ids(w) == ("GCP01", "GCP09")
    assert ids_field.text() == "GCP01, GCP09"
    assert w.file_actions.save_to(tmp_path / "renamed.xml"), problems(w)
    assert load_project(tmp_path / "renamed.xml").processing.gcps.control.ids == (
        "GCP01", "GCP09")

    # deleted with the Delete key: its id goes from the control ids, the file is valid
    _select_row(qtbot, w, table, 0)
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Delete)
    assert [t.id for t in w.document.project.targets] == ["GCP02", "GCP09", "GCP04"]
    assert _ids(w) == ("GCP09",)
    assert ids_field.text() == "GCP09"
    assert gcps.error_label.text() == ""
    assert w.file_actions.save_to(tmp_path / "deleted.xml"), problems(w)
    assert load_project(tmp_path / "deleted.xml").processing.gcps.control.ids == ("GCP09",)

    # the last GCP the control ids name: refused, saying where to choose others
    before = w.document.project
    _select_row(qtbot, w, table, 1)
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Delete)
    assert w.document.project == before
    text = gcps.error_label.text()
    assert text.startswith("GCP09 not deleted: GCP09 is the only control GCP named in the "
                           "Processing panel"), text
    assert "a subset of the targets as control" in text, text

    # a similarity after SfM left with two control GCPs: refused, saying why
    w.editor.edit(edits.replace_path(
        w.document.project, "processing.gcps", pr.GcpProcessing(
            mode="similarity", control=pr.ControlSelection(ids=("GCP02", "GCP09",
                                                                "GCP04")))),
        "three control GCPs for a similarity")
    wait_idle(qtbot, w)
    before = w.document.project
    _select_row(qtbot, w, table, 2)
    gcps.delete_button.click()
    assert w.document.project == before
    text = gcps.error_label.text()
    assert text.startswith("GCP04 not deleted: "), text
    assert "2 GCPs, but a similarity after SfM needs at least 3" in text, text

    # a control count above the GCPs left: refused as well
    w.editor.edit(edits.replace_path(
        w.document.project, "processing.gcps", pr.GcpProcessing(
            mode="bundle", control=pr.ControlSelection(count=3))), "three control GCPs")
    wait_idle(qtbot, w)
    before = w.document.project
    _select_row(qtbot, w, table, 0)
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Delete)
    assert w.document.project == before
    assert "control count 3, but the project would have 2 GCPs" in gcps.error_label.text()

    # an automatic layout keeps the control ids its GCPs still have …
    w.editor.edit(edits.replace_path(
        w.document.project, "processing.gcps", pr.GcpProcessing(
            mode="bundle", control=pr.ControlSelection(ids=("GCP02", "GCP09")))),
        "GCP02 and GCP09 the control points")
    wait_idle(qtbot, w)
    set_field(qtbot, gcps.count, "3")
    set_field(qtbot, gcps.n_check, "1")
    apply = next(b for b in gcps.findChildren(QPushButton) if b.text() == "Apply layout")
    qtbot.mouseClick(apply, Qt.MouseButton.LeftButton)
    assert [t.id for t in w.document.project.targets] == ["GCP01", "GCP02", "GCP03"]
    assert _ids(w) == ("GCP02",)
    assert w.file_actions.save_to(tmp_path / "layout.xml"), problems(w)
    # … and is refused when it has none of them
    w.editor.edit(edits.replace_path(w.document.project, "processing.gcps.control.ids",
                                     ("GCP03",)), "GCP03 the control point")
    wait_idle(qtbot, w)
    set_field(qtbot, gcps.count, "2")
    before = w.document.project
    qtbot.mouseClick(apply, Qt.MouseButton.LeftButton)
    assert w.document.project == before
    assert gcps.error_label.text().startswith(
        "layout not applied: GCP03 is the only control GCP named in the Processing panel")


def _choose_by_click(qtbot, combo, text: str) -> None:
    """Open the drop-down with a click, go to the item ``text`` with the arrow keys and
    press Enter."""
    qtbot.mouseClick(combo, Qt.MouseButton.LeftButton)
    view = combo.view()
    qtbot.waitUntil(view.isVisible)
    steps = combo.findText(text) - combo.currentIndex()
    for _ in range(abs(steps)):
        qtbot.keyClick(view, Qt.Key.Key_Down if steps > 0 else Qt.Key.Key_Up)
    qtbot.keyClick(view, Qt.Key.Key_Return)
    qtbot.waitUntil(lambda: not view.isVisible())


def test_the_gcp_mode_chosen_is_kept_over_save_and_reopen(qtbot, window, tmp_path):
    from PySide6.QtWidgets import QComboBox

    from designer.project import load_project
    from tests.gui.helpers import field, type_text

    w = window
    activate(qtbot, w)
    project = edits.ensure_flight_plan(w.document.project)
    for x in (-10.0, 10.0, 0.0, -5.0):
        project = edits.add_target(project, x, 5.0)
    w.editor.edit(project, "four GCPs")
    panel = open_panel(w, "Processing")
    wait_idle(qtbot, w)
    qtbot.mouseClick(panel.enabled, Qt.MouseButton.LeftButton)
    mode = field(w, QComboBox, "processing.gcps.mode")
    _choose_by_click(qtbot, mode, "in the bundle adjustment")
    qtbot.mouseClick(panel.subset, Qt.MouseButton.LeftButton)
    type_text(qtbot, w, panel.ids, "GCP01, GCP02")
    gcps = w.document.project.processing.gcps
    assert (gcps.mode, gcps.control.ids) == ("bundle", ("GCP01", "GCP02"))

    path = tmp_path / "two-control.xml"
    assert w.file_actions.save_to(path), problems(w)
    assert load_project(path).processing.gcps.mode == "bundle"
    assert w.file_actions.new(None)
    wait_idle(qtbot, w)
    assert w.file_actions.open(path), problems(w)
    wait_idle(qtbot, w)
    gcps = w.document.project.processing.gcps
    assert (gcps.mode, gcps.control.ids) == ("bundle", ("GCP01", "GCP02"))
    assert mode.currentText() == "in the bundle adjustment"
    assert panel.ids.text() == "GCP01, GCP02"

    # a similarity with these two control GCPs is refused where it is chosen, saying why
    before = w.document.project
    _choose_by_click(qtbot, mode, "similarity after SfM (7 parameters)")
    assert w.document.project == before
    assert mode.currentText() == "in the bundle adjustment"
    text = panel.input_label.text()
    assert ("GCP use: a similarity after SfM needs at least 3 control GCPs, and control "
            "GCPs (GCP01, GCP02) gives 2") in text, text
    assert "not applied" in text
    assert w.file_actions.save_to(path), problems(w)
    assert load_project(path).processing.gcps.mode == "bundle"
