"""The moving objects of a render job: each object's mesh in its own frame (one .npz
beside job.json) and its pose at each frame's time (docs/world.md, Moving objects)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from designer.project import model as m
from designer.render.job_files import save_npz
from designer.render.job_spec import MaterialSpec, MeshSpec
from designer.scene.moving import MovingPose, pose_at, shape_mesh

#: Blender object-name prefix of a moving object (keeps them apart from the scene's own)
MOVING_PREFIX = "moving:"


def moving_job(project: m.Project, base_dir: Path, scene, job_dir: Path, times,
               origin: np.ndarray, contexts: list[dict]
               ) -> tuple[tuple[MeshSpec, ...], dict | None, list[tuple[MovingPose, ...]]]:
    """(the job's mesh specs, the meshes as :func:`moving_meshes`, per frame every moving
    object's pose) for frames taken at ``times`` (StationTime each); each frame's poses
    also go into its context (``contexts``, one dict per frame, filled in). Nothing
    without moving objects or a time line."""
    if not project.scene.moving_objects or times is None:
        return (), None, []
    specs, meshes = moving_meshes(project, base_dir, job_dir)
    moving = frame_moving_poses(project, scene, [t.time_s for t in times])
    for i, frame_poses in enumerate(moving):
        contexts[i]["moving_poses"] = local_poses(frame_poses, origin)
    return specs, meshes, moving


def moving_meshes(project: m.Project, base_dir: Path, job_dir: Path
                  ) -> tuple[tuple[MeshSpec, ...], dict[str, tuple[np.ndarray, np.ndarray]]]:
    """(the job's mesh specs, {object id: (vertices (N, 3), faces (M, 3)) in the object's
    frame, m}). Each object is drawn in its albedo as flat open ground is lit."""
    specs, meshes = [], {}
    for k, obj in enumerate(project.scene.moving_objects):
        vertices, faces = shape_mesh(obj, base_dir)
        name = f"moving_{k}.npz"
        save_npz(Path(job_dir) / name, vertices_local=vertices, faces=faces)
        specs.append(MeshSpec(MOVING_PREFIX + obj.id, name,
                              (MaterialSpec(color=tuple(float(c) for c in obj.albedo_rgb)),)))
        meshes[obj.id] = (vertices, faces)
    return tuple(specs), meshes


def frame_moving_poses(project: m.Project, scene, times_s: list[float]
                       ) -> list[tuple[MovingPose, ...]]:
    """Per frame, every moving object's pose at the frame's time."""
    return [tuple(pose_at(obj, t, scene) for obj in project.scene.moving_objects)
            for t in times_s]


def local_poses(poses: tuple[MovingPose, ...], origin: np.ndarray
                ) -> tuple[tuple[str, float, float, float, float], ...]:
    """A frame's poses as FrameSpec.moving_poses: base centre local (world − origin)."""
    return tuple((MOVING_PREFIX + p.object_id,
                  *(float(v) for v in np.asarray(p.position_world) - origin),
                  float(p.heading_deg)) for p in poses)
