"""The model → core boundary for cameras: a project camera as the core's interior
orientation (the one camera type every layer computes with), full size or as rendered."""

from __future__ import annotations

import dataclasses

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.interior import InteriorOrientation
from designer.project import model as m


def interior_from_camera(camera: m.Camera) -> InteriorOrientation:
    """The core camera model of a project camera."""
    d = camera.distortion
    if isinstance(d, m.BrownConradyDistortion):
        distortion = BrownConrady(d.k1, d.k2, d.k3, d.p1, d.p2)
    elif isinstance(d, m.FisheyeEquidistantDistortion):
        distortion = FisheyeEquidistant(d.k1, d.k2, d.k3, d.k4)
    else:
        distortion = None
    return InteriorOrientation(
        focal_length_mm=camera.focal_length_mm, sensor_width_mm=camera.sensor_width_mm,
        sensor_height_mm=camera.sensor_height_mm, image_width_px=camera.image_width_px,
        image_height_px=camera.image_height_px,
        principal_point_x_mm=camera.principal_point_x_mm,
        principal_point_y_mm=camera.principal_point_y_mm,
        pixel_aspect=camera.pixel_aspect, distortion=distortion)


def render_interior(camera: m.Camera, resolution_scale: float = 1.0) -> InteriorOrientation:
    """The camera as rendered: same sensor and lens, image size × ``resolution_scale``."""
    full = interior_from_camera(camera)
    if resolution_scale == 1.0:
        return full
    return dataclasses.replace(
        full, image_width_px=round(camera.image_width_px * resolution_scale),
        image_height_px=round(camera.image_height_px * resolution_scale))
