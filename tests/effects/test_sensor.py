"""Sensor noise statistics, per-frame seeding and the sRGB transfer function."""

import numpy as np
import pytest

from designer.effects.base import FrameContext, frame_key
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
    out = simulate_sensor(flat(level), frame_key(1, 0), full_well_e=full_well,
                          adc_bits=None)
    e = out.astype(np.float64) * full_well
    lam = level * full_well
    se_mean = np.sqrt(lam / e.size)
    assert abs(e.mean() - lam) < 5 * se_mean
    # the sample variance of a Poisson has a relative standard error ≈ sqrt(2 / n)
    assert e.var() == pytest.approx(lam, rel=5 * np.sqrt(2 / e.size))


def test_exposure_scale_and_read_noise():
    full_well, read = 10000.0, 12.0
    out = simulate_sensor(flat(0.4), frame_key(2, 0), full_well_e=full_well,
                          exposure_scale=0.5, read_noise_e=read, adc_bits=None)
    e = out.astype(np.float64) * full_well
    lam = 0.4 * 0.5 * full_well
    assert e.mean() == pytest.approx(lam, abs=5 * np.sqrt((lam + read**2) / e.size))
    assert e.var() == pytest.approx(lam + read**2, rel=0.02)
    only_read = simulate_sensor(flat(0.4), frame_key(3, 0), full_well_e=full_well,
                                shot_noise=False, read_noise_e=read, adc_bits=None)
    assert (only_read * full_well).std() == pytest.approx(read, rel=0.01)


def test_dark_current_adds_its_mean_and_poisson_variance():
    full_well = 10000.0
    out = simulate_sensor(flat(0.0), frame_key(4, 0), full_well_e=full_well,
                          dark_current_e_per_s=50.0, exposure_time_s=2.0, adc_bits=None)
    e = out.astype(np.float64) * full_well
    assert e.mean() == pytest.approx(100.0, abs=5 * np.sqrt(100 / e.size))
    assert e.var() == pytest.approx(100.0, rel=0.02)


def test_adc_quantises_to_the_bit_depth_and_saturates():
    out = simulate_sensor(np.linspace(0, 1.5, 10_000, dtype=np.float32),
                          frame_key(5, 0), full_well_e=1000.0, adc_bits=10)
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
    # the documented seeding: the first word of SeedSequence([seed, frame_index])
    assert frame_key(11, 3) == np.random.SeedSequence([11, 3]).generate_state(1, np.uint64)[0]
    assert frame_key(11, 3, 1) != frame_key(11, 3)
    with pytest.raises(ValueError):
        frame_key(1, -1)


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


@pytest.mark.parametrize("lam", [0.4, 4.0, 25.0, 90.0])
def test_low_light_shot_noise_is_exactly_poisson(lam):
    """Below GAUSSIAN_ABOVE_E the electron counts follow the Poisson law itself (a
    chi-square test of the whole distribution, not only its mean and variance)."""
    from scipy import stats

    n = 200_000
    # a well far deeper than λ, so that saturation does not clip the upper tail
    out = simulate_sensor(flat(lam / 1e6, n), frame_key(7, 0), full_well_e=1e6,
                          adc_bits=None).astype(np.float64) * 1e6
    k = np.rint(out).astype(np.int64).ravel()
    assert np.abs(out.ravel() - k).max() < 0.05  # whole electrons
    lo = 0
    hi = int(lam + 6 * np.sqrt(lam) + 3)
    observed = np.bincount(np.clip(k, lo, hi), minlength=hi + 1)
    expected = stats.poisson.pmf(np.arange(hi + 1), lam) * n
    expected[-1] += stats.poisson.sf(hi, lam) * n
    keep = expected > 5
    chi2 = ((observed[keep] - expected[keep]) ** 2 / expected[keep]).sum()
    assert stats.chi2.sf(chi2, keep.sum() - 1) > 1e-3


def test_photon_transfer_curve_follows_shot_plus_read_noise():
    """Variance against signal over the whole range (both the exact Poisson and the
    normal regime): var = λ + σ_read², each level within 5 %."""
    full_well, read = 20000.0, 6.0
    levels = np.array([0.002, 0.01, 0.04, 0.1, 0.3, 0.6, 0.9])
    img = np.repeat(levels[:, None], 40_000, axis=1).astype(np.float32)
    e = simulate_sensor(img, frame_key(8, 0), full_well_e=full_well, read_noise_e=read,
                        adc_bits=None).astype(np.float64) * full_well
    lam = levels * full_well
    np.testing.assert_allclose(e.var(axis=1), lam + read**2, rtol=0.05)
    np.testing.assert_allclose(e.mean(axis=1), lam, atol=5 * np.sqrt(lam.max() / 40_000))


def test_noise_does_not_depend_on_the_number_of_threads():
    import numba

    model = SensorModel(full_well_e=3000.0, read_noise_e=4.0, seed=2)
    img = np.random.default_rng(0).random((64, 80, 3)).astype(np.float32)
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = model.apply(img, 5, CTX), GaussianNoiseDN(2.0, 1).apply(img, 5, CTX)
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        many = model.apply(img, 5, CTX), GaussianNoiseDN(2.0, 1).apply(img, 5, CTX)
    finally:
        numba.set_num_threads(before)
    np.testing.assert_array_equal(one[0], many[0])
    np.testing.assert_array_equal(one[1], many[1])


