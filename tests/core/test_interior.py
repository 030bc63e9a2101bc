import math

import numpy as np
import pytest

from designer.core.distortion import BrownConrady, FisheyeEquidistant
from designer.core.interior import InteriorOrientation
from designer.errors import CameraModelError


def phantom4(**changes):
    params = dict(focal_length_mm=8.8, sensor_width_mm=13.2, sensor_height_mm=8.8,
                  image_width_px=5472, image_height_px=3648)
    params.update(changes)
    return InteriorOrientation(**params)


def test_pixel_intrinsics_follow_the_conventions():
    cam = phantom4(principal_point_x_mm=0.0132, principal_point_y_mm=0.0088)
    pitch = 13.2 / 5472
    assert cam.fx_px == pytest.approx(8.8 / pitch, rel=1e-12)
    assert cam.fy_px == pytest.approx(8.8 * 3648 / 8.8, rel=1e-12)
    # x0 to the right moves cx right; y0 up moves cy up (smaller row)
    assert cam.cx_px == pytest.approx(5472 / 2 + 0.0132 / pitch, rel=1e-12)
    assert cam.cy_px == pytest.approx(3648 / 2 - 0.0088 / pitch, rel=1e-12)
    K = cam.K_px
    assert K.shape == (3, 3) and K[0, 2] == cam.cx_px and K[1, 1] == cam.fy_px


def test_field_of_view_of_a_centred_pinhole():
    h, v, d = phantom4().field_of_view_deg()
    assert h == pytest.approx(2 * math.degrees(math.atan(6.6 / 8.8)), abs=1e-9)
    assert v == pytest.approx(2 * math.degrees(math.atan(4.4 / 8.8)), abs=1e-9)
    assert d == pytest.approx(2 * math.degrees(math.atan(math.hypot(6.6, 4.4) / 8.8)), abs=1e-9)


def test_field_of_view_of_a_fisheye_exceeds_what_a_pinhole_can_see():
    # equidistant, no k: theta = r_d, so a half-width of 1.3 rad in normalised units
    cam = InteriorOrientation(
        focal_length_mm=2.0, sensor_width_mm=5.2, sensor_height_mm=5.2,
        image_width_px=1000, image_height_px=1000, distortion=FisheyeEquidistant())
    h, _, _ = cam.field_of_view_deg()
    assert h == pytest.approx(2 * math.degrees(1.3), abs=1e-6)


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        (dict(focal_length_mm=0.0), "focal_length_mm"),
        (dict(focal_length_mm=-8.8), "must be > 0"),
        (dict(sensor_width_mm=float("nan")), "not a finite number"),
        (dict(sensor_height_mm=float("inf")), "not a finite number"),
        (dict(image_width_px=0), "positive whole number"),
        (dict(image_height_px=3648.5), "positive whole number"),
        (dict(sensor_height_mm=9.0), "pixels are not square"),
        # the way to square pixels, in the camera's numbers
        (dict(sensor_height_mm=9.0), r"equal sensor height / image height \(e\.g\. sensor "
                                     r"height 8\.8 mm\)"),
        (dict(sensor_height_mm=9.0, pixel_aspect=1.0), "disagrees"),
        (dict(pixel_aspect=-1.0), "pixel_aspect"),
    ],
)
def test_impossible_cameras_are_rejected_with_a_clear_message(changes, message):
    with pytest.raises(CameraModelError, match=message):
        phantom4(**changes)


def test_non_square_pixels_are_accepted_when_the_aspect_is_stated():
    cam = phantom4(sensor_height_mm=9.0, pixel_aspect=(9.0 / 3648) / (13.2 / 5472))
    assert cam.fy_px != pytest.approx(cam.fx_px)


def test_square_pixel_tolerance_is_relative_1e6():
    ok = phantom4(sensor_height_mm=8.8 * (1 + 5e-7))
    assert ok.fx_px > 0
    with pytest.raises(CameraModelError):
        phantom4(sensor_height_mm=8.8 * (1 + 5e-6))


def test_rays_through_pixels_invert_the_intrinsics():
    rng = np.random.default_rng(3)
    cam = phantom4(principal_point_x_mm=0.05, principal_point_y_mm=-0.03,
                   distortion=BrownConrady(k1=-0.1, k2=0.03, p1=1e-3, p2=-5e-4))
    uv = rng.uniform([0, 0], [5472, 3648], size=(500, 2))
    rays = cam.rays_cv(uv)
    assert np.allclose(np.linalg.norm(rays, axis=1), 1.0)
    xy = rays[:, :2] / rays[:, 2:]
    xy_d = cam.distortion.distort(xy)
    uv_back = np.column_stack([xy_d[:, 0] * cam.fx_px + cam.cx_px,
                               xy_d[:, 1] * cam.fy_px + cam.cy_px])
    assert np.max(np.abs(uv_back - uv)) < 1e-6
