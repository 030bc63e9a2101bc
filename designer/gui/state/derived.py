"""Everything the view derives from a project, as plain functions (Qt-free).

They run in worker threads (:mod:`designer.gui.qt.tasks`), take immutable inputs and
return frozen results, so a result can be handed to the UI thread as it is. World
coordinates in metres. Each wraps the project's own code: the scene builder, the
flight planner, the coverage analysis — the GUI computes nothing of its own.
"""

from __future__ import annotations

import math
import threading
from collections import OrderedDict
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer.checks.station_clearance import plant_cylinders
from designer.checks.terrain_reach import Reach, terrain_file_reach
from designer.core.heightfield import Heightfield
from designer.core.interior import InteriorOrientation
from designer.core.raycast import TerrainRaycaster, raycaster_of
from designer.errors import DesignerError
from designer.gui.state.view_geometry import (
    MAX_DISPLAY_NODES_PER_SIDE,
    StationGeometry,
    TerrainDisplay,
    far_ground_display,
    grid_faces,
    station_geometry,
    surroundings_display,
    terrain_display,
    vertex_normals,
    with_mount_frusta,
)
from designer.project import model as m
from designer.scene.build import build_heightfield, build_targets, build_terrain_mesh
from designer.scene.build import build_texture as _build_texture
from designer.scene.lighting import (
    irradiance,
    sun_direction_world,
    sun_position_deg,
    surface_normals,
)
from designer.scene.mesh import TerrainMesh
from designer.scene.objects import PlacedObjects, build_objects
from designer.survey.flight import CameraCalc, camera_calc
from designer.survey.surroundings import GrownTerrain


@dataclass(frozen=True, eq=False)
class TerrainResult:
    """The terrain as computed for the view; ``irradiance`` (N,) is the light at each
    display vertex (relative, 1 = flat ground in full sun, see :func:`display_irradiance`)."""

    terrain: m.Terrain
    heightfield: Heightfield | None
    mesh: TerrainMesh | None
    raycaster: TerrainRaycaster | None
    display: TerrainDisplay
    z_mean_m: float
    centre_world: np.ndarray
    n_vertices: int
    tiles: tuple[int, int]
    max_display_nodes: int = MAX_DISPLAY_NODES_PER_SIDE
    irradiance: np.ndarray | None = None
    #: the box a DEM or terrain mesh holds ground in (None: flat, procedural), read here
    #: once so that each edit only compares places with it
    #: (:func:`designer.checks.terrain_reach.reach_warnings`)
    reach: Reach | None = None


def compute_terrain(project: m.Project, base_dir: Path,
                    max_display_nodes: int = MAX_DISPLAY_NODES_PER_SIDE) -> TerrainResult:
    """Height field (or mesh), its ray caster and the thinned display mesh."""
    terrain = project.scene.terrain
    hf = build_heightfield(terrain, Path(base_dir), project.crs)
    mesh = None
    tiles = (project.scene.texture.repeat_X, project.scene.texture.repeat_Y)
    if hf is None:
        origin = np.array([project.origin.E0, project.origin.N0, project.origin.H0])
        mesh = build_terrain_mesh(terrain, None, Path(base_dir), origin)
        z = mesh.vertices_world[:, 2]
        n = len(mesh.vertices_world)
        rc = None
    else:
        z = hf.heights_m
        n = z.size
        rc = raycaster_of(hf)
    display = terrain_display(hf, mesh, tiles, max_display_nodes)
    lo, hi = display.points_world.min(axis=0), display.points_world.max(axis=0)
    centre = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, float(np.mean(z))])
    light = display_irradiance(project.scene.lighting, display, hf, rc, project=project)
    return TerrainResult(terrain, hf, mesh, rc, display, float(np.mean(z)), centre, n, tiles,
                         max_display_nodes, light, terrain_file_reach(project, base_dir))


