"""Turn a project into a render job: scene files in local coordinates plus job.json.

The job is what a render worker reads (``designer.render.worker``); it is prepared once
per output folder and shared by all workers, local or on a cluster. Everything handed
to Blender is local — world minus the project origin — because Blender stores float32.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from designer import __version__
from designer.core.interior import InteriorOrientation
from designer.core.layout import IMAGES_DIR, JOB_DIR
from designer.core.truth import CameraPose, CameraSet
from designer.project import model as m
from designer.project.utc import iso_utc
from designer.render.blender_camera import blender_camera
from designer.render.effects_job import effects_spec
from designer.render.job_cameras import frame_contexts, frame_specs, job_cameras
from designer.render.job_light import (  # noqa: F401  (TARGET_*: part of the job's face)
    TARGET_BLACK,
    TARGET_WHITE,
    FrameLight,
    ObjectLighting,
    frame_light,
)
from designer.render.job_moving import moving_job
from designer.render.job_rolling import rolling_job
from designer.render.job_spec import SKY_RGB, AdaptiveSampling, RenderJob, RenderSpec
from designer.render.job_terrain import finish_terrain, terrain_texture, write_terrain
from designer.render.job_vegetation import vegetation_job
from designer.scene.build import BuiltScene, build_scene
from designer.survey.project_poses import project_images
from designer.survey.surroundings import project_surroundings
from designer.survey.timeline import StationTime, project_station_times

#: samples per pixel of each quality preset; measured costs in the README
QUALITY_SAMPLES = {"draft": 4, "survey": 16, "metrology": 64}
PIXEL_FILTERS = {"box": "BOX", "gaussian": "GAUSSIAN", "blackman-harris": "BLACKMAN_HARRIS"}


@dataclass(frozen=True)
class PreparedJob:
    job_path: Path
    job: RenderJob
    interior: InteriorOrientation
    poses: tuple[CameraPose, ...]
    scene: BuiltScene
    #: when each image is taken (None: the project has no time line)
    times: tuple[StationTime, ...] | None = None
    #: the sun (grid azimuth, elevation; deg) of each image
    suns: tuple[tuple[float, float], ...] = ()
    #: per image, every moving object's pose then (empty: no moving objects)
    moving_poses: tuple[tuple, ...] = ()
    #: {moving object id: (vertices, faces) in its own frame, m}
    moving_meshes: dict | None = None
    #: the one camera's rolling shutter (None: a global shutter, or several cameras: see
    #: ``frame_shutters``) and, when any image has one, the platform's velocity at each
    #: image (world m/s, (N, 3))
    rolling_shutter: m.RollingShutter | None = None
    velocities_m_s: np.ndarray | None = None
    #: each image's rolling shutter, its own camera's (None: a global shutter); empty
    #: when no image has one
    frame_shutters: tuple = ()
    #: the buildings as drawn (designer.scene.buildings.BuildingMesh; empty: none)
    buildings: tuple = ()
    #: the placed plants, one PlantSet per group (empty: no vegetation)
    plants: tuple = ()
    #: a multi-camera rig: every camera's rendered interior and each image's camera
    #: (None: one camera, ``interior``)
    cameras: CameraSet | None = None

    @property
    def camera_model(self) -> InteriorOrientation | CameraSet:
        """What the exporters take: the one interior, or the camera set of a rig."""
        return self.interior if self.cameras is None else self.cameras

    def interior_of(self, image_name: str) -> InteriorOrientation:
        """The rendered interior orientation of one image's camera."""
        return self.interior if self.cameras is None else self.cameras.interior_of(image_name)


