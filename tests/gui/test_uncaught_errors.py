"""Nothing fails silently: an exception no slot caught is shown in the window (its one-line
summary, the traceback under Details) and logged, not only printed in the terminal."""

from __future__ import annotations

import logging
import sys

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QPushButton

pytestmark = pytest.mark.gui


def _broken() -> None:
    {}["no-such-key"]


# pytest-qt would otherwise take the exception itself and fail the test
@pytest.mark.qt_no_exception_capture
def test_an_error_in_a_slot_is_shown_in_the_window_and_logged(qtbot, window, caplog):
    w = window
    button = QPushButton("Break")
    button.clicked.connect(_broken)
    w.statusBar().addPermanentWidget(button)
    qtbot.waitExposed(button)
    assert not w.error_bar.isVisible()
    hook = w.error_bar.hook
    assert sys.excepthook is hook

    with caplog.at_level(logging.ERROR, logger="designer.gui"):
        qtbot.mouseClick(button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(w.error_bar.isVisible, timeout=5000)
    text = w.error_bar.message.text()
    assert "KeyError" in text and "no-such-key" in text, text
    assert "_broken" in text  # where it happened
    assert "_broken" in w.error_bar.message.toolTip()  # the traceback
    logged = [r for r in caplog.records if r.name == "designer.gui" and r.exc_info]
    assert logged and logged[0].exc_info[0] is KeyError

    # a second error replaces the first; Dismiss hides the bar
    qtbot.mouseClick(button, Qt.MouseButton.LeftButton)
    assert "2 errors" in w.error_bar.message.text()
    qtbot.mouseClick(w.error_bar.dismiss, Qt.MouseButton.LeftButton)
    assert not w.error_bar.isVisible()

    # the window's hook is taken away with the window
    w.close()
    assert sys.excepthook is hook.previous
