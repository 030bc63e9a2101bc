"""Sensor noise: a physical photon-to-digital-number model, and plain Gaussian DN noise.

``SensorModel`` works in linear light (float32, 1 = white, see ``designer.effects.base``):

1. signal electrons  λ = clip(V, 0) · full_well_e · exposure_scale
2. photon shot noise  Poisson(λ)
3. dark current  Poisson(dark_current_e_per_s · exposure_time_s), not subtracted
4. read noise  Normal(0, read_noise_e²)
5. saturation  clip to 0 … full_well_e
6. ADC  round(e / full_well_e · (2^bits − 1)), returned as DN / (2^bits − 1)

No colour filter array: every channel is treated as its own monochrome pixel.
``GaussianNoiseDN`` adds N(0, σ²) to the stored sRGB-encoded image, σ in digital numbers of
an 8-bit image (0 … 255 scale) and scaled with the bit depth (σ·257 for 16 bit): in the
chain it works on encoded values on 0 … 1, where that is σ / 255 at any depth.

Every random draw comes from ``frame_rng(seed, frame_index, stream)``: the same seed and
frame reproduce an image exactly, different frames get independent noise.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from designer.effects.base import Effect, FrameContext, frame_rng

#: elements drawn per block, so the temporaries of a 20 MP RGB image stay small
_BLOCK = 1 << 20
#: the random stream of each effect (they may share a seed)
_STREAM_DN, _STREAM_SENSOR = 0, 1


def simulate_sensor(
    linear: np.ndarray,
    rng: np.random.Generator,
    *,
    full_well_e: float,
    exposure_scale: float = 1.0,
    shot_noise: bool = True,
    dark_current_e_per_s: float = 0.0,
    exposure_time_s: float = 0.0,
    read_noise_e: float = 0.0,
    adc_bits: int | None = 12,
) -> np.ndarray:
    """Linear light → linear light after the sensor (steps 1–6 of the module docstring).

    Returns float32 of the input's shape; with ``adc_bits=None`` no quantisation.
    """
    if not full_well_e > 0 or not exposure_scale >= 0:
        raise ValueError("full_well_e must be > 0 and exposure_scale >= 0")
    if min(dark_current_e_per_s, exposure_time_s, read_noise_e) < 0:
        raise ValueError("dark current, exposure time and read noise must be >= 0")
    if adc_bits is not None and not 1 <= adc_bits <= 24:
        raise ValueError(f"adc_bits = {adc_bits!r} must be from 1 to 24")
    src = np.asarray(linear, dtype=np.float32).ravel()
    out = np.empty(src.shape, dtype=np.float32)
    dark_e = dark_current_e_per_s * exposure_time_s
    levels = None if adc_bits is None else float(2**adc_bits - 1)
    for start in range(0, src.size, _BLOCK):
        block = src[start:start + _BLOCK]
        e = np.clip(block.astype(np.float64), 0.0, None) * (full_well_e * exposure_scale)
        if shot_noise:
            e = rng.poisson(e).astype(np.float64)
        if dark_e > 0:
            e += rng.poisson(dark_e, size=e.shape)
        if read_noise_e > 0:
            e += read_noise_e * rng.standard_normal(e.shape)
        v = np.clip(e, 0.0, full_well_e) / full_well_e
        if levels is not None:
            v = np.rint(v * levels) / levels
        out[start:start + block.size] = v
    return out.reshape(np.shape(linear))


@dataclass(frozen=True)
class SensorModel(Effect):
    """Shot noise, dark current, read noise and ADC quantisation (``simulate_sensor``).

    Attributes:
        full_well_e: electrons at which a pixel saturates; linear 1.0 × exposure_scale
            fills it.
        exposure_scale: relative exposure (1 = the render's white fills the well).
        read_noise_e: standard deviation of the read noise, electrons.
        dark_current_e_per_s, exposure_time_s: mean dark electrons = their product.
        adc_bits: ADC resolution; None for no quantisation.
        shot_noise: draw photon shot noise (Poisson).
        seed: random seed; combined with the frame index.
    """

    full_well_e: float = 20000.0
    exposure_scale: float = 1.0
    read_noise_e: float = 0.0
    dark_current_e_per_s: float = 0.0
    exposure_time_s: float = 0.0
    adc_bits: int | None = 12
    shot_noise: bool = True
    seed: int = 0
    kind: ClassVar[str] = "sensor"

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext) -> np.ndarray:
        return simulate_sensor(
            image, frame_rng(self.seed, frame_index, _STREAM_SENSOR),
            full_well_e=self.full_well_e, exposure_scale=self.exposure_scale,
            shot_noise=self.shot_noise, dark_current_e_per_s=self.dark_current_e_per_s,
            exposure_time_s=self.exposure_time_s, read_noise_e=self.read_noise_e,
            adc_bits=self.adc_bits,
        )


@dataclass(frozen=True)
class GaussianNoiseDN(Effect):
    """N(0, σ²) added to the stored (sRGB-encoded) values, σ in 8-bit digital numbers."""

    sigma_dn: float
    seed: int = 0
    kind: ClassVar[str] = "noise_dn"
    domain: ClassVar[str] = "encoded"

    def __post_init__(self) -> None:
        if not self.sigma_dn >= 0:
            raise ValueError(f"sigma_dn = {self.sigma_dn!r} must be >= 0")

    @property
    def is_identity(self) -> bool:
        return self.sigma_dn == 0

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext) -> np.ndarray:
        rng = frame_rng(self.seed, frame_index, _STREAM_DN)
        noise = rng.standard_normal(image.shape, dtype=np.float32)
        noise *= np.float32(self.sigma_dn / 255.0)
        return image + noise