def sun_angles_deg(lighting: m.Lighting, project: m.Project | None = None
                   ) -> tuple[float, float]:
    """(azimuth clockwise from grid north, elevation) of the project's sun, degrees; a sun
    over time is shown as it is at take-off (it needs the ``project``'s time line)."""
    sun = lighting.sun
    if isinstance(sun, m.Sun):
        return float(sun.azimuth_deg), float(sun.elevation_deg)
    if isinstance(sun, m.SunOverTime):
        from designer.errors import DesignerError
        from designer.scene.sun_over_time import takeoff_sun

        if project is None:
            raise DesignerError("a sun over time needs the project's time line")
        return takeoff_sun(project, sun)
    return sun_position_deg(sun.date_time, sun.latitude_deg, sun.longitude_deg)


def display_irradiance(lighting: m.Lighting, display: TerrainDisplay,
                       heightfield: Heightfield | None = None,
                       raycaster: TerrainRaycaster | None = None,
                       project: m.Project | None = None) -> np.ndarray:
    """Light (N,) at the display mesh's vertices, by the renderer's own model
    (:func:`designer.scene.lighting.irradiance`: Lambert sun with cast shadows plus an
    isotropic sky, 1 = flat ground in full sun). Normals of a height field are taken over
    one display cell (the surface as drawn); shadows are cast by the full height field.
    A mesh terrain gets its vertex normals and no cast shadows. Cloud shadows are drawn
    over it (:func:`compute_cloud_preview`)."""
    azimuth, elevation = sun_angles_deg(lighting, project)
    sun = sun_direction_world(azimuth, elevation)
    points = display.points_world
    lit = np.ones(len(points))
    if heightfield is not None:
        step = display.stride * min(heightfield.dx_m, heightfield.dy_m)
        normals = surface_normals(heightfield, points[:, 0], points[:, 1], step)
        facing = np.flatnonzero(normals @ sun > 0)
        if raycaster is not None and sun[2] > 0 and len(facing):
            start = points[facing] + 0.01 * normals[facing]
            hits = raycaster.first_hit(start, np.tile(sun, (len(facing), 1)))
            lit[facing[np.isfinite(hits[:, 0])]] = 0.0
    else:
        normals = vertex_normals(points, display.faces)
    return irradiance(normals, lit, sun, lighting.sun_strength, lighting.sky_strength)


#: cells per side of the grid the cloud shadows are drawn with in the view
CLOUD_GRID_CELLS = 256
#: how far above the ground the cloud shadows are drawn (m), as the coverage map
CLOUD_LIFT_M = 0.05


@dataclass(frozen=True, eq=False)
class CloudPreview:
    """The cloud shadows as drawn over the terrain: a triangle mesh (``points_world``
    (N, 3), ``faces`` (M, 3)) laid on the ground and the share of the light each vertex
    loses (``darkening`` (N,), 0 = none)."""

    points_world: np.ndarray
    faces: np.ndarray
    darkening: np.ndarray


def compute_cloud_preview(project: m.Project, terrain: TerrainResult,
                          cells: int = CLOUD_GRID_CELLS, time_s: float = 0.0
                          ) -> CloudPreview | None:
    """The project's cloud shadows as the render makes them ``time_s`` after take-off
    (the render's pattern, :func:`designer.scene.cloud_shadows.attenuation`, drifted by
    the wind, evaluated on a grid of ``cells`` cells per side over the terrain): each
    grid node's loss of light on flat ground by the renderer's light model, the direct
    sun times ``depth · shadow`` against sun and sky. None without cloud shadows. A
    height field gets the grid laid on it; a mesh terrain its own vertices."""
    lighting = project.scene.lighting
    if lighting.clouds is None:
        return None
    hf, display = terrain.heightfield, terrain.display
    if hf is not None:
        x0, x1, y0, y1 = hf.extent_m
        step = max(x1 - x0, y1 - y0) / cells
        nx = max(2, int(np.ceil((x1 - x0) / step)) + 1)
        ny = max(2, int(np.ceil((y1 - y0) / step)) + 1)
        X, Y = np.meshgrid(np.linspace(x0, x1, nx), np.linspace(y0, y1, ny))
        Z = hf.height_at_clamped(X.ravel(), Y.ravel()) + CLOUD_LIFT_M
        points = np.column_stack([X.ravel(), Y.ravel(), Z])
        faces = grid_faces(ny, nx)
    else:
        points, faces = display.points_world, display.faces
    origin = np.array([project.origin.E0, project.origin.N0])
    factor = cloud_attenuation(lighting.clouds, points[:, :2] - origin, cells, time_s)
    azimuth, elevation = sun_angles_deg(lighting, project)
    sun = sun_direction_world(azimuth, elevation)
    up = np.tile([0.0, 0.0, 1.0], (len(points), 1))
    light = irradiance(up, factor, sun, lighting.sun_strength, lighting.sky_strength)
    return CloudPreview(points, faces, np.clip(1.0 - light, 0.0, 1.0))


