"""Each project effect element has exactly one registered effect, built from it whole."""

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from designer.core.distortion import BrownConrady
from designer.effects import (
    EffectChain,
    FrameContext,
    GaussianBlur,
    GaussianNoiseDN,
    JpegCompression,
    LensDistortion,
    LinearMotionBlur,
    RadialVignetting,
    SensorModel,
    effects_from_model,
    pinhole_render_camera,
)
from designer.effects.base import Effect
from designer.effects.exposure import ExposureWhiteBalance
from designer.effects.optics import ThinLensDefocus
from designer.effects.registry import implements, registered_effects, registry_problems
from designer.project import model as m
from tests.synthetic import pixel_camera

DISTORTED = pixel_camera(64, 48, 60.0, BrownConrady(k1=-0.15, p1=1e-3))


def test_every_element_has_one_registered_effect_and_vice_versa():
    registry = registered_effects()
    assert registry_problems(registry, m.Effects) == []
    assert set(registry) == {m.Vignetting, m.Defocus, m.Blur, m.MotionBlur, m.SensorNoise,
                             m.Sensor, m.ExposureVariation, m.Jpeg, m.ChromaticAberration}
    for model_class, effect in registry.items():
        assert effect.model is model_class
    # an element left unregistered, or an effect registered for two elements, is named
    missing = {c: e for c, e in registry.items() if c is not m.Blur}
    assert registry_problems(missing, m.Effects) == ["<Blur> has no registered effect"]
    twice = {**missing, m.Blur: GaussianBlur, m.Jpeg: GaussianBlur}
    assert registry_problems(twice, m.Effects) == ["GaussianBlur implements 2 elements"]
    stray = {**registry, m.Render: GaussianBlur}
    assert "GaussianBlur implements Render, which Effects does not hold" in \
        registry_problems(stray, m.Effects)


def test_an_element_cannot_be_implemented_twice():
    with pytest.raises(ValueError, match="Blur is implemented twice"):
        @implements(m.Blur)
        @dataclass(frozen=True)
        class OtherBlur(Effect):
            kind: ClassVar[str] = "blur"

            @classmethod
            def from_model(cls, element, camera):
                return cls()
    with pytest.raises(TypeError, match="defines no from_model"):
        implements(m.Render)(type("NoFromModel", (Effect,), {}))
    assert registered_effects()[m.Blur] is GaussianBlur
    assert m.Render not in registered_effects()


def test_the_registry_builds_the_chain_the_hand_written_adapter_built():
    """Every element, and the effects as the former if-chain constructed them from the
    model's fields: the same effects, so the same bytes."""
    effects = m.Effects(
        vignetting=m.Vignetting(0.2, 0.03, -0.01, natural_cos4=True),
        sensor_noise=m.SensorNoise(1.5, 5), sensor=m.Sensor(20000.0, 3.0, seed=4),
        blur=m.Blur(0.7), motion_blur=m.MotionBlur(1 / 500, 12.0), jpeg=m.Jpeg(90),
        defocus=m.Defocus(2.8, 30.0, 60.0),
        exposure_variation=m.ExposureVariation(0.2, 300.0, 5000.0, 6))
    _, warp = pinhole_render_camera(DISTORTED, 2)
    s, x = effects.sensor, effects.exposure_variation
    by_hand = EffectChain([
        LensDistortion(warp),
        RadialVignetting(DISTORTED, (-0.2, 0.03, -0.01), natural_cos4=True),
        ThinLensDefocus(DISTORTED, 2.8, 30.0, 60.0), GaussianBlur(0.7),
        LinearMotionBlur(1 / 500, 12.0, 2.0), GaussianNoiseDN(1.5, 5),
        SensorModel(full_well_e=s.full_well_e, exposure_scale=s.exposure_scale,
                    read_noise_e=s.read_noise_e,
                    dark_current_e_per_s=s.dark_current_e_per_s,
                    exposure_time_s=s.exposure_time_s, adc_bits=s.adc_bits,
                    shot_noise=True, seed=s.seed),
        ExposureWhiteBalance(x.exposure_sigma_ev, x.white_balance_sigma_k, x.reference_k,
                             x.seed),
        JpegCompression(90)])
    chain = effects_from_model(effects, DISTORTED, warp=warp)
    assert chain.kinds == by_hand.kinds and len(chain.kinds) == 9
    assert chain.effects == by_hand.effects
    H, W = warp.render_interior.image_size_px[::-1]
    raw = (np.random.default_rng(1).random((H, W, 3)) * 255).astype(np.uint8)
    ctx = FrameContext(gsd_m=0.05, flight_direction_uv=(1.0, 0.2))
    out = chain.apply(raw, 3, ctx)
    assert out.shape == (48, 64, 3)
    np.testing.assert_array_equal(out, by_hand.apply(raw, 3, ctx))
