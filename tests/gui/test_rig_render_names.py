"""A rig survey rendered from the Render panel: each thumbnail carries the name of the
image it shows (a rig station gives one image per camera, so the frames are not the
stations), never a station's name or a bare frame number."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from PySide6.QtCore import Qt

from designer.gui.qt.command_process import RenderProcess
from designer.survey.project_poses import project_images
from tests.gui.helpers import problems, wait_idle
from tests.gui.render_helpers import FAKE_RENDER

pytestmark = pytest.mark.gui


def test_rig_frames_are_named_as_their_images(qtbot, window, monkeypatch, tmp_path):
    w = window
    assert w.file_actions.new("survey-structures")  # a five-camera rig and an orbit
    wait_idle(qtbot, w)
    assert w.file_actions.save_to(tmp_path / "rig.xml"), problems(w)
    names = [Path(s.image_name).stem for s in project_images(
        w.document.project, w.sync.terrain.heightfield).stations]
    n = len(names)
    assert n > len(w.sync.stations.stations)
    script = tmp_path / "fake_render.py"
    script.write_text(FAKE_RENDER)
    monkeypatch.setattr(RenderProcess, "command", staticmethod(
        lambda project, out_dir, resume=False, quality=None, workers=None:
        [sys.executable, str(script), str(out_dir), str(n), "0"]))

    panel = w.panels["Render"]
    w.docks["Render"].raise_()
    qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: panel.start_button.isEnabled(), timeout=60000)
    assert panel.thumbs.count() == n
    labels = [panel.thumbs.item(i).text().split("\n")[0] for i in range(n)]
    assert labels == names
