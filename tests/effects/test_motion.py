"""Linear motion blur: the PSF sums to 1, is centred, and has the right length and
direction."""

import math

import numpy as np
import pytest

from designer.core.rotation import rotation_from_opk
from designer.effects.base import FrameContext
from designer.effects.motion import (
    LinearMotionBlur,
    flight_direction_uv,
    linear_motion_kernel,
    motion_blur,
)
from designer.errors import DesignerError


def moments(kernel):
    k = kernel.astype(np.float64)
    hy, hx = k.shape[0] // 2, k.shape[1] // 2
    v, u = np.mgrid[-hy:hy + 1, -hx:hx + 1]
    mean = np.array([(k * u).sum(), (k * v).sum()])
    du, dv = u - mean[0], v - mean[1]
    cov = np.array([[(k * du * du).sum(), (k * du * dv).sum()],
                    [(k * du * dv).sum(), (k * dv * dv).sum()]])
    return k.sum(), mean, cov


@pytest.mark.parametrize("d", [(7.3, 0.0), (0.0, -4.6), (5.0, 3.2), (-11.7, 6.1), (0.4, 0.2)])
def test_kernel_sums_to_one_is_centred_and_has_the_length_and_direction(d):
    total, mean, cov = moments(linear_motion_kernel(d))
    assert total == pytest.approx(1.0, abs=1e-6)
    np.testing.assert_allclose(mean, [0.0, 0.0], atol=1e-6)
    length = math.hypot(*d)
    direction = np.array(d) / length
    # along the motion: a uniform segment (L² / 12) widened by the bilinear spread of
    # its points (0 … 1/4 px²)
    along = direction @ cov @ direction
    assert length**2 / 12 - 1e-3 <= along <= length**2 / 12 + 0.25
    if length > 3:
        _, vecs = np.linalg.eigh(cov)
        principal = vecs[:, 1]
        assert abs(principal @ direction) == pytest.approx(1.0, abs=2e-4)  # < ~1.1°


def test_zero_motion_is_the_identity():
    assert linear_motion_kernel((0.0, 0.0)).tolist() == [[0, 0, 0], [0, 1, 0], [0, 0, 0]]
    assert LinearMotionBlur(0.0, 10.0).is_identity and LinearMotionBlur(0.01, 0.0).is_identity


@pytest.mark.parametrize("d", [(12.5, 0.0), (9.3, 7.0), (-6.2, -20.0)])
def test_blurred_edge_has_the_motion_length_and_stays_in_place(d):
    """A vertical edge blurred by (du, dv) px turns into a linear ramp |du| px wide,
    centred on the edge (mid-exposure pose: no shift)."""
    img = np.zeros((80, 120), np.float32)
    img[:, 60:] = 1.0  # edge at u = 60
    L = abs(d[0])
    out = motion_blur(img, d)[40].astype(np.float64)
    centre = (1 - out).sum() - 60.0  # the edge position: the dark area left of it
    assert centre == pytest.approx(0.0, abs=1e-4)
    u = np.arange(120) + 0.5
    ramp = (u > 60 - L / 2 + 1.5) & (u < 60 + L / 2 - 1.5)
    slope = np.diff(out)[ramp[:-1]]
    assert slope.mean() == pytest.approx(1 / L, rel=0.02)


def test_effect_uses_speed_exposure_and_gsd():
    effect = LinearMotionBlur(exposure_time_s=1 / 500, speed_m_s=15.0, pixels_per_output_px=2.0)
    ctx = FrameContext(gsd_m=0.02, flight_direction_uv=(0.0, -3.0))
    assert effect.displacement_px(ctx) == pytest.approx((0.0, -3.0))  # 15/500/0.02 · 2
    with pytest.raises(DesignerError, match="ground sample distance"):
        effect.apply(np.zeros((5, 5), np.float32), 0, FrameContext())


def test_flight_direction_in_the_image():
    # nadir, image top north: flying north moves up the image (v decreases)
    R = rotation_from_opk(0.0, 0.0, 0.0)
    assert flight_direction_uv([0.0, 10.0, 0.0], R) == pytest.approx((0.0, -1.0))
    assert flight_direction_uv([10.0, 0.0, 0.0], R) == pytest.approx((1.0, 0.0))
    assert flight_direction_uv([0.0, 0.0, 5.0], R) == (0.0, 0.0)
    # heading east with κ = 90° (image top pointing west): east is image down
    R = rotation_from_opk(0.0, 0.0, math.pi / 2)
    assert flight_direction_uv([1.0, 0.0, 0.0], R) == pytest.approx((0.0, 1.0), abs=1e-12)
