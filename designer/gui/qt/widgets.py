"""Small building blocks of the panels: unit-labelled fields bound to the model.

A :class:`Bindings` ties each field to a getter and a setter of the project. A person's
change becomes one undoable edit (quick consecutive changes of the same field merge into
one undo step); a model change (undo, open, another panel) writes the field with its
signals blocked, so views never echo edits back.

Number fields never change a value behind the user's back: text that is not a number,
or a number outside the field's range, is refused when typing is done (Enter, focus
out): the field gets a red border, keeps the typed text and says what it accepts
(``listener``); nothing reaches the project until the text is valid.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from PySide6.QtCore import QEvent, Qt
from PySide6.QtGui import QValidator
from PySide6.QtWidgets import (
    QAbstractSpinBox,
    QCheckBox,
    QComboBox,
    QDoubleSpinBox,
    QFormLayout,
    QFrame,
    QLabel,
    QLineEdit,
    QScrollArea,
    QSpinBox,
    QVBoxLayout,
    QWidget,
)

from designer.gui.state.edits import AbsentElement, check_path, get_path, replace_path
from designer.project import model as m

Getter = Callable[[m.Project], Any]
Setter = Callable[[m.Project, Any], m.Project]


INVALID_STYLE = "border: 2px solid #d0302a; border-radius: 2px;"


def format_number(value: float, decimals: int = 6) -> str:
    """Fixed-point text without trailing zeros (``5405950.5``, never ``5.40595e+06``)."""
    text = f"{value:.{decimals}f}"
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


class _Checked:
    """What both checked spin boxes share (mixed into QDoubleSpinBox / QSpinBox)."""

    label = "value"
    _integer = False
    #: the minimum itself is refused: a range open at its low end (an XSD minExclusive,
    #: such as a length greater than 0), kept exact rather than moved one decimal inside
    low_open = False
    #: called with (field, message) when the field's verdict changes ("" = valid)
    listener: Callable[[QWidget, str], None] | None = None

    def __init__(self, label: str = "value") -> None:
        super().__init__()  # the Qt spin box this is mixed into
        self.label = label
        self.error = ""
        self.setKeyboardTracking(False)
        self.setFocusPolicy(Qt.FocusPolicy.StrongFocus)  # the wheel alone gives no focus
        self.setMinimumWidth(90)  # else the widest value of the range sets the panel's width
        self.setCorrectionMode(QAbstractSpinBox.CorrectionMode.CorrectToPreviousValue)

    # -------------------------------------------------------------- parsing
    def _strip(self, text: str) -> str:
        text = text.strip()
        suffix, prefix = self.suffix().strip(), self.prefix().strip()
        if suffix and text.endswith(suffix):
            text = text[:-len(suffix)]
        if prefix and text.startswith(prefix):
            text = text[len(prefix):]
        return text.strip().replace(",", ".").replace("−", "-")

    def allowed(self) -> str:
        """The accepted range as the user reads it (``0 to 99 %``)."""
        digits = 0 if self._integer else self.decimals()
        unit = self.suffix().strip()
        def text(value: float) -> str:  # a whole number's thousands grouped for reading
            return (f"{int(value):,}".replace(",", "\u202f") if self._integer
                    else format_number(value, digits))

        low = text(self.minimum())
        low = f"more than {low} up" if self.low_open else low
        return f"{low} to {text(self.maximum())}" + (f" {unit}" if unit else "")

    def in_range(self, value: float) -> bool:
        low_ok = value > self.minimum() if self.low_open else value >= self.minimum()
        return low_ok and value <= self.maximum()

    def problem(self, text: str) -> str:
        """Why ``text`` cannot be applied ("" when it can)."""
        raw = self._strip(text)
        if raw == "":
            return f"{self.label}: give a number from {self.allowed()}; not applied"
        try:
            value = int(raw) if self._integer else float(raw)
        except ValueError:
            kind = "a whole number" if self._integer else "a number"
            return (f"{self.label}: “{text.strip()}” is not {kind} (allowed: "
                    f"{self.allowed()}); not applied")
        if (self.low_open and not self._integer
                and round(value, self.decimals()) <= self.minimum() < value):
            # the field holds its decimals only: the value would become the minimum
            return (f"{self.label}: {raw} rounds to "
                    f"{format_number(self.minimum(), self.decimals())} in this field; "
                    f"allowed: {self.allowed()}; not applied")
        if not self.in_range(value):  # NaN is in no range
            return (f"{self.label}: {raw} is out of range; allowed: {self.allowed()}; "
                    "not applied")
        return ""

    def _parse(self, text: str):
        raw = self._strip(text)
        return int(raw) if self._integer else float(raw)

    def valueFromText(self, text: str):
        try:
            return self._parse(text)
        except ValueError:
            return self.value()

    # -------------------------------------------------------------- Qt hooks
    def validate(self, text: str, pos: int):
        # any text may be typed; whether it is applied is decided when typing is done
        state = (QValidator.State.Acceptable if not self.problem(text)
                 else QValidator.State.Intermediate)
        return state, text, pos

    def fixup(self, text: str) -> str:
        return text

    def shown_value(self) -> str:
        """The project's value as the field shows it (``0.25``, ``10 m``)."""
        if self.specialValueText() and self.value() == self.minimum():
            return self.specialValueText()
        return f"{self.prefix()}{self.textFromValue(self.value())}{self.suffix()}".strip()

    def event(self, event) -> bool:
        # Esc in a refused field is the field's (it puts the value back), not the
        # window's shortcut (back to navigating the view)
        if (event.type() == QEvent.Type.ShortcutOverride and self.error
                and event.key() == Qt.Key.Key_Escape):
            event.accept()
            return True
        return super().event(event)

    def keyPressEvent(self, event) -> None:
        if event.key() in (Qt.Key.Key_Return, Qt.Key.Key_Enter):
            if self._refuse():
                event.accept()
                return
        if event.key() == Qt.Key.Key_Escape and self.error:
            # nothing typed was applied: the project's value is still the field's value
            self.lineEdit().setText(self.shown_value())
            self.lineEdit().selectAll()
            self._set_error("")
            event.accept()
            return
        super().keyPressEvent(event)

    def focusOutEvent(self, event) -> None:
        text = self.lineEdit().text()
        refused = self._refuse()
        super().focusOutEvent(event)
        if refused:  # keep what was typed (and red) so it can be corrected
            self.lineEdit().setText(text)

    def stepBy(self, steps: int) -> None:
        if self.low_open and self.value() + steps * self.singleStep() <= self.minimum():
            # Qt would clamp to the minimum, which an open range refuses
            low = format_number(self.minimum(), 0 if self._integer else self.decimals())
            self._set_error(f"{self.label}: {low} is out of range; allowed: "
                            f"{self.allowed()}; not applied")
            return
        self._set_error("")
        super().stepBy(steps)

    def setValue(self, value) -> None:
        self._set_error("")
        super().setValue(value)

    def _refuse(self) -> bool:
        message = self.problem(self.lineEdit().text())
        self._set_error(self._way_back(message))
        return bool(message)

    def _way_back(self, message: str) -> str:
        """A refusal with the key that undoes the typing (the value stays the project's)."""
        return f"{message} (Esc: back to {self.shown_value()})" if message else ""

    def _set_error(self, message: str) -> None:
        if message == self.error:
            return
        self.error = message
        self.setProperty("invalid", bool(message))
        self.setStyleSheet(INVALID_STYLE if message else "")
        self.setToolTip(message)
        # a plain callback, not a signal: a field refreshed from the model (signals
        # blocked) must still take its message away
        if self.listener is not None:
            self.listener(self, message)


