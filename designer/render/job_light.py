"""The lit objects of a render job: terrain with its baked light map, GCP targets and
scene objects, each drawn as emission under one sun — and, for a sun over time, one set
per sun of the flight (:class:`~designer.render.job_spec.LightStep`).

Each light map is baked exactly for its sun (no interpolation between bakes; the
measured cost and the error interpolation would bring are in docs/world.md). A frame's
step is its own sun: frames taken at the same moment share one.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from designer.core.heightfield import Heightfield
from designer.project import model as m
from designer.render.job_files import save_npz, write_png
from designer.render.job_spec import LightStep, MaterialSpec, MeshSpec
from designer.scene.build import BuiltScene
from designer.scene.lighting import (
    LIGHTMAP_SCALE,
    bake_lightmap,
    bake_lightmap_direct,
    encode_lightmap_png16,
    irradiance,
    lightmap_texel_centres,
    sun_direction_world,
)
from designer.scene.objects import OBJECT_ALBEDO_RGB, PlacedObjects, build_objects

#: linear reflectance of a target's white and black quadrants
TARGET_WHITE, TARGET_BLACK = 0.8, 0.03
LIGHTMAP_MAX_PX = 512
#: light levels the scene objects' faces are drawn with (one emission material each)
OBJECT_LIGHT_LEVELS = 64


def frame_suns(project: m.Project, times) -> list[tuple[float, float]] | None:
    """The sun (grid azimuth, elevation; deg) of each frame when the project's sun
    follows the time line, else None (one sun for all)."""
    sun = project.scene.lighting.sun
    if not isinstance(sun, m.SunOverTime) or times is None:
        return None
    from designer.scene.sun_over_time import project_site, suns_at

    return suns_at([t.time_utc for t in times], project_site(project, sun))


class ObjectLighting:
    """Writes the lit objects of a scene under a given sun into the job folder."""

    def __init__(self, project: m.Project, base_dir: Path, scene: BuiltScene,
                 origin: np.ndarray, job_dir: Path,
                 terrain_material: MaterialSpec | tuple[MaterialSpec, ...]) -> None:
        self.project, self.base_dir, self.scene = project, Path(base_dir), scene
        self.origin, self.job_dir = origin, Path(job_dir)
        #: the terrain's materials (two for a detail and a coarse bake, by face)
        self.terrain_materials = (terrain_material if isinstance(terrain_material, tuple)
                                  else (terrain_material,))
        #: per sun (and cloud moment): its targets and scene objects; per sun: its
        #: (light map, direct part)
        self._others: dict[tuple, list[MeshSpec]] = {}
        self._bakes: dict[tuple[float, float], tuple[np.ndarray, np.ndarray]] = {}
        #: the clouds' factor on the direct sun at the last light map's texel centres, as
        #: a regular grid (Heightfield: bilinear between nodes, edges held beyond)
        self._clouds_now: Heightfield | None = None
        #: the buildings standing on the terrain (built on first use)
        self._buildings: list | None = None

    @property
    def buildings(self) -> list:
        """The project's buildings (:class:`designer.scene.buildings.BuildingMesh`)."""
        if self._buildings is None:
            self._buildings = []
            if self.project.scene.buildings:
                from designer.render.job_buildings import write_building_textures
                from designer.scene.buildings import build_buildings

                self._buildings = build_buildings(self.project, self.base_dir, self.scene)
                write_building_textures(self.job_dir)
        return self._buildings

    def lightmap_size_px(self) -> tuple[int, int]:
        x0, x1, y0, y1 = self.scene.heightfield.extent_m
        scale = LIGHTMAP_MAX_PX / max(x1 - x0, y1 - y0)
        return max(2, round((x1 - x0) * scale)), max(2, round((y1 - y0) * scale))

    def objects(self, azimuth_deg: float, elevation_deg: float, tag: str = "",
                time_s: float | None = None) -> list[MeshSpec]:
        """Terrain (with a light map baked for this sun), targets and scene objects;
        files are named with ``tag`` (''  for the one sun of a static scene). With
        cloud shadows, the direct sun on the terrain's light map, the targets, the scene
        objects and the buildings is dimmed by the clouds at ``time_s`` (s after take-off;
        None: at take-off), each point as the ground under it."""
        scene = self.scene
        materials = self.terrain_materials
        clouds = self.project.scene.lighting.clouds
        cloudy = clouds is not None and scene.heightfield is not None
        if scene.heightfield is not None:
            size = self.lightmap_size_px()
            if not cloudy:
                light = bake_lightmap(scene.heightfield, azimuth_deg, elevation_deg,
                                      scene.sun_strength, scene.sky_strength, size_px=size)
            else:
                light = self._cloudy_light(azimuth_deg, elevation_deg, size, time_s or 0.0)
            name = f"lightmap{tag}.png"
            write_png(self.job_dir / name, encode_lightmap_png16(light))
            materials = tuple(replace(mat, lightmap=name,
                                      strength=mat.strength * LIGHTMAP_SCALE)
                              for mat in materials)
        objects = [MeshSpec("terrain", "terrain.npz", materials)]
        cache = self._others
        key = (azimuth_deg, elevation_deg, (time_s or 0.0) if cloudy else None)
        if key in cache:  # same sun (and clouds), other light map
            return objects + cache[key]
        sun_share = self._sun_share if cloudy else None
        others = []
        if scene.targets:
            # targets lit per cloud moment differ in material indices: a file per step
            others.append(_targets_object(scene, self.origin, self.job_dir, azimuth_deg,
                                          elevation_deg, sun_share,
                                          f"targets{tag}.npz" if cloudy else "targets.npz"))
        placed = build_objects(self.project, self.base_dir, azimuth_deg, elevation_deg,
                               sun_share)
        if not placed.is_empty:
            others.append(_scene_objects(placed, self.origin, self.job_dir,
                                         f"objects{tag}.npz"))
        if self.buildings:
            from designer.render.job_buildings import buildings_object

            others.append(buildings_object(self.buildings, self.origin, self.job_dir,
                                           azimuth_deg, elevation_deg, scene.sun_strength,
                                           scene.sky_strength, f"buildings{tag}.npz",
                                           sun_share))
        cache[key] = others
        return objects + others

    def _cloudy_light(self, azimuth_deg: float, elevation_deg: float,
                      size: tuple[int, int], time_s: float) -> np.ndarray:
        """The light map with the direct sun dimmed by the cloud shadows at ``time_s``;
        the clouds' factor on the direct sun is kept for :meth:`_sun_share`."""
        from designer.scene.cloud_shadows import attenuation

        bakes = self._bakes
        key = (azimuth_deg, elevation_deg)
        if key not in bakes:
            scene = self.scene
            bakes.clear()
            bakes[key] = bake_lightmap_direct(scene.heightfield, azimuth_deg, elevation_deg,
                                              scene.sun_strength, scene.sky_strength, size)
        light, direct = bakes[key]
        xs, ys = lightmap_texel_centres(self.scene.heightfield, size)
        a = attenuation(self.project.scene.lighting.clouds, xs - self.origin[0],
                        ys - self.origin[1], time_s)
        # rows north to south in the light map, south to north in the grid
        self._clouds_now = Heightfield(float(xs[0]), float(ys[-1]), float(xs[1] - xs[0]),
                                       float(ys[0] - ys[1]), a[::-1])
        return (light - direct * (1.0 - a)).astype(np.float32)

    def _sun_share(self, x_m: np.ndarray, y_m: np.ndarray) -> np.ndarray:
        """The clouds' factor on the direct sun at world points (x_m, y_m), as the light
        map just baked has it (bilinear between its texel centres, edge texels beyond)."""
        return self._clouds_now.height_at_clamped(x_m, y_m)

    def steps(self, suns: list[tuple[float, float]], times_s: list[float] | None = None
              ) -> tuple[tuple[LightStep, ...], list[int]]:
        """One light step per distinct sun — and, with ``times_s`` (cloud shadows), per
        distinct moment — and each frame's step index."""
        index: dict[tuple, int] = {}
        steps = []
        keys = [(sun, None if times_s is None else times_s[i]) for i, sun in enumerate(suns)]
        for sun, t in keys:
            if (sun, t) not in index:
                index[(sun, t)] = len(steps)
                steps.append(LightStep(sun[0], sun[1], tuple(
                    self.objects(*sun, tag=f"-{len(steps):05d}", time_s=t))))
        return tuple(steps), [index[k] for k in keys]


