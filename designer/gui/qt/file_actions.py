"""File menu of the window: New (blank or a template), Open, Open Recent, Save, Save As,
the unsaved-changes prompt. Saving validates what would be written and, when there are
problems, writes nothing and lists them in the Problems panel."""

from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QSettings, QTimer
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import QFileDialog, QMenu, QMessageBox

from designer.gui.state import files
from designer.gui.state.wording import count, humanize, problem_text
from designer.project import TEMPLATE_NAMES, ProjectError, read_project_file

MAX_RECENT = 8
TEMPLATE_TITLES = {
    "survey": "Example survey (hills, 10 GCPs, grid flight)",
    "survey-ideal": "Example survey, ideal camera (no distortion, no image effects)",
    "survey-dynamic": "Example survey, changing world (moving sun, clouds, car, person)",
    "survey-structures": "Example survey with structures (buildings, plants, oblique rig)",
    "survey-block": "Survey block (12 ha, about 720 images, 25 GCPs)",
    "validation-cube": "Validation cube (24 orbit photos)",
    "psf": "PSF (slanted edges)", "texture": "Texture (image texture tiled)"}


def template_title(name: str) -> str:
    """File → New's entry for the template ``name``: its title, never the bare name."""
    if name in TEMPLATE_TITLES:
        return TEMPLATE_TITLES[name]
    from designer.project.templates import template

    return template(name).project.name