def cloud_attenuation(clouds: m.CloudShadows, xy_local: np.ndarray,
                      cells: int = CLOUD_GRID_CELLS, time_s: float = 0.0) -> np.ndarray:
    """The direct sun's factor (N,) at local points (N, 2) (world − origin, m) under the
    cloud shadows ``time_s`` after take-off (``1 − depth · shadow``, the render's own
    :func:`designer.scene.cloud_shadows.attenuation`), evaluated on a grid of ``cells``
    cells per side over the points' extent and interpolated bilinearly between its
    nodes."""
    from designer.scene.cloud_shadows import attenuation

    xy = np.asarray(xy_local, dtype=float)
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    step = max(float(np.max(hi - lo)) / cells, 1e-3)
    nx, ny = (int(np.ceil((hi - lo)[k] / step)) + 1 for k in (0, 1))
    xs, ys = lo[0] + step * np.arange(nx), lo[1] + step * np.arange(ny)
    grid = attenuation(clouds, xs, ys, time_s)  # (ny, nx), rows along y
    u = np.clip((xy[:, 0] - lo[0]) / step, 0, nx - 1)
    v = np.clip((xy[:, 1] - lo[1]) / step, 0, ny - 1)
    i0 = np.minimum(u.astype(int), max(nx - 2, 0))
    j0 = np.minimum(v.astype(int), max(ny - 2, 0))
    i1, j1 = np.minimum(i0 + 1, nx - 1), np.minimum(j0 + 1, ny - 1)
    fu, fv = u - i0, v - j0
    return ((grid[j0, i0] * (1 - fu) + grid[j0, i1] * fu) * (1 - fv)
            + (grid[j1, i0] * (1 - fu) + grid[j1, i1] * fu) * fv)


def retile(result: TerrainResult, tiles: tuple[int, int]) -> TerrainDisplay:
    """The display mesh with another texture repeat (no new height field)."""
    return terrain_display(result.heightfield, result.mesh, tiles, result.max_display_nodes)


#: procedural texture tiles the window keeps (a tile of the blank project's 1 cm grass is
#: 2000 × 2000 px, 12 MB, and takes ~1 s to synthesise)
KEPT_TEXTURES = 4
_kept_textures: OrderedDict[tuple, np.ndarray] = OrderedDict()
_kept_lock = threading.Lock()


def compute_texture(project: m.Project, base_dir: Path) -> np.ndarray:
    """The texture tile (H, W, 3) uint8, as the renderer will use it.

    A procedural tile is a function of the texture's declaration and the terrain's
    extent alone, so the last :data:`KEPT_TEXTURES` of them are kept: an undo, a redo
    or another window of the same project draws its texture without synthesising it
    again. Image and orthophoto textures are read from their files every time (a file
    can change under the same name). The array handed out is read-only."""
    tex, terrain = project.scene.texture, project.scene.terrain
    if not isinstance(tex.source, m.ProceduralTexture):
        return _build_texture(tex, terrain, Path(base_dir), project.crs)
    key = (tex.source, tex.repeat_X, tex.repeat_Y, terrain.extent)
    with _kept_lock:
        rgb = _kept_textures.get(key)
        if rgb is not None:
            _kept_textures.move_to_end(key)
            return rgb
    rgb = _build_texture(tex, terrain, Path(base_dir), project.crs)
    rgb.flags.writeable = False
    with _kept_lock:
        _kept_textures[key] = rgb
        while len(_kept_textures) > KEPT_TEXTURES:
            _kept_textures.popitem(last=False)
    return rgb


