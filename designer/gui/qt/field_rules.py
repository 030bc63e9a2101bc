"""Number fields with a rule across fields (highest above lowest, a scale giving whole
pixels): a value that breaks the rule is refused like one out of range — the field
turns red, keeps the typed text and says why in the user's own numbers; nothing reaches
the project. The rule is asked again when the value would be stepped (arrow keys)."""

from __future__ import annotations

from collections.abc import Callable

from designer.gui.qt.widgets import CheckedDoubleSpin, CheckedSpin

#: the rule: the reason a value is refused ("" when it may be applied)
Rule = Callable[[float], str]


class _Ruled:
    """The rule of a checked spin box (mixed in before the box's class)."""

    rule: Rule

    def problem(self, text: str) -> str:
        message = super().problem(text)
        if message:
            return message
        reason = self.rule(self._parse(text))
        return f"{reason}; not applied" if reason else ""

    def stepBy(self, steps: int) -> None:
        value = min(max(self.value() + steps * self.singleStep(), self.minimum()),
                    self.maximum())
        reason = self.rule(value if self._integer else round(value, self.decimals()))
        if reason:
            self._set_error(f"{reason}; not applied")
            return
        super().stepBy(steps)


class RuledDoubleSpin(_Ruled, CheckedDoubleSpin):
    """A :class:`~designer.gui.qt.widgets.CheckedDoubleSpin` that also refuses the values
    its ``rule`` names a reason against."""

    def __init__(self, rule: Rule, label: str = "value") -> None:
        super().__init__(label)
        self.rule = rule


class RuledSpin(_Ruled, CheckedSpin):
    """A :class:`~designer.gui.qt.widgets.CheckedSpin` (whole numbers) with a rule."""

    def __init__(self, rule: Rule, label: str = "value") -> None:
        super().__init__(label)
        self.rule = rule


def ruled_dspin(rule: Rule, lo: float, hi: float, decimals: int = 3, step: float = 1.0,
                suffix: str = "", label: str = "value") -> RuledDoubleSpin:
    """:func:`~designer.gui.qt.widgets.dspin` with a rule across fields."""
    from designer.gui.qt.widgets import set_up_dspin

    return set_up_dspin(RuledDoubleSpin(rule, label), lo, hi, decimals, step, suffix)


def ruled_ispin(rule: Rule, lo: int, hi: int, suffix: str = "",
                label: str = "value") -> RuledSpin:
    """:func:`~designer.gui.qt.widgets.ispin` with a rule across fields."""
    box = RuledSpin(rule, label)
    box.setRange(lo, hi)
    if suffix:
        box.setSuffix(f" {suffix}")
    return box


def ruled_like(box, rule: Rule) -> RuledDoubleSpin:
    """A ruled copy of the number field ``box`` (a declared field's limits, decimals,
    step, unit and tooltip) that also refuses what ``rule`` names a reason against."""
    ruled = ruled_dspin(rule, box.minimum(), box.maximum(), box.decimals(),
                        box.singleStep(), box.suffix().strip())
    ruled.setSpecialValueText(box.specialValueText())
    ruled.setToolTip(box.toolTip())
    return ruled
