"""Runs a :class:`~designer.gui.state.reconstruct_job.ReconstructJob`'s commands one after the
other in their own processes; the window only reads their output.

Cancel sends SIGINT, on which a designer command stops cleanly; COLMAP's feature
extraction and matching run in C++ and do not look at Python's Ctrl-C flag, so a
command still running after :data:`CANCEL_GRACE_MS` is killed (SIGKILL). Not SIGTERM:
COLMAP's logging library catches it and prints a native stack trace, which reads like
a crash. The reconstruction folder is scratch (a new run starts it afresh) and every
file in it is written atomically, so stopping at once leaves nothing half-written.
"""

from __future__ import annotations

from PySide6.QtCore import QObject, QTimer, Signal

from designer.gui.qt.command_process import CommandProcess
from designer.gui.state.reconstruct_job import COMPARE_STAGE, STAGES, ReconstructJob, stage_of_line

#: how long (ms) a cancelled command may take to stop on SIGINT before it is killed
CANCEL_GRACE_MS = 2000


class StoppingProcess(CommandProcess):
    """A command that Cancel stops with SIGINT, then SIGKILL after CANCEL_GRACE_MS."""

    def cancel(self) -> None:
        if not self.running:
            return
        super().cancel()
        process = self.process
        QTimer.singleShot(CANCEL_GRACE_MS, self, lambda: self._kill_if(process))

    def _kill_if(self, process) -> None:
        if process is self.process and self.running:
            self.process.kill()  # QProcess.kill: SIGKILL; finished() follows


class ReconstructRun(QObject):
    stage = Signal(int, str)     # stage index, title
    output = Signal(str)         # every line the commands print
    finished = Signal(int, str)  # exit code (0: done), a message

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.process = StoppingProcess(self)
        self.process.output.connect(self._line)
        self.process.finished.connect(self._step_done)
        self.job: ReconstructJob | None = None
        self._queue: list[list[str]] = []
        self._step = 0
        self.current_stage = -1
        self.cancelled = False

    @property
    def running(self) -> bool:
        return self.process.running or bool(self._queue)

    def start(self, job: ReconstructJob) -> None:
        if self.running:
            raise RuntimeError("a reconstruction is already running")
        self.job, self.cancelled = job, False
        self._queue = job.commands()
        self._step = 0
        self.current_stage = -1
        self._next()

    def cancel(self) -> None:
        self.cancelled = True
        self._queue = []
        self.process.cancel()

    def kill(self) -> None:
        self._queue = []
        self.process.kill()

    def _next(self) -> None:
        argv = self._queue.pop(0)
        if self._step == 1:
            self._set_stage(COMPARE_STAGE)
        self.process.start(argv, cwd=self.job.survey_dir)

    def _set_stage(self, index: int) -> None:
        if index > self.current_stage:
            self.current_stage = index
            self.stage.emit(index, STAGES[index][0])

    def _line(self, text: str) -> None:
        self.output.emit(text)
        index = stage_of_line(text) if self._step == 0 else None
        if index is not None:
            self._set_stage(index)

    def _step_done(self, code: int, stderr_tail: str) -> None:
        name = ("designer reconstruct", "designer compare")[min(self._step, 1)]
        if self.cancelled:
            self.finished.emit(130, "cancelled")
            return
        if code != 0:
            self._queue = []
            last = [line for line in stderr_tail.splitlines() if line.strip()][-1:]
            self.finished.emit(code, f"{name} failed (exit {code})"
                               + (f": {last[0]}" if last else ""))
            return
        self._step += 1
        if self._queue:
            self._next()
        else:
            self.finished.emit(0, "done")
