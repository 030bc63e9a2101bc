"""Build the concrete scene of a project: terrain, texture, GCP targets and sun.

Everything here is in world coordinates (float64) and deterministic for a project:
the same file always gives the same terrain, texture, targets and surveyed
coordinates. The render job (designer.render.job) turns it into local coordinates.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from designer.core.heightfield import Heightfield
from designer.errors import DesignerError
from designer.project import model as m
from designer.project.scene_limits import MAX_TEXTURE_TEXELS
from designer.project.validate_shared import plain_number
from designer.scene.gcp_target import (
    DEFAULT_LIFT_M,
    target_clearance_m,
    target_mesh,
    target_point_world,
    target_pose_on_terrain,
)
from designer.scene.lighting import sun_position_deg
from designer.scene.mesh import TerrainMesh, heightfield_to_mesh, load_mesh
from designer.scene.orthophoto import Orthophoto, load_orthophoto, orthophoto_uv
from designer.scene.surroundings import Growth, grow_terrain
from designer.scene.terrain import load_dem, procedural_terrain
from designer.scene.texture import checkerboard_texture, load_texture, procedural_texture
from designer.scene.texture_variation import VariationImages, variation_images

#: the largest procedural texture side generated (px)
MAX_TEXTURE_PX = MAX_TEXTURE_TEXELS  # one limit: designer check refuses what is not made


@dataclass(frozen=True)
class BuiltTarget:
    """A GCP target as built: true point (the visible checker centre) and its geometry."""

    target: m.Target
    true_xyz: np.ndarray
    surveyed_xyz: np.ndarray
    sigma_xyz: np.ndarray
    vertices_world: np.ndarray
    faces: np.ndarray
    colors: np.ndarray


@dataclass(frozen=True)
class BuiltScene:
    #: the rendered terrain: the declared one plus its surroundings
    #: (:mod:`designer.scene.surroundings`); None for a mesh terrain
    heightfield: Heightfield | None
    terrain: TerrainMesh
    texture_rgb: np.ndarray
    texture_tiles: tuple[int, int]
    interpolation: str
    targets: tuple[BuiltTarget, ...]
    sun_azimuth_deg: float
    sun_elevation_deg: float
    sun_strength: float
    sky_strength: float
    #: (N, 2) texture coordinates per terrain vertex of an orthophoto (placed by its
    #: geotransform, not tiled); None: the texture is tiled over the terrain's own uv
    texture_uv: np.ndarray | None = None
    #: the texture variation over the terrain's UV extent
    #: (:mod:`designer.scene.texture_variation`), None without one
    variation: VariationImages | None = None
    #: the declared terrain (the area of interest) the stations are planned over; the
    #: rendered ``heightfield`` when there are no surroundings
    declared_heightfield: Heightfield | None = None
    #: how the rendered terrain was grown beyond the declared one
    growth: Growth = field(default_factory=Growth)


def uv_extent_m(hf: Heightfield | None, mesh: TerrainMesh) -> tuple[float, float, float, float]:
    """(x_min, x_max, y_min, y_max) of the world area the terrain's UV 0..1 spans: the
    height field's grid, or a mesh terrain's bounding box (its planar UV)."""
    if hf is not None:
        return hf.extent_m
    xy = mesh.vertices_world[:, :2]
    return (float(xy[:, 0].min()), float(xy[:, 0].max()),
            float(xy[:, 1].min()), float(xy[:, 1].max()))


def build_heightfield(terrain: m.Terrain, base_dir: Path,
                      crs: str | None = None) -> Heightfield | None:
    """The terrain as a height field (None for a mesh terrain).

    A DEM is read in the project's ``crs`` (reprojected if the file is in another) and
    cropped to the nodes covering the terrain extent.
    """
    e = terrain.extent
    src = terrain.source
    if isinstance(src, m.FlatTerrain):
        return Heightfield(e.min_X, e.min_Y, e.width_m, e.length_m,
                           np.full((2, 2), float(src.height_m)))
    if isinstance(src, m.ProceduralTerrain):
        relief = 0.5 * (src.max_height_m - src.min_height_m)
        return procedural_terrain(
            e.width_m, e.length_m, src.grid_spacing_m, relief, src.seed,
            x0_m=e.min_X, y0_m=e.min_Y,
            base_height_m=0.5 * (src.max_height_m + src.min_height_m),
            roughness=src.roughness, hill_size_m=src.hill_size_m)
    if isinstance(src, m.DemTerrain):
        return load_dem(base_dir / src.file, crs, (e.min_X, e.min_Y, e.max_X, e.max_Y))
    return None


def build_terrain_mesh(
    terrain: m.Terrain, hf: Heightfield | None, base_dir: Path, origin: np.ndarray
) -> TerrainMesh:
    if hf is not None:
        return heightfield_to_mesh(hf)
    mesh = load_mesh(base_dir / terrain.source.file)
    # Mesh terrain files hold world − origin coordinates.
    return TerrainMesh(vertices_world=mesh.vertices_world + origin, faces=mesh.faces,
                       uv=mesh.uv)


def build_orthophoto(texture: m.Texture, terrain: m.Terrain, base_dir: Path,
                     crs: str | None) -> Orthophoto | None:
    """The part of an orthophoto texture over the terrain extent (None for other textures)."""
    if not isinstance(texture.source, m.OrthophotoTexture):
        return None
    e = terrain.extent
    return load_orthophoto(base_dir / texture.source.file, crs,
                           (e.min_X, e.min_Y, e.max_X, e.max_Y))


#: the patterns drawn as noise, which needs this many texels a side at least
NOISE_PATTERNS = ("grass", "soil", "gravel", "noise")
MIN_NOISE_TEXELS = 16


def tile_problem(width_m: float, length_m: float, repeat_x: int, repeat_y: int,
                 texel_m: float, pattern: str) -> str:
    """Why a procedural tile of the extent (m) over the repeats at ``texel_m`` cannot be
    made ("" when it can): the texels of a side must be at most MAX_TEXTURE_PX and, for a
    noise pattern, at least MIN_NOISE_TEXELS (rounded as :func:`build_texture` does). Worded
    with the Texture panel's field names, for the GUI and the command line alike."""
    tile_w, tile_h = width_m / repeat_x, length_m / repeat_y
    w_px, h_px = round(tile_w / texel_m), round(tile_h / texel_m)
    made = (f"a tile ({plain_number(tile_w)} × {plain_number(tile_h)} m: the extent "
            f"{plain_number(width_m)} × {plain_number(length_m)} m over repeat X "
            f"{repeat_x}, repeat Y {repeat_y}) {w_px} × {h_px} texels")
    if max(w_px, h_px) > MAX_TEXTURE_PX:
        return f"{made}, more than {MAX_TEXTURE_PX}; raise the texel size or repeat X/Y"
    if pattern in NOISE_PATTERNS and min(w_px, h_px) < MIN_NOISE_TEXELS:
        return (f"{made} of {plain_number(texel_m, 4)} m, fewer than {MIN_NOISE_TEXELS}; "
                "lower the texel size or the repeats")
    return ""


