"""Problems found in a project file, with the place in the file they refer to.

Every problem is printed as ``FILE:LINE:COLUMN: <element>: what is wrong; the fix``,
one per line, all of them, so an editor can jump to each.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from designer.errors import DesignerError


@dataclass(frozen=True)
class Problem:
    """One located problem: ``message`` already starts with ``<element>:``."""

    message: str
    line: int = 1
    column: int = 1

    def format(self, source: str) -> str:
        return f"{source}:{self.line}:{self.column}: {self.message}"


class ProjectError(DesignerError):
    """A project file that cannot be used; ``str()`` lists every problem, one a line."""

    def __init__(self, source: str, problems: list[Problem]) -> None:
        self.source = str(source)
        self.problems = list(problems)
        super().__init__(str(self))

    @property
    def lines(self) -> list[str]:
        return [p.format(self.source) for p in self.problems]

    def __str__(self) -> str:
        return "\n".join(self.lines)


@dataclass(frozen=True)
class Issue:
    """A semantic problem about a model object, before it is given a place in the file.

    ``obj`` is the model object (its element's line is looked up in a
    :class:`SourceMap`), ``tag`` the element named in the message, ``attr`` the
    attribute that holds the wrong value (for the column), ``key`` how the reader
    registered the element when it differs from ``tag`` (e.g. ``"vertex:3"``).
    """

    obj: object
    tag: str
    message: str
    attr: str | None = None
    key: str | None = None


class SourceMap:
    """Where each model object came from: (object, element) → line, and the text for columns.

    Objects are identified by ``id()``; the map keeps a reference to the project so
    the ids stay valid.
    """

    def __init__(self, text: str) -> None:
        self._lines = text.splitlines()
        self._where: dict[tuple[int, str], int] = {}
        self._first: dict[int, int] = {}
        self.keep_alive: object = None

    def add(self, obj: object, key: str, line: int | None) -> None:
        line = int(line or 1)
        self._where[(id(obj), key)] = line
        self._first.setdefault(id(obj), line)

    def locate(self, issue: Issue) -> Problem:
        """The issue as a located :class:`Problem`."""
        key = issue.key or issue.tag
        line = self._where.get((id(issue.obj), key)) or self._first.get(id(issue.obj), 1)
        column = self.column(line, issue.tag, issue.attr)
        return Problem(f"<{issue.tag}>: {issue.message}", line, column)

    def column(self, line: int, tag: str, attr: str | None = None) -> int:
        """1-based column of ``<tag`` (or of ``attr=`` after it) on ``line``; 1 if not found."""
        if not 1 <= line <= len(self._lines):
            return 1
        text = self._lines[line - 1]
        m = re.search(rf"<(?:[\w.\-]+:)?{re.escape(tag)}(?=[\s/>]|$)", text)
        start = m.start() if m else 0
        if attr is None:
            return start + 1
        pattern = re.compile(rf"(?<![\w\-]){re.escape(attr)}\s*=")
        for offset, later in enumerate(self._lines[line - 1: line + 30]):
            a = pattern.search(later, start if offset == 0 else 0)
            if a:
                return a.start() + 1 if offset == 0 else 1
        return start + 1


def unlocated(issue: Issue) -> Problem:
    """An issue of a model that was not read from a file (line 0, column 0)."""
    return Problem(f"<{issue.tag}>: {issue.message}", 0, 0)
