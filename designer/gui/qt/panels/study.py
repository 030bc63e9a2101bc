"""Study: vary parameters of the open project across many virtual surveys
(``designer study``) — factors and their levels, the design, replicates and metrics; the
variant and run counts, the distinct renders and an estimate of the time, checked live;
save and open study files; run with progress, cancel and resume; the results table and
the report's plots of a study folder.

The study's base project is the window's project (saved: its file; unsaved: inline), or
the base-project file of a study that was opened, until "Use the open project".
"""

from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import Qt, QTimer
from PySide6.QtWidgets import (
    QCheckBox,
    QGridLayout,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QListWidget,
    QListWidgetItem,
    QPushButton,
    QVBoxLayout,
)

from designer.gui.qt.panels.base import ERROR_STYLE, Panel
from designer.gui.qt.panels.study_files import StudyFiles, checked_state, relative
from designer.gui.qt.panels.study_run import StudyRunBox
from designer.gui.qt.study_form import (
    LEVELS_HINT,
    FactorRow,
    base_value,
    check_study,
    design_text,
)
from designer.gui.qt.study_results import StudyResults
from designer.gui.qt.widgets import combo, form, ispin, message_box
from designer.gui.state.study_data import duration_text
from designer.gui.state.study_words import (
    draw_words,
    factor_words,
    metric_words,
    study_problem_lines,
    tip,
)
from designer.gui.state.wording import count, estimate_basis
from designer.render_time.model import load_speed
from designer.study.cost import COSTS
from designer.study.factors import DRAWS, FACTORS
from designer.study.spec import DEFAULT_METRICS, BaseProject, FactorSpec, Replicates, Study

DESIGNS = [("one at a time (each factor around the base)", "one-at-a-time"),
           ("full factorial (every combination)", "full-factorial")]
UNTITLED = "untitled-study.xml"
WARNING_STYLE = "color: #b9770e; font-weight: bold"
#: the height of the plan line, errors and warnings (lines of text; longer ones scroll)
MESSAGE_LINES = 9


#: why a study without factors cannot run, and what adds one
NO_FACTOR = ("no factor yet: choose what the study varies in the list under “factors” "
             "and press Add, then type its levels")

