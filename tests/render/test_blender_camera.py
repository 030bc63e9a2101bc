"""Blender camera settings: Blender clamps lens and sensor width below 1 mm, so tiny
cameras are scaled (the pinhole image depends only on their ratio)."""

import pytest

from designer.core.interior import InteriorOrientation
from designer.render.blender_camera import BLENDER_MIN_MM, blender_camera


def interior(f_mm, sensor_w_mm, w_px=400, h_px=300, pp=(0.0, 0.0)):
    return InteriorOrientation(focal_length_mm=f_mm, sensor_width_mm=sensor_w_mm,
                               sensor_height_mm=sensor_w_mm * h_px / w_px, image_width_px=w_px,
                               image_height_px=h_px, principal_point_x_mm=pp[0],
                               principal_point_y_mm=pp[1])


@pytest.mark.parametrize(("f_mm", "sensor_mm"), [(8.8, 13.2), (1.2, 0.8), (0.5, 2.0),
                                                 (0.3, 0.2)])
def test_the_ratio_and_shifts_are_kept_and_nothing_is_below_blenders_minimum(f_mm, sensor_mm):
    plain = interior(f_mm, sensor_mm, pp=(0.01 * sensor_mm, -0.02 * sensor_mm))
    cam = blender_camera(plain)
    assert cam.lens_mm >= BLENDER_MIN_MM and cam.sensor_width_mm >= BLENDER_MIN_MM
    assert cam.lens_mm / cam.sensor_width_mm == pytest.approx(f_mm / sensor_mm, rel=1e-12)
    # focal length in pixels, the only thing the projection uses, is unchanged
    assert cam.lens_mm / cam.sensor_width_mm * 400 == pytest.approx(plain.fx_px, rel=1e-12)
    assert (cam.shift_x, cam.shift_y) == pytest.approx(
        ((200 - plain.cx_px) / 400, (plain.cy_px - 150) / 400), abs=1e-15)
    if f_mm >= 1 and sensor_mm >= 1:
        assert (cam.lens_mm, cam.sensor_width_mm) == (f_mm, sensor_mm)  # left as they are