class CheckedDoubleSpin(_Checked, QDoubleSpinBox):
    """A number field that refuses invalid or out-of-range text instead of clamping it."""

    def textFromValue(self, value: float) -> str:
        return format_number(value, self.decimals())


class CheckedSpin(_Checked, QSpinBox):
    """A whole-number field that refuses invalid or out-of-range text."""

    _integer = True


def dspin(lo: float, hi: float, decimals: int = 3, step: float = 1.0,
          suffix: str = "", label: str = "value", low_open: bool = False
          ) -> CheckedDoubleSpin:
    """A number field that reports a value only when typing is done (Enter, focus out)
    and refuses text outside [lo, hi] (with ``low_open``: (lo, hi]) with a message."""
    box = set_up_dspin(CheckedDoubleSpin(label), lo, hi, decimals, step, suffix)
    box.low_open = low_open
    return box


def set_up_dspin(box, lo: float, hi: float, decimals: int, step: float, suffix: str):
    """``box`` (a QDoubleSpinBox) with these limits, decimals, step and unit suffix."""
    box.setDecimals(decimals)
    box.setRange(lo, hi)
    box.setSingleStep(step)
    box.setAccelerated(True)
    if suffix:
        box.setSuffix(f" {suffix}")
    return box


def ispin(lo: int, hi: int, suffix: str = "", label: str = "value") -> CheckedSpin:
    box = CheckedSpin(label)
    box.setRange(lo, hi)
    if suffix:
        box.setSuffix(f" {suffix}")
    return box


