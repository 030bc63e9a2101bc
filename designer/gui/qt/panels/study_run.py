"""The run part of the Study panel: the output folder, workers, Run / Resume and Cancel,
progress (runs finished of the total, the current stage) from the JSON lines of
``designer study run --progress json``."""

from __future__ import annotations

import time
from pathlib import Path

from PySide6.QtWidgets import (
    QFileDialog,
    QGroupBox,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QProgressBar,
    QPushButton,
    QToolButton,
)

from designer.gui.qt.boxes import follow_process, log_view
from designer.gui.qt.study_process import StudyProcess, study_command
from designer.gui.qt.study_results import FAILED_COLOUR
from designer.gui.qt.widgets import form, ispin, message_box
from designer.gui.state.study_data import StudyFolder, duration_text, read_folder

#: ``designer study run``'s exit status when it finished and some runs failed (every
#: result written; designer.cli.study.RUNS_FAILED_EXIT)
RUNS_FAILED_EXIT = 3


class StudyRunBox(QGroupBox):
    def __init__(self, panel) -> None:
        super().__init__("run")
        self.panel = panel
        f = form(self)
        row = QHBoxLayout()
        self.folder = QLineEdit()
        self.folder.setObjectName("study-output")
        self.folder.setPlaceholderText("output folder (new, or a study to resume)")
        self.folder.textChanged.connect(lambda _t: self.update_buttons())
        browse = QToolButton()
        browse.setText("…")
        browse.clicked.connect(self._browse)
        row.addWidget(self.folder, 1)
        row.addWidget(browse)
        f.addRow("output folder", row)
        self.workers = ispin(1, 64, label="Study workers")
        self.workers.setToolTip("worker processes: renders and reconstructions run in "
                                "parallel")
        self.workers.valueChanged.connect(lambda _v: panel.changed())
        f.addRow("workers", self.workers)
        buttons = QHBoxLayout()
        self.run_button = QPushButton("Run")
        self.run_button.setObjectName("study-run")
        self.run_button.clicked.connect(self.run)
        self.cancel_button = QPushButton("Cancel")
        self.cancel_button.setObjectName("study-cancel")
        self.cancel_button.clicked.connect(self.cancel)
        buttons.addWidget(self.run_button)
        buttons.addWidget(self.cancel_button)
        f.addRow(buttons)
        # why Run is greyed, in words under it (an area of a fixed height: the reason
        # comes and goes with every check and moves nothing below)
        self.reason = QLabel("")
        self.reason.setObjectName("study-run-reason")
        self.reason.setWordWrap(True)
        f.addRow(message_box([self.reason], 3))
        # how a run goes, in a box of its own that the panel places under the study's
        # errors: an empty study's errors then show under Run without scrolling the panel
        self.progress_box = QGroupBox("progress")
        p = form(self.progress_box)
        self.progress = QProgressBar()
        self.progress.setFormat("%v / %m runs")
        p.addRow(self.progress)
        self.state = QLabel("")
        self.state.setObjectName("study-state")
        self.state.setWordWrap(True)
        p.addRow(self.state)
        self.log = log_view(300, 90)
        p.addRow(self.log)
        self.process = StudyProcess(self)
        follow_process(self.process, self.log, self.on_event, self._finished)
        self.out_dir: Path | None = None
        self._folder_state = "empty"
        self.update_buttons()

    def settings(self):
        return getattr(self.panel.window(), "settings", None)

    def default_folder(self, study_path: Path) -> None:
        if not self.folder.text().strip():
            self.folder.setText(str(study_path.parent / f"{study_path.stem}-study"))

    def _browse(self) -> None:
        chosen = QFileDialog.getExistingDirectory(self, "Study output folder",
                                                  self.folder.text() or str(Path.cwd()))
        if chosen:
            self.folder.setText(chosen)

    def folder_state(self) -> StudyFolder | None:
        text = self.folder.text().strip()
        if not text:
            return None
        try:
            return read_folder(Path(text).expanduser(), contents=False)
        except Exception:  # an unreadable record: the command says what is wrong
            return None

    def update_buttons(self) -> None:
        running = self.process.running
        folder = self.folder_state()
        self._folder_state = folder.state if folder is not None else "empty"
        self.run_button.setText("Resume" if self._folder_state == "partial" else "Run")
        tip = "" if running else self.why_not_run(folder)
        self.run_button.setToolTip(tip)
        self.run_button.setEnabled(not running and not tip)
        self.reason.setText(f"Run is greyed: {tip}" if tip else "")
        self.cancel_button.setEnabled(running)

    def why_not_run(self, folder: StudyFolder | None) -> str:
        """Why Run cannot start now ("" when it can)."""
        panel = self.panel
        if panel.plan is None:
            errors = getattr(panel, "errors", None)
            if errors is not None and not errors.isHidden():
                return "the study has errors (listed below); fix them"
            return "the study is being checked…"
        if folder is None:
            return "choose an output folder (a new one, or a study to resume)"
        if folder.state == "complete":
            return (f"the output folder holds the finished study '{folder.name}' (Open "
                    "study folder… shows its results); choose another folder to run again")
        return ""

    # ------------------------------------------------------------------ run
    def run(self) -> None:
        panel = self.panel
        # the checked plan: saving the study (and the project it is based on) starts a
        # new check of the same study, which clears panel.plan until it is done
        plan = panel.plan
        if plan is None or self.process.running:
            return
        text = panel.study_text(panel.study_path) if panel.study_path else None
        if panel.study_path is None or text != panel._opened_text:
            if not panel.save_study(panel.study_path):
                return
        folder = self.folder_state()
        if folder is None:
            return
        resume = folder.state == "partial"
        self.out_dir = folder.path
        self.total = len(plan.runs)
        self.progress.setRange(0, self.total)
        self.progress.setValue(folder.runs_done if resume else 0)
        self.renders_started = self.renders_done = 0
        self.failed_runs = 0
        self._show_failed(False)
        self.log.clear()
        self._t0 = time.perf_counter()
        argv = study_command(panel.study_path, self.out_dir, resume, self.workers.value())
        self.process.start(argv, cwd=panel.study_path.parent)
        self.state.setText(("resuming" if resume else "starting") + f" the study into "
                           f"{self.out_dir} …")
        self.update_buttons()

    def cancel(self) -> None:
        self.process.cancel()
        self.state.setText("stopping: finished runs are kept; Resume continues later")

    def on_event(self, event: dict) -> None:
        kind = event.get("event")
        if kind == "planned":
            self.state.setText(f"stage: planning runs {event['done']} / {event['total']}")
        elif kind == "render_started":
            self.renders_started += 1
            self.log.appendPlainText(f"rendering image set {event['image_set'][:10]} "
                                     f"({event['runs']} runs share it)")
            self.state.setText(self._stage_text())
        elif kind == "render_done":
            self.renders_done += 1
            seconds = event.get("seconds")
            self.log.appendPlainText(f"image set {event['image_set'][:10]} rendered"
                                     + (f" in {seconds:.0f} s" if seconds else ""))
            self.state.setText(self._stage_text())
        elif kind == "run_done":
            self.progress.setRange(0, int(event["total"]))
            self.progress.setValue(int(event["done"]))
            self.log.appendPlainText(f"{event['run']}: {event['status']}")
            if event["status"] != "ok":
                self.failed_runs += 1
                self._show_failed(True)
            self.state.setText(self._stage_text()
                               + f"; last finished {event['run']} ({event['status'][:60]})")

    def _stage_text(self) -> str:
        rendering = self.renders_started - self.renders_done
        stage = (f"rendering {rendering} image set{'s' if rendering != 1 else ''}"
                 if rendering else "reconstructing and comparing")
        if rendering and self.renders_done:
            stage += ", reconstructing"
        failed = getattr(self, "failed_runs", 0)
        return (f"stage: {stage}; {self.progress.value()} / {self.progress.maximum()} runs "
                f"finished" + (f", {failed} failed" if failed else ""))

    def _show_failed(self, failed: bool) -> None:
        """The progress bar and the state line in red once a run failed (or the study)."""
        self.progress.setProperty("failed", failed)
        self.progress.setStyleSheet(
            f"QProgressBar::chunk {{ background-color: {FAILED_COLOUR}; }}" if failed else "")
        self.state.setStyleSheet(f"color: {FAILED_COLOUR}" if failed else "")

    def _finished(self, code: int, stderr_tail: str) -> None:
        seconds = time.perf_counter() - getattr(self, "_t0", time.perf_counter())
        folder = read_folder(self.out_dir) if self.out_dir is not None else None
        done = f"{folder.runs_done} of {folder.runs_total}" if folder else "?"
        failed = folder.failed_rows if folder is not None else []
        if self.process.cancelled:
            self.state.setText(f"cancelled after {duration_text(seconds)}: {done} runs "
                               f"finished and kept in {self.out_dir}"
                               + (f" ({len(failed)} failed)" if failed else "")
                               + "; Resume continues")
        elif code in (0, RUNS_FAILED_EXIT) and failed:
            self.state.setText(f"finished in {duration_text(seconds)}: {folder.outcome()}; "
                               "results below")
        elif code == 0:
            self.state.setText(f"done in {duration_text(seconds)}: {done} runs; results "
                               "below")
        else:
            last = [line for line in stderr_tail.splitlines() if line.strip()][-1:]
            self.state.setText(f"the study failed (exit {code})"
                               + (f": {last[0]}" if last else ""))
        self._show_failed(bool(failed) or (code != 0 and not self.process.cancelled))
        if folder is not None and folder.state != "empty":
            self.panel.results.show_folder(folder)
        self.update_buttons()

    def clear_progress(self) -> None:
        """Forget the last run's progress, state and log (not while a study runs)."""
        if self.process.running:
            return
        self.progress.reset()
        self._show_failed(False)
        self.state.setText("")
        self.log.clear()

    def shutdown(self) -> None:
        if self.process.running:
            self.process.cancel()
            if not self.process.process.waitForFinished(15000):
                self.process.kill()
