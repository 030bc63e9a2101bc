"""Small building blocks of the panels: unit-labelled fields bound to the model.

A :class:`Bindings` ties each field to a getter and a setter of the project. A person's
change becomes one undoable edit (consecutive changes of the same field merge into one
undo step); a model change (undo, open, another panel) writes the field with its
signals blocked, so views never echo edits back.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from PySide6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QDoubleSpinBox,
    QFormLayout,
    QLabel,
    QLineEdit,
    QSpinBox,
    QWidget,
)

from designer.gui.edits import get_path, replace_path
from designer.project import model as m

Getter = Callable[[m.Project], Any]
Setter = Callable[[m.Project, Any], m.Project]


def dspin(lo: float, hi: float, decimals: int = 3, step: float = 1.0,
          suffix: str = "") -> QDoubleSpinBox:
    """A spin box that reports a value only when typing is done (Enter, focus out)."""
    box = QDoubleSpinBox()
    box.setRange(lo, hi)
    box.setDecimals(decimals)
    box.setSingleStep(step)
    box.setKeyboardTracking(False)
    box.setAccelerated(True)
    box.setMinimumWidth(90)  # else the widest value of the range sets the panel's width
    if suffix:
        box.setSuffix(f" {suffix}")
    return box


def ispin(lo: int, hi: int, suffix: str = "") -> QSpinBox:
    box = QSpinBox()
    box.setRange(lo, hi)
    box.setKeyboardTracking(False)
    box.setMinimumWidth(90)
    if suffix:
        box.setSuffix(f" {suffix}")
    return box


def combo(items: list[tuple[str, Any]]) -> QComboBox:
    box = QComboBox()
    box.setMinimumWidth(90)
    box.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
    for text, data in items:
        box.addItem(text, data)
    return box


def readout() -> QLabel:
    label = QLabel("–")
    label.setWordWrap(True)
    label.setTextInteractionFlags(label.textInteractionFlags()
                                  | label.textInteractionFlags().TextSelectableByMouse)
    return label


def path_accessors(path: str) -> tuple[Getter, Setter]:
    return (lambda p: get_path(p, path)), (lambda p, v: replace_path(p, path, v))


class Bindings:
    """Fields bound to the project through an :class:`~designer.gui.undo.Editor`."""

    def __init__(self, editor) -> None:
        self.editor = editor
        self._items: list[tuple[QWidget, Getter]] = []

    def bind(self, widget: QWidget, access: str | tuple[Getter, Setter], text: str) -> QWidget:
        """Bind ``widget`` to a dotted model path or a (getter, setter) pair."""
        get, put = path_accessors(access) if isinstance(access, str) else access
        merge = access if isinstance(access, str) else f"{text}@{id(widget)}"
        widget.setObjectName(access if isinstance(access, str) else text)

        def changed(value: Any) -> None:
            project = self.editor.project
            try:
                new = put(project, value)
            except (AttributeError, TypeError, IndexError):
                return  # the field's parent is absent; the panel offers to create it
            self.editor.edit(new, text, merge=merge)

        if isinstance(widget, QDoubleSpinBox | QSpinBox):
            widget.valueChanged.connect(changed)
        elif isinstance(widget, QCheckBox):
            widget.toggled.connect(changed)
        elif isinstance(widget, QComboBox):
            widget.currentIndexChanged.connect(lambda _i: changed(widget.currentData()))
        elif isinstance(widget, QLineEdit):
            widget.editingFinished.connect(lambda: changed(widget.text()))
        else:
            raise TypeError(type(widget))
        self._items.append((widget, get))
        return widget

    def refresh(self, project: m.Project) -> None:
        """Show the project's values; fields whose parent is absent are disabled."""
        for widget, get in self._items:
            try:
                value = get(project)
            except (AttributeError, TypeError, IndexError, KeyError):
                widget.setEnabled(False)
                continue
            widget.setEnabled(value is not None or isinstance(widget, QComboBox))
            blocked = widget.blockSignals(True)
            try:
                _set_value(widget, value)
            finally:
                widget.blockSignals(blocked)


def _set_value(widget: QWidget, value: Any) -> None:
    if isinstance(widget, QDoubleSpinBox):
        if value is not None:
            widget.setValue(float(value))
    elif isinstance(widget, QSpinBox):
        if value is not None:
            widget.setValue(int(value))
    elif isinstance(widget, QCheckBox):
        widget.setChecked(bool(value))
    elif isinstance(widget, QComboBox):
        index = widget.findData(value)
        widget.setCurrentIndex(index if index >= 0 else 0)
    elif isinstance(widget, QLineEdit):
        widget.setText("" if value is None else str(value))


def form(parent: QWidget | None = None) -> QFormLayout:
    layout = QFormLayout(parent)
    layout.setFieldGrowthPolicy(QFormLayout.FieldGrowthPolicy.AllNonFixedFieldsGrow)
    return layout
