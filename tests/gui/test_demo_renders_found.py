"""The window finds the demo's renders: ``designer demo -o DIR`` renders into DIR/survey,
and the project it writes (DIR/survey.xml) says so, so opening it shows its images in the
Results panel, not "DIR/output: not rendered yet" (issue 53, finding 7)."""

from __future__ import annotations

import pytest

from designer.demo import SURVEY_DIR, write_demo_project
from tests.gui.helpers import open_panel, problems, wait_idle

pytestmark = pytest.mark.gui

NAMES = ("DJI_00001.png", "DJI_00002.png", "DJI_00003.png")


def _fake_render(survey):
    """A render folder as ``designer render`` leaves it, as far as the Results panel reads
    it: the COLMAP ground truth naming three images, and the images."""
    colmap = survey / "ground-truth" / "colmap"
    colmap.mkdir(parents=True)
    (colmap / "cameras.txt").write_text("1 PINHOLE 100 80 100 100 50 40\n")
    (colmap / "images.txt").write_text("".join(
        f"{k} 1 0 0 0 0 0 0 1 {name}\n\n" for k, name in enumerate(NAMES, 1)))
    (survey / "images").mkdir()
    for name in NAMES:
        (survey / "images" / name).write_bytes(b"")


def test_the_demo_project_opens_with_its_renders_found(qtbot, window, tmp_path):
    w = window
    demo = tmp_path / "demo-output"
    path = write_demo_project(demo)
    assert path == demo / "survey.xml"
    _fake_render(demo / SURVEY_DIR)
    assert w.file_actions.open(path), problems(w)
    wait_idle(qtbot, w)
    results = open_panel(w, "Results")
    wait_idle(qtbot, w)
    text = results.survey_label.text()
    assert "not rendered yet" not in text, text
    assert text == f"{(demo / SURVEY_DIR).resolve()}: 3 rendered images with their ground truth"
