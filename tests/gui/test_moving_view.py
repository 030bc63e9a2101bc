"""Moving objects in the 3D view (issue 53, finding 11): the example's car and person
(survey-dynamic template) are drawn where the render poses them — at the take-off on
their paths' first points, on the ground — with their paths, and move along their paths
when a later photo is selected."""

from __future__ import annotations

import numpy as np
import pytest

from designer.gui.state.moving_view import moving_display
from designer.project import template, write_project
from designer.scene.moving import path_xy_heading
from tests.gui.helpers import problems, wait_idle


def test_moving_display_poses_each_object_on_the_ground():
    from designer.core.heightfield import Heightfield

    project = template("survey-dynamic").project
    car, _walker = project.scene.moving_objects
    E0, N0 = project.origin.E0, project.origin.N0
    x = np.linspace(E0 - 60, E0 + 60, 61)
    y = np.linspace(N0 - 60, N0 + 60, 61)
    hf = Heightfield(x[0], y[0], 2.0, 2.0,
                     np.add.outer(0.05 * (y - N0), 0.02 * (x - E0)) + 100.0)
    shown = moving_display(project, hf, ".", 10.0)
    assert shown.ids == ("car1", "walker1")
    assert np.all(shown.faces < len(shown.vertices_world))
    # the car 20 m along its path after 10 s at 2 m/s, its base on the ground there
    cx, cy, _ = path_xy_heading(car, 10.0)
    near = np.hypot(shown.vertices_world[:, 0] - cx, shown.vertices_world[:, 1] - cy) < 3.0
    assert near.any()
    assert shown.vertices_world[near, 2].min() == pytest.approx(
        float(hf.height_at_clamped(np.array([cx]), np.array([cy]))[0]), abs=0.05)
    assert len(shown.path_points) > 4 and len(shown.path_lines)
    assert moving_display(template("survey").project, hf, ".", 0.0) is None


@pytest.mark.gui
def test_the_window_draws_the_moving_objects_and_moves_them_with_the_photo(
        qtbot, window, tmp_path):
    w = window
    path = tmp_path / "dynamic.xml"
    write_project(template("survey-dynamic").project, path)
    assert w.file_actions.open(path), problems(w)
    wait_idle(qtbot, w)
    assert w.view.has_layer("movers") and w.view.has_layer("movers:paths")
    car = w.document.project.scene.moving_objects[0]
    first = np.asarray(w.view.layer_data("movers").points).copy()
    start = np.array([car.path[0].X, car.path[0].Y]) - w.view.offset[:2]
    assert np.hypot(*(first[:, :2] - start).T).min() < 3.0  # at the take-off: its start
    w.sync.select_photo(len(w.sync.stations.stations) - 1)  # the last photo: later on
    wait_idle(qtbot, w)
    moved = np.asarray(w.view.layer_data("movers").points)
    assert not np.allclose(moved, first)
