"""Helpers of the Results tests: a cloud alone in the view, seen from above, and where one
of its points is on the screen (to click it)."""

from __future__ import annotations

import numpy as np

#: the view's layers that would hide the cloud or catch a click meant for it
SCENE_LAYERS = ("terrain", "targets", "frusta", "footprints", "flight", "area")


def cloud_seen_from_above(w) -> None:
    """Hide the scene's layers and look straight down on the opened cloud."""
    for layer in SCENE_LAYERS:
        w.view.set_layer_visible(layer, False)
    w.view.view_top()
    w.view.render_now()


def point_on_screen(w, xyz_world: np.ndarray):
    """The widget pixel (QPoint, from the plotter's top-left) where the world point
    ``xyz_world`` is drawn."""
    from PySide6.QtCore import QPoint

    ren = w.view.plotter.renderer
    ren.SetWorldPoint(*(np.asarray(xyz_world, dtype=float) - w.view.offset), 1.0)
    ren.WorldToDisplay()
    u, v, _ = ren.GetDisplayPoint()
    # VTK's display y runs up from the bottom row
    return QPoint(round(u), w.view.plotter.height() - 1 - round(v))
