"""Lighting panel: sun and sky edited through the undo stack; the view lights the terrain
with them, as the renderer bakes its light."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox, QLineEdit, QSpinBox

from designer.gui.qt.panels.lighting import DEFAULT_CLOUDS
from designer.gui.state import derived
from designer.gui.state.view_geometry import shade_rgb
from designer.project import model as m
from designer.scene.lighting import sun_position_deg, surface_normals
from tests.gui.helpers import field, set_field, wait_idle

pytestmark = pytest.mark.gui


def _drawn_shade(w) -> np.ndarray:
    return np.asarray(w.view.layer_data("terrain")["shade"], dtype=float).mean(axis=1)


def test_sun_and_sky_edits_relight_the_drawn_terrain(qtbot, window):
    w = window
    terrain = w.panels["Terrain"]
    terrain.kind.setCurrentIndex(terrain.kind.findData("procedural"))
    wait_idle(qtbot, w)
    panel = w.panels["Lighting"]
    w.docks["Lighting"].raise_()
    before = _drawn_shade(w)

    # The sun low in the west: slopes facing west are lit, slopes facing east are dark.
    set_field(qtbot, field(w, QDoubleSpinBox, "scene.lighting.sun.azimuth_deg"), "270")
    set_field(qtbot, field(w, QDoubleSpinBox, "scene.lighting.sun.elevation_deg"), "20")
    wait_idle(qtbot, w)
    lighting = w.document.project.scene.lighting
    assert lighting.sun == m.Sun(270.0, 20.0)
    assert panel.sun_label.text() == "azimuth 270.0°, elevation 20.0°"
    shade = _drawn_shade(w)
    assert not np.allclose(shade, before)
    t = w.sync.terrain
    expected = derived.display_irradiance(lighting, t.display, t.heightfield, t.raycaster)
    np.testing.assert_allclose(w.view.layer_data("terrain")["shade"], shade_rgb(expected))
    points = t.display.points_world
    normals = surface_normals(t.heightfield, points[:, 0], points[:, 1],
                              t.display.stride * t.heightfield.dx_m)
    west, east = normals[:, 0] < -0.1, normals[:, 0] > 0.1
    assert west.sum() > 100 and east.sum() > 100
    assert shade[west].mean() > shade[east].mean() + 40
    # the per-vertex colours are the only lighting: none is computed per pixel
    assert not w.view.plotter.actors["terrain"].prop.lighting

    # A stronger sky brightens the shadows; undo takes it back.
    set_field(qtbot, field(w, QDoubleSpinBox, "scene.lighting.sky_strength"), "3")
    wait_idle(qtbot, w)
    assert w.document.project.scene.lighting.sky_strength == 3.0
    brighter = _drawn_shade(w)
    assert brighter[east].mean() > shade[east].mean() + 20
    assert "gets" in panel.contrast_label.text()
    w.undo_stack.undo()
    wait_idle(qtbot, w)
    assert w.document.project.scene.lighting.sky_strength == 1.0
    np.testing.assert_allclose(_drawn_shade(w), shade)


def test_sun_computed_for_a_moment_and_place(qtbot, window):
    w = window
    panel = w.panels["Lighting"]
    w.docks["Lighting"].raise_()
    panel.kind.setCurrentIndex(panel.kind.findData("position"))
    assert isinstance(w.document.project.scene.lighting.sun, m.SunPosition)
    assert panel.position.isVisibleTo(panel) and not panel.direction.isVisibleTo(panel)
    moment = field(w, QLineEdit, "scene.lighting.sun.date_time")
    moment.selectAll()
    qtbot.keyClicks(moment, "2024-12-21T09:30:00+01:00")
    qtbot.keyClick(moment, Qt.Key.Key_Return)
    set_field(qtbot, field(w, QDoubleSpinBox, "scene.lighting.sun.latitude_deg"), "46.5")
    wait_idle(qtbot, w)
    sun = w.document.project.scene.lighting.sun
    assert (sun.date_time, sun.latitude_deg) == ("2024-12-21T09:30:00+01:00", 46.5)
    azimuth, elevation = sun_position_deg(sun.date_time, 46.5, sun.longitude_deg)
    assert panel.sun_label.text() == (f"azimuth {azimuth:.1f}°, elevation {elevation:.1f}° "
                                      "(computed)")
    # Back to a direction: the computed one, so the light stays where it was.
    panel.kind.setCurrentIndex(panel.kind.findData("direction"))
    assert w.document.project.scene.lighting.sun == m.Sun(round(azimuth, 1),
                                                          round(elevation, 1))
    w.undo_stack.undo()
    assert w.document.project.scene.lighting.sun == sun
    assert panel.kind.currentData() == "position"


def test_cloud_shadows_are_edited_through_the_undo_stack(qtbot, window):
    w = window
    panel = w.panels["Lighting"]
    w.docks["Lighting"].raise_()
    assert w.document.project.scene.lighting.clouds is None
    panel.cloudy.setChecked(True)
    wait_idle(qtbot, w)
    assert w.document.project.scene.lighting.clouds == DEFAULT_CLOUDS
    set_field(qtbot, field(w, QDoubleSpinBox, "scene.lighting.clouds.cover"), "0.45")
    set_field(qtbot, field(w, QDoubleSpinBox, "scene.lighting.clouds.wind_speed_m_s"), "8")
    set_field(qtbot, field(w, QSpinBox, "scene.lighting.clouds.seed"), "5")
    wait_idle(qtbot, w)
    clouds = w.document.project.scene.lighting.clouds
    assert (clouds.cover, clouds.wind_speed_m_s, clouds.seed) == (0.45, 8.0, 5)
    assert "take-off" in panel.clouds_note.text() or "drift" in panel.clouds_note.text()
    for _ in range(3):
        w.undo_stack.undo()
    wait_idle(qtbot, w)
    assert w.document.project.scene.lighting.clouds == DEFAULT_CLOUDS
    w.undo_stack.undo()
    wait_idle(qtbot, w)
    assert w.document.project.scene.lighting.clouds is None
    assert not panel.cloudy.isChecked()