@dataclass(frozen=True, eq=False)
class TextureResult:
    """The texture image (H, W, 3) uint8 and, for an orthophoto, the crop that places it
    by its geotransform (``orthophoto``; ``None``: the image is tiled over the terrain)."""

    rgb: np.ndarray
    orthophoto: object | None = None
    crs: str | None = None

    def display_uv(self, display: TerrainDisplay) -> np.ndarray:
        """Texture coordinates of the drawn terrain's vertices, as the renderer maps it:
        an orthophoto by its geotransform, any other texture by the display's tiling."""
        if self.orthophoto is None:
            return display.uv
        from designer.scene.orthophoto import orthophoto_uv

        return orthophoto_uv(self.orthophoto, display.points_world[:, :2], self.crs)


def compute_texture_result(project: m.Project, base_dir: Path) -> TextureResult:
    """:func:`compute_texture` with what places an orthophoto on the terrain."""
    from designer.scene.build import build_orthophoto

    tex, terrain = project.scene.texture, project.scene.terrain
    ortho = build_orthophoto(tex, terrain, Path(base_dir), project.crs)
    if ortho is not None:
        return TextureResult(ortho.rgb, ortho, project.crs)
    return TextureResult(compute_texture(project, base_dir))


def texel_size_m(project: m.Project, texture_rgb: np.ndarray | None) -> tuple[float, float]:
    """Ground size (m) of one texel along X and Y (NaN when unknown)."""
    tex = project.scene.texture
    e = project.scene.terrain.extent
    if isinstance(tex.source, m.ProceduralTexture):
        return tex.source.texel_size_m, tex.source.texel_size_m
    if texture_rgb is None:
        return math.nan, math.nan
    h, w = texture_rgb.shape[:2]
    return e.width_m / tex.repeat_X / w, e.length_m / tex.repeat_Y / h


@dataclass(frozen=True, eq=False)
class BuildingsResult:
    """The buildings as the renderer draws them: one merged mesh (``vertices_world``,
    ``faces``), each face's relative light and whether it is roof (else facade)."""

    vertices_world: np.ndarray
    faces: np.ndarray
    face_irradiance: np.ndarray
    face_roof: np.ndarray


def compute_buildings(project: m.Project, base_dir: Path, terrain: TerrainResult
                      ) -> BuildingsResult:
    """Every building standing on the computed terrain, lit by the project's sun."""
    from designer.scene.buildings import ROOF, build_buildings
    from designer.scene.lighting import irradiance, sun_direction_world
    from designer.scene.surfaces import Ground, merge_triangles

    built = build_buildings(project, Path(base_dir), Ground(terrain.heightfield, terrain.mesh))
    v, f = merge_triangles([(b.vertices_world, b.faces) for b in built])
    normal = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    normal = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    light = project.scene.lighting
    sun = sun_direction_world(*sun_angles_deg(light, project))
    e = irradiance(normal, np.ones(len(f)), sun, light.sun_strength, light.sky_strength)
    roof = np.concatenate([b.face_kind == ROOF for b in built]) if built else np.zeros(0, bool)
    return BuildingsResult(v, f, e, roof)


@dataclass(frozen=True, eq=False)
class VegetationResult:
    """The plants as the renderer places them, standing upright (the wind's sway is not
    drawn): one merged mesh (``vertices_world``, ``faces``), each face's linear albedo
    (M, 3) (foliage in its group's colour, wood in the wood colour) and the number of
    plants; ``plants``: each plant's (base_world (P, 3), height_m (P,), crown_m (P,)),
    which the camera stations are kept clear of
    (designer.checks.station_clearance.plant_cylinders)."""

    vertices_world: np.ndarray
    faces: np.ndarray
    face_albedo: np.ndarray
    n_plants: int
    plants: tuple | None = None


