"""Ground truth of a rolling-shutter camera (docs/world.md, "Rolling shutter").

``ground-truth/rolling_shutter.csv`` states the model as Metashape and Pix4D use it: per
image the pose of the first row read (the image's pose in every other file), the readout
time and the platform's velocity during it (world frame, m/s); and the pixel coordinates
of the GCPs in every export are where the rolling-shutter image shows them
(:func:`designer.core.rolling_shutter.rolling_shutter_projection`).
"""

from __future__ import annotations

import numpy as np

from designer.core.layout import ROLLING_SHUTTER_CSV  # noqa: F401  (part of its face)
from designer.core.rolling_shutter import rolling_shutter_projection

COLUMNS = ("image", "readout_s", "direction", "velocity_E_m_s", "velocity_N_m_s",
           "velocity_H_m_s", "first_row_time", "first_row_time_s")


def rolling_shutter_uv(prepared, camera: np.ndarray, point: np.ndarray,
                       points_world: np.ndarray) -> np.ndarray:
    """(K, 2) pixel coordinates of ``points_world[point[k]]`` in image ``camera[k]`` of a
    prepared job, each image through its own camera's rolling shutter (every image named
    must have one)."""
    uv = np.full((len(camera), 2), np.nan)
    for c in np.unique(camera):
        pick = np.flatnonzero(camera == c)
        pose = prepared.poses[c]
        rs = prepared.frame_shutters[c]
        uv[pick] = rolling_shutter_projection(
            points_world[point[pick]], pose.C_world, pose.R_cam_to_world,
            prepared.velocities_m_s[c], rs.readout_s, prepared.interior_of(pose.image_name),
            rs.direction)
    return uv


def rolling_shutter_csv(prepared) -> str:
    """The table of ROLLING_SHUTTER_CSV (COLUMNS), one row per rolling-shutter image (a
    job with several cameras adds a last column, ``camera``: the image's camera);
    velocities to 1e-6 m/s, the first row's time as ISO 8601 UTC and seconds after
    take-off."""
    multi = prepared.cameras is not None
    rows = [",".join(COLUMNS + (("camera",) if multi else ()))]
    for pose, rs, vel, t, frame in zip(prepared.poses, prepared.frame_shutters,
                                       prepared.velocities_m_s, prepared.times,
                                       prepared.job.frames, strict=True):
        if rs is None:
            continue
        row = (f"{pose.image_name},{rs.readout_s!r},{rs.direction},"
               f"{vel[0]:.6f},{vel[1]:.6f},{vel[2]:.6f},{frame.time_utc},{t.time_s!r}")
        rows.append(row + (f",{frame.camera_id}" if multi else ""))
    return "\n".join(rows) + "\n"
