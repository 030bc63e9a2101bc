"""Layers of the 3D view that show results over the scene: the coverage heat map, a
point cloud coloured by its signed distance (its colour range, picking a point), GCP
errors as lines; and framing the view on what is drawn. Mixed into
:class:`~designer.gui.qt.scene_view.SceneView`, whose layer bookkeeping (``_show``,
``_meshes``, ``_kept``, ``_visible``, ``local``, ``offset``) they use. Coordinates are
world (m) in, local (world − offset) to VTK."""

from __future__ import annotations

import numpy as np

#: colour bars: white text on a dark panel of their own (``SceneView.bar_panel``),
#: so they read over the light surroundings as over the dark background, and nothing
#: drawn in the scene runs through their labels
BAR_STYLE = {"color": "white", "shadow": False, "title_font_size": 16,
             "label_font_size": 14, "vertical": False, "position_x": 0.3,
             "position_y": 0.03, "height": 0.09, "width": 0.4}
RESIDUAL_COLOUR = (1.0, 0.85, 0.1)
#: the cloud's colour bar (and the name of its scalars): in mm, as the histogram and
#: every distance of the Results panel
CLOUD_BAR = "signed distance (mm)"
#: the coverage heat map's colour bar
COVERAGE_BAR = "images seeing the ground"