def test_vignetting_runs_inside_the_sensor_pass():
    """The chain folds vignetting and the final encoding into the sensor pass: the same
    image as running the steps one after the other, up to one code of 65535 where the
    separate steps' float32 intermediate values round differently from the fused pass's
    float64 ones."""
    from designer.core.interior import InteriorOrientation
    from designer.effects.chain import EffectChain
    from designer.effects.optics import RadialVignetting

    interior = InteriorOrientation(focal_length_mm=8.8, sensor_width_mm=13.2,
                                   sensor_height_mm=8.8, image_width_px=96,
                                   image_height_px=64)
    vignetting = RadialVignetting.from_corner_falloff(interior, 0.3)
    sensor = SensorModel(full_well_e=8000.0, read_noise_e=3.0, adc_bits=12, seed=4)
    img = (np.random.default_rng(1).random((64, 96, 3)) * 200 + 30).astype(np.uint16) * 256
    fused = EffectChain([vignetting, sensor]).apply(img, 2)
    linear = decode_image(img)
    separate = encode_image(sensor.apply(vignetting.apply(linear, 2, CTX), 2, CTX), np.uint16)
    diff = np.abs(fused.astype(np.int64) - separate)
    assert np.mean(diff == 0) > 0.99 and diff.max() <= 1


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
def test_encoding_rounds_to_the_nearest_code(dtype):
    """encode_image = round(sRGB(V) · top) computed in float64, for any linear value."""
    rng = np.random.default_rng(9)
    linear = np.concatenate([rng.random(200_000), rng.random(50_000) * 0.004,
                             [-0.5, 0.0, 1.0, 1.7, np.nan]]).astype(np.float32)
    top = np.iinfo(dtype).max
    expected = np.clip(np.rint(linear_to_srgb(np.nan_to_num(linear).astype(np.float64)) * top),
                       0, top)
    got = encode_image(linear, dtype)
    assert got.dtype == dtype
    np.testing.assert_array_equal(got, expected)


def test_counter_based_normals_are_standard_normal():
    """The ziggurat on SplitMix64 counters: moments, the whole distribution (KS) and the
    tails beyond 3.5 σ and 4.5 σ, where a broken tail algorithm would show."""
    from scipy import stats

    from designer.effects import _sensor_kernels

    z = _sensor_kernels.add_normal(np.zeros((4000, 1000), np.float32), frame_key(3, 1), 1.0)
    z = z.ravel().astype(np.float64)
    assert abs(z.mean()) < 5 / np.sqrt(z.size)
    assert z.var() == pytest.approx(1.0, rel=5 * np.sqrt(2 / z.size))
    assert stats.kstest(z, "norm").pvalue > 1e-3
    for k, rel in ((3.5, 0.1), (4.5, 0.6)):
        expected = 2 * stats.norm.sf(k) * z.size
        assert np.sum(np.abs(z) > k) == pytest.approx(expected, rel=rel)


def test_compiled_srgb_encoding_and_rounding_match_the_reference():
    from designer.effects._pixel_kernels import srgb_encode
    from designer.effects.srgb import encode_table, quantise

    rng = np.random.default_rng(11)
    v = np.concatenate([rng.random(100_000), rng.random(10_000) * 0.005,
                        [-1.0, 0.0, 0.0031308, 1.0, 2.0]]).astype(np.float32)
    reference = linear_to_srgb(v.astype(np.float64))  # the float64 numpy path
    np.testing.assert_allclose(srgb_encode(v, encode_table()), reference, atol=1.5e-7)
    encoded = rng.random(100_000).astype(np.float32) * 1.2 - 0.1
    for dtype in (np.uint8, np.uint16):
        top = np.iinfo(dtype).max
        expected = np.clip(np.rint(encoded.astype(np.float64) * top), 0, top).astype(dtype)
        np.testing.assert_array_equal(quantise(encoded, dtype), expected)


def test_sensor_then_dn_noise_fused_equals_the_steps():
    from designer.effects.chain import EffectChain
    from designer.effects.srgb import quantise

    sensor = SensorModel(full_well_e=6000.0, read_noise_e=2.0, seed=1)
    dn = GaussianNoiseDN(1.5, seed=2)
    img = (np.random.default_rng(3).random((40, 50, 3)) * 255).astype(np.uint8)
    fused = EffectChain([sensor, dn]).apply(img, 4)
    encoded = linear_to_srgb(sensor.apply(decode_image(img), 4, CTX))
    steps = quantise(dn.apply(encoded, 4, CTX), np.uint8)
    diff = np.abs(fused.astype(np.int64) - steps)
    assert diff.max() <= 1 and np.mean(diff == 0) > 0.99


def test_vignetting_sensor_and_dn_noise_fused_equal_the_steps():
    from designer.core.interior import InteriorOrientation
    from designer.effects.chain import EffectChain
    from designer.effects.optics import RadialVignetting
    from designer.effects.srgb import quantise

    interior = InteriorOrientation(focal_length_mm=8.8, sensor_width_mm=13.2,
                                   sensor_height_mm=8.8, image_width_px=60,
                                   image_height_px=40)
    vignetting = RadialVignetting.from_corner_falloff(interior, 0.3)
    sensor = SensorModel(full_well_e=6000.0, read_noise_e=2.0, seed=1)
    dn = GaussianNoiseDN(1.5, seed=2)
    img = (np.random.default_rng(3).random((40, 60, 3)) * 255).astype(np.uint8)
    for tail in ([], [dn]):
        fused = EffectChain([vignetting, sensor, *tail]).apply(img, 4)
        linear = sensor.apply(vignetting.apply(decode_image(img), 4, CTX), 4, CTX)
        encoded = linear_to_srgb(linear)
        steps = quantise(dn.apply(encoded, 4, CTX) if tail else encoded, np.uint8)
        diff = np.abs(fused.astype(np.int64) - steps)
        assert diff.max() <= 1 and np.mean(diff == 0) > 0.99, tail
