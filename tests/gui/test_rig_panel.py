"""The oblique rig in the GUI: added from the Flight panel, chosen as the flight's
camera, its mounts edited in the table through the undo stack, and every mount's frustum
drawn in the 3D view."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import Qt

from designer.survey.project_poses import project_images
from tests.gui.helpers import add_hills_and_flight, wait_idle

pytestmark = pytest.mark.gui


def test_rig_is_added_edited_and_every_mount_drawn(qtbot, window):
    w = window
    panel = w.panels["Flight"]
    w.docks["Flight"].raise_()
    add_hills_and_flight(w)
    wait_idle(qtbot, w)
    n_stations = w.sync.stations.n_images
    assert panel.add_rig.isVisible() and panel.mount_table.rowCount() == 0

    qtbot.mouseClick(panel.add_rig, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    project = w.document.project
    rig = project.trajectory.rigs[0]
    assert project.trajectory.flight_plan.camera == rig.name
    assert panel.camera.currentData() == rig.name  # the rig is the flight's camera
    assert panel.mount_table.rowCount() == 5 and not panel.add_rig.isVisible()

    # five images per station, and a frustum (apex + 4 corners) for each of them
    stations = w.sync.stations
    assert stations.n_images == 5 * n_stations
    assert panel.images_label.text() == str(5 * n_stations)
    assert w.view.layer_data("frusta").n_points == 5 * 5 * n_stations
    # the frusta are the mounted cameras': their axes agree with the images' rotations
    images = project_images(project, w.sync.terrain.heightfield)
    apex = stations.geometry.frustum_points.reshape(-1, 5, 3)
    axis = apex[:, 1:].mean(axis=1) - apex[:, 0]
    axis /= np.linalg.norm(axis, axis=1)[:, None]
    by_camera = [s.R_cam_to_world[:, 2] for s in images.stations]  # one camera here
    assert np.allclose(axis, -np.array(by_camera), atol=1e-9)
    tilts = np.degrees(np.arccos(np.clip(-axis[:, 2], -1, 1)))
    assert (np.sum(np.isclose(tilts, 45.0, atol=0.5)) == 4 * n_stations)

    # a mount's angle typed in the table is one undoable edit
    row = next(r for r in range(5) if panel.mount_table.item(r, 2).text() == "_L")
    panel.mount_table.item(row, 4).setText("30")
    wait_idle(qtbot, w)
    mount = w.document.project.trajectory.rigs[0].mounts[row]
    assert (mount.suffix, mount.phi_deg) == ("_L", 30.0)
    panel.mount_table.item(row, 4).setText("not a number")  # put back, nothing changes
    wait_idle(qtbot, w)
    assert panel.mount_table.item(row, 4).text() == "30"
    w.undo_stack.undo()
    wait_idle(qtbot, w)
    assert w.document.project.trajectory.rigs[0].mounts[row].phi_deg == 45.0
    assert panel.mount_table.item(row, 4).text() == "45"
    w.undo_stack.undo()  # the rig is gone again
    wait_idle(qtbot, w)
    assert w.document.project.trajectory.rigs == ()
    assert w.view.layer_data("frusta").n_points == 5 * n_stations
