"""``designer study run STUDY.xml -o DIR --progress json`` in its own process session.

The study runs its stages in worker processes (and each render in Blender worker
processes of its own), so the command starts a new session: Cancel sends SIGINT to the
whole process group — what Ctrl-C in a terminal does, on which every process stops —
and, if anything still runs after :data:`CANCEL_GRACE_MS`, SIGKILL to the group. A study
loses no finished run either way; ``--resume`` continues it.
"""

from __future__ import annotations

import os
import signal
import sys
from pathlib import Path

from PySide6.QtCore import QTimer

from designer.gui.qt.command_process import CommandProcess

#: how long (ms) the study's processes may take to stop on SIGINT before they are killed
CANCEL_GRACE_MS = 5000


def study_command(study: Path, out_dir: Path, resume: bool = False,
                  workers: int = 1) -> list[str]:
    argv = [sys.executable, "-m", "designer", "study", "run", str(study), "-o", str(out_dir),
            "--progress", "json", "--workers", str(workers)]
    return argv + (["--resume"] if resume else [])


class StudyProcess(CommandProcess):
    """The study command, leader of a new session; Cancel stops its whole process group."""

    own_session = True
    what = "a study"

    def _signal_group(self, sig: int) -> None:
        pid = self.process.processId() if self.process is not None else 0
        if not pid:
            return
        try:
            os.killpg(pid, sig)
        except ProcessLookupError:
            pass

    def cancel(self) -> None:
        if not self.running:
            return
        self.cancelled = True
        if os.name != "posix":
            self.process.kill()
            return
        self._signal_group(signal.SIGINT)
        process = self.process
        QTimer.singleShot(CANCEL_GRACE_MS, self, lambda: self._kill_if(process))

    def _kill_if(self, process) -> None:
        if process is self.process and self.running:
            self._signal_group(signal.SIGKILL)

    def kill(self) -> None:
        if self.running:
            if os.name == "posix":
                self._signal_group(signal.SIGKILL)
            else:
                self.process.kill()
            self.process.waitForFinished(5000)
