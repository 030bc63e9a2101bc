"""The window's task runner: a job superseded by a newer one of the same key stops at
its next check (job_control.check), and one superseded while it waited for a thread is
not run at all — a burst of edits leaves the threads to the latest."""

from __future__ import annotations

import threading
import time

import pytest

from designer.gui.qt.tasks import TaskRunner
from designer.gui.state import job_control

pytestmark = pytest.mark.gui


def test_a_superseded_job_stops_at_its_check_and_a_queued_one_never_runs(qtbot):
    runner = TaskRunner(max_workers=1)
    started, stopped_after_s, results = [], [], []
    release = threading.Event()

    def long_job(name: str) -> str:
        started.append(name)
        t0 = time.perf_counter()
        try:
            while time.perf_counter() - t0 < 20.0:
                job_control.check()
                release.wait(0.01)
        finally:
            stopped_after_s.append(time.perf_counter() - t0)
        return name

    runner.submit("plan", long_job, "first", on_done=results.append)
    qtbot.waitUntil(lambda: started == ["first"], timeout=5000)
    # two newer edits: the second supersedes the first before any thread is free for it
    runner.submit("plan", long_job, "second", on_done=results.append)
    runner.submit("plan", long_job, "third", on_done=results.append)
    qtbot.waitUntil(lambda: len(started) >= 2, timeout=5000)
    assert started == ["first", "third"], (started, stopped_after_s)
    assert stopped_after_s[0] < 5.0  # the first stopped at a check, long before 20 s
    runner.cancel("plan")  # the third stops too: nothing of 'plan' is delivered
    release.set()
    runner.submit("other", lambda: "done", on_done=results.append)  # the thread is free
    qtbot.waitUntil(lambda: not runner.busy, timeout=5000)
    assert results == ["done"]
    assert started == ["first", "third"] and len(stopped_after_s) == 2  # 'second' never ran


def test_check_outside_a_job_does_nothing():
    job_control.check()  # no job in this thread: no error
