"""The Terrain panel checks its rules across fields where they are typed, in the numbers
typed: an extent whose min is not below its max, or a grid spacing (or an extent edge)
that leaves no whole number of grid cells, is refused — the field turns red and says
why; nothing reaches the project, so no other panel breaks. When the terrain cannot be
made all the same, the Flight panel says so (not that the terrain is a mesh)."""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QDoubleSpinBox

from designer.gui.qt.widgets import format_number as num
from tests.gui.helpers import field, open_panel, set_field, wait_idle

pytestmark = pytest.mark.gui


def _survey(qtbot, w):
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    return open_panel(w, "Terrain")


def _refused(qtbot, w, box, text: str, before) -> str:
    set_field(qtbot, box, text)
    wait_idle(qtbot, w)
    assert w.document.project == before, "applied"
    assert box.property("invalid") and box.text().strip().startswith(text)
    assert not any(w.sync.errors.get(k) for k in ("terrain", "texture", "stations")), \
        w.sync.errors
    return w.panels["Terrain"].input_label.text()


def test_an_extent_min_above_its_max_is_refused_in_the_numbers_typed(qtbot, window):
    w = window
    terrain = _survey(qtbot, w)
    e = w.document.project.scene.terrain.extent
    before = w.document.project
    min_x = field(terrain, QDoubleSpinBox, "scene.terrain.extent.min_X")
    message = _refused(qtbot, w, min_x, "512100", before)
    assert f"min X (512100 m) must be below max X ({num(e.max_X)} m)" in message, message
    max_y = field(terrain, QDoubleSpinBox, "scene.terrain.extent.max_Y")
    message = _refused(qtbot, w, max_y, "5405900", before)
    assert f"max Y (5405900 m) must be above min Y ({num(e.min_Y)} m)" in message, message
    # a valid edge is applied
    set_field(qtbot, max_y, num(e.max_Y + 10))
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.extent.max_Y == e.max_Y + 10
    assert not max_y.property("invalid")


def test_a_grid_spacing_that_leaves_part_cells_is_refused(qtbot, window):
    w = window
    terrain = _survey(qtbot, w)
    e = w.document.project.scene.terrain.extent
    before = w.document.project
    spacing = field(terrain, QDoubleSpinBox, "scene.terrain.source.grid_spacing_m")
    message = _refused(qtbot, w, spacing, "0.7", before)
    assert (f"grid spacing 0.7 m does not divide the extent's width ({num(e.width_m)} m, "
            "min X to max X)") in message, message
    assert "grid-spacing-m" not in message and "spacing_m=" not in message
    # an extent edge that leaves part of a cell, named from the edge's side
    min_x = field(terrain, QDoubleSpinBox, "scene.terrain.extent.min_X")
    message = _refused(qtbot, w, min_x, num(e.min_X + 0.3), before)
    assert (f"min X ({num(e.min_X + 0.3)} m) leaves a width of {num(e.width_m - 0.3, 3)} m, not a "
            "whole number of 0.5 m grid cells") in message, message


def test_a_terrain_that_cannot_be_made_is_named_in_the_flight_panel(qtbot, window):
    from dataclasses import replace

    w = window
    _survey(qtbot, w)
    project = w.document.project
    src = project.scene.terrain.source
    # a project opened with part cells (the panel would refuse to type it)
    broken = replace(project, scene=replace(project.scene, terrain=replace(
        project.scene.terrain, source=replace(src, grid_spacing_m=0.7))))
    w.editor.edit(broken, "spacing")
    wait_idle(qtbot, w)
    assert w.sync.terrain is None and w.sync.errors.get("terrain")
    flight = open_panel(w, "Flight")
    wait_idle(qtbot, w)
    text = flight.error_label.text()
    assert "mesh" not in text, text
    assert "Terrain panel" in text, text


def test_an_extent_that_makes_no_texture_is_refused_where_it_is_typed(qtbot, window):
    w = window
    terrain = _survey(qtbot, w)  # 100 × 100 m, repeat 5 × 5, 0.025 m texels
    e = w.document.project.scene.terrain.extent
    before = w.document.project
    max_x = field(terrain, QDoubleSpinBox, "scene.terrain.extent.max_X")
    typed = num(e.min_X + 1100)
    message = _refused(qtbot, w, max_x, typed, before)
    assert (f"max X ({typed} m) would break the texture: texel size 0.025 m makes a tile "
            "(220 × 20 m: the extent 1100 × 100 m over repeat X 5, repeat Y 5) 8800 × 800 "
            "texels, more than 8192; raise the texel size or repeat X/Y in the Texture panel "
            "first") in message, message
    assert message.endswith(f"; not applied (Esc: back to {num(e.max_X)} m)"), message
    assert "texel-size-m" not in message and " px" not in message, message


def test_an_extent_that_leaves_gcps_off_the_terrain_is_refused(qtbot, window):
    w = window
    terrain = _survey(qtbot, w)
    e = w.document.project.scene.terrain.extent
    before = w.document.project
    off = [t for t in before.targets if t.true.X > e.min_X + 60]
    assert off
    max_x = field(terrain, QDoubleSpinBox, "scene.terrain.extent.max_X")
    typed = num(e.min_X + 60)
    message = _refused(qtbot, w, max_x, typed, before)
    first = off[0]
    assert (f"max X ({typed} m) would leave {len(off)} GCPs off the terrain ({first.id} at "
            f"X {num(first.true.X)}, Y {num(first.true.Y)}") in message, message
    assert "move them in the GCPs panel first" in message, message
    # an extent that keeps every GCP and the texture is applied
    set_field(qtbot, max_x, num(e.max_X + 100))
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.extent.max_X == e.max_X + 100
    assert not max_x.property("invalid")


def test_an_extent_that_leaves_a_building_or_the_flight_area_off_is_refused(qtbot, window):
    from dataclasses import replace

    import designer.project.model as m

    w = window
    terrain = _survey(qtbot, w)  # flight area X 511965..512035, Y 5405965..5406035
    project = w.document.project
    hall = m.Building("hall", footprint=tuple(m.PathPoint(X, Y) for X, Y in (
        (512040.0, 5406000.0), (512045.5, 5406000.0), (512045.5, 5406010.0),
        (512040.0, 5406010.0))))
    scene = replace(project.scene, buildings=(hall,),
                    targets=replace(project.scene.targets, targets=()))
    w.editor.edit(replace(project, scene=scene), "hall, no GCPs")
    wait_idle(qtbot, w)
    before = w.document.project
    max_x = field(terrain, QDoubleSpinBox, "scene.terrain.extent.max_X")
    message = _refused(qtbot, w, max_x, "512042", before)
    assert ("max X (512042 m) would leave building hall off the terrain (its corner at "
            "X 512045.5, Y 5406000); move it in the Buildings panel first or keep the extent "
            "around it; not applied") in message, message
    min_y = field(terrain, QDoubleSpinBox, "scene.terrain.extent.min_Y")
    message = _refused(qtbot, w, min_y, "5405970", before)
    assert ("min Y (5405970 m) would leave 2 corners of the flight area off the terrain "
            "(corner 1 at X 511965, Y 5405965; corner 2 at X 512035, Y 5405965); move them "
            "in the Flight panel first or keep the extent around them; not applied"
            ) in message, message
    # an extent around both is applied
    set_field(qtbot, min_y, "5405960")
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.extent.min_Y == 5405960