#: the GUI's symbol of a declared unit, where it differs from the unit's text
_UNIT_SUFFIX = {"deg": "°"}


def declared_field(cls: type, name: str) -> QWidget:
    """The field of a declared attribute (designer.project.declare): its range as the
    limits (an open end one step of the last decimal inside), its unit as the suffix,
    its doc as the tooltip; a choice is a combo box."""
    from designer.project.declare import declared_field as lookup

    d = lookup(cls, name)
    a = d.attr
    suffix = _UNIT_SUFFIX.get(a.unit, a.unit)
    if d.choices is not None:
        box: QWidget = combo([(c, c) for c in d.choices])
    elif d.base is int:
        lo = -(2**31) + 1 if a.low is None else int(a.low) + (1 if a.low_open else 0)
        hi = 2**31 - 1 if a.high is None else int(a.high) - (1 if a.high_open else 0)
        box = ispin(lo, hi, suffix)
    elif d.base is float:
        tick = 10.0 ** -a.decimals
        lo = -1e12 if a.low is None else a.low + (tick if a.low_open else 0.0)
        hi = 1e12 if a.high is None else a.high - (tick if a.high_open else 0.0)
        box = dspin(lo, hi, a.decimals, a.step, suffix)
    else:
        raise TypeError(f"no GUI field for {cls.__name__}.{name}")
    if a.special is not None and hasattr(box, "setSpecialValueText"):
        box.setSpecialValueText(a.special)
    box.setToolTip(f"{a.doc} ({d.range_text()})" if d.base is not str else a.doc)
    box.switched_on_value = _switched_on_value(cls, name, d)
    return box


def _switched_on_value(cls: type, name: str, d) -> Any:
    """What the field holds once its element is switched on (the declaration's "on"
    values, else its default); None when the declaration gives none. Shown, greyed,
    while the element is absent, instead of whatever the field held (or its minimum)."""
    from dataclasses import MISSING

    from designer.project.declare import switched_on

    try:
        return getattr(switched_on(cls), name)
    except (TypeError, ValueError):  # a class with required fields of its own
        return None if d.default is MISSING else d.default


def combo(items: list[tuple[str, Any]]) -> QComboBox:
    box = QComboBox()
    box.setFocusPolicy(Qt.FocusPolicy.StrongFocus)  # the wheel alone gives no focus
    box.setMinimumWidth(90)
    box.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
    for text, data in items:
        box.addItem(text, data)
    return box


