"""Exceptions no slot caught: shown in the window, logged, never only in the terminal.

Qt calls ``sys.excepthook`` for an exception that leaves a Python slot (and the
document's listeners do the same for theirs). The window installs :class:`ExceptHook`:
it logs the traceback (logger ``designer.gui``) and shows the exception's one-line
summary in the window's :class:`ErrorBar` (a red bar above the 3D view; the traceback
in its tooltip and under Details), then hands the exception on to the hook that was
there before unless that one only prints it (the log does that already).
"""

from __future__ import annotations

import logging
import sys
import traceback
import weakref

from PySide6.QtWidgets import QFrame, QHBoxLayout, QLabel, QMessageBox, QPushButton

log = logging.getLogger("designer.gui")

BAR_STYLE = ("QFrame#error-bar { background: #fdecea; border: 1px solid #c0392b; } "
             "QFrame#error-bar QLabel { color: #8e1c12; }")


def summary(exc_type, exc, tb) -> str:
    """``Type: message (in function, file:line)`` — the innermost frame."""
    message = str(exc).strip().splitlines()
    text = exc_type.__name__ + (f": {message[0]}" if message else "")
    frames = traceback.extract_tb(tb) if tb is not None else []
    if frames:
        last = frames[-1]
        text += f" (in {last.name}, {last.filename.rsplit('/', 1)[-1]}:{last.lineno})"
    return text


class ErrorBar(QFrame):
    """A hidden bar that shows the last uncaught exception until dismissed."""

    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self.setObjectName("error-bar")
        self.setStyleSheet(BAR_STYLE)
        row = QHBoxLayout(self)
        row.setContentsMargins(8, 4, 8, 4)
        self.message = QLabel("")
        self.message.setObjectName("error-message")
        self.message.setWordWrap(True)
        self.details = QPushButton("Details…")
        self.details.clicked.connect(self._show_details)
        self.dismiss = QPushButton("Dismiss")
        self.dismiss.clicked.connect(self.clear)
        row.addWidget(self.message, 1)
        row.addWidget(self.details)
        row.addWidget(self.dismiss)
        self.count = 0
        self.traceback = ""
        self.hook: ExceptHook | None = None
        self.hide()

    def show_error(self, line: str, details: str) -> None:
        self.count += 1
        self.traceback = details
        more = f" ({self.count} errors since the last Dismiss)" if self.count > 1 else ""
        self.message.setText(f"Something went wrong: {line}{more}. It was not done; "
                             "the details are in the log.")
        self.message.setToolTip(details)
        self.show()

    def clear(self) -> None:
        self.count = 0
        self.traceback = ""
        self.hide()

    def _show_details(self) -> None:
        box = QMessageBox(QMessageBox.Icon.Critical, "Error details", self.message.text(),
                          QMessageBox.StandardButton.Close, self)
        box.setDetailedText(self.traceback)
        box.open()
        self._details_box = box

    # ------------------------------------------------------------------ the hook
    def install(self) -> ExceptHook:
        """Make this bar the place uncaught exceptions are shown (until :meth:`uninstall`)."""
        self.hook = ExceptHook(self, sys.excepthook)
        sys.excepthook = self.hook
        return self.hook

    def uninstall(self) -> None:
        if self.hook is not None and sys.excepthook is self.hook:
            sys.excepthook = self.hook.previous
        self.hook = None


class ExceptHook:
    """``sys.excepthook`` that logs and shows in an :class:`ErrorBar`."""

    def __init__(self, bar: ErrorBar, previous) -> None:
        self._bar = weakref.ref(bar)
        self.previous = previous

    def __call__(self, exc_type, exc, tb) -> None:
        if issubclass(exc_type, KeyboardInterrupt):
            self.previous(exc_type, exc, tb)
            return
        line = summary(exc_type, exc, tb)
        log.error("uncaught exception: %s", line, exc_info=(exc_type, exc, tb))
        bar = self._bar()
        try:
            if bar is not None:
                bar.show_error(line, "".join(traceback.format_exception(exc_type, exc, tb)))
        except RuntimeError:  # the window is gone already
            pass
        if self.previous is not sys.__excepthook__:
            self.previous(exc_type, exc, tb)
