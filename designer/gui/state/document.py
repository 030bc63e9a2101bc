"""The open project as an observable document: Qt-free, plain-Python events.

The project model is immutable (frozen dataclasses), so the document holds one
:class:`~designer.project.model.Project` value and replaces it whole on every edit. An
edit is therefore cheap to undo (keep the old value) and "unsaved changes" is a value
comparison with the project as last saved, so undoing back to the saved state makes the
document clean again.

Events (subscribe with :meth:`Events.connect`, callbacks get keyword arguments):

* ``project(old, new, parts)``: the project value changed; ``parts`` is the set of
  :data:`PARTS` that differ (views rebuild only those);
* ``file(path, dirty)``: the file name, the dirty flag or ``changed`` changed;
* ``reset(project)``: a different project was loaded or created (views drop caches).
"""

from __future__ import annotations

import dataclasses
import sys
from collections.abc import Callable
from pathlib import Path

from designer.project import model as m

#: the parts of a project that views track separately
PARTS = ("meta", "terrain", "texture", "lighting", "targets", "objects", "cameras",
         "trajectory", "effects", "render", "outputs", "processing")


def changed_parts(old: m.Project | None, new: m.Project) -> set[str]:
    """Which of :data:`PARTS` differ between two projects (all of them if ``old`` is None)."""
    if old is None:
        return set(PARTS)
    if old is new:
        return set()
    out = set()
    so, sn = old.scene, new.scene
    if so.terrain != sn.terrain:
        out.add("terrain")
    if so.texture != sn.texture:
        out.add("texture")
    if so.lighting != sn.lighting:
        out.add("lighting")
    if so.targets != sn.targets:
        out.add("targets")
    if (so.objects != sn.objects or so.moving_objects != sn.moving_objects
            or so.buildings != sn.buildings or so.vegetation != sn.vegetation):
        out.add("objects")
    for part in ("cameras", "trajectory", "effects", "render", "outputs", "processing"):
        if getattr(old, part) != getattr(new, part):
            out.add(part)
    if (old.name, old.crs, old.origin, old.description) != (
            new.name, new.crs, new.origin, new.description):
        out.add("meta")
    return out


class Events:
    """A tiny observer list per event name; callbacks are called in connection order."""

    def __init__(self, *names: str) -> None:
        self._callbacks: dict[str, list[Callable[..., None]]] = {n: [] for n in names}

    def connect(self, name: str, callback: Callable[..., None]) -> None:
        self._callbacks[name].append(callback)

    def disconnect(self, name: str, callback: Callable[..., None]) -> None:
        self._callbacks[name].remove(callback)

    def emit(self, name: str, **kwargs) -> None:
        """Call every listener; one that fails is reported (``sys.excepthook``) and does
        not stop the others, nor undo the change that is being announced."""
        for callback in list(self._callbacks[name]):
            try:
                callback(**kwargs)
            except Exception:
                sys.excepthook(*sys.exc_info())


class ProjectDocument:
    """The current project, its file and whether it has unsaved changes.

    ``base_dir`` is the folder relative file names in the project are resolved
    against: the project file's folder, or for a new project from a template a scratch
    folder holding the template's companion files until it is first saved.
    """

    def __init__(self, project: m.Project, path: Path | None = None,
                 base_dir: Path | None = None) -> None:
        self.events = Events("project", "file", "reset")
        self._project = project
        self._saved: m.Project | None = project if path is not None else None
        #: the project as opened, created (New) or last saved: "changed" compares with it
        self._baseline = project
        self.path = Path(path) if path is not None else None
        self.base_dir = Path(base_dir) if base_dir is not None else (
            self.path.parent if self.path is not None else Path.cwd())

    # ------------------------------------------------------------------ state
    @property
    def project(self) -> m.Project:
        return self._project

    @property
    def dirty(self) -> bool:
        """True when the project differs from the file (always for a never-saved one)."""
        return self._saved is None or self._saved != self._project

    @property
    def changed(self) -> bool:
        """True when the project was edited since it was opened, created or saved: a new
        project as New made it is not saved yet (``dirty``) but has nothing to lose."""
        return self._baseline != self._project

    @property
    def title(self) -> str:
        """The file name, with '*' when there are changes to save."""
        name = self.path.name if self.path is not None else "untitled.xml"
        return f"{name}{' *' if self.changed else ''}"

    # ------------------------------------------------------------------ changes
    def set_project(self, project: m.Project) -> None:
        """Replace the project value (an edit, an undo or a redo) and notify."""
        old, was = self._project, (self.dirty, self.changed)
        if project == old:
            return
        self._project = project
        self.events.emit("project", old=old, new=project, parts=changed_parts(old, project))
        if (self.dirty, self.changed) != was:
            self.events.emit("file", path=self.path, dirty=self.dirty)

    def reset(self, project: m.Project, path: Path | None, base_dir: Path | None = None,
              saved: bool = True) -> None:
        """Switch to another project (New, Open): views drop everything they cached."""
        old = self._project
        self._project = project
        self.path = Path(path) if path is not None else None
        self.base_dir = Path(base_dir) if base_dir is not None else (
            self.path.parent if self.path is not None else Path.cwd())
        self._saved = project if (saved and path is not None) else None
        self._baseline = project
        self.events.emit("reset", project=project)
        self.events.emit("project", old=old, new=project, parts=set(PARTS))
        self.events.emit("file", path=self.path, dirty=self.dirty)

    def mark_saved(self, path: Path) -> None:
        """The current project is now what ``path`` holds."""
        self.path = Path(path)
        self.base_dir = self.path.parent
        self._saved = self._baseline = self._project
        self.events.emit("file", path=self.path, dirty=False)

    def replace_part(self, **fields) -> m.Project:
        """A copy of the project with top-level fields replaced (not applied)."""
        return dataclasses.replace(self._project, **fields)