@dataclass(frozen=True)
class FrameLight:
    """How a job's frames are lit: ``objects`` (the first light step's, with a sun over
    time), the light ``steps`` (empty: one sun for every frame), each frame's step index
    (None with one sun) and each frame's sun (grid azimuth, elevation; deg)."""

    objects: list
    steps: tuple
    frame_steps: list
    suns: list


def frame_light(light: ObjectLighting, project: m.Project, scene: BuiltScene, times,
                n_frames: int) -> FrameLight:
    """Write the lit objects of the job's ``n_frames`` frames taken at ``times``
    (StationTime each; None: no time line): one set for one sun, else one per light
    step."""
    suns = frame_suns(project, times)
    clouds = project.scene.lighting.clouds
    drifting = clouds is not None and times is not None
    if suns is None and not drifting:
        # one sun (and clouds frozen at take-off, if any): the objects as built are lit
        # for every frame
        objects = light.objects(scene.sun_azimuth_deg, scene.sun_elevation_deg)
        suns = [(scene.sun_azimuth_deg, scene.sun_elevation_deg)] * n_frames
        return FrameLight(objects, (), [None] * n_frames, suns)
    if suns is None:
        suns = [(scene.sun_azimuth_deg, scene.sun_elevation_deg)] * n_frames
    steps, frame_steps = light.steps(suns, [t.time_s for t in times] if drifting else None)
    return FrameLight(list(steps[0].objects), steps, frame_steps, suns)


