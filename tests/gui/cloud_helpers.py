"""Helpers of the Results tests: a cloud alone in the view, seen from above, and where one
of its points is on the screen (to click it)."""

from __future__ import annotations

import numpy as np

#: the view's layers that would hide the cloud or catch a click meant for it
SCENE_LAYERS = ("terrain", "targets", "frusta", "footprints", "flight", "area")


def cloud_seen_from_above(w) -> None:
    """Hide the scene's layers and look straight down on the opened cloud, framed on its
    points (their 1st to 99th percentiles: an outlier far below stays out of the frame,
    and the points lie pixels apart instead of in a heap of a few dozen pixels)."""
    for layer in SCENE_LAYERS:
        w.view.set_layer_visible(layer, False)
    w.view.view_top()
    local = w.panels["Results"].result.points_world - w.view.offset
    lo, hi = np.percentile(local, [1, 99], axis=0)
    w.view.plotter.renderer.ResetCamera(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2])
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


def isolated_point(w, points_world: np.ndarray, radius_px: float = 8.0) -> int:
    """Index of the first point drawn with no other point within ``radius_px`` on the
    screen (a click there can mean only it: the view frames the whole scene, and a cloud
    of a few hundred points has neighbours a pixel apart)."""
    screen = np.array([(p.x(), p.y()) for p in (point_on_screen(w, q) for q in points_world)],
                      dtype=float)
    for k in range(len(screen)):
        d = np.hypot(*(screen - screen[k]).T)
        d[k] = np.inf
        if d.min() > radius_px:
            return k
    raise AssertionError(f"no point of the cloud lies {radius_px} px from every other")
