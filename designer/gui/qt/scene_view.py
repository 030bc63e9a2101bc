"""The 3D view: the one class that owns the pyvistaqt ``QtInteractor``.

It knows nothing about the project model: :mod:`designer.gui.qt.scene_sync` hands it
arrays (world coordinates) per layer and it maps layer names to VTK actors, updating
an existing actor's data in place where it can. World coordinates are shifted by a
display offset (the terrain's centre) before they reach VTK, which renders in float32.

Layers: ``terrain``, ``surroundings``, ``objects``, ``targets`` (markers, checker plates,
labels), ``frusta``, ``footprints``, ``flight``, ``area``, ``coverage``, ``cloud``, plus
the interaction overlays of :mod:`designer.gui.qt.interaction`.
"""

from __future__ import annotations

import numpy as np
from PySide6.QtCore import Signal
from PySide6.QtWidgets import QLabel, QVBoxLayout, QWidget

from designer.gui.qt.interaction import ViewInteraction
from designer.gui.state.view_overlays import BAR_STYLE, CLOUD_BAR, COVERAGE_BAR, OverlayLayers
from designer.scene.objects import OBJECT_ALBEDO_RGB

ROLE_COLOURS = {"control": (0.85, 0.1, 0.1), "check": (0.1, 0.35, 0.95)}
LAYER_STYLE = {
    "frusta": {"color": (0.95, 0.75, 0.1), "line_width": 1.0},
    # opaque: a translucent layer costs a full-window compositing pass every frame
    "footprints": {"color": (0.82, 0.84, 0.86), "line_width": 1.0},
    "flight": {"color": (0.1, 0.9, 0.9), "line_width": 2.0},
    "area": {"color": (1.0, 0.3, 1.0), "line_width": 3.0},
    "draft": {"color": (1.0, 0.5, 0.0), "line_width": 3.0},
    "movers:paths": {"color": (0.55, 1.0, 0.2), "line_width": 2.0},  # apart from the rest
}
#: largest texture side sent to the GPU (px); the full image stays in the model's hands
MAX_DISPLAY_TEXTURE_PX = 2048
TERRAIN_COLOUR = (0.55, 0.6, 0.45)
#: the ground beyond the terrain's extent that renders include: lighter and plain, so the
#: terrain (the area of interest) stands out from it
SURROUNDINGS_COLOUR = (0.72, 0.75, 0.66)
#: beyond them, to the horizon, ground no image sees: darker, so it reads as not rendered
FAR_GROUND_COLOUR = (0.52, 0.55, 0.48)
#: its layer (a part of "surroundings": hidden and shown with it)
FAR_GROUND = "surroundings:far"
OBJECT_COLOUR = OBJECT_ALBEDO_RGB  # as the renderer draws them
#: the buildings' facades and roofs (about the mean colour of their textures)
FACADE_COLOUR, ROOF_COLOUR = (0.80, 0.72, 0.60), (0.58, 0.27, 0.17)
MODE_TEXT = {
    "place": "Placing GCPs: click the terrain to add one, drag a GCP to move it · "
             "Esc: stop placing",
    "area": "Drawing the survey area: click the corners, double-click or Enter to close · "
            "Esc: cancel",
}
SOFTWARE_RENDERERS = ("llvmpipe", "softpipe", "SwiftShader", "Software Rasterizer")


#: the panel: its colour, how much it hides of what is drawn behind it, and its margin
#: around the bar (normalised viewport: the end labels stand out half their width)
BAR_PANEL_COLOUR = (0.1, 0.11, 0.14)
BAR_PANEL_OPACITY = 0.85
BAR_PANEL_MARGIN = (0.05, 0.012)
#: the height of the bar's title line over the bar (normalised viewport)
BAR_TITLE_HEIGHT = 0.012

