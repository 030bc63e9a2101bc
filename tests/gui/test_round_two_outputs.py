"""Round two, with Blender for real: the Render and Results panels' out-of-date lines
read as sentences, follow every change that matters (processing too), and are right
the moment a render finishes. Tiny surveys (96 × 72 px images, draft)."""

from __future__ import annotations

import dataclasses
import json

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox

from designer.evaluate.writers import write_distances_ply
from designer.gui import edits, output_state
from designer.gui.reconstruct_job import ReconstructJob
from designer.project import model as m
from designer.sfm.settings import settings_dict
from tests.gui.helpers import field, problems, set_field, wait_idle

pytestmark = [pytest.mark.gui, pytest.mark.blender, pytest.mark.slow]


def _wait_state(qtbot, w, predicate, timeout_ms: int = 120000) -> None:
    qtbot.waitUntil(lambda: not w.stale_watch.pending and not w.tasks.busy
                    and predicate(), timeout=timeout_ms)


def _tiny_survey(qtbot, w, tmp_path, gcps: bool = True):
    """A tiny survey (2–8 images of 96 × 72 px, two GCPs) saved, rendered and
    "reconstructed" (the record designer reconstruct leaves: the digests of the images
    and summary.json with the processing settings); reopened. Returns the project path
    and the number of images."""
    pytest.importorskip("bpy")
    project = w.document.project
    project = edits.set_camera(project, m.Camera("cam96", 8.8, 13.2, 9.9, 960, 720))
    project = edits.set_flight(project, area=((-10.0, -10.0), (10.0, -10.0), (10.0, 10.0),
                                              (-10.0, 10.0)), altitude_agl_m=40.0,
                               front_overlap_percent=60.0, side_overlap_percent=50.0)
    project = edits.replace_path(project, "render", m.Render(
        preset="draft", resolution_scale=0.1, workers=1))
    if gcps:
        project = edits.add_target(edits.add_target(project, -3.0, 0.0), 3.0, 0.0)
    w.editor.edit(project, "a tiny survey")
    wait_idle(qtbot, w)
    path = tmp_path / "tiny.xml"
    assert w.file_actions.save_to(path), problems(w)
    n = w.sync.stations.n_images
    assert 2 <= n <= 8
    render = w.panels["Render"]
    qtbot.mouseClick(render.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: render.start_button.isEnabled(), timeout=600000)
    assert render.state.text().startswith(f"done: {n} images"), render.log.toPlainText()

    survey = render.out_dir
    job = ReconstructJob(path, survey)
    job.compare_dir.mkdir(parents=True)
    write_distances_ply(job.distances_ply, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], [0.01, 0.02])
    processing = w.document.project.processing or m.Processing()
    (job.out_dir / "summary.json").write_text(json.dumps(
        {"mode": job.mode, "settings": settings_dict(processing)}))
    output_state.record_reconstruction_inputs(survey, job.out_dir,
                                              output_state.manifest_digests(survey))
    assert w.open_project(path)
    wait_idle(qtbot, w)
    results = w.panels["Results"]
    _wait_state(qtbot, w, lambda: results.out_of_date.text().startswith("reconstructed"))
    return path, n


def test_results_say_in_a_sentence_why_the_images_are_out_of_date(qtbot, window, tmp_path):
    w = window
    _path, n = _tiny_survey(qtbot, w, tmp_path)
    results = w.panels["Results"]

    set_field(qtbot, field(w, QDoubleSpinBox, "scene.terrain.source.height_m"), "1.5")
    _wait_state(qtbot, w, lambda: results.out_of_date.stale)
    text = results.out_of_date.text()
    assert text.startswith(f"out of date: the rendered images no longer match the project "
                           f"({n} images out of date: the scene"), text
    assert text.endswith("; render, then reconstruct again"), text
    assert "are (" not in text
    w.undo_stack.undo()
    _wait_state(qtbot, w, lambda: not results.out_of_date.stale)

    # a project the render cannot be compared with (two GCPs of one id, as a hand-edited
    # file may have): said as such, not as a broken sentence
    targets = w.document.project.targets
    w.editor.edit(edits.set_targets(w.document.project, (
        targets[0], dataclasses.replace(targets[1], id=targets[0].id))), "same ids")
    _wait_state(qtbot, w, lambda: results.out_of_date.stale)
    text = results.out_of_date.text()
    assert text.startswith("out of date: the rendered images cannot be compared with the "
                           "project ("), text
    assert "are (" not in text and "cannot compare" not in text


def test_a_processing_change_marks_the_reconstruction_out_of_date(qtbot, window, tmp_path):
    from PySide6.QtWidgets import QComboBox

    w = window
    _tiny_survey(qtbot, w, tmp_path)
    results = w.panels["Results"]
    processing = w.panels["Processing"]
    w.docks["Processing"].raise_()
    # the project's own settings, the defaults the reconstruction used: still up to date
    qtbot.mouseClick(processing.enabled, Qt.MouseButton.LeftButton)
    assert w.document.project.processing is not None
    _wait_state(qtbot, w, lambda: True)
    assert not results.out_of_date.stale, results.out_of_date.text()

    mode = field(processing, QComboBox, "processing.gcps.mode")
    mode.setCurrentIndex(mode.findData("bundle"))
    assert w.document.project.processing.gcps.mode == "bundle"
    _wait_state(qtbot, w, lambda: results.out_of_date.stale)
    assert results.out_of_date.text() == (
        "out of date: the processing settings changed since this reconstruction (GCPs): "
        "reconstruct again")
    # back to the settings it was made with: up to date again
    mode.setCurrentIndex(mode.findData("similarity"))
    _wait_state(qtbot, w, lambda: not results.out_of_date.stale)
    assert results.out_of_date.text().startswith("reconstructed from")


def test_a_finished_resume_is_not_shown_out_of_date(qtbot, window, tmp_path):
    from designer.core.layout import images_dir

    w = window
    _path, n = _tiny_survey(qtbot, w, tmp_path, gcps=False)
    render = w.panels["Render"]
    w.docks["Render"].raise_()
    _wait_state(qtbot, w, lambda: render.out_of_date.text().startswith(f"the {n} rendered"))
    first = sorted(images_dir(render.out_dir).glob("IMG_*"))[0]
    first.unlink()  # one image lost: the folder is out of date
    w.stale_watch.check_now()
    _wait_state(qtbot, w, lambda: render.out_of_date.stale)
    assert render.out_of_date.text() == "out of date: 1 image not rendered"
    assert render.start_button.text() == "Re-render 1 changed image"

    seen = []  # what the panel says the moment the render is done (at 100 %)
    render.process.finished.connect(lambda *_: seen.append(
        (render.progress.value(), render.out_of_date.isVisible(), render.out_of_date.stale,
         render.out_of_date.text())))
    qtbot.mouseClick(render.start_button, Qt.MouseButton.LeftButton)
    assert not render.out_of_date.stale  # the render is changing the folder right now
    qtbot.waitUntil(lambda: render.start_button.isEnabled(), timeout=600000)
    assert first.is_file()
    (value, _visible, stale, text), = seen
    assert value == n and not stale and "not rendered" not in text, text
    _wait_state(qtbot, w, lambda: render.out_of_date.text().startswith(f"the {n} rendered"))
    assert not render.out_of_date.stale and render.start_button.text() == "Render"
