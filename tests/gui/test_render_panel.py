"""Render panel: progress, thumbnails and cancel, reading ``designer render``'s JSON lines.

The first tests stand a small script in for ``designer render`` (same events, same exit
code 130 on SIGINT) so they need no Blender; the last renders for real with Cycles.
"""

from __future__ import annotations

import sys

import pytest
from PySide6.QtCore import Qt

from designer.gui.qt.command_process import RenderProcess
from designer.gui.state import edits
from designer.project import model as m
from tests.gui.helpers import problems, wait_idle
from tests.gui.render_helpers import FAKE_RENDER

pytestmark = pytest.mark.gui



def _fake(monkeypatch, tmp_path, n: int, delay: float) -> None:
    script = tmp_path / "fake_render.py"
    script.write_text(FAKE_RENDER)
    monkeypatch.setattr(RenderProcess, "command", staticmethod(
        lambda project, out_dir, resume=False, quality=None, workers=None:
        [sys.executable, str(script), str(out_dir), str(n), str(delay)]))


def test_progress_and_thumbnails(qtbot, saved_project, monkeypatch, tmp_path):
    w = saved_project
    _fake(monkeypatch, tmp_path, n=4, delay=0.05)
    panel = w.panels["Render"]
    panel.n_frames = 4
    qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    assert not panel.start_button.isEnabled() and panel.cancel_button.isEnabled()
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=20000)
    wait_idle(qtbot, w)
    assert panel.progress.value() == 4
    assert panel.thumbs.count() == 4
    assert all(not panel.thumbs.item(i).icon().isNull() for i in range(4))
    assert panel.state.text().startswith("done: 4 images")
    assert (tmp_path / "output" / "images" / "IMG_00004.png").is_file()


def test_cancel_stops_the_render_cleanly(qtbot, saved_project, monkeypatch, tmp_path):
    w = saved_project
    _fake(monkeypatch, tmp_path, n=50, delay=0.2)
    panel = w.panels["Render"]
    panel.start()
    qtbot.waitUntil(lambda: len(panel.frames_done) >= 2, timeout=20000)
    qtbot.mouseClick(panel.cancel_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=20000)
    assert 2 <= len(panel.frames_done) < 50
    assert panel.state.text().startswith("cancelled after")


def test_a_cancel_before_the_first_image_has_no_rest_to_render(qtbot, saved_project,
                                                             monkeypatch, tmp_path):
    w = saved_project
    _fake(monkeypatch, tmp_path, n=5, delay=30.0)  # the first image takes 30 s
    panel = w.panels["Render"]
    w.docks["Render"].raise_()
    qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: panel.cancel_button.isEnabled(), timeout=20000)
    qtbot.wait(1000)  # the worker has started
    qtbot.mouseClick(panel.cancel_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=20000)
    assert panel.frames_done == {}
    # no "render only the rest" when there is no rest: nothing was rendered
    assert panel.state.text() == ("cancelled before this run finished an image; start the "
                                  "render again")


def test_render_needs_a_valid_saved_project(qtbot, window, monkeypatch, tmp_path):
    w = window  # a blank project: no flight, so saving reports problems
    from PySide6.QtWidgets import QFileDialog

    monkeypatch.setattr(QFileDialog, "getSaveFileName",
                        staticmethod(lambda *a, **k: (str(tmp_path / "blank.xml"), "")))
    panel = w.panels["Render"]
    panel.start()
    assert not panel.process.running
    assert "save the project" in panel.state.text()
    assert not (tmp_path / "blank.xml").exists()
    assert w.docks["Problems"].isVisibleTo(w) and problems(w)


@pytest.mark.blender
@pytest.mark.slow
def test_real_render(qtbot, saved_project, tmp_path):
    pytest.importorskip("bpy")
    w = saved_project
    project = w.document.project
    w.editor.edit(edits.replace_path(project, "render", m.Render(
        preset="draft", resolution_scale=0.0625, workers=1)), "tiny draft")
    wait_idle(qtbot, w)
    n = w.sync.stations.n_images
    panel = w.panels["Render"]
    panel.start()
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=300000)
    wait_idle(qtbot, w)
    assert panel.state.text().startswith(f"done: {n} images"), panel.log.toPlainText()
    assert panel.thumbs.count() == n
    assert (tmp_path / "output" / "ground-truth" / "colmap" / "images.txt").is_file()


@pytest.mark.parametrize("stderr", ["designer: error: the scene cannot be built\n", ""])
def test_a_failed_render_says_why_in_words(qtbot, saved_project, monkeypatch, tmp_path,
                                           stderr):
    w = saved_project
    script = tmp_path / "failing_render.py"
    script.write_text(f"import sys\nsys.stderr.write({stderr!r})\nsys.exit(1)\n")
    monkeypatch.setattr(RenderProcess, "command", staticmethod(
        lambda project, out_dir, resume=False, quality=None, workers=None:
        [sys.executable, str(script)]))
    panel = w.panels["Render"]
    qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=20000)
    text = panel.state.text()
    assert text.startswith("render failed (exit 1)"), text
    assert "[" not in text and "'" not in text, text  # no Python list of lines
    if stderr:
        assert text.endswith(": designer: error: the scene cannot be built"), text
    else:
        assert "log" in text, text
