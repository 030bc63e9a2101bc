"""Vignetting profiles, Gaussian blur and thin-lens defocus."""

import math

import numpy as np
import pytest

from designer.core.distortion import BrownConrady
from designer.effects.base import FrameContext
from designer.effects.optics import (
    Defocus,
    GaussianBlur,
    NaturalVignetting,
    RadialVignetting,
    ThinLensDefocus,
    defocus_diameter_mm,
    disc_kernel,
    gaussian_blur,
    radial_vignetting_gain,
)
from designer.errors import DesignerError
from tests.synthetic import pixel_camera

CTX = FrameContext()


@pytest.mark.parametrize("falloff", [0.0, 0.2, 0.6, 1.0])
def test_corner_falloff_profile_at_centre_and_corner(falloff):
    interior = pixel_camera(300, 200, 400.0, None)  # principal point at the centre
    effect = RadialVignetting.from_corner_falloff(interior, falloff)
    g = radial_vignetting_gain(interior, effect.coefficients, np.array([150.0, 0.0, 300.0, 0.0]),
                               np.array([100.0, 0.0, 200.0, 200.0]))
    np.testing.assert_allclose(g, [1.0, 1 - falloff, 1 - falloff, 1 - falloff], atol=1e-12)
    flat = np.full((200, 300, 3), 0.5, np.float32)
    out = effect.apply(flat, 0, CTX)
    v, u = np.mgrid[0:200, 0:300] + 0.5
    rho2 = ((u - 150) ** 2 + (v - 100) ** 2) / (150**2 + 100**2)
    np.testing.assert_allclose(out[..., 1], 0.5 * (1 - falloff * rho2), rtol=1e-6, atol=1e-7)
    assert effect.is_identity == (falloff == 0)


def test_off_centre_principal_point_loses_exactly_c_at_the_farthest_corner():
    interior = pixel_camera(300, 200, 400.0, None, pp_px=(20.0, -10.0))  # cx = 170, cy = 90
    coeffs = RadialVignetting.from_corner_falloff(interior, 0.3).coefficients
    corners_u, corners_v = np.array([0.0, 300, 0, 300]), np.array([0.0, 0, 200, 200])
    g = radial_vignetting_gain(interior, coeffs, corners_u, corners_v)
    assert g.min() == pytest.approx(0.7, abs=1e-12)
    assert np.argmin(g) == 2  # bottom-left is farthest from (170, 90)
    assert radial_vignetting_gain(interior, coeffs, np.array([170.0]), np.array([90.0]))[0] == 1


def test_natural_vignetting_is_cos4_of_the_ray_angle():
    interior = pixel_camera(120, 80, 60.0, None)
    out = NaturalVignetting(interior).apply(np.ones((80, 120), np.float32), 0, CTX)
    v, u = np.mgrid[0:80, 0:120] + 0.5
    tan2 = ((u - 60) ** 2 + (v - 40) ** 2) / 60.0**2
    np.testing.assert_allclose(out, 1 / (1 + tan2) ** 2, rtol=1e-6)
    # with distortion the angle comes from the lens inverse: barrel sees wider, darker
    barrel = NaturalVignetting(pixel_camera(120, 80, 60.0, BrownConrady(k1=-0.1)))
    assert barrel.gain[0, 0] < out[0, 0]


def test_vignetting_refuses_another_image_size():
    effect = RadialVignetting.from_corner_falloff(pixel_camera(30, 20, 40.0, None), 0.1)
    with pytest.raises(ValueError, match="30 x 20"):
        effect.apply(np.ones((21, 30), np.float32), 0, CTX)
    with pytest.raises(ValueError):
        RadialVignetting.from_corner_falloff(pixel_camera(30, 20, 40.0, None), 1.5)


@pytest.mark.parametrize("sigma", [0.8, 1.5, 4.0])
def test_gaussian_blur_spreads_a_point_by_sigma(sigma):
    img = np.zeros((81, 81), np.float32)
    img[40, 40] = 1.0
    out = GaussianBlur(sigma).apply(img, 0, CTX)
    assert out.sum() == pytest.approx(1.0, abs=1e-5)
    _, u = np.mgrid[0:81, 0:81] - 40.0
    assert (out * u).sum() == pytest.approx(0.0, abs=1e-6)
    var = (out * u * u).sum()
    assert math.sqrt(var) == pytest.approx(sigma, rel=0.02)
    assert img[40, 40] == 1.0  # input untouched
    assert GaussianBlur(0.0).is_identity
    np.testing.assert_array_equal(gaussian_blur(img, 0.0), img)


