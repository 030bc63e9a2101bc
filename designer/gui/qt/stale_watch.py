"""Watches whether the render output (and its reconstruction) is still the project's.

After an edit (debounced), when a file is opened or saved, when a render finishes and
when the output folder changes on disk (a ``designer render`` run from a terminal
rewrites its manifest as each image lands; a file system watcher on the folder, or while
it does not exist on the nearest folder above it, sees it),
:func:`designer.gui.state.output_state.render_state` runs in a worker thread (keyed
``output-state``: a newer check supersedes an older one) and ``render_state`` is
emitted with the answer (None: nothing rendered yet, or a render is running);
``folder_changed`` says the folder changed on disk (its images may be new).
"""

from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QFileSystemWatcher, QObject, QTimer, Signal

from designer.gui.state.output_state import render_state

#: quiet time after the last edit before the (seconds-long) check starts, ms
DEBOUNCE_MS = 700


class StaleWatch(QObject):
    render_state = Signal(object)  # RenderState | None
    folder_changed = Signal()

    def __init__(self, document, tasks, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.document, self.tasks = document, tasks
        #: True while a render writes the folder (no check then)
        self.is_busy = lambda: False
        self.state = None
        self._closed = False
        self._timer = QTimer(self)
        self._timer.setSingleShot(True)
        self._timer.setInterval(DEBOUNCE_MS)
        self._timer.timeout.connect(self.check_now)
        self._watcher = QFileSystemWatcher(self)
        self._watcher.directoryChanged.connect(self._on_disk)
        self._watcher.fileChanged.connect(self._on_disk)
        for event in ("project", "file", "reset"):
            document.events.connect(event, self._later)

    def _later(self, *_args, **_kwargs) -> None:
        if not self._closed:
            self._watch()
            self._timer.start()

    def _watch(self) -> None:
        """Watch the output folder and its manifest, or while the folder does not exist
        the nearest folder above it (its creation shows there)."""
        from designer.render.manifest import MANIFEST

        out_dir = self.out_dir()
        wanted = []
        if out_dir is not None and not self._closed:
            folder = out_dir
            while not folder.is_dir() and folder != folder.parent:
                folder = folder.parent
            wanted.append(str(folder))
            if (out_dir / MANIFEST).is_file():
                wanted.append(str(out_dir / MANIFEST))
        watched = self._watcher.directories() + self._watcher.files()
        gone = [p for p in watched if p not in wanted]
        if gone:
            self._watcher.removePaths(gone)
        new = [p for p in wanted if p not in watched]
        if new:
            self._watcher.addPaths(new)

    def _on_disk(self, _path: str) -> None:
        """The output folder changed on disk: check it again once it is quiet."""
        if self._closed:
            return
        self.folder_changed.emit()
        self._later()

    def shutdown(self) -> None:
        """No more checks (the window closes; its worker threads stop)."""
        self._closed = True
        self._timer.stop()
        self._watch()  # watches nothing

    @property
    def pending(self) -> bool:
        """A check is waiting for its quiet time."""
        return self._timer.isActive()

    def out_dir(self) -> Path | None:
        path = self.document.path
        if path is None:
            return None
        return (path.parent / self.document.project.outputs.directory).resolve()

    def check_now(self) -> None:
        self._timer.stop()
        if self._closed:
            return
        out_dir = self.out_dir()
        if out_dir is None or self.is_busy():
            self.tasks.cancel("output-state")
            self._emit(None)
            return
        self.tasks.submit("output-state", render_state, out_dir, self.document.path,
                          self.document.project, on_done=self._emit,
                          on_error=lambda _e: self._emit(None))

    def _emit(self, state) -> None:
        self.state = state
        self.render_state.emit(state)
