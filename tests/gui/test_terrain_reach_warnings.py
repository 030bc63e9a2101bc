"""The Flight panel warns, as ``designer check`` does, of GCPs, buildings and flight-area
vertices outside the ground a terrain mesh or DEM holds, and the warning follows the
edits that move them."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from PySide6.QtWidgets import QLabel

from tests.gui.helpers import answer_file_dialog, choose_menu, open_panel, type_cell, wait_idle

pytestmark = pytest.mark.gui


def _half_mesh_project(tmp_path):
    """The survey on a terrain mesh that holds only the west half of the extent (local
    X −50..0), a shed east of it."""
    from designer.core.heightfield import Heightfield
    from designer.project import model as m
    from designer.project.templates import _house, template
    from designer.scene.mesh import heightfield_to_mesh, write_mesh_ply
    from tests.synthetic import write_project_file

    p = template("survey").project
    terrain = dataclasses.replace(p.scene.terrain, source=m.MeshTerrain("ground.ply"))
    shed = _house("shed", p.origin.E0 + 30, p.origin.N0 - 10, 6.0, 4.0, "flat", 3.0)
    p = dataclasses.replace(p, scene=dataclasses.replace(p.scene, terrain=terrain,
                                                         buildings=(shed,)))
    path = write_project_file(p, tmp_path)
    write_mesh_ply(heightfield_to_mesh(Heightfield(-50.0, -50.0, 50.0, 100.0,
                                                   np.zeros((2, 2)))), tmp_path / "ground.ply")
    return path, p


def test_places_off_a_terrain_mesh_are_warned_in_the_flight_panel(qtbot, window, tmp_path):
    w = window
    path, p = _half_mesh_project(tmp_path)
    answer_file_dialog(path)
    choose_menu(qtbot, w, "File", "Open…")
    wait_idle(qtbot, w)
    assert w.document.path == path
    label = open_panel(w, "Flight").findChild(QLabel, "plan-warnings")
    qtbot.waitUntil(lambda: "outside the terrain mesh" in label.text(), timeout=10000)
    text = label.text()
    east = [t for t in p.targets if t.true.X > p.origin.E0]
    assert east
    assert f"GCP {east[0].id} (X " in text, text
    assert ("lie outside the terrain mesh ground.ply, which holds ground only over "
            "X 511950..512000, Y 5405950..5406050: the scene has no ground there; move the "
            "GCPs onto the terrain (GCPs panel), or use a terrain file that covers them"
            ) in text, text
    assert "building 'shed' corner 1 (X 512027, Y 5405988)" in text, text
    assert "draw the flight area over the terrain (Flight panel)" in text, text
    assert label.isVisible()

    # the first GCP east of the mesh typed onto it: it leaves the warning at once
    gcps = open_panel(w, "GCPs")
    row = [t.id for t in w.document.project.targets].index(east[0].id)
    type_cell(qtbot, w, gcps.table, row, 2, f"{p.origin.E0 - 20:.1f}")
    wait_idle(qtbot, w)
    assert w.document.project.targets[row].true.X == pytest.approx(p.origin.E0 - 20)
    open_panel(w, "Flight")
    assert f"GCP {east[0].id} (X " not in label.text(), label.text()
    assert "building 'shed' corner 1" in label.text()
