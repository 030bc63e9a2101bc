"""The window finds the demo's renders: ``designer demo -o DIR`` renders into DIR/survey,
and the project it writes (DIR/survey.xml) says so, so opening it shows its images in the
Results panel, not "DIR/output: not rendered yet" (issue 53, finding 7)."""

from __future__ import annotations

import json

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


def test_the_demo_project_opens_with_its_reconstruction_shown(qtbot, window, tmp_path):
    """``designer demo`` reconstructs into DIR/reconstruction and compares into
    DIR/accuracy, beside DIR/survey: the Results panel finds that reconstruction as it
    finds its own (SURVEY/reconstruction-MODE), not "no reconstruction in …"."""
    import numpy as np

    from designer.demo import ACCURACY_DIR, RECONSTRUCTION_DIR
    from designer.evaluate.writers import write_distances_ply

    w = window
    demo = tmp_path / "demo-output"
    path = write_demo_project(demo)
    _fake_render(demo / SURVEY_DIR)
    (demo / RECONSTRUCTION_DIR).mkdir()
    # the settings the demo reconstructs with, as reconstruct records them
    from designer.demo import demo_processing
    from designer.project import load_project
    from designer.sfm.settings import settings_dict

    settings = settings_dict(demo_processing(load_project(path)))
    (demo / RECONSTRUCTION_DIR / "summary.json").write_text(
        json.dumps({"settings": settings}, default=str))
    (demo / ACCURACY_DIR).mkdir()
    distances = demo / ACCURACY_DIR / "distances.ply"
    xyz = np.column_stack([np.arange(30.0), np.zeros(30), np.full(30, 100.0)])
    write_distances_ply(distances, xyz, np.linspace(-0.01, 0.02, 30))
    assert w.file_actions.open(path), problems(w)
    wait_idle(qtbot, w)
    results = open_panel(w, "Results")
    wait_idle(qtbot, w)
    r = results.result
    assert r is not None, results.state.text()
    assert r.path == distances and len(r.points_world) == 30
    assert "no reconstruction" not in results.state.text(), results.state.text()
    assert w.view.has_layer("cloud")
    # the poses the demo reconstructs with: free SfM; with the project's settings
    assert results.mode.currentData() == "free"
    assert not results.out_of_date.stale, results.out_of_date.text()
    from designer.gui.state.output_state import processing_changes

    assert processing_changes(demo / RECONSTRUCTION_DIR, w.document.project.processing) == []
