"""The scripted walkthrough: a survey designed from scratch with the mouse and the panels.

New project → generate terrain → place 5 GCPs by clicking in the 3D view → choose a
camera preset → set up a flight → check the image count against ``designer plan`` →
save → reopen → the XML validates. Then undo/redo over the same session.
"""

from __future__ import annotations

import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtWidgets import QDoubleSpinBox

from designer.checks.plan_report import plan_project, plan_summary
from designer.project import load_project
from designer.project import model as m
from tests.gui.helpers import design_example, field, ground_pixels, problems, wait_idle

pytestmark = pytest.mark.gui


def test_design_save_reopen(qtbot, window, tmp_path):
    w = window
    design_example(qtbot, w)
    project = w.document.project

    # The image count shown is designer plan's.
    expected = plan_summary(plan_project(project, w.document.base_dir))["n_images"]
    assert w.sync.stations.n_images == expected
    assert w.panels["Flight"].images_label.text() == str(expected)
    assert w.view.layer_data("frusta").n_points == 5 * expected
    # flown by height: the (read-only) GSD field shows the GSD that height gives
    gsd_field = w.panels["Flight"].gsd_spin
    assert not gsd_field.isEnabled()
    assert gsd_field.value() == pytest.approx(100 * w.sync.stations.calc.gsd_m, abs=1e-3)

    # Save, then reopen: the file validates and holds what was designed.
    path = tmp_path / "walkthrough.xml"
    assert w.file_actions.save_to(path), problems(w)
    assert not w.document.dirty
    assert w.windowTitle().startswith("walkthrough.xml")
    loaded = load_project(path)  # XSD + semantic checks
    assert loaded == project
    assert w.file_actions.recent()[0] == str(path.resolve())

    assert w.file_actions.new(None)
    assert w.file_actions.open(path)
    wait_idle(qtbot, w)
    assert w.document.project == project
    assert w.document.path == path
    assert not w.document.dirty
    assert w.sync.stations.n_images == expected
    assert len(w.sync.targets.ids) == 5


def test_undo_redo_every_edit(qtbot, window):
    w = window
    design_example(qtbot, w)
    doc, stack = w.document, w.undo_stack
    designed = doc.project
    steps = stack.count()
    # new blank is the clean start; every edit after it is on the stack
    assert steps >= 12

    stack.undo()  # side overlap back to 70 %
    assert doc.project.trajectory.flight_plan.side_overlap_percent == 70.0
    stack.undo()
    stack.undo()
    stack.undo()  # the flight plan is gone
    assert doc.project.trajectory.flight_plan is None
    wait_idle(qtbot, w)
    assert w.sync.stations is None
    assert w.panels["Flight"].create.isVisible()
    stack.undo()  # camera back to the Phantom 4 Pro
    assert doc.project.cameras[0].focal_length_mm == 8.8
    stack.undo()
    stack.undo()  # two GCPs fewer
    assert len(doc.project.targets) == 3
    wait_idle(qtbot, w)
    assert w.panels["GCPs"].table.rowCount() == 3
    assert w.view.layer_data("targets").n_points == 3

    while stack.canRedo():
        stack.redo()
    wait_idle(qtbot, w)
    assert doc.project == designed
    while stack.canUndo():
        stack.undo()
    assert doc.project.scene.terrain.kind == "flat"
    assert doc.project.targets == ()


def test_spin_box_steps_merge_into_one_undo_step(qtbot, window):
    w = window
    w.editor.edit(w.document.replace_part(trajectory=m.Trajectory(flight_plan=m.FlightPlan(
        camera=w.document.project.cameras[0].id, image_prefix="IMG_",
        area=((-40.0, -40.0), (40.0, -40.0), (40.0, 40.0), (-40.0, 40.0)),
        altitude_agl_m=50.0))), "flight")
    box = field(w, QDoubleSpinBox, "trajectory.flight_plan.altitude_agl_m")
    before = w.undo_stack.count()
    for _ in range(5):
        box.stepUp()
    assert w.document.project.trajectory.flight_plan.altitude_agl_m == 75.0  # 5 × 5 m
    assert w.undo_stack.count() == before + 1
    w.undo_stack.undo()
    assert w.document.project.trajectory.flight_plan.altitude_agl_m == 50.0
    assert box.value() == 50.0  # the field follows the model


def test_drag_moves_a_gcp_and_delete_removes_it(qtbot, window):
    w = window
    design_example(qtbot, w, n_gcps=2)
    w.view.interaction.set_mode("place")
    moved = w.document.project.targets[0]
    xyz = w.sync.targets.true_xyz[0]
    ren = w.view.plotter.renderer
    ren.SetWorldPoint(*(xyz - w.view.offset), 1.0)
    ren.WorldToDisplay()
    xd, yd, _ = ren.GetDisplayPoint()
    h = w.view.plotter.height()
    start = QPoint(round(xd), round(h - 1 - yd))
    end = start + QPoint(60, 25)
    target_ground = w.view.interaction.ground_at(end.x(), end.y())
    qtbot.mousePress(w.view.plotter, Qt.MouseButton.LeftButton, pos=start)
    qtbot.mouseMove(w.view.plotter, pos=start + QPoint(30, 12))
    qtbot.mouseMove(w.view.plotter, pos=end)
    qtbot.mouseRelease(w.view.plotter, Qt.MouseButton.LeftButton, pos=end)
    after = w.document.project.targets[0]
    assert after.id == moved.id
    assert (after.true.X, after.true.Y) == pytest.approx(tuple(target_ground[:2]), abs=0.6e-4)
    assert len(w.document.project.targets) == 2  # moved, not added
    w.undo_stack.undo()
    assert w.document.project.targets[0] == moved

    gcps = w.panels["GCPs"]
    gcps.table.selectRow(1)
    gcps.delete_selected()
    assert [t.id for t in w.document.project.targets] == ["GCP01"]


def test_status_bar_shows_world_coordinates_under_the_cursor(qtbot, window):
    w = window
    assert w.file_actions.new("survey")  # UTM-sized coordinates (E 512 km, N 5406 km)
    wait_idle(qtbot, w)
    (x, y, ground), = ground_pixels(w, 1)
    from PySide6.QtCore import QEvent, QPointF
    from PySide6.QtGui import QMouseEvent
    from PySide6.QtWidgets import QApplication

    plotter = w.view.plotter
    move = QMouseEvent(QEvent.Type.MouseMove, QPointF(x, y),
                       plotter.mapToGlobal(QPointF(x, y)), Qt.MouseButton.NoButton,
                       Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier)
    QApplication.sendEvent(plotter, move)  # a hover, as the window system delivers it
    text = w.coords.text()
    assert text.startswith("E 512")
    east = float(text.split("N")[0][1:].replace(" ", ""))
    north = float(text.split("N")[1].split("H")[0].replace(" ", ""))
    assert (east, north) == pytest.approx(tuple(ground[:2]), abs=1e-3)
    assert w.document.project.scene.terrain.extent.contains(east, north)
