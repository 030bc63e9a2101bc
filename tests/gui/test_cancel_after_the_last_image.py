"""Render panel: Cancel pressed after the last image landed (the command still writing its
records) says every image is up to date and nothing is left, not "start the render again
to render only the rest" (issue 53, finding 6).

A small script stands in for ``designer render --progress json``, as in
test_round_three_render.py: it renders its images, then waits (as the command does while
it finishes its records) and on SIGINT prints the command's ``interrupted`` counts."""

from __future__ import annotations

import sys
import textwrap

import pytest
from PySide6.QtCore import Qt

from designer.gui.qt.command_process import RenderProcess

pytestmark = pytest.mark.gui

FAKE = textwrap.dedent("""
    import json, signal, sys, time
    from pathlib import Path
    out, n = Path(sys.argv[1]), int(sys.argv[2])
    (out / "images").mkdir(parents=True, exist_ok=True)
    def stop(*_):
        print(json.dumps({"event": "interrupted", "total": n, "up_to_date": n,
                          "rendered_now": n, "out_of_date": 0, "not_rendered": 0,
                          "resume": True}), flush=True)
        print("designer: interrupted by SIGINT", file=sys.stderr, flush=True)
        sys.exit(130)
    signal.signal(signal.SIGINT, stop)
    print(json.dumps({"event": "worker_started", "worker": 0, "pid": 1,
                      "frames": list(range(n))}), flush=True)
    for i in range(n):
        path = out / "images" / f"IMG_{i + 1:05d}.png"
        path.write_bytes(b"")
        print(json.dumps({"event": "frame_done", "index": i, "path": str(path),
                          "seconds": 0.1}), flush=True)
    time.sleep(60)  # the records being finished when Cancel comes
""")


def test_cancel_after_the_last_image_says_nothing_is_left(qtbot, saved_project,
                                                          monkeypatch, tmp_path):
    w = saved_project
    script = tmp_path / "fake_render.py"
    script.write_text(FAKE)
    monkeypatch.setattr(RenderProcess, "command", staticmethod(
        lambda project, out_dir, resume=False, quality=None, workers=None:
        [sys.executable, str(script), str(out_dir), "4"]))
    panel = w.panels["Render"]
    assert panel.resume.isChecked()
    qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: len(panel.frames_done) == 4, timeout=20000)
    qtbot.mouseClick(panel.cancel_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=20000)
    text = panel.state.text()
    assert text == ("cancelled: all 4 images up to date (4 rendered by this run); nothing "
                    "is left to render"), text
