"""What every panel shares: the editor, the scene sync, bound fields, refresh on events."""

from __future__ import annotations

import os
from pathlib import Path

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QScrollArea, QVBoxLayout, QWidget

from designer.gui.widgets import Bindings


class Panel(QWidget):
    """A side panel. Subclasses set ``title`` and ``parts`` (the document parts that
    make it refresh) and build their fields in ``build(layout)``."""

    title = "Panel"
    parts: frozenset[str] = frozenset()

    def __init__(self, editor, sync, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        self.editor, self.sync = editor, sync
        self.bindings = Bindings(editor)
        inner = QWidget()
        self.body = QVBoxLayout(inner)
        self.body.setContentsMargins(6, 6, 6, 6)
        scroll = QScrollArea()
        scroll.setWidgetResizable(True)
        scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        scroll.setWidget(inner)
        outer = QVBoxLayout(self)
        outer.setContentsMargins(0, 0, 0, 0)
        outer.addWidget(scroll)
        self.build(self.body)
        self.body.addStretch(1)
        editor.document.events.connect("project", self._on_project)
        self.refresh()

    @property
    def project(self):
        return self.editor.project

    def build(self, layout: QVBoxLayout) -> None:
        raise NotImplementedError

    def _on_project(self, old, new, parts) -> None:
        if parts & self.parts:
            self.refresh()

    def refresh(self) -> None:
        self.bindings.refresh(self.project)

    def relative_path(self, path: str) -> str:
        """``path`` relative to the project's folder where it lies below it."""
        base = self.editor.document.base_dir
        try:
            return Path(os.path.relpath(path, base)).as_posix()
        except ValueError:
            return str(path)
