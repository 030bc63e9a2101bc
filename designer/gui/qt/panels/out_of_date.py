"""The "out of date" line of the Render and Results panels (as survey software marks
processing steps whose inputs changed): what changed and what brings it up to date."""

from __future__ import annotations

from PySide6.QtWidgets import QLabel

STALE_STYLE = ("background: #fff3cd; color: #7a4b00; border: 1px solid #e0b252; "
               "padding: 3px;")
FRESH_STYLE = "color: #2e7d32;"


class OutOfDate(QLabel):
    """Hidden while there is nothing to compare; green when up to date, amber when not."""

    def __init__(self, name: str) -> None:
        super().__init__("")
        self.setObjectName(name)
        self.setWordWrap(True)
        self.stale = False
        self.hide()

    def show_state(self, stale: str | None, fresh: str = "", says_it: bool = False) -> None:
        """``stale``: why it is out of date (None or "": it is not); ``fresh``: the text
        when up to date ("" hides the line); ``says_it``: ``stale`` begins by saying what
        is out of date ("12 images out of date: …"), so no "out of date:" goes before it."""
        self.stale = bool(stale)
        if stale:
            self.setText(stale if says_it else f"out of date: {stale}")
            self.setStyleSheet(STALE_STYLE)
        else:
            self.setText(fresh)
            self.setStyleSheet(FRESH_STYLE)
        self.setVisible(bool(stale or fresh))
