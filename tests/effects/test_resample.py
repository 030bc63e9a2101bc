"""The compiled resampler: exact positions, agreement with scipy, thread independence."""

import numba
import numpy as np
import pytest
from scipy import ndimage

from designer.effects.resample import SUPPORT_PX, block_mean, sample_image, warp_image


def smooth_image(h=120, w=160, c=3, seed=1):
    rng = np.random.default_rng(seed)
    img = ndimage.gaussian_filter(rng.random((h, w, c)), (1.5, 1.5, 0))
    return img.astype(np.float32)


@pytest.mark.parametrize("order", [1, 3])
def test_agrees_with_scipy_away_from_the_edges(order):
    img = smooth_image()
    rng = np.random.default_rng(2)
    margin = SUPPORT_PX[order] + 2
    u = rng.uniform(margin, 160 - margin, (40, 50))
    v = rng.uniform(margin, 120 - margin, (40, 50))
    ours = sample_image(img, u, v, order)
    ref = np.stack([ndimage.map_coordinates(img[:, :, c].astype(np.float64),
                                            [v - 0.5, u - 0.5], order=order, mode="nearest")
                    for c in range(3)], axis=-1)
    assert ours.shape == (40, 50, 3) and ours.dtype == np.float32
    assert np.abs(ours - ref).max() < 5e-6  # a stronger bound would test scipy's boundary


@pytest.mark.parametrize("order", [1, 3])
def test_a_ramp_is_reproduced_at_the_exact_position(order):
    """The value of a ramp equal to the pixel's own u coordinate (scaled to 0 … 1) is the
    sampled position: the resampler moves nothing. The kernels sum in float32 (a few
    units of 6e-8 of full scale), which on this 400 px ramp is ~1e-4 px; on images of
    real scenes, where an edge rises by a large part of full scale within a pixel or
    two, the same value error moves an edge by ~1e-7 px."""
    w, h = 400, 60
    ramp = np.tile((np.arange(w) + 0.5) / w, (h, 1)).astype(np.float32)
    rng = np.random.default_rng(3)
    u = rng.uniform(SUPPORT_PX[order], w - SUPPORT_PX[order], 5000)
    v = rng.uniform(SUPPORT_PX[order], h - SUPPORT_PX[order], 5000)
    error_px = (sample_image(ramp, u, v, order).astype(np.float64) * w - u)
    assert np.abs(error_px).max() < 2e-4


def test_cubic_interpolates_the_samples():
    img = smooth_image()
    uu, vv = np.meshgrid(np.arange(160) + 0.5, np.arange(120) + 0.5)
    out = warp_image(img, uu, vv, 3)
    assert np.abs(out - img).max() < 1e-6


def test_oversampling_averages_blocks():
    img = smooth_image()
    uu, vv = np.meshgrid(np.arange(20, 100, 0.5) + 0.25, np.arange(20, 80, 0.5) + 0.25)
    once = warp_image(img, uu, vv, 3)
    averaged = warp_image(img, uu, vv, 3, oversample=2)
    assert averaged.shape == (60, 80, 3)
    np.testing.assert_allclose(averaged, block_mean(once, 2), atol=1e-6)


def test_grey_images_and_shapes():
    img = smooth_image(c=1)[:, :, 0]
    out = sample_image(img, np.array([[50.5, 60.25]]), np.array([[40.5, 41.0]]))
    assert out.shape == (1, 2)
    assert out[0, 0] == pytest.approx(img[40, 50], abs=1e-6)
    with pytest.raises(ValueError, match="same shape"):
        sample_image(img, np.zeros(3), np.zeros(4))
    with pytest.raises(ValueError, match="order"):
        sample_image(img, np.zeros(3), np.zeros(3), order=2)


def test_result_does_not_depend_on_the_number_of_threads():
    img = smooth_image(200, 300)
    rng = np.random.default_rng(4)
    u = rng.uniform(0, 300, (150, 200))
    v = rng.uniform(0, 200, (150, 200))
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = warp_image(img, u, v, 3)
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        many = warp_image(img, u, v, 3)
    finally:
        numba.set_num_threads(before)
    assert np.array_equal(one, many)


def test_the_rgb_fast_path_equals_the_general_kernel():
    from designer.effects._resample_kernels import (
        bspline_coefficients,
        sample_cubic,
        sample_cubic_rgb,
    )

    coeffs = bspline_coefficients(smooth_image(90, 110))
    rng = np.random.default_rng(5)
    u = rng.uniform(-3, 113, (70, 80))  # also beyond the edges
    v = rng.uniform(-3, 93, (70, 80))
    no_gain = np.empty((0, 0), np.float32)
    np.testing.assert_allclose(sample_cubic_rgb(coeffs, u, v, no_gain),
                               sample_cubic(coeffs, u, v, 1), atol=2e-6)


def test_a_gain_in_the_warps_pass_equals_a_separate_multiplication():
    img = smooth_image(90, 110)
    rng = np.random.default_rng(6)
    u = rng.uniform(0, 110, (70, 80))
    v = rng.uniform(0, 90, (70, 80))
    gain = rng.uniform(0.5, 1.0, (70, 80)).astype(np.float32)
    for oversample_maps in (False, True):
        if oversample_maps:  # the general kernel (grey) multiplies afterwards
            fused = warp_image(img[:, :, 0], u, v, gain=gain)
            separate = warp_image(img[:, :, 0], u, v) * gain
        else:
            fused = warp_image(img, u, v, gain=gain)
            separate = warp_image(img, u, v) * gain[:, :, None]
        np.testing.assert_array_equal(fused, separate)
