"""What every panel shares: the editor, the scene sync, bound fields, refresh on events."""

from __future__ import annotations

import os
from pathlib import Path

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QLabel, QScrollArea, QSplitter, QVBoxLayout, QWidget

from designer.gui.qt.widgets import Bindings, CheckedDoubleSpin, CheckedSpin

ERROR_STYLE = "color: #c0392b"


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
        self.input_label = QLabel()
        self.input_label.setObjectName("input-errors")
        self.input_label.setWordWrap(True)
        self.input_label.setStyleSheet(ERROR_STYLE)
        self.input_label.hide()
        self.input_errors: dict[QWidget, str] = {}
        self._status_refusal = ""  # the refusal this panel last put in the status bar
        self.build(self.body)
        self.body.addStretch(1)
        figures = self.build_figures()
        if figures is None:
            outer.addWidget(scroll)
        else:
            outer.addWidget(_fields_over_figures(scroll, figures))
        # below the fields: appearing, the message shortens the panel's scrolled part
        # from its bottom and moves no field (above them, it pushed them down under the
        # mouse)
        outer.addWidget(self.input_label)
        self.watch_fields()
        editor.document.events.connect("project", self._on_project)
        self.refresh()

    def watch_fields(self, root: QWidget | None = None) -> None:
        """Show the verdicts of the number fields below ``root`` (default: the panel)."""
        for box in (root or self).findChildren(CheckedDoubleSpin) + \
                (root or self).findChildren(CheckedSpin):
            box.listener = self._field_verdict

    def _field_verdict(self, widget: QWidget, message: str) -> None:
        if message:
            self.input_errors[widget] = message
        else:
            self.input_errors.pop(widget, None)
        self.show_input_errors()

    def show_input_errors(self) -> None:
        text = "\n".join(dict.fromkeys(self.input_errors.values()))
        self.input_label.setText(text)
        self.input_label.setVisible(bool(text))
        window = self.window()
        if not hasattr(window, "statusBar"):
            return
        # a refusal leaves the status bar with the panel's message (a later message
        # about something else stays)
        shown = self._status_refusal
        line = text.splitlines()[-1] if text else ""
        if shown and shown != line and window.statusBar().currentMessage() == shown:
            window.statusBar().clearMessage()
        if line:
            window.statusBar().showMessage(line, 8000)
        self._status_refusal = line

    @property
    def project(self):
        return self.editor.project

    def build(self, layout: QVBoxLayout) -> None:
        raise NotImplementedError

    def build_figures(self) -> QWidget | None:
        """What the panel computes from its fields (figures that arrive from worker
        threads and grow and shrink), shown in a pane of its own below the fields so
        that no field moves when they change; None: the panel has none."""
        return None

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


def _fields_over_figures(fields: QScrollArea, figures: QWidget) -> QSplitter:
    """The fields' scroll area above a scroll area of the figures, split by a handle the
    user can drag. Each pane keeps its height whatever its content: figures that arrive
    or grow scroll in their pane and push no field down."""
    pane = QScrollArea()
    pane.setObjectName("figures")
    pane.setWidgetResizable(True)
    pane.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
    pane.setWidget(figures)
    split = QSplitter(Qt.Orientation.Vertical)
    split.setChildrenCollapsible(False)
    split.addWidget(fields)
    split.addWidget(pane)
    # the fields take what the figures leave; the figures start with about 2/5
    split.setStretchFactor(0, 3)
    split.setStretchFactor(1, 2)
    return split