def compute_vegetation(project: m.Project, base_dir: Path, terrain: TerrainResult
                       ) -> VegetationResult:
    """Every plant of the project's groups on the computed terrain (the renderer's
    placement: same seeds, same clearances)."""
    from designer.scene.surfaces import Ground, merge_triangles
    from designer.scene.vegetation import WOOD_ALBEDO, place_vegetation, posed_set

    sets = [s for s in place_vegetation(project, Path(base_dir),
                                        Ground(terrain.heightfield, terrain.mesh)) if len(s)]
    v, f = merge_triangles([posed_set(s, None, None) for s in sets])
    albedo = [np.where(np.tile(s.template.material_index, len(s))[:, None] == 1,
                       np.asarray(WOOD_ALBEDO), np.asarray(s.albedo_rgb)) for s in sets]
    return VegetationResult(v, f, np.vstack(albedo) if albedo else np.zeros((0, 3)),
                            sum(len(s) for s in sets), plant_cylinders(sets))


#: the scene's objects as the renderer draws them (designer.scene.objects)
ObjectsResult = PlacedObjects


def compute_objects(project: m.Project, base_dir: Path) -> ObjectsResult:
    """Read and place every scene object (an unreadable file names itself)."""
    return build_objects(project, Path(base_dir), *sun_angles_deg(project.scene.lighting, project))


@dataclass(frozen=True, eq=False)
class TargetsResult:
    ids: list[str]
    roles: list[str]
    true_xyz: np.ndarray
    plates: list[tuple[np.ndarray, np.ndarray, np.ndarray]]
    #: (N, 3) where the survey puts them (true plus the survey's errors), metres
    surveyed_xyz: np.ndarray


def compute_targets(project: m.Project, hf: Heightfield | None) -> TargetsResult:
    built = build_targets(project, hf)
    return TargetsResult(
        [b.target.id for b in built], [b.target.role for b in built],
        np.array([b.true_xyz for b in built]).reshape(-1, 3),
        [(b.vertices_world, b.faces, b.colors) for b in built],
        np.array([b.surveyed_xyz for b in built]).reshape(-1, 3))


@dataclass(frozen=True, eq=False)
class StationsResult:
    """Camera stations as drawn plus the figures the Flight panel shows."""

    geometry: StationGeometry
    n_images: int
    camera_id: str
    interior: InteriorOrientation
    calc: CameraCalc | None
    render_time_s: float | None
    C_world: np.ndarray
    R_cam_to_world: np.ndarray
    stations: tuple = ()
    #: every image (all cameras of a rig) as the render-time model sees it
    #: (designer.render_time.model): size, samples, share on the terrain
    render_costs: tuple = ()
    #: every rendered image's name, in render (frame) order: a rig station gives one per
    #: camera, so these are not the stations' names
    image_names: tuple[str, ...] = ()
    #: the terrain grown for these images (designer.survey.surroundings.GrownTerrain),
    #: which the plan figures analyse over: grown once per edit
    grown: GrownTerrain | None = None
    #: the ground the renders include beyond the terrain's extent, as drawn (a coarse
    #: ring, :func:`designer.gui.state.view_geometry.surroundings_display`); None: none
    surroundings: TerrainDisplay | None = None
    #: beyond it, to the view's horizon, ground no image sees
    #: (:func:`designer.gui.state.view_geometry.far_ground_display`); None without
    #: surroundings (the renders then end at the extent, and so does the view)
    far_ground: TerrainDisplay | None = None
    #: every image of these stations (designer.survey.project_poses.ProjectImages), which
    #: the plan figures analyse: the flight is not planned again for them
    images: object = None


def render_estimate_s(project: m.Project, costs, preset: str | None = None) -> float:
    """Estimated wall seconds of rendering the images ``costs`` (ImageCost) on this
    machine (:mod:`designer.render_time.model`), at the project's samples or a preset's."""
    return render_estimate(project, costs, preset).total_s


def render_estimate(project: m.Project, costs, preset: str | None = None):
    """:func:`render_estimate_s` with the set-up apart from the images' seconds
    (a ``render_time.model.RenderEstimate``)."""
    from dataclasses import replace as _replace

    from designer.render_time.model import estimate_render, render_workers

    if preset is not None:
        costs = [_replace(c, samples=m.PRESET_SAMPLES[preset]) for c in costs]
    return estimate_render(costs, render_workers(project, len(costs)))


