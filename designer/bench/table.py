"""The plain-text table the benchmarks print: a heading row, a rule, a row per
measurement and, below, a note on how the figures were taken."""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

#: format-spec types that make a number (right-aligned unless the spec says otherwise)
NUMBER_TYPES = set("bcdoxXneEfFgG%")


@dataclass(frozen=True)
class Column:
    """A column: its heading, the format spec of its values (``"<20"``, ``">9.3f"``,
    ``"6d"``) and the row's key or a function of the row giving the value."""

    title: str
    spec: str
    value: str | Callable[[dict], Any]

    def heading(self) -> str:
        """The title aligned and padded as the values are (a number's precision and type
        dropped)."""
        align, width, kind = re.fullmatch(
            r"([<>^]?)(\d*)(?:\.\d+)?([a-zA-Z%]?)", self.spec).groups()
        align = align or (">" if kind in NUMBER_TYPES else "<")
        return f"{self.title:{align}{width}}"

    def cell(self, row: dict) -> str:
        value = self.value(row) if callable(self.value) else row[self.value]
        return f"{value:{self.spec}}"


def text_table(columns: Sequence[Column], rows: Sequence[dict], note: str = "",
               rule_width: int | None = None) -> str:
    """The table of ``rows``: the headings, a rule of ``rule_width`` dashes (the
    headings' width by default), a line per row, then ``note`` when given."""
    head = " ".join(c.heading() for c in columns)
    lines = [head, "-" * (len(head) if rule_width is None else rule_width)]
    lines += [" ".join(c.cell(r) for c in columns) for r in rows]
    if note:
        lines.append(note)
    return "\n".join(lines)
