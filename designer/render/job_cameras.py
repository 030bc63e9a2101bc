"""The cameras and frames of a render job: each camera's interior as rendered (a
distorted camera as the pinhole that covers its field, warped afterwards), a rig's
per-frame cameras, and each frame's spec with what the effects need to know of it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from designer.core.interior import InteriorOrientation
from designer.core.projection import ground_sample_distance_m, pixel_rays_world
from designer.core.truth import CameraPose, CameraSet
from designer.effects.distortion_render import DistortionWarp, pinhole_render_camera
from designer.effects.motion import flight_direction_uv
from designer.project import model as m
from designer.project.interiors import render_interior
from designer.render.blender_camera import blender_camera, blender_matrix_world
from designer.render.job_spec import FrameSpec
from designer.scene.build import BuiltScene


@dataclass(frozen=True)
class JobCameras:
    """The cameras of a job's images: ``interiors`` and ``rendered`` (the pinhole
    rendered and its distortion warp, None for none) by camera id; ``camera_ids`` each
    image's camera; ``cameras`` the rig's CameraSet (None: one camera)."""

    interiors: dict[str, InteriorOrientation]
    rendered: dict[str, tuple[InteriorOrientation, DistortionWarp | None]]
    camera_ids: tuple[str, ...]
    #: the first camera of the project's order: the job's own camera
    camera_id: str
    cameras: CameraSet | None = None

    @property
    def multi(self) -> bool:
        return self.cameras is not None

    @property
    def interior(self) -> InteriorOrientation:
        return self.interiors[self.camera_id]

    def frame_interiors(self) -> list[InteriorOrientation]:
        """Each image's camera interior."""
        return [self.interiors[c] for c in self.camera_ids]

    def frame_rendered(self) -> list[InteriorOrientation]:
        """Each image's camera as rendered (the pinhole)."""
        return [self.rendered[c][0] for c in self.camera_ids]


def job_cameras(project: m.Project, images) -> JobCameras:
    """The cameras of the planned ``images`` (designer.survey.project_poses)."""
    camera_order = images.camera_order()
    interiors = {c: render_interior(project.camera(c), project.render.resolution_scale)
                 for c in camera_order}
    # A distorted camera is rendered as a pinhole just large enough to cover its field,
    # then warped through the exact inverse (designer.effects): the warp is made once
    # per camera.
    rendered = {c: pinhole_render_camera(i, project.render.distortion_oversample)
                for c, i in interiors.items()}
    cameras = None
    if images.is_multi_camera:
        cameras = CameraSet(interiors, dict(zip((s.image_name for s in images.stations),
                                                images.camera_ids, strict=True)))
    return JobCameras(interiors, rendered, tuple(images.camera_ids), camera_order[0],
                      cameras)


def frame_specs(poses: list[CameraPose], cams: JobCameras, contexts: list[dict],
                origin: np.ndarray) -> tuple[FrameSpec, ...]:
    """Each frame's spec: its camera matrix (local: world − ``origin``), a rig's camera
    of it, and its context (``contexts``, one dict per frame)."""
    n = len(poses)
    frame_cameras, frame_ids, frame_sizes = [None] * n, [None] * n, [None] * n
    if cams.multi:
        specs = {c: blender_camera(cams.rendered[c][0]) for c in cams.interiors}
        frame_cameras = [specs[c] for c in cams.camera_ids]
        frame_ids = list(cams.camera_ids)
        frame_sizes = [cams.interiors[c].image_size_px for c in cams.camera_ids]
    return tuple(FrameSpec(index=i, image_name=p.image_name,
                           matrix_world_local=_matrix_rows(blender_matrix_world(
                               p.C_world, p.R_cam_to_world, origin)),
                           camera=frame_cameras[i], camera_id=frame_ids[i],
                           size_px=frame_sizes[i], **contexts[i])
                 for i, p in enumerate(poses))


def frame_contexts(stations, interiors: list[InteriorOrientation], scene: BuiltScene
                   ) -> list[dict]:
    """Per frame (with its camera's interior): GSD at the principal point (m/px), the
    flight direction in the image and the distance along the optical axis to the ground
    there (m)."""
    out = []
    for st, interior in zip(stations, interiors, strict=True):
        centre = np.array([[interior.cx_px, interior.cy_px]])
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


def _matrix_rows(M: np.ndarray) -> tuple[tuple[float, ...], ...]:
    return tuple(tuple(float(v) for v in row) for row in M)
