"""Sensor noise statistics, per-frame seeding and the sRGB transfer function."""

import numpy as np
import pytest

from designer.effects.base import FrameContext, frame_rng
from designer.effects.sensor import GaussianNoiseDN, SensorModel, simulate_sensor
from designer.effects.srgb import (
    decode_image,
    encode_image,
    linear_to_srgb,
    srgb_to_linear,
)

CTX = FrameContext()
N = 400_000  # pixels in a flat field: the variance is then known to ~0.3 %


def flat(level, n=N):
    return np.full((n // 500, 500), level, np.float32)


@pytest.mark.parametrize("level", [0.05, 0.3, 0.8])
def test_shot_noise_is_poisson(level):
    """Mean and variance of the electrons equal λ = level · full well (Poisson)."""
    full_well = 5000.0
    out = simulate_sensor(flat(level), np.random.default_rng(1), full_well_e=full_well,
                          adc_bits=None)
    e = out.astype(np.float64) * full_well
    lam = level * full_well
    se_mean = np.sqrt(lam / e.size)
    assert abs(e.mean() - lam) < 5 * se_mean
    # the sample variance of a Poisson has a relative standard error ≈ sqrt(2 / n)
    assert e.var() == pytest.approx(lam, rel=5 * np.sqrt(2 / e.size))


def test_exposure_scale_and_read_noise():
    full_well, read = 10000.0, 12.0
    out = simulate_sensor(flat(0.4), np.random.default_rng(2), full_well_e=full_well,
                          exposure_scale=0.5, read_noise_e=read, adc_bits=None)
    e = out.astype(np.float64) * full_well
    lam = 0.4 * 0.5 * full_well
    assert e.mean() == pytest.approx(lam, abs=5 * np.sqrt((lam + read**2) / e.size))
    assert e.var() == pytest.approx(lam + read**2, rel=0.02)
    only_read = simulate_sensor(flat(0.4), np.random.default_rng(3), full_well_e=full_well,
                                shot_noise=False, read_noise_e=read, adc_bits=None)
    assert (only_read * full_well).std() == pytest.approx(read, rel=0.01)


def test_dark_current_adds_its_mean_and_poisson_variance():
    full_well = 10000.0
    out = simulate_sensor(flat(0.0), np.random.default_rng(4), full_well_e=full_well,
                          dark_current_e_per_s=50.0, exposure_time_s=2.0, adc_bits=None)
    e = out.astype(np.float64) * full_well
    assert e.mean() == pytest.approx(100.0, abs=5 * np.sqrt(100 / e.size))
    assert e.var() == pytest.approx(100.0, rel=0.02)


def test_adc_quantises_to_the_bit_depth_and_saturates():
    out = simulate_sensor(np.linspace(0, 1.5, 10_000, dtype=np.float32),
                          np.random.default_rng(5), full_well_e=1000.0, adc_bits=10)
    dn = out.astype(np.float64) * 1023
    np.testing.assert_allclose(dn, np.rint(dn), atol=1e-3)
    assert out.max() == 1.0 and out.min() >= 0.0
    assert (out[-100:] == 1.0).all()  # 1.5 × full well saturates


def test_seeding_per_frame():
    model = SensorModel(full_well_e=2000.0, read_noise_e=3.0, seed=11)
    img = flat(0.5, 10_000)
    a0, b0 = model.apply(img, 0, CTX), model.apply(img, 0, CTX)
    a1 = model.apply(img, 1, CTX)
    other_seed = SensorModel(full_well_e=2000.0, read_noise_e=3.0, seed=12).apply(img, 0, CTX)
    np.testing.assert_array_equal(a0, b0)
    assert not np.array_equal(a0, a1) and not np.array_equal(a0, other_seed)
    dn = GaussianNoiseDN(2.0, seed=11)
    np.testing.assert_array_equal(dn.apply(img, 3, CTX), dn.apply(img, 3, CTX))
    assert not np.array_equal(dn.apply(img, 3, CTX), dn.apply(img, 4, CTX))
    # the documented seeding: SeedSequence([seed, frame_index])
    expect = np.random.default_rng(np.random.SeedSequence([11, 3])).standard_normal(
        img.shape, dtype=np.float32)
    np.testing.assert_array_equal(frame_rng(11, 3).standard_normal(img.shape, np.float32),
                                  expect)
    with pytest.raises(ValueError):
        frame_rng(1, -1)


def test_dn_noise_sigma_on_the_8_bit_scale():
    out = GaussianNoiseDN(3.0, seed=1).apply(flat(0.5), 0, CTX)
    assert (out.astype(np.float64) * 255).std() == pytest.approx(3.0, rel=0.01)
    assert out.mean() == pytest.approx(0.5, abs=1e-4)
    assert GaussianNoiseDN(0.0).is_identity


# ------------------------------------------------------------------------------- sRGB
def test_srgb_reference_values():
    np.testing.assert_allclose(srgb_to_linear(np.array([0.0, 0.04045, 0.5, 1.0])),
                               [0.0, 0.04045 / 12.92, 0.21404114048223255, 1.0], rtol=1e-12)
    np.testing.assert_allclose(linear_to_srgb(np.array([0.0031308, 0.21404114048223255, 1.0])),
                               [0.0031308 * 12.92, 0.5, 1.0], rtol=1e-9)
    x = np.linspace(0, 1, 10001)
    np.testing.assert_allclose(linear_to_srgb(srgb_to_linear(x)), x, atol=1e-12)


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
def test_srgb_round_trip_is_exact_for_every_code(dtype):
    codes = np.arange(np.iinfo(dtype).max + 1).astype(dtype)
    lin = decode_image(codes)
    assert lin.dtype == np.float32
    np.testing.assert_array_equal(encode_image(lin, dtype), codes)
    top = np.iinfo(dtype).max
    np.testing.assert_allclose(lin, srgb_to_linear(codes / top), atol=1e-7)
