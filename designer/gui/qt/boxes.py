"""Boxes several panels build alike: a file's name beside a browse button, a group led
by a checkbox that switches it on, a list of the project's items with add and remove
buttons, a word-wrapped message label, a form of read-only figures and a worker
process's log."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from PySide6.QtWidgets import (
    QBoxLayout,
    QCheckBox,
    QComboBox,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QPlainTextEdit,
    QPushButton,
)

from designer.gui.qt.widgets import form, readout


def wrapped_label(style: str = "") -> QLabel:
    """An empty label that wraps its text to the panel's width, in ``style`` (a Qt style
    sheet, e.g. a colour) when given."""
    label = QLabel()
    label.setWordWrap(True)
    if style:
        label.setStyleSheet(style)
    return label


def file_box(title: str, button_text: str, on_browse: Callable[[], None]
             ) -> tuple[QGroupBox, QLabel]:
    """A group titled ``title``: a label for the file's name (``–`` until one is set)
    beside a button ``button_text`` that calls ``on_browse``. Returns the group and the
    label."""
    box = QGroupBox(title)
    row = QHBoxLayout(box)
    name = QLabel("–")
    name.setWordWrap(True)
    browse = QPushButton(button_text)
    browse.clicked.connect(lambda _checked=False: on_browse())
    row.addWidget(name, 1)
    row.addWidget(browse)
    return box, name


def checked_group(title: str, check_text: str, on_toggled: Callable[[bool], None],
                  tooltip: str = "") -> tuple[QGroupBox, QFormLayout, QCheckBox]:
    """A group titled ``title`` (with ``tooltip``) whose form starts with a checkbox
    ``check_text`` that switches the group's element on or off (``on_toggled(on)``).
    Returns the group, its form (for the fields below the checkbox) and the checkbox."""
    box = QGroupBox(title)
    if tooltip:
        box.setToolTip(tooltip)
    fields = form(box)
    check = QCheckBox(check_text)
    check.toggled.connect(on_toggled)
    fields.addRow(check)
    return box, fields, check


def item_chooser(layout: QBoxLayout, object_name: str, on_choose: Callable[[], None],
                 adds: Sequence[tuple[str, Callable[[], None]]],
                 on_remove: Callable[[], None]
                 ) -> tuple[QComboBox, list[QPushButton], QPushButton]:
    """A list of the project's items (a combo box named ``object_name`` whose choice
    calls ``on_choose``) above a row of buttons: one per (label, callback) in ``adds``,
    then "remove". Both are added to ``layout``; returns the list, the add buttons in
    the order of ``adds`` and the remove button."""
    chooser = QComboBox()
    chooser.setObjectName(object_name)
    chooser.currentIndexChanged.connect(lambda _i: on_choose())
    layout.addWidget(chooser)
    buttons = QHBoxLayout()
    added = []
    for label, callback in adds:
        button = QPushButton(label)
        button.clicked.connect(lambda _checked=False, call=callback: call())
        buttons.addWidget(button)
        added.append(button)
    remove = QPushButton("remove")
    remove.clicked.connect(lambda _checked=False: on_remove())
    buttons.addWidget(remove)
    layout.addLayout(buttons)
    return chooser, added, remove


def chosen_index(chooser: QComboBox) -> int:
    """The chosen item's index; the first when none is chosen yet."""
    return max(chooser.currentIndex(), 0)


def refill_chooser(chooser: QComboBox, items: Sequence[tuple[str, Any]]) -> None:
    """Replace ``chooser``'s items by ``items`` (text, data) without signalling a choice,
    keeping the chosen index (the last item when the list got shorter)."""
    keep = chosen_index(chooser)
    blocked = chooser.blockSignals(True)
    chooser.clear()
    for text, data in items:
        chooser.addItem(text, data)
    chooser.setCurrentIndex(min(max(keep, 0), len(items) - 1))
    chooser.blockSignals(blocked)


def log_view(max_lines: int, max_height_px: int) -> QPlainTextEdit:
    """A read-only text box for a worker process's output, keeping its last ``max_lines``
    lines and at most ``max_height_px`` high."""
    log = QPlainTextEdit()
    log.setReadOnly(True)
    log.setMaximumBlockCount(max_lines)
    log.setMaximumHeight(max_height_px)
    return log


def readouts(layout: QBoxLayout, *names: str) -> list[QLabel]:
    """A form of read-only figures, one row per name in ``names``, added to ``layout``;
    returns their labels in that order."""
    fields = form()
    labels = [readout() for _ in names]
    for name, label in zip(names, labels, strict=True):
        fields.addRow(name, label)
    layout.addLayout(fields)
    return labels


def follow_process(process, log: QPlainTextEdit, on_event: Callable, on_finished: Callable
                   ) -> None:
    """Wire a worker ``process`` (signals ``event``, ``output``, ``finished``) to a panel:
    its events to ``on_event``, its output lines to ``log``, its end to ``on_finished``."""
    process.event.connect(on_event)
    process.output.connect(log.appendPlainText)
    process.finished.connect(on_finished)
