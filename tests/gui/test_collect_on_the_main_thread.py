"""Cyclic garbage made during a GUI test is collected on the main thread, never by an
automatic collection in a background thread (tests/gui/conftest.py)."""

from __future__ import annotations

import gc
import threading
from concurrent.futures import ThreadPoolExecutor


def _cycle(finalized: list[bool]) -> type:
    """A class whose instances refer to themselves (only the cyclic collector frees
    them) and append to ``finalized`` whether they were freed on the main thread."""

    class Cycle:
        def __init__(self) -> None:
            self.me = self

        def __del__(self) -> None:
            finalized.append(threading.current_thread() is threading.main_thread())

    return Cycle


def test_garbage_made_in_a_worker_thread_is_collected_on_the_main_thread():
    finalized: list[bool] = []
    Cycle = _cycle(finalized)

    def work() -> int:
        Cycle()
        # far past the first generation's threshold: an automatic collection, if on,
        # runs here, in this thread
        junk = [[] for _ in range(50 * gc.get_threshold()[0])]
        return len(junk)

    with ThreadPoolExecutor(1) as pool:
        assert pool.submit(work).result() > 0
    assert finalized == []  # nothing collected in the worker
    gc.collect()
    assert finalized == [True]


def test_the_windows_collector_keeps_collection_on_the_gui_thread(qtbot):
    """``designer gui``'s MainThreadCollector: with automatic collection on (as in the
    program), garbage made in a task's thread is not collected there but by the GUI
    thread's timer, without anyone calling gc.collect."""
    from designer.gui.qt.main_thread_gc import MainThreadCollector

    finalized: list[bool] = []
    Cycle = _cycle(finalized)

    def work() -> list:
        Cycle()
        # kept (returned): the allocation count stays past the first threshold
        return [[] for _ in range(50 * gc.get_threshold()[0])]

    gc.enable()
    collector = MainThreadCollector(interval_ms=50)
    try:
        with ThreadPoolExecutor(1) as pool:
            junk = pool.submit(work).result()
        assert finalized == []
        qtbot.waitUntil(lambda: finalized == [True], timeout=5000)
    finally:
        collector.stop()
    assert gc.isenabled() and junk
