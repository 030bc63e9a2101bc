"""The 3D view's colour bars read on any ground (issue 53, finding 8: white ticks on the
light surroundings, the title crowding the tick labels, a drawn line through "-30.5"):
each bar lies on a dark panel of its own that hides what is drawn behind it, with the
tick labels on the far side of the colour strip from the title."""

from __future__ import annotations

import numpy as np
import pytest

from designer.gui.state.view_overlays import CLOUD_BAR
from designer.project import template, write_project
from tests.gui.helpers import open_panel, problems, wait_idle, write_xyz_ply

pytestmark = pytest.mark.gui


def _bar_pixels(w, title: str) -> np.ndarray:
    """The view's pixels (H, W, 3) inside the colour bar's rectangle."""
    plotter = w.view.plotter
    bar = plotter.scalar_bars[title]
    image = np.asarray(plotter.screenshot(return_img=True))
    h, wid = image.shape[:2]
    x0, y0 = bar.GetPositionCoordinate().GetValue()[:2]
    dx, dy = bar.GetPosition2Coordinate().GetValue()[:2]
    rows = slice(int(h * (1 - y0 - dy)), int(h * (1 - y0)))
    cols = slice(int(wid * x0), int(wid * (x0 + dx)))
    return image[rows, cols, :3]


def test_the_cloud_colour_bar_reads_on_light_ground(qtbot, window, tmp_path):
    w = window
    path = tmp_path / "survey.xml"
    write_project(template("survey").project, path)
    assert w.file_actions.open(path), problems(w)
    wait_idle(qtbot, w)
    hf = w.sync.terrain.heightfield
    e = w.document.project.scene.terrain.extent
    rng = np.random.default_rng(5)
    x = rng.uniform(e.min_X + 5, e.max_X - 5, 2000)
    y = rng.uniform(e.min_Y + 5, e.max_Y - 5, 2000)
    xyz = np.column_stack([x, y, hf.height_at(x, y) + rng.normal(0, 0.02, len(x))])
    write_xyz_ply(tmp_path / "cloud.ply", xyz)
    open_panel(w, "Results").open_cloud(tmp_path / "cloud.ply")
    wait_idle(qtbot, w)

    bar = w.view.plotter.scalar_bars[CLOUD_BAR]
    # on a panel of its own, under it, and the title kept apart from the labels
    assert f"{CLOUD_BAR}:panel" in w.view.plotter.actors
    # the title on a line of its own above the labels (VTK's own sat on top of them)
    assert bar.GetTitle() == "" and f"{CLOUD_BAR}:title" in w.view.plotter.actors
    # light ground everywhere behind the bar (the brightest a scene can be): the bar's
    # rectangle still reads as a dark panel with white text on it
    w.view.plotter.set_background("white")
    w.view.render_now()
    pixels = _bar_pixels(w, CLOUD_BAR).astype(float)
    # the rows of the colour strip: its blue end at the left
    left = pixels[:, 2:8].mean(axis=1)
    strip = left[:, 2] > left[:, 0] + 40
    assert strip.any()
    text_rows = pixels[~strip]
    luminance = text_rows.mean(axis=2)
    assert (luminance < 110).mean() > 0.6, (luminance < 110).mean()  # a dark panel …
    assert (luminance > 200).sum() > 150, (luminance > 200).sum()  # … with white text

