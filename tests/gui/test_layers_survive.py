"""Layers survive every edit and its undo (problem 5 of the user test): the point cloud
and its colour bar stay while the Results panel shows their statistics."""

from __future__ import annotations

import numpy as np
import pytest

from designer.gui.state import edits
from designer.project import model as m
from tests.gui.helpers import add_hills_and_flight, wait_idle, write_xyz_ply

pytestmark = pytest.mark.gui

BAR = "signed distance (mm)"


def _cloud_drawn_at(w, xyz) -> None:
    assert w.view.has_layer("cloud")
    assert BAR in w.view.plotter.scalar_bars
    assert w.view.plotter.actors["cloud"].GetVisibility()
    drawn = np.asarray(w.view.layer_data("cloud").points, dtype=float) + w.view.offset
    np.testing.assert_allclose(drawn, xyz, atol=1e-3)  # float32 local coordinates


def test_cloud_survives_edits_and_undos(qtbot, window, tmp_path):
    w = window
    add_hills_and_flight(w)
    wait_idle(qtbot, w)
    hf = w.sync.terrain.heightfield
    x = np.linspace(-40, 40, 400)
    y = np.linspace(-30, 30, 400)
    xyz = np.column_stack([x, y, hf.height_at(x, y) + 0.05])
    write_xyz_ply(tmp_path / "cloud.ply", xyz)
    results = w.panels["Results"]
    results.open_cloud(tmp_path / "cloud.ply")
    wait_idle(qtbot, w)
    _cloud_drawn_at(w, xyz)

    p = w.document.project
    src = p.scene.terrain.source
    for text, new in (
            ("terrain moved away", edits.replace_path(
                p, "scene.terrain.extent", m.Extent(1000.0, 1000.0, 1100.0, 1100.0))),
            ("a terrain that cannot be built", edits.replace_path(
                p, "scene.terrain.source", m.ProceduralTerrain(
                    seed=src.seed, grid_spacing_m=3.0, roughness=src.roughness,
                    min_height_m=src.min_height_m, max_height_m=src.max_height_m))),
            ("flight lower", edits.set_flight(p, altitude_agl_m=30.0)),
            ("a GCP", edits.add_target(p, 1.0, 2.0))):
        w.editor.edit(new, text)
        wait_idle(qtbot, w)
        w.undo_stack.undo()
        wait_idle(qtbot, w)
        _cloud_drawn_at(w, xyz)
        assert results.stats.rowCount() > 5
    assert w.view.has_layer("targets") is False and w.view.has_layer("frusta")
    # "Clear" is the one thing that takes it away
    results.clear()
    wait_idle(qtbot, w)
    assert not w.view.has_layer("cloud") and BAR not in w.view.plotter.scalar_bars
