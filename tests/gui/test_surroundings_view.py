"""The 3D view draws the ground the renders include beyond the terrain's extent (its
surroundings) as a plain ring around the terrain, so the image footprints lie on drawn
ground; with surroundings "none" the ring goes, and comes back with an undo."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QComboBox

from tests.gui.helpers import choose_entry, field, open_panel, wait_idle

pytestmark = pytest.mark.gui


def _ring_world(w) -> np.ndarray:
    """The drawn surroundings' points in world coordinates (m)."""
    return np.asarray(w.view.layer_data("surroundings").points, float) + w.view.offset


def test_the_view_draws_the_surroundings_the_renders_include(qtbot, window, tmp_path):
    from designer.survey.surroundings import project_surroundings

    w = window
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)
    assert w.file_actions.new("survey")
    wait_idle(qtbot, w)
    p = w.document.project
    growth, declared = project_surroundings(p, w.document.base_dir)
    assert any(growth.steps)  # the survey's images see past its 100 m × 100 m
    assert w.view.has_layer("surroundings")
    ring = _ring_world(w)
    x0, x1, y0, y1 = declared.extent_m
    # as far as the renderer grows the terrain (whole tiles), and none of it over the terrain
    tile = (x1 - x0) / p.scene.texture.repeat_X
    w_, e_, s_, n_ = growth.steps
    assert ring[:, 0].min() == pytest.approx(x0 - w_ * tile)
    assert ring[:, 0].max() == pytest.approx(x1 + e_ * tile)
    assert ring[:, 1].min() == pytest.approx(y0 - s_ * tile)
    assert ring[:, 1].max() == pytest.approx(y1 + n_ * tile)
    faces = np.asarray(w.view.layer_data("surroundings").regular_faces)
    centres = ring[faces].mean(axis=1)
    inside = ((centres[:, 0] > x0) & (centres[:, 0] < x1) & (centres[:, 1] > y0)
              & (centres[:, 1] < y1))
    assert not inside.any()
    assert len(ring) <= 100 * 100  # a coarse grid: cheap to draw
    # on the ground the renderer draws: heights of the grown terrain
    from designer.survey.project_poses import project_images
    from designer.survey.surroundings import rendered_terrain

    grown = rendered_terrain(p, declared, project_images(p, declared)).heightfield
    # (to float32 of the drawn points)
    assert np.abs(ring[:, 2] - grown.height_at(ring[:, 0], ring[:, 1])).max() < 1e-4
    # every footprint lies on drawn ground (the terrain or its surroundings)
    feet = w.sync.stations.geometry.footprint_points
    assert feet[:, 0].min() >= ring[:, 0].min() and feet[:, 0].max() <= ring[:, 0].max()
    assert feet[:, 1].min() >= ring[:, 1].min() and feet[:, 1].max() <= ring[:, 1].max()
    # on its heights, beyond the terrain too (not on a plane at the terrain's mean height)
    outside = ~declared.contains(feet[:, 0], feet[:, 1])
    assert outside.sum() > 100
    dz = np.abs(feet[:, 2] - grown.height_at(feet[:, 0], feet[:, 1]))
    assert dz[~outside].max() < 0.01
    assert dz[outside].max() < 0.1  # cast on every other node of the surroundings
    assert w.view.plotter.actors["surroundings"].GetVisibility()
    w.view.view_top()
    w.view.render_now()
    w.view.plotter.grab().save(str(tmp_path / "surroundings-top.png"))
    w.view.reset_view()
    w.view.render_now()
    w.grab().save(str(tmp_path / "surroundings.png"))

    # surroundings "none" in the Terrain panel: the renders stop at the extent, so does the view
    panel = open_panel(w, "Terrain")
    choose_entry(qtbot, w, field(panel, QComboBox, "scene.terrain.surroundings"), "none")
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.surroundings == "none"
    assert not w.view.has_layer("surroundings")
    assert "surroundings" not in w.view.plotter.actors
    w.view.render_now()
    w.grab().save(str(tmp_path / "no-surroundings.png"))

    QTest.keyClick(w.windowHandle(), Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    wait_idle(qtbot, w)
    assert w.document.project.scene.terrain.surroundings is None
    assert w.view.has_layer("surroundings")
