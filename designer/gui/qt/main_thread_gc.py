"""Python's cyclic garbage collected on the GUI thread only.

An automatic collection runs in whichever thread happens to allocate, and the window's
background tasks allocate. A collection in a task's thread can free VTK objects (a
replaced layer's actor and mapper, a closed view's plotter) whose deletion takes VTK's
own collector lock, while the main thread, drawing, holds that lock and waits for the
GIL the task's thread holds: both would wait for ever. With a :class:`MainThreadCollector`
alive, automatic collection is off and a timer on the GUI thread collects instead, the
generations Python's own thresholds call for."""

from __future__ import annotations

import gc

from PySide6.QtCore import QObject, QTimer

#: how often the GUI thread compares the allocation counts with the thresholds (ms)
CHECK_INTERVAL_MS = 500


class MainThreadCollector(QObject):
    """Automatic collection off while this lives (until :meth:`stop`); a timer on the
    thread that creates it collects generation 0, 1 or 2 when Python's counts pass its
    thresholds, as the automatic collection would have."""

    def __init__(self, parent: QObject | None = None,
                 interval_ms: int = CHECK_INTERVAL_MS) -> None:
        super().__init__(parent)
        self.threshold = gc.get_threshold()
        gc.disable()
        self._timer = QTimer(self)
        self._timer.timeout.connect(self.check)
        self._timer.start(interval_ms)

    def check(self) -> int:
        """Collect the generation the counts call for; the objects collected."""
        (n0, n1, n2), (t0, t1, t2) = gc.get_count(), self.threshold
        if n0 <= t0:
            return 0
        generation = 2 if n1 > t1 and n2 > t2 else 1 if n1 > t1 else 0
        return gc.collect(generation)

    def stop(self) -> None:
        """Automatic collection back on."""
        self._timer.stop()
        gc.enable()