class MessageLabel(QLabel):
    """A message under a field or table: wrapped to the panel's width, its whole text
    also its tooltip (read in full wherever the label is squeezed)."""

    def __init__(self, style: str = "color: #c0392b") -> None:
        super().__init__()
        self.setWordWrap(True)
        self.setStyleSheet(style)

    def setText(self, text: str) -> None:
        super().setText(text)
        self.setToolTip(text)


def readout() -> QLabel:
    label = QLabel("–")
    label.setWordWrap(True)
    label.setTextInteractionFlags(label.textInteractionFlags()
                                  | label.textInteractionFlags().TextSelectableByMouse)
    return label


def path_accessors(path: str) -> tuple[Getter, Setter]:
    """Getter and setter of a model path (checked now: a misspelt path raises
    :class:`~designer.gui.state.edits.UnknownField`)."""
    check_path(path)
    return (lambda p: get_path(p, path)), (lambda p, v: replace_path(p, path, v))


def model_getter(path: str, convert: Callable[[Any], Any] | None = None) -> Getter:
    """A getter of a model path (checked now), its value passed through ``convert``."""
    check_path(path)
    if convert is None:
        return lambda p: get_path(p, path)
    return lambda p: convert(get_path(p, path))


class Bindings:
    """Fields bound to the project through an :class:`~designer.gui.qt.undo.Editor`.

    A field whose element the project lacks (:class:`~designer.gui.state.edits.AbsentElement`:
    an optional element that is off, a union variant without the field) is disabled; a
    path that names no field of the model raises when it is bound, and any other error
    of a getter or setter propagates: a broken binding is loud, never a greyed field."""

    def __init__(self, editor) -> None:
        self.editor = editor
        self._items: list[tuple[QWidget, Getter]] = []

    def bind(self, widget: QWidget, access: str | tuple[Getter, Setter], text: str) -> QWidget:
        """Bind ``widget`` to a dotted model path or a (getter, setter) pair (build the
        getter with :func:`model_getter` so that its path is checked too)."""
        get, put = path_accessors(access) if isinstance(access, str) else access
        merge = access if isinstance(access, str) else f"{text}@{id(widget)}"
        widget.setObjectName(access if isinstance(access, str) else text)
        if isinstance(widget, _Checked) and widget.label == "value":
            widget.label = text

        def changed(value: Any) -> None:
            project = self.editor.project
            try:
                new = put(project, value)
            except AbsentElement:
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

    @property
    def items(self) -> list[tuple[QWidget, Getter]]:
        """(field, getter) of every binding, in the order bound."""
        return list(self._items)

    def refresh(self, project: m.Project) -> None:
        """Show the project's values; fields whose parent is absent are disabled and show
        their ``switched_on_value`` (a value, or a function of the project giving it)."""
        for widget, get in self._items:
            try:
                value = get(project)
            except AbsentElement:
                widget.setEnabled(False)
                shown = getattr(widget, "switched_on_value", None)
                if callable(shown):  # it depends on the project (e.g. its camera)
                    shown = shown(project)
                if shown is not None:  # greyed, what switching the element on gives
                    blocked = widget.blockSignals(True)
                    _set_value(widget, shown)
                    widget.blockSignals(blocked)
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


def message_box(labels: list[QLabel], lines: int) -> QScrollArea:
    """The labels stacked in an area of a fixed height (``lines`` lines of text), scrolled
    when longer: messages that come, go and change length there move nothing below."""
    inner = QWidget()
    v = QVBoxLayout(inner)
    v.setContentsMargins(0, 0, 0, 0)
    for label in labels:
        v.addWidget(label)
    v.addStretch(1)
    area = QScrollArea()
    area.setWidget(inner)
    area.setWidgetResizable(True)
    area.setFrameShape(QFrame.Shape.NoFrame)
    area.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
    area.setFixedHeight(lines * area.fontMetrics().lineSpacing() + 4)
    return area
