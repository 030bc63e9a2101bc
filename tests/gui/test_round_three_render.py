"""Render panel, round three: the cancel text counts what the command says it kept and
knows the resume box; the done text gives the command's own timing (the log's seconds).

A small script stands in for ``designer render --progress json``: the same events as the
command, including ``interrupted`` (the kept images' counts) and ``finished`` (the
labelled timings), and the same last line and exit code 130 on SIGINT.
"""

from __future__ import annotations

import sys
import textwrap

import pytest
from PySide6.QtCore import Qt

from designer.gui.qt.command_process import RenderProcess
from designer.render_time.timing import RenderTimes

pytestmark = pytest.mark.gui

FAKE = textwrap.dedent("""
    import json, signal, sys, time
    from pathlib import Path
    out, n, delay, resume = Path(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), \\
        sys.argv[4] == "1"
    (out / "images").mkdir(parents=True, exist_ok=True)
    done = []
    def stop(*_):
        # 2 images on disk from other inputs, the rest not rendered
        print(json.dumps({"event": "interrupted", "total": n, "up_to_date": len(done),
                          "rendered_now": len(done), "out_of_date": 2,
                          "not_rendered": n - len(done) - 2, "resume": resume}), flush=True)
        print("designer: interrupted by SIGINT", file=sys.stderr, flush=True)
        sys.exit(130)
    signal.signal(signal.SIGINT, stop)
    print(json.dumps({"event": "worker_started", "worker": 0, "pid": 1,
                      "frames": list(range(n))}), flush=True)
    for i in range(n):
        time.sleep(delay)
        path = out / "images" / f"IMG_{i + 1:05d}.png"
        path.write_bytes(b"")
        done.append(i)
        print(json.dumps({"event": "frame_done", "index": i, "path": str(path),
                          "seconds": 0.4}), flush=True)
    times = {"images": n, "command_wall_s": 18.04, "prepare_s": 7.9,
             "ground_truth_s": 0.3, "images_wall_s": 9.8, "cycles_s_per_image": 0.4}
    print(json.dumps({"event": "finished", **times}), flush=True)
    print(f"{out}: {n} images rendered, 0 already complete and up to date, in 18.0 s wall "
          "for the whole command (preparing the scene 7.9 s, ground truth 0.3 s, images "
          "9.8 s); Cycles 0.40 s per image; images in ...", flush=True)
""")


def _fake(monkeypatch, tmp_path, n: int, delay: float) -> None:
    script = tmp_path / "fake_render.py"
    script.write_text(FAKE)
    monkeypatch.setattr(RenderProcess, "command", staticmethod(
        lambda project, out_dir, resume=False, quality=None, workers=None:
        [sys.executable, str(script), str(out_dir), str(n), str(delay),
         "1" if resume else "0"]))


def test_cancel_with_resume_ticked_counts_the_images_and_does_not_ask_to_tick_it(
        qtbot, saved_project, monkeypatch, tmp_path):
    w = saved_project
    _fake(monkeypatch, tmp_path, n=40, delay=0.3)
    panel = w.panels["Render"]
    assert panel.resume.isChecked()
    qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: len(panel.frames_done) >= 1, timeout=20000)
    qtbot.mouseClick(panel.cancel_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=20000)
    text = panel.state.text()
    assert "tick" not in text and "with 'resume'" not in text, text
    n = len(panel.frames_done)
    assert f"{n} of 40 images up to date" in text, text
    assert "2 out of date" in text, text
    assert f"{40 - n - 2} not rendered" in text, text
    assert text.endswith("start the render again to render only the rest"), text


def test_cancel_with_resume_unticked_says_to_tick_it(qtbot, saved_project,
                                                     monkeypatch, tmp_path):
    w = saved_project
    _fake(monkeypatch, tmp_path, n=40, delay=0.3)
    panel = w.panels["Render"]
    qtbot.mouseClick(panel.resume, Qt.MouseButton.LeftButton)
    assert not panel.resume.isChecked()
    qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: len(panel.frames_done) >= 1, timeout=20000)
    qtbot.mouseClick(panel.cancel_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=20000)
    assert panel.state.text().endswith(
        "start the render with 'resume' ticked to render only the rest"), panel.state.text()


def test_done_text_gives_the_commands_timing_as_the_log_does(qtbot, saved_project,
                                                             monkeypatch, tmp_path):
    w = saved_project
    _fake(monkeypatch, tmp_path, n=3, delay=0.3)
    panel = w.panels["Render"]
    qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=20000)
    timing = RenderTimes(3, 18.04, 7.9, 0.3, 9.8, 0.4).text()
    log_lines = [line for line in panel.log.toPlainText().splitlines() if timing in line]
    assert log_lines, panel.log.toPlainText()
    text = panel.state.text()
    assert text.startswith(f"done: 3 images rendered {timing}"), text


FIRST_SLOW = textwrap.dedent("""
    import json, sys, time
    from pathlib import Path
    out = Path(sys.argv[1])
    (out / "images").mkdir(parents=True, exist_ok=True)
    print(json.dumps({"event": "worker_started", "worker": 0, "pid": 1,
                      "frames": [0, 1, 2]}), flush=True)
    for order, seconds in enumerate((6.0, 0.5, 0.7)):
        path = out / "images" / f"IMG_{order + 1:05d}.png"
        path.write_bytes(b"")
        print(json.dumps({"event": "frame_done", "index": order, "order": order,
                          "path": str(path), "seconds": seconds}), flush=True)
    time.sleep(3.0)  # the panel shows the count until the command ends
""")


def test_a_workers_first_image_is_labelled_and_left_out_of_the_speed(
        qtbot, saved_project, monkeypatch, tmp_path):
    """The first image of a worker also waits for Cycles to build the scene: its
    thumbnail says so and the measured speed is that of the images after it."""
    w = saved_project
    script = tmp_path / "first_slow.py"
    script.write_text(FIRST_SLOW)
    monkeypatch.setattr(RenderProcess, "command", staticmethod(
        lambda project, out_dir, resume=False, quality=None, workers=None:
        [sys.executable, str(script), str(out_dir)]))
    panel = w.panels["Render"]
    qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: len(panel.frames_done) == 3 and "measured" in panel.state.text(),
                    timeout=20000)
    assert "0.6 s per image measured after each worker's first" in panel.state.text(), (
        panel.state.text())
    captions = [panel.thumbs.item(k).text() for k in range(3)]
    assert captions[0].endswith("6.0 s with set-up"), captions
    assert captions[1].endswith("0.5 s") and captions[2].endswith("0.7 s"), captions
    assert "Cycles building the scene" in panel.thumbs.item(0).toolTip()
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=20000)
