"""Undo/redo: every edit replaces the whole (immutable) project value on a QUndoStack.

:class:`Editor` is what panels call: ``editor.edit(new_project, "Flight altitude",
merge="flight.altitude")``. Consecutive edits with the same ``merge`` key (a spin box
stepped ten times, a target dragged) become one undo step, as long as they follow each
other within :data:`MERGE_WINDOW_S` with no undo or redo in between (a value typed
again later is a step of its own).
"""

from __future__ import annotations

import time

from PySide6.QtGui import QUndoCommand, QUndoStack

from designer.gui.state.document import ProjectDocument
from designer.project import model as m

_MERGE_IDS: dict[str, int] = {}
#: longest pause (s) between two edits of one field that still makes them one step
MERGE_WINDOW_S = 2.0


def _merge_id(key: str | None) -> int:
    if key is None:
        return -1
    return _MERGE_IDS.setdefault(key, len(_MERGE_IDS) + 1)


class ReplaceProject(QUndoCommand):
    """Swap the document's project between two values."""

    def __init__(self, document: ProjectDocument, old: m.Project, new: m.Project,
                 text: str, merge: str | None = None) -> None:
        super().__init__(text)
        self.document, self.old, self.new = document, old, new
        self._id = _merge_id(merge)

    def id(self) -> int:
        return self._id

    def mergeWith(self, other: QUndoCommand) -> bool:
        if not isinstance(other, ReplaceProject) or other.id() != self.id() or self._id < 0:
            return False
        self.new = other.new
        return True

    def redo(self) -> None:
        self.document.set_project(self.new)

    def undo(self) -> None:
        self.document.set_project(self.old)


class Editor:
    """The one way panels and the 3D view change the project."""

    def __init__(self, document: ProjectDocument, stack: QUndoStack) -> None:
        self.document = document
        self.stack = stack
        self._last: tuple[str | None, int, float] = (None, -1, 0.0)

    @property
    def project(self) -> m.Project:
        return self.document.project

    def edit(self, new: m.Project, text: str, merge: str | None = None) -> None:
        """Apply ``new`` as an undoable step (nothing happens if it equals the current)."""
        if new == self.document.project:
            return
        key, index, when = self._last
        now = time.monotonic()
        mergeable = (merge is not None and merge == key and self.stack.index() == index
                     and now - when <= MERGE_WINDOW_S)
        self.stack.push(ReplaceProject(self.document, self.document.project, new, text,
                                       merge if mergeable else None))
        # the next edit may merge into this one only if it carries a merge id itself
        if not mergeable and merge is not None:
            self.stack.command(self.stack.index() - 1)._id = _merge_id(merge)
        self._last = (merge, self.stack.index(), now)
