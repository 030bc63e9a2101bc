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

from designer.core.truth import CameraPose
from designer.render.blender_camera import blender_matrix_world


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
