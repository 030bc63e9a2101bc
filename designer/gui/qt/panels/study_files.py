"""The Study panel's files: save and open study files, open study output folders.

Opening a study whose base-project file is missing asks for the base project (a file
dialog); the study then uses that file until "Use the open project".
"""

from __future__ import annotations

import os
from pathlib import Path

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QFileDialog

from designer.gui.state.study_data import range_text
from designer.study.factors import FACTORS


class StudyFiles:
    """Mixed into :class:`~designer.gui.qt.panels.study.StudyPanel`."""

    def save_study(self, path: Path | None = None) -> bool:
        """Write the study file (the open project saved first when it is the base)."""
        if path is None:
            start = str(self.study_path or self.editor.document.base_dir /
                        f"{self.name.text().strip() or 'study'}.xml")
            chosen, _ = QFileDialog.getSaveFileName(self, "Save study", start,
                                                    "designer study (*.xml)")
            if not chosen:
                return False
            path = Path(chosen)
        path = Path(path)
        doc = self.editor.document
        if self.base_file is None and self.inline_base is None and (
                doc.path is None or doc.dirty):
            window = self.window()
            if not hasattr(window, "file_actions") or not window.file_actions.save():
                self._show_errors(["save the project (the study's base) first"])
                return False
        try:
            text = self.study_text(path)
        except ValueError as error:
            self._show_errors([str(error)])
            return False
        from designer.atomic import write_text_atomic

        path.parent.mkdir(parents=True, exist_ok=True)
        write_text_atomic(path, text)
        self.study_path, self._opened_text = path, text
        self.file_label.setText(f"saved: {path}")
        self.run_box.default_folder(path)
        self._show_base()
        self.changed()
        return True

    def open_study(self, path: Path | None = None) -> bool:
        """Fill the panel from a study file; its errors are listed when it cannot be read."""
        if path is None:
            chosen, _ = QFileDialog.getOpenFileName(
                self, "Open study", str(self.editor.document.base_dir),
                "designer study (*.xml)")
            if not chosen:
                return False
            path = Path(chosen)
        from designer.gui.state.study_words import study_problem_lines
        from designer.project.problems import ProjectError
        from designer.study.xml import read_study

        path = Path(path)
        try:
            study = read_study(path)
        except ProjectError as error:
            self._show_errors(study_problem_lines(error))
            return False
        for row in list(self.rows):
            self.rows.remove(row)
            row.setParent(None)
        self.name.setText(study.name)
        self.description = study.description
        doc_path = self.editor.document.path
        picked = None
        self.base_file = self.inline_base = None
        if study.base.file is not None:
            base = (path.parent / study.base.file).resolve()
            if not base.is_file():
                picked = self.pick_base(base)
                base = picked or base
            if doc_path is None or base != doc_path.resolve():
                self.base_file = base
        else:
            self.inline_base = study.base.inline_xml.lstrip(b"\n")
        for f in study.factors:
            if f.name in FACTORS:
                levels = range_text(f.range_spec) if f.range_spec else " ".join(f.values)
                self.add_factor(f.name, levels)
            else:
                self._show_errors([f"{path}: unknown factor '{f.name}' (line "
                                   f"{f.where.line}): not shown"])
        self.design.setCurrentIndex(self.design.findData(study.design))
        self.replicates.setValue(study.replicates.count)
        for name, box in self.vary.items():
            box.setChecked(name in study.replicates.vary)
        for k in range(self.metrics.count()):
            item = self.metrics.item(k)
            item.setCheckState(checked_state(item.data(Qt.ItemDataRole.UserRole)
                                             in study.metrics))
        self.cost_axis.setCurrentIndex(self.cost_axis.findData(study.cost))
        self.study_path = path
        self.file_label.setText(f"opened: {path}" + (
            "; its base project is another file now: save the study to keep it"
            if picked else ""))
        self.run_box.default_folder(path)
        self._show_base()
        try:  # as the file is: checked as it is on disk (its own line numbers)
            self._opened_text = self.study_text()
        except ValueError:
            self._opened_text = None
        if picked or (study.base.file is not None
                      and self._base(path).file != study.base.file):
            # the base is another file now, or the window's project with changes not
            # saved: the file on disk is not what the panel shows
            self._opened_text = None
        self.changed()
        return True

    def pick_base(self, missing: Path) -> Path | None:
        """Ask for the base project of a study whose base file is missing."""
        chosen, _ = QFileDialog.getOpenFileName(
            self, f"The study's base project {missing.name} is missing: choose it",
            str(missing.parent if missing.parent.is_dir() else Path.cwd()),
            "designer project (*.xml)")
        return Path(chosen).resolve() if chosen else None

    def open_folder(self, path: Path | None = None) -> bool:
        """Show a study output folder's results; a partial one becomes the run folder."""
        if path is None:
            chosen = QFileDialog.getExistingDirectory(self, "Open study folder",
                                                      str(self.editor.document.base_dir))
            if not chosen:
                return False
            path = Path(chosen)
        from designer.errors import DesignerError
        from designer.gui.state.study_data import read_folder

        try:
            folder = read_folder(path)
        except DesignerError as error:
            self.results.summary.setText(str(error))
            return False
        self.results.show_folder(folder)
        if folder.state == "partial":
            self.run_box.folder.setText(str(folder.path))
        return folder.state != "empty"


def checked_state(on: bool):
    from PySide6.QtCore import Qt

    return Qt.CheckState.Checked if on else Qt.CheckState.Unchecked


def relative(path: Path, folder: Path) -> str:
    try:
        return Path(os.path.relpath(Path(path).resolve(), Path(folder).resolve())).as_posix()
    except ValueError:
        return str(Path(path).resolve())

