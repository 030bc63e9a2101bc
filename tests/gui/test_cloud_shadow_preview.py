"""The 3D view previews the cloud shadows: with <cloud-shadows> the drawn terrain is
darker where the render's own pattern (designer.scene.cloud_shadows) puts a shadow and
as before where it puts none; a change of a cloud field redraws it, and without cloud
shadows the terrain is drawn as it was."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtWidgets import QDoubleSpinBox, QScrollArea

from designer.scene.cloud_shadows import attenuation
from tests.gui.helpers import field, open_panel, set_field, wait_idle

pytestmark = pytest.mark.gui


def _click_check_box(qtbot, panel, box) -> None:
    """Scroll the panel to ``box`` and click on its tick."""
    panel.findChild(QScrollArea).ensureWidgetVisible(box)
    qtbot.mouseClick(box, Qt.MouseButton.LeftButton, pos=QPoint(8, box.height() // 2))


def _ground_pixels(w) -> list[tuple[int, int, np.ndarray]]:
    """Widget pixels of a 20 × 20 grid over the view that show the terrain (not within
    2 m of its edges), with the ground point under each."""
    e = w.document.project.scene.terrain.extent
    width, height = w.view.plotter.width(), w.view.plotter.height()
    out = []
    for y in np.linspace(0.1 * height, 0.9 * height, 20).astype(int):
        for x in np.linspace(0.1 * width, 0.9 * width, 20).astype(int):
            ground = w.view.interaction.ground_at(int(x), int(y))
            if ground is not None and e.min_X + 2 < ground[0] < e.max_X - 2 \
                    and e.min_Y + 2 < ground[1] < e.max_Y - 2:
                out.append((int(x), int(y), ground))
    assert len(out) > 100, len(out)
    return out


def _brightness(w, pixels) -> np.ndarray:
    """The view's drawn brightness (sum of R, G, B) at widget pixels [(x, y, …)]."""
    w.view.render_now()
    image = np.asarray(w.view.plotter.screenshot(None, return_img=True), dtype=float)
    return np.array([image[y, x, :3].sum() for x, y, _ground in pixels])


def _render_factor(w, pixels) -> np.ndarray:
    """The render's factor on the direct sun at the ground under each pixel (its own
    pattern at take-off, on a fine 0.25 m grid, nearest node)."""
    project = w.document.project
    xy = np.array([g[:2] for _x, _y, g in pixels]) - [project.origin.E0, project.origin.N0]
    lo, hi = xy.min(axis=0) - 1, xy.max(axis=0) + 1
    xs, ys = np.arange(lo[0], hi[0], 0.25), np.arange(lo[1], hi[1], 0.25)
    a = attenuation(project.scene.lighting.clouds, xs, ys, 0.0)
    i = np.clip(np.rint((xy[:, 0] - lo[0]) / 0.25).astype(int), 0, len(xs) - 1)
    j = np.clip(np.rint((xy[:, 1] - lo[1]) / 0.25).astype(int), 0, len(ys) - 1)
    return a[j, i]


def _flat_light(w, factor: np.ndarray) -> np.ndarray:
    """The light on flat ground with the direct sun times ``factor``, relative to full
    sun (the renderer's sun and sky)."""
    lighting = w.document.project.scene.lighting
    sun = lighting.sun_strength * np.sin(np.radians(lighting.sun.elevation_deg))
    return (sun * factor + lighting.sky_strength) / (sun + lighting.sky_strength)


def test_cloud_shadows_darken_the_drawn_terrain_where_the_render_puts_them(qtbot, window):
    w = window
    assert w.file_actions.new(None)  # flat ground, 100 × 100 m
    wait_idle(qtbot, w)
    pixels = _ground_pixels(w)
    clear = _brightness(w, pixels)

    lighting = open_panel(w, "Lighting")
    _click_check_box(qtbot, lighting, lighting.cloudy)
    wait_idle(qtbot, w)
    clouds = w.document.project.scene.lighting.clouds
    assert clouds is not None
    cloudy = _brightness(w, pixels)
    factor = _render_factor(w, pixels)
    shadow, open_sky = factor < 1 - 0.5 * clouds.depth, factor > 0.999
    assert shadow.sum() > 10 and open_sky.sum() > 20, (shadow.sum(), open_sky.sum())
    # in the shadows: darker, by the render's loss of light on flat ground (the direct
    # sun times the factor, the sky's share unchanged) …
    assert np.all(cloudy[shadow] < 0.85 * clear[shadow]), cloudy[shadow] / clear[shadow]
    expected = _flat_light(w, factor)
    assert np.abs(cloudy / clear - expected).max() < 0.08, np.abs(cloudy / clear - expected)
    # … under open sky: as without clouds
    assert np.abs(cloudy[open_sky] - clear[open_sky]).max() <= 6

    # a cloud field changed in the panel redraws the pattern: more cover, more shadow
    set_field(qtbot, field(lighting, QDoubleSpinBox, "scene.lighting.clouds.cover"), "0.7")
    wait_idle(qtbot, w)
    assert w.document.project.scene.lighting.clouds.cover == 0.7
    more = _brightness(w, pixels)
    assert (more < 0.8 * clear).sum() > 1.5 * (cloudy < 0.8 * clear).sum()
    factor = _render_factor(w, pixels)
    assert np.abs(more / clear - _flat_light(w, factor)).max() < 0.08

    # switched off: the terrain is drawn as it was
    _click_check_box(qtbot, lighting, lighting.cloudy)
    wait_idle(qtbot, w)
    assert w.document.project.scene.lighting.clouds is None
    assert np.abs(_brightness(w, pixels) - clear).max() <= 3
