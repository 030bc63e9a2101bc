"""Work off the UI thread: a thread pool whose results come back as Qt signals.

Each job has a ``key`` (``"terrain"``, ``"stations"``, …). Submitting a job for a key
supersedes the earlier one: its result, when it arrives, is dropped, so the view only
ever shows the answer to the latest edit; a superseded job still waiting for a thread
is not run, and a running one stops at its next :func:`designer.gui.state.job_control
.check`. numpy, VTK-free geometry and the survey code
release the GIL for their heavy loops, so the window stays responsive.
"""

from __future__ import annotations

import traceback
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

from PySide6.QtCore import QObject, Signal, Slot

from designer.gui.state import job_control


class TaskRunner(QObject):
    """Runs ``fn(*args)`` in worker threads and calls back on the UI thread."""

    _finished = Signal(str, int, object, object)  # key, generation, result, error
    busy_changed = Signal(bool)

    def __init__(self, parent: QObject | None = None, max_workers: int = 2) -> None:
        super().__init__(parent)
        self._pool = ThreadPoolExecutor(max_workers=max_workers,
                                        thread_name_prefix="designer-gui")
        self._generation: dict[str, int] = {}
        self._callbacks: dict[tuple[str, int], tuple[Callable, Callable | None]] = {}
        self._running = 0
        self._closed = False
        self._finished.connect(self._deliver)

    @property
    def busy(self) -> bool:
        return self._running > 0

    def submit(self, key: str, fn: Callable, *args, on_done: Callable[[object], None],
               on_error: Callable[[BaseException], None] | None = None) -> None:
        """Run ``fn(*args)`` in a thread; ``on_done(result)`` or ``on_error(exc)`` later,
        on the UI thread, unless a newer job with the same key was submitted meanwhile."""
        generation = self._generation.get(key, 0) + 1
        self._generation[key] = generation
        self._callbacks[(key, generation)] = (on_done, on_error)
        self._running += 1
        if self._running == 1:
            self.busy_changed.emit(True)

        def work():
            if self._generation.get(key) != generation:
                # superseded while it waited for a thread: not run at all, so a burst of
                # edits does not queue obsolete work in front of the latest
                self._finished.emit(key, generation, None, None)
                return
            try:
                with job_control.job(lambda: self._generation.get(key) != generation):
                    result, error = fn(*args), None
            except job_control.Superseded:  # stopped at a check: its result is dropped
                result, error = None, None
            except Exception as exc:  # handed to the UI thread
                result, error = None, exc
                error.__traceback_text__ = traceback.format_exc()
            self._finished.emit(key, generation, result, error)

        self._pool.submit(work)

    def cancel(self, key: str) -> None:
        """Drop the result of the job running for ``key``, if any."""
        self._generation[key] = self._generation.get(key, 0) + 1

    @Slot(str, int, object, object)
    def _deliver(self, key: str, generation: int, result, error) -> None:
        on_done, on_error = self._callbacks.pop((key, generation), (None, None))
        self._running -= 1
        if self._closed:
            return
        try:
            if self._generation.get(key) != generation or on_done is None:
                return  # superseded by a newer job for the same key
            if error is None:
                on_done(result)
            elif on_error is not None:
                on_error(error)
            else:
                raise error
        finally:
            if self._running == 0:
                self.busy_changed.emit(False)

    def shutdown(self) -> None:
        """Stop: queued jobs are dropped, results still on their way are ignored."""
        self._closed = True
        self._pool.shutdown(wait=True, cancel_futures=True)
