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

from PySide6.QtCore import QProcess, QProcessEnvironment, QTimer

import designer
from designer.gui.qt.command_process import CommandProcess
from designer.lifetime import child_environment

#: how long (ms) the study's processes may take to stop on SIGINT before they are killed
CANCEL_GRACE_MS = 5000


def study_command(study: Path, out_dir: Path, resume: bool = False,
                  workers: int = 1) -> list[str]:
    argv = [sys.executable, "-m", "designer", "study", "run", str(study), "-o", str(out_dir),
            "--progress", "json", "--workers", str(workers)]
    return argv + (["--resume"] if resume else [])


class StudyProcess(CommandProcess):
    """The study command; Cancel stops its whole process group."""

    def start(self, argv: list[str], cwd: Path | None = None) -> None:
        """Start ``argv`` as the leader of a new session (its own process group)."""
        if self.running:
            raise RuntimeError("a study is already running")
        self._buffer, self._stderr, self.cancelled = b"", b"", False
        proc = QProcess(self)
        if os.name == "posix":
            params = QProcess.UnixProcessParameters()
            params.flags = QProcess.UnixProcessFlag.CreateNewSession
            proc.setUnixProcessParameters(params)
        if cwd is not None:
            proc.setWorkingDirectory(str(cwd))
        # the command imports this window's designer package, wherever it is started
        env = QProcessEnvironment.systemEnvironment()
        root = str(Path(designer.__file__).resolve().parents[1])
        env.insert("PYTHONPATH", os.pathsep.join(
            p for p in (root, env.value("PYTHONPATH", "")) if p))
        for key, value in child_environment().items():  # it dies with this window
            env.insert(key, value)
        proc.setProcessEnvironment(env)
        proc.readyReadStandardOutput.connect(self._read_stdout)
        proc.readyReadStandardError.connect(self._read_stderr)
        proc.finished.connect(self._done)
        self.process = proc
        proc.start(argv[0], argv[1:])

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
