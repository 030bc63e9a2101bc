"""Safe input for the whole window, as one application event filter.

* The mouse wheel over a number field or a drop-down list (also one inside a table)
  changes it only while that field has the keyboard focus; otherwise the wheel scrolls
  what holds the field (the panel, the table), as the pointer merely passed over it.
* Ctrl+Z / Ctrl+Shift+Z (and Ctrl+Y) always undo / redo one step of the project, even
  while a text or number field has the focus (a field's own text undo would swallow
  the key and leave the project as it was).
"""

from __future__ import annotations

from PySide6.QtCore import QEvent, QObject
from PySide6.QtGui import QKeySequence
from PySide6.QtWidgets import QAbstractSpinBox, QComboBox, QWidget


def _changes_on_wheel(widget: QObject) -> QWidget | None:
    """The field a wheel event over ``widget`` would change (None: not a field)."""
    if isinstance(widget, QAbstractSpinBox | QComboBox):
        return widget
    parent = widget.parent() if isinstance(widget, QWidget) else None
    if isinstance(parent, QAbstractSpinBox | QComboBox):
        return parent  # the line edit inside a spin box or an editable combo box
    return None


def is_undo_key(event) -> bool:
    if event.matches(QKeySequence.StandardKey.Undo):
        return True
    if event.matches(QKeySequence.StandardKey.Redo):
        return True
    return event.keyCombination().toCombined() == QKeySequence("Ctrl+Y")[0].toCombined()


class InputGuard(QObject):
    """Installed on the QApplication by the window (removed when it closes)."""

    def __init__(self, window: QWidget) -> None:
        super().__init__(window)
        self.window = window

    def eventFilter(self, obj, event) -> bool:
        kind = event.type()
        if kind == QEvent.Type.Wheel:
            field = _changes_on_wheel(obj)
            if field is not None and not field.hasFocus():
                event.ignore()  # not consumed: Qt hands it on to the parent, which scrolls
                return True
            return False
        if kind == QEvent.Type.ShortcutOverride and isinstance(obj, QWidget) \
                and is_undo_key(event) and self._inside(obj):
            # not accepted: the field does not take the key, the window's Undo/Redo
            # actions do
            event.ignore()
            return True
        return False

    def _inside(self, widget: QObject) -> bool:
        while widget is not None:
            if widget is self.window:
                return True
            widget = widget.parent()
        return False
