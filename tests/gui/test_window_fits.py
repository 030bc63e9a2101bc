"""At the window's default size (1600 × 1000) a surveyor reads without scrolling sideways
(issue 53, finding 5): every dock tab's title is whole in view (the left group showed
"Moving objec", its tabs scrolled), and the GCP table shows each target's id, role,
images and true X, Y, Z (it showed id, role, X and part of Y), each column as wide as
what it holds, with the right dock shown (round four: the true Z was cut, as narrow as
its header while every GCP lay on the ground and past the dock's edge once one was
typed)."""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QTabBar

from designer.project import template, write_project
from tests.gui.helpers import open_panel, problems, wait_idle

pytestmark = pytest.mark.gui

#: the GCP table's columns (logical indices) a surveyor reads at once
ESSENTIAL = {"id": 0, "role": 1, "X": 2, "Y": 3, "Z": 4, "images": 9}


def test_every_dock_tab_is_whole_in_view(qtbot, window):
    w = window
    assert w.size().width() == 1600 and w.size().height() == 1000
    bars = [bar for bar in w.findChildren(QTabBar)
            if bar.parent() is w and bar.isVisible() and bar.count() > 1]
    titles = {bar.tabText(i) for bar in bars for i in range(bar.count())}
    assert {"Terrain", "Moving objects", "Vegetation", "Camera", "Study"} <= titles, titles
    for bar in bars:
        for i in range(bar.count()):
            rect = bar.tabRect(i)
            assert bar.rect().contains(rect), (bar.tabText(i), rect, bar.rect())


def test_the_gcp_table_shows_id_role_images_and_position_unscrolled(qtbot, window,
                                                                    tmp_path):
    w = window
    path = tmp_path / "survey.xml"
    write_project(template("survey").project, path)
    assert w.file_actions.open(path), problems(w)
    gcps = open_panel(w, "GCPs")
    wait_idle(qtbot, w)
    table = gcps.table
    assert table.rowCount() == 10
    assert table.horizontalScrollBar().value() == 0
    header = table.horizontalHeader()
    width = table.viewport().width()
    for name, c in ESSENTIAL.items():
        left = header.sectionViewportPosition(c)
        right = left + header.sectionSize(c)
        assert 0 <= left and right <= width, (name, left, right, width)


def test_the_gcp_tables_columns_hold_their_values_whole_with_the_right_dock_shown(
        qtbot, window, tmp_path):
    import dataclasses

    from designer.gui.state import edits

    w = window
    path = tmp_path / "survey.xml"
    write_project(template("survey").project, path)
    assert w.file_actions.open(path), problems(w)
    gcps = open_panel(w, "GCPs")
    wait_idle(qtbot, w)
    assert w.docks["Flight"].isVisible() and not w.docks["Flight"].isFloating()
    table = gcps.table
    header = table.horizontalHeader()
    z_blank = header.sectionSize(ESSENTIAL["Z"])
    # a GCP on a mast: its true Z typed, a height of a high site with its millimetres
    t = w.document.project.targets[0]
    raised = dataclasses.replace(t, true=dataclasses.replace(t.true, Z=1234.567))
    w.editor.edit(edits.replace_target(w.document.project, 0, raised), "Z")
    wait_idle(qtbot, w)
    assert table.item(0, ESSENTIAL["Z"]).text() == "1234.567"
    assert header.sectionSize(ESSENTIAL["Z"]) == z_blank  # the column kept its width
    width = table.viewport().width()
    for name, c in ESSENTIAL.items():
        left = header.sectionViewportPosition(c)
        right = left + header.sectionSize(c)
        assert 0 <= left and right <= width, (name, left, right, width)
        # the column is as wide as its values and header: nothing in it is cut
        assert header.sectionSize(c) >= max(table.sizeHintForColumn(c),
                                            header.sectionSizeHint(c)), name


def test_an_empty_studys_errors_show_without_scrolling_the_study_panel(qtbot, window):
    """Round four: the errors of a study without factors lay below the fold of the Study
    panel (under the run's progress bar and log); they show under Run, unscrolled."""
    from PySide6.QtCore import QPoint
    from PySide6.QtWidgets import QScrollArea

    w = window
    panel = open_panel(w, "Study")
    wait_idle(qtbot, w)
    qtbot.waitUntil(panel.errors.isVisible, timeout=10000)
    assert "no factor yet" in panel.errors.text()
    area = panel.findChild(QScrollArea)  # the panel's own, around its fields
    assert area.verticalScrollBar().value() == 0
    viewport = area.viewport()
    for widget in (panel.errors, panel.run_box.run_button, panel.run_box.reason):
        top = widget.mapTo(viewport, QPoint(0, 0)).y()
        assert 0 <= top and top + widget.height() <= viewport.height(), (
            widget.objectName(), top, widget.height(), viewport.height())
