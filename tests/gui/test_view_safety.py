"""The 3D view never places or reports ground that is not there (problem 4 of the user
test), shows the mode it is in, leaves it on Esc."""

from __future__ import annotations

import numpy as np
import pytest
from PySide6.QtCore import QPoint, Qt
from PySide6.QtTest import QTest

from designer.gui.state import edits
from designer.project import model as m
from tests.gui.helpers import ground_pixels, wait_idle

pytestmark = pytest.mark.gui


def _hills(qtbot, w) -> None:
    project = w.document.project
    terrain = m.Terrain(project.scene.terrain.extent, m.ProceduralTerrain(
        seed=3, grid_spacing_m=1.0, roughness=0.2, min_height_m=0.0, max_height_m=6.0))
    w.editor.edit(edits.replace_path(project, "scene.terrain", terrain), "hills")
    wait_idle(qtbot, w)


def _off_terrain_pixels(w) -> list[tuple[int, int]]:
    """Pixels of the view where the ray does not come down onto the terrain's top
    surface (checked by stepping along it over the height field) although it meets the
    solid terrain block: it enters the block from the side, beside or below it."""
    hf = w.sync.terrain.heightfield
    rc = w.sync.terrain.raycaster
    x0, x1, y0, y1 = hf.extent_m
    plotter = w.view.plotter
    out = []
    for y in range(10, plotter.height() - 5, 25):
        for x in range(10, plotter.width() - 5, 40):
            origin, d = w.view.ray_through(x, y)
            if not np.all(np.isfinite(rc.first_hit(origin[None], d[None])[0])):
                continue  # the sky: no hit at all
            t = np.linspace(0, 5000, 100001)
            p = origin + t[:, None] * d
            inside = (p[:, 0] >= x0) & (p[:, 0] <= x1) & (p[:, 1] >= y0) & (p[:, 1] <= y1)
            if not inside.any():
                continue
            below = p[inside, 2] < hf.height_at(p[inside, 0], p[inside, 1])
            if below[0] or not below.any():  # enters the block from the side, or never
                out.append((x, y))           # reaches the ground from above
    return out[:: max(1, len(out) // 6)]


def test_clicks_off_the_terrain_place_nothing(qtbot, window):
    w = window
    _hills(qtbot, w)
    w.view.reset_view()
    wait_idle(qtbot, w)
    off = _off_terrain_pixels(w)
    assert len(off) >= 3, "the view shows too little background to test"
    w.panels["GCPs"].place.setChecked(True)
    banner = w.view.mode_banner
    assert banner.isVisible() and "Placing GCPs" in banner.text()
    for x, y in off:
        QTest.mouseMove(w.view.plotter, QPoint(x, y))
        qtbot.mouseMove(w.view.plotter, QPoint(x, y))
        qtbot.waitUntil(lambda: w.coords.text() == "off the terrain", timeout=2000)
        qtbot.mouseClick(w.view.plotter, Qt.MouseButton.LeftButton, pos=QPoint(x, y))
    wait_idle(qtbot, w)
    assert w.document.project.targets == ()
    # over the terrain a click places a GCP and the status bar shows its ground
    x, y, ground = ground_pixels(w, 1)[0]
    qtbot.mouseMove(w.view.plotter, QPoint(x, y))
    qtbot.waitUntil(lambda: w.coords.text().startswith("E "), timeout=2000)
    hf = w.sync.terrain.heightfield
    assert ground[2] == pytest.approx(float(hf.height_at(ground[0], ground[1])), abs=0.01)
    qtbot.mouseClick(w.view.plotter, Qt.MouseButton.LeftButton, pos=QPoint(x, y))
    assert len(w.document.project.targets) == 1


def test_mode_banner_and_esc_leave_any_mode(qtbot, window):
    w = window
    w.activateWindow()
    qtbot.waitUntil(w.isActiveWindow)
    w.editor.edit(edits.ensure_flight_plan(w.document.project), "flight")
    wait_idle(qtbot, w)
    banner = w.view.mode_banner
    assert not banner.isVisible()
    for start, words in ((lambda: w.panels["GCPs"].place.setChecked(True), "Placing GCPs"),
                         (lambda: w.panels["Flight"].draw.setChecked(True),
                          "Drawing the survey area")):
        start()
        assert banner.isVisible() and words in banner.text()
        # Esc with the focus in the view, then with it in a panel field
        w.view.plotter.setFocus()
        qtbot.waitUntil(w.view.plotter.hasFocus)
        QTest.keyClick(w.windowHandle(), Qt.Key.Key_Escape)
        assert w.view.interaction.mode == "navigate" and not banner.isVisible()
        start()
        assert w.view.interaction.mode != "navigate"
        box = w.panels["Flight"].altitude_spin
        w.docks["Flight"].raise_()
        box.setFocus()
        qtbot.waitUntil(box.hasFocus)
        QTest.keyClick(w.windowHandle(), Qt.Key.Key_Escape)
        assert w.view.interaction.mode == "navigate" and not banner.isVisible()
    assert not w.panels["GCPs"].place.isChecked() and not w.panels["Flight"].draw.isChecked()