def rendered_size_px(interior: InteriorOrientation, resolution_scale: float) -> tuple[int, int]:
    """Width and height (px) of the rendered images, rounded as the renderer rounds them
    (:func:`designer.survey.project_poses.render_interior`)."""
    if resolution_scale == 1.0:
        return interior.image_width_px, interior.image_height_px
    return (round(interior.image_width_px * resolution_scale),
            round(interior.image_height_px * resolution_scale))


def rendered_gsd_m(gsd_m: float, interior: InteriorOrientation,
                   resolution_scale: float) -> float:
    """The GSD (m) of the rendered image: the same sensor and lens, fewer pixels across."""
    return gsd_m * interior.image_width_px / rendered_size_px(interior, resolution_scale)[0]


def compute_stations(project: m.Project, terrain: TerrainResult | None) -> StationsResult:
    """Stations of the flight plan and explicit photos, drawn over the terrain and the
    surroundings the renders include (footprints lie on both)."""
    from designer.project.interiors import interior_from_camera
    from designer.render_time.model import project_image_costs
    from designer.survey.project_poses import (
        platform_stations,
        project_images,
        project_stations,
    )
    from designer.survey.surroundings import grown_terrain

    hf = terrain.heightfield if terrain is not None else None
    platform = platform_stations(project, hf)  # the flight planned once for both
    stations, camera_id = project_stations(project, hf, platform)
    try:
        interior = interior_from_camera(project.camera(camera_id))
    except KeyError:
        raise DesignerError(f"the stations use camera '{camera_id}', which is not defined; "
                            "choose a camera in the Flight panel") from None
    images = project_images(project, hf, platform)
    # grown once per edit: the plan figures analyse over the same grown terrain
    grown = grown_terrain(project, hf, images)
    rendered = grown.surroundings.heightfield
    surrounded = hf is not None and rendered is not hf
    rc = terrain.raycaster if terrain is not None else None
    first_hit = (_ground_hit(rc, _coarse(rendered)) if surrounded
                 else rc.surface_hit if rc else None)
    ground = (first_hit, terrain.z_mean_m if terrain is not None else 0.0)
    C = np.array([s.C_world for s in stations])
    R = np.array([s.R_cam_to_world for s in stations])
    line = np.array([s.line_index for s in stations])
    geometry = station_geometry(C, R, line, interior, *ground)
    plan = project.trajectory.flight_plan
    calc = None
    if plan is not None:
        calc = camera_calc(interior, altitude_agl_m=plan.altitude_agl_m, gsd_m=plan.gsd_m,
                           front_overlap_fraction=plan.front_overlap_percent / 100,
                           side_overlap_fraction=plan.side_overlap_percent / 100,
                           orientation=plan.orientation)
    n_images = len(stations)
    if project.trajectory.rigs:
        geometry, n_images = _rig_geometry(project, images, geometry, *ground)
    # the render draws the terrain with its surroundings: every pixel that sees them costs
    costs = tuple(project_image_costs(project, images, rendered))
    seconds = render_estimate_s(project, costs)
    ring = surroundings_display(rendered, hf.extent_m) if surrounded else None
    far = far_ground_display(rendered) if surrounded else None
    return StationsResult(geometry, n_images, camera_id, interior, calc, seconds, C, R,
                          tuple(stations), costs,
                          tuple(s.image_name for s in images.stations), grown, ring, far,
                          images)


#: the surroundings the footprints are cast on keep at most this many nodes per side
#: (they are pictures; the ring drawn is coarser still)
MAX_FOOTPRINT_SURROUNDING_NODES = 256


def _coarse(hf: Heightfield) -> TerrainRaycaster:
    """A ray caster over every k-th node of ``hf`` (at most
    :data:`MAX_FOOTPRINT_SURROUNDING_NODES` per side, the last row and column kept)."""
    ny, nx = hf.heights_m.shape
    k = max(1, math.ceil((max(nx, ny) - 1) / (MAX_FOOTPRINT_SURROUNDING_NODES - 1)))
    rows, cols = range(0, ny + k - 1, k), range(0, nx + k - 1, k)
    z = hf.heights_m[np.ix_([min(i, ny - 1) for i in rows], [min(j, nx - 1) for j in cols])]
    return TerrainRaycaster(Heightfield(hf.x0_m, hf.y0_m, hf.dx_m * k, hf.dy_m * k, z))


