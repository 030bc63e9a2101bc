"""The Flight panel warns, as ``designer check`` does, of the cases that degrade results
(designer.checks.hard_cases): here control GCPs nearly on one line, and the warning
follows the GCP table's edits."""

from __future__ import annotations

import pytest
from PySide6.QtWidgets import QLabel

from tests.gui.helpers import answer_file_dialog, choose_menu, open_panel, type_cell, wait_idle

pytestmark = pytest.mark.gui


def test_nearly_collinear_control_is_warned_until_a_gcp_leaves_the_line(qtbot, window,
                                                                         tmp_path):
    from tests.hard_cases import scenes
    from tests.synthetic import write_project_file

    w = window
    p = scenes.collinear_control(0.0)  # five control GCPs 20 m along N = N0
    path = write_project_file(p, tmp_path)
    answer_file_dialog(path)
    choose_menu(qtbot, w, "File", "Open…")
    wait_idle(qtbot, w)
    assert w.document.path == path
    label = open_panel(w, "Flight").findChild(QLabel, "plan-warnings")
    qtbot.waitUntil(lambda: "nearly collinear" in label.text(), timeout=10000)
    text = label.text()
    assert ("⚠ the 5 control GCPs (G0, G1, G2, G3, G4) are nearly collinear: they span a "
            "strip ") in text, text
    assert ("move or add control GCPs off the line, at least a tenth of its length away"
            ) in text, text
    # as designer check: the texture's texels against the GSD of this flight
    assert "texture texels (2.0 cm) are finer than a third of the GSD" in text, text
    assert label.isVisible()

    # the middle control GCP typed 8 m north of the line: the control spreads, no warning
    gcps = open_panel(w, "GCPs")
    row = [t.id for t in w.document.project.targets].index("G2")
    gcps.table.scrollToItem(gcps.table.item(row, 3))  # the Y column, scrolled to
    type_cell(qtbot, w, gcps.table, row, 3, f"{p.origin.N0 + 8:.1f}")
    wait_idle(qtbot, w)
    assert w.document.project.targets[row].true.Y == pytest.approx(p.origin.N0 + 8)
    open_panel(w, "Flight")
    assert "nearly collinear" not in label.text(), label.text()
    assert "texture texels (2.0 cm)" in label.text()


def test_collinear_control_and_a_thin_network_on_a_terrain_mesh_are_warned(
        qtbot, window, tmp_path):
    """The control's surveyed coordinates and the count of images need no height field:
    on a terrain mesh the Flight panel warns of nearly collinear control and of two
    photos as designer check does."""
    from dataclasses import replace

    from designer.checks.hard_cases import collinear_control_warning, network_warnings
    from designer.project import model as m
    from tests.hard_cases import scenes

    w = window
    p = scenes.surveyed_at_true(scenes.collinear_control(0.0))
    p = replace(p, trajectory=m.Trajectory(
        exterior_orientations=p.trajectory.exterior_orientations[:2]))
    path = scenes.on_a_terrain_mesh(p, tmp_path)
    answer_file_dialog(path)
    choose_menu(qtbot, w, "File", "Open…")
    wait_idle(qtbot, w)
    assert w.document.path == path
    assert w.document.project.scene.terrain.kind == "mesh"
    label = open_panel(w, "Flight").findChild(QLabel, "plan-warnings")
    qtbot.waitUntil(lambda: "nearly collinear" in label.text(), timeout=10000)
    surveyed = [t.surveyed.position for t in p.targets[:5]]
    warning = collinear_control_warning([t.id for t in p.targets[:5]],
                                        [(s.X, s.Y, s.Z) for s in surveyed])
    assert f"⚠ {warning.message}; {warning.panel_fix or warning.fix}" in label.text()
    (thin,) = network_warnings(p, 2, [-1, -1])
    assert thin.message.startswith("2 images: structure from motion needs at least 3")
    assert f"⚠ {thin.message}; {thin.panel_fix}" in label.text(), label.text()
    assert label.isVisible()