def test_defocus_thin_lens_formula():
    # f = 50 mm, N = 2, focused at 2 m, object at 4 m:
    # c = f² |d − s| / (N d (s − f)) = 2500 · 2000 / (2 · 4000 · 1950) mm
    c = defocus_diameter_mm(50.0, 2.0, 2.0, 4.0)
    assert c == pytest.approx(2500 * 2000 / (2 * 4000 * 1950))
    assert defocus_diameter_mm(50.0, 2.0, 2.0, 2.0) == 0.0
    interior = pixel_camera(100, 100, 100.0, None, f_mm=8.0)  # pitch 0.08 mm
    effect = Defocus.from_thin_lens(interior, 2.8, 5.0, 50.0)
    expect = defocus_diameter_mm(8.0, 2.8, 5.0, 50.0) / 0.08
    assert effect.diameter_x_px == pytest.approx(expect)


@pytest.mark.parametrize("diameter", [0.0, 0.6, 3.0, 7.3])
def test_disc_kernel_area_and_second_moment(diameter):
    k = disc_kernel(diameter).astype(np.float64)
    assert k.shape[0] % 2 == 1 and k.sum() == pytest.approx(1.0, abs=1e-6)
    h = k.shape[0] // 2
    v, u = np.mgrid[-h:h + 1, -h:h + 1]
    assert (k * u).sum() == pytest.approx(0.0, abs=1e-6)
    assert (k * u * u).sum() == pytest.approx((k * v * v).sum(), rel=1e-6)  # round
    if diameter >= 3:
        # fully covered pixels hold 1 / (π R²); the support ends at the disc's radius
        assert k[h, h] * math.pi * (diameter / 2) ** 2 == pytest.approx(1.0, rel=0.01)
        assert k[h, h + math.ceil(diameter / 2 + 0.5)] == 0


def test_polynomial_and_cos4_vignetting_profile():
    """gain = cos⁴θ · (1 − c ρ² + a4 ρ⁴ + a6 ρ⁶), measured on a flat field within 1e-6."""
    interior = pixel_camera(300, 200, 250.0, None)
    effect = RadialVignetting(interior, (-0.3, 0.1, -0.05), natural_cos4=True)
    out = effect.apply(np.full((200, 300, 3), 0.6, np.float32), 0, CTX)[..., 0]
    v, u = np.mgrid[0:200, 0:300] + 0.5
    rho2 = ((u - 150) ** 2 + (v - 100) ** 2) / (150**2 + 100**2)
    cos4 = 1 / (1 + ((u - 150) ** 2 + (v - 100) ** 2) / 250.0**2) ** 2
    expect = 0.6 * cos4 * (1 - 0.3 * rho2 + 0.1 * rho2**2 - 0.05 * rho2**3)
    np.testing.assert_allclose(out, expect, rtol=1e-6)
    assert not RadialVignetting(interior, (0.0,), natural_cos4=True).is_identity
    assert RadialVignetting(interior, (0.0, 0.0)).is_identity


def test_thin_lens_defocus_follows_each_frames_distance():
    interior = pixel_camera(200, 200, 2000.0, None, f_mm=8.0)  # pitch 0.004 mm
    effect = ThinLensDefocus(interior, 2.0, 20.0)
    near, far = FrameContext(distance_m=2.0), FrameContext(distance_m=20.0)
    expect = defocus_diameter_mm(8.0, 2.0, 20.0, 2.0) / 0.004  # 3.6 px
    assert effect.diameter_px(near) == pytest.approx((expect, expect))
    assert effect.diameter_px(far) == (0.0, 0.0)  # in focus
    point = np.zeros((61, 61), np.float32)
    point[30, 30] = 1.0
    psf = effect.apply(point, 0, near).astype(np.float64)
    _, u = np.mgrid[0:61, 0:61] - 30
    # a uniform disc of radius R has second moment R²/4 per axis; area-sampling it over
    # the pixels adds a pixel's 1/12
    assert (psf * u * u).sum() == pytest.approx((expect / 2) ** 2 / 4 + 1 / 12, rel=0.02)
    fixed = ThinLensDefocus(interior, 2.0, 20.0, object_distance_m=2.0)
    assert fixed.diameter_px(CTX) == pytest.approx((expect, expect))
    with pytest.raises(DesignerError, match="object distance"):
        effect.diameter_px(CTX)
    with pytest.raises(DesignerError, match="focal length"):
        ThinLensDefocus(interior, 2.0, 0.005)
