"""Keeps the 3D view in step with the document: model events in, view updates out.

On each ``project`` event it looks at which parts changed and recomputes only what
depends on them, in worker threads (:class:`~designer.gui.qt.tasks.TaskRunner`):

terrain → height field, ray caster, display mesh and its light → targets, stations,
coverage; texture → texture image (1–2 s for a procedural one) and the display UVs;
lighting → the light on the drawn terrain and objects, the cloud shadows drawn over it;
objects → the placed meshes, the buildings and the plants (also rebuilt on the new
terrain);
cameras / trajectory / render → stations (frusta, footprints, flight lines, figures) and
the surroundings the renders include (planned from the images).

Panels read the latest results (``terrain``, ``stations``, ``texture_rgb``) and listen to
the ``*_changed`` signals; errors arrive as messages (a half-typed flight plan is not an
exception, it is a message in the Flight panel).
"""

from __future__ import annotations

import dataclasses

import numpy as np
from PySide6.QtCore import QObject, Signal

from designer.errors import DesignerError
from designer.gui.qt.photo_selection import FOLLOW_SELECTION, PhotoSelection
from designer.gui.qt.tasks import TaskRunner
from designer.gui.state import derived
from designer.gui.state.document import ProjectDocument
from designer.gui.state.moving_view import moving_display
from designer.project import model as m

TERRAIN_PARTS = {"terrain"}
#: a picked point farther than this (m) from the terrain's top surface is not ground
GROUND_TOLERANCE_M = 0.05
STATION_PARTS = {"cameras", "trajectory", "render", "terrain"}


#: why the Flight panel has no figures while camera stations are under the ground
UNDER_THE_GROUND = ("no figures over the terrain: camera stations are under the ground "
                    "(see Problems)")


def _message(error: BaseException) -> str:
    from designer.gui.state.wording import error_text, humanize

    if isinstance(error, DesignerError | ValueError | KeyError | OSError):
        return error_text(error)
    return f"{type(error).__name__}: {humanize(str(error))}"


