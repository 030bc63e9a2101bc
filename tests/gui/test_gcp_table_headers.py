"""Every header of the GCPs table reads whole ("images", "Z (blank: on ground)"), at the
window's default size and after the table is scrolled to its last column."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt

from tests.gui.helpers import answer_file_dialog, choose_menu, open_panel, wait_idle

pytestmark = pytest.mark.gui


def _cut_headers(table) -> list[str]:
    """The headers whose section is narrower than their text (with the style's margins)."""
    header = table.horizontalHeader()
    metrics = header.fontMetrics()
    cut = []
    for c in range(table.columnCount()):
        text = table.horizontalHeaderItem(c).text()
        need = metrics.horizontalAdvance(text)
        if header.sectionSize(c) < need:
            cut.append(f"{text!r}: {header.sectionSize(c)} px < {need} px")
    return cut


def test_every_gcp_header_reads_whole(qtbot, window, tmp_path):
    from designer.cli.main import main

    w = window
    path = tmp_path / "survey.xml"
    assert main(["new", str(path), "--template", "survey"]) == 0
    answer_file_dialog(path)
    choose_menu(qtbot, w, "File", "Open…")
    wait_idle(qtbot, w)
    gcps = open_panel(w, "GCPs")
    table = gcps.table
    qtbot.waitUntil(lambda: table.rowCount() > 0 and table.isVisible(), timeout=5000)
    qtbot.waitUntil(lambda: table.item(0, 9) is not None and bool(table.item(0, 9).text()),
                    timeout=60000)
    assert w.size().width() == 1600  # the default size
    assert not _cut_headers(table), _cut_headers(table)

    # click the first cell and go to the row's end with the keyboard: the table scrolls
    rect = table.visualItemRect(table.item(0, 0))
    qtbot.mouseClick(table.viewport(), Qt.MouseButton.LeftButton, pos=rect.center())
    qtbot.keyClick(table, Qt.Key.Key_End)
    bar = table.horizontalScrollBar()
    qtbot.waitUntil(lambda: bar.value() == bar.maximum(), timeout=3000)
    assert bar.maximum() > 0  # the table is wider than its panel: it did scroll
    qtbot.wait(100)
    assert not _cut_headers(table), _cut_headers(table)
    # the last header is whole inside the view, not cut by its right edge
    header = table.horizontalHeader()
    last = table.columnCount() - 1
    right = header.sectionViewportPosition(last) + header.sectionSize(last)
    assert right <= header.viewport().width(), (right, header.viewport().width())
