"""Mouse work in the 3D view: ground under the cursor, placing and dragging GCPs, drawing
the survey area. A Qt event filter on the interactor widget, so the camera controls of
VTK keep working whenever the filter lets an event through.

Modes:

* ``navigate``: VTK's trackball camera; the ground under the cursor goes to the status bar.
* ``place``: a left click (press and release within a few pixels) on the ground places
  a GCP; a left press on an existing GCP drags it (released: moved). Dragging
  elsewhere still turns the camera.
* ``area``: each left click adds a vertex of the survey area; a double click, a right
  click or Enter closes it (3 vertices at least); Esc cancels.

The ground point comes from ``ground_picker(origin, direction) -> (3,) | None`` (a
height-field ray cast, set by the scene sync) or, without one, from the terrain actor.
A click where the ray meets no terrain top (the sky, the background, the side of the
terrain block) does nothing; the status bar then reads "off the terrain". Esc leaves
any mode.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from PySide6.QtCore import QEvent, QObject, Qt, Signal

#: a press and release closer than this (px) is a click, not a drag
CLICK_PX = 4
#: a GCP within this many pixels' worth of ground of the cursor can be grabbed
GRAB_PX = 12


class ViewInteraction(QObject):
    mode_changed = Signal(str)

    def __init__(self, view) -> None:
        super().__init__(view)
        self.view = view
        self.mode = "navigate"
        self.ground_picker: Callable[[np.ndarray, np.ndarray], np.ndarray | None] | None = None
        self._press: tuple[float, float] | None = None
        self._dragging: str | None = None
        self._area: list[np.ndarray] = []
        self._swallow_release = False
        view.plotter.installEventFilter(self)

    def detach(self) -> None:
        self.view.plotter.removeEventFilter(self)

    # ------------------------------------------------------------------ API
    def set_mode(self, mode: str) -> None:
        if mode not in ("navigate", "place", "area"):
            raise ValueError(mode)
        self._cancel()
        if mode != self.mode:
            self.mode = mode
            self.mode_changed.emit(mode)

    def ground_at(self, x_px: float, y_px: float) -> np.ndarray | None:
        """The ground point (world, m) under widget pixel (x, y), or None."""
        if self.ground_picker is not None:
            origin, direction = self.view.ray_through(x_px, y_px)
            hit = self.ground_picker(origin, direction)
            if hit is None or not np.all(np.isfinite(hit)):
                return None
            return np.asarray(hit, dtype=float)
        return self.view.pick_terrain_actor(x_px, y_px)

    def target_near(self, x_px: float, y_px: float) -> str | None:
        """Id of the GCP drawn closest to a pixel, if within GRAB_PX."""
        best, best_d = None, float(GRAB_PX)
        ren = self.view.plotter.renderer
        h = self.view.plotter.height()
        dpr = self.view.plotter.devicePixelRatioF()
        for target_id, xyz in self.view.target_positions():
            ren.SetWorldPoint(*(xyz - self.view.offset), 1.0)
            ren.WorldToDisplay()
            xd, yd, _ = ren.GetDisplayPoint()
            d = float(np.hypot(xd / dpr - x_px, (h - 1 - yd / dpr) - y_px))
            if d < best_d:
                best, best_d = target_id, d
        return best

    # ------------------------------------------------------------------ events
    def eventFilter(self, obj, event) -> bool:
        kind = event.type()
        if kind == QEvent.Type.MouseMove:
            return self._move(event)
        if kind == QEvent.Type.MouseButtonPress:
            return self._pressed(event)
        if kind == QEvent.Type.MouseButtonDblClick:
            return self._double(event)
        if kind == QEvent.Type.MouseButtonRelease:
            return self._released(event)
        if kind == QEvent.Type.KeyPress and event.key() == Qt.Key.Key_Escape \
                and self.mode != "navigate":
            self.set_mode("navigate")  # Esc leaves any mode (and drops a half-drawn area)
            return True
        if kind == QEvent.Type.KeyPress and self.mode == "area":
            if event.key() in (Qt.Key.Key_Return, Qt.Key.Key_Enter):
                self._finish_area()
                return True
        if kind == QEvent.Type.Leave:
            self.view.ground_hovered.emit(None)
        return False

    def _pos(self, event) -> tuple[float, float]:
        p = event.position()
        return float(p.x()), float(p.y())

    def _move(self, event) -> bool:
        x, y = self._pos(event)
        ground = self.ground_at(x, y)
        # the readout is of the point a click picks: a drawn cloud's point under the
        # cursor, else the ground; () : the cursor is over the view but not the terrain
        k = self.view.cloud_point_at(x, y)
        hovered = ground if k is None else self.view.cloud_point_world(k)
        self.view.ground_hovered.emit(() if hovered is None else tuple(hovered))
        if self._dragging is not None:
            if ground is not None:
                self.view.show_polygon("draft", np.array([ground, ground + [0, 0, 0.01]]),
                                       closed=False)
            return True
        if self.mode == "area" and self._area and ground is not None:
            self.view.show_polygon("draft", np.array([*self._area, ground]), closed=False)
        return False

    def _pressed(self, event) -> bool:
        if event.button() == Qt.MouseButton.RightButton and self.mode == "area":
            self._finish_area()
            return True
        if event.button() != Qt.MouseButton.LeftButton:
            return False
        x, y = self._pos(event)
        self._press = (x, y)
        if self.mode == "place":
            grabbed = self.target_near(x, y)
            if grabbed is not None:
                self._dragging = grabbed
                return True
        return self.mode == "area"

    def _released(self, event) -> bool:
        if event.button() != Qt.MouseButton.LeftButton:
            return self.mode == "area" and event.button() == Qt.MouseButton.RightButton
        x, y = self._pos(event)
        press, self._press = self._press, None
        clicked = press is not None and np.hypot(x - press[0], y - press[1]) <= CLICK_PX
        if self._dragging is not None:
            target_id, self._dragging = self._dragging, None
            self.view.show_polygon("draft", None)
            ground = self.ground_at(x, y)
            if ground is not None and not clicked:
                self.view.target_moved.emit(target_id, float(ground[0]), float(ground[1]))
            return True
        if self.mode == "area":
            if self._swallow_release:
                self._swallow_release = False
                return True
            ground = self.ground_at(x, y)
            if clicked and ground is not None:
                self._area.append(ground)
                self.view.show_polygon("draft", np.array(self._area), closed=False)
            return True
        if self.mode == "place" and clicked:
            ground = self.ground_at(x, y)
            if ground is not None:
                self.view.ground_clicked.emit(*(float(v) for v in ground))
        elif self.mode == "navigate" and clicked:
            self.view.clicked.emit(x, y)
        return False

    def _double(self, event) -> bool:
        if self.mode != "area" or event.button() != Qt.MouseButton.LeftButton:
            return False
        self._swallow_release = True
        self._finish_area()
        return True

    def _finish_area(self) -> None:
        vertices = [(float(p[0]), float(p[1])) for p in self._area]
        self._cancel()
        if len(vertices) >= 3:
            self.view.area_drawn.emit(vertices)

    def _cancel(self) -> None:
        self._area = []
        self._dragging = None
        self._press = None
        if self.view.has_layer("draft"):
            self.view.show_polygon("draft", None)