class SceneSync(PhotoSelection, QObject):
    terrain_changed = Signal()
    texture_changed = Signal()
    targets_changed = Signal()
    stations_changed = Signal()
    coverage_changed = Signal()
    lighting_changed = Signal()
    plan_changed = Signal()
    #: the plan figures started or stopped being computed (``plan_computing``)
    plan_computing_changed = Signal()
    #: the problems found over what is drawn (camera stations under the ground) changed
    problems_changed = Signal()
    message = Signal(str)
    #: an error's message: it holds until the error goes (``message_withdrawn``) or a
    #: later message replaces it
    error_message = Signal(str)
    #: a message posted by ``error_message`` that no longer holds (its error went)
    message_withdrawn = Signal(str)
    #: a photo was selected (its station's index) or none is (None):
    #: designer.gui.qt.photo_selection
    photo_selected = Signal(object)

    def __init__(self, document: ProjectDocument, view, tasks: TaskRunner) -> None:
        super().__init__(view)
        self.document, self.view, self.tasks = document, view, tasks
        self.terrain: derived.TerrainResult | None = None
        self.texture_rgb: np.ndarray | None = None
        self.texture: derived.TextureResult | None = None
        self.targets: derived.TargetsResult | None = None
        self.stations: derived.StationsResult | None = None
        self.coverage: derived.CoverageResult | None = None
        self.objects: derived.ObjectsResult | None = None
        self.buildings: derived.BuildingsResult | None = None
        self.vegetation: derived.VegetationResult | None = None
        #: camera stations under the ground, over what is drawn (None: none)
        self.low_stations = None
        #: the flight over the real terrain (designer.gui.state.plan_figures), or None
        self.plan = None
        #: the (terrain, stations) ``plan`` was computed over; None while one is computed
        self._plan_inputs: tuple | None = None
        #: the plan figures of the latest stations are being computed in a worker thread
        #: (seconds at survey size): ``plan`` is None or the figures before the edit
        self.plan_computing = False
        self.errors: dict[str, str] = {}
        self.coverage_enabled = False
        self._tiles: tuple[int, int] | None = None
        self._area_key: tuple | None = None
        document.events.connect("project", self._on_project)
        document.events.connect("reset", self._on_reset)
        view.interaction.ground_picker = self._pick_ground
        self._init_photo_selection()

    # ------------------------------------------------------------------ events
    def _on_reset(self, project) -> None:
        self.terrain = None
        if self.low_stations is not None:
            self.low_stations = None
            self.problems_changed.emit()
        self.texture_rgb = None
        self.stations = None
        self.coverage = None
        self.plan = None
        self._plan_inputs = None
        self._set_plan_computing(False)
        self._tiles = None
        self._area_key = None
        self.selected_photo = None  # of the project before
        self.cloud_moment = FOLLOW_SELECTION
        self.view.show_selected_station(None)
        self.photo_selected.emit(None)

    def _on_project(self, old, new, parts) -> None:
        if parts & TERRAIN_PARTS or self.terrain is None:
            self.refresh_terrain()
        else:
            if "texture" in parts:
                self._retile()
            if "targets" in parts:
                self.refresh_targets()
            if parts & STATION_PARTS:
                self.refresh_stations()
        procedural = isinstance(self.document.project.scene.texture.source,
                                m.ProceduralTexture)
        if "texture" in parts or (parts & TERRAIN_PARTS and procedural):
            self.refresh_texture()
        if "lighting" in parts and not parts & TERRAIN_PARTS and self.terrain is not None:
            self.refresh_lighting()
            self.refresh_cloud_shadows()
        if parts & {"objects", "trajectory"} and not parts & TERRAIN_PARTS:
            self.refresh_moving()  # (a new terrain poses them when it is done)
        if parts & {"objects", "lighting"}:
            self.refresh_objects()
            if not parts & TERRAIN_PARTS:
                self.refresh_buildings()
                self.refresh_vegetation()
        if "trajectory" in parts or "terrain" in parts:
            self._show_area()

    def _fail(self, key: str, error: BaseException) -> None:
        self._clear(key)
        self.errors[key] = _message(error)
        self.error_message.emit(f"{key}: {self.errors[key]}")

    def _clear(self, key: str) -> None:
        """``key`` works again: its error goes, and so does the message that posted it."""
        text = self.errors.pop(key, None)
        if text:
            self.message_withdrawn.emit(f"{key}: {text}")

    # ------------------------------------------------------------------ terrain
    def refresh_terrain(self) -> None:
        project = self.document.project
        self.tasks.submit("terrain", derived.compute_terrain, project, self.document.base_dir,
                          self.view.max_display_nodes, on_done=self._terrain_done,
                          on_error=lambda e: self._terrain_failed(e))

    def _terrain_failed(self, error: BaseException) -> None:
        self.terrain = None
        self.view.remove_layer("terrain")
        self.view.show_cloud_shadows(None)
        self._fail("terrain", error)
        self.terrain_changed.emit()
        self.refresh_targets()
        self.refresh_stations()
        self.refresh_buildings()
        self.refresh_vegetation()

    def _terrain_done(self, result: derived.TerrainResult) -> None:
        self._clear("terrain")
        first = self.terrain is None or not np.allclose(
            self.view.offset[:2], result.centre_world[:2], atol=0.5 * max(
                result.terrain.extent.width_m, result.terrain.extent.length_m))
        self.terrain = result
        if first:
            self.view.set_offset(result.centre_world)  # drops every layer: draw them anew
            if self.objects is not None:
                self._objects_done(self.objects)
        self.view.interaction.ground_picker = (
            self._pick_ground if result.raycaster is not None else None)
        p = self.document.project.scene.texture
        self._tiles = (p.repeat_X, p.repeat_Y)
        display = (result.display if self._tiles == result.tiles
                   else derived.retile(result, self._tiles))
        self.view.show_terrain(display.points_world, display.faces, self._uv(display),
                               self.texture_rgb, p.interpolation == "linear",
                               result.irradiance)
        if first:
            self.view.reset_view()
        self.refresh_cloud_shadows()
        self.refresh_moving()
        self.terrain_changed.emit()
        self.refresh_targets()
        self.refresh_stations()
        self.refresh_buildings()
        self.refresh_vegetation()
        self._show_area()

    def _retile(self) -> None:
        tex = self.document.project.scene.texture
        tiles = (tex.repeat_X, tex.repeat_Y)
        if self.terrain is None or tiles == self._tiles:
            return
        self._tiles = tiles
        display = derived.retile(self.terrain, tiles)
        self.view.show_terrain(display.points_world, display.faces, self._uv(display),
                               self.texture_rgb, tex.interpolation == "linear",
                               self.terrain.irradiance)

    # ------------------------------------------------------------------ moving objects
    def refresh_moving(self) -> None:
        """Pose the moving objects at the moment the view draws (the cloud shadows'
        moment: the selected photo's time, else the take-off), in a worker thread."""
        project = self.document.project
        if not project.scene.moving_objects:
            self.tasks.cancel("moving")
            self.view.show_moving(None)
            return
        terrain = self.terrain
        hf = terrain.heightfield if terrain is not None else None
        z = terrain.z_mean_m if terrain is not None else 0.0
        self.tasks.submit("moving", moving_display, project, hf, self.document.base_dir,
                          self.cloud_time_s(), z, on_done=self._moving_done,
                          on_error=lambda e: self._fail("moving objects", e))

    def _moving_done(self, shown) -> None:
        self._clear("moving objects")
        self.view.show_moving(shown)

    # ------------------------------------------------------------------ objects
    def refresh_objects(self) -> None:
        """Read and place the scene's mesh objects (a worker thread: files are read)."""
        if not self.document.project.scene.objects:
            self.tasks.cancel("objects")
            self._objects_done(None)
            return
        self.tasks.submit("objects", derived.compute_objects, self.document.project,
                          self.document.base_dir, on_done=self._objects_done,
                          on_error=self._objects_failed)

    def _objects_done(self, result: derived.ObjectsResult | None) -> None:
        self._clear("objects")
        self.objects = result
        if result is None:
            self.view.show_objects(None)
        else:
            self.view.show_objects(result.vertices_world, result.faces,
                                   result.face_irradiance)

    def _objects_failed(self, error: BaseException) -> None:
        self.objects = None
        self.view.show_objects(None)
        self._fail("objects", error)

    # ------------------------------------------------------------------ buildings
    def refresh_buildings(self) -> None:
        """Build the scene's buildings on the computed terrain (a worker thread)."""
        if not self.document.project.scene.buildings or self.terrain is None:
            self.tasks.cancel("buildings")
            self._buildings_done(None)
            return
        self.tasks.submit("buildings", derived.compute_buildings, self.document.project,
                          self.document.base_dir, self.terrain, on_done=self._buildings_done,
                          on_error=self._buildings_failed)

    def _buildings_done(self, result: derived.BuildingsResult | None) -> None:
        self._clear("buildings")
        self.buildings = result
        self._recheck_clearance()
        if result is None:
            self.view.show_buildings(None)
        else:
            self.view.show_buildings(result.vertices_world, result.faces,
                                     result.face_irradiance, result.face_roof)

    def _buildings_failed(self, error: BaseException) -> None:
        self.buildings = None
        self._recheck_clearance()
        self.view.show_buildings(None)
        self._fail("buildings", error)

    # ------------------------------------------------------------------ vegetation
    def refresh_vegetation(self) -> None:
        """Place the scene's plants on the computed terrain (a worker thread)."""
        if self.document.project.scene.vegetation is None or self.terrain is None:
            self.tasks.cancel("vegetation")
            self._vegetation_done(None)
            return
        self.tasks.submit("vegetation", derived.compute_vegetation, self.document.project,
                          self.document.base_dir, self.terrain, on_done=self._vegetation_done,
                          on_error=self._vegetation_failed)

    def _vegetation_done(self, result: derived.VegetationResult | None) -> None:
        self._clear("vegetation")
        self.vegetation = result
        self._recheck_clearance()
        if result is None:
            self.view.show_vegetation(None)
        else:
            self.view.show_vegetation(result.vertices_world, result.faces, result.face_albedo)

    def _vegetation_failed(self, error: BaseException) -> None:
        self.vegetation = None
        self._recheck_clearance()
        self.view.show_vegetation(None)
        self._fail("vegetation", error)

    # ------------------------------------------------------------------ lighting
    def refresh_lighting(self) -> None:
        """Light the drawn terrain anew (sun, sky, cloud shadows) without recomputing the
        terrain."""
        terrain = self.terrain
        self.tasks.submit("lighting", derived.display_irradiance,
                          self.document.project.scene.lighting, terrain.display,
                          terrain.heightfield, terrain.raycaster, self.document.project,
                          on_done=lambda light: self._lighting_done(terrain, light),
                          on_error=lambda e: self._fail("lighting", e))

    def _lighting_done(self, terrain: derived.TerrainResult, light: np.ndarray) -> None:
        if terrain is not self.terrain:
            return  # the terrain changed meanwhile; its own result carries its light
        self._clear("lighting")
        self.terrain = dataclasses.replace(terrain, irradiance=light)
        self.view.set_terrain_irradiance(light)
        self.lighting_changed.emit()

    def refresh_cloud_shadows(self) -> None:
        """Draw the project's cloud shadows over the terrain anew (none: take them away)."""
        terrain = self.terrain
        if terrain is None or self.document.project.scene.lighting.clouds is None:
            self.tasks.cancel("cloud-shadows")
            self.view.show_cloud_shadows(None)
            return
        self.tasks.submit("cloud-shadows", derived.compute_cloud_preview,
                          self.document.project, terrain, derived.CLOUD_GRID_CELLS,
                          self.cloud_time_s(),
                          on_done=lambda preview: self._cloud_shadows_done(terrain, preview),
                          on_error=lambda e: self._fail("cloud shadows", e))

    def _cloud_shadows_done(self, terrain: derived.TerrainResult,
                            preview: derived.CloudPreview | None) -> None:
        if self.terrain is None or terrain.display is not self.terrain.display:
            return  # drawn for a terrain since replaced; its own preview follows
        self._clear("cloud shadows")
        if preview is None:
            self.view.show_cloud_shadows(None)
        else:
            self.view.show_cloud_shadows(preview.points_world, preview.faces,
                                         preview.darkening)

    # ------------------------------------------------------------------ texture
    def refresh_texture(self) -> None:
        self.tasks.submit("texture", derived.compute_texture_result, self.document.project,
                          self.document.base_dir, on_done=self._texture_done,
                          on_error=self._texture_failed)

    def _uv(self, display) -> np.ndarray:
        """The drawn terrain's texture coordinates for the current texture."""
        return display.uv if self.texture is None else self.texture.display_uv(display)

    def _displayed(self):
        """The terrain display as drawn now (its current tiling), or None."""
        if self.terrain is None:
            return None
        return (self.terrain.display if self._tiles in (None, self.terrain.tiles)
                else derived.retile(self.terrain, self._tiles))

    def _texture_done(self, result: derived.TextureResult) -> None:
        self._clear("texture")
        placed_before = self.texture is not None and self.texture.orthophoto is not None
        self.texture, self.texture_rgb = result, result.rgb
        tex = self.document.project.scene.texture
        display = self._displayed()
        if display is not None and (placed_before or result.orthophoto is not None):
            self.view.set_terrain_uv(self._uv(display))
        self.view.set_texture(result.rgb, tex.interpolation == "linear")
        self.texture_changed.emit()

    def _texture_failed(self, error: BaseException) -> None:
        self.texture, self.texture_rgb = None, None
        self.view.set_texture(None)
        self._fail("texture", error)
        self.texture_changed.emit()

    # ------------------------------------------------------------------ targets
    def refresh_targets(self) -> None:
        project = self.document.project
        hf = self.terrain.heightfield if self.terrain is not None else None
        if self.terrain is None and project.targets:
            return  # drawn once the terrain is there
        try:
            self.targets = derived.compute_targets(project, hf)
            self._clear("targets")
        except (DesignerError, ValueError) as error:
            self.targets = None
            self._fail("targets", error)
        t = self.targets
        if t is None:
            self.view.show_targets([], [], np.zeros((0, 3)))
        else:
            self.view.show_targets(t.ids, t.roles, t.true_xyz, t.plates)
        if self._plan_current():
            self._count_gcps()
        elif self.stations is not None and self.terrain is not None:
            self.refresh_plan()
        self.targets_changed.emit()

    def _plan_current(self) -> bool:
        """Whether ``plan`` is the analysis of the terrain and stations shown now (none
        computed for newer ones)."""
        inputs = self._plan_inputs
        return (self.plan is not None and inputs is not None
                and inputs[0] is self.terrain and inputs[1] is self.stations)

    def _count_gcps(self) -> None:
        """Count the images that see each GCP anew, on this thread: the flight's figures
        stay, and the GCP table and warnings follow a GCP edit as it is made."""
        from designer.gui.state.plan_figures import with_targets

        try:
            self.plan = with_targets(self.plan, self.document.project, self.terrain,
                                     self.targets, self.stations.images)
        except (DesignerError, ValueError) as error:
            self._plan_failed(error)
            return
        self.plan_changed.emit()

    # ------------------------------------------------------------------ stations
    def refresh_stations(self) -> None:
        project = self.document.project
        if not project.cameras or (project.trajectory.flight_plan is None
                                   and not project.trajectory.exterior_orientations):
            self.tasks.cancel("stations")
            self._stations_failed(DesignerError("no camera stations yet: set up a flight"))
            return
        self.tasks.submit("stations", derived.compute_stations, project, self.terrain,
                          on_done=self._stations_done, on_error=self._planning_failed)

    def _planning_failed(self, error: BaseException) -> None:
        if self.terrain is None and self.errors.get("terrain"):
            # planned without the terrain, the stations fail for its want (a height-field
            # terrain would be taken for a mesh): the terrain is what to fix
            error = DesignerError("no camera stations while the terrain cannot be made; "
                                  "the Terrain panel says why")
        self._stations_failed(error)

    def _stations_done(self, result: derived.StationsResult) -> None:
        self._clear("stations")
        self.stations = result
        self.view.show_stations(result.geometry)
        ring, far = result.surroundings, result.far_ground
        self.view.show_surroundings(*((ring.points_world, ring.faces) if ring is not None
                                      else (None, None)))
        self.view.show_far_ground(*((far.points_world, far.faces) if far is not None
                                    else (None, None)))
        if len(result.C_world) and not self.view.in_view(result.C_world).any():
            # an edit moved every camera out of sight: show them with the terrain
            self.view.frame_all(result.C_world)
        self.stations_changed.emit()
        self._stations_replaced()
        self._check_clearance()
        self.refresh_plan()
        if self.coverage_enabled:
            self.refresh_coverage()

    def _stations_failed(self, error: BaseException) -> None:
        self.stations = None
        self.view.show_stations(None)
        self.view.show_surroundings(None, None)  # planned from the images: none without
        self.view.show_far_ground(None, None)
        self.errors["stations"] = _message(error)
        self.view.show_selected_station(None)
        self.stations_changed.emit()
        self._check_clearance()
        self.refresh_plan()

    def _check_clearance(self) -> bool:
        """Judge the stations drawn against the terrain, buildings and plants drawn
        (designer.gui.state.station_problems, milliseconds); True when whether some are
        under the ground changed."""
        from designer.gui.state.station_problems import window_low_stations

        low = window_low_stations(self.document.project, self.terrain, self.stations,
                                  self.buildings, self.vegetation)
        if low == self.low_stations:
            return False
        flipped = (low is None) != (self.low_stations is None)
        self.low_stations = low
        self.problems_changed.emit()
        return flipped

    def _recheck_clearance(self) -> None:
        """After the buildings or plants change: the plan is analysed again when the
        stations went under (or came out of) the ground."""
        if self._check_clearance():
            self.refresh_plan()

    def station_problems(self) -> list[str]:
        """Camera stations under the ground, as lines of the Problems list."""
        from designer.gui.state.station_problems import station_problem_lines

        return station_problem_lines(self.document.project, self.low_stations)

    def reach_warnings(self) -> list[str]:
        """GCPs, buildings and flight-area vertices outside the ground the terrain file
        holds (as ``designer check`` warns), each with its fix; compared with the reach
        read with the terrain, so asking after every edit costs microseconds."""
        from designer.checks.terrain_reach import reach_warnings

        reach = self.terrain.reach if self.terrain is not None else None
        return [f"{w.message}; {w.fix}"
                for w in reach_warnings(self.document.project, reach)]

    def hard_case_warnings(self) -> list[str]:
        """The cases that degrade results (``designer check``'s hard cases: lenses near
        their fold, nearly collinear control, the texture against the GSD, thin networks),
        each with its fix; over the targets drawn and the flight's analysis, so asking
        after every edit costs well under a millisecond
        (designer.gui.state.hard_cases)."""
        from designer.gui.state.hard_cases import hard_case_lines

        return hard_case_lines(self.document.project, self.targets, self.plan,
                               self.stations)

    # ------------------------------------------------------------------ plan figures
    def refresh_plan(self) -> None:
        """Analyse the flight over the real terrain (as designer plan does), in a thread."""
        from designer.gui.state.plan_figures import compute_plan_figures

        terrain, stations = self.terrain, self.stations
        self._plan_inputs = None
        if self.low_stations is not None:
            # figures measured from under the ground mean nothing: the Problems list
            # says what to fix, the Flight panel why it has no figures
            self.tasks.cancel("plan")
            self._set_plan_computing(False)
            self.plan = None
            self.errors["plan"] = UNDER_THE_GROUND
            self.plan_changed.emit()
            return
        if self.errors.get("plan") == UNDER_THE_GROUND:
            self._clear("plan")
        if terrain is None or stations is None or terrain.heightfield is None:
            self.tasks.cancel("plan")
            self._set_plan_computing(False)
            self.plan = None
            self.plan_changed.emit()
            return
        # the window is usable meanwhile: the stations, render estimate and everything
        # else are shown; the Flight panel marks its figures over the terrain as being
        # computed until they arrive
        self.tasks.submit("plan", compute_plan_figures, self.document.project, terrain,
                          stations, self.targets,
                          on_done=lambda figures: self._plan_done(figures, terrain, stations),
                          on_error=self._plan_failed)
        self._set_plan_computing(True)

    def _set_plan_computing(self, computing: bool) -> None:
        if computing != self.plan_computing:
            self.plan_computing = computing
            self.plan_computing_changed.emit()

    def _plan_done(self, figures, terrain, stations) -> None:
        self._clear("plan")
        self.plan = figures
        self._plan_inputs = (terrain, stations)
        self._set_plan_computing(False)
        self.plan_changed.emit()

    def _plan_failed(self, error: BaseException) -> None:
        self.plan = None
        self._plan_inputs = None
        self.errors["plan"] = _message(error)
        self._set_plan_computing(False)
        self.plan_changed.emit()

    # ------------------------------------------------------------------ coverage
    def set_coverage_enabled(self, enabled: bool) -> None:
        self.coverage_enabled = enabled
        if enabled:
            self.refresh_coverage()
        else:
            self.view.remove_layer("coverage")
            self.view.request_render()

    def refresh_coverage(self) -> None:
        if self.terrain is None or self.stations is None:
            return
        self.message.emit("computing the coverage map…")
        self.tasks.submit("coverage", derived.compute_coverage, self.document.project,
                          self.terrain, self.stations, on_done=self._coverage_done,
                          on_error=lambda e: self._fail("coverage", e))

    def _coverage_done(self, result: derived.CoverageResult) -> None:
        self._clear("coverage")
        self.coverage = result
        if self.coverage_enabled:
            self.view.show_coverage(result.points_world, result.shape, result.count)
            shares = ", ".join(f"{100 * v:.0f} % by ≥ {k}" for k, v in result.shares.items())
            self.message.emit(f"coverage: area seen {shares}")
        self.coverage_changed.emit()

    # ------------------------------------------------------------------ area, picking
    def _show_area(self) -> None:
        plan = self.document.project.trajectory.flight_plan
        key = (None if plan is None else plan.area, id(self.terrain), self.view.offset.tobytes())
        if key == self._area_key:
            return  # unchanged: no frame for nothing
        self._area_key = key
        if plan is None or len(plan.area) < 3:
            self.view.show_polygon("area", None)
            return
        self.view.show_polygon("area", derived.draped_polygon(np.array(plan.area),
                                                              self.terrain))

    def _pick_ground(self, origin: np.ndarray, direction: np.ndarray):
        if self.terrain is None or self.terrain.raycaster is None:
            return None
        rc = self.terrain.raycaster
        hit = rc.first_hit(origin[None, :], direction[None, :])[0]
        if not np.all(np.isfinite(hit)):
            return None
        x0, x1, y0, y1 = rc.heightfield.extent_m
        if not (x0 <= hit[0] <= x1 and y0 <= hit[1] <= y1):
            return None
        # a ray passing beside the terrain meets the side of the solid block, below the
        # surface: that is no ground to place anything on
        if abs(hit[2] - float(rc.height(hit[0], hit[1]))) > GROUND_TOLERANCE_M:
            return None
        return hit