def prepare_job(
    project: m.Project,
    base_dir: Path,
    out_dir: Path,
    quality: str | None = None,
    *,
    bake_texture: bool = True,
) -> PreparedJob:
    """Build the scene, write its files under ``out_dir/.designer-job`` and the job.json.

    The job's workers write the images into ``out_dir/images``
    (:mod:`designer.core.layout`). A varied ground texture is baked into one image
    (:mod:`designer.render.texture_bake`) where the bake fits; ``bake_texture=False``
    keeps Cycles' node graph (``designer bench render`` measures both).
    """
    out_dir = Path(out_dir)
    job_dir = out_dir / JOB_DIR
    job_dir.mkdir(parents=True, exist_ok=True)
    origin = np.array([project.origin.E0, project.origin.N0, project.origin.H0])
    # the stations are planned over the declared terrain; the surroundings grow the
    # rendered terrain as far as their images see
    growth, declared = project_surroundings(project, base_dir)
    scene = build_scene(project, base_dir, growth)
    images = project_images(project, declared)
    stations = list(images.stations)
    poses = [CameraPose(s.image_name, s.C_world, s.R_cam_to_world) for s in stations]
    cams = job_cameras(project, images)
    effects = effects_spec(project.effects, cams.interiors, cams.rendered, job_dir,
                           rig=cams.multi)
    texture = terrain_texture(project, scene, job_dir, poses, cams.frame_rendered(),
                              bake_texture)
    terrain_material = write_terrain(scene, texture, origin, job_dir)
    # each step below adds what it knows of a frame to the frame's context
    contexts = frame_contexts(stations, cams.frame_interiors(), scene)
    light = ObjectLighting(project, base_dir, scene, origin, job_dir, terrain_material)
    times = _frame_times(project, images)
    lit = frame_light(light, project, scene, times, len(stations))
    objects, tiled_spec = finish_terrain(texture, scene, lit.objects, job_dir,
                                         not lit.steps, contexts)
    _time_contexts(contexts, times, lit)
    moving_specs, meshes, moving = moving_job(project, base_dir, scene, job_dir, times,
                                              origin, contexts)
    plant_specs, wind_spec, plants = vegetation_job(project, base_dir, scene, job_dir,
                                                    origin)
    frame_shutters, velocities, rolling = rolling_job(
        project, images, times, poses, cams.frame_interiors(), origin, contexts)
    job = RenderJob(
        designer_version=__version__,
        project=project.name,
        output_dir=str((out_dir / IMAGES_DIR).resolve()),
        origin_world=tuple(float(v) for v in origin),
        render=_render_spec(project.render, quality),
        camera=blender_camera(cams.rendered[cams.camera_id][0]),
        width_px=cams.interior.image_width_px,
        height_px=cams.interior.image_height_px,
        objects=tuple(objects),
        # the sky above the horizon where images see it (else the black background)
        background_rgb=SKY_RGB if scene.growth.horizon else (0.0, 0.0, 0.0),
        light_steps=lit.steps, moving_objects=moving_specs, vegetation=plant_specs,
        wind=wind_spec, tiled_texture=tiled_spec,
        image_metadata=project.render.image_metadata, effects=effects,
        frames=frame_specs(poses, cams, contexts, origin),
    )
    job_path = job.write(job_dir / "job.json")
    return PreparedJob(job_path=job_path, job=job, interior=cams.interior, poses=tuple(poses),
                       scene=scene, times=None if times is None else tuple(times),
                       suns=tuple(lit.suns), moving_poses=tuple(moving), moving_meshes=meshes,
                       rolling_shutter=rolling, velocities_m_s=velocities,
                       frame_shutters=tuple(frame_shutters),
                       buildings=tuple(light.buildings), plants=tuple(plants),
                       cameras=cams.cameras)


def _frame_times(project: m.Project, images) -> list[StationTime] | None:
    """When each image is taken (None: the project has no time line). The time line is
    the platform's: every image of a rig station is taken then."""
    times = project_station_times(project, images.platform)
    if times is None:
        return None
    return [StationTime(st.image_name, times[k].time_s, times[k].time_utc)
            for st, k in zip(images.stations, images.station_index, strict=True)]


def _time_contexts(contexts: list[dict], times: list[StationTime] | None,
                   lit: FrameLight) -> None:
    """Add each frame's time, sun and light step to its context."""
    if times is None:
        return
    for i, t in enumerate(times):
        contexts[i].update(time_s=t.time_s, time_utc=iso_utc(t.time_utc),
                           sun_azimuth_deg=float(lit.suns[i][0]),
                           sun_elevation_deg=float(lit.suns[i][1]),
                           light_step=lit.frame_steps[i])


def _render_spec(render: m.Render, quality: str | None) -> RenderSpec:
    """The renderer's settings: the project's, or those of a ``quality`` preset."""
    samples = QUALITY_SAMPLES[quality] if quality else render.effective_samples
    preset = quality or (render.preset if render.samples is None else None)
    return RenderSpec(
        samples=samples, seed=0,
        pixel_filter=PIXEL_FILTERS[render.pixel_filter_type],
        filter_width_px=float(render.pixel_filter_width_px),
        format="tiff" if render.output_format == "tiff" else "png",
        bit_depth=render.bit_depth, quality=quality,
        # metrology: plain 64 spp's corner accuracy in a third of its time, from the
        # sweep in docs/validation.md (designer bench accuracy)
        adaptive_sampling=(AdaptiveSampling(threshold=0.01, min_samples=4)
                           if preset == "metrology" else None))