class StudyPanel(StudyFiles, Panel):
    title = "Study"

    def build(self, layout) -> None:
        self.study_path: Path | None = None
        self.base_file: Path | None = None   # None: the window's project
        self.inline_base: bytes | None = None
        self.description: str | None = None
        self._opened_text: str | None = None  # the panel's text when the file was opened
        self.plan = self.cost = None
        self.rows: list[FactorRow] = []

        files = QHBoxLayout()
        self.open_button = QPushButton("Open study…")
        self.open_button.clicked.connect(lambda: self.open_study())
        self.save_button = QPushButton("Save study…")
        self.save_button.clicked.connect(lambda: self.save_study())
        files.addWidget(self.open_button)
        files.addWidget(self.save_button)
        layout.addLayout(files)
        self.file_label = QLabel("not saved")
        self.file_label.setWordWrap(True)
        layout.addWidget(self.file_label)

        study = QGroupBox("study")
        f = form(study)
        self.name = QLineEdit("study")
        self.name.setObjectName("study-name")
        self.name.textChanged.connect(self.changed)
        f.addRow("name", self.name)
        self.base_label = QLabel()
        self.base_label.setWordWrap(True)
        f.addRow("base project", self.base_label)
        self.use_window = QPushButton("Use the open project")
        self.use_window.clicked.connect(self.use_window_project)
        f.addRow(self.use_window)
        layout.addWidget(study)

        factors = QGroupBox("factors")
        v = QVBoxLayout(factors)
        add = QHBoxLayout()
        self.factor_choice = combo([(f"{factor_words(f.name)} ({f.stage})", f.name)
                                    for f in FACTORS.values()])
        self.factor_choice.setObjectName("study-factor-choice")
        for k, f in enumerate(FACTORS.values()):
            self.factor_choice.setItemData(k, tip(f.doc, f.name), 3)  # Qt.ToolTipRole
        self.add_button = QPushButton("Add")
        self.add_button.setObjectName("study-add-factor")
        self.add_button.clicked.connect(lambda: self.add_factor(
            self.factor_choice.currentData()))
        add.addWidget(self.factor_choice, 1)
        add.addWidget(self.add_button)
        v.addLayout(add)
        self.factor_box = QVBoxLayout()
        v.addLayout(self.factor_box)
        hint = QLabel(f"<small>Levels: {LEVELS_HINT}. render factors change the images; "
                      "processing factors share one render.</small>")
        hint.setWordWrap(True)
        v.addWidget(hint)
        layout.addWidget(factors)

        design = QGroupBox("design and replicates")
        f = form(design)
        self.design = combo(DESIGNS)
        self.design.currentIndexChanged.connect(self.changed)
        f.addRow("design", self.design)
        self.replicates = ispin(1, 1000, "per variant", "Replicates")
        self.replicates.setObjectName("study-replicates")
        self.replicates.valueChanged.connect(self.changed)
        f.addRow("replicates", self.replicates)
        grid = QGridLayout()
        self.vary: dict[str, QCheckBox] = {}
        for k, (name, (doc, _)) in enumerate(DRAWS.items()):
            box = QCheckBox(draw_words(name))
            box.setToolTip(tip(f"re-draw {doc} in every replicate", name))
            box.toggled.connect(self.changed)
            grid.addWidget(box, k // 2, k % 2)
            self.vary[name] = box
        f.addRow("re-drawn", grid)
        layout.addWidget(design)

        metrics = QGroupBox("metrics (each tooltip names its results.csv column)")
        v = QVBoxLayout(metrics)
        from designer.study.results import METRIC_COLUMNS

        self.metrics = QListWidget()
        self.metrics.setMaximumHeight(130)
        for name in METRIC_COLUMNS:
            item = QListWidgetItem(metric_words(name))
            item.setData(Qt.ItemDataRole.UserRole, name)
            item.setToolTip(tip("a column of results.csv in the study's report", name))
            item.setCheckState(checked_state(name in DEFAULT_METRICS))
            self.metrics.addItem(item)
        self.metrics.itemChanged.connect(self.changed)
        v.addWidget(self.metrics)
        f = form()
        self.cost_axis = combo([(c.label, c.name) for c in COSTS.values()])
        for k, c in enumerate(COSTS.values()):
            self.cost_axis.setItemData(k, tip(c.label, c.name), 3)  # Qt.ToolTipRole
        self.cost_axis.setObjectName("study-cost")
        self.cost_axis.setToolTip("the cost the report plots accuracy against (the study "
                                  "file's cost; docs/studies.md)")
        self.cost_axis.currentIndexChanged.connect(self.changed)
        f.addRow("accuracy against", self.cost_axis)
        v.addLayout(f)
        layout.addWidget(metrics)

        # the plan line, errors and warnings below the Run box, in an area of a fixed
        # height: they come, go and change length with every check, and moved Run and
        # Cancel (above them) and Open study folder and the results (below) under the mouse
        self.run_box = StudyRunBox(self)
        layout.addWidget(self.run_box)

        self.plan_label = QLabel("")
        self.plan_label.setObjectName("study-plan")
        self.plan_label.setWordWrap(True)
        self.errors = QLabel("")
        self.errors.setObjectName("study-errors")
        self.errors.setWordWrap(True)
        self.errors.setStyleSheet(ERROR_STYLE)
        self.errors.hide()
        self.warnings = QLabel("")
        self.warnings.setObjectName("study-warnings")
        self.warnings.setWordWrap(True)
        self.warnings.setStyleSheet(WARNING_STYLE)
        self.warnings.hide()
        self.messages = message_box([self.plan_label, self.errors, self.warnings],
                                    MESSAGE_LINES)
        self.messages.setObjectName("study-messages")
        layout.addWidget(self.messages)
        layout.addWidget(self.run_box.progress_box)

        results = QGroupBox("results")
        v = QVBoxLayout(results)
        self.open_folder_button = QPushButton("Open study folder…")
        self.open_folder_button.clicked.connect(lambda: self.open_folder())
        v.addWidget(self.open_folder_button)
        self.results = StudyResults()
        v.addWidget(self.results)
        layout.addWidget(results)

        self._timer = QTimer(self)
        self._timer.setSingleShot(True)
        self._timer.setInterval(250)
        self._timer.timeout.connect(self.check_now)
        self.editor.document.events.connect("file", lambda **_: self._file_changed())
        self.editor.document.events.connect("reset", lambda **_: self._project_replaced())
        self._project_path = self._open_path()
        self._show_base()

    # ------------------------------------------------------------------ the study
    def add_factor(self, name: str, levels: str = "") -> FactorRow | None:
        if name in [r.name for r in self.rows]:
            self._show_errors([f"factor “{factor_words(name)}” is in the study already; "
                               "edit its levels"])
            return None
        factor = FACTORS[name]
        # the window's project until a check gives the study's base (_checked)
        row = FactorRow(name, factor.stage, factor.doc, base_value(factor, self.project),
                        levels)
        row.changed.connect(self.changed)
        row.remove.connect(self.remove_factor)
        self.factor_box.addWidget(row)
        self.rows.append(row)
        row.levels.setFocus()
        self.changed()
        return row

    def remove_factor(self, row: FactorRow) -> None:
        self.rows.remove(row)
        row.setParent(None)
        row.deleteLater()
        self.changed()

    def changed(self, *_) -> None:
        """Something in the study changed: check it again shortly."""
        self.plan = self.cost = None
        self.plan_label.setText("checking…")
        self.run_box.update_buttons()
        self._timer.start()

    def _path_for_check(self) -> Path:
        return self.study_path or self.editor.document.base_dir / UNTITLED

    def _base(self, study_path: Path) -> BaseProject:
        doc = self.editor.document
        file = self.base_file
        if file is None and self.inline_base is None and doc.path is not None \
                and not doc.dirty:
            file = doc.path
        if file is not None:
            return BaseProject(file=relative(file, study_path.parent))
        if self.inline_base is not None:
            return BaseProject(inline_xml=self.inline_base)
        from designer.gui.state.files import rebase_files
        from designer.project.model_to_xml import project_to_bytes

        # the window's project, not saved: its files are named from its own folder, and
        # a study's inline project names them from the study file's folder
        return BaseProject(inline_xml=project_to_bytes(
            rebase_files(self.project, doc.base_dir, study_path.parent)))

    def study(self, study_path: Path | None = None) -> Study:
        """The study the panel shows; ValueError for levels that are not usable."""
        path = study_path or self._path_for_check()
        factors = tuple(FactorSpec(r.name, r.values(), range_spec=r.range_spec())
                        for r in self.rows)
        metrics = tuple(self.metrics.item(k).data(Qt.ItemDataRole.UserRole)
                        for k in range(self.metrics.count())
                        if self.metrics.item(k).checkState() == checked_state(True))
        return Study(name=self.name.text().strip(), base=self._base(path), factors=factors,
                     design=self.design.currentData(),
                     replicates=Replicates(self.replicates.value(), tuple(
                         n for n, box in self.vary.items() if box.isChecked())),
                     metrics=metrics, description=self.description,
                     cost=self.cost_axis.currentData(), source=path)

    def study_text(self, study_path: Path | None = None) -> str:
        from designer.study.writer import study_to_xml

        return study_to_xml(self.study(study_path))

    def check_now(self) -> None:
        if not self.isVisible():  # checked when the panel is shown
            self._check_when_shown = True
            return
        self._check_when_shown = False
        if not self.rows:  # said in the panel's words, not the study file's
            self._show_errors([NO_FACTOR])
            return
        try:
            text = self.study_text()
        except ValueError as error:
            self._show_errors([str(error)])
            return
        path = self._path_for_check()
        # an opened study not changed since: check the file itself (its own positions)
        from_file = self._opened_text == text and self.study_path is not None
        # each kind of image with its own records (the cost says which it names)
        self.sync.tasks.submit("study-check", check_study, None if from_file else text,
                               str(path), path, None, self._open_project_inline(),
                               on_done=self._checked, on_error=self._check_failed)

    def _open_project_inline(self):
        """(project, its file's name, its folder) when the study's base is the window's
        project written into the study (not saved, or unsaved changes), else None."""
        doc = self.editor.document
        if self.base_file is not None or self.inline_base is not None or (
                doc.path is not None and not doc.dirty):
            return None
        source = str(doc.path) if doc.path is not None else "the open project (not saved yet)"
        return self.project, source, doc.base_dir

    def _checked(self, result) -> None:
        self.plan, self.cost = result
        c, reps = self.cost, self.plan.study.replicates.count
        workers = self.run_box.workers.value()
        self.plan_label.setText(
            f"<b>{count(c.variants, 'variant')} × {count(reps, 'replicate')} = "
            f"{count(c.runs, 'run')}</b><br>{design_text(self.plan)}<br>"
            f"{count(c.renders, 'render')} "
            f"(distinct image sets, {count(c.images_rendered, 'image')}), "
            f"{count(c.reconstructions, 'reconstruction')}<br>estimated time: "
            f"{duration_text(c.total_s)} on one worker "
            f"(render {duration_text(c.render_s)}, reconstruct {duration_text(c.reconstruct_s)}, "
            f"planning and results {duration_text(c.overhead_s)})"
            + (f", ≈ {duration_text(c.total_s / workers)} with {workers}" if workers > 1
               else "")
            + f"<br>render time: {estimate_basis(c.basis_speed or load_speed())}")
        for row in self.rows:  # each factor's value in the study's base project
            if row.name in FACTORS:
                row.set_base(base_value(FACTORS[row.name], self.plan.base))
        self.errors.hide()
        self.warnings.setText("\n".join(f"⚠ {line}" for line in c.warnings))
        self.warnings.setVisible(bool(c.warnings))
        self.run_box.update_buttons()

    def _check_failed(self, error: BaseException) -> None:
        from designer.project.problems import ProjectError

        if isinstance(error, ProjectError):  # the study's: in words
            lines = study_problem_lines(error)
        else:
            lines = getattr(error, "lines", None) or [str(error)]
        self._show_errors(list(lines))

    def _show_errors(self, lines: list[str]) -> None:
        self.plan = self.cost = None
        self.plan_label.setText("not runnable: fix the study")
        self.errors.setText("\n".join(lines))
        self.errors.show()
        self.warnings.hide()
        self.run_box.update_buttons()

    def _show_base(self) -> None:
        doc = self.editor.document
        if self.base_file is not None:
            self.base_label.setText(str(self.base_file))
        elif self.inline_base is not None:
            self.base_label.setText("the project inside the study file")
        elif doc.path is not None:
            self.base_label.setText(f"the open project: {doc.path}"
                                    + (" (unsaved changes: saved with the study)"
                                       if doc.dirty else ""))
        else:
            self.base_label.setText("the open project (not saved yet: saved with the study)")
        self.use_window.setVisible(self.base_file is not None or self.inline_base is not None)

    def use_window_project(self) -> None:
        self.base_file = self.inline_base = None
        self._show_base()
        self.changed()

    def _on_project(self, old, new, parts) -> None:
        if self.base_file is None and self.inline_base is None:
            self._show_base()
            self.changed()

    def _file_changed(self) -> None:
        """Saved (or saved as): the base's words follow (no unsaved changes any more)."""
        if self.base_file is None and self.inline_base is None:
            self._show_base()
        self.changed()

    def _open_path(self) -> Path | None:
        path = self.editor.document.path
        return path.resolve() if path is not None else None

    def _project_replaced(self) -> None:
        """Another project was opened (or a new one made): the results shown were of the
        project before. A study on the window's project is on the new one now: the study
        file and the output folder it had were the old project's, so the study is not
        saved and has no output folder until it is given one (a study with a base file of
        its own keeps both)."""
        self.results.clear()
        self.run_box.clear_progress()
        path = self._open_path()
        replaced, self._project_path = path != self._project_path, path
        if not replaced or self.base_file is not None or self.inline_base is not None \
                or self.run_box.process.running:
            return
        if self.study_path is not None:
            self.file_label.setText(f"not saved (the study is on the project just opened; "
                                    f"{self.study_path.name} stays on the one before)")
        self.study_path = self._opened_text = None
        self.run_box.folder.clear()
        self._show_base()
        self.changed()

    def refresh(self) -> None:
        pass

    def showEvent(self, event) -> None:
        super().showEvent(event)
        if getattr(self, "_check_when_shown", False):
            self.changed()

    def shutdown(self) -> None:
        self.run_box.shutdown()

