"""Sensor noise: a physical photon-to-digital-number model, and plain Gaussian DN noise.

``SensorModel`` works in linear light (float32, 1 = white, see ``designer.effects.base``):

1. signal electrons  λ = clip(V · gain, 0) · full_well_e · exposure_scale (gain: the
   vignetting, when the chain runs it here, else 1)
2. photon shot noise and dark current  Poisson(λ + dark_current_e_per_s · exposure_time_s)
   (a sum of Poisson variables is Poisson; the dark signal is not subtracted)
3. read noise  Normal(0, read_noise_e²)
4. saturation  clip to 0 … full_well_e
5. ADC  round(e / full_well_e · (2^bits − 1)), returned as DN / (2^bits − 1)

Poisson draws are exact (inversion below 10 e⁻, Hörmann's PTRS above) up to
``GAUSSIAN_ABOVE_E`` = 100 expected electrons; from there on a normal with the same mean
and variance is drawn (together with the read noise, one draw per pixel). Mean and
variance are thus exact everywhere; the shape differs from Poisson's by its skewness
1/√λ ≤ 0.1 (the largest difference of the distribution functions is ≤ 0.7 % at 100 e⁻,
≤ 0.2 % at 1000 e⁻), which the 8-bit codes of a survey image cannot show. Exact
rejection sampling costs ~40 ns per value: a 20 MP frame whose fifth lies below 1000 e⁻
took 0.77 s instead of 0.45 s with the limit at 1000 e⁻ (`designer bench effects`).

No colour filter array: every channel is treated as its own monochrome pixel.
``GaussianNoiseDN`` adds N(0, σ²) to the stored sRGB-encoded image, σ in digital numbers of
an 8-bit image (0 … 255 scale) and scaled with the bit depth (σ·257 for 16 bit): in the
chain it works on encoded values on 0 … 1, where that is σ / 255 at any depth.

Every random draw is counter-based on ``frame_key(seed, frame_index, stream)`` and the
element's position: the same seed and frame reproduce an image exactly on any number of
threads, different frames get independent noise.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from designer.effects import _sensor_kernels
from designer.effects.base import CameraContext, Effect, FrameContext, channels_last, frame_key
from designer.effects.registry import implements
from designer.effects.srgb import code_thresholds, encode_table, max_code
from designer.project import model as m

#: expected electrons from which shot noise is drawn as a normal of the same mean and
#: variance (see the module docstring)
GAUSSIAN_ABOVE_E = 100.0
#: the random stream of each effect (they may share a seed)
_STREAM_DN, _STREAM_SENSOR = 0, 1


def simulate_sensor(
    linear: np.ndarray,
    key: np.uint64 | int,
    *,
    full_well_e: float,
    exposure_scale: float = 1.0,
    shot_noise: bool = True,
    dark_current_e_per_s: float = 0.0,
    exposure_time_s: float = 0.0,
    read_noise_e: float = 0.0,
    adc_bits: int | None = 12,
    gain: np.ndarray | None = None,
    codes: np.dtype | None = None,
    encoded: bool = False,
    dn_noise: tuple[float, np.uint64] | None = None,
) -> np.ndarray:
    """Linear light → linear light after the sensor (steps 1–5 of the module docstring).

    ``key`` seeds the random numbers (``frame_key``); ``gain`` (H, W) multiplies the light
    first. Returns float32 linear light of the input's shape (with ``adc_bits=None`` not
    quantised; ``encoded``: its sRGB-encoded values), or with ``codes`` (uint8/uint16)
    the sRGB-encoded image of that type (``designer.effects.srgb.encode_image`` of it, in
    the same pass; with ``dn_noise`` = (σ on 0 … 1, key) Gaussian noise added to the
    encoded values first, as ``GaussianNoiseDN`` does).
    """
    if not full_well_e > 0 or not exposure_scale >= 0:
        raise ValueError("full_well_e must be > 0 and exposure_scale >= 0")
    if min(dark_current_e_per_s, exposure_time_s, read_noise_e) < 0:
        raise ValueError("dark current, exposure time and read noise must be >= 0")
    if adc_bits is not None and not 1 <= adc_bits <= 24:
        raise ValueError(f"adc_bits = {adc_bits!r} must be from 1 to 24")
    src = np.asarray(linear, dtype=np.float32)
    planes = src.reshape(1, -1, 1) if src.ndim == 1 else channels_last(src)
    if gain is None:
        gain = np.ones(planes.shape[:2], dtype=np.float32)
    elif gain.shape != planes.shape[:2]:
        raise ValueError(f"gain {gain.shape} does not fit the image {planes.shape[:2]}")
    planes = np.ascontiguousarray(planes)
    gain = np.ascontiguousarray(gain, dtype=np.float32)
    common = (np.uint64(key), float(full_well_e * exposure_scale), float(full_well_e),
              float(dark_current_e_per_s * exposure_time_s), float(read_noise_e),
              0.0 if adc_bits is None else float(2**adc_bits - 1), bool(shot_noise),
              GAUSSIAN_ABOVE_E)
    if dn_noise is not None and dn_noise[0] > 0:
        if codes is None:
            raise ValueError("DN noise in the sensor's pass needs codes")
        out = np.empty(planes.shape, codes)
        _sensor_kernels.sensor_dn_codes(planes, gain, *common, encode_table(),
                                        float(dn_noise[0]), np.uint64(dn_noise[1]),
                                        max_code(codes), out)
        return out.reshape(src.shape)
    no_table = np.empty(0)
    thresholds, first, table = no_table, np.empty(0, np.int32), no_table
    if codes is None:
        out = np.empty(planes.shape, np.float32)
        table = encode_table() if encoded else no_table
    else:
        out = np.empty(planes.shape, codes)
        thresholds, first = code_thresholds(8 if max_code(codes) == 255 else 16)
    _sensor_kernels.sensor(planes, gain, *common, thresholds, first, table, out)
    return out.reshape(src.shape)


@implements(m.Sensor)
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

    @classmethod
    def from_model(cls, element: m.Sensor, camera: CameraContext) -> SensorModel:
        """``<sensor>``: photon shot noise always on."""
        return cls(full_well_e=element.full_well_e, exposure_scale=element.exposure_scale,
                   read_noise_e=element.read_noise_e,
                   dark_current_e_per_s=element.dark_current_e_per_s,
                   exposure_time_s=element.exposure_time_s, adc_bits=element.adc_bits,
                   shot_noise=True, seed=element.seed)

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext,
              gain: np.ndarray | None = None, codes: np.dtype | None = None,
              encoded: bool = False, dn_noise: GaussianNoiseDN | None = None) -> np.ndarray:
        """``gain`` (H, W): a vignetting the chain folds into this pass; ``codes``: return
        the stored image of that type, ``encoded``: the sRGB-encoded values (the chain's
        next conversion, in the same pass); ``dn_noise``: the DN noise that follows, also
        in this pass (with ``codes``)."""
        dn = None if dn_noise is None else dn_noise.pass_parameters(frame_index)
        return simulate_sensor(
            image, frame_key(self.seed, frame_index, _STREAM_SENSOR), gain=gain, codes=codes,
            encoded=encoded, dn_noise=dn,
            full_well_e=self.full_well_e, exposure_scale=self.exposure_scale,
            shot_noise=self.shot_noise, dark_current_e_per_s=self.dark_current_e_per_s,
            exposure_time_s=self.exposure_time_s, read_noise_e=self.read_noise_e,
            adc_bits=self.adc_bits,
        )


@implements(m.SensorNoise)
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

    @classmethod
    def from_model(cls, element: m.SensorNoise, camera: CameraContext) -> GaussianNoiseDN:
        return cls(element.sigma_dn, element.seed)

    @property
    def is_identity(self) -> bool:
        return self.sigma_dn == 0

    def pass_parameters(self, frame_index: int) -> tuple[float, np.uint64]:
        """(σ on the 0 … 1 scale, random key) for a kernel that adds this noise."""
        return self.sigma_dn / 255.0, frame_key(self.seed, frame_index, _STREAM_DN)

    def apply(self, image: np.ndarray, frame_index: int, context: FrameContext,
              codes: np.dtype | None = None) -> np.ndarray:
        """``codes``: return the stored image of that type (rounded in the same pass)."""
        key = frame_key(self.seed, frame_index, _STREAM_DN)
        src = np.ascontiguousarray(image, dtype=np.float32)
        if codes is None:
            return _sensor_kernels.add_normal(src, key, self.sigma_dn / 255.0)
        out = np.empty(src.shape, dtype=codes)
        _sensor_kernels.add_normal_codes(src, key, self.sigma_dn / 255.0, max_code(codes), out)
        return out
