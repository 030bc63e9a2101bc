"""The GCPs panel's messages are shown whole: wrapped inside the panel's width (never
cut at its right edge or bottom), the whole text also the label's tooltip."""

from __future__ import annotations

import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtWidgets import QPushButton

from tests.gui.helpers import open_panel, set_field, wait_idle

pytestmark = pytest.mark.gui


def _shown_whole(label) -> None:
    """Every line of ``label`` lies inside what its panel shows of it."""
    text = label.text()
    assert text
    # the label is as high as its wrapped text needs at its width …
    assert label.height() >= label.heightForWidth(label.width()), (
        label.height(), label.heightForWidth(label.width()))
    # … and the whole label is inside the visible part of the panel (its dock's scroll
    # area): its corners are in the visible region
    visible = label.visibleRegion()
    for corner in (label.rect().topLeft(), label.rect().bottomRight() - QPoint(1, 1)):
        assert visible.contains(corner), (corner, visible.boundingRect(), label.rect())
    assert label.toolTip() == text


def test_the_layout_refusal_is_shown_whole(qtbot, window):
    w = window
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    gcps = open_panel(w, "GCPs")
    set_field(qtbot, gcps.count, "4")
    set_field(qtbot, gcps.n_check, "6")
    button = next(b for b in gcps.findChildren(QPushButton) if b.text() == "Apply layout")
    qtbot.mouseClick(button, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    label = gcps.error_label
    assert label.text().endswith("give at most 4; not applied"), label.text()
    qtbot.wait(100)
    _shown_whole(label)