class FileActions:
    """Owns the file state the document does not: scratch files and recent files."""

    def __init__(self, window, settings: QSettings) -> None:
        self.window = window
        self.document = window.document
        self.stack = window.undo_stack
        self.settings = settings
        self.scratch_files: tuple[str, ...] = ()

    # ------------------------------------------------------------------ menu
    def build_menu(self, menu: QMenu) -> None:
        w = self.window
        new = menu.addMenu("&New")
        blank = new.addAction("Blank project", lambda: self.new(None))
        blank.setShortcut(QKeySequence.StandardKey.New)
        for name in TEMPLATE_NAMES:
            new.addAction(template_title(name), lambda n=name: self.new(n))
        menu.addAction(_action(w, "&Open…", QKeySequence.StandardKey.Open, self.open_dialog))
        self.recent_menu = menu.addMenu("Open &Recent")
        self._fill_recent()
        menu.addSeparator()
        menu.addAction(_action(w, "&Save", QKeySequence.StandardKey.Save, self.save))
        menu.addAction(_action(w, "Save &As…", QKeySequence.StandardKey.SaveAs, self.save_as))

    def _fill_recent(self) -> None:
        self.recent_menu.clear()
        for path in self.recent():
            self.recent_menu.addAction(path, lambda p=path: self.open(Path(p)))
        self.recent_menu.setEnabled(bool(self.recent()))

    def recent(self) -> list[str]:
        value = self.settings.value("recent", [])
        if isinstance(value, str):
            value = [value]
        return [str(v) for v in (value or [])]

    def _remember(self, path: Path) -> None:
        entries = [str(path.resolve())] + [p for p in self.recent()
                                           if p != str(path.resolve())]
        self.settings.setValue("recent", entries[:MAX_RECENT])
        self.settings.sync()
        self._refill_recent()

    def _forget(self, path: Path) -> None:
        """Take ``path`` out of Open Recent."""
        gone = str(path.resolve())
        self.settings.setValue("recent", [p for p in self.recent() if p != gone])
        self.settings.sync()
        self._refill_recent()

    def _refill_recent(self) -> None:
        # later, not now: the entry chosen in Open Recent is still delivering its click,
        # and filling the menu again deletes it
        QTimer.singleShot(0, self._fill_recent)

    # ------------------------------------------------------------------ actions
    def maybe_save(self) -> bool:
        """True when it is fine to drop the current project (saved, discarded)."""
        if not self.document.changed:
            return True
        answer = QMessageBox.question(
            self.window, "Unsaved changes",
            f"{self.document.title.rstrip(' *')} has unsaved changes. Save them?",
            QMessageBox.StandardButton.Save | QMessageBox.StandardButton.Discard
            | QMessageBox.StandardButton.Cancel)
        if answer == QMessageBox.StandardButton.Save:
            return self.save()
        return answer == QMessageBox.StandardButton.Discard

    def new(self, template_name: str | None) -> bool:
        if not self.maybe_save():
            return False
        if template_name is None:
            project, scratch, names = files.blank_project(), None, ()
        else:
            project, scratch, names = files.new_from_template(template_name)
        self.scratch_files = names
        self.stack.clear()
        self.document.reset(project, None, scratch)
        self.window.show_problems([])
        return True

    def open_dialog(self) -> None:
        start = str(self.document.base_dir)
        path, _ = QFileDialog.getOpenFileName(self.window, "Open project", start,
                                              "designer project (*.xml)")
        if path:
            self.open(Path(path))

    def open(self, path: Path) -> bool:
        """Open a project file: a schema-valid file opens even with semantic problems
        (they are listed, so they can be fixed here); an unreadable one does not."""
        path = Path(path)
        if not path.exists():  # said before asking to save: nothing would be opened
            self._forget(path)
            self.window.show_problems(
                [f"{path} no longer exists (moved, renamed or deleted); it is removed "
                 "from Open Recent — open it where it is now with File → Open…"],
                f"Cannot open {path.name}")
            return False
        if not self.maybe_save():
            return False
        try:
            project, smap = read_project_file(path)
        except (ProjectError, OSError) as error:
            lines = ([problem_text(p, error.source) for p in error.problems]
                     if isinstance(error, ProjectError) else [humanize(f"{path}: {error}")])
            self.window.show_problems(lines, f"Cannot open {path.name}")
            return False
        from designer.project import semantic_problems

        problems = [problem_text(p, str(path))
                    for p in semantic_problems(project, path.parent, smap)]
        self.scratch_files = ()
        self.stack.clear()
        self.document.reset(project, path)
        self._remember(path)
        self.window.show_problems(problems, f"{path.name} has problems to fix")
        if not problems:
            self.window.statusBar().showMessage(f"opened {path.name}", 5000)
        return True

    def save(self) -> bool:
        if self.document.path is None:
            return self.save_as()
        return self.save_to(self.document.path)

    def save_as(self) -> bool:
        start = str(self.document.path or Path.cwd() / "survey.xml")
        path, _ = QFileDialog.getSaveFileName(self.window, "Save project as", start,
                                              "designer project (*.xml)")
        if not path:
            return False
        if not path.lower().endswith(".xml"):
            path += ".xml"
        return self.save_to(Path(path))

    def save_to(self, path: Path) -> bool:
        """Validate and write; on problems write nothing and list them."""
        doc = self.document
        plan = files.plan_save(doc.project, path, doc.base_dir, self.scratch_files)
        if not plan.ok:
            self.window.show_problems(
                plan.problems, f"Not saved: {count(len(plan.problems), 'problem')} to fix")
            return False
        try:
            files.commit_save(plan)
        except OSError as error:
            self.window.show_problems([f"{path}: cannot write ({error})"], "Not saved")
            return False
        if plan.project != doc.project:
            # file names were rewritten for the new folder: older undo steps hold names
            # relative to the old folder, so they cannot be replayed
            self.stack.clear()
            doc.set_project(plan.project)
        doc.mark_saved(path)
        self.stack.setClean()
        self.scratch_files = ()
        self._remember(path)
        self.window.show_problems([])
        self.window.statusBar().showMessage(f"saved {path}", 5000)
        return True


def _action(parent, text: str, shortcut, slot) -> QAction:
    action = QAction(text, parent)
    action.setShortcut(shortcut)
    action.triggered.connect(slot)
    return action
