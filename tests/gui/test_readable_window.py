"""The window reads right at a glance: dock tabs show their whole titles, File → New
lists templates by readable titles, and a new project reads as new (not saved yet, not
modified) until it is edited."""

from __future__ import annotations

import re

import pytest
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QMessageBox, QTabBar

from designer.gui.state import edits
from designer.project import TEMPLATE_NAMES
from tests.gui.helpers import choose_menu, wait_idle

pytestmark = pytest.mark.gui


def _dock_tab_bars(w) -> list[QTabBar]:
    return [bar for bar in w.findChildren(QTabBar)
            if bar.parent() is w and bar.isVisible() and bar.count() > 1]


def test_dock_tabs_show_their_whole_titles(qtbot, window):
    w = window
    bars = _dock_tab_bars(w)
    titles = sorted(bar.tabText(i) for bar in bars for i in range(bar.count()))
    assert {"Terrain", "Vegetation", "Camera", "Study"} <= set(titles), titles
    for bar in bars:
        metrics = bar.fontMetrics()
        for i in range(bar.count()):
            text = bar.tabText(i)
            rect = bar.tabRect(i)  # tabs along the window's sides: their titles run down
            length = max(rect.width(), rect.height())
            assert length >= metrics.horizontalAdvance(text), (
                f"tab '{text}' is {length} px long, its title "
                f"{metrics.horizontalAdvance(text)} px")
    # a tab scrolled out of sight is still reached with a click on its title
    left = next(bar for bar in bars if "Vegetation" in
                [bar.tabText(i) for i in range(bar.count())])
    index = next(i for i in range(left.count()) if left.tabText(i) == "Vegetation")
    left.setCurrentIndex(index)
    qtbot.wait(50)
    assert w.panels["Vegetation"].isVisible()


def test_file_new_lists_templates_by_title(qtbot, window):
    w = window
    bar = w.menuBar()
    file_menu = next(a.menu() for a in bar.actions() if a.text().replace("&", "") == "File")
    new_menu = next(a.menu() for a in file_menu.actions()
                    if a.text().replace("&", "") == "New")
    entries = [a.text() for a in new_menu.actions() if a.text()]
    assert len(entries) == 1 + len(TEMPLATE_NAMES), entries
    for text in entries:
        assert text not in TEMPLATE_NAMES and not re.fullmatch(r"[a-z0-9-]+", text), entries
        assert text[0].isupper(), entries


def _reads_as_new(w) -> None:
    title = w.windowTitle()
    assert title.startswith("untitled.xml"), title
    assert "not saved" in title, title
    assert not w.isWindowModified(), title


def test_a_new_project_reads_as_new_until_it_is_edited(qtbot, window, monkeypatch):
    w = window
    asked = []
    monkeypatch.setattr(QMessageBox, "question", staticmethod(
        lambda *a, **k: asked.append(a[2]) or QMessageBox.StandardButton.Discard))
    _reads_as_new(w)  # the blank project the window starts with

    # a template from File → New: new, and nothing to lose
    choose_menu(qtbot, w, "File", "New", "Example survey (hills, 10 GCPs, grid flight)")
    wait_idle(qtbot, w)
    assert w.document.project.name.startswith("Example survey")
    _reads_as_new(w)
    assert asked == []

    # an edit: now it has changes to save, and New asks before dropping them
    w.editor.edit(edits.set_flight(w.document.project, altitude_agl_m=61.0), "height")
    wait_idle(qtbot, w)
    assert w.isWindowModified() and "not saved" in w.windowTitle()
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow, timeout=20000)  # under load a key sent before is lost
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    wait_idle(qtbot, w)
    _reads_as_new(w)  # undone: as it came
    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Z,
                   Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.ShiftModifier)
    wait_idle(qtbot, w)
    assert w.isWindowModified()
    choose_menu(qtbot, w, "File", "New", "Blank project")
    wait_idle(qtbot, w)
    assert len(asked) == 1 and "unsaved changes" in asked[0], asked
    _reads_as_new(w)


def test_one_photo_is_one_photo(qtbot, window, tmp_path):
    """Counts agree with their noun: a flight of one photo reads '1 photo', in the undo
    entry and the status bar."""
    import shutil

    from tests.flight.helpers import EXAMPLE
    from tests.gui.flight_helpers import _flown_images
    from tests.gui.helpers import answer_file_dialogs, problems

    w = window
    base = tmp_path / "base" / "survey.xml"
    shutil.copytree(EXAMPLE.parent, base.parent)
    assert w.open_project(base)
    wait_idle(qtbot, w)
    _flown_images(tmp_path / "flown", 1)
    answer_file_dialogs([tmp_path / "flown"])
    choose_menu(qtbot, w, "File", "Import flight", "From a folder of images…")
    wait_idle(qtbot, w)
    assert problems(w) == []
    assert len(w.document.project.trajectory.exterior_orientations) == 1
    status = w.statusBar().currentMessage()
    assert status.startswith("imported 1 photo from"), status
    assert w.undo_stack.text(w.undo_stack.index() - 1) == "Import flight (1 photo)"

    from designer.gui.state.wording import count

    assert count(1, "image") == "1 image" and count(3, "image") == "3 images"
    assert count(0, "GCP") == "0 GCPs" and count(1, "run") == "1 run"
