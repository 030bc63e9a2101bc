"""The GCPs panel's automatic layout checks its fields against each other before it
replaces the targets: more check points than GCPs is refused in the numbers typed (not
quietly turned into a layout of check points only); nothing reaches the project."""

from __future__ import annotations

import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QPushButton

from tests.gui.helpers import open_panel, set_field, wait_idle

pytestmark = pytest.mark.gui


def _apply(qtbot, panel) -> None:
    button = next(b for b in panel.findChildren(QPushButton) if b.text() == "Apply layout")
    qtbot.mouseClick(button, Qt.MouseButton.LeftButton)


def test_more_check_points_than_gcps_is_refused(qtbot, window):
    w = window
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    gcps = open_panel(w, "GCPs")
    before = w.document.project
    set_field(qtbot, gcps.count, "4")
    set_field(qtbot, gcps.n_check, "6")
    _apply(qtbot, gcps)
    wait_idle(qtbot, w)
    assert w.document.project == before, [t.role for t in w.document.project.targets]
    said = gcps.error_label.text()
    assert "6 check points" in said and "4 GCPs" in said and "not applied" in said, said
    # as many as the GCPs or fewer: applied, exactly that many check points
    set_field(qtbot, gcps.n_check, "1")
    _apply(qtbot, gcps)
    wait_idle(qtbot, w)
    roles = [t.role for t in w.document.project.targets]
    assert len(roles) == 4 and roles.count("check") == 1, roles
    assert gcps.error_label.text() == ""


def test_a_gcp_off_the_terrain_is_named_by_its_id_in_the_numbers_typed(qtbot, window):
    from tests.gui.helpers import type_cell

    w = window
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    gcps = open_panel(w, "GCPs")
    from designer.gui.qt.widgets import format_number as num

    e = w.document.project.scene.terrain.extent
    gid = w.document.project.targets[0].id
    type_cell(qtbot, w, gcps.table, 0, 2, "512500")  # past max X
    wait_idle(qtbot, w)
    said = gcps.error_label.text()
    assert f"{gid} at X 512500, Y " in said, said
    assert (f"terrain (X {num(e.min_X)} to {num(e.max_X)}, Y {num(e.min_Y)} to "
            f"{num(e.max_Y)})") in said, said
    assert "[" not in said and ".000" not in said, said


def test_a_layout_that_cannot_be_placed_names_the_field_in_the_numbers_typed(qtbot, window):
    w = window
    assert w.file_actions.new("survey")  # 100 × 100 m
    wait_idle(qtbot, w)
    gcps = open_panel(w, "GCPs")
    before = w.document.project
    gcps.layout_kind.setCurrentIndex(gcps.layout_kind.findData("random"))
    set_field(qtbot, gcps.margin, "200")
    _apply(qtbot, gcps)
    wait_idle(qtbot, w)
    assert w.document.project == before
    said = gcps.error_label.text()
    assert said.startswith("margin 200 m: a margin of 200 m leaves nothing"), said
    assert "200.0" not in said and said.endswith("not applied"), said
    set_field(qtbot, gcps.margin, "10")
    set_field(qtbot, gcps.spacing, "60")
    _apply(qtbot, gcps)
    wait_idle(qtbot, w)
    assert w.document.project == before
    said = gcps.error_label.text()
    assert said.startswith("min spacing (random) 60 m: 9 GCPs cannot be 60 m apart"), said
    assert "m²" in said and "m^2" not in said and said.endswith("not applied"), said
