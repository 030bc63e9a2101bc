"""Write the figure products (histogram and error-map PNGs, GeoTIFF) in helper processes.

Starting matplotlib and rasterio costs about half a second and drawing a figure a few
tenths more, all single-threaded Python. :class:`FigureWriter` starts helper Python
processes (``python -m designer.evaluate._figure_worker``) that import both while this
process reads the inputs and computes the distances, then draw the figures while it
writes the other products. Each job is a call of a writer in :mod:`.maps`; its file is
written atomically there. Where no helper can be started the jobs run in this process.

Use::

    with FigureWriter() as figures:       # or take_figure_writer()
        figures.submit("write_histogram_png", path, stats)
        ...
    # leaving the block waits for every file; a failure raises DesignerError
"""

from __future__ import annotations

import os
import pickle
import queue
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

from designer.errors import DesignerError

#: the writers of :mod:`.maps` a job may call
JOBS = ("write_histogram_png", "write_error_map_png", "write_error_map_geotiff")
#: helper processes: two draw the two PNGs at the same time
HELPERS = 2


class _Helper:
    """One helper process and the thread that feeds it pickled jobs in order."""

    def __init__(self, env: dict) -> None:
        self.stderr = tempfile.TemporaryFile()
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "designer.evaluate._figure_worker"],
            stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=self.stderr, env=env)
        self.jobs: queue.Queue = queue.Queue()
        self.feeder = threading.Thread(target=self._feed, daemon=True,
                                       name="designer-figure-feeder")
        self.feeder.start()

    def _feed(self) -> None:
        # a blocking pipe write waits for the helper to read: done here, not by the caller
        try:
            while (data := self.jobs.get()) is not None:
                self.proc.stdin.write(data)
                self.proc.stdin.flush()
        except OSError:
            pass  # the helper died: close() reports its error
        finally:
            try:
                self.proc.stdin.close()
            except OSError:
                pass

    def finish(self) -> str | None:
        """Wait for the helper; None, or its error message."""
        self.jobs.put(None)
        self.feeder.join()
        code = self.proc.wait()
        self.stderr.seek(0)
        text = self.stderr.read().decode(errors="replace").strip()
        self.stderr.close()
        if code == 0:
            return None
        return text.splitlines()[-1] if text else f"exit code {code}"

    def kill(self) -> None:
        self.proc.kill()
        self.jobs.put(None)
        self.proc.wait()
        self.stderr.close()


class FigureWriter:
    """Jobs for :mod:`.maps` writers, run in helper processes (see the module docstring)."""

    def __init__(self, helpers: int = HELPERS) -> None:
        self._helpers: list[_Helper] = []
        self._next = 0
        env = dict(os.environ)
        # the helpers import this very package, wherever the parent found it
        root = str(Path(__file__).resolve().parents[2])
        env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH")) if p)
        try:
            for _ in range(helpers):
                self._helpers.append(_Helper(env))
        except OSError:  # e.g. no Python executable to start: run the jobs here
            for h in self._helpers:
                h.kill()
            self._helpers = []

    def submit(self, job: str, *args, **kwargs) -> None:
        """Run ``designer.evaluate.maps.<job>(*args, **kwargs)``; jobs go to the helpers in
        turn, and run in this process when there are none."""
        if job not in JOBS:
            raise ValueError(f"unknown figure job {job!r}")
        if not self._helpers:
            from designer.evaluate import maps

            getattr(maps, job)(*args, **kwargs)
            return
        helper = self._helpers[self._next % len(self._helpers)]
        self._next += 1
        helper.jobs.put(pickle.dumps((job, args, kwargs), protocol=pickle.HIGHEST_PROTOCOL))

    def close(self) -> None:
        """Wait until every file is written; raise DesignerError if a helper failed."""
        helpers, self._helpers = self._helpers, []
        errors = [e for e in (h.finish() for h in helpers) if e]
        if errors:
            raise DesignerError(f"writing the figures failed: {errors[0]}")

    def abort(self) -> None:
        """Stop the helpers without waiting for their files."""
        helpers, self._helpers = self._helpers, []
        for h in helpers:
            h.kill()

    def __enter__(self) -> FigureWriter:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.close()
        else:
            self.abort()


_prestarted: FigureWriter | None = None


def prestart() -> None:
    """Start the helpers now, so they are ready when :func:`take_figure_writer` is
    called (``designer compare`` does this before reading its inputs)."""
    global _prestarted
    if _prestarted is None:
        _prestarted = FigureWriter()


def take_figure_writer() -> FigureWriter:
    """The pre-started writer, or a new one."""
    global _prestarted
    writer, _prestarted = _prestarted, None
    return writer if writer is not None else FigureWriter()


def discard_prestarted() -> None:
    """Stop pre-started helpers that were not taken (the command failed before)."""
    global _prestarted
    writer, _prestarted = _prestarted, None
    if writer is not None:
        writer.abort()
