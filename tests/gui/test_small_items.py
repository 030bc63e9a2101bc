"""The smaller findings of the user test: the camera id follows the preset, defocus
focuses on the flown ground, one shutter for sensor and motion blur, readable colour
bars, GCP errors drawn in 3D, the view re-frames when the cameras leave it."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtWidgets import QDoubleSpinBox

from designer.gui.state import edits
from tests.gui.helpers import add_hills_and_flight, field, set_field, wait_idle, write_xyz_ply

pytestmark = pytest.mark.gui


def test_camera_id_follows_the_preset(qtbot, window):
    w = window
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "flight")
    wait_idle(qtbot, w)
    assert w.document.project.cameras[0].id == "p4p"
    camera = w.panels["Camera"]
    camera.preset.setCurrentIndex(camera.preset.findData("a6000"))
    p = w.document.project
    assert p.cameras[0].id == "a6000"
    assert p.trajectory.flight_plan.camera == "a6000"
    # a user's own id stays
    w.editor.edit(edits.set_camera(p, p.cameras[0].__class__(
        **{**p.cameras[0].__dict__, "id": "my-cam"})), "rename")
    camera.preset.setCurrentIndex(camera.preset.findData("p4p"))
    assert w.document.project.cameras[0].id == "my-cam"


def test_defocus_focuses_on_the_ground_and_one_shutter(qtbot, window):
    w = window
    w.editor.edit(edits.set_flight(edits.ensure_flight_plan(w.document.project),
                                   altitude_agl_m=80.0), "flight at 80 m")
    wait_idle(qtbot, w)
    effects = w.panels["Effects"]
    effects.groups["defocus"].setChecked(True)
    assert w.document.project.effects.defocus.focus_distance_m == 80.0
    effects.groups["sensor"].setChecked(True)
    effects.groups["motion_blur"].setChecked(True)
    e = w.document.project.effects
    assert e.motion_blur.exposure_time_s == e.sensor.exposure_time_s
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)
    set_field(qtbot, field(w, QDoubleSpinBox, "motion blur exposure time (shutter)"), "0.002")
    e = w.document.project.effects
    assert e.motion_blur.exposure_time_s == e.sensor.exposure_time_s == 0.002
    sensor_box = field(w, QDoubleSpinBox,
                       "sensor (photon shot noise, dark current, read noise, ADC) "
                       "exposure time (shutter)")
    assert sensor_box.value() == 0.002


def test_colour_bar_readable_and_gcp_errors_in_3d(qtbot, window, tmp_path):
    w = window
    add_hills_and_flight(w)
    project = edits.add_target(edits.add_target(w.document.project, 10.0, 5.0), -20.0, 15.0)
    w.editor.edit(project, "two GCPs")
    wait_idle(qtbot, w)
    hf = w.sync.terrain.heightfield
    x = np.linspace(-30, 30, 200)
    write_xyz_ply(tmp_path / "cloud.ply", np.column_stack([x, x, hf.height_at(x, x) + 0.01]))
    results = w.panels["Results"]
    results.open_cloud(tmp_path / "cloud.ply")
    wait_idle(qtbot, w)
    bar = w.view.plotter.scalar_bars["signed distance (mm)"]
    assert min(bar.GetTitleTextProperty().GetColor()) > 0.9   # light on the dark sky
    assert min(bar.GetLabelTextProperty().GetColor()) > 0.9

    truth = w.sync.targets.true_xyz
    csv = tmp_path / "gcp_residuals.csv"
    csv.write_text("id,role,X,Y,Z\n"
                   f"GCP01,control,{truth[0, 0] + 0.01},{truth[0, 1]},{truth[0, 2]}\n"
                   f"GCP02,control,{truth[1, 0]},{truth[1, 1]},{truth[1, 2] + 0.03}\n")
    results.open_residuals(csv)
    wait_idle(qtbot, w)
    lines = w.view.layer_data("residuals")
    pts = np.asarray(lines.points, dtype=float) + w.view.offset
    start, end = pts[:2], pts[2:]
    np.testing.assert_allclose(start, truth, atol=1e-3)
    scale = float(w.view.residual_title.split("×")[1])
    assert scale >= 10
    np.testing.assert_allclose(end - start, scale * np.array([[0.01, 0, 0], [0, 0, 0.03]]),
                               atol=1e-3)
    assert f"× {scale:g}" in results.rmse.text()


def test_view_reframes_when_the_cameras_leave_it(qtbot, window):
    w = window
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "flight")
    wait_idle(qtbot, w)
    w.view.reset_view()
    w.view.render_now()
    w.editor.edit(edits.set_flight(w.document.project, altitude_agl_m=3000.0), "very high")
    wait_idle(qtbot, w)
    C = w.sync.stations.C_world
    assert C[:, 2].min() > 2900
    assert w.view.in_view(C).all()
    # and "Frame all" shows cameras, terrain and GCPs after the view was turned away
    w.view.plotter.camera.azimuth = 180
    w.view.plotter.camera.elevation = -80
    w.frame_all()
    assert w.view.in_view(C).all()
