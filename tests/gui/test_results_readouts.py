"""The Results panel and the status bar agree: the poses selector shows the poses of the
reconstruction shown when a project is reopened, and a point picked in a cloud is read
the same, the same point, in the panel and in the status bar's cursor readout."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import Qt

from designer.evaluate.writers import write_distances_ply
from designer.gui.state.reconstruct_job import ReconstructJob
from designer.gui.state.wording import point_text
from tests.gui.cloud_helpers import cloud_seen_from_above, isolated_point, point_on_screen
from tests.gui.helpers import (
    add_hills_and_flight,
    cloud_with_outlier,
    open_panel,
    open_with_ctrl_o,
    problems,
    wait_idle,
)

pytestmark = pytest.mark.gui


def _distances_on_the_ground(job: ReconstructJob, hf) -> None:
    """The job's comparison: 40 points along the X axis, 2 cm above the terrain."""
    x = np.arange(-20.0, 20.0)
    xyz = np.column_stack([x, np.zeros(40), hf.height_at(x, np.zeros(40)) + 0.02])
    job.compare_dir.mkdir(parents=True)
    write_distances_ply(job.distances_ply, xyz, np.full(40, 0.02))


def test_a_reopened_free_sfm_reconstruction_shows_free_sfm_poses(qtbot, window, tmp_path):
    w = window
    add_hills_and_flight(w)
    wait_idle(qtbot, w)
    project_path = tmp_path / "hills.xml"
    assert w.file_actions.save_to(project_path), problems(w)
    results = open_panel(w, "Results")
    assert results.mode.currentData() == "known-poses"  # the default
    job = ReconstructJob(project_path, results.survey_dir(), "free")
    _distances_on_the_ground(job, w.sync.terrain.heightfield)
    assert w.file_actions.new(None)
    wait_idle(qtbot, w)

    open_with_ctrl_o(qtbot, w, project_path)
    assert w.document.path == project_path
    assert results.result is not None and results.result.path == job.distances_ply
    assert results.mode.currentData() == "free", results.mode.currentText()
    assert results.mode.currentText().startswith("free SfM")


def test_a_picked_point_reads_the_same_in_the_panel_and_the_status_bar(qtbot, window,
                                                                       tmp_path):
    w = window
    add_hills_and_flight(w)
    wait_idle(qtbot, w)
    results = open_panel(w, "Results")
    path, _xyz = cloud_with_outlier(w, tmp_path, n=400)
    results.open_cloud(path)
    wait_idle(qtbot, w)
    cloud_seen_from_above(w)
    r = results.result
    k = isolated_point(w, r.points_world)
    pos = point_on_screen(w, r.points_world[k])
    # the cursor moved onto the point, then a click on it
    qtbot.mouseMove(w.view.plotter, pos)
    qtbot.mouseClick(w.view.plotter, Qt.MouseButton.LeftButton, pos=pos)
    picked = results.picked.text()
    said = point_text(r.points_world[k])
    assert said in picked, (said, picked)
    qtbot.waitUntil(lambda: w.coords.text() == f"{said} (world)", timeout=3000)
    assert said in w.statusBar().currentMessage()


def test_the_colour_range_without_distances_says_where_it_comes_from(qtbot, window,
                                                                    tmp_path):
    """No reconstruction: the greyed colour range says the distances set it, not the
    field's minimum of 0.1 mm (the walk of 12-06); a result then gives its own range."""
    w = window
    add_hills_and_flight(w)
    wait_idle(qtbot, w)
    results = open_panel(w, "Results")
    assert not results.range_spin.isEnabled()
    assert results.range_spin.text() == "set by the distances"
    project_path = tmp_path / "hills.xml"
    assert w.file_actions.save_to(project_path), problems(w)
    job = ReconstructJob(project_path, results.survey_dir(), "known-poses")
    _distances_on_the_ground(job, w.sync.terrain.heightfield)
    open_with_ctrl_o(qtbot, w, project_path)
    qtbot.waitUntil(lambda: results.range_spin.isEnabled(), timeout=60_000)
    assert results.range_spin.text().endswith("mm")
    assert results.range_spin.value() > 0
