"""The rolling shutter of a render job (docs/world.md, "Rolling shutter").

Cycles renders it exactly with its own rolling shutter (``rolling_shutter_type`` TOP,
``rolling_shutter_duration`` 0, motion blur on): every sample of the image row r
(0 = top row) is traced at the shutter fraction τ = (r + 1) / H (measured: an edge swept
by a camera moving 60 px over the shutter lies on u = 79.55 − 0.4996 r px against
79.5 − 0.5 r predicted, 160 × 120 px, 256 samples), and the camera moves linearly between
the two poses the job gives it at τ = 0 and τ = 1. The designer model exposes row r at
t0 + r / H · readout (top-to-bottom) or t0 + (H − 1 − r) / H · readout (bottom-to-top),
so the two poses are those of the instants t(τ) = t0 + (τ − 1/H) · readout and
t0 + (1 − τ) · readout. No banding: each row is one instant, as on the sensor.
"""

from __future__ import annotations

import numpy as np

from designer.core.interior import InteriorOrientation
from designer.core.truth import CameraPose
from designer.errors import DesignerError
from designer.project import model as m
from designer.render.blender_camera import blender_matrix_world
from designer.survey.timeline import station_velocities_m_s


def shutter_delays_s(height_px: int, readout_s: float, direction: str) -> tuple[float, float]:
    """Seconds after the first row's instant of Cycles' shutter start (τ = 0) and end
    (τ = 1) for the model's row times (module docstring)."""
    if direction == "top-to-bottom":
        return -readout_s / height_px, readout_s * (height_px - 1) / height_px
    if direction == "bottom-to-top":
        return readout_s, 0.0
    raise ValueError(f"rolling-shutter direction {direction!r}")


def shutter_matrices_local(pose: CameraPose, velocity_m_s: np.ndarray, readout_s: float,
                           direction: str, height_px: int, origin_world: np.ndarray
                           ) -> tuple[tuple[tuple[float, ...], ...], ...]:
    """Blender camera matrices (local) at Cycles' shutter start and end: the first-row
    pose moved by the velocity over each instant's delay, attitude unchanged."""
    out = []
    for delay in shutter_delays_s(height_px, readout_s, direction):
        C = np.asarray(pose.C_world, float) + np.asarray(velocity_m_s, float) * delay
        M = blender_matrix_world(C, pose.R_cam_to_world, origin_world)
        out.append(tuple(tuple(float(v) for v in row) for row in M))
    return tuple(out)


def rolling_job(project: m.Project, images, times, poses: list[CameraPose],
                frame_interiors: list[InteriorOrientation], origin_world: np.ndarray,
                contexts: list[dict]):
    """(each image's rolling shutter, empty when no image has one; the platform velocity
    at each image (N, 3) m/s or None; the one camera's rolling shutter, None for a rig or
    a global shutter). Each rolling frame's shutter matrices go into its context
    (``contexts``, one dict per frame, filled in)."""
    frame_shutters, velocities = frame_rolling_shutters(project, images, times)
    for i, (pose, rs) in enumerate(zip(poses, frame_shutters, strict=True)):
        if rs is not None:
            contexts[i]["shutter_matrices_local"] = shutter_matrices_local(
                pose, velocities[i], rs.readout_s, rs.direction,
                frame_interiors[i].image_height_px, origin_world)
    rolling = frame_shutters[0] if not images.is_multi_camera else None
    if velocities is None:
        frame_shutters = ()
    return frame_shutters, velocities, rolling


def frame_rolling_shutters(project: m.Project, images, times):
    """(each image's rolling shutter, its own camera's: None for a global shutter (no
    element, or a readout of 0); the platform velocity at each image (N, 3) m/s, None when
    no image has a rolling shutter). Every image of a rig station shares its velocity."""
    shutters = {}
    for c in images.camera_order():
        rs = project.camera(c).rolling_shutter
        shutters[c] = None if rs is None or rs.readout_s == 0 else rs
    frame_shutters = [shutters[c] for c in images.camera_ids]
    rolling = [c for c, rs in shutters.items() if rs is not None]
    if not rolling:
        return frame_shutters, None
    if times is None:
        raise DesignerError(f"camera '{rolling[0]}' has a rolling shutter but the trajectory "
                            "has no <time-line>; add one or set readout-s 0")
    _readout_within_frame_interval(shutters, images, times)
    platform = station_velocities_m_s(images.platform, project.trajectory.time_line)
    return frame_shutters, platform[np.asarray(images.station_index)]


def _readout_within_frame_interval(shutters, images, times) -> None:
    """DesignerError when a camera's readout is not shorter than the time between two of
    its photos: its rows would still be read when the next exposure starts (validation
    checks this against a declared trigger-interval-s; here, against the time line)."""
    for cam, rs in shutters.items():
        if rs is None:
            continue
        mine = [t for t, c in zip(times, images.camera_ids, strict=True) if c == cam]
        seconds = np.unique([t.time_s for t in mine])  # a rig station's images: one time
        if len(seconds) < 2:
            continue
        gaps = np.diff(seconds)
        k = int(np.argmin(gaps))
        if rs.readout_s >= gaps[k] * (1 - 1e-9):
            first = next(t.image_name for t in mine if t.time_s == seconds[k])
            second = next(t.image_name for t in mine if t.time_s == seconds[k + 1])
            raise DesignerError(
                f"camera '{cam}': readout-s {rs.readout_s:g} s is not shorter than the "
                f"{gaps[k]:.3g} s between {first} and {second} on the time line; a frame "
                "must be read before the next is taken: shorten the readout, fly slower or "
                "space the photos further")