def _targets_object(scene: BuiltScene, origin: np.ndarray, job_dir: Path,
                    azimuth_deg: float, elevation_deg: float,
                    sun_share: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
                    file_name: str = "targets.npz") -> MeshSpec:
    """All GCP targets as one mesh, shaded like the ground: without clouds materials 0
    white and 1 black, with one light for all (targets share open ground); with cloud
    shadows (``sun_share``: the direct sun's factor at world x, y) each target is lit as
    the ground under it, materials 2k white and 2k + 1 black for its light level k."""
    vertices, faces, material_index, light = [], [], [], []
    sun = sun_direction_world(azimuth_deg, elevation_deg)
    offset = 0
    for t in scene.targets:
        normal = np.cross(t.vertices_world[1] - t.vertices_world[0],
                          t.vertices_world[3] - t.vertices_world[0])
        normal /= np.linalg.norm(normal)
        lit = 1.0
        if scene.heightfield is not None and sun[2] > 0:
            hit = scene.heightfield.intersect_rays(t.true_xyz[None] + 0.01 * normal, sun[None])
            lit = 0.0 if np.isfinite(hit[0, 0]) else 1.0
        if sun_share is not None:
            lit *= float(sun_share(t.true_xyz[None, 0], t.true_xyz[None, 1])[0])
        e = float(irradiance(normal[None], np.array([lit]), sun,
                             scene.sun_strength, scene.sky_strength)[0])
        vertices.append(t.vertices_world - origin)
        faces.append(t.faces + offset)
        white = t.colors[:, 0] > 127
        material_index.append(np.where(white, 0, 1))
        light.append(np.full(len(t.faces), e))
        offset += len(t.vertices_world)
    if sun_share is None:
        # One light value for all targets keeps two materials; targets share open ground.
        levels = np.array([float(np.median([e[0] for e in light]))])
        level = np.zeros(sum(len(e) for e in light), np.int64)
    else:
        levels, level = np.unique(np.round(np.concatenate(light), 12), return_inverse=True)
    save_npz(job_dir / file_name, vertices_local=np.concatenate(vertices),
             faces=np.concatenate(faces),
             material_index=2 * level.ravel() + np.concatenate(material_index))
    return MeshSpec("gcp_targets", file_name, tuple(
        MaterialSpec(color=(reflectance * float(e),) * 3)
        for e in levels for reflectance in (TARGET_WHITE, TARGET_BLACK)))


def _scene_objects(placed: PlacedObjects, origin: np.ndarray, job_dir: Path,
                   file_name: str = "objects.npz") -> MeshSpec:
    """The scene's mesh objects as one mesh, each face drawn with its light (quantised
    to OBJECT_LIGHT_LEVELS levels between the darkest and brightest face, < 1 % steps for
    the usual range) times the objects' albedo."""
    light = placed.face_irradiance
    lo, hi = float(light.min()), float(light.max())
    n = OBJECT_LIGHT_LEVELS if hi > lo else 1
    level = np.zeros(len(light), np.int64) if n == 1 else np.rint(
        (light - lo) / (hi - lo) * (n - 1)).astype(np.int64)
    used = np.unique(level)
    index = np.searchsorted(used, level)
    values = lo + used * ((hi - lo) / max(n - 1, 1))
    save_npz(job_dir / file_name, vertices_local=placed.vertices_world - origin,
              faces=placed.faces, material_index=index)
    return MeshSpec("scene_objects", file_name,
                    tuple(MaterialSpec(color=tuple(float(c * e) for c in OBJECT_ALBEDO_RGB))
                          for e in values))

