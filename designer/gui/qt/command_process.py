"""``designer`` commands in their own process (QProcess), read line by line.

:class:`CommandProcess` runs any command and forwards each JSON object it prints as the
``event`` signal and every other line (stdout or stderr) as ``output``; the render,
reconstruct and study processes are its subclasses, started by its one ``start``.

:class:`RenderProcess` runs ``designer render … --progress json``. Blender runs in the
render command's worker processes, never in the window's: the window only reads JSON
events (``worker_started``, ``scene_ready``, ``frame_done``, ``frame_skipped``,
``retry``, ``worker_done``). Cancel sends SIGINT, on which the command stops its workers
cleanly (exit code 130) and leaves only complete images.
"""

from __future__ import annotations

import json
import os
import signal
import sys
from pathlib import Path

from PySide6.QtCore import QObject, QProcess, QProcessEnvironment, Signal

import designer
from designer.lifetime import child_environment


class CommandProcess(QObject):
    """One command in a QProcess; ``cancel_signal`` is what Cancel sends it,
    ``own_session`` whether it leads a process group of its own, ``what`` how the refusal
    to start a second one names it."""

    event = Signal(dict)
    finished = Signal(int, str)  # exit code, last lines of stderr
    output = Signal(str)         # any non-JSON line
    cancel_signal = signal.SIGINT
    own_session = False
    what = "a command"

    def __init__(self, parent: QObject | None = None) -> None:
        super().__init__(parent)
        self.process: QProcess | None = None
        self._buffer = b""
        self._stderr = b""
        self.cancelled = False

    @property
    def running(self) -> bool:
        return self.process is not None and self.process.state() != QProcess.ProcessState.NotRunning

    def start(self, argv: list[str], cwd: Path | None = None) -> None:
        """Start ``argv`` (in ``cwd``); it imports this window's designer package and dies
        with the window. With ``own_session`` it leads a new session (its own process
        group), so that a subclass can signal it and every process it started at once."""
        if self.running:
            raise RuntimeError(f"{self.what} is already running")
        self._buffer, self._stderr, self.cancelled = b"", b"", False
        proc = QProcess(self)
        if self.own_session and os.name == "posix":
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

    def cancel(self) -> None:
        """Ask the command to stop (``cancel_signal``); it exits after cleaning up."""
        if not self.running:
            return
        self.cancelled = True
        pid = self.process.processId()
        if pid and os.name == "posix":
            os.kill(pid, self.cancel_signal)
        else:
            self.process.terminate()

    def kill(self) -> None:
        if self.running:
            self.process.kill()
            self.process.waitForFinished(5000)

    def _read_stdout(self) -> None:
        self._buffer += bytes(self.process.readAllStandardOutput())
        *lines, self._buffer = self._buffer.split(b"\n")
        for raw in lines:
            text = raw.decode("utf-8", "replace").strip()
            if not text:
                continue
            try:
                event = json.loads(text)
            except json.JSONDecodeError:
                self.output.emit(text)
                continue
            if isinstance(event, dict) and "event" in event:
                self.event.emit(event)
            else:
                self.output.emit(text)

    def _read_stderr(self) -> None:
        chunk = bytes(self.process.readAllStandardError())
        self._stderr = (self._stderr + chunk)[-20000:]
        for line in chunk.decode("utf-8", "replace").splitlines():
            if line.strip():
                self.output.emit(line)

    def _done(self, code: int, _status) -> None:
        self._read_stdout()
        if self._buffer.strip():
            self._buffer += b"\n"
            self._read_stdout()
        tail = "\n".join(self._stderr.decode("utf-8", "replace").splitlines()[-10:])
        self.finished.emit(int(code), tail)


class RenderProcess(CommandProcess):
    """``designer render … --progress json``; Cancel sends SIGINT (clean stop)."""

    @staticmethod
    def command(project: Path, out_dir: Path, resume: bool = False,
                quality: str | None = None, workers: int | None = None) -> list[str]:
        args = ["-m", "designer", "render", str(project), "-o", str(out_dir),
                "--progress", "json"]
        if resume:
            args.append("--resume")
        if quality:
            args += ["--quality", quality]
        if workers:
            args += ["--workers", str(workers)]
        return [sys.executable, *args]
