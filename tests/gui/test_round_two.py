"""Round two of the desktop designer: nothing fails silently, nothing reads wrong. An
edit that would break the project is refused where it is typed, in the user's terms."""

from __future__ import annotations

import dataclasses

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox, QLineEdit

from designer.gui.state import edits
from designer.project import processing as pr
from tests.gui.helpers import (
    cloud_with_outlier,
    field,
    open_panel,
    problems,
    set_field,
    type_cell,
    wait_idle,
)

pytestmark = pytest.mark.gui


def _type_line(qtbot, line: QLineEdit, text: str) -> None:
    """Select all of a text field, type ``text`` (empty: delete), Enter."""
    line.setFocus()
    line.selectAll()
    if text:
        qtbot.keyClicks(line, text)
    else:
        qtbot.keyClick(line, Qt.Key.Key_Delete)
    qtbot.keyClick(line, Qt.Key.Key_Return)


def test_clearing_the_camera_id_is_refused_and_a_new_id_renames_its_uses(qtbot, window):
    w = window
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "flight")
    wait_idle(qtbot, w)
    camera = open_panel(w, "Camera")
    n_stations = w.sync.stations.n_images
    assert n_stations > 0
    line = field(camera, QLineEdit, "cameras[0].id")
    old = w.document.project.cameras[0].id

    _type_line(qtbot, line, "")
    wait_idle(qtbot, w)
    p = w.document.project
    assert p.cameras[0].id == old and p.trajectory.flight_plan.camera == old
    assert w.sync.stations is not None and w.sync.stations.n_images == n_stations
    message = camera.input_label.text()
    assert camera.input_label.isVisible()
    assert "Camera id" in message and "required" in message and "not applied" in message
    assert line.property("invalid")
    assert w.panels["Flight"].error_label.text() == ""

    _type_line(qtbot, line, "my cam")  # a space: not an id
    wait_idle(qtbot, w)
    assert w.document.project.cameras[0].id == old
    assert "my cam" in camera.input_label.text()

    # a valid id is applied, and the flight plan follows it
    _type_line(qtbot, line, "my-cam")
    wait_idle(qtbot, w)
    p = w.document.project
    assert p.cameras[0].id == "my-cam" and p.trajectory.flight_plan.camera == "my-cam"
    assert w.sync.stations is not None and w.sync.stations.n_images == n_stations
    assert not camera.input_label.isVisible() and not line.property("invalid")
    assert w.panels["Flight"].error_label.text() == ""
    # one undo brings the old id back everywhere
    w.undo_action.trigger()
    p = w.document.project
    assert p.cameras[0].id == old and p.trajectory.flight_plan.camera == old
    assert line.text() == old


def test_highest_below_lowest_is_refused_in_the_users_terms(qtbot, window):
    w = window
    terrain = open_panel(w, "Terrain")
    terrain.kind.setCurrentIndex(terrain.kind.findData("procedural"))
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "flight")
    wait_idle(qtbot, w)
    lowest = field(terrain, QDoubleSpinBox, "scene.terrain.source.min_height_m")
    highest = field(terrain, QDoubleSpinBox, "scene.terrain.source.max_height_m")
    set_field(qtbot, lowest, "-10")
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.source.min_height_m == -10.0
    before = w.document.project

    set_field(qtbot, highest, "-20")
    wait_idle(qtbot, w)
    assert w.document.project == before  # nothing applied
    assert w.sync.terrain is not None and w.sync.stations is not None
    message = terrain.input_label.text()
    assert terrain.input_label.isVisible()
    assert "highest (-20 m) must be above lowest (-10 m)" in message, message
    assert "relief" not in message and "-5" not in message
    assert highest.property("invalid") and highest.text().strip().startswith("-20")
    assert terrain.error_label.text() == ""
    assert w.panels["Flight"].error_label.text() == ""
    # moving the focus away keeps the refusal (and the typed text) to correct
    lowest.setFocus()
    qtbot.wait(50)
    assert highest.property("invalid") and w.document.project == before
    # the arrow keys cannot step past the rule either
    set_field(qtbot, highest, "-10")
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.source.max_height_m == -10.0
    assert not terrain.input_label.isVisible()
    highest.setFocus()
    qtbot.keyClick(highest, Qt.Key.Key_Down)
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.source.max_height_m == -10.0
    assert "must be above lowest" in terrain.input_label.text()

    # a lowest typed above the highest: the same, named from the lowest's side
    set_field(qtbot, lowest, "0")
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.source.min_height_m == -10.0
    assert "lowest (0 m) must be below highest (-10 m)" in terrain.input_label.text()
    # a valid value is applied and the messages go
    set_field(qtbot, lowest, "-12")
    wait_idle(qtbot, w)
    src = w.document.project.scene.terrain.source
    assert (src.min_height_m, src.max_height_m) == (-12.0, -10.0)
    assert not terrain.input_label.isVisible()


