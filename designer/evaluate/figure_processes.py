"""Draw the figure products in two forked processes, for ``designer compare``.

matplotlib draws in Python, holding the GIL: in one process the histogram and the error
map are drawn one after the other, after the distances, while the second core idles.
:class:`FigureProcesses` forks a process while the command is still single-threaded
(before any input is read); it imports matplotlib there — beside the main process
reading the inputs, without taking turns on one GIL — and then forks a second process
from itself, which shares those imports. The histogram is drawn by one, the error map
by the other, at the same time. Jobs and results travel as pickles over pipes; each
file is written atomically by the process that draws it.

Used where :func:`os.fork` exists and the caller is single-threaded
(:func:`designer.evaluate.figures.prestart`); :class:`~.figures.FigureWriter` (a thread)
everywhere else. Same interface: ``submit``, ``close``, ``abort``, context manager.
"""

from __future__ import annotations

import os
import pickle
import signal
import struct
import traceback

from designer.evaluate.figure_jobs import JOBS, Writers

#: which process draws a job: the histogram in one, the error map (and any other) in
#: the other
_SECOND = ("write_histogram_png",)
_HEADER = struct.Struct("<Q")


def _send(fd: int, message) -> None:
    data = pickle.dumps(message, protocol=pickle.HIGHEST_PROTOCOL)
    view = memoryview(_HEADER.pack(len(data)) + data)
    while view:
        view = view[os.write(fd, view):]


def _receive(fd: int):
    """The next message, or None at the end of the pipe."""
    header = _read_exactly(fd, _HEADER.size)
    if header is None:
        return None
    data = _read_exactly(fd, _HEADER.unpack(header)[0])
    return None if data is None else pickle.loads(data)


def _read_exactly(fd: int, n: int) -> bytes | None:
    parts, left = [], n
    while left:
        chunk = os.read(fd, min(left, 1 << 20))
        if not chunk:
            return None
        parts.append(chunk)
        left -= len(chunk)
    return b"".join(parts)


def _serve(jobs_fd: int, results_fd: int) -> None:
    """Run :mod:`.maps` writers sent over ``jobs_fd`` until None or the pipe's end."""
    from designer.evaluate import maps

    while (job := _receive(jobs_fd)) is not None:
        name, args, kwargs = job
        try:
            getattr(maps, name)(*args, **kwargs)
            _send(results_fd, ("written", None))
        except BaseException as exc:  # reported by the parent's close()
            try:
                _send(results_fd, ("failed", exc))
            except Exception:  # an exception that does not pickle
                text = "".join(traceback.format_exception_only(exc)).strip()
                _send(results_fd, ("failed", RuntimeError(f"{name}: {text}")))


def _child(first: tuple[int, int], second: tuple[int, int], close_fds: list[int],
           parent_pid: int) -> None:
    """Body of the first forked process: import, fork the second, serve; never returns."""
    code = 0
    try:
        signal.signal(signal.SIGINT, signal.SIG_DFL)  # Ctrl-C ends it quietly
        from designer.lifetime import die_with_parent

        die_with_parent(parent_pid)
        for fd in close_fds:
            os.close(fd)
        import rasterio  # noqa: F401  (the GeoTIFF writer's)
        from matplotlib.backends import backend_agg  # noqa: F401
        from matplotlib.figure import Figure  # noqa: F401

        from designer.evaluate import maps  # noqa: F401

        me = os.getpid()
        pid = os.fork()
        if pid == 0:  # the second process: the histogram
            die_with_parent(me)
            os.close(first[0])
            os.close(first[1])
            try:
                _serve(*second)
            finally:
                os._exit(0)
        os.close(second[0])
        os.close(second[1])
        _serve(*first)
        os.waitpid(pid, 0)
    except BaseException:
        code = 1
    finally:
        os._exit(code)


class FigureProcesses(Writers):
    """Two processes drawing :mod:`.maps` figures; create while single-threaded."""

    def __init__(self) -> None:
        # per process: (jobs read end, jobs write end), (results read end, write end)
        pipes = [(os.pipe(), os.pipe()) for _ in range(2)]
        parent = os.getpid()
        pid = os.fork()
        if pid == 0:
            ends = [(jobs[0], results[1]) for jobs, results in pipes]
            mine = [jobs[1] for jobs, _ in pipes] + [results[0] for _, results in pipes]
            _child(ends[0], ends[1], mine, parent)
        self._pid = pid
        for jobs, results in pipes:
            os.close(jobs[0])
            os.close(results[1])
        self._jobs = [jobs[1] for jobs, _ in pipes]
        self._results = [results[0] for _, results in pipes]
        self._pending = [0, 0]
        self._lost = False
        self._closed = False

    def submit(self, job: str, *args, **kwargs) -> None:
        """Send ``designer.evaluate.maps.<job>(*args, **kwargs)`` to its process."""
        if job not in JOBS:
            raise ValueError(f"unknown figure job {job!r}")
        k = 1 if job in _SECOND else 0
        try:
            _send(self._jobs[k], (job, args, kwargs))
        except BrokenPipeError:  # the process has ended: close() says so
            self._lost = True
            return
        self._pending[k] += 1

    def close(self) -> None:
        """Wait until every file is written; re-raise the first writer error."""
        error: BaseException | None = None
        lost = self._lost
        for k in range(2):
            for _ in range(self._pending[k]):
                result = _receive(self._results[k])  # None: the process has ended
                if result is None:
                    lost = True
                elif result[0] == "failed" and error is None:
                    error = result[1]
            self._pending[k] = 0
        lost = self._finish() or lost
        if error is not None:
            raise error
        if lost:
            raise RuntimeError("a figure process ended before writing its files")

    def abort(self) -> None:
        """Stop both processes (a file being written is finished first)."""
        self._finish()

    def _finish(self) -> bool:
        """Close the pipes, so the processes end, and wait for them; True when the first
        one failed."""
        if self._closed:
            return False
        self._closed = True
        for fd in self._jobs + self._results:
            os.close(fd)
        _, status = os.waitpid(self._pid, 0)
        return os.waitstatus_to_exitcode(status) != 0
