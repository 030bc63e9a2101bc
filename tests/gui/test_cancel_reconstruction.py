"""Cancelling a reconstruction stops its command without a native stack trace (problem 8
of the user test): COLMAP's logging prints one on SIGTERM."""

from __future__ import annotations

import sys

import pytest

from designer.gui.qt.reconstruct_process import ReconstructRun

pytestmark = pytest.mark.gui

# a command that has COLMAP loaded (its signal handlers installed) and is busy in a
# stage that does not look at Ctrl-C (as COLMAP's C++ feature matching)
BUSY_COLMAP = ("import pycolmap, signal, time; signal.signal(signal.SIGINT, signal.SIG_IGN); "
               "print('colmap loaded', flush=True); [time.sleep(0.05) for _ in range(2000)]")


class _Job:
    """A reconstruction job whose one command is BUSY_COLMAP (its stages never end)."""

    survey_dir = None

    def commands(self):
        return [[sys.executable, "-c", BUSY_COLMAP]]


def test_cancel_prints_no_stack_trace(qtbot, qapp, tmp_path):
    run = ReconstructRun()
    lines, done = [], []
    run.output.connect(lines.append)
    run.finished.connect(lambda code, message: done.append((code, message)))
    _Job.survey_dir = tmp_path
    run.start(_Job())
    qtbot.waitUntil(lambda: "colmap loaded" in lines, timeout=60000)
    run.cancel()
    qtbot.waitUntil(lambda: bool(done), timeout=30000)
    assert done == [(130, "cancelled")]
    assert not run.running
    text = "\n".join(lines)
    assert "SIGTERM" not in text and "stack trace" not in text and "***" not in text
    assert "Traceback" not in text