class OverlayLayers:
    """The result layers of :class:`~designer.gui.qt.scene_view.SceneView` (a mixin)."""

    def show_coverage(self, grid_xyz_world: np.ndarray, shape: tuple[int, int],
                      counts: np.ndarray) -> None:
        """The coverage heat map: images seeing each ground cell, draped 5 cm up."""
        pv = self._pv
        ny, nx = shape
        pts = self.local(grid_xyz_world + [0.0, 0.0, 0.05])
        grid = pv.StructuredGrid(pts[:, 0].reshape(ny, nx), pts[:, 1].reshape(ny, nx),
                                 np.nan_to_num(pts[:, 2]).reshape(ny, nx))
        grid["images"] = np.asarray(counts, dtype=float).ravel(order="C")
        grid = grid.threshold(0.5, scalars="images")
        self.remove_layer("coverage")
        self.plotter.add_mesh(grid, name="coverage", scalars="images", cmap="viridis",
                              opacity=0.6, reset_camera=False, render=False,
                              scalar_bar_args={"title": COVERAGE_BAR,
                                               **BAR_STYLE, "position_y": 0.44})
        self.bar_panel(COVERAGE_BAR)
        self._meshes["coverage"] = grid
        self.request_render()

    def show_cloud_shadows(self, points_world: np.ndarray | None,
                           faces: np.ndarray | None = None,
                           darkening: np.ndarray | None = None) -> None:
        """The cloud shadows laid over the terrain (None: none): black, each vertex as
        opaque as the share of light it loses, so the ground under it is drawn that much
        darker. Pulled towards the camera a little so it is never hidden in the ground
        it lies on."""
        if points_world is None or not len(points_world):
            self.remove_layer("cloud-shadows")
            self.request_render()
            return
        pv = self._pv
        f = np.asarray(faces, dtype=np.int64)
        mesh = pv.PolyData(self.local(points_world),
                           np.column_stack([np.full(len(f), 3), f]).ravel())
        rgba = np.zeros((len(mesh.points), 4), dtype=np.uint8)
        rgba[:, 3] = np.round(255 * np.clip(darkening, 0.0, 1.0))
        mesh.point_data["shadow"] = rgba
        self.remove_layer("cloud-shadows")
        self.plotter.add_mesh(mesh, name="cloud-shadows", scalars="shadow", rgba=True,
                              lighting=False, show_scalar_bar=False, reset_camera=False,
                              render=False, pickable=False)
        actor = self.plotter.actors["cloud-shadows"]
        actor.mapper.SetRelativeCoincidentTopologyPolygonOffsetParameters(-2, -2)
        actor.SetVisibility(self._visible.get("cloud-shadows", True))
        self._meshes["cloud-shadows"] = mesh
        self.request_render()

    def show_cloud(self, points_world: np.ndarray, distances_m: np.ndarray,
                   limit_m: float) -> None:
        """A point cloud coloured by signed distance, diverging map centred on 0 (the
        distances are given in m, drawn and written on the colour bar in mm)."""
        pv = self._pv
        cloud = pv.PolyData(self.local(points_world))
        cloud[CLOUD_BAR] = 1000 * np.asarray(distances_m, dtype=float)
        self.remove_layer("cloud")
        lim = 1000 * limit_m
        self.plotter.add_mesh(cloud, name="cloud", scalars=CLOUD_BAR,
                              cmap="RdBu_r", clim=(-lim, lim), point_size=3,
                              render_points_as_spheres=False, reset_camera=False,
                              render=False, scalar_bar_args={"title": CLOUD_BAR,
                                                             "fmt": "%.1f", **BAR_STYLE})
        self.bar_panel(CLOUD_BAR)
        self._meshes["cloud"] = cloud
        self._cloud_world = np.asarray(points_world, dtype=float)
        self._kept["cloud"] = lambda: self.show_cloud(points_world, distances_m, limit_m)
        self.plotter.actors["cloud"].SetVisibility(self._visible.get("cloud", True))
        self.request_render()

    def set_cloud_range(self, limit_m: float) -> None:
        """Colour the cloud over ±limit_m (beyond: the end colours)."""
        actor = self.plotter.actors.get("cloud")
        if actor is None:
            return
        actor.mapper.scalar_range = (-1000 * limit_m, 1000 * limit_m)
        mesh = self._meshes["cloud"]
        points = np.asarray(mesh.points, dtype=float) + self.offset
        d = np.asarray(mesh[CLOUD_BAR], dtype=float) / 1000
        self._kept["cloud"] = lambda: self.show_cloud(points, d, limit_m)
        self.request_render()

    def cloud_point_at(self, x_px: float, y_px: float, radius_px: float = 6.0) -> int | None:
        """Index of the cloud point drawn nearest a widget pixel (y down), within
        ``radius_px``, or None."""
        mesh = self._meshes.get("cloud")
        if mesh is None or not self._visible.get("cloud", True):
            return None
        ren = self.plotter.renderer
        w, h = self.plotter.width(), self.plotter.height()
        m4 = ren.GetActiveCamera().GetCompositeProjectionTransformMatrix(
            w / max(h, 1), -1, 1)
        M = np.array([[m4.GetElement(i, j) for j in range(4)] for i in range(4)])
        # the points on the screen, kept while neither the camera nor the cloud changes
        # (the cursor's readout asks at every mouse move)
        key = (id(mesh), mesh.n_points, w, h, M.tobytes())
        if getattr(self, "_cloud_screen", (None,))[0] != key:
            p = np.asarray(mesh.points, dtype=float)
            clip = np.c_[p, np.ones(len(p))] @ M.T
            with np.errstate(divide="ignore", invalid="ignore"):
                ndc = clip[:, :3] / clip[:, 3:4]
            self._cloud_screen = (key, (ndc[:, 0] + 1) / 2 * w, (1 - ndc[:, 1]) / 2 * h,
                                  ndc, clip[:, 3])
        _key, u, v, ndc, depth = self._cloud_screen
        r = np.hypot(u - x_px, v - y_px)
        near = np.flatnonzero((r <= radius_px) & (depth > 0) & (np.abs(ndc[:, 2]) <= 1))
        if not near.size:
            return None
        # the nearest on screen; of points drawn on the same pixel, the one in front
        return int(near[np.lexsort((ndc[near, 2], np.round(r[near])))[0]])

    def cloud_point_world(self, index: int) -> np.ndarray:
        """The world position (3,) of the drawn cloud's point ``index``, as given."""
        return self._cloud_world[index]

    def show_residuals(self, start_world: np.ndarray, end_world: np.ndarray,
                       labels: list[str], title: str, ids: list[str] = ()) -> None:
        """GCP errors as lines from each true position to its (exaggerated) estimate,
        with a label per line; kept across display offset changes like the cloud.
        ``ids``: the GCPs the labels name (their own name labels are not drawn while
        the error labels are shown, so the two do not cover each other)."""
        start = np.asarray(start_world, dtype=float).reshape(-1, 3)
        end = np.asarray(end_world, dtype=float).reshape(-1, 3)
        ids = list(ids)
        self.remove_layer("residuals")
        if not len(start):
            self.request_render()
            return
        n = len(start)
        cells = np.column_stack([np.full(n, 2), np.arange(n), np.arange(n) + n]).ravel()
        lines = self._lines(np.vstack([start, end]), cells)
        self.plotter.add_mesh(lines, name="residuals", color=RESIDUAL_COLOUR, line_width=4,
                              reset_camera=False, render=False, lighting=False)
        self._meshes["residuals"] = lines
        tips = self._pv.PolyData(self.local(end))
        self.plotter.add_mesh(tips, name="residuals:tips", color=RESIDUAL_COLOUR,
                              point_size=9, render_points_as_spheres=True,
                              reset_camera=False, render=False)
        self._meshes["residuals:tips"] = tips
        self.plotter.add_point_labels(
            self.local(end), labels, name="residuals:labels", font_size=12, point_size=0,
            shape_opacity=0.5, text_color="yellow", always_visible=True, render=False,
            reset_camera=False)
        self._meshes["residuals:labels"] = tips
        self.residual_title = title
        for name in ("residuals", "residuals:tips", "residuals:labels-points",
                     "residuals:labels-labels"):
            if name in self.plotter.actors:
                self.plotter.actors[name].SetVisibility(self._visible.get("residuals", True))
        self._kept["residuals"] = lambda: self.show_residuals(start, end, labels, title, ids)
        self._residual_ids = set(ids)
        self._target_labels()
        self.request_render()

    def frame_all(self, extra_points_world: np.ndarray | None = None) -> None:
        """Fit the view (keeping its direction) to the terrain and ``extra_points``."""
        boxes = []
        if self._terrain_bounds is not None:
            boxes.append(self._terrain_bounds)
        if extra_points_world is not None and len(extra_points_world):
            p = np.asarray(extra_points_world, dtype=float).reshape(-1, 3)
            p = p[np.all(np.isfinite(p), axis=1)]
            if len(p):
                boxes.append(np.array([p.min(axis=0), p.max(axis=0)]))
        if not boxes:
            self.plotter.reset_camera()
            return
        lo = np.min([b[0] for b in boxes], axis=0) - self.offset
        hi = np.max([b[1] for b in boxes], axis=0) - self.offset
        self.plotter.reset_camera(bounds=(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]))
        self.plotter.reset_camera_clipping_range()
        self.request_render()

    def _ndc(self, points_world: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Normalised device coordinates (N, 3) of world points and their clip w (N,):
        positive in front of the camera."""
        p = np.asarray(points_world, dtype=float).reshape(-1, 3) - self.offset
        w, h = self.plotter.width(), self.plotter.height()
        m4 = self.plotter.renderer.GetActiveCamera().GetCompositeProjectionTransformMatrix(
            w / max(h, 1), -1, 1)
        M = np.array([[m4.GetElement(i, j) for j in range(4)] for i in range(4)])
        clip = np.c_[p, np.ones(len(p))] @ M.T
        with np.errstate(divide="ignore", invalid="ignore"):
            return clip[:, :3] / clip[:, 3:4], clip[:, 3]

    def in_view(self, points_world: np.ndarray) -> np.ndarray:
        """(N,) True where a point projects inside the view, in front of the camera."""
        ndc, depth = self._ndc(points_world)
        return (depth > 0) & np.all(np.abs(ndc[:, :2]) <= 1, axis=1)

    def point_near(self, points_world: np.ndarray, x_px: float, y_px: float,
                   radius_px: float) -> int | None:
        """Index of the world point drawn nearest a widget pixel (y down), within
        ``radius_px`` and in front of the camera, or None; of points drawn on the same
        pixel, the one nearer the camera."""
        ndc, depth = self._ndc(points_world)
        w, h = self.plotter.width(), self.plotter.height()
        r = np.hypot((ndc[:, 0] + 1) / 2 * w - x_px, (1 - ndc[:, 1]) / 2 * h - y_px)
        # in front of the camera; not tested against the clipping range, which the
        # renderer fits to the drawn layers only at the next frame
        near = np.flatnonzero((r <= radius_px) & (depth > 0))
        if not near.size:
            return None
        return int(near[np.lexsort((depth[near], np.round(r[near])))[0]])

    def show_selected_station(self, C_world: np.ndarray | None, name: str = "") -> None:
        """The selected photo's camera station: a white dot on its perspective centre,
        labelled with the image's name (None: no photo selected)."""
        self.remove_layer("selected-station")
        if C_world is not None:
            points = self.local(C_world)
            self.plotter.add_point_labels(
                points, [name], name="selected-station", font_size=14, point_size=14,
                point_color="white", render_points_as_spheres=True, shape_opacity=0.55,
                text_color="white", always_visible=True, render=False, reset_camera=False)
            self._meshes["selected-station"] = self._pv.PolyData(points)
            # the camera's near and far planes fitted to what is drawn now: a station
            # above the view's clipping range would not show its mark
            self.plotter.reset_camera_clipping_range()
        self.request_render()

    def cloud_lookup_table(self):
        actor = self.plotter.actors.get("cloud")
        return None if actor is None else actor.mapper.lookup_table