def _ground_hit(declared: TerrainRaycaster, around: TerrainRaycaster):
    """``first_hit`` on the declared terrain's top surface, and for rays that miss it (or
    meet only the side of its block) on the surroundings ``around``: footprints on the
    ground the renders include."""
    hf = declared.heightfield

    def first_hit(origins: np.ndarray, directions: np.ndarray) -> np.ndarray:
        hit = declared.first_hit(origins, directions)
        with np.errstate(invalid="ignore"):
            top = np.abs(hit[:, 2] - hf.height_at(hit[:, 0], hit[:, 1])) <= 0.05
        if not top.all():
            o = np.broadcast_to(origins, hit.shape)[~top]
            hit[~top] = around.first_hit(o, np.asarray(directions)[~top])
        return hit

    return first_hit


def _rig_geometry(project: m.Project, images, platform: StationGeometry, first_hit,
                  z_mean_m: float) -> tuple[StationGeometry, int]:
    """Frusta and footprints of every mount of the rigs flown (``images``: the project's
    images; footprints on ``first_hit``'s ground), and the image count of all cameras."""
    from designer.project.interiors import interior_from_camera

    mounts = []
    for camera_id in images.camera_order():
        k = [i for i, c in enumerate(images.camera_ids) if c == camera_id]
        interior = interior_from_camera(project.camera(camera_id))
        st = [images.stations[i] for i in k]
        mounts.append(station_geometry(
            np.array([s.C_world for s in st]), np.array([s.R_cam_to_world for s in st]),
            np.array([s.line_index for s in st]), interior, first_hit, z_mean_m,
            glyph_m=platform.glyph_m))
    return with_mount_frusta(platform, mounts), len(images.stations)


@dataclass(frozen=True, eq=False)
class CoverageResult:
    points_world: np.ndarray
    shape: tuple[int, int]
    count: np.ndarray
    shares: dict[int, float]


def compute_coverage(project: m.Project, terrain: TerrainResult,
                     stations: StationsResult) -> CoverageResult:
    """Images seeing each cell of a ground grid over the survey area (occlusion included)."""
    from designer.survey.coverage import coverage_map, ground_grid

    if terrain.heightfield is None:
        raise DesignerError("the coverage map needs a height-field terrain")
    plan = project.trajectory.flight_plan
    e = project.scene.terrain.extent
    area = (np.array(plan.area) if plan is not None else
            np.array([[e.min_X, e.min_Y], [e.max_X, e.min_Y], [e.max_X, e.max_Y],
                      [e.min_X, e.max_Y]]))
    grid = ground_grid(terrain.heightfield, area)
    cover = coverage_map(grid, stations.C_world, stations.R_cam_to_world, stations.interior,
                         terrain.raycaster)
    xyz = grid.points_world()
    count = np.where(grid.valid, cover.count, 0)
    return CoverageResult(xyz, grid.shape, count, cover.shares)


def draped_polygon(xy: np.ndarray, terrain: TerrainResult | None, lift_m: float = 0.3,
                   step_m: float | None = None) -> np.ndarray:
    """A closed polygon (N, 2) densified along its edges and laid on the terrain (N', 3)."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    if terrain is None or terrain.heightfield is None:
        z = terrain.z_mean_m if terrain is not None else 0.0
        return np.column_stack([xy, np.full(len(xy), z + lift_m)])
    hf = terrain.heightfield
    if step_m is None:
        x0, x1, y0, y1 = hf.extent_m
        step_m = max(x1 - x0, y1 - y0) / 200
    pts = []
    for a, b in zip(xy, np.roll(xy, -1, axis=0), strict=True):
        k = max(1, int(np.ceil(np.hypot(*(b - a)) / step_m)))
        pts.append(a + (b - a) * (np.arange(k) / k)[:, None])
    dense = np.vstack(pts)
    z = hf.height_at_clamped(dense[:, 0], dense[:, 1]) + lift_m
    return np.column_stack([dense, z])
