"""The exact Blender camera for an interior orientation and pose (no bpy here).

Mapping (docs/conventions.md, verified by rendering in the tests): with
``sensor_fit = 'HORIZONTAL'``, ``sensor_width = sw`` and ``lens = f``, a principal point
at (cx, cy) px needs ``shift_x = (W/2 − cx) / W`` and ``shift_y = (cy − H/2) / W`` —
both divided by W, the fitted dimension, with opposite signs. Non-square pixels are
rendered with Blender's pixel aspect. The camera object's rotation matrix is
``R_cam_to_world`` and its location ``C_world − origin``: Blender stores float32, so
only local coordinates are handed to it.
"""

from __future__ import annotations

import numpy as np

from designer.core.interior import InteriorOrientation
from designer.render.job_spec import CameraSpec

#: Blender's smallest focal length and sensor width (bpy.types.Camera: lens and
#: sensor_width are floats in [1, inf]); smaller values are clamped silently.
BLENDER_MIN_MM = 1.0


def blender_camera(interior: InteriorOrientation) -> CameraSpec:
    """Blender camera settings that render exactly the pinhole part of ``interior``.

    A pinhole image depends only on focal length / sensor width, so where either is
    below Blender's 1 mm minimum both are scaled up together (a 0.8 mm sensor with a
    1.2 mm lens renders as 1 mm and 1.5 mm): the image is the same, nothing is clamped.
    """
    W, H = interior.image_size_px
    aspect = interior.pixel_pitch_y_mm / interior.pixel_pitch_x_mm
    scale = max(1.0, BLENDER_MIN_MM / interior.focal_length_mm,
                BLENDER_MIN_MM / interior.sensor_width_mm)
    # Blender normalises the pixel aspect so the larger of the two is 1... either way
    # only the ratio y/x matters for the projection.
    return CameraSpec(
        lens_mm=float(interior.focal_length_mm * scale),
        sensor_width_mm=float(interior.sensor_width_mm * scale),
        sensor_fit="HORIZONTAL",
        shift_x=(W / 2 - interior.cx_px) / W,
        shift_y=(interior.cy_px - H / 2) / W,
        resolution_x_px=W,
        resolution_y_px=H,
        pixel_aspect_x=1.0,
        pixel_aspect_y=float(aspect),
    )


def blender_matrix_world(
    C_world: np.ndarray, R_cam_to_world: np.ndarray, origin_world: np.ndarray
) -> np.ndarray:
    """4×4 camera object matrix in the local (world − origin) frame, float64."""
    M = np.eye(4)
    M[:3, :3] = np.asarray(R_cam_to_world, dtype=float)
    M[:3, 3] = np.asarray(C_world, dtype=float) - np.asarray(origin_world, dtype=float)
    return M