def build_texture(texture: m.Texture, terrain: m.Terrain, base_dir: Path,
                  crs: str | None = None) -> np.ndarray:
    """The texture image (H, W, 3) uint8 RGB; an orthophoto's crop over the extent."""
    src = texture.source
    if isinstance(src, m.OrthophotoTexture):
        return build_orthophoto(texture, terrain, base_dir, crs).rgb
    if isinstance(src, m.ImageTexture):
        return load_texture(base_dir / src.file)
    e = terrain.extent
    tile_w = e.width_m / texture.repeat_X
    tile_h = e.length_m / texture.repeat_Y
    w_px = round(tile_w / src.texel_size_m)
    h_px = round(tile_h / src.texel_size_m)
    if max(w_px, h_px) > MAX_TEXTURE_PX:
        # in the Texture panel's words, as it refuses such a tile where it is typed
        raise DesignerError(f"texel size {plain_number(src.texel_size_m, 4)} m makes "
                            + tile_problem(e.width_m, e.length_m, texture.repeat_X,
                                           texture.repeat_Y, src.texel_size_m, src.pattern))
    if src.pattern == "checkerboard":
        return checkerboard_texture((max(2, w_px // 2 * 2), max(2, h_px // 2 * 2)), 1)
    if src.pattern in ("grass", "soil"):
        return procedural_texture((w_px, h_px), src.seed, kind=src.pattern)
    if src.pattern in ("gravel", "noise"):
        return procedural_texture((w_px, h_px), src.seed, kind="soil")
    raise DesignerError(
        f"texture pattern '{src.pattern}' cannot be rendered on terrain yet; use grass, soil, "
        "gravel, noise or checkerboard")


def _m(value: float) -> str:
    """A coordinate (m) as written: to the mm, without trailing zeros or an exponent."""
    return f"{float(value):.3f}".rstrip("0").rstrip(".")


def build_targets(project: m.Project, hf: Heightfield | None) -> tuple[BuiltTarget, ...]:
    targets = project.targets
    if not targets:
        return ()
    accuracy = project.scene.targets.survey_accuracy
    rng = np.random.default_rng(accuracy.seed if accuracy else 0)
    out = []
    for t in targets:
        if hf is None:
            if t.true.Z is None:
                raise DesignerError(
                    f"target {t.id}: a mesh terrain cannot drape targets; give its true Z")
            centre = np.array([t.true.X, t.true.Y, t.true.Z])
            R = np.eye(3)
            lift = DEFAULT_LIFT_M
        else:
            if not hf.contains(float(t.true.X), float(t.true.Y)):
                x0, x1, y0, y1 = hf.extent_m
                raise DesignerError(
                    f"GCP {t.id} at X {_m(t.true.X)}, Y {_m(t.true.Y)} lies outside the "
                    f"terrain (X {_m(x0)} to {_m(x1)}, Y {_m(y0)} to {_m(y1)}); move it onto "
                    "the terrain")
            centre, R = target_pose_on_terrain(hf, t.true.X, t.true.Y, t.size_m)
            if t.true.Z is not None:
                centre = np.array([t.true.X, t.true.Y, t.true.Z])
            # Lift the plate clear of curved ground so the terrain never pokes through.
            clearance = target_clearance_m(hf, centre, R, t.size_m, DEFAULT_LIFT_M)
            lift = DEFAULT_LIFT_M + max(0.0, 0.002 - clearance)
        vertices, faces, colors = target_mesh(centre, R, t.size_m, lift)
        true_xyz = target_point_world(centre, R, lift)
        # Draw the simulated survey error for every target, in file order, so adding a
        # measured position to one target does not change the others' errors.
        sigma = (np.array([accuracy.sigma.X, accuracy.sigma.Y, accuracy.sigma.Z])
                 if accuracy else np.zeros(3))
        error = rng.normal(0.0, 1.0, 3) * sigma
        if t.surveyed is not None:
            p, s = t.surveyed.position, t.surveyed.sigma
            surveyed, sigma = np.array([p.X, p.Y, p.Z]), np.array([s.X, s.Y, s.Z])
        else:
            surveyed = true_xyz + error
        out.append(BuiltTarget(t, true_xyz, surveyed, sigma, vertices, faces, colors))
    return tuple(out)


def build_scene(project: m.Project, base_dir: Path, growth: Growth | None = None
                ) -> BuiltScene:
    """Everything the renderer and the ground truth need, in world coordinates: the
    declared terrain grown by ``growth`` (:func:`designer.survey.surroundings.
    project_surroundings` plans it; None: the declared terrain alone)."""
    base_dir = Path(base_dir)
    origin = np.array([project.origin.E0, project.origin.N0, project.origin.H0])
    scene = project.scene
    declared = build_heightfield(scene.terrain, base_dir, project.crs)
    growth = growth or Growth()
    tiles = (scene.texture.repeat_X, scene.texture.repeat_Y)
    hf = declared
    if declared is not None and any(growth.steps):
        grown = grow_terrain(project, declared, growth)
        hf, tiles = grown.heightfield, grown.texture_tiles(tiles)
    mesh = build_terrain_mesh(scene.terrain, hf, base_dir, origin)
    ortho = build_orthophoto(scene.texture, scene.terrain, base_dir, project.crs)
    if ortho is not None:
        texture = ortho.rgb
        texture_uv = orthophoto_uv(ortho, mesh.vertices_world[:, :2], project.crs)
    else:
        texture = build_texture(scene.texture, scene.terrain, base_dir)
        texture_uv = None
    sun = scene.lighting.sun
    if isinstance(sun, m.Sun):
        azimuth, elevation = sun.azimuth_deg, sun.elevation_deg
    elif isinstance(sun, m.SunOverTime):  # the sun at take-off; each photo has its own
        from designer.scene.sun_over_time import takeoff_sun

        azimuth, elevation = takeoff_sun(project, sun)
    else:
        azimuth, elevation = sun_position_deg(sun.date_time, sun.latitude_deg, sun.longitude_deg)
    return BuiltScene(
        heightfield=hf, terrain=mesh, texture_rgb=texture,
        texture_tiles=tiles,
        interpolation=scene.texture.interpolation,
        targets=build_targets(project, hf),
        sun_azimuth_deg=float(azimuth), sun_elevation_deg=float(elevation),
        sun_strength=scene.lighting.sun_strength, sky_strength=scene.lighting.sky_strength,
        texture_uv=texture_uv,
        variation=(None if scene.texture.variation is None or texture_uv is not None else
                   variation_images(scene.texture.variation, uv_extent_m(hf, mesh))),
        declared_heightfield=declared, growth=growth)