def test_a_scale_giving_part_pixels_is_refused_and_its_problem_opens_render(
        qtbot, window, tmp_path):
    w = window
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "flight")
    wait_idle(qtbot, w)
    assert w.file_actions.save_to(tmp_path / "scale.xml"), problems(w)
    render = open_panel(w, "Render")
    scale = field(render, QDoubleSpinBox, "render.resolution_scale")
    cam = w.document.project.cameras[0]  # 5472 × 3648 px
    before = w.document.project

    # typed: refused in the Render panel, with the pixels and the nearest whole scale
    set_field(qtbot, scale, "0.1")
    wait_idle(qtbot, w)
    assert w.document.project == before
    message = render.input_label.text()
    assert render.input_label.isVisible() and scale.property("invalid")
    assert f"{cam.image_width_px} × 0.1 = 547.2 px" in message, message
    assert "nearest scale giving whole pixels: 0.125" in message, message
    set_field(qtbot, scale, "0.125")
    wait_idle(qtbot, w)
    assert w.document.project.render.resolution_scale == 0.125
    assert not render.input_label.isVisible()
    # 0.05 gives 273.6 px: 0.0625 (342 × 228 px) is nearer than 0.125, and the field
    # takes and shows it as it is
    set_field(qtbot, scale, "0.05")
    wait_idle(qtbot, w)
    assert "nearest scale giving whole pixels: 0.0625" in render.input_label.text()
    set_field(qtbot, scale, "0.0625")
    wait_idle(qtbot, w)
    assert w.document.project.render.resolution_scale == 0.0625
    assert not render.input_label.isVisible()
    assert scale.text().rstrip("0") == "0.0625", scale.text()

    # a project that has such a scale (read from a file): the problem opens Render …
    w.editor.edit(edits.replace_path(w.document.project, "render.resolution_scale", 0.1),
                  "scale from a file")
    wait_idle(qtbot, w)
    qtbot.mouseClick(render.start_button, Qt.MouseButton.LeftButton)
    assert not render.process.running
    assert "save the project" in render.state.text()
    listed = problems(w)
    assert any("Render › camera 'p4p': image width 5472 px × resolution scale 0.1 = 547.2 "
               "px is not a whole number of pixels" in line for line in listed), listed
    open_panel(w, "Lighting")  # the Texture panel is not in front before the click
    open_panel(w, "Camera")
    item = w.problems.item(0)
    rect = w.problems.visualItemRect(item)
    qtbot.mouseClick(w.problems.viewport(), Qt.MouseButton.LeftButton, pos=rect.center())
    qtbot.wait(50)
    assert not w.docks["Render"].visibleRegion().isEmpty()
    assert w.docks["Camera"].visibleRegion().isEmpty()
    assert w.docks["Texture"].visibleRegion().isEmpty()

    # … and once fixed, the Render panel no longer asks to save without problems
    set_field(qtbot, scale, "0.25")
    qtbot.waitUntil(lambda: not problems(w), timeout=5000)
    wait_idle(qtbot, w)
    assert "save the project" not in render.state.text()
    assert render.start_button.isEnabled()


def test_a_duplicate_gcp_id_is_refused_where_it_is_typed(qtbot, window):
    w = window
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)
    project = edits.add_target(edits.ensure_flight_plan(w.document.project), 10.0, 5.0)
    project = edits.add_target(project, -10.0, 5.0)
    project = dataclasses.replace(project, processing=pr.Processing(
        gcps=pr.GcpProcessing(control=pr.ControlSelection(ids=("GCP02",)))))
    w.editor.edit(project, "a flight and two GCPs, GCP02 the control point")
    gcps = open_panel(w, "GCPs")
    wait_idle(qtbot, w)
    before = w.document.project
    assert [t.id for t in before.targets] == ["GCP01", "GCP02"]

    type_cell(qtbot, w, gcps.table, 1, 0, "GCP01")
    assert w.document.project == before
    text = gcps.error_label.text()
    assert "GCP02 id: “GCP01” is the id of another GCP (row 1)" in text, text
    assert "not applied" in text
    assert gcps.table.item(1, 0).background().color().red() > 200
    type_cell(qtbot, w, gcps.table, 1, 0, "GCP 2")  # a space splits COLMAP's lines
    assert w.document.project == before
    assert "“GCP 2”" in gcps.error_label.text()
    # a free id is applied
    type_cell(qtbot, w, gcps.table, 1, 0, "GCP07")
    assert [t.id for t in w.document.project.targets] == ["GCP01", "GCP07"]
    assert w.document.project.processing.gcps.control.ids == ("GCP07",)  # followed
    assert gcps.error_label.text() == ""


def test_another_cloud_forgets_the_point_picked_in_the_last(qtbot, window, tmp_path):
    import numpy as np
    from PySide6.QtWidgets import QPushButton

    from tests.gui.cloud_helpers import cloud_seen_from_above, point_on_screen
    from tests.gui.helpers import add_hills_and_flight, answer_file_dialog

    w = window
    add_hills_and_flight(w)
    wait_idle(qtbot, w)
    results = open_panel(w, "Results")
    hint = results.picked.text()
    first, _xyz = cloud_with_outlier(w, tmp_path, n=400)
    results.open_cloud(first)
    wait_idle(qtbot, w)
    cloud_seen_from_above(w)
    r = results.result
    pos = point_on_screen(w, r.points_world[17])
    qtbot.mouseClick(w.view.plotter, Qt.MouseButton.LeftButton, pos=pos)
    assert results.picked.text().startswith("Δ = ")

    # another cloud, opened with the button: the value picked in the first one goes
    second = tmp_path / "second" / "cloud.ply"
    second.parent.mkdir()
    second.write_bytes(first.read_bytes())
    button = next(b for b in results.findChildren(QPushButton)
                  if b.text() == "Open point cloud…")
    answer_file_dialog(second)
    qtbot.mouseClick(button, Qt.MouseButton.LeftButton)
    wait_idle(qtbot, w)
    assert results.result is not r and np.array_equal(results.result.points_world,
                                                      r.points_world)
    assert results.picked.text() == hint
    # and Clear takes it away as well
    qtbot.mouseClick(w.view.plotter, Qt.MouseButton.LeftButton, pos=pos)
    assert results.picked.text().startswith("Δ = ")
    clear = next(b for b in results.findChildren(QPushButton) if b.text() == "Clear")
    qtbot.mouseClick(clear, Qt.MouseButton.LeftButton)
    assert results.picked.text() == hint