class SceneView(OverlayLayers, QWidget):
    """A QWidget holding the interactor; signals carry world coordinates (m)."""

    ground_hovered = Signal(object)          # (X, Y, Z), () off the terrain, None: left
    ground_clicked = Signal(float, float, float)
    target_moved = Signal(str, float, float)
    area_drawn = Signal(object)              # [(X, Y), …]
    clicked = Signal(float, float)           # a click (no drag) in navigate mode, px
    frame_rendered = Signal()

    def __init__(self, parent: QWidget | None = None) -> None:
        super().__init__(parent)
        import pyvista as pv
        from pyvistaqt import QtInteractor

        self._pv = pv
        # No timer-driven re-renders (auto_update) and no multisampling: on a software
        # OpenGL (Xvfb, CI) both cost far more than the frame itself.
        self.plotter = QtInteractor(self, auto_update=False, multi_samples=0)
        self.plotter.set_background("#20242c", top="#59667a")
        caps = self.plotter.ren_win.ReportCapabilities() or ""
        #: a software rasteriser (Mesa llvmpipe under Xvfb, CI): every pixel costs CPU
        self.software_gl = any(s in caps for s in SOFTWARE_RENDERERS)
        #: nodes per side of the drawn terrain (the height field itself keeps them all)
        self.max_display_nodes = 256 if self.software_gl else 1024
        if not self.software_gl:
            self.plotter.enable_anti_aliasing("fxaa")
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(0)
        # what a click does right now (shown only outside the navigate mode)
        self.mode_banner = QLabel()
        self.mode_banner.setObjectName("mode-banner")
        self.mode_banner.setStyleSheet(
            "QLabel { background: #f0b429; color: #1b1b1b; font-weight: bold; "
            "padding: 4px 8px; }")
        self.mode_banner.hide()
        layout.addWidget(self.mode_banner)
        layout.addWidget(self.plotter)
        self.offset = np.zeros(3)
        self._meshes: dict[str, object] = {}
        #: how to draw again the layers that survive a new display offset
        self._kept: dict[str, object] = {}
        self._visible: dict[str, bool] = {}
        self._texture = None
        self._irradiance: np.ndarray | None = None
        self._terrain_bounds: np.ndarray | None = None
        self._targets: list[tuple[str, np.ndarray, float]] = []
        #: the GCPs the error labels (layer "residuals") name
        self._residual_ids: set[str] = set()
        self.frames = 0
        self.plotter.ren_win.AddObserver("EndEvent", self._on_frame)
        self.interaction = ViewInteraction(self)
        self.interaction.mode_changed.connect(self._show_mode)
        self.plotter.add_axes(interactive=False, line_width=2, labels_off=False)

    # ------------------------------------------------------------------ basics
    def _show_mode(self, mode: str) -> None:
        self.mode_banner.setText(MODE_TEXT.get(mode, ""))
        self.mode_banner.setVisible(mode in MODE_TEXT)

    def _on_frame(self, *_args) -> None:
        self.frames += 1
        self.frame_rendered.emit()

    def request_render(self) -> None:
        """Schedule a repaint (several updates in one event-loop turn give one frame)."""
        self.plotter.update()

    def set_offset(self, offset_world: np.ndarray) -> None:
        """Change the display offset. Layers of the model must be set again afterwards;
        layers of results (the point cloud, GCP residuals) are redrawn here, as nothing
        else would bring them back."""
        self.offset = np.asarray(offset_world, dtype=float).copy()
        kept = dict(self._kept)
        for name in list(self._meshes):
            self.remove_layer(name)
        for draw in kept.values():
            draw()

    def local(self, points_world: np.ndarray) -> np.ndarray:
        return (np.asarray(points_world, dtype=float).reshape(-1, 3) - self.offset).astype(
            np.float32)

    def remove_layer(self, name: str) -> None:
        self._kept.pop(name, None)
        if self._meshes.pop(name, None) is not None:
            self.plotter.remove_actor(name, render=False)
        for part in (f"{name}-points", f"{name}-labels"):  # a label layer's two actors
            if part in self.plotter.actors:
                self.plotter.remove_actor(part, render=False)
        if name == "cloud":
            self._remove_scalar_bar(CLOUD_BAR)
        if name == "coverage":
            self._remove_scalar_bar(COVERAGE_BAR)
        if name == "residuals":
            for part in ("residuals:tips", "residuals:labels"):
                self._meshes.pop(part, None)
            for part in ("residuals:tips", "residuals:labels-points",
                         "residuals:labels-labels"):
                if part in self.plotter.actors:
                    self.plotter.remove_actor(part, render=False)
            if self._residual_ids:
                self._residual_ids = set()
                self._target_labels()

    def bar_panel(self, title: str) -> None:
        """Lay the colour bar ``title`` on a dark panel a margin larger than the bar (its
        end labels stand out half their width), its title on the panel's top line, apart
        from the tick labels (VTK sets a horizontal bar's title on top of its labels):
        ``{title}:panel`` and ``{title}:title``, removed with the bar."""
        import vtk

        bar = self.plotter.scalar_bars[title]
        bar.SetTitle("")  # drawn by the text actor below
        x0, y0 = bar.GetPositionCoordinate().GetValue()[:2]
        w, h = bar.GetPosition2Coordinate().GetValue()[:2]
        mx, my = BAR_PANEL_MARGIN
        top = y0 + h + BAR_TITLE_HEIGHT
        points = vtk.vtkPoints()
        for x, y in ((x0 - mx, y0 - my), (x0 + w + mx, y0 - my), (x0 + w + mx, top + my),
                     (x0 - mx, top + my)):
            points.InsertNextPoint(x, y, 0.0)
        quad = vtk.vtkCellArray()
        quad.InsertNextCell(4, [0, 1, 2, 3])
        rect = vtk.vtkPolyData()
        rect.SetPoints(points)
        rect.SetPolys(quad)
        where = vtk.vtkCoordinate()
        where.SetCoordinateSystemToNormalizedViewport()
        mapper = vtk.vtkPolyDataMapper2D()
        mapper.SetInputData(rect)
        mapper.SetTransformCoordinate(where)
        panel = vtk.vtkActor2D()
        panel.SetMapper(mapper)
        panel.GetProperty().SetColor(*BAR_PANEL_COLOUR)
        panel.GetProperty().SetOpacity(BAR_PANEL_OPACITY)
        self.plotter.add_actor(panel, name=f"{title}:panel", reset_camera=False,
                               render=False, pickable=False)
        text = vtk.vtkTextActor()
        text.SetInput(title)
        text.GetPositionCoordinate().SetCoordinateSystemToNormalizedViewport()
        text.GetPositionCoordinate().SetValue(x0 + w / 2, top - 0.004)
        style = text.GetTextProperty()
        style.SetFontSize(BAR_STYLE["title_font_size"])
        style.SetColor(1.0, 1.0, 1.0)
        style.SetJustificationToCentered()
        style.SetVerticalJustificationToTop()
        self.plotter.add_actor(text, name=f"{title}:title", reset_camera=False,
                               render=False, pickable=False)
        # overlays are drawn in the order they were added: the bar again, over its panel
        # (through vtkRenderer itself: pyvista's Renderer hides these methods)
        vtk.vtkRenderer.RemoveViewProp(self.plotter.renderer, bar)
        vtk.vtkRenderer.AddViewProp(self.plotter.renderer, bar)

    def _remove_scalar_bar(self, title: str) -> None:
        if title in self.plotter.scalar_bars:
            self.plotter.remove_scalar_bar(title, render=False)
        for part in (f"{title}:panel", f"{title}:title"):
            if part in self.plotter.actors:
                self.plotter.remove_actor(part, render=False)

    def has_layer(self, name: str) -> bool:
        return name in self._meshes

    def layer_data(self, name: str):
        """The pyvista dataset drawn for a layer (tests and benchmarks read it)."""
        return self._meshes.get(name)

    def set_layer_visible(self, name: str, visible: bool) -> None:
        self._visible[name] = visible
        for key, actor in self.plotter.actors.items():
            if key == name or key.startswith(name + ":"):
                actor.SetVisibility(visible)
        if name == "residuals":  # the GCPs it names are named by their own labels again
            self._target_labels()
        self.request_render()

    def _show(self, name: str, dataset, **style) -> None:
        """Draw ``dataset`` as layer ``name``: in place if the layer exists."""
        if dataset.n_points == 0:
            self.remove_layer(name)
            self.request_render()
            return
        old = self._meshes.get(name)
        if old is not None and type(old) is type(dataset) and not style.get("texture"):
            old.copy_from(dataset, deep=False)
        else:
            self.remove_layer(name)
            self.plotter.add_mesh(dataset, name=name, reset_camera=False, render=False,
                                  **style)
            self._meshes[name] = self.plotter.actors[name].mapper.dataset
        self.plotter.actors[name].SetVisibility(self._visible.get(name.split(":")[0], True))
        self.request_render()

    def _lines(self, points_world: np.ndarray, cells: np.ndarray):
        poly = self._pv.PolyData()
        if len(points_world) and len(cells):
            poly.points = self.local(points_world)
            poly.lines = np.asarray(cells, dtype=np.int64)
        return poly

    # ------------------------------------------------------------------ layers
    def show_terrain(self, points_world: np.ndarray, faces: np.ndarray, uv: np.ndarray,
                     texture_rgb: np.ndarray | None = None, linear: bool = True,
                     irradiance: np.ndarray | None = None) -> None:
        """The terrain mesh, textured; with ``irradiance`` (relative light per vertex,
        :func:`~designer.gui.state.view_geometry.shade_rgb`) it is drawn lit by the project's
        sun and sky, else by the view's own lights."""
        pv = self._pv
        faces = np.asarray(faces, dtype=np.int64)
        cells = np.column_stack([np.full(len(faces), 3), faces]).ravel()
        mesh = pv.PolyData(self.local(points_world), cells)
        mesh.active_texture_coordinates = np.asarray(uv, dtype=np.float32)
        first = self._terrain_bounds is None
        self._terrain_bounds = np.array([points_world.min(axis=0), points_world.max(axis=0)])
        if texture_rgb is not None:
            self._texture = self._make_texture(texture_rgb, linear)
        style = ({"texture": self._texture} if self._texture is not None
                 else {"color": TERRAIN_COLOUR})
        self._show("terrain", mesh, smooth_shading=False, **style)
        self.set_terrain_irradiance(irradiance)
        if first:
            self.reset_view()

    def show_surroundings(self, points_world: np.ndarray | None,
                          faces: np.ndarray | None) -> None:
        """The ground the renders include beyond the terrain (a coarse triangle ring,
        world m), in one plain colour lit by the view's lights; None: none."""
        if points_world is None or faces is None or not len(faces):
            self.remove_layer("surroundings")
            self.request_render()
            return
        f = np.asarray(faces, dtype=np.int64)
        mesh = self._pv.PolyData(self.local(points_world),
                                 np.column_stack([np.full(len(f), 3), f]).ravel())
        self._show("surroundings", mesh, color=SURROUNDINGS_COLOUR, smooth_shading=False)

    def show_far_ground(self, points_world: np.ndarray | None,
                        faces: np.ndarray | None) -> None:
        """Beyond the surroundings, to the horizon, ground no image sees: a plain skirt
        darker than the surroundings (None: none). Left out of what the top view frames."""
        if points_world is None or faces is None or not len(faces):
            self.remove_layer(FAR_GROUND)
            self.request_render()
            return
        f = np.asarray(faces, dtype=np.int64)
        mesh = self._pv.PolyData(self.local(points_world),
                                 np.column_stack([np.full(len(f), 3), f]).ravel())
        self._show(FAR_GROUND, mesh, color=FAR_GROUND_COLOUR, smooth_shading=False,
                   pickable=False)

    def set_terrain_irradiance(self, irradiance: np.ndarray | None) -> None:
        """Shade the terrain by a light value per vertex (None: the view's own lights).

        The colours are multiplied with the texture by the GPU, so no per-pixel lighting
        is left to compute: on a software OpenGL that is most of a frame's terrain cost.
        """
        from designer.gui.state.view_geometry import shade_rgb

        mesh, actor = self._meshes.get("terrain"), self.plotter.actors.get("terrain")
        if irradiance is not None and (mesh is None or len(irradiance) != mesh.n_points):
            irradiance = None  # computed for another mesh: wait for the matching one
        self._irradiance = irradiance
        if mesh is None or actor is None:
            return
        mapper = actor.GetMapper()
        if irradiance is None:
            mapper.ScalarVisibilityOff()
            actor.prop.lighting = True
        else:
            base = (1.0, 1.0, 1.0) if self._texture is not None else TERRAIN_COLOUR
            mesh.point_data["shade"] = shade_rgb(irradiance, base)
            mapper.SetScalarModeToUsePointFieldData()
            mapper.SelectColorArray("shade")
            mapper.SetColorModeToDirectScalars()
            mapper.ScalarVisibilityOn()
            actor.prop.lighting = False
        self.request_render()

    def _make_texture(self, rgb: np.ndarray, linear: bool):
        step = max(1, int(np.ceil(max(rgb.shape[:2]) / MAX_DISPLAY_TEXTURE_PX)))
        image = np.ascontiguousarray(rgb[::step, ::step, :3])
        texture = self._pv.Texture(image)
        texture.repeat = True
        texture.interpolate = linear
        texture.mipmap = linear
        return texture

    def set_terrain_uv(self, uv: np.ndarray) -> None:
        """New texture coordinates for the drawn terrain (same vertices)."""
        actor = self.plotter.actors.get("terrain")
        if actor is None:
            return
        mesh = actor.mapper.dataset
        mesh.active_texture_coordinates = np.asarray(uv, dtype=np.float32)
        self.request_render()

    def set_texture(self, rgb: np.ndarray | None, linear: bool = True) -> None:
        """Swap the terrain's texture (None: plain colour)."""
        self._texture = self._make_texture(rgb, linear) if rgb is not None else None
        actor = self.plotter.actors.get("terrain")
        if actor is None:
            return
        if self._texture is None:
            actor.texture = None
            actor.prop.color = TERRAIN_COLOUR
        else:
            actor.prop.color = (1.0, 1.0, 1.0)
            actor.texture = self._texture
        self.set_terrain_irradiance(self._irradiance)
        self.request_render()

    def show_targets(self, ids: list[str], roles: list[str], xyz_world: np.ndarray,
                     plates: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = ()) -> None:
        """Markers (coloured by role), labels and the checker plates of the GCPs."""
        pv = self._pv
        xyz = np.asarray(xyz_world, dtype=float).reshape(-1, 3)
        self._targets = [(i, p, 0.0) for i, p in zip(ids, xyz, strict=True)]
        for name in ("targets", "targets:labels", "targets:plates"):
            self.remove_layer(name)
        if not len(xyz):
            self.request_render()
            return
        markers = pv.PolyData(self.local(xyz))
        markers["rgb"] = (np.array([ROLE_COLOURS.get(r, (1, 1, 0)) for r in roles])
                          * 255).astype(np.uint8)
        self.plotter.add_mesh(markers, name="targets", scalars="rgb", rgb=True,
                              render_points_as_spheres=True, point_size=14,
                              reset_camera=False, render=False)
        self._meshes["targets"] = markers
        self._target_labels()
        if plates:
            v = np.vstack([p[0] for p in plates])
            starts = np.cumsum([0] + [len(p[0]) for p in plates[:-1]])
            f = np.vstack([p[1] + s for p, s in zip(plates, starts, strict=True)])
            colours = np.vstack([p[2] for p in plates])
            mesh = pv.PolyData(self.local(v),
                               np.column_stack([np.full(len(f), f.shape[1]), f]).ravel())
            mesh.cell_data["rgb"] = np.asarray(colours)[:, :3].astype(np.uint8)
            self.plotter.add_mesh(mesh, name="targets:plates", scalars="rgb", rgb=True,
                                  reset_camera=False, render=False, lighting=False)
            self._meshes["targets:plates"] = mesh
        for name in ("targets", "targets:labels", "targets:plates"):
            if name in self.plotter.actors:
                self.plotter.actors[name].SetVisibility(self._visible.get("targets", True))
        self.request_render()

    def _target_labels(self) -> None:
        """The GCPs' names over their markers, but for the GCPs the error labels name
        while they are shown (a small error would put both labels at one place)."""
        if "targets" not in self._meshes:
            return
        self._meshes.pop("targets:labels", None)
        for part in ("targets:labels-points", "targets:labels-labels"):
            if part in self.plotter.actors:
                self.plotter.remove_actor(part, render=False)
        named = (self._residual_ids if "residuals" in self._meshes
                 and self._visible.get("residuals", True) else set())
        shown = [(i, p) for i, p, _ in self._targets if i not in named]
        if shown:
            points = self.local(np.array([p for _, p in shown]))
            self.plotter.add_point_labels(
                points, [i for i, _ in shown], name="targets:labels", font_size=14,
                point_size=0, shape_opacity=0.55, text_color="white", always_visible=True,
                render=False, reset_camera=False)
            self._meshes["targets:labels"] = self._pv.PolyData(points)
            for part in ("targets:labels-points", "targets:labels-labels"):
                if part in self.plotter.actors:
                    self.plotter.actors[part].SetVisibility(self._visible.get("targets", True))
        self.request_render()

    def _show_faces(self, name: str, vertices_world: np.ndarray | None,
                    faces: np.ndarray | None, face_rgb) -> None:
        """Draw layer ``name``: one triangle mesh, each face in its colour (``face_rgb``:
        a function giving (M, 3) uint8, called only when there are faces), unlit (the
        colours carry the renderer's light); nothing when there are no faces."""
        self.remove_layer(name)
        if vertices_world is None or faces is None or not len(faces):
            self.request_render()
            return
        f = np.asarray(faces, dtype=np.int64)
        mesh = self._pv.PolyData(self.local(vertices_world),
                                 np.column_stack([np.full(len(f), 3), f]).ravel())
        mesh.cell_data["rgb"] = face_rgb()
        self.plotter.add_mesh(mesh, name=name, scalars="rgb", rgb=True, lighting=False,
                              reset_camera=False, render=False)
        self._meshes[name] = mesh
        self.plotter.actors[name].SetVisibility(self._visible.get(name, True))
        self.request_render()

    def show_objects(self, vertices_world: np.ndarray | None, faces: np.ndarray | None = None,
                     face_irradiance: np.ndarray | None = None) -> None:
        """The scene's mesh objects (one merged mesh), each face shaded by its light."""
        from designer.gui.state.view_geometry import shade_rgb

        self._show_faces("objects", vertices_world, faces,
                         lambda: shade_rgb(face_irradiance, OBJECT_COLOUR))

    def show_buildings(self, vertices_world: np.ndarray | None, faces: np.ndarray | None = None,
                       face_irradiance: np.ndarray | None = None,
                       face_roof: np.ndarray | None = None) -> None:
        """The buildings (one merged mesh): facades and roofs in their colours, each face
        shaded by its light."""
        from designer.gui.state.view_geometry import shade_rgb

        self._show_faces("buildings", vertices_world, faces, lambda: np.where(
            np.asarray(face_roof)[:, None], shade_rgb(face_irradiance, ROOF_COLOUR),
            shade_rgb(face_irradiance, FACADE_COLOUR)))

    def show_vegetation(self, vertices_world: np.ndarray | None,
                        faces: np.ndarray | None = None,
                        face_albedo: np.ndarray | None = None) -> None:
        """The plants (one merged mesh), each face in its albedo lit as flat open ground,
        as the renderer draws them."""
        from designer.gui.state.view_geometry import flat_lit_rgb

        self._show_faces("vegetation", vertices_world, faces, lambda: flat_lit_rgb(face_albedo))

    def show_moving(self, shown) -> None:
        """The moving objects (a ``moving_view.MovingDisplay``, None: none): each posed at
        the drawn moment in its albedo lit as flat open ground, as the renderer draws
        them, and their paths."""
        from designer.gui.state.view_geometry import flat_lit_rgb

        if shown is None:
            self._show_faces("movers", None, None, None)
            self.remove_layer("movers:paths")
            return
        self._show_faces("movers", shown.vertices_world, shown.faces,
                         lambda: flat_lit_rgb(shown.face_albedo))
        self._show("movers:paths", self._lines(shown.path_points, shown.path_lines),
                   **LAYER_STYLE["movers:paths"])

    def target_positions(self) -> list[tuple[str, np.ndarray]]:
        return [(i, p) for i, p, _ in self._targets]

    def show_stations(self, geometry) -> None:
        """Frusta, footprints and flight lines of a :class:`StationGeometry` (or None)."""
        if geometry is None:
            for name in ("frusta", "footprints", "flight"):
                self.remove_layer(name)
            self.request_render()
            return
        self._show("frusta", self._lines(geometry.frustum_points, geometry.frustum_lines),
                   **LAYER_STYLE["frusta"])
        self._show("footprints", self._lines(geometry.footprint_points,
                                             geometry.footprint_lines),
                   **LAYER_STYLE["footprints"])
        self._show("flight", self._lines(geometry.flight_points, geometry.flight_lines),
                   **LAYER_STYLE["flight"])
        self.plotter.reset_camera_clipping_range()  # the nearest stations not cut off

    def show_polygon(self, name: str, xyz_world: np.ndarray | None, closed: bool = True) -> None:
        """A polyline (the survey area, the area being drawn)."""
        if xyz_world is None or len(xyz_world) < 2:
            self.remove_layer(name)
            self.request_render()
            return
        n = len(xyz_world)
        ids = np.r_[np.arange(n), 0] if closed else np.arange(n)
        self._show(name, self._lines(xyz_world, np.r_[len(ids), ids]), **LAYER_STYLE[name])

    # ------------------------------------------------------------------ camera
    def reset_view(self) -> None:
        """An oblique view from the south over the whole terrain."""
        if self._terrain_bounds is None:
            self.plotter.reset_camera()
            return
        lo, hi = self._terrain_bounds - self.offset
        centre = (lo + hi) / 2
        radius = 0.5 * float(max(np.linalg.norm(hi[:2] - lo[:2]), 1.0))
        cam = self.plotter.camera
        aspect = self.plotter.width() / max(1, self.plotter.height())
        half_v = np.radians(cam.view_angle) / 2
        half = min(half_v, np.arctan(np.tan(half_v) * aspect))
        distance = 1.05 * radius / np.sin(half)
        direction = np.array([0.0, -0.77, 0.64])  # from the south, 40° above the horizon
        cam.focal_point = tuple(centre)
        cam.position = tuple(centre + distance * direction)
        cam.up = (0.0, 0.0, 1.0)
        self.plotter.camera_set = True  # else pyvista picks its own view at the first frame
        self.plotter.reset_camera_clipping_range()
        self.request_render()

    def view_top(self) -> None:
        far = self.plotter.actors.get(FAR_GROUND)
        shown = bool(far.GetVisibility()) if far is not None else False
        if far is not None:  # framed on what images see, not on the far ground
            far.SetVisibility(False)
        self.plotter.view_xy()
        if far is not None:
            far.SetVisibility(shown)
            self.plotter.reset_camera_clipping_range()
        self.request_render()

    # ------------------------------------------------------------------ output
    def render_now(self) -> None:
        """Render synchronously (screenshots, benchmarks)."""
        before = self.frames
        self.plotter.repaint()
        if self.frames == before:
            # Qt skipped the paint (the window not exposed at this moment): render anyway,
            # so that what is read back afterwards is the current scene
            self.plotter.ren_win.Render()

    def ray_through(self, x_px: float, y_px: float) -> tuple[np.ndarray, np.ndarray]:
        """World ray (origin, unit direction) through widget pixel (x, y), y down."""
        ren = self.plotter.renderer
        dpr = self.plotter.devicePixelRatioF()
        xd, yd = x_px * dpr, (self.plotter.height() - y_px - 1) * dpr
        ends = []
        for depth in (0.0, 1.0):
            ren.SetDisplayPoint(xd, yd, depth)
            ren.DisplayToWorld()
            w = np.array(ren.GetWorldPoint(), dtype=float)
            ends.append(w[:3] / w[3])
        direction = ends[1] - ends[0]
        return ends[0] + self.offset, direction / np.linalg.norm(direction)

    def pick_terrain_actor(self, x_px: float, y_px: float) -> np.ndarray | None:
        """Ground point under a pixel from the terrain actor itself (mesh terrains)."""
        import vtk

        actor = self.plotter.actors.get("terrain")
        if actor is None:
            return None
        picker = vtk.vtkCellPicker()
        picker.SetTolerance(0.0005)
        picker.PickFromListOn()
        picker.AddPickList(actor)
        dpr = self.plotter.devicePixelRatioF()
        if not picker.Pick(x_px * dpr, (self.plotter.height() - y_px - 1) * dpr, 0,
                           self.plotter.renderer):
            return None
        return np.array(picker.GetPickPosition(), dtype=float) + self.offset

    def close_view(self) -> None:
        """Release the interactor and its OpenGL context (called from closeEvent)."""
        self.interaction.detach()
        self.plotter.close()
