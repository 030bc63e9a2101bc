"""Turn a project into a render job: scene files in local coordinates plus job.json.

The job is what a render worker reads (``designer.render.worker``); it is prepared once
per output folder and shared by all workers, local or on a cluster. Everything handed
to Blender is local — world minus the project origin — because Blender stores float32.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import cv2
import numpy as np

from designer import __version__
from designer.atomic import atomic_path
from designer.core.interior import InteriorOrientation
from designer.core.projection import ground_sample_distance_m, pixel_rays_world
from designer.core.truth import CameraPose
from designer.effects.distortion_render import pinhole_render_camera
from designer.effects.from_model import effects_from_model
from designer.effects.motion import flight_direction_uv
from designer.project import model as m
from designer.project import write_project
from designer.render.blender_camera import blender_camera, blender_matrix_world
from designer.render.job_spec import (
    TEXTURE_UV_MAP,
    AdaptiveSampling,
    EffectsSpec,
    FrameSpec,
    MaterialSpec,
    MeshSpec,
    RenderJob,
    RenderSpec,
)
from designer.scene.build import BuiltScene, build_scene
from designer.scene.lighting import (
    LIGHTMAP_SCALE,
    bake_lightmap,
    encode_lightmap_png16,
    irradiance,
    sun_direction_world,
)
from designer.scene.objects import OBJECT_ALBEDO_RGB, PlacedObjects, build_objects
from designer.survey.project_poses import project_stations, render_interior

#: samples per pixel of each quality preset; measured costs in the README
QUALITY_SAMPLES = {"draft": 4, "survey": 16, "metrology": 64}
PIXEL_FILTERS = {"box": "BOX", "gaussian": "GAUSSIAN", "blackman-harris": "BLACKMAN_HARRIS"}
#: linear reflectance of a target's white and black quadrants
TARGET_WHITE, TARGET_BLACK = 0.8, 0.03
LIGHTMAP_MAX_PX = 512
JOB_DIR = ".designer-job"


@dataclass(frozen=True)
class PreparedJob:
    job_path: Path
    job: RenderJob
    interior: InteriorOrientation
    poses: tuple[CameraPose, ...]
    scene: BuiltScene


def prepare_job(
    project: m.Project,
    base_dir: Path,
    out_dir: Path,
    quality: str | None = None,
) -> PreparedJob:
    """Build the scene, write its files under ``out_dir/.designer-job`` and the job.json."""
    out_dir = Path(out_dir)
    job_dir = out_dir / JOB_DIR
    job_dir.mkdir(parents=True, exist_ok=True)
    origin = np.array([project.origin.E0, project.origin.N0, project.origin.H0])
    scene = build_scene(project, base_dir)
    stations, camera_id = project_stations(project, scene.heightfield)
    poses = [CameraPose(s.image_name, s.C_world, s.R_cam_to_world) for s in stations]
    interior = render_interior(project.camera(camera_id), project.render.resolution_scale)
    # A distorted camera is rendered as a pinhole just large enough to cover its field,
    # then warped through the exact inverse (designer.effects): the warp is made once.
    render_camera, warp = pinhole_render_camera(interior,
                                                project.render.distortion_oversample)
    effects = None
    if not effects_from_model(project.effects, interior, warp=warp).is_empty:
        write_project(project, job_dir / "project.xml")
        if warp is not None:
            warp.save(job_dir / "distortion_warp.npz")
        effects = EffectsSpec(project="project.xml", camera_id=camera_id,
                              resolution_scale=project.render.resolution_scale,
                              warp="distortion_warp.npz" if warp is not None else None)

    _write_png(job_dir / "texture.png", cv2.cvtColor(scene.texture_rgb, cv2.COLOR_RGB2BGR))
    terrain_material = MaterialSpec(texture="texture.png",
                                    uv_tiles=tuple(float(t) for t in scene.texture_tiles),
                                    interpolation=scene.interpolation.capitalize())
    terrain_uv = {}
    if scene.texture_uv is not None:
        # An orthophoto: its own texture coordinates (from its geotransform), no tiling,
        # edge texels held beyond the image; the light map keeps the terrain's uv.
        terrain_material = replace(terrain_material, uv_tiles=(1.0, 1.0),
                                   uv_map=TEXTURE_UV_MAP, extension="EXTEND")
        terrain_uv = {"uv_texture": scene.texture_uv}
    if scene.heightfield is not None:
        x0, x1, y0, y1 = scene.heightfield.extent_m
        scale = LIGHTMAP_MAX_PX / max(x1 - x0, y1 - y0)
        size = (max(2, round((x1 - x0) * scale)), max(2, round((y1 - y0) * scale)))
        light = bake_lightmap(scene.heightfield, scene.sun_azimuth_deg, scene.sun_elevation_deg,
                              scene.sun_strength, scene.sky_strength, size_px=size)
        _write_png(job_dir / "lightmap.png", encode_lightmap_png16(light))
        terrain_material = replace(terrain_material, lightmap="lightmap.png",
                                   strength=LIGHTMAP_SCALE)
    _save_npz(job_dir / "terrain.npz", vertices_local=scene.terrain.vertices_world - origin,
              faces=scene.terrain.faces, uv=scene.terrain.uv, **terrain_uv)
    objects = [MeshSpec("terrain", "terrain.npz", (terrain_material,))]
    if scene.targets:
        objects.append(_targets_object(scene, origin, job_dir))
    placed = build_objects(project, base_dir, scene.sun_azimuth_deg, scene.sun_elevation_deg)
    if not placed.is_empty:
        objects.append(_scene_objects(placed, origin, job_dir))

    render = project.render
    samples = QUALITY_SAMPLES[quality] if quality else render.effective_samples
    preset = quality or (render.preset if render.samples is None else None)
    contexts = _frame_contexts(stations, interior, scene)
    job = RenderJob(
        designer_version=__version__,
        project=project.name,
        output_dir=str(out_dir.resolve()),
        origin_world=tuple(float(v) for v in origin),
        render=RenderSpec(
            samples=samples, seed=0,
            pixel_filter=PIXEL_FILTERS[render.pixel_filter_type],
            filter_width_px=float(render.pixel_filter_width_px),
            format="tiff" if render.output_format == "tiff" else "png",
            bit_depth=render.bit_depth, quality=quality,
            # metrology: plain 64 spp's corner accuracy in a third of its time, from the
            # sweep in docs/validation.md (designer bench accuracy)
            adaptive_sampling=(AdaptiveSampling(threshold=0.01, min_samples=4)
                               if preset == "metrology" else None)),
        camera=blender_camera(render_camera),
        width_px=interior.image_width_px,
        height_px=interior.image_height_px,
        objects=tuple(objects),
        effects=effects,
        frames=tuple(FrameSpec(index=i, image_name=p.image_name,
                               matrix_world_local=_matrix_rows(blender_matrix_world(
                                   p.C_world, p.R_cam_to_world, origin)),
                               **contexts[i])
                     for i, p in enumerate(poses)),
    )
    job_path = job.write(job_dir / "job.json")
    return PreparedJob(job_path=job_path, job=job, interior=interior, poses=tuple(poses),
                       scene=scene)


def _matrix_rows(M: np.ndarray) -> tuple[tuple[float, ...], ...]:
    return tuple(tuple(float(v) for v in row) for row in M)


def _frame_contexts(stations, interior: InteriorOrientation, scene: BuiltScene) -> list[dict]:
    """Per frame: GSD at the principal point (m/px), the flight direction in the image and
    the distance along the optical axis to the ground there (m)."""
    out = []
    centre = np.array([[interior.cx_px, interior.cy_px]])
    for st in stations:
        ray = pixel_rays_world(centre, st.R_cam_to_world, interior)
        depth = None
        if scene.heightfield is not None:
            hit = scene.heightfield.intersect_rays(st.C_world[None], ray)[0]
            if np.isfinite(hit[0]):
                depth = float(-(hit - st.C_world) @ st.R_cam_to_world[:, 2])
        if depth is None:
            depth = float(st.C_world[2] - np.mean(scene.terrain.vertices_world[:, 2]))
        az = np.radians(st.flight_azimuth_deg)
        velocity = np.array([np.sin(az), np.cos(az), 0.0])
        du, dv = flight_direction_uv(velocity, st.R_cam_to_world)
        out.append({"gsd_m": float(ground_sample_distance_m(interior, abs(depth))),
                    "flight_direction_uv": (float(du), float(dv)),
                    "distance_m": float(abs(depth))})
    return out


def _targets_object(scene: BuiltScene, origin: np.ndarray, job_dir: Path) -> MeshSpec:
    """All GCP targets as one mesh: material 0 white, 1 black, shaded like the ground."""
    vertices, faces, material_index, light = [], [], [], []
    sun = sun_direction_world(scene.sun_azimuth_deg, scene.sun_elevation_deg)
    offset = 0
    for t in scene.targets:
        normal = np.cross(t.vertices_world[1] - t.vertices_world[0],
                          t.vertices_world[3] - t.vertices_world[0])
        normal /= np.linalg.norm(normal)
        lit = 1.0
        if scene.heightfield is not None and sun[2] > 0:
            hit = scene.heightfield.intersect_rays(t.true_xyz[None] + 0.01 * normal, sun[None])
            lit = 0.0 if np.isfinite(hit[0, 0]) else 1.0
        e = float(irradiance(normal[None], np.array([lit]), sun,
                             scene.sun_strength, scene.sky_strength)[0])
        vertices.append(t.vertices_world - origin)
        faces.append(t.faces + offset)
        white = t.colors[:, 0] > 127
        material_index.append(np.where(white, 0, 1))
        light.append(e)
        offset += len(t.vertices_world)
    # One light value for all targets keeps two materials; targets share open ground.
    e = float(np.median(light))
    _save_npz(job_dir / "targets.npz", vertices_local=np.concatenate(vertices),
              faces=np.concatenate(faces), material_index=np.concatenate(material_index))
    return MeshSpec("gcp_targets", "targets.npz",
                    (MaterialSpec(color=(TARGET_WHITE * e,) * 3),
                     MaterialSpec(color=(TARGET_BLACK * e,) * 3)))


#: light levels the scene objects' faces are drawn with (one emission material each)
OBJECT_LIGHT_LEVELS = 64


def _scene_objects(placed: PlacedObjects, origin: np.ndarray, job_dir: Path) -> MeshSpec:
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
    _save_npz(job_dir / "objects.npz", vertices_local=placed.vertices_world - origin,
              faces=placed.faces, material_index=index)
    return MeshSpec("scene_objects", "objects.npz",
                    tuple(MaterialSpec(color=tuple(float(c * e) for c in OBJECT_ALBEDO_RGB))
                          for e in values))


def _write_png(path: Path, image: np.ndarray) -> None:
    with atomic_path(path) as tmp:
        if not cv2.imwrite(str(tmp), image):
            raise OSError(f"could not write {path}")


def _save_npz(path: Path, **arrays) -> None:
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        np.savez(f, **arrays)
