"""Render provenance in the window, with Blender for real: a tiny survey (96 × 72 px
images) is rendered, the terrain is changed in the window, Render and Results say "out
of date" with the reason, Render re-renders what changed, and all is up to date again."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox

from designer.evaluate.writers import write_distances_ply
from designer.gui import edits, output_state
from designer.gui.reconstruct_job import ReconstructJob
from designer.project import model as m
from tests.gui.helpers import field, problems, set_field, wait_idle

pytestmark = [pytest.mark.gui, pytest.mark.blender, pytest.mark.slow]


def _wait_state(qtbot, w, predicate, timeout_ms: int = 120000) -> None:
    qtbot.waitUntil(lambda: not w.stale_watch.pending and not w.tasks.busy
                    and predicate(), timeout=timeout_ms)


def test_terrain_edit_marks_render_and_results_out_of_date(qtbot, window, tmp_path):
    pytest.importorskip("bpy")
    w = window
    project = w.document.project
    camera = m.Camera("cam96", 8.8, 13.2, 9.9, 960, 720)
    project = edits.set_camera(project, camera)
    project = edits.set_flight(project, area=((-10.0, -10.0), (10.0, -10.0), (10.0, 10.0),
                                              (-10.0, 10.0)), altitude_agl_m=40.0,
                               front_overlap_percent=60.0, side_overlap_percent=50.0)
    project = edits.replace_path(project, "render", m.Render(
        preset="draft", resolution_scale=0.1, workers=1))
    w.editor.edit(project, "a tiny survey")
    wait_idle(qtbot, w)
    path = tmp_path / "tiny.xml"
    assert w.file_actions.save_to(path), problems(w)
    n = w.sync.stations.n_images
    assert 2 <= n <= 8
    render, results = w.panels["Render"], w.panels["Results"]
    assert not render.out_of_date.isVisible() or not render.out_of_date.stale

    qtbot.mouseClick(render.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: render.start_button.isEnabled(), timeout=600000)
    assert render.state.text().startswith(f"done: {n} images"), render.log.toPlainText()
    _wait_state(qtbot, w, lambda: render.out_of_date.text().startswith(f"the {n} rendered"))
    assert not render.out_of_date.stale and render.start_button.text() == "Render"

    # a reconstruction of these images, recorded with the digests it was made from
    survey = render.out_dir
    job = ReconstructJob(path, survey)
    job.compare_dir.mkdir(parents=True)
    write_distances_ply(job.distances_ply, [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]], [0.01, 0.02])
    output_state.record_reconstruction_inputs(survey, job.out_dir,
                                              output_state.manifest_digests(survey))
    assert w.open_project(path)
    wait_idle(qtbot, w)
    _wait_state(qtbot, w, lambda: results.out_of_date.text().startswith("reconstructed"))
    assert not results.out_of_date.stale

    # the terrain changes in the window: every image is out of date, for the scene and
    # (flown at a height above the ground) for its pose
    set_field(qtbot, field(w, QDoubleSpinBox, "scene.terrain.source.height_m"), "1.5")
    assert w.document.project.scene.terrain.source.height_m == 1.5
    _wait_state(qtbot, w, lambda: render.out_of_date.stale)
    text = render.out_of_date.text()
    assert text == (f"out of date: {n} images out of date: the scene (terrain, texture, "
                    "lighting, buildings or plants), the pose; ground truth out of date "
                    "(the project changed since it was written)"), text
    assert render.start_button.text() == f"Re-render {n} changed images"
    assert results.out_of_date.stale
    assert "the rendered images no longer match the project (" in results.out_of_date.text()
    # undone, the images are the project's again
    w.undo_stack.undo()
    _wait_state(qtbot, w, lambda: not render.out_of_date.stale)
    w.undo_stack.redo()
    _wait_state(qtbot, w, lambda: render.out_of_date.stale)

    # re-render what changed (saves first): up to date again
    qtbot.mouseClick(render.start_button, Qt.MouseButton.LeftButton)
    qtbot.waitUntil(lambda: render.start_button.isEnabled(), timeout=600000)
    assert not w.document.dirty
    assert render.state.text().startswith(f"done: {n} images"), render.log.toPlainText()
    _wait_state(qtbot, w, lambda: render.out_of_date.text().startswith(f"the {n} rendered"))
    assert not render.out_of_date.stale and render.start_button.text() == "Render"
    # the reconstruction was made from the images before: out of date until redone
    assert results.out_of_date.text() == (
        f"out of date: {n} images rendered anew since this reconstruction: reconstruct again")
