"""Messages the user can act on (problem 7 of the user test): field names as labelled,
numbers in fixed point, refused table cells, problems that go away once fixed, and
coordinates saved to 0.1 mm."""

from __future__ import annotations

import re

import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtWidgets import QDoubleSpinBox

from designer.gui.state import edits
from designer.gui.state.wording import FIELD_NAMES, LIBRARY_NAMES, humanize
from designer.project import model as m
from designer.project.declare import declared_field
from tests.gui.helpers import field, ground_pixels, problems, type_cell, wait_idle

pytestmark = pytest.mark.gui


def test_humanize_names_fields_and_prints_fixed_point():
    text = humanize("size_x_m=100 is not a whole number of spacing_m=3.0 cells; vertex "
                    "(5.40595e+06, 123.456789) of dem_1.tif")
    assert "size_x_m" not in text and "spacing_m" not in text
    assert "terrain width (X)=100" in text and "grid spacing=3.0" in text
    assert "5405950" in text and "e+06" not in text and "123.457" in text
    assert "dem_1.tif" in text  # file names stay as they are


def test_field_names_are_the_declarations_labels():
    """A field's name in a library message is its declaration's label; only the library's
    own parameters are in the hand-written table."""
    for cls, name in ((m.Camera, "focal_length_mm"), (m.Sensor, "full_well_e"),
                      (m.ProceduralTexture, "texel_size_m")):
        assert name not in LIBRARY_NAMES
        assert FIELD_NAMES[name] == declared_field(cls, name).label
    assert humanize("exposure_time_s = 2 is too long") == "exposure time (shutter) = 2 is too long"
    # labelled differently by two declarations: not named from either
    assert {declared_field(m.TimeLine, "speed_m_s").label,
            declared_field(m.MovingObject, "speed_m_s").label} == {"ground speed", "speed"}
    assert "speed_m_s" not in FIELD_NAMES


def test_terrain_error_names_the_field_as_labelled(qtbot, window):
    w = window
    terrain = m.Terrain(w.document.project.scene.terrain.extent, m.ProceduralTerrain(
        seed=3, grid_spacing_m=3.0, roughness=0.2, min_height_m=0.0, max_height_m=3.0))
    w.editor.edit(edits.replace_path(w.document.project, "scene.terrain", terrain), "hills")
    wait_idle(qtbot, w)
    text = w.panels["Terrain"].error_label.text()
    assert "whole number" in text
    assert "size_x_m" not in text and "spacing_m" not in text
    assert "terrain width (X)" in text


def test_refused_gcp_cell_and_problems_that_an_undo_fixed(qtbot, window, tmp_path):
    w = window
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)
    w.editor.edit(edits.add_target(edits.ensure_flight_plan(w.document.project), 10.0, 5.0),
                  "a flight and one GCP")
    w.docks["GCPs"].raise_()
    wait_idle(qtbot, w)
    gcps = w.panels["GCPs"]
    table = gcps.table

    type_cell(qtbot, w, table, 0, 2, "1O.5")  # a letter O for a zero
    assert w.document.project.targets[0].true.X == 10.0
    assert "GCP01 X: “1O.5” is not a number" in gcps.error_label.text()
    assert table.item(0, 2).text() == "1O.5"
    assert table.item(0, 2).background().color().red() > 200
    type_cell(qtbot, w, table, 0, 2, "10.5")
    assert w.document.project.targets[0].true.X == 10.5
    assert gcps.error_label.text() == ""

    # a GCP typed far off the terrain: the save is refused and the problem listed …
    type_cell(qtbot, w, table, 0, 2, "5405950.12346")
    assert w.document.project.targets[0].true.X == 5405950.1235  # 0.1 mm
    assert not w.file_actions.save_to(tmp_path / "off.xml")
    listed = problems(w)
    assert listed and any("5405950" in line for line in listed)
    assert not any(re.search(r"\de[+-]\d", line) for line in listed)
    assert "e+06" not in gcps.error_label.text() and "5405950.12" in gcps.error_label.text()
    # … and the undo that fixes it empties the list
    w.undo_action.trigger()
    qtbot.waitUntil(lambda: not problems(w), timeout=5000)
    assert not w.docks["Problems"].isVisible()


def test_placed_gcps_are_saved_to_a_tenth_of_a_millimetre(qtbot, window, tmp_path):
    w = window
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "flight")
    wait_idle(qtbot, w)
    w.panels["GCPs"].place.setChecked(True)
    for x, y, _ground in ground_pixels(w, 3):
        qtbot.mouseClick(w.view.plotter, Qt.MouseButton.LeftButton, pos=QPoint(x, y))
    wait_idle(qtbot, w)
    assert len(w.document.project.targets) == 3
    path = tmp_path / "gcps.xml"
    assert w.file_actions.save_to(path), problems(w)
    text = path.read_text()
    coords = re.findall(r'<true [^>]*X="([^"]+)" Y="([^"]+)"', text)
    assert len(coords) == 3
    for value in (v for pair in coords for v in pair):
        assert len(value.split(".")[-1]) <= 4 if "." in value else True
    assert field(w, QDoubleSpinBox, "scene.terrain.extent.min_X").value() == -50
