"""Write the figure products (histogram and error-map PNGs) in a helper thread.

Importing matplotlib costs about a third of a second and drawing a figure a few tenths
more, single-threaded Python. :class:`FigureWriter` does both in a thread: it imports
while the distance kernels run (they release the GIL) and draws while the caller
writes the other products (mostly NumPy and file output, which release it too). Each
job is a call of a writer in :mod:`.maps`, whose file is written atomically.

Use::

    with take_figure_writer() as figures:
        figures.submit("write_histogram_png", path, stats)
        ...
    # leaving the block waits for every file and re-raises a writer's error
"""

from __future__ import annotations

import os
import queue
import threading

from designer.evaluate.figure_jobs import JOBS, Writers


class FigureWriter(Writers):
    """A thread running :mod:`.maps` writers in submission order."""

    def __init__(self) -> None:
        self._jobs: queue.Queue = queue.Queue()
        self._error: BaseException | None = None
        self._stop = False
        self._thread = threading.Thread(target=self._run, daemon=True,
                                        name="designer-figures")
        self._thread.start()

    def _run(self) -> None:
        try:
            # matplotlib, and rasterio for the caller's GeoTIFF writer
            import rasterio  # noqa: F401
            from matplotlib.backends import backend_agg  # noqa: F401
            from matplotlib.figure import Figure  # noqa: F401

            from designer.evaluate import maps
        except BaseException as exc:  # reported by close()
            self._error = exc
        while (job := self._jobs.get()) is not None:
            if self._error is not None or self._stop:
                continue
            name, args, kwargs = job
            try:
                getattr(maps, name)(*args, **kwargs)
            except BaseException as exc:
                self._error = exc

    def submit(self, job: str, *args, **kwargs) -> None:
        """Queue ``designer.evaluate.maps.<job>(*args, **kwargs)``."""
        if job not in JOBS:
            raise ValueError(f"unknown figure job {job!r}")
        self._jobs.put((job, args, kwargs))

    def close(self) -> None:
        """Wait until every queued file is written; re-raise the first writer error."""
        self._jobs.put(None)
        self._thread.join()
        if self._error is not None:
            raise self._error

    def abort(self) -> None:
        """Drop the queued jobs (one being written still finishes, in the background)."""
        self._stop = True
        self._jobs.put(None)


_prestarted: Writers | None = None


def prestart(*, processes: bool = False) -> None:
    """Start the figure writer now, so it is ready when :func:`take_figure_writer` is
    called: with ``processes``, two forked processes (:mod:`.figure_processes`; only
    where this process can fork and has no other thread yet — the ``designer compare``
    program), else a thread."""
    global _prestarted
    if _prestarted is None:
        if processes and hasattr(os, "fork") and threading.active_count() == 1:
            from designer.evaluate.figure_processes import FigureProcesses

            _prestarted = FigureProcesses()
        else:
            _prestarted = FigureWriter()


def take_figure_writer() -> Writers:
    """The pre-started writer (:class:`FigureWriter` or
    :class:`~.figure_processes.FigureProcesses`), or a new :class:`FigureWriter`."""
    global _prestarted
    writer, _prestarted = _prestarted, None
    return writer if writer is not None else FigureWriter()


def discard_prestarted() -> None:
    """Stop a pre-started writer that was not taken (the command failed before)."""
    global _prestarted
    writer, _prestarted = _prestarted, None
    if writer is not None:
        writer.abort()
